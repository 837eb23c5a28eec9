// The state behind the opaque srt::Material (internal): what sepal_material_create sets up
// and the draws read.
#pragma once
#include <stdint.h>

#include "sepal/sepal_material.h"

namespace srt {

struct Material {
    sepal_caps caps;
    sepal_fmt_material info;
    sepal_fmt_plan plan;
    sepal_fmt_pass passes[SEPAL_FMT_MAX_PASSES];
    uint32_t texture_count;
    uint32_t gl_textures[SEPAL_FMT_MAX_TEXTURES];
    uint32_t texture_role[SEPAL_FMT_MAX_TEXTURES];
    uint32_t term_textures[SEPAL_FMT_MAX_TERMS][2];  // per term: its G and H texture index
    float texture_scale[SEPAL_FMT_MAX_TEXTURES][3];  // decode: scale * q + bias (fused shaders)
    float texture_bias[SEPAL_FMT_MAX_TEXTURES][3];
    // GL ES 1.1: per pass, the largest value GL clamps at 1 (vertex colour, or colour x tex0
    // on one texture unit) per unit irradiance: what its exposure must keep below 1.
    float pass_need[SEPAL_FMT_MAX_PASSES];
    // A radiance material's diffuse profile (format 2), copied: the DIFFUSE pass's vertex
    // colours are computed from it every frame. side 0: none (1 everywhere).
    float diffuse_profile[SEPAL_FMT_MAX_DIFFUSE_SIDE * SEPAL_FMT_MAX_DIFFUSE_SIDE * 3];
    uint32_t diffuse_side;
    uint32_t diffuse_texture;  // GL ES 2: the profile as an RGB texture (fused per-pixel), or 0
    // A reciprocal material (format 2.1): per term, its G texture's level 0 in 8 bits (16-bit
    // assets rounded as the upload rounds them), for the RECIPROCAL passes' per-vertex third
    // lookup; texture_term maps a texture index to its term.
    uint8_t reciprocal_g[SEPAL_FMT_MAX_RECIPROCAL_TERMS]
                        [SEPAL_FMT_MAX_RECIPROCAL_SIDE * SEPAL_FMT_MAX_RECIPROCAL_SIDE * 3];
    uint32_t reciprocal_width[SEPAL_FMT_MAX_RECIPROCAL_TERMS], reciprocal_height[SEPAL_FMT_MAX_RECIPROCAL_TERMS];
    uint32_t texture_term[SEPAL_FMT_MAX_TEXTURES];
    int single_unit;          // one texture unit: products through the copy texture
    int subtract_by_inversion;  // no blend subtract: invert, add, invert back
    int has_negative_passes;
    uint32_t copy_texture;    // running sum (single-unit path), 0 when unused
    int copy_width, copy_height;  // power-of-two size of the copy texture
    int max_width, max_height;
    // GL ES 2: shader programs compiled at creation (0 on GL ES 1.1).
    uint32_t program_pass, program_fullscreen, program_mesh_texture, program_accumulated;
    uint32_t program_fused_vertex, program_fused_pixel;
    int fused_group;  // terms summed per fused pass: min(terms, texture units / 2, 8)
    // Half-float target (sepal_material_create_float_target): frames are drawn there with no
    // exposure and no doublings, then copied to the current framebuffer for display.
    int float_target;
    uint32_t float_fbo, float_color, float_depth;
    // A framebuffer with fewer than 8 bits a channel (srt::accumulates): the passes are
    // summed in this 8-bit target (colour texture and depth renderbuffer, a power of two at
    // least max_width x max_height) and written to the framebuffer once, rounded. 0 when
    // unused.
    uint32_t acc_fbo, acc_color, acc_depth;
    int acc_width, acc_height;
    // Set by sepal_material_context_lost: the GL names above belong to a dead context.
    int context_lost;
    // SEPAL_WEAKER_* bits of the context against the asset's device profile.
    uint32_t weaker;
};
static_assert(sizeof(Material) <= sizeof(sepal_material), "sepal_material's storage (SEPAL_MATERIAL_BYTES) is too small");
static_assert(alignof(Material) <= alignof(sepal_material), "sepal_material's storage is not aligned for it");

// The runtime's view of a caller's storage (the only casts between the two).
inline Material* material(sepal_material* m) { return reinterpret_cast<Material*>(m); }
inline const Material* material(const sepal_material* m) { return reinterpret_cast<const Material*>(m); }
inline sepal_material* storage(Material* m) { return reinterpret_cast<sepal_material*>(m); }
inline const sepal_material* storage(const Material* m) { return reinterpret_cast<const sepal_material*>(m); }

}  // namespace srt
