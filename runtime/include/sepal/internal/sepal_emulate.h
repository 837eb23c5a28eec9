// sepal/internal/sepal_emulate.h - the GL ES 1.1 emulator: what sepal_draw shows on a GL ES
// context, computed on the CPU. Internal: for sepal's own tools (the bake ranks its candidates
// with it, `sepal render --backend gles1-model`, ports/common's scene renders) and tests. It
// is not installed and not in libsepal.so or libsepal.a; it links from build/lib/
// libsepal_emulate.a, before the runtime's library, and may change with any release.
//
// Usage:
//   sepal_emulate_desc e = {0};
//   e.asset = &asset; e.mesh = &mesh; e.scene = &scene; e.width = w; e.height = h;
//   e.gles_version = 1; e.rgba = rgba;                 // w * h * 4 bytes, top row first
//   e.scratch_floats = sepal_emulate_scratch_floats(w, h, mesh.vertex_count, scene.light_count);
//   e.scratch = scratch;                               // that many floats
//   if (sepal_emulate_draw(&e, &err) != SEPAL_OK) puts(err.message);
//
// Limits: as below (no one-texture-unit path, no diffuse texture maps). Thread safety: no GL
// and no global state: any threads at once, each with its own buffers and scratch.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "sepal/sepal_frame.h"
#include "sepal/sepal_material.h"

#ifdef __cplusplus
extern "C" {
#endif

// ---- the GL ES 1.1 emulator ------------------------------------------------------------
// What sepal_draw shows on a GL ES 1.1 context (or the GL ES 2 multipass path), computed on
// the CPU with the same frame preparation and the GL pipeline's arithmetic: 8-bit texels
// with MIP levels chosen from 2x2-quad derivatives, vertex colours clamped to [0,1],
// perspective-correct interpolation, combiner stages clamped and scaled, every pass rounded
// to the framebuffer's bits, saturating blends, doublings and inversions. The bake ranks its
// candidates with it (a GL context per candidate would cost more and depend on the driver);
// tests/runtime/emulate_test.cpp holds it to llvmpipe's images. Deterministic, single
// threaded, no allocation (callers hand in the buffers). Not emulated: the one-texture-unit
// path (SEPAL_MASK_MULTITEXTURE is refused) and diffuse texture maps.
// Framebuffer bits: red_bits, green_bits and blue_bits (1..8; 0 means 8) are the colour
// buffer's, as sepal_caps reports them. With fewer than 8, the plan is summed in 8 bits and
// written once, rounded to nearest, as the runtime does on a context with framebuffer objects;
// mask SEPAL_MASK_FBO for the per-pass path, where each pass and full-screen step blends in 8 bits
// against the stored value and keeps the top bits of the result: GL's rule with GL_DITHER
// off (each component truncated to the framebuffer's bits) and what llvmpipe does with it
// on; rgba receives the stored values widened to 8 bits by repeating their bits, as
// glReadPixels returns them. Dithering (a position-dependent choice between the two nearest
// values, unspecified by GL) is not modelled (docs/ports.md, "Framebuffer bits").
typedef struct sepal_emulate_desc {
    const sepal_asset* asset;
    const sepal_mesh* mesh;   // world space
    const sepal_scene* scene;
    int width, height;
    int gles_version;         // 1: GL ES 1.1; 2: the GL ES 2 multipass path
    uint32_t mask;            // SEPAL_MASK_BLEND_SUBTRACT: subtraction by inversion
    uint8_t* rgba;            // width * height * 4 bytes out, top row first
    float* scratch;           // sepal_emulate_scratch_floats() floats
    size_t scratch_floats;
    sepal_draw_stats* stats;  // optional: the frame's counters, as sepal_draw reports them
    int red_bits, green_bits, blue_bits;  // the framebuffer's bits per channel; 0 means 8
} sepal_emulate_desc;

size_t sepal_emulate_scratch_floats(int width, int height, int vertex_count, int light_count);
sepal_result sepal_emulate_draw(const sepal_emulate_desc* desc, sepal_error* err);

// ---- the same frame through the GL ES emulator ----------------------------------------
// As sepal_emulate_draw, one object at a time into rgba (width x height x 4 bytes, top row
// first) and depth (width x height floats, kept between objects; sepal_frame_clear_cpu
// with color NULL sets it). scratch: sepal_emulate_scratch_floats(w, h, vertices, lights).
sepal_result sepal_frame_emulate(const sepal_frame_desc* desc, const sepal_object* object, int gles_version,
                                 uint32_t mask, uint8_t* rgba, float* depth, float* scratch, size_t scratch_floats,
                                 sepal_draw_stats* stats, sepal_error* err);

#ifdef __cplusplus
}
#endif
