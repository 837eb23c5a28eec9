// Per-vertex texture coordinates of the factors (see srt_param_texcoords).
#include <math.h>

#include "internal.h"
#include "sepal_format.h"

namespace {

void map(srt_hemi_map m, const float a[3], float uv[2]) {
    if (m == SRT_MAP_XY) {
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

void normalize(float v[3], const float fallback[3]) {
    const float l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 1e-12f) {
        v[0] /= l, v[1] /= l, v[2] /= l;
    } else {
        v[0] = fallback[0], v[1] = fallback[1], v[2] = fallback[2];
    }
}

}  // namespace

extern "C" int srt_param_texcoords(srt_param p, srt_hemi_map m, const float wi[3],
                                   const float wo[3], float g[2], float h[2]) {
    static const float kUp[3] = {0, 0, 1};
    const int above = wi[2] > 0.0f && wo[2] > 0.0f;
    float half[3] = {wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]};
    normalize(half, kUp);  // wi = -wo: no half vector; any choice, the BRDF is 0 there
    switch (p) {
        case SRT_PARAM_IV:
            map(m, wi, g);
            map(m, wo, h);
            return above;
        case SRT_PARAM_VH:
            map(m, wo, g);
            map(m, half, h);
            return above;
        case SRT_PARAM_GS_HALF: {
            map(m, half, g);
            // Kautz-McCool eq. 6: t' = norm(t - (h.t) h), s' = h x t'. Singular only at
            // h = +-t (grazing retro-reflection); fall back to s there.
            float tp[3] = {1.0f - half[0] * half[0], -half[0] * half[1], -half[0] * half[2]};
            const float ty[3] = {-half[1] * half[0], 1.0f - half[1] * half[1], -half[1] * half[2]};
            normalize(tp, ty);
            const float sp[3] = {half[1] * tp[2] - half[2] * tp[1], half[2] * tp[0] - half[0] * tp[2],
                                 half[0] * tp[1] - half[1] * tp[0]};
            const float d[3] = {wi[0] * tp[0] + wi[1] * tp[1] + wi[2] * tp[2],
                                wi[0] * sp[0] + wi[1] * sp[1] + wi[2] * sp[2],
                                wi[0] * half[0] + wi[1] * half[1] + wi[2] * half[2]};
            map(m, d, h);
            return above;
        }
        default:
            g[0] = g[1] = h[0] = h[1] = 0.5f;
            return -1;
    }
}

extern "C" int srt_param_texcoords_pixel(srt_param p, srt_hemi_map m, const float wi[3],
                                         const float wo[3], float g[2], float h[2]) {
    const int above = wi[2] > 0.0f && wo[2] > 0.0f;
    const float kPi = 3.14159265358979f;
    if (p == SRT_PARAM_RUSINKIEWICZ) {
        static const float kUp[3] = {0, 0, 1};
        float half[3] = {wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]};
        normalize(half, kUp);
        map(m, half, g);
        // d = rot_y(-theta_h) rot_z(-phi_h) wi: the half vector rotated to the pole.
        const float ct = half[2] < 1.0f ? half[2] : 1.0f;
        const float st = sqrtf(fmaxf(0.0f, 1.0f - ct * ct));
        const float phi = atan2f(half[1], half[0]);
        const float cp = cosf(phi), sp = sinf(phi);
        const float x1 = wi[0] * cp + wi[1] * sp, y1 = -wi[0] * sp + wi[1] * cp, z1 = wi[2];
        const float d[3] = {x1 * ct - z1 * st, y1, x1 * st + z1 * ct};
        map(m, d, h);
        return above;
    }
    if (p == SRT_PARAM_ELEV_AZIM) {
        // Plain angle textures: G(theta_i, theta_o), H(phi_i, phi_o) (H wraps).
        const float ti = acosf(fminf(1.0f, fmaxf(-1.0f, wi[2]))), to = acosf(fminf(1.0f, fmaxf(-1.0f, wo[2])));
        float pi_ = atan2f(wi[1], wi[0]), po = atan2f(wo[1], wo[0]);
        if (pi_ < 0.0f) pi_ += 2.0f * kPi;
        if (po < 0.0f) po += 2.0f * kPi;
        g[0] = ti / (0.5f * kPi);
        g[1] = to / (0.5f * kPi);
        h[0] = pi_ / (2.0f * kPi);
        h[1] = po / (2.0f * kPi);
        return above;
    }
    return srt_param_texcoords(p, m, wi, wo, g, h);
}
