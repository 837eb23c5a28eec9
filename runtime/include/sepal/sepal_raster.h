// sepal_raster.h - a small software triangle rasterizer with GL's conventions.
//
// Usage:
//   static float depth[W * H];                // caller-owned depth buffer
//   sepal_raster_target t = {W, H, depth};
//   sepal_raster_clear_depth(&t);
//   sepal_raster_desc d = {0};
//   d.clip = clip_positions; d.vertex_count = n_vertices;  // float[4] per vertex (after projection)
//   d.varyings = attributes; d.varying_count = 5; d.varying_stride = 5;  // floats per vertex
//   d.indices = idx; d.index_count = n;
//   d.fragment = shade; d.user = &my_state;   // called per covered pixel that passes depth
//   sepal_raster_triangles(&t, &d, &err);
//
// Conventions, chosen so its images line up pixel for pixel with GL's: the viewport is
// the whole target; window x = (ndc.x + 1) W / 2, window y = (ndc.y + 1) H / 2 with y up
// (the fragment callback receives the row counted from the TOP, like images); pixel
// centres at +0.5; vertex positions snapped to 1/256 pixel and exact integer edge
// functions with the top-left fill rule, so shared edges are drawn once; perspective-
// correct interpolation of varyings; depth in [0, 1] tested with LEQUAL (or LESS) and
// written when the test passes. Triangles are clipped against the near plane (z = -w)
// only; x/y are limited by the target (scissored, no clipping needed).
// Limits: targets up to 8192 x 8192, up to 32 varyings per vertex, 65535 vertices.
// No allocation; callers provide all memory. Not thread-safe per target.
//
// Thread safety: no global state; calls on distinct targets may run at once, calls on one
// target may not (the depth buffer is written).
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "sepal/sepal_rt.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SEPAL_RASTER_MAX_VARYINGS 32

typedef struct sepal_raster_target {
    int width, height;
    float* depth;  // width * height floats, row 0 = bottom (GL's window rows)
} sepal_raster_target;

// x: column from the left; y: row from the top; varyings: perspective-correct values.
// depth: the fragment's window depth in [0, 1].
typedef void (*sepal_fragment_fn)(void* user, int x, int y, float depth, const float* varyings);

typedef enum sepal_cull { SEPAL_CULL_NONE = 0, SEPAL_CULL_BACK = 1 } sepal_cull;
typedef enum sepal_depth_func { SEPAL_DEPTH_LEQUAL = 0, SEPAL_DEPTH_LESS = 1, SEPAL_DEPTH_ALWAYS = 2 } sepal_depth_func;

typedef struct sepal_raster_desc {
    const float* clip;        // 4 floats per vertex: clip-space x, y, z, w
    int vertex_count;
    const float* varyings;    // varying_stride floats per vertex (may be NULL if count 0)
    int varying_count;        // 0..SEPAL_RASTER_MAX_VARYINGS
    int varying_stride;       // >= varying_count
    const uint16_t* indices;  // triangles
    int index_count;
    sepal_cull cull;            // counter-clockwise triangles face the viewer, as in GL
    sepal_depth_func depth_func;
    int no_depth_write;       // 0: passing fragments write depth (GL's default)
    sepal_fragment_fn fragment;
    void* user;
} sepal_raster_desc;

void sepal_raster_clear_depth(sepal_raster_target* t);
sepal_result sepal_raster_triangles(sepal_raster_target* t, const sepal_raster_desc* d, sepal_error* err);

#ifdef __cplusplus
}
#endif
