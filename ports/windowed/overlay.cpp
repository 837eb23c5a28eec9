#include "windowed/overlay.h"

#include <GLES2/gl2.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb/stb_easy_font.h>
#pragma GCC diagnostic pop

namespace sepal_ports {
namespace {
int pow2_at_least(int v) {
    int p = 1;
    while (p < v) p <<= 1;
    return p;
}
}  // namespace

bool blit_rgba(Blitter* b, int gles, const uint8_t* rgba, int width, int height, int x, int y, int window_width,
               int window_height, std::string* err) {
    if (b->gles != 0 && b->gles != gles) {
        *err = "blit: the blitter belongs to the other GL ES version's context";
        return false;
    }
    b->gles = gles;
    const int tw = pow2_at_least(width), th = pow2_at_least(height);
    // glBindTexture and glTexImage2D are common to GL ES 1.1 and 2 (same entry points).
    if (!b->texture) glGenTextures(1, &b->texture);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, b->texture);
    if (tw > b->texture_width || th > b->texture_height) {
        b->texture_width = tw > b->texture_width ? tw : b->texture_width;
        b->texture_height = th > b->texture_height ? th : b->texture_height;
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, b->texture_width, b->texture_height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                     nullptr);
        // Nearest at a 1:1 scale: every pixel lands unchanged.
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    const float u = (float)width / (float)b->texture_width, v = (float)height / (float)b->texture_height;
    const int gl_y = window_height - y - height;
    (void)window_width;
    const bool ok = gles == 1 ? blit_gles1(b, x, gl_y, width, height, u, v, err)
                              : blit_gles2(b, x, gl_y, width, height, u, v, err);
    if (ok && glGetError() != GL_NO_ERROR) {
        *err = "blit: GL error";
        return false;
    }
    return ok;
}

void blit_release(Blitter* b) {
    if (b->texture) glDeleteTextures(1, &b->texture);
    if (b->program) glDeleteProgram(b->program);
    *b = Blitter{};
}

void text_strip(const std::vector<std::string>& lines, int width, int height, std::vector<uint8_t>* rgba) {
    rgba->assign((size_t)width * height * 4, 0);
    for (size_t i = 0; i < rgba->size(); i += 4) (*rgba)[i] = (*rgba)[i + 1] = 24, (*rgba)[i + 2] = 32, (*rgba)[i + 3] = 255;
    static char quads[64 * 1024];  // ~270 bytes a character: room for two long lines
    for (size_t line = 0; line < lines.size(); ++line) {
        std::vector<char> text(lines[line].begin(), lines[line].end());
        text.push_back('\0');
        const int n = stb_easy_font_print(4.0f, 3.0f + 12.0f * (float)line, text.data(), nullptr, quads, sizeof quads);
        for (int q = 0; q < n; ++q) {
            const float* v0 = (const float*)(quads + q * 64);       // 4 vertices of 16 bytes
            const float* v2 = (const float*)(quads + q * 64 + 32);  // the opposite corner
            for (int y = (int)v0[1]; y < (int)v2[1] && y < height; ++y)
                for (int x = (int)v0[0]; x < (int)v2[0] && x < width; ++x) {
                    uint8_t* p = rgba->data() + ((size_t)y * width + x) * 4;
                    p[0] = 235, p[1] = 235, p[2] = 225;
                }
        }
    }
}

}  // namespace sepal_ports
