// Runtime internals shared by its translation units (not part of the API).
#pragma once
#include <math.h>
#include <string.h>
#include "sepal/sepal_rt.h"
#include "sepal/sepal_asset.h"
#include "sepal/sepal_scene.h"

namespace srt {

// Fills err (may be NULL) and returns code: `return fail(err, SEPAL_ERR_GL, "...", ...);`
sepal_result fail(sepal_error* err, sepal_result code, const char* fmt, ...)
    __attribute__((format(printf, 3, 4)));

inline sepal_result ok(sepal_error* err) {
    if (err) {
        err->code = SEPAL_OK;
        err->message[0] = '\0';
    }
    return SEPAL_OK;
}

// Whole-word search in a space-separated GL extension string.
bool has_extension(const char* list, const char* name);

// The GL ES major version of a GL_VERSION string, or 0 when it is not GL ES. Drivers spell
// GL ES 1.x differently: the spec's "OpenGL ES-CM 1.1 ..." (Mesa) or "OpenGL ES 1.1 ..."
// (NVIDIA), so the profile suffix is optional and the number decides.
int gles_major_version(const char* version);

// ---- small vector maths shared by the backends ----
inline float dot3(const float* a, const float* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
// sepal_diffuse_profile's three channels at once (the bilinear weights found once): the
// per-vertex colours and the CPU backend call it per vertex or pixel and light.
// layout: sepal_fmt_diffuse_layout (the runtime's own copy is RGB_F32).
float diffuse_sample(const void* profile, uint32_t layout, size_t k, int c);
void diffuse_profile_rgb(const void* profile, uint32_t side, uint32_t layout, float cos_i, float cos_o, float out[3]);

// Below this gs-half's frame is undefined (a fallback is taken and counted): |t'|^2 =
// 1 - h.x^2 (h within 1e-3 rad of the tangent). param.cpp, the batched set-up and
// shaders/fused_pixel.frag use it.
constexpr float kGsMin2 = 1e-6f;

// Normalizes v in place; false (v unchanged) when it is too short to have a direction.
// Inline: the per-vertex set-up calls it several times per vertex and light.
inline bool normalize3(float* v) {
    const float l = sqrtf(dot3(v, v));
    if (!(l > 1e-20f) || !isfinite(l)) return false;
    const float inv = 1.0f / l;  // one divide: the set-up runs per vertex and light, every frame
    v[0] *= inv, v[1] *= inv, v[2] *= inv;
    return true;
}

// An orthonormal shading frame (t, s, n) from a (possibly interpolated) normal and a
// tangent with handedness in w: Gram-Schmidt, with fallbacks where the input cannot give
// one. Returns the fallbacks taken (0 for none):
//   kFrameNormalFallback: the normal is zero or not finite; n = +z (world) is used;
//   kFrameTangentFallback: the tangent is zero, within 1e-6 of parallel to n, or not
//     finite: t = the x (or y) axis made perpendicular to n; or its handedness w is not
//     finite: +1. (A finite w keeps its sign, as in the exact renderer.)
enum { kFrameNormalFallback = 1, kFrameTangentFallback = 2 };
struct ShadingFrame {
    float t[3], s[3], n[3];
    void to_local(const float* w, float* out) const {
        out[0] = dot3(w, t), out[1] = dot3(w, s), out[2] = dot3(w, n);
    }
};
int shading_frame(const float normal[3], const float tangent[4], ShadingFrame* f);

// A vertex can be drawn and shaded: finite position, finite normal of non-zero length.
bool vertex_usable(const sepal_vertex& v);
// The normal and tangent every backend interpolates for a usable vertex: the mesh's own,
// except a tangent shading_frame would replace (kFrameTangentFallback), which becomes
// that replacement (unit, perpendicular to n, w = +-1), so per-vertex and per-pixel
// backends interpolate the same thing. Also gives the vertex's frame (one shading_frame
// call). Returns true when the tangent was replaced.
bool repaired_attributes(const sepal_vertex& v, float normal[3], float tangent[4], ShadingFrame* frame);

// Texture coordinates of a direction pair for any parameterization (param.cpp), with the
// number of frame fallbacks taken (0 or 1) added to *fallbacks. Returns 1 above the
// horizon, 0 below, -1 for a per-pixel-only parameterization when per_pixel is false.
int param_texcoords(sepal_param p, sepal_hemi_map m, const float wi[3], const float wo[3], float g[2],
                    float h[2], bool per_pixel, int* fallbacks);
// atan2(y, x) in float without branches (selects only, so the batched vertex set-up
// vectorizes it; libm's atan2f and asinf do not, and cost 5.7x gs-half's whole set-up):
// an odd minimax polynomial of degree 13 for atan on [0, 1] after reduction by octant,
// within 5e-7 rad of atan2 (the polynomial 3.3e-7, float rounding the rest; tested in
// tests/extremes_test.cpp); +-0 for y = x = 0 (libm: 0 or pi).
inline float atan2_poly(float y, float x) {
    const float ax = fabsf(x), ay = fabsf(y);
    const float hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
    const float t = hi > 0.0f ? lo / hi : 0.0f;
    const float t2 = t * t;
    float p = 0.00681176409f;
    p = p * t2 - 0.0336041413f;
    p = p * t2 + 0.0796235949f;
    p = p * t2 - 0.132333398f;
    p = p * t2 + 0.198078156f;
    p = p * t2 - 0.333173692f;
    p = p * t2 + 0.999996126f;
    float a = t * p;
    a = ay > ax ? 1.57079637f - a : a;
    a = x < 0.0f ? 3.14159274f - a : a;
    return copysignf(a, y);  // -0 as libm has it: atan2(-0, -1) = -pi
}

// axis (param.cpp): one direction's coordinates, alpha / pi + 1/2 and beta / pi + 1/2 with
// alpha = atan2(a.x, |(a.y, a.z)|) (asin(a.x) for a unit a, without asin's loss near the
// poles) and beta = atan2(a.y, a.z), 0 at a = +-t (a.y = a.z = 0, on the horizon). Below the
// horizon beta is clamped to +-pi/2 (the texture's edge, as CLAMP_TO_EDGE reads it), so
// coordinates stay continuous for interpolation except across a.y = 0, a.z < 0 (light or
// view far behind the surface, where nothing is lit).
inline void axis_uv(float a0, float a1, float a2, float* alpha_u, float* beta_u) {
    const float kInvPi = 0.318309886f;
    const float r = sqrtf(a1 * a1 + a2 * a2);
    *alpha_u = atan2_poly(a0, r) * kInvPi + 0.5f;
    const float b = atan2_poly(a1, a2) * kInvPi + 0.5f;
    *beta_u = b < 0.0f ? 0.0f : b > 1.0f ? 1.0f : b;
}

// gs-mirror's H point d (wo in the frame about r) behind r's horizon (wo.r < 0: light and eye
// on the same side, far from the normal) has no place in a hemisphere map, whose XY form would
// fold it onto its mirror image (wo = -r onto the lobe's peak): it is taken to the rim, the
// value at wo.r = 0 (offline/factor/param.h). Branch-free for the batched set-up.
inline void mirror_rim(float d[3]) {
    const float l2 = d[0] * d[0] + d[1] * d[1];
    const bool behind = d[2] < 0.0f, flat = !(l2 > 1e-24f);
    const float inv = 1.0f / sqrtf(flat ? 1.0f : l2);
    d[0] = behind ? (flat ? 1.0f : d[0] * inv) : d[0];
    d[1] = behind ? (flat ? 0.0f : d[1] * inv) : d[1];
    d[2] = behind ? 0.0f : d[2];
}

// True for the parameterizations whose coordinates may be computed per vertex and
// interpolated (iv, gs-half, vh, axis, gs-mirror): GL ES 1.1 and the per-vertex GL ES 2 paths.
inline bool param_per_vertex(sepal_param p) {
    return p == SEPAL_PARAM_IV || p == SEPAL_PARAM_GS_HALF || p == SEPAL_PARAM_VH || p == SEPAL_PARAM_AXIS ||
           p == SEPAL_PARAM_GS_MIRROR;
}

// Unit direction from a surface point towards a light, and the light's falloff there
// (1/d^2 for point lights, 1 for directional ones).
float light_direction(const struct sepal_light& light, const float position[3], float dir[3]);

// Texture units a pass reads: PRODUCT and RECIPROCAL 2 (a reciprocal pass's third lookup
// is per vertex, in its colour: vertex_setup.h), TEXTURE 1, CONSTANT and DIFFUSE none.
inline int pass_texture_count(const sepal_fmt_pass& p) {
    return p.op == SEPAL_OP_PRODUCT || p.op == SEPAL_OP_RECIPROCAL ? 2 : p.op == SEPAL_OP_TEXTURE ? 1 : 0;
}
// GL ES 1.1 clamps vertex colours at 1: passes send colour / boost and scale by 4 in their
// last combiner stage (GL_RGB_SCALE accepts 1, 2 or 4), boost = 4 / rgb_scale. An untextured
// pass (DIFFUSE, CONSTANT) gets its stage by binding any of the material's textures to unit 0
// with the combiner replacing by the primary colour: without it the diffuse colour
// E cos D clamped at 1 and the whole frame went to 1/4 exposure and 2 doublings (velvet:
// 4-level rings). A material without textures has nothing to bind: boost 1.
inline float pass_color_boost(const sepal_fmt_pass& p, uint32_t material_textures) {
    return pass_texture_count(p) == 0 && material_textures == 0 ? 1.0f : 4.0f / (float)p.rgb_scale;
}

// Returns SEPAL_OK, or drains GL's error flags and fills err naming `what`. Works on
// either GL ES version (glGetError is common to both).
sepal_result gl_check(const char* what, sepal_error* err);

// The asset's factor textures by term (asset_eval.cpp), found once per frame.
struct AssetTerms {
    const sepal_asset_texture* g[SEPAL_FMT_MAX_TERMS];
    const sepal_asset_texture* h[SEPAL_FMT_MAX_TERMS];
};
void find_terms(const sepal_asset& a, AssetTerms* t);
struct PairCounts {
    int param_fallbacks = 0, negative_clamped = 0;
};
// f cos(theta_i) of one direction pair as the CPU backend draws it (sepal_asset_eval):
// false, and 0, when either direction is at or below the horizon.
bool eval_pair(const sepal_asset& a, const AssetTerms& t, const float wi[3], const float wo[3], float f_cos[3],
               PairCounts* counts);

// True for an asset sepal_asset_parse filled (a zeroed or never-parsed one has no magic, no
// terms and no passes): what the draw entry points take.
inline bool asset_parsed(const sepal_asset& a) {
    return memcmp(a.header.magic, SEPAL_FMT_MAGIC, 8) == 0 && a.material.terms >= 1 && a.plan.pass_count >= 1 &&
           a.plan.pass_count <= SEPAL_FMT_MAX_PASSES && a.texture_count >= 1 && a.texture_count <= SEPAL_FMT_MAX_TEXTURES;
}

}  // namespace srt
