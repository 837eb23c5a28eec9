// sepal_material.h - baked assets on the GPU: upload once, then draw frames.
//
// Usage (a port made a GL ES context current; caps from sepal_query_caps):
//   static sepal_asset asset;                      // parsed from the file's bytes
//   sepal_asset_parse(bytes, size, &asset, &err);
//   static sepal_material mat;
//   sepal_material_create(&caps, &asset, 512, 512, &mat, &err);   // textures uploaded here
//   size_t n = sepal_draw_scratch_floats(mesh.vertex_count, scene.light_count);
//   float* scratch = malloc(n * sizeof(float));   // once, at load (the runtime allocates nothing)
//   sepal_draw_desc d = {0}; d.material = &mat; d.mesh = &mesh; d.scene = &scene;
//   d.width = 512; d.height = 512; d.scratch = scratch; d.scratch_floats = n;
//   sepal_draw(&d, &stats, &err);                  // clears, draws all passes, scales up
//   sepal_material_destroy(&mat);
// sepal_draw is a frame of one object (sepal_frame.h): it clears the viewport (0, 0, width,
// height), draws the world-space mesh with the scene's camera, fills the background where
// the mesh is not, and leaves the GL state as it found it. For many objects, the engine's
// matrices, framebuffer and model matrices: sepal_frame.h.
//
// GL ES 2 (shaders/): the same plan with tiny shaders (SEPAL_MODE_MULTIPASS), or fused
// shaders summing every term in one pass per light, with per-vertex factor coordinates
// as in the paper (SEPAL_MODE_FUSED_VERTEX) or everything per pixel (SEPAL_MODE_FUSED_PIXEL,
// which also takes the rusinkiewicz and elevation/azimuth parameterizations). Fused
// passes clamp each light's f at 0, as the CPU backend does; more terms than the texture
// units hold are drawn in groups.
//
// How a frame is drawn on GL ES 1.1 (Kautz-McCool section 5): per vertex, on the CPU, the
// factors' texture coordinates from wi and wo in the vertex frame, and the light's
// irradiance cos(theta_i) I / d^2 as the vertex colour. The first pass (or a pre-pass in
// black) lays down depth; every pass of the asset's plan is then drawn once per light with
// depth test EQUAL: tex0 x tex1 x colour (two texture units, GL_MODULATE) added with blending, or
// subtracted. The framebuffer holds [0,1], so the colours carry an exposure 2^-m chosen per
// frame from the lights so that no partial sum exceeds 1; the final doublings (blend
// GL_DST_COLOR, GL_ONE) undo 2^-m and the plan's own scale. Plans that only add are drawn
// in stages of falling exposure, each pass at the largest its colours allow, with the
// doublings spread between the stages (so a huge peak's pass does not sink the others
// below one framebuffer level; same number of doublings). Doublings, inversions and the
// one-unit path's running sum are drawn over the object's own mesh with depth EQUAL, not
// as full-screen quads: only the object's visible pixels change.
// Fallback paths, each forced by a capability mask so tests run them on any driver:
//   - no GL_OES_blend_subtract: the framebuffer is inverted (1 - x, a blend with
//     GL_ONE_MINUS_DST_COLOR), the subtracted passes are added, and it is inverted back:
//     exact in 8 bits, and 2 passes over the object in all instead of an extension.
//   - one texture unit: the paper's two passes per product (G x colour, then H with a
//     multiplicative blend), the running sum kept in a texture (glCopyTexSubImage2D)
//     and added back by a pass over the object that reads it at each pixel's own position
//     (projective texture coordinates); the exposure also keeps colour x G below 1,
//     where GL clamps it before the blend.
// Reciprocal materials (format 2.1, homomorphic factors p(wi) q(h) p(wo)): a RECIPROCAL
// pass is drawn as a product pass (tex0 x tex1 on two units, or the one-unit path) whose
// vertex colour also carries the third lookup, tex0 at the swapped pair's coordinate (vh:
// p(wi)), sampled on the CPU per vertex and light from a copy of the texture kept in the
// material (bilinear at level 0, 8 bits), like the diffuse profile. GL ES 2 multipass does
// the same; the fused shaders read it from the texture (per pixel, or at per-vertex
// coordinates); the CPU backend per pixel.
// Framebuffer objects are not needed by any GL ES 1.1 path.
// Limits: viewport up to the size given at creation (copy textures are sized then);
// 16-bit assets are rounded to 8 bits at upload (GL ES 1.1 has no 16-bit textures).
//
// Thread safety: sepal_material_create, _destroy, _restore, sepal_draw and the
// sepal_texture_* functions call GL: only on the thread whose context is current, one call
// at a time per context (GL contexts are per thread), and a material only with the context
// it was created in; sepal_material_context_lost calls no GL but writes the material (not
// while another call uses it). sepal_draw_cpu calls no GL: any threads at once,
// each with its own buffers and scratch (the asset, mesh and scene may be shared: only read).
// The *_scratch_floats functions and sepal_read_float are pure.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "sepal/sepal_asset.h"
#include "sepal/sepal_rt.h"
#include "sepal/sepal_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

// A material on the GPU: opaque. What the runtime keeps per material (GL names, the plan,
// per-pass needs, shader programs, a reciprocal material's 8-bit G copies) is private and
// may change in any release; only the size is part of the ABI, with room for the inside to
// grow, so a sepal_material may be declared anywhere (static, in a struct, on the heap)
// and no call allocates. Read what an application needs with sepal_material_get_info.
#define SEPAL_MATERIAL_BYTES (56u * 1024u)
typedef struct sepal_material {
    uint64_t opaque_[SEPAL_MATERIAL_BYTES / 8];
} sepal_material;

typedef struct sepal_material_info {
    int created;       // 1 from a successful create (or restore) until destroy
    int gles_version;  // of the context it was created for
    int max_width, max_height;
    int float_target;  // drawn into its half-float target (sepal_material_create_float_target)
    int single_unit;   // one texture unit: products through a copy of the framebuffer
    int subtracts;     // the plan has subtracted passes
    int subtract_by_inversion;  // drawn by inverting the framebuffer (no blend subtract)
    int context_lost;  // sepal_material_context_lost was called; restore it
    int passes;        // the plan's passes per light
    int textures;
    uint32_t weaker_context;  // SEPAL_WEAKER_* bits of its context against the asset's profile
    // A framebuffer with fewer than 8 bits a channel (RGB565): each object's passes are summed
    // in an 8-bit target (GL ES 1.1: GL_OES_framebuffer_object; GL ES 2: core) and written
    // once, rounded to the framebuffer's bits; 0: each pass is rounded to them (no extension,
    // SEPAL_MASK_FBO, one texture unit on GL ES 1.1, a float target, or a target the context
    // could not make).
    int accumulates;
} sepal_material_info;
// Fills out (all zero for a material never created or destroyed); calls no GL.
void sepal_material_get_info(const sepal_material* m, sepal_material_info* out);

// Reads the last frame of a float-target material as linear RGBA floats, bottom row
// first (GL's order), width x height of the last draw. SEPAL_ERR_UNSUPPORTED without one.
// Values the half-float target could not hold come back clamped, never as inf or NaN:
// overflow (inf) as 65504, the largest half float, NaN as 0; *nonfinite_clamped (may be
// NULL) receives how many.
sepal_result sepal_read_float(const sepal_material* m, int width, int height, float* rgba, int* nonfinite_clamped,
                          sepal_error* err);

// How a material is drawn. GL ES 1.1 has only MULTIPASS.
typedef enum sepal_draw_mode {
    SEPAL_MODE_MULTIPASS = 0,     // the asset's pass plan (GL ES 1.1, or GL ES 2 tiny shaders)
    SEPAL_MODE_FUSED_VERTEX = 1,  // GL ES 2: one pass per light sums all terms; per-vertex coordinates
    SEPAL_MODE_FUSED_PIXEL = 2,   // GL ES 2: the same with everything per pixel (any parameterization)
} sepal_draw_mode;

sepal_result sepal_material_create(const sepal_caps* caps, const sepal_asset* asset, int max_width,
                               int max_height, sepal_material* out, sepal_error* err);
// The same with a half-float target of max_width x max_height (GL ES 2 on a GL ES 3
// context with caps.has_float_target; SEPAL_ERR_UNSUPPORTED otherwise): sepal_draw draws
// there with no exposure and no doublings (sepal_read_float reads it back), to measure what
// the 8-bit framebuffer costs. GPU memory: 10 bytes per pixel.
sepal_result sepal_material_create_float_target(const sepal_caps* caps, const sepal_asset* asset, int max_width,
                                                int max_height, sepal_material* out, sepal_error* err);
void sepal_material_destroy(sepal_material* m);

// GL context loss (EGL_CONTEXT_LOST on phones after a power event, or a context the app
// destroyed and recreated): every GL object of the material died with the context.
// sepal_material_context_lost forgets them without a GL call (there is no context to call);
// sepal_draw then refuses the material, and sepal_material_destroy makes no GL call either.
// With the new context current, sepal_material_restore uploads everything again from the
// same parsed asset (its bytes still alive, as for sepal_material_create) with the new
// context's caps: the material is as sepal_material_create left it, same viewport limit.
// No allocation. It refuses a material that was not lost (SEPAL_ERR_INVALID_ARGUMENT: its
// GL objects would leak) and an asset other than the one the material was created from.
// On any other failure the material is as after sepal_material_destroy.
//   if (eglGetError() == EGL_CONTEXT_LOST) {
//       sepal_material_context_lost(&mat);
//       ... create and make current a new context, sepal_query_caps(..., &caps, &err) ...
//       sepal_material_restore(&mat, &caps, &asset, &err);
//   }
void sepal_material_context_lost(sepal_material* m);
sepal_result sepal_material_restore(sepal_material* m, const sepal_caps* caps, const sepal_asset* asset,
                                    sepal_error* err);

// Floats of scratch sepal_draw needs (per-vertex texture coordinates, irradiance, colours).
size_t sepal_draw_scratch_floats(int vertex_count, int light_count);

typedef struct sepal_draw_desc {
    const sepal_material* material;
    const sepal_mesh* mesh;    // world space
    const sepal_scene* scene;
    int width, height;       // the viewport, at most the material's max size
    float* scratch;          // sepal_draw_scratch_floats() floats
    size_t scratch_floats;
    // Optional diffuse texture map modulating the result per pixel at the mesh's UVs
    // (Kautz-McCool Fig. 13): a GL texture name from sepal_texture_create_rgba8, or 0.
    // Multipass with three or more texture units (GL ES 1.1 combiner stage, GL ES 2 pass
    // shader) and a plan without subtractions: every pass is multiplied by it. Otherwise one
    // mesh pass multiplies the framebuffer, whose sum then needs headroom (more doublings:
    // banding in highlights under weights below 1). SEPAL_MASK_THIRD_UNIT forces the latter.
    uint32_t diffuse_texture;
    sepal_draw_mode mode;      // 0: multipass
} sepal_draw_desc;

// Uploads an RGBA8 image (top row first, power-of-two sides) with a MIP chain, for use
// as sepal_draw_desc.diffuse_texture. Delete it with sepal_texture_destroy.
sepal_result sepal_texture_create_rgba8(const uint8_t* rgba, int width, int height, uint32_t* out,
                                    sepal_error* err);
void sepal_texture_destroy(uint32_t texture);

// What a frame cost, and every repair, skip or clamp the runtime made on the way: nothing
// it does to odd input is silent. Units: GL backends count per vertex (and vertex-light
// pair) on the CPU side; the CPU backend counts vertices the same way and per pixel (and
// pixel-light pair) where it says so. The fused-pixel shader takes the same per-pixel
// fallbacks as the CPU backend but cannot count them: its counts are the per-vertex ones.
typedef struct sepal_draw_stats {
    int draw_calls;         // mesh passes, including the depth pre-pass
    // Framebuffer-wide operations: doublings, inversions, accumulations (each drawn over the
    // object's mesh, its visible pixels only), and sepal_draw's background and float-target
    // copy (full-screen).
    int fullscreen_passes;
    int copies;             // framebuffer-to-texture copies
    int doublings;          // final framebuffer doublings
    float exposure;         // 2^-m applied to the vertex colours (the first stage's, if staged)
    // GL ES 1.1, add-only plans: passes are drawn in stages of falling exposure with the
    // doublings between them, so a huge peak's pass does not push the others below one
    // framebuffer level (same total doublings). 1 when every pass shares one exposure.
    int exposure_stages;
    // Vertex-light pairs (CPU: pixel-light pairs) with the light or the eye below the
    // horizon of the shading frame (a back-facing frame included): that light adds 0 there.
    int below_horizon;
    // Lights dimmer at the mesh than the asset was baked for (irradiance I / d^2 at the
    // centre of the mesh's bounds, in the dimmest lit channel, below the material's
    // irradiance_min: sepal_format.h's light range): their highlights may show the white
    // level's flat grey plateau, or shift hue. Lights of zero intensity are not counted.
    int dim_lights;
    // Vertices whose tangent was zero, parallel to the normal or not finite (xyz or the
    // handedness w): any unit vector perpendicular to the normal is used, handedness +1.
    int fallback_tangents;
    // Vertices with a non-finite position or a zero or non-finite normal: they cannot be
    // placed or shaded, and every triangle using one is skipped (skipped_triangles).
    int bad_vertices;
    int skipped_triangles;
    // Triangles with repeated or collinear corners (zero area in world space). Drawn as
    // they are: GL and the CPU rasterizer cover no pixel with them.
    int zero_area_triangles;
    // Direction pairs (vertex-light; CPU: pixel-light) where the parameterization's frame
    // is undefined and a fixed one is used: gs-half with h within 1e-3 rad of the tangent,
    // rusinkiewicz with h within 1e-6 rad of the normal, h itself when wi = -wo.
    int param_fallbacks;
    // 1 when the plan paths needed an exposure below 2^-30 (irradiance times the largest
    // pass colour over 2^30): vertex colours clamp at 1 instead of the frame failing.
    int exposure_clamped;
    // Irradiance values (GL: vertex-light channels) or radiances (CPU: pixel channels)
    // that overflowed float or were NaN: clamped to FLT_MAX, NaN to 0. (Values a
    // half-float target overflowed are counted by sepal_read_float.)
    int nonfinite_clamped;
    // CPU only: pixel-light pairs where a signed factorization summed to f < 0 in some
    // channel, clamped to 0 as every backend does (GL cannot count them).
    int negative_clamped;
    // CPU only: pixels whose interpolated frame was degenerate (normals or tangents of
    // the triangle's corners cancelling out): the fallback frame is used.
    int pixel_frame_fallbacks;
    // 1 when the material's context is weaker than the device profile the asset was judged
    // for (sepal_profile_check: fewer framebuffer bits, a smaller texture limit, fewer
    // units): the frame is drawn, but not as the bake judged it.
    int weaker_context;
} sepal_draw_stats;

// ---- the device profile ------------------------------------------------------------------
// Whether a context holds the device profile an asset was judged for (asset->profile:
// sepal_format.h's PROF chunk, or the default profile; docs/devices.md). SEPAL_OK when it
// does; SEPAL_ERR_UNSUPPORTED with a message naming what is weaker when it does not: a
// channel with fewer framebuffer bits, a texture limit below the one the bake held the
// textures to, fewer texture units, or no blend subtraction for a plan that subtracts
// (judged with it). The asset still draws (sepal_draw_stats.weaker_context counts such
// frames), but not as the bake judged it: bake for that device's profile. Caps of 0 bits
// or size (not reported) are not counted as weaker. weaker (may be NULL) receives the
// SEPAL_WEAKER_* bits. Calls no GL; pure.
#define SEPAL_WEAKER_BITS 1u
#define SEPAL_WEAKER_TEXTURE_SIZE 2u
#define SEPAL_WEAKER_UNITS 4u
#define SEPAL_WEAKER_SUBTRACT 8u
sepal_result sepal_profile_check(const sepal_caps* caps, const sepal_asset* asset, uint32_t* weaker, sepal_error* err);

sepal_result sepal_draw(const sepal_draw_desc* desc, sepal_draw_stats* stats, sepal_error* err);

// ---- the CPU backend -------------------------------------------------------------------
// Renders the same scene from the asset in float with no GL: the software rasterizer
// (sepal_raster.h, pixel-aligned with GL), frames interpolated per pixel, the factors'
// coordinates per pixel (every parameterization), textures decoded as scale * q + bias
// and sampled bilinearly at level 0, f = sum_k G_k H_k evaluated directly (not through
// the pass plan) and clamped at 0 per light, radiance as in sepal_scene.h. For devices without a GPU and as the
// precise reference of the factored BRDF. No allocation: callers hand in the buffers;
// the asset's bytes must stay alive.
typedef struct sepal_cpu_desc {
    const sepal_asset* asset;
    const sepal_mesh* mesh;   // world space
    const sepal_scene* scene;
    int width, height;
    float* color;           // width * height * 3 floats out: linear radiance, top row first
    float* depth;           // width * height floats of scratch
    float* scratch;         // sepal_cpu_scratch_floats() floats
    size_t scratch_floats;
    // Optional diffuse map, as sepal_draw_desc.diffuse_texture: RGBA8, top row first,
    // bilinear at level 0 with repeat wrapping; NULL for none.
    const uint8_t* diffuse_rgba;
    int diffuse_width, diffuse_height;
    // Optional: the frame's counters (draw_calls 1, the repair, skip and clamp counts).
    sepal_draw_stats* stats;
} sepal_cpu_desc;

size_t sepal_cpu_scratch_floats(int vertex_count);
sepal_result sepal_draw_cpu(const sepal_cpu_desc* desc, sepal_error* err);

#ifdef __cplusplus
}
#endif
