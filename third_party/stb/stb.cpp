// stb_image and stb_image_write (Debian libstb-dev, public domain / MIT), compiled once for
// the whole project: offline/util/image.cpp (PNG in and out), ports/common/render_gl.cpp
// (diffuse maps) and ports/windowed (sepal-view's PNG) include the headers and link this
// (build/lib/libsepal_stb.a). It lives outside offline/ and ports/ because both use it and
// neither may depend on the other. PNG only, from memory only: callers read files with their
// own bounded readers (no unbounded allocation from a file's claims).
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_HDR  // environment maps (offline/sampling)
#define STBI_NO_STDIO
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#pragma GCC diagnostic ignored "-Wtype-limits"
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop
