// Shared by the GL backends' executors (internal): what sepal_draw prepares per frame.
#pragma once
#include "sepal/sepal_frame.h"
#include "sepal/sepal_material.h"
#include "mesh_view.h"
#include "vertex_setup.h"

namespace srt {

struct FramePrep {
    float view[16], proj[16];  // view: the modelview (the engine's view times the model matrix)
    MeshView mesh;             // what the executors draw (positions in object space)
    VertexSetupResult vertices;
    // 2^-e on the vertex colours of the plan's passes; 1 for the fused modes, whose
    // shaders compute f E directly and let the framebuffer clamp it at 1, as the display
    // would.
    float exposure;
    // GL ES 1.1 add-only plans: each pass's own exposure shift (2^-shift), at most the
    // frame's; passes are drawn by falling shift with doublings in between. Otherwise
    // staged is false and every pass uses `exposure`.
    bool staged;
    int pass_shift[SEPAL_FMT_MAX_PASSES];
    // Multipass with a third texture unit (GL ES 1.1 fixed function, or GL ES 2's pass
    // shader): the diffuse map (a tree's blend map) multiplies each pass instead of the
    // framebuffer after the passes, so the sum needs no headroom for it and (GL ES 1.1) the
    // plan keeps its staged exposure.
    bool diffuse_per_pass;
};

// On a framebuffer with fewer than 8 bits in some channel (RGB565), the GL paths sum an
// object's passes in an 8-bit target (GL ES 1.1: GL_OES_framebuffer_object and two units;
// GL ES 2: core) and write the sum to the framebuffer once, rounded to its bits, instead of
// rounding every pass and doubling the rounding (docs/ports.md, "Framebuffer bits"). The
// emulator decides the same way.
inline bool accumulates(const sepal_caps& c, bool single_unit) {
    const int bits[3] = {c.red_bits, c.green_bits, c.blue_bits};
    bool fewer = false;
    for (int b : bits) fewer = fewer || (b > 0 && b < 8);
    return (c.gles_version == 2 || (c.gles_version == 1 && !single_unit)) && c.has_fbo && fewer;
}
// The final write's fragment per channel, k v + h for the 8-bit sum v: a framebuffer of n bits
// keeps the top n bits of the fragment rounded to 8 bits (llvmpipe, with or without
// GL_DITHER; docs/ports.md), floor(round(255 k v + 255 h) / 2^(8-n)), which with
// k = (2^n - 1) 2^(8-n) / 255 and h = (2^(7-n) - 1/2) / 255 is round(v (2^n - 1)): the nearest
// n-bit value, as one rounding of the exact sum would give (with 2^(7-n) alone, the 8-bit
// rounding pushed a sixteenth of the values a step up: 6-8% of a frame's pixels). GL ES 1.1
// only: a driver that converts the fragment to n bits directly, rounding (the GL ES
// specification's rule), would store the other of the two nearest values near half a step,
// and no k and h serve both rules; the GL ES 2 write quantizes in its shader, exact under
// both (shaders/accumulated.frag). 8 bits or more: k = 1, h = 0.
inline float write_scale(int bits) {
    return bits > 0 && bits < 8 ? (float)(((1 << bits) - 1) << (8 - bits)) / 255.0f : 1.0f;
}
inline float write_bias(int bits) { return bits > 0 && bits < 8 ? ((float)(1 << (7 - bits)) - 0.5f) / 255.0f : 0.0f; }

// Everything sepal_material_create sets up except GL objects: validation against caps, the
// plan, per-pass needs, the paths (one unit, subtraction by inversion, fused groups).
sepal_result material_plan(const sepal_caps* caps, const sepal_asset* asset, int max_width, int max_height,
                           srt::Material* out, sepal_error* err);
// Validates the draw, sets up the vertices (scratch), and sizes the exposure, the doublings
// and the stages: everything a GL executor (or the GL ES 1.1 emulator) needs. mesh: the
// object's vertices (d->mesh is not read), d->scene its scene in the shading space
// (object_space), modelview and proj its matrices; float_target: the target holds floats
// (no exposure, no doublings). stats is cleared and filled with the object's counters.
sepal_result prepare_frame(const sepal_draw_desc* d, const MeshView& mesh, const float modelview[16],
                           const float proj[16], bool float_target, FramePrep* out, sepal_draw_stats* stats,
                           sepal_error* err);

// Where an object is shaded. Under a similarity model: its own space, the eye (from the
// inverse view) and the lights moved by the inverse model matrix, point intensities divided
// by the scale squared (distances grow by it), so that shading the object-space mesh gives
// the world-space radiance; transform false. Under any other affine model (det > 0): world
// space, the scene as given, and transform true with m the model's 3 x 4 and n its 3 x 3's
// inverse transpose (MeshView's). modelview = view x model either way.
struct ObjectSpace {
    sepal_scene scene;
    float modelview[16];
    bool transform;
    float m[12], n[9];
};
sepal_result object_space(const float view[16], const float model[16], const sepal_light* lights, int light_count,
                          ObjectSpace* out, sepal_error* err);
void mat4_mul(const float* a, const float* b, float* out);  // column-major a x b

// The GL ES state a frame touches, saved at begin and put back at end (sepal_frame.h lists
// it); the begin also sets the frame-wide state the passes assume and clears if asked.
// Each backend's object draw sets the per-object rest. material_fbo (GL ES 2, sepal_draw
// of a float-target material): drawn into after the state is saved.
void gles1_frame_begin(const sepal_frame_desc& d, void* saved);
void gles1_frame_end(const sepal_caps& caps, const void* saved);
void gles2_frame_begin(const sepal_frame_desc& d, void* saved, uint32_t material_fbo);
void gles2_frame_end(const sepal_caps& caps, const void* saved);
constexpr size_t kSavedStateBytes = sizeof(((sepal_frame*)nullptr)->saved);
// sepal_draw's background: a far-plane quad where the depth is still clear.
void gles1_background(const float rgb[3], sepal_draw_stats* stats);
void gles2_background(const srt::Material* m, const float rgb[3], sepal_draw_stats* stats);
// sepal_draw of a float-target material: the float frame shown in the framebuffer bound at
// begin (saved), width x height.
void gles2_show_float(const srt::Material* m, const void* saved, int width, int height, sepal_draw_stats* stats);
// Lights of the scene whose irradiance at the centre of the mesh's bounds (dimmest lit
// channel) is above 0 and below the material's declared irradiance_min (0 when it declares none).
int dim_lights(const sepal_fmt_material& m, const MeshView& mesh, const sepal_scene& scene);
// The order passes are drawn in (the plan's; staged: by falling exposure shift, stable).
void pass_order(const srt::Material* m, const FramePrep& prep, uint16_t* order);

// The GL ES 1.1 executor's sequence of framebuffer operations, shared with the emulator so
// both do the same thing: passes (each with its exposure, drawn once per light), stage
// doublings between them (staged plans), the inversion around subtracted passes (no blend
// subtract), and the final doublings.
struct Gles1Step {
    enum Kind { kPass, kDouble, kInvert } kind;
    int count;        // kDouble: doublings
    uint16_t pass;    // kPass: index into the plan
    float exposure;   // kPass: 2^-shift on its vertex colours
    bool inverted;    // kPass: drawn into the inverted framebuffer (subtract becomes add)
};
constexpr int kMaxGles1Steps = 2 * SEPAL_FMT_MAX_PASSES + 3;  // a stage and a pass per pass, 2 inversions, the end
int gles1_schedule(const srt::Material* m, const FramePrep& prep, int total_doublings, Gles1Step* steps);

sepal_result draw_gles1(const sepal_draw_desc* d, const FramePrep& prep, sepal_draw_stats* stats, sepal_error* err);
sepal_result create_gles2_programs(srt::Material* m, sepal_error* err);
void destroy_gles2_programs(srt::Material* m);
// The framebuffer-object entry points of m's context: GL_OES_framebuffer_object's from the
// caps on GL ES 1.1, the core ones on GL ES 2 (gles2_fbo_functions). One 8-bit target
// (srt::accumulates) is made, switched to and deleted through them for both versions.
using FboFunctions = decltype(sepal_caps::fbo_es1);
const FboFunctions& gles2_fbo_functions();
const FboFunctions& fbo_functions(const srt::Material* m);
// GL ES 2: the program that writes the 8-bit sum (shaders/accumulated.frag); false when it
// does not build (the material then keeps the per-pass path).
bool create_gles2_sum_program(srt::Material* m);
// The object's passes into the 8-bit target, at the viewport's size, cleared; and back to
// the framebuffer, viewport and scissor test the engine had bound.
struct SumTarget {
    int bound, viewport[4];
    bool scissor;
};
SumTarget enter_sum_target(const srt::Material* m);
void leave_sum_target(const srt::Material* m, const SumTarget& t);
sepal_result draw_gles2(const sepal_draw_desc* d, const FramePrep& prep, sepal_draw_stats* stats, sepal_error* err);

}  // namespace srt
