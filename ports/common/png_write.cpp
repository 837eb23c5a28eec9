#include "common/png_write.h"

#include <stdio.h>
#include <unistd.h>

#include <vector>

// stb_image_write encodes; its implementation is compiled once (third_party/stb/stb.cpp).
#include <stb/stb_image_write.h>

namespace sepal_ports {
namespace {
void append(void* ctx, void* data, int size) {
    auto* v = static_cast<std::vector<unsigned char>*>(ctx);
    v->insert(v->end(), (unsigned char*)data, (unsigned char*)data + size);
}
}  // namespace

bool write_png_atomic(const std::string& path, int width, int height, const uint8_t* rgba) {
    // Opaque RGB, as `sepal render` writes: a GL read-back's alpha is whatever the clear and
    // the blends left (0 where the background was cleared), not coverage a viewer should see.
    std::vector<unsigned char> rgb(size_t(width) * size_t(height) * 3), png;
    for (size_t p = 0; p < size_t(width) * size_t(height); ++p)
        for (int c = 0; c < 3; ++c) rgb[p * 3 + c] = rgba[p * 4 + c];
    if (!stbi_write_png_to_func(append, &png, width, height, 3, rgb.data(), width * 3)) return false;
    const std::string tmp = path + ".tmp." + std::to_string((int)getpid());
    FILE* f = fopen(tmp.c_str(), "wb");
    if (!f) return false;
    bool ok = fwrite(png.data(), 1, png.size(), f) == png.size();
    ok = fclose(f) == 0 && ok;
    if (ok && rename(tmp.c_str(), path.c_str()) != 0) ok = false;
    if (!ok) remove(tmp.c_str());
    return ok;
}

}  // namespace sepal_ports
