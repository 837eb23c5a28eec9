// Shared by the GL backends' executors (internal): what sepal_draw prepares per frame.
#pragma once
#include "sepal/sepal_material.h"
#include "vertex_setup.h"

namespace srt {

struct FramePrep {
    float view[16], proj[16];
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
};

sepal_result draw_gles1(const sepal_draw_desc* d, const FramePrep& prep, sepal_draw_stats* stats, sepal_error* err);
sepal_result create_gles2_programs(sepal_material* m, sepal_error* err);
void destroy_gles2_programs(sepal_material* m);
sepal_result draw_gles2(const sepal_draw_desc* d, const FramePrep& prep, sepal_draw_stats* stats, sepal_error* err);

}  // namespace srt
