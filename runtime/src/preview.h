// Preview drawing per GL ES version (internal; see sepal_preview_draw in sepal_rt.h).
#pragma once
#include "internal.h"

namespace srt {
// desc is validated and light_dir is unit length before these are called.
sepal_result preview_gles1(const sepal_caps& caps, const sepal_preview_desc& desc,
                         const float light_dir[3], sepal_error* err);
sepal_result preview_gles2(const sepal_caps& caps, const sepal_preview_desc& desc,
                         const float light_dir[3], sepal_error* err);
// The preview's texture on unit 0 (the desc's RGBA8 map, or 1x1 white), bound; the caller
// deletes it after drawing. GL calls both versions share (preview.cpp).
uint32_t preview_texture(const sepal_preview_desc& desc);
}  // namespace srt
