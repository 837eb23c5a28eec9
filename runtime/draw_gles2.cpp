// The GL ES 2 executor (shaders/): not written yet; materials refuse GL ES 2 contexts.
#include "draw_internal.h"

namespace srt {
srt_result draw_gles2(const srt_draw_desc*, const FramePrep&, srt_draw_stats*, srt_error* err) {
    return fail(err, SRT_ERR_UNSUPPORTED, "draw: the GL ES 2 backend is not implemented yet");
}
}  // namespace srt
