// GL ES 2 helpers shared by the runtime's shader paths (internal).
#pragma once
#include <GLES2/gl2.h>

#include "internal.h"

namespace srt {
// Compiles and links a program; on failure returns 0 and puts the shader's name and the
// driver's log into err. attributes: NULL-terminated names bound to locations 0, 1, ...
GLuint gles2_program(const char* name, const char* vertex_src, const char* fragment_src,
                     const char* const* attributes, sepal_error* err);
}  // namespace srt
