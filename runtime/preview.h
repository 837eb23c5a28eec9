// Preview drawing per GL ES version (internal; see srt_preview_draw in sepal_rt.h).
#pragma once
#include "internal.h"

namespace srt {
// desc is validated and light_dir is unit length before these are called.
srt_result preview_gles1(const srt_caps& caps, const srt_preview_desc& desc,
                         const float light_dir[3], srt_error* err);
srt_result preview_gles2(const srt_caps& caps, const srt_preview_desc& desc,
                         const float light_dir[3], srt_error* err);
}  // namespace srt
