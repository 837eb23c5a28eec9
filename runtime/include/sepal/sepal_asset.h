// sepal_asset.h - reading .sepal assets (sepal_format.h is the format's data), evaluating
// one at a direction pair, the parameterizations' texture coordinates and the format's checksum.
//
// Usage (bytes: a whole .sepal file the caller read; it must outlive the asset):
//   static sepal_asset asset;                       // ~13 KB: keep it static
//   sepal_error err = {SEPAL_OK, ""};
//   if (sepal_asset_parse(bytes, size, &asset, &err) != SEPAL_OK) { puts(err.message); }
//   printf("%u passes\n", (unsigned)asset.plan.pass_count);
//   float wi[3] = {0, 0, 1}, wo[3] = {0.6f, 0, 0.8f}, fc[3];
//   if (sepal_asset_eval(&asset, wi, wo, fc) == 1) printf("f cos %g\n", fc[0]);
//
// Limits: a little-endian host; files up to SEPAL_FMT_MAX_FILE_BYTES. No allocation.
//
// Thread safety: sepal_asset_parse, sepal_asset_eval, sepal_diffuse_profile,
// sepal_horizon_window, sepal_param_texcoords(_pixel) and sepal_crc32 keep no state: any
// threads may call them at once (sepal_asset_parse on distinct outputs). A parsed
// sepal_asset is only read afterwards and may be shared between threads (and materials)
// while its bytes stay alive.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "sepal/sepal_format.h"
#include "sepal/sepal_rt.h"

#ifdef __cplusplus
extern "C" {
#endif

// ---- reading (runtime/src/asset.cpp) ------------------------------------------------------
// A parsed asset: descriptions copied out, pixel data and META pointing into the caller's
// buffer (which must outlive it). No allocation.
typedef struct sepal_asset_texture {
    sepal_fmt_texture desc;
    const uint8_t* level_data[SEPAL_FMT_MAX_LEVELS];  // level 0 first
    uint32_t level_bytes[SEPAL_FMT_MAX_LEVELS];
} sepal_asset_texture;

typedef struct sepal_asset {
    sepal_fmt_header header;
    sepal_fmt_material material;
    sepal_fmt_plan plan;
    sepal_asset_texture textures[SEPAL_FMT_MAX_TEXTURES];
    uint32_t texture_count;
    sepal_fmt_pass passes[SEPAL_FMT_MAX_PASSES];
    const char* meta;  // not NUL-terminated; NULL when absent
    uint32_t meta_bytes;
    // The diffuse profile: side * side samples in the caller's buffer, stored as
    // diffuse_layout says (sepal_fmt_diffuse_layout; read them through sepal_diffuse_profile
    // or with memcpy: no alignment is promised), or NULL with side 0 (profile 1 everywhere).
    const uint8_t* diffuse_profile;
    uint32_t diffuse_side;
    uint32_t diffuse_layout;
    // The device profile it was judged for (format 2.4's PROF chunk), or without the chunk
    // the default profile (sepal_format.h): has_profile says which.
    sepal_fmt_profile profile;
    uint32_t has_profile;
} sepal_asset;

// The diffuse profile at (cos theta_i, cos theta_o), channel c (bilinear, clamped to [0,1]
// in both, NaN read as 0); 1 without a profile. profile: side * side samples in `layout`
// (sepal_fmt_diffuse_layout; any alignment), e.g. an asset's diffuse_profile, diffuse_side
// and diffuse_layout.
float sepal_diffuse_profile(const void* profile, uint32_t side, uint32_t layout, float cos_i, float cos_o, int c);

// The horizon window of a radiance material (format 2.7; sepal_fmt_material.horizon = c0):
// min(1, cos_i / c0) for cos_i > 0, 0 at and below the horizon; 1 above it when c0 is 0 (no
// window). What a light's irradiance E is multiplied by before the factors' sum.
float sepal_horizon_window(float horizon, float cos_i);

// Validates everything (sizes, bounds, checksums, enums, cross references) and fills
// out. Any failure returns a code and a message naming the problem; out is then
// unspecified. Needs a little-endian host (every supported target is).
sepal_result sepal_asset_parse(const void* bytes, size_t size, sepal_asset* out, sepal_error* err);

// ---- evaluation (runtime/src/asset_eval.cpp) ---------------------------------------------
// What the asset draws for one direction pair in the local frame (n = +z, t = +x, both
// directions unit and pointing away from the surface), per unit irradiance: f cos(theta_i)
// in f_cos[3], computed as the CPU backend computes each pixel and light (the same code):
//   s_c  = ratio_c * sum_k G_k(x) H_k(y) [G_k(x~) for reciprocal materials], at least 0,
//          textures decoded as scale * q + bias and sampled bilinearly at level 0;
//   f_cos_c = s_c (radiance materials: the factors hold f cos) or s_c cos(theta_i)
//          (otherwise), plus diffuse_c * cos(theta_i) * profile_c(cos_i, cos_o).
// The white level (material.white_level) is not applied: the bake capped f cos there and
// the display clips what a light makes of it; f = f_cos / cos(theta_i).
// Returns 1 when both directions are above the horizon, 0 otherwise (f_cos is 0), -1 for a
// NULL pointer or an asset sepal_asset_parse did not fill (nothing written).
int sepal_asset_eval(const sepal_asset* asset, const float wi[3], const float wo[3], float f_cos[3]);

// ---- parameterization (runtime/src/param.cpp) --------------------------------------------
// Texture coordinates of the G and H factors for one direction pair in the local frame
// (n = +z, t = +x), for the per-vertex parameterizations (iv, gs-half, vh, axis, gs-mirror); the same
// maths as offline/factor/param.h. Returns 1 when both directions are above the horizon, 0
// otherwise (coordinates are still filled and continuous, for interpolation).
// Returns -1 for the per-pixel-only parameterizations, and for an unknown parameterization or
// map or a NULL pointer (nothing is written then).
int sepal_param_texcoords(sepal_param p, sepal_hemi_map m, const float wi[3], const float wo[3],
                        float g_uv[2], float h_uv[2]);
// The same for every parameterization, including the per-pixel-only ones: rusinkiewicz
// (G = map(h), H = map(d), d = rot_y(-theta_h) rot_z(-phi_h) wi) and elev-azim
// (G at (theta_i, theta_o) / (pi/2), H at (phi_i, phi_o) / (2 pi), H periodic).
int sepal_param_texcoords_pixel(sepal_param p, sepal_hemi_map m, const float wi[3], const float wo[3],
                              float g_uv[2], float h_uv[2]);

// CRC-32 (polynomial 0xEDB88320, initial and final xor 0xFFFFFFFF): chain calls by
// passing the previous result as crc, starting from 0.
uint32_t sepal_crc32(uint32_t crc, const void* data, size_t size);

#ifdef __cplusplus
}
#endif
