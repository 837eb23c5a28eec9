// Shared scenes for GL chain tests: render through ports/headless into a sepal::Image.
#pragma once
#include <string>

#include "util/image.h"

namespace sepal_test {
// A textured quad (16x16 grid, checker texture) tilted under one directional light,
// drawn by the runtime's preview path on GL ES `gles` (1 or 2). Returns false with the
// reason (EGL, context or runtime error).
bool render_lit_quad(int gles, int width, int height, sepal::Image* out, std::string* err);
}  // namespace sepal_test
