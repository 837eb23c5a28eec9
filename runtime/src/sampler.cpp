// Importance sampling of BRDFs: the sampler file reader and sample/pdf/eval (see
// sepal_sampler.h). No allocation; all state lives in the caller's sepal_sampler_view.
#include <float.h>
#include <math.h>
#include <string.h>

#include "internal.h"
#include "sepal/sepal_asset.h"
#include "sepal/sepal_sampler.h"

static_assert(sizeof(sepal_smp_header) == 64, "sampler header layout");
static_assert(sizeof(sepal_smp_desc) == 64, "sampler desc layout");
static_assert(sizeof(sepal_smp_lobe) == 32, "sampler lobe layout");

namespace {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kTwoPi = 2.0f * kPi;
constexpr uint64_t kPrefix = sizeof(sepal_smp_header) + sizeof(sepal_smp_desc);
// The largest float below 1: a u of exactly 1 (a caller's rounding) is treated as this.
constexpr float kOneMinus = 0x1.fffffep-1f;

// ---- layout --------------------------------------------------------------------------------
enum Array {
    kZ = SEPAL_SMP_ARRAY_Z_EDGES,
    kF = SEPAL_SMP_ARRAY_F,
    kU = SEPAL_SMP_ARRAY_U_CDF,
    kV = SEPAL_SMP_ARRAY_V_CDF,
    kCa = SEPAL_SMP_ARRAY_COLOUR_A,
    kCb = SEPAL_SMP_ARRAY_COLOUR_B,
    kCc = SEPAL_SMP_ARRAY_COLOUR_C,
    kLobes = SEPAL_SMP_ARRAY_LOBES,
    kTables = SEPAL_SMP_ARRAY_TABLES,
    kArrays = SEPAL_SMP_ARRAY_COUNT
};

uint64_t pad8(uint64_t n) { return (n + 7) & ~uint64_t(7); }

// Offsets and sizes of every array (from the file start) and the end; false on counts out
// of range.
bool layout(uint32_t kind, const sepal_smp_desc& d, uint64_t off[kArrays], uint64_t size[kArrays], uint64_t* end) {
    for (int i = 0; i < kArrays; ++i) off[i] = 0, size[i] = 0;
    uint64_t at = kPrefix;
    auto put = [&](Array a, uint64_t floats) {
        off[a] = at;
        size[a] = floats * 4;
        at += pad8(floats * 4);
    };
    const bool views = kind == SEPAL_SAMPLER_FACTORED || kind == SEPAL_SAMPLER_TABULATED;
    if (views) {
        if (d.n_theta_o < 1 || d.n_theta_o > SEPAL_SMP_MAX_VIEW_SIDE || d.n_phi_o < 1 ||
            d.n_phi_o > SEPAL_SMP_MAX_VIEW_SIDE || d.n_theta_p < 1 ||
            d.n_theta_p > SEPAL_SMP_MAX_DIR_SIDE || d.n_phi_p < 1 || d.n_phi_p > SEPAL_SMP_MAX_DIR_SIDE)
            return false;
    }
    const uint64_t To = d.n_theta_o, Po = d.n_phi_o, Tp = d.n_theta_p, Pp = d.n_phi_p;
    switch (kind) {
        case SEPAL_SAMPLER_FACTORED:
            if (d.terms < 1 || d.terms > SEPAL_SMP_MAX_TERMS || d.colour > 1) return false;
            put(kZ, Tp + 1);
            put(kF, d.terms * To * Po);
            put(kU, d.terms * (Tp + 1));
            put(kV, d.terms * (Pp + 1));
            if (d.colour) {
                put(kCa, 3 * To * Po);
                put(kCb, 3 * Tp);
                put(kCc, 3 * Pp);
            }
            break;
        case SEPAL_SAMPLER_COSINE: break;
        case SEPAL_SAMPLER_LOBES:
            if (d.lobe_count < 1 || d.lobe_count > SEPAL_SMP_MAX_LOBES) return false;
            off[kLobes] = at;
            size[kLobes] = uint64_t(d.lobe_count) * sizeof(sepal_smp_lobe);
            at += size[kLobes];
            break;
        case SEPAL_SAMPLER_TABULATED:
            put(kZ, Tp + 1);
            put(kTables, To * Po * ((Tp + 1) + Tp * (Pp + 1)));
            break;
        default: return false;
    }
    *end = at;
    return true;
}

const char* kind_name(uint32_t k) {
    static const char* names[] = {"factored", "cosine", "lobes", "tabulated"};
    return k < SEPAL_SAMPLER_KIND_COUNT ? names[k] : "unknown";
}

bool all_finite(const float* p, uint64_t n, bool non_negative) {
    for (uint64_t i = 0; i < n; ++i)
        if (!isfinite(p[i]) || (non_negative && p[i] < 0.0f)) return false;
    return true;
}

// A CDF of n bins: n + 1 finite values from exactly 0 to exactly 1, non-decreasing.
bool valid_cdf(const float* c, uint32_t n) {
    if (c[0] != 0.0f || c[n] != 1.0f) return false;
    for (uint32_t i = 0; i < n; ++i)
        if (!(c[i + 1] >= c[i])) return false;
    return true;
}

bool valid_z_edges(const float* z, uint32_t n, float last) {
    if (z[0] != 1.0f || z[n] != last) return false;
    for (uint32_t i = 0; i < n; ++i)
        if (!(z[i + 1] < z[i])) return false;
    return true;
}

// ---- small maths -----------------------------------------------------------------------------
inline float dot(const float* a, const float* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline float clampf(float x, float lo, float hi) { return x < lo ? lo : (x > hi ? hi : x); }
inline float unit_u(float u) { return u >= 0.0f ? (u < 1.0f ? u : kOneMinus) : 0.0f; }

// Largest i in [0, n-1] with cdf[i] <= x: the bin holding x (its width is then > 0).
// Branch-free (the step is a select): a search's branches are unpredictable, and its
// three to five searches per sample were a third of sample()'s profile.
uint32_t find_bin(const float* cdf, uint32_t n, float x) {
    const float* base = cdf;  // invariant: the answer is in [base, base + n)
    while (n > 1) {
        const uint32_t half = n / 2;
        base = base[half] <= x ? base + half : base;
        n -= half;
    }
    return (uint32_t)(base - cdf);
}

// Picks a bin of the CDF with x in [0,1) and returns x rescaled to [0,1) within it.
uint32_t pick(const float* cdf, uint32_t n, float x, float* rescaled) {
    const uint32_t i = find_bin(cdf, n, x);
    const float w = cdf[i + 1] - cdf[i];
    *rescaled = w > 0.0f ? clampf((x - cdf[i]) / w, 0.0f, kOneMinus) : 0.0f;
    return i;
}

// The z bin (edges decreasing from 1 to 0 or -1) holding z: largest i in [0, n-1] with
// edges[i] >= z; branch-free as find_bin.
uint32_t z_bin(const float* edges, uint32_t n, float z) {
    const float* base = edges;
    while (n > 1) {
        const uint32_t half = n / 2;
        base = base[half] >= z ? base + half : base;
        n -= half;
    }
    return (uint32_t)(base - edges);
}

uint32_t phi_bin(float phi, uint32_t n) {
    const int j = (int)(phi * (float)n / kTwoPi);
    return j < 0 ? 0u : (j >= (int)n ? n - 1 : (uint32_t)j);
}

// atan2_poly (internal.h, within 5e-7 rad of atan2f, without its branches): these angles
// only pick a bin, and sample() and pdf() pick it from the same wi.
float azimuth(float x, float y) {
    float phi = srt::atan2_poly(y, x);
    if (phi < 0.0f) phi += kTwoPi;
    return phi < kTwoPi ? phi : 0.0f;
}

// Orthonormal basis (b1, b2) around the unit vector a (Duff et al. 2017).
void basis(const float* a, float* b1, float* b2) {
    const float sign = copysignf(1.0f, a[2]);
    const float p = -1.0f / (sign + a[2]);
    const float q = a[0] * a[1] * p;
    b1[0] = 1.0f + sign * a[0] * a[0] * p, b1[1] = sign * q, b1[2] = -sign * a[0];
    b2[0] = q, b2[1] = sign + a[1] * a[1] * p, b2[2] = -a[1];
}

void cosine_sample(const float u[2], float* w) {
    const float r = sqrtf(u[0]), phi = kTwoPi * u[1];
    w[0] = r * cosf(phi), w[1] = r * sinf(phi);
    w[2] = sqrtf(fmaxf(0.0f, 1.0f - u[0]));
}
inline float cosine_pdf(const float* w) { return w[2] > 0.0f ? w[2] / kPi : 0.0f; }
// Rec. 709 luminance, what the samplers follow (offline/sampling/factored_fit.h's luminance).
inline float luminance3(const float* c) { return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]; }

// wi from a half vector (upper hemisphere) and wo: the mirror of wo about h.
void reflect(const float* wo, const float* h, float* wi) {
    const float d = 2.0f * dot(wo, h);
    for (int k = 0; k < 3; ++k) wi[k] = d * h[k] - wo[k];
}
// The half vector of (wi, wo) in the upper hemisphere and 1/|dwi/dh| = 1/(4 |wi.h|);
// false when wi = -wo (no half vector).
bool half_of(const float* wi, const float* wo, float* h, float* inv_jacobian) {
    h[0] = wi[0] + wo[0], h[1] = wi[1] + wo[1], h[2] = wi[2] + wo[2];
    const float len = sqrtf(dot(h, h));
    if (!(len > 1e-7f)) return false;
    const float s = h[2] < 0.0f ? -1.0f / len : 1.0f / len;
    h[0] *= s, h[1] *= s, h[2] *= s;
    const float c = fabsf(dot(wi, h));
    if (!(c > 1e-9f)) return false;
    *inv_jacobian = 1.0f / (4.0f * c);
    return true;
}

// The format 1.3 axes (sepal_smp_axis).
inline bool mirror_axis(uint32_t axis) { return axis == SEPAL_SMP_AXIS_T_MIRROR || axis == SEPAL_SMP_AXIS_S_MIRROR; }
inline bool view_axis(uint32_t axis) { return axis == SEPAL_SMP_AXIS_T_VIEW || axis == SEPAL_SMP_AXIS_S_VIEW; }

// Rotations between the local frame and the view frame: about n by phi_o (view phi), about
// t or s by b (the view axes; to_view lowers the angle about the axis by b); the identity
// (cos 1, sin 0) otherwise.
inline void rotate(const sepal_sampler_view* v, const float* w, float* out, float sign) {
    out[0] = w[0], out[1] = w[1], out[2] = w[2];
    const uint32_t axis = v->sampler ? v->sampler->desc.axis : (uint32_t)SEPAL_SMP_AXIS_N;
    if (view_axis(axis)) {
        const int p = axis == SEPAL_SMP_AXIS_T_VIEW ? 1 : 0;  // atan2(w[p], w[2]) is the angle
        const float c = v->cos_phi, s = sign * v->sin_phi;
        out[p] = c * w[p] - s * w[2];
        out[2] = c * w[2] + s * w[p];
        return;
    }
    out[0] = v->cos_phi * w[0] + sign * v->sin_phi * w[1];
    out[1] = -sign * v->sin_phi * w[0] + v->cos_phi * w[1];
}
inline void to_view(const sepal_sampler_view* v, const float* w, float* out) { rotate(v, w, out, 1.0f); }
inline void from_view(const sepal_sampler_view* v, const float* w, float* out) { rotate(v, w, out, -1.0f); }

// Bilinear weights on the view grid at (theta_o, phi_o): theta clamped, phi periodic.
struct ViewLerp {
    uint32_t idx[4];
    float w[4];
};
ViewLerp view_lerp(uint32_t To, uint32_t Po, float theta, float phi) {
    ViewLerp l;
    float fx = clampf(theta / (0.5f * kPi) * (float)To - 0.5f, 0.0f, (float)(To - 1));
    const uint32_t i0 = (uint32_t)fx, i1 = i0 + 1 < To ? i0 + 1 : i0;
    const float tx = fx - (float)i0;
    float fy = phi / kTwoPi * (float)Po - 0.5f;
    const float fl = floorf(fy);
    const float ty = fy - fl;
    int j0 = (int)fl % (int)Po;
    if (j0 < 0) j0 += (int)Po;
    const uint32_t j1 = ((uint32_t)j0 + 1) % Po;
    l.idx[0] = i0 * Po + (uint32_t)j0, l.w[0] = (1 - tx) * (1 - ty);
    l.idx[1] = i0 * Po + j1, l.w[1] = (1 - tx) * ty;
    l.idx[2] = i1 * Po + (uint32_t)j0, l.w[2] = tx * (1 - ty);
    l.idx[3] = i1 * Po + j1, l.w[3] = tx * ty;
    return l;
}
inline float lerp_at(const float* table, const ViewLerp& l) {
    return table[l.idx[0]] * l.w[0] + table[l.idx[1]] * l.w[1] + table[l.idx[2]] * l.w[2] +
           table[l.idx[3]] * l.w[3];
}

// Density over (z, phi) of bin (i, j) of a CDF pair.
inline float bin_density(const float* ucdf, const float* vcdf, const float* z, uint32_t i,
                         uint32_t j, uint32_t Pp) {
    return (ucdf[i + 1] - ucdf[i]) / (z[i] - z[i + 1]) * ((vcdf[j + 1] - vcdf[j]) * (float)Pp / kTwoPi);
}

// ---- factored coordinates (desc.axis) ---------------------------------------------------------
// c1 is a direction's component along the axis (edges in z_edges), c2 its angle about the
// axis over [c2_lo, c2_lo + c2_span) in Pp uniform bins; dOmega = dc1 dc2 for all three.
inline float c2_lo(uint32_t axis) { return axis == SEPAL_SMP_AXIS_N ? 0.0f : -0.5f * kPi; }
inline float c2_span(uint32_t axis) { return axis == SEPAL_SMP_AXIS_N ? kTwoPi : kPi; }
// The view and mirror axes bin (c1, c2) about t or s as T and S do.
inline uint32_t fixed_axis(uint32_t axis) {
    return axis == SEPAL_SMP_AXIS_T_VIEW || axis == SEPAL_SMP_AXIS_T_MIRROR   ? (uint32_t)SEPAL_SMP_AXIS_T
           : axis == SEPAL_SMP_AXIS_S_VIEW || axis == SEPAL_SMP_AXIS_S_MIRROR ? (uint32_t)SEPAL_SMP_AXIS_S
                                                                               : axis;
}
// The mirror axes' c1 from a = wi.t (or wi.s) and the cone m, with dc1/da in *jacobian.
inline float to_mirror(float a, float m, float* jacobian) {
    const float side = a >= m ? 1.0f - m : 1.0f + m;
    *jacobian = 1.0f / side;
    return clampf((a - m) / side, -1.0f, 1.0f);
}
inline float from_mirror(float c1, float m) { return clampf(m + c1 * (c1 >= 0.0f ? 1.0f - m : 1.0f + m), -1.0f, 1.0f); }

void to_coords(uint32_t axis, const float* w, float* c1, float* c2) {
    switch (fixed_axis(axis)) {
        case SEPAL_SMP_AXIS_T: *c1 = w[0], *c2 = srt::atan2_poly(w[1], w[2]); break;
        case SEPAL_SMP_AXIS_S: *c1 = w[1], *c2 = srt::atan2_poly(w[0], w[2]); break;
        default: *c1 = w[2], *c2 = azimuth(w[0], w[1]); break;
    }
}

void from_coords(uint32_t axis, float c1, float c2, float* w) {
    const float r = sqrtf(fmaxf(0.0f, 1.0f - c1 * c1));
    switch (fixed_axis(axis)) {
        case SEPAL_SMP_AXIS_T: w[0] = c1, w[1] = r * sinf(c2), w[2] = r * cosf(c2); break;
        case SEPAL_SMP_AXIS_S: w[0] = r * sinf(c2), w[1] = c1, w[2] = r * cosf(c2); break;
        default: w[0] = r * cosf(c2), w[1] = r * sinf(c2), w[2] = c1; break;
    }
}

uint32_t c2_bin(uint32_t axis, float c2, uint32_t n) {
    const int j = (int)((c2 - c2_lo(axis)) * (float)n / c2_span(axis));
    return j < 0 ? 0u : (j >= (int)n ? n - 1 : (uint32_t)j);
}

// The (c1, c2) bin of a unit wp in the view frame.
// jacobian: dc1/da for the mirror axes (the density over wp is the one over (c1, c2) times
// it), 1 for the others.
void factored_bin(const sepal_sampler_view* v, const float* w, uint32_t* i, uint32_t* j, float* jacobian) {
    const sepal_sampler& s = *v->sampler;
    float c1, c2;
    to_coords(s.desc.axis, w, &c1, &c2);
    *jacobian = 1.0f;
    if (mirror_axis(s.desc.axis)) c1 = to_mirror(c1, v->mirror, jacobian);
    *i = z_bin(s.z_edges, s.desc.n_theta_p, c1);
    *j = c2_bin(s.desc.axis, c2, s.desc.n_phi_p);
}

// Draws a direction from a pair of CDFs: c1 over the decreasing edges, c2 uniform bins.
// x drives c2, y drives c1 (both in [0,1)).
void draw_coords(const float* ucdf, const float* vcdf, const float* z, uint32_t Tp, uint32_t Pp,
                 uint32_t axis, float mirror, float x, float y, float* w) {
    float t;
    const uint32_t j = pick(vcdf, Pp, x, &t);
    const float c2 = c2_lo(axis) + ((float)j + t) * c2_span(axis) / (float)Pp;
    const uint32_t i = pick(ucdf, Tp, y, &t);
    float c1 = clampf(z[i] + t * (z[i + 1] - z[i]), z[Tp], 1.0f);
    if (mirror_axis(axis)) c1 = from_mirror(c1, mirror);
    from_coords(axis, c1, c2, w);
}

// ---- analytic lobes ----------------------------------------------------------------------------
// Azimuth with density proportional to 1 / (a cos^2 phi + b sin^2 phi) from u, k = sqrt(a/b):
// the inverse CDF in the first quadrant (tan phi = k tan(pi u / 2)), mirrored to the others.
float elliptic_azimuth(float u, float k) {
    const float q = floorf(u * 4.0f);
    const float uq = clampf(u * 4.0f - q, 0.0f, kOneMinus);
    const float p = atanf(k * tanf(0.5f * kPi * uq));
    switch ((int)q) {
        case 0: return p;
        case 1: return kPi - p;
        case 2: return kPi + p;
        default: return kTwoPi - p;
    }
}

// Density of a half-vector lobe at h (upper hemisphere, unit).
float half_lobe_pdf(const sepal_smp_lobe& l, const float* h) {
    const float sxy = h[0] * h[0] + h[1] * h[1];
    if (l.type == SEPAL_LOBE_HALF_AS) {
        const float nu = l.p[0], nv = l.p[1];
        const float e = sxy > 0.0f ? (nu * h[0] * h[0] + nv * h[1] * h[1]) / sxy : 0.0f;
        return sqrtf((nu + 1.0f) * (nv + 1.0f)) / kTwoPi * powf(h[2], e);
    }
    // Ward / Beckmann
    const float ax = l.p[0], ay = l.p[1];
    if (!(h[2] > 0.0f)) return 0.0f;
    const float e = (h[0] * h[0] / (ax * ax) + h[1] * h[1] / (ay * ay)) / (h[2] * h[2]);
    return expf(-e) / (kPi * ax * ay * h[2] * h[2] * h[2]);
}

void half_lobe_sample(const sepal_smp_lobe& l, float x, float y, float* h) {
    float phi, z;
    if (l.type == SEPAL_LOBE_HALF_AS) {
        const float nu = l.p[0], nv = l.p[1];
        phi = elliptic_azimuth(x, sqrtf((nu + 1.0f) / (nv + 1.0f)));
        const float c = cosf(phi), s = sinf(phi);
        const float e = nu * c * c + nv * s * s;
        z = powf(1.0f - y, 1.0f / (e + 1.0f));
    } else {
        const float ax = l.p[0], ay = l.p[1];
        phi = elliptic_azimuth(x, ay / ax);
        const float c = cosf(phi), s = sinf(phi);
        const float t2 = -logf(1.0f - y) / (c * c / (ax * ax) + s * s / (ay * ay));
        z = 1.0f / sqrtf(1.0f + t2);
    }
    const float r = sqrtf(fmaxf(0.0f, 1.0f - z * z));
    h[0] = r * cosf(phi), h[1] = r * sinf(phi), h[2] = z;
}

// Phong-axis lobe: the axis C o wo and its length.
float phong_axis(const sepal_smp_lobe& l, const float* wo, float* a) {
    a[0] = l.p[0] * wo[0], a[1] = l.p[1] * wo[1], a[2] = l.p[2] * wo[2];
    const float len = sqrtf(dot(a, a));
    if (len > 0.0f) a[0] /= len, a[1] /= len, a[2] /= len;
    return len;
}

float lobe_pdf(const sepal_smp_lobe& l, const float* wo, const float* wi) {
    switch (l.type) {
        case SEPAL_LOBE_COSINE: return cosine_pdf(wi);
        case SEPAL_LOBE_PHONG_AXIS: {
            float a[3];
            if (!(phong_axis(l, wo, a) > 0.0f)) return 0.0f;
            const float c = dot(a, wi);
            return c > 0.0f ? (l.p[3] + 1.0f) / kTwoPi * powf(c, l.p[3]) : 0.0f;
        }
        default: {
            float h[3], inv_j;
            if (!half_of(wi, wo, h, &inv_j)) return 0.0f;
            return half_lobe_pdf(l, h) * inv_j;
        }
    }
}

void lobe_sample(const sepal_smp_lobe& l, const float* wo, float x, float y, float* wi) {
    const float u[2] = {x, y};
    switch (l.type) {
        case SEPAL_LOBE_COSINE: cosine_sample(u, wi); return;
        case SEPAL_LOBE_PHONG_AXIS: {
            float a[3], b1[3], b2[3];
            phong_axis(l, wo, a);
            basis(a, b1, b2);
            const float c = powf(1.0f - x, 1.0f / (l.p[3] + 1.0f));
            const float s = sqrtf(fmaxf(0.0f, 1.0f - c * c)), phi = kTwoPi * y;
            const float cp = s * cosf(phi), sp = s * sinf(phi);
            for (int k = 0; k < 3; ++k) wi[k] = cp * b1[k] + sp * b2[k] + c * a[k];
            return;
        }
        default: {
            float h[3];
            half_lobe_sample(l, x, y, h);
            reflect(wo, h, wi);
            return;
        }
    }
}

// ---- the factored and tabulated densities (without the defensive share) ------------------------
// Density over the sphere of wi of the factored mixture (the view's term probabilities);
// with over_wp, the density over wp instead (before the Jacobian).
float factored_pdf(const sepal_sampler_view* v, const float* wi, bool over_wp = false) {
    const sepal_sampler& s = *v->sampler;
    const sepal_smp_desc& d = s.desc;
    float wp[3], inv_j = 1.0f;
    if (d.param == SEPAL_SMP_PARAM_HALF) {
        if (!half_of(wi, v->wo, wp, &inv_j)) return 0.0f;
    } else {
        if (!(wi[2] >= 0.0f)) return 0.0f;
        wp[0] = wi[0], wp[1] = wi[1], wp[2] = wi[2];
    }
    float w[3];
    to_view(v, wp, w);
    const uint32_t Tp = d.n_theta_p, Pp = d.n_phi_p;
    uint32_t i, j;
    float jacobian;
    factored_bin(v, w, &i, &j, &jacobian);
    // sum_l w_l U_l(c1) V_l(c2): the bin's width in c1 and in c2 is shared by every term.
    // Four partial sums: one chain of 16 dependent adds was the loop's latency.
    float acc[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    const float* u = s.u_cdf + i;
    const float* c = s.v_cdf + j;
    for (uint32_t l = 0; l < v->count; ++l, u += Tp + 1, c += Pp + 1)
        acc[l & 3] += v->weight[l] * ((u[1] - u[0]) * (c[1] - c[0]));
    float p = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    p *= jacobian * (float)Pp / (c2_span(d.axis) * (s.z_edges[i] - s.z_edges[i + 1]));
    return over_wp ? p : p * inv_j;
}

const float* view_table(const sepal_sampler& s, uint32_t view) {
    const uint64_t Tp = s.desc.n_theta_p, Pp = s.desc.n_phi_p;
    return s.tables + view * ((Tp + 1) + Tp * (Pp + 1));
}

float tabulated_pdf(const sepal_sampler_view* v, const float* wi) {
    if (!(wi[2] >= 0.0f)) return 0.0f;
    const sepal_sampler& s = *v->sampler;
    const uint32_t Tp = s.desc.n_theta_p, Pp = s.desc.n_phi_p;
    float w[3];
    to_view(v, wi, w);
    const uint32_t i = z_bin(s.z_edges, Tp, w[2]);
    const uint32_t j = phi_bin(azimuth(w[0], w[1]), Pp);
    const float* t = view_table(s, v->table);
    return bin_density(t, t + (Tp + 1) + i * (Pp + 1), s.z_edges, i, j, Pp);
}

}  // namespace

// ---- API -----------------------------------------------------------------------------------------
extern "C" uint64_t sepal_sampler_layout(uint32_t kind, const sepal_smp_desc* d,
                                        uint64_t offsets[SEPAL_SMP_ARRAY_COUNT],
                                        uint64_t sizes[SEPAL_SMP_ARRAY_COUNT]) {
    uint64_t off[kArrays], size[kArrays], end = 0;
    if (!d || !layout(kind, *d, off, size, &end)) return 0;
    for (int i = 0; i < kArrays; ++i) {
        if (offsets) offsets[i] = off[i];
        if (sizes) sizes[i] = size[i];
    }
    return end;
}

extern "C" sepal_result sepal_sampler_parse(const void* bytes, size_t size, sepal_sampler* out,
                                            sepal_error* err) {
    const uint16_t probe = 1;
    if (*(const uint8_t*)&probe != 1)
        return srt::fail(err, SEPAL_ERR_UNSUPPORTED, "sampler: big-endian hosts are not supported");
    if (!out || !bytes) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "sampler: NULL argument");
    memset(out, 0, sizeof *out);
    if ((uintptr_t)bytes % 4 != 0)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "sampler: buffer is not 4-byte aligned");
    if (size < kPrefix)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "sampler: %zu bytes is too short for the 128-byte header (truncated?)", size);
    const uint8_t* base = (const uint8_t*)bytes;
    sepal_smp_header& h = out->header;
    memcpy(&h, base, sizeof h);
    if (memcmp(h.magic, SEPAL_SMP_MAGIC, 8) != 0)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "sampler: bad magic (not a sepal sampler file)");
    if (h.version_major != SEPAL_SMP_VERSION_MAJOR)
        return srt::fail(err, SEPAL_ERR_UNSUPPORTED,
                         "sampler: format version %u.%u; this runtime reads version %d.x",
                         h.version_major, h.version_minor, SEPAL_SMP_VERSION_MAJOR);
    sepal_smp_header zeroed = h;
    zeroed.header_crc = 0;
    if (h.header_bytes != sizeof h || sepal_crc32(0, &zeroed, sizeof zeroed) != h.header_crc)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "sampler: header checksum mismatch (corrupt header)");
    if (h.file_bytes != size)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "sampler: header says %llu bytes, the buffer holds %zu (truncated or padded)",
                         (unsigned long long)h.file_bytes, size);
    if (size > SEPAL_SMP_MAX_FILE_BYTES)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "sampler: %zu bytes is over the %u-byte limit", size,
                         SEPAL_SMP_MAX_FILE_BYTES);
    if (sepal_crc32(0, base + sizeof h, size - sizeof h) != h.payload_crc)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "sampler: payload checksum mismatch (corrupt data)");
    if (h.kind >= SEPAL_SAMPLER_KIND_COUNT)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "sampler: unknown kind %u", h.kind);
    const sepal_smp_desc& d = out->desc;
    memcpy(&out->desc, base + sizeof h, sizeof out->desc);
    out->kind = h.kind;
    uint64_t off[kArrays], size_of[kArrays], end = 0;
    if (!layout(h.kind, d, off, size_of, &end))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "sampler: %s counts out of range (views %ux%u of 1..%d, bins %ux%u of 1..%d, "
                         "terms %u of 1..%d, lobes %u of 1..%d, colour %u)",
                         kind_name(h.kind), d.n_theta_o, d.n_phi_o, SEPAL_SMP_MAX_VIEW_SIDE, d.n_theta_p,
                         d.n_phi_p, SEPAL_SMP_MAX_DIR_SIDE, d.terms, SEPAL_SMP_MAX_TERMS, d.lobe_count,
                         SEPAL_SMP_MAX_LOBES, d.colour);
    if (end != size)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "sampler: %s with these counts is %llu bytes, the file is %zu", kind_name(h.kind),
                         (unsigned long long)end, size);
    auto arr = [&](Array a) { return off[a] ? (const float*)(base + off[a]) : nullptr; };
    const uint32_t To = d.n_theta_o, Po = d.n_phi_o, Tp = d.n_theta_p, Pp = d.n_phi_p;
    const bool views = h.kind == SEPAL_SAMPLER_FACTORED || h.kind == SEPAL_SAMPLER_TABULATED;
    // Every kind mixes in cosine samples by this share (a LOBES file too).
    if (!(d.defensive >= 0.0f && d.defensive <= 1.0f))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "sampler: %s: defensive share %g outside [0, 1]",
                         kind_name(h.kind), (double)d.defensive);
    if (views) {
        if (d.param >= SEPAL_SMP_PARAM_COUNT || d.phi_frame >= SEPAL_SMP_PHI_COUNT)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "sampler: unknown parameterization %u or phi frame %u",
                             d.param, d.phi_frame);
        if (d.phi_frame == SEPAL_SMP_PHI_VIEW && Po != 1)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "sampler: view-relative phi needs 1 phi_o bin, not %u",
                             Po);
        if (d.jacobian > 1)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "sampler: jacobian flag %u (0 or 1)", d.jacobian);
        for (int c = 0; c < 3; ++c)
            if (!(d.diffuse[c] >= 0.0f && d.diffuse[c] <= SEPAL_SMP_MAX_DIFFUSE) ||
                (d.diffuse[c] != 0.0f && (h.kind != SEPAL_SAMPLER_FACTORED || h.version_minor < 1)))
                return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                                 "sampler: diffuse part %g (channel %d) outside [0, %g], or set in a %s "
                                 "file of version 1.%u (only factored samplers of 1.1 have one)",
                                 (double)d.diffuse[c], c, (double)SEPAL_SMP_MAX_DIFFUSE, kind_name(h.kind),
                                 h.version_minor);
        if (d.axis >= SEPAL_SMP_AXIS_COUNT ||
            (d.axis != SEPAL_SMP_AXIS_N && (h.kind != SEPAL_SAMPLER_FACTORED || h.version_minor < 2 ||
                                            d.phi_frame != SEPAL_SMP_PHI_ABSOLUTE)) ||
            (view_axis(d.axis) && (h.version_minor < 3 || d.param != SEPAL_SMP_PARAM_HALF)) ||
            (mirror_axis(d.axis) && (h.version_minor < 3 || d.param != SEPAL_SMP_PARAM_INCIDENT)))
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "sampler: axis %u in a %s file of version 1.%u (axes 1 and 2 only in factored "
                             "samplers of 1.2 with absolute phi; 3 and 4 also need 1.3 and the half vector, "
                             "5 and 6 1.3 and the incident direction)",
                             d.axis, kind_name(h.kind), h.version_minor);
        const float last = d.axis == SEPAL_SMP_AXIS_N ? 0.0f : -1.0f;
        out->z_edges = arr(kZ);
        if (!valid_z_edges(out->z_edges, Tp, last))
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "sampler: bin edges must fall strictly from 1 to %g", (double)last);
    }
    if (h.kind == SEPAL_SAMPLER_FACTORED) {
        out->F = arr(kF), out->u_cdf = arr(kU), out->v_cdf = arr(kV);
        if (!all_finite(out->F, uint64_t(d.terms) * To * Po, true))
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "sampler: a term weight is negative or not finite");
        for (uint32_t l = 0; l < d.terms; ++l)
            if (!valid_cdf(out->u_cdf + l * (Tp + 1), Tp) || !valid_cdf(out->v_cdf + l * (Pp + 1), Pp))
                return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                                 "sampler: term %u's CDF does not rise from 0 to 1", l);
        if (d.colour) {
            out->colour_a = arr(kCa), out->colour_b = arr(kCb), out->colour_c = arr(kCc);
            if (!all_finite(out->colour_a, 3ull * To * Po, true) || !all_finite(out->colour_b, 3ull * Tp, true) ||
                !all_finite(out->colour_c, 3ull * Pp, true))
                return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "sampler: a colour factor is negative or not finite");
        }
    } else if (h.kind == SEPAL_SAMPLER_TABULATED) {
        out->tables = arr(kTables);
        for (uint32_t view = 0; view < To * Po; ++view) {
            const float* t = view_table(*out, view);
            bool ok = valid_cdf(t, Tp);
            for (uint32_t i = 0; ok && i < Tp; ++i) ok = valid_cdf(t + (Tp + 1) + i * (Pp + 1), Pp);
            if (!ok)
                return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "sampler: view %u's CDFs do not rise from 0 to 1",
                                 view);
        }
    } else if (h.kind == SEPAL_SAMPLER_LOBES) {
        out->lobes = (const sepal_smp_lobe*)(base + off[kLobes]);
        float sum = 0.0f;
        for (uint32_t k = 0; k < d.lobe_count; ++k) {
            const sepal_smp_lobe& l = out->lobes[k];
            bool ok = l.type < SEPAL_LOBE_TYPE_COUNT && isfinite(l.weight) && l.weight >= 0.0f &&
                      all_finite(l.p, 6, false);
            if (ok && l.type == SEPAL_LOBE_PHONG_AXIS) ok = l.p[3] >= 0.0f && l.p[3] <= 1e6f;
            if (ok && l.type == SEPAL_LOBE_HALF_AS)
                ok = l.p[0] >= 0.0f && l.p[1] >= 0.0f && l.p[0] <= 1e6f && l.p[1] <= 1e6f;
            if (ok && l.type == SEPAL_LOBE_HALF_WARD) ok = l.p[0] >= 1e-4f && l.p[1] >= 1e-4f && l.p[0] <= 10.0f && l.p[1] <= 10.0f;
            if (!ok)
                return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                                 "sampler: lobe %u has an unknown type, a bad weight or parameters out of range", k);
            sum += l.weight;
        }
        if (!(sum > 0.0f) || !isfinite(sum))
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "sampler: the lobe weights sum to %g", (double)sum);
    }
    return srt::ok(err);
}

extern "C" void sepal_sampler_set_view(const sepal_sampler* s, const float wo[3], sepal_sampler_view* v) {
    if (!v) return;
    memset(v, 0, sizeof *v);
    v->sampler = s;
    if (!s || !wo) {  // cosine sampling only, as for a view below the horizon
        v->wo[2] = 1.0f;
        v->defensive = 1.0f;
        v->count = 1;
        v->weight[0] = 1.0f;
        v->cdf[1] = 1.0f;
        v->fallback = 1;
        return;
    }
    float w[3] = {wo[0], wo[1], wo[2]};
    if (!srt::normalize3(w)) w[0] = 0, w[1] = 0, w[2] = 0;
    v->wo[0] = w[0], v->wo[1] = w[1], v->wo[2] = w[2];
    const sepal_smp_desc& d = s->desc;
    const float phi_o = (w[0] * w[0] + w[1] * w[1] > 1e-24f) ? azimuth(w[0], w[1]) : 0.0f;
    const float theta_o = acosf(clampf(w[2], 0.0f, 1.0f));
    if (d.phi_frame == SEPAL_SMP_PHI_VIEW) {
        v->cos_phi = cosf(phi_o), v->sin_phi = sinf(phi_o);
    } else if (s->kind == SEPAL_SAMPLER_FACTORED && view_axis(d.axis)) {
        // Half the view's angle about the axis (0 for a wo along the axis).
        const float b = 0.5f * atan2f(d.axis == SEPAL_SMP_AXIS_T_VIEW ? w[1] : w[0], w[2]);
        v->cos_phi = cosf(b), v->sin_phi = sinf(b);
    } else {
        v->cos_phi = 1.0f, v->sin_phi = 0.0f;
    }
    if (s->kind == SEPAL_SAMPLER_FACTORED && mirror_axis(d.axis))
        v->mirror = clampf(-(d.axis == SEPAL_SMP_AXIS_T_MIRROR ? w[0] : w[1]), -0.999f, 0.999f);
    v->defensive = d.defensive;
    v->count = 1;
    v->weight[0] = 1.0f;
    v->fallback = !(w[2] > 0.0f);
    float sum = 0.0f;
    switch (s->kind) {
        case SEPAL_SAMPLER_FACTORED: {
            const ViewLerp l = view_lerp(d.n_theta_o, d.n_phi_o, theta_o, phi_o);
            v->count = d.terms;
            for (uint32_t t = 0; t < d.terms; ++t) {
                v->weight[t] = lerp_at(s->F + t * d.n_theta_o * d.n_phi_o, l);
                sum += v->weight[t];
            }
            v->total = sum;
            if (s->colour_a)
                for (int c = 0; c < 3; ++c) v->colour[c] = lerp_at(s->colour_a + c * d.n_theta_o * d.n_phi_o, l);
            break;
        }
        case SEPAL_SAMPLER_LOBES: {
            v->count = d.lobe_count;
            for (uint32_t k = 0; k < d.lobe_count; ++k) {
                const sepal_smp_lobe& l = s->lobes[k];
                float g = 1.0f;
                if (l.type == SEPAL_LOBE_PHONG_AXIS) {
                    float a[3];
                    const float len = phong_axis(l, w, a);
                    // The lobe's integral over the sphere, |C o wo|^n 2 pi / (n + 1), in
                    // double: |C o wo| may exceed 1 and n reach 1e6.
                    const double gi = len > 0.0f ? pow((double)len, (double)l.p[3]) * 6.283185307179586 /
                                                       ((double)l.p[3] + 1.0)
                                                 : 0.0;
                    g = gi < 1e30 ? (float)gi : 1e30f;
                }
                v->weight[k] = l.weight * g;
                sum += v->weight[k];
            }
            v->fallback = v->fallback || !(sum > 0.0f) || !isfinite(sum);
            break;
        }
        case SEPAL_SAMPLER_TABULATED: {
            const uint32_t i = (uint32_t)clampf(theta_o / (0.5f * kPi) * (float)d.n_theta_o, 0.0f,
                                                (float)(d.n_theta_o - 1));
            const uint32_t j = d.phi_frame == SEPAL_SMP_PHI_VIEW ? 0 : phi_bin(phi_o, d.n_phi_o);
            v->table = i * d.n_phi_o + j;
            sum = 1.0f;
            break;
        }
        default: sum = 1.0f; v->defensive = 1.0f; break;
    }
    if (s->kind == SEPAL_SAMPLER_FACTORED) {
        // The Lambert part's albedo pi D against the terms' albedo sum_l F_l(wo): cosine
        // samples take its share (format 1.1). A view whose terms are all 0 is all diffuse:
        // the fallback below, cosine samples only, is then exact.
        const float rho = kPi * luminance3(d.diffuse);
        if (rho > 0.0f && sum > 0.0f && isfinite(sum)) v->defensive += (1.0f - v->defensive) * rho / (rho + sum);
        if (!(sum > 0.0f)) v->fallback = 1;
    }
    if (v->fallback) {
        v->defensive = 1.0f;
        return;
    }
    if (sum > 0.0f && v->count > 1) {
        float acc = 0.0f;
        for (uint32_t k = 0; k < v->count; ++k) {
            v->weight[k] /= sum;
            v->cdf[k] = acc;
            acc += v->weight[k];
        }
        v->cdf[v->count] = 1.0f;
    } else {
        v->weight[0] = 1.0f;
        v->cdf[0] = 0.0f, v->cdf[1] = 1.0f;
    }
}

extern "C" float sepal_sampler_pdf(const sepal_sampler_view* v, const float wi[3]) {
    if (!v || !wi) return 0.0f;
    const float e = v->sampler ? v->defensive : 1.0f;
    float p = e > 0.0f ? e * cosine_pdf(wi) : 0.0f;
    if (e >= 1.0f) return p;
    const sepal_sampler& s = *v->sampler;
    float rest = 0.0f;
    switch (s.kind) {
        case SEPAL_SAMPLER_FACTORED: rest = factored_pdf(v, wi); break;
        case SEPAL_SAMPLER_TABULATED: rest = tabulated_pdf(v, wi); break;
        case SEPAL_SAMPLER_LOBES:
            for (uint32_t k = 0; k < v->count; ++k)
                if (v->weight[k] > 0.0f) rest += v->weight[k] * lobe_pdf(s.lobes[k], v->wo, wi);
            break;
        default: break;
    }
    p += (1.0f - e) * rest;
    return isfinite(p) ? p : 0.0f;
}

extern "C" int sepal_sampler_sample(const sepal_sampler_view* v, const float u_in[2], float wi[3], float* pdf) {
    if (!v || !u_in || !wi || !pdf) {
        if (pdf) *pdf = 0.0f;
        return -1;
    }
    float u[2] = {unit_u(u_in[0]), unit_u(u_in[1])};
    const float e = v->sampler ? v->defensive : 1.0f;
    wi[0] = wi[1] = 0.0f, wi[2] = 1.0f;
    if (u[0] < e || e >= 1.0f) {
        u[0] = clampf(u[0] / e, 0.0f, kOneMinus);
        cosine_sample(u, wi);
    } else {
        const sepal_sampler& s = *v->sampler;
        float x = clampf((u[0] - e) / (1.0f - e), 0.0f, kOneMinus);
        const uint32_t k = pick(v->cdf, v->count, x, &x);
        switch (s.kind) {
            case SEPAL_SAMPLER_FACTORED: {
                const sepal_smp_desc& d = s.desc;
                float wv[3], wp[3];
                draw_coords(s.u_cdf + k * (d.n_theta_p + 1), s.v_cdf + k * (d.n_phi_p + 1), s.z_edges,
                            d.n_theta_p, d.n_phi_p, d.axis, v->mirror, x, u[1], wv);
                from_view(v, wv, wp);
                if (d.param == SEPAL_SMP_PARAM_HALF) reflect(v->wo, wp, wi);
                else wi[0] = wp[0], wi[1] = wp[1], wi[2] = wp[2];
                break;
            }
            case SEPAL_SAMPLER_TABULATED: {
                const sepal_smp_desc& d = s.desc;
                const float* t = view_table(s, v->table);
                float y;
                const uint32_t i = pick(t, d.n_theta_p, x, &y);
                // theta bin i from the marginal (x, rescaled to y within it), phi from its
                // conditional CDF (u[1]): z is y's position within the bin.
                const float* cond = t + (d.n_theta_p + 1) + i * (d.n_phi_p + 1);
                float tphi;
                const uint32_t j = pick(cond, d.n_phi_p, u[1], &tphi);
                const float phi = ((float)j + tphi) * kTwoPi / (float)d.n_phi_p;
                const float z = clampf(s.z_edges[i] + y * (s.z_edges[i + 1] - s.z_edges[i]), 0.0f, 1.0f);
                const float r = sqrtf(fmaxf(0.0f, 1.0f - z * z));
                const float wv[3] = {r * cosf(phi), r * sinf(phi), z};
                from_view(v, wv, wi);
                break;
            }
            case SEPAL_SAMPLER_LOBES: lobe_sample(s.lobes[k], v->wo, x, u[1], wi); break;
            default: cosine_sample(u, wi); break;
        }
    }
    if (!srt::normalize3(wi)) {
        *pdf = 0.0f;
        return -1;
    }
    // The density of the whole mixture, computed from wi exactly as sepal_sampler_pdf does,
    // so the two always agree.
    *pdf = sepal_sampler_pdf(v, wi);
    if (!(*pdf > 0.0f)) return -1;
    return wi[2] > 0.0f ? 1 : 0;
}

extern "C" int sepal_sampler_eval(const sepal_sampler_view* v, const float wi[3], float rgb[3]) {
    if (!rgb) return 0;
    rgb[0] = rgb[1] = rgb[2] = 0.0f;
    if (!v || !v->sampler || !wi) return 0;
    const sepal_sampler& s = *v->sampler;
    if (s.kind != SEPAL_SAMPLER_FACTORED || !(wi[2] > 0.0f) || !(v->wo[2] > 0.0f)) return 0;
    // The reconstruction: total(wo) x the factored density over wi (without the defensive
    // share), times the colour ratio ca(wo) cb(theta_p) cc(phi_p); plus D cos(theta_i).
    const float* D = s.desc.diffuse;
    const float cos_i = wi[2] / sqrtf(wi[0] * wi[0] + wi[1] * wi[1] + wi[2] * wi[2]);
    if (v->fallback) {  // all terms 0 at this view: f cos ~= D cos
        for (int c = 0; c < 3; ++c) rgb[c] = D[c] * cos_i;
        return 1;
    }
    const float lum = v->total * factored_pdf(v, wi, !s.desc.jacobian);
    if (!s.colour_a) {  // no colour tables: the luminance, grey
        const float g = lum + luminance3(D) * cos_i;
        rgb[0] = rgb[1] = rgb[2] = isfinite(g) ? g : 0.0f;
        return 1;
    }
    const sepal_smp_desc& d = s.desc;
    float wp[3], w[3], inv_j;
    if (d.param == SEPAL_SMP_PARAM_HALF) {
        if (!half_of(wi, v->wo, wp, &inv_j)) return 1;
    } else {
        wp[0] = wi[0], wp[1] = wi[1], wp[2] = wi[2];
    }
    to_view(v, wp, w);
    uint32_t i, j;
    float jacobian;
    factored_bin(v, w, &i, &j, &jacobian);
    for (int c = 0; c < 3; ++c)
        rgb[c] = lum * v->colour[c] * s.colour_b[c * d.n_theta_p + i] * s.colour_c[c * d.n_phi_p + j] + D[c] * cos_i;
    for (int c = 0; c < 3; ++c)
        if (!isfinite(rgb[c])) rgb[c] = 0.0f;
    return 1;
}
