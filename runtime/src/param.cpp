// Texture coordinates of the factors (see sepal_param_texcoords; shaders/fused_pixel.frag
// has the same maths, thresholds included, for the per-pixel GL path).
#include <math.h>

#include "internal.h"
#include "sepal/sepal_asset.h"

namespace {

// Below this the rusinkiewicz frame is undefined (a fallback is taken and counted): sin^2
// theta_h (h within 1e-6 rad of the normal); gs-half's is kGsMin2 (internal.h). The shader
// uses the same constants.
constexpr float kPoleMin2 = 1e-12f;

void map(sepal_hemi_map m, const float a[3], float uv[2]) {
    if (m == SEPAL_MAP_XY) {
        uv[0] = 0.5f * (a[0] + 1.0f);
        uv[1] = 0.5f * (a[1] + 1.0f);
        return;
    }
    // Parabolic: finite for slightly back-facing vectors (a.z > -1), as the paper notes.
    float d = 1.0f + a[2];
    if (d < 1e-4f) d = 1e-4f;
    uv[0] = 0.5f * (a[0] / d + 1.0f);
    uv[1] = 0.5f * (a[1] / d + 1.0f);
}

// Normalizes v; false (v = fallback) when it has no direction.
bool normalize(float v[3], const float fallback[3]) {
    const float l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 1e-12f && isfinite(l)) {
        const float inv = 1.0f / l;
        v[0] *= inv, v[1] *= inv, v[2] *= inv;
        return true;
    }
    v[0] = fallback[0], v[1] = fallback[1], v[2] = fallback[2];
    return false;
}

// v in gs-half's frame about the unit vector a (Kautz-McCool eq. 6): t' = norm(t - (a.t) a),
// s' = a x t', d = (v.t', v.s', v.a). False when the fallback frame was taken.
bool gs_coords(const float a[3], const float v[3], float d[3]) {
    static const float kUp[3] = {0, 0, 1};
    bool ok = true;
    // The first component of t - (a.t) a is 1 - a.x^2 = a.y^2 + a.z^2, written so because
    // near a = t (gs-half: grazing retro-reflection; gs-mirror: light grazing along t, the
    // frame's singularity) the difference cancels.
    float tp[3] = {a[1] * a[1] + a[2] * a[2], -a[0] * a[1], -a[0] * a[2]};
    if (tp[0] > srt::kGsMin2) {  // |t'|^2 = 1 - a.x^2 = tp[0] for a unit a
        const float inv = 1.0f / sqrtf(tp[0] * tp[0] + tp[1] * tp[1] + tp[2] * tp[2]);
        tp[0] *= inv, tp[1] *= inv, tp[2] *= inv;
    } else {  // a within 1e-3 rad of +-t: Gram-Schmidt on s instead
        float ty[3] = {-a[0] * a[1], a[0] * a[0] + a[2] * a[2], -a[1] * a[2]};
        normalize(ty, kUp);
        tp[0] = ty[0], tp[1] = ty[1], tp[2] = ty[2];
        ok = false;
    }
    const float sp[3] = {a[1] * tp[2] - a[2] * tp[1], a[2] * tp[0] - a[0] * tp[2], a[0] * tp[1] - a[1] * tp[0]};
    d[0] = v[0] * tp[0] + v[1] * tp[1] + v[2] * tp[2];
    d[1] = v[0] * sp[0] + v[1] * sp[1] + v[2] * sp[2];
    d[2] = v[0] * a[0] + v[1] * a[1] + v[2] * a[2];
    return ok;
}

}  // namespace

namespace srt {

int param_texcoords(sepal_param p, sepal_hemi_map m, const float wi[3], const float wo[3], float g[2], float h[2],
                    bool per_pixel, int* fallbacks) {
    static const float kUp[3] = {0, 0, 1};
    const float kPi = 3.14159265358979f;
    const int above = wi[2] > 0.0f && wo[2] > 0.0f;
    float half[3] = {wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]};
    // wi = -wo (only below the horizon): no half vector; any choice, the light adds 0.
    bool fallback = (p == SEPAL_PARAM_GS_HALF || p == SEPAL_PARAM_VH || p == SEPAL_PARAM_RUSINKIEWICZ) &&
                    !normalize(half, kUp);
    switch (p) {
        case SEPAL_PARAM_IV:
            map(m, wi, g);
            map(m, wo, h);
            break;
        case SEPAL_PARAM_VH:
            map(m, wo, g);
            map(m, half, h);
            break;
        case SEPAL_PARAM_GS_HALF: {
            map(m, half, g);
            float d[3];
            fallback = !gs_coords(half, wi, d) || fallback;
            map(m, d, h);
            break;
        }
        case SEPAL_PARAM_GS_MIRROR: {
            const float r[3] = {-wi[0], -wi[1], wi[2]};
            map(m, r, g);
            float d[3];
            fallback = !gs_coords(r, wo, d);
            mirror_rim(d);
            map(m, d, h);
            break;
        }
        case SEPAL_PARAM_RUSINKIEWICZ: {
            if (!per_pixel) break;
            map(m, half, g);
            // d = rot_y(-theta_h) rot_z(-phi_h) wi: the half vector rotated to the pole.
            // cos and sin of phi_h straight from h (no atan2: GLSL's atan(0, 0) is undefined);
            // at the pole phi_h is undefined and 0 is used, as offline/factor/param.cpp's atan2 does.
            // sin theta_h from h.x, h.y rather than sqrt(1 - h.z^2), which cancels near the pole.
            const float st2 = half[0] * half[0] + half[1] * half[1];
            const float st = sqrtf(st2), ct = half[2];
            float cp = 1.0f, sp = 0.0f;
            if (st2 > kPoleMin2)
                cp = half[0] / st, sp = half[1] / st;
            else
                fallback = true;
            const float x1 = wi[0] * cp + wi[1] * sp, y1 = -wi[0] * sp + wi[1] * cp, z1 = wi[2];
            const float d[3] = {x1 * ct - z1 * st, y1, x1 * st + z1 * ct};
            map(m, d, h);
            break;
        }
        case SEPAL_PARAM_ELEV_AZIM: {
            if (!per_pixel) break;
            // Plain angle textures: G(theta_i, theta_o), H(phi_i, phi_o) (H wraps).
            const float ti = acosf(fminf(1.0f, fmaxf(-1.0f, wi[2]))), to = acosf(fminf(1.0f, fmaxf(-1.0f, wo[2])));
            float pi_ = atan2f(wi[1], wi[0]), po = atan2f(wo[1], wo[0]);
            if (pi_ < 0.0f) pi_ += 2.0f * kPi;
            if (po < 0.0f) po += 2.0f * kPi;
            g[0] = ti / (0.5f * kPi);
            g[1] = to / (0.5f * kPi);
            h[0] = pi_ / (2.0f * kPi);
            h[1] = po / (2.0f * kPi);
            break;
        }
        case SEPAL_PARAM_AXIS:
            // G at (alpha_i, alpha_o), H at (beta_i, beta_o) (internal.h): no half vector.
            srt::axis_uv(wi[0], wi[1], wi[2], &g[0], &h[0]);
            srt::axis_uv(wo[0], wo[1], wo[2], &g[1], &h[1]);
            break;
        default:
            g[0] = g[1] = h[0] = h[1] = 0.5f;
            return -1;
    }
    if (!per_pixel && (p == SEPAL_PARAM_RUSINKIEWICZ || p == SEPAL_PARAM_ELEV_AZIM)) {
        g[0] = g[1] = h[0] = h[1] = 0.5f;
        return -1;
    }
    if (fallback && fallbacks) ++*fallbacks;
    return above;
}

}  // namespace srt

extern "C" int sepal_param_texcoords(sepal_param p, sepal_hemi_map m, const float wi[3], const float wo[3], float g[2],
                                   float h[2]) {
    if ((unsigned)p >= SEPAL_PARAM_COUNT || (unsigned)m >= SEPAL_MAP_COUNT || !wi || !wo || !g || !h) return -1;
    return srt::param_texcoords(p, m, wi, wo, g, h, false, nullptr);
}

extern "C" int sepal_param_texcoords_pixel(sepal_param p, sepal_hemi_map m, const float wi[3], const float wo[3],
                                         float g[2], float h[2]) {
    if ((unsigned)p >= SEPAL_PARAM_COUNT || (unsigned)m >= SEPAL_MAP_COUNT || !wi || !wo || !g || !h) return -1;
    return srt::param_texcoords(p, m, wi, wo, g, h, true, nullptr);
}
