// Builds without GL ES 1.1 (the web port: WebGL 1 is GL ES 2 without fixed function) leave
// out draw_gles1.cpp and preview_gles1.cpp and link these instead, which refuse with a
// message. Native builds compile this file empty.
#ifdef SEPAL_NO_GLES1
#include "draw_internal.h"
#include "preview.h"

namespace srt {

sepal_result draw_gles1(const sepal_draw_desc*, const FramePrep&, sepal_draw_stats*, sepal_error* err) {
    return fail(err, SEPAL_ERR_UNSUPPORTED, "draw: this build has no GL ES 1.1 paths (SEPAL_NO_GLES1); use GL ES 2");
}

void gles1_frame_begin(const sepal_frame_desc&, void*) {}
void gles1_frame_end(const sepal_caps&, const void*) {}
void gles1_background(const float*, sepal_draw_stats*) {}

sepal_result preview_gles1(const sepal_caps&, const sepal_preview_desc&, const float*, sepal_error* err) {
    return fail(err, SEPAL_ERR_UNSUPPORTED, "preview: this build has no GL ES 1.1 paths (SEPAL_NO_GLES1)");
}

}  // namespace srt
#endif
