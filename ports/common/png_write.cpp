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
    std::vector<unsigned char> png;
    if (!stbi_write_png_to_func(append, &png, width, height, 4, rgba, width * 4)) return false;
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
