// sepal_frame.h - a frame of many objects in the engine's framebuffer, with its matrices.
//
// Usage (GL ES 1.1 or 2; the engine has drawn its sky, floor and UI already):
//   static float scratch[1 << 20];                  // >= sepal_draw_scratch_floats of the largest object
//   sepal_frame_desc fd = {0};
//   fd.caps = &caps;                                // the context's, from sepal_query_caps
//   memcpy(fd.view, view, sizeof fd.view);          // the engine's, column-major
//   memcpy(fd.projection, proj, sizeof fd.projection);
//   fd.viewport[2] = width; fd.viewport[3] = height;
//   fd.scratch = scratch; fd.scratch_floats = sizeof scratch / sizeof scratch[0];
//   sepal_frame frame;
//   sepal_frame_begin(&frame, &fd, &err);          // saves the GL state it will touch
//   sepal_object o = {0};
//   o.material = &mat; o.mesh = &mesh; o.lights = lights; o.light_count = 2;
//   sepal_model_identity(o.model); o.model[12] = 1.5f;   // object to world
//   sepal_frame_draw(&frame, &o, &stats, &err);    // as many objects as you like
//   sepal_vertex_data vd;                           // or the engine's own vertices, in place:
//   memset(&vd, 0, sizeof vd);
//   vd.position.data = vd.normal.data = vd.tangent.data = vd.uv.data = engine_vertices;
//   vd.position.stride = vd.normal.stride = vd.tangent.stride = vd.uv.stride = sizeof engine_vertices[0];
//   vd.position.offset = offsetof(struct engine_vertex, p);
//   vd.normal.offset = offsetof(struct engine_vertex, n);
//   vd.tangent.offset = offsetof(struct engine_vertex, t);
//   vd.uv.offset = offsetof(struct engine_vertex, uv);
//   vd.vertex_count = vertex_count; vd.indices = engine_indices; vd.index_count = index_count;
//   o.mesh = NULL; o.vertices = &vd;
//   o.model[0] = 2.0f; o.model[4] = 0.5f;           // any affine model with det > 0
//   sepal_frame_draw(&frame, &o, &stats, &err);
//   sepal_frame_end(&frame, &err);                 // GL state back as found
//
// What a frame does to the framebuffer: nothing unless fd.clear asks for a clear (colour
// to fd.clear_color, depth to 1; default: keep both). Each object is depth tested (LESS)
// against what is there, and every one of its passes (the plan's passes, the doublings
// that undo its exposure, the inversions that stand in for blend subtract, the single-unit
// path's running sum) is a draw of the object's own mesh with depth EQUAL: pixels it does
// not cover keep their colour bit for bit, and each object has its own exposure. Objects
// write depth, so later objects (and the engine's later draws) are occluded correctly.
// Hidden surfaces of one object cost their depth test only.
//
// The GL state contract: between sepal_frame_begin and sepal_frame_end the runtime owns
// the state listed below; sepal_frame_end puts every item back as begin found it (tests/
// runtime/frame_state_test.cpp queries all of it before and after a frame). Do not draw
// your own things between begin and end.
//   both: viewport, scissor/stencil/polygon-offset/cull/depth/blend/dither enables, front
//     face, cull face, depth func, depth mask, colour mask, clear colour and depth, blend
//     function and equation, the active texture unit, the 2D texture bound on each unit
//     the runtime uses, GL_ARRAY_BUFFER and GL_ELEMENT_ARRAY_BUFFER bindings.
//   GL ES 1.1: lighting, alpha test, fog, colour logic op, GL_TEXTURE_2D per unit, shade
//     model, matrix mode, the projection and modelview matrices and unit 0-2's texture
//     matrix, the current colour, each unit's texture environment (mode, combiners,
//     sources, operands, scales), client active texture, the vertex, colour, normal and
//     texture coordinate arrays (enable, size, type, stride, pointer, buffer); the normal
//     array and every unit's texture coordinates are disabled during the frame (a driver
//     may fetch an enabled array the passes do not use).
//   GL ES 2: the current program, blend function and equation per RGB and alpha, vertex
//     attributes 0-5 (enable, size, type, normalized, stride, pointer, buffer, current
//     value).
// Not touched: stencil function and masks, polygon offset values, scissor box, pixel
// store, framebuffer binding (the frame draws into the one bound at begin). On a GL ES 3
// context bind vertex array object 0 before the frame (GL ES 2 has none; attributes
// would be set on the bound one).
//
// Vertices: a sepal_mesh, or the engine's own arrays by offset and stride
// (sepal_vertex_data: positions, normals, tangents, UVs, 16-bit indices), read in place:
// nothing is copied into sepal_vertex and nothing is allocated; the per-vertex set-up
// writes only the frame's scratch. Model matrices: any affine map with a positive
// determinant. Under a similarity (rotation, translation, uniform scale) shading runs in
// object space with the eye and lights moved there; under any other (non-uniform scale,
// shear) each vertex is moved to world space as the set-up reads it (normals by the
// inverse transpose) and shading runs there, on every backend alike.
// A viewport up to each material's creation size. The material's own float target
// (sepal_material_create_float_target) serves sepal_draw only; in a frame, set fd.float_target when
// the framebuffer bound at begin is a float one of the engine's (no exposure, no
// doublings). Not thread-safe: one frame per context at a time, on the context's thread.
//
// The CPU backend (and the GL ES emulator the tools use, sepal/internal/sepal_emulate.h) draw
// the same frame description into caller buffers (sepal_frame_draw_cpu), so a multi-object GL
// frame can be compared pixel for pixel with them and with the exact renderer (offline/).
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "sepal/sepal_material.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sepal_frame_desc {
    const sepal_caps* caps;   // GL frames: the current context's (unused by CPU and emulator)
    float view[16];           // world to eye, column-major
    float projection[16];     // eye to clip, column-major
    int viewport[4];          // x, y, width, height (CPU, emulator: x, y ignored; the buffers' size)
    int clear;                // 0 (default): keep colour and depth; 1: clear both first
    float clear_color[4];
    int float_target;         // GL ES 2: the framebuffer bound at begin holds floats
    float* scratch;           // sepal_draw_scratch_floats() of the largest object (GL frames)
    size_t scratch_floats;
} sepal_frame_desc;

// ---- the engine's vertex data --------------------------------------------------------
// One attribute in the engine's memory, as sokol's vertex layouts: vertex i's element (32-bit
// floats) at (const char*)data + offset + i * stride. stride 0: tightly packed (the
// element's size). data + offset and stride must be multiples of 4 (float alignment).
typedef struct sepal_vertex_stream {
    const void* data;
    int offset;  // bytes
    int stride;  // bytes, 0 or >= the element's size
} sepal_vertex_stream;

// An object's vertices without a copy into sepal_vertex: the four attributes may share one
// interleaved buffer (same data and stride, their own offsets) or live in separate ones.
// Object space; read (never written) during each draw, so keep them alive and unchanged
// until the draw returns (GL calls read them then; nothing is kept after).
typedef struct sepal_vertex_data {
    sepal_vertex_stream position;  // 3 floats
    sepal_vertex_stream normal;    // 3 floats (need not be unit length)
    sepal_vertex_stream tangent;   // 4 floats: xyz the primary tangent, w the handedness
    sepal_vertex_stream uv;        // 2 floats
    int vertex_count;              // 1..65535
    const uint16_t* indices;       // triangles, counter-clockwise front faces
    int index_count;               // a multiple of 3
} sepal_vertex_data;

typedef struct sepal_object {
    const sepal_material* material;  // GL frames
    const sepal_asset* asset;        // CPU backend and emulator
    const sepal_mesh* mesh;          // object space (or vertices below; exactly one of them)
    float model[16];                 // object to world, column-major: affine, det > 0
    const sepal_light* lights;       // world space, the lights that reach this object
    int light_count;                 // 0..SEPAL_MAX_LIGHTS
    sepal_draw_mode mode;            // GL ES 2 (0: multipass)
    uint32_t diffuse_texture;        // as sepal_draw_desc.diffuse_texture
    const sepal_vertex_data* vertices;  // the engine's arrays, instead of mesh
} sepal_object;

typedef struct sepal_frame {
    sepal_frame_desc desc;
    int active;
    // The GL state saved at begin (internal layout).
    uint64_t saved[160];
} sepal_frame;

// Column-major identity (a convenience for model matrices).
void sepal_model_identity(float m[16]);
// What every backend shades for an object, for the exact renderer (offline/) and tests:
// the scene in the object's shading space, the clip-from-shading-space matrix, and (when
// vertices is not NULL) the object's vertices moved into that space, at most capacity of
// them (SEPAL_ERR_CAPACITY when it has more; *count receives how many). Under a
// similarity model (rotation, translation, uniform scale) the shading space is the
// object's own (the eye and lights moved by the inverse model matrix, point intensities
// divided by the scale squared; the vertices as given); under any other affine model it is
// the world (vertices by the model matrix, normals by its inverse transpose, tangents by
// it). Refuses a projective or singular model, a negative determinant (a mirror: it flips
// the triangles' winding and the tangent frames' handedness), a light count outside
// 0..SEPAL_MAX_LIGHTS and malformed vertex data (messages say which).
sepal_result sepal_object_shading(const sepal_frame_desc* desc, const sepal_object* object, sepal_scene* scene,
                                  float clip_from_shading[16], sepal_vertex* vertices, int capacity, int* count,
                                  sepal_error* err);
// The same for a similarity model only (today's callers): the scene in object space and
// clip_from_object = projection x view x model; any other model is refused.
sepal_result sepal_object_scene(const sepal_frame_desc* desc, const sepal_object* object, sepal_scene* scene,
                                float clip_from_object[16], sepal_error* err);

sepal_result sepal_frame_begin(sepal_frame* frame, const sepal_frame_desc* desc, sepal_error* err);
sepal_result sepal_frame_draw(sepal_frame* frame, const sepal_object* object, sepal_draw_stats* stats,
                              sepal_error* err);
// Restores the GL state; also after a failed draw (the frame is over either way).
sepal_result sepal_frame_end(sepal_frame* frame, sepal_error* err);

// ---- the same frame on the CPU ---------------------------------------------------------
// Draws one object of the frame into color (width x height x 3 linear floats, top row
// first) and depth (width x height floats: sepal_frame_clear_cpu sets the far plane), each
// kept where the object does not cover a pixel in front. desc->clear is ignored: call
// sepal_frame_clear_cpu once per frame. scratch: sepal_cpu_scratch_floats(vertices).
sepal_result sepal_frame_draw_cpu(const sepal_frame_desc* desc, const sepal_object* object, float* color,
                                  float* depth, float* scratch, size_t scratch_floats, sepal_draw_stats* stats,
                                  sepal_error* err);
void sepal_frame_clear_cpu(int width, int height, const float rgb[3], float* color, float* depth);

#ifdef __cplusplus
}
#endif
