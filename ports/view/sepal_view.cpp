// sepal-view: the runtime's own viewer. Built from runtime/ and ports/ only (no offline
// code). Today it renders the runtime's preview (a lit, textured sphere); it grows into
// the asset viewer as the runtime does.
//
//   sepal-view --headless [--gles 1|2] [--size WxH] -o out.png
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <vector>

#include "sepal_headless.h"
#include "sepal_rt.h"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#define STBI_WRITE_NO_STDIO
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace {

int usage(FILE* f, int code) {
    fprintf(f,
            "usage: sepal-view --headless [--gles 1|2] [--size WxH] -o out.png\n"
            "  --headless    render offscreen through EGL (the only mode in this build)\n"
            "  --gles N      GL ES version: 1 (fixed function, default) or 2\n"
            "  --size WxH    image size, default 512x512\n"
            "  -o PATH       output PNG\n");
    return code;
}

void append(void* ctx, void* data, int size) {
    auto* v = static_cast<std::vector<unsigned char>*>(ctx);
    v->insert(v->end(), (unsigned char*)data, (unsigned char*)data + size);
}

// Writes next to the target and renames, so a failed run leaves no half-written PNG.
bool write_png_atomic(const char* path, int w, int h, const uint8_t* rgba) {
    std::vector<unsigned char> png;
    if (!stbi_write_png_to_func(append, &png, w, h, 4, rgba, w * 4)) return false;
    char tmp[4096];
    snprintf(tmp, sizeof tmp, "%s.tmp.%d", path, (int)getpid());
    FILE* f = fopen(tmp, "wb");
    if (!f) return false;
    bool ok = fwrite(png.data(), 1, png.size(), f) == png.size();
    ok = fclose(f) == 0 && ok;
    if (ok && rename(tmp, path) != 0) ok = false;
    if (!ok) remove(tmp);
    return ok;
}

}  // namespace

int main(int argc, char** argv) {
    bool headless = false;
    int gles = 1, width = 512, height = 512;
    const char* out = nullptr;
    for (int i = 1; i < argc; ++i) {
        const char* a = argv[i];
        const bool has_value = i + 1 < argc;
        if (!strcmp(a, "--headless")) {
            headless = true;
        } else if (!strcmp(a, "--gles") && has_value) {
            gles = atoi(argv[++i]);
        } else if (!strcmp(a, "--size") && has_value) {
            if (sscanf(argv[++i], "%dx%d", &width, &height) != 2) return usage(stderr, 2);
        } else if (!strcmp(a, "-o") && has_value) {
            out = argv[++i];
        } else if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            return usage(stdout, 0);
        } else {
            fprintf(stderr, "sepal-view: unknown or incomplete argument '%s'\n", a);
            return usage(stderr, 2);
        }
    }
    if (!headless) {
        fprintf(stderr, "sepal-view: this build has only the headless port; pass --headless\n");
        return 2;
    }
    if (!out) return usage(stderr, 2);
    if (gles != 1 && gles != 2) {
        fprintf(stderr, "sepal-view: --gles %d: use 1 or 2\n", gles);
        return 2;
    }
    if (width < 1 || height < 1 || width > 8192 || height > 8192) {
        fprintf(stderr, "sepal-view: --size %dx%d out of range 1..8192\n", width, height);
        return 2;
    }

    char msg[512];
    sh_desc hd = {};
    hd.width = width;
    hd.height = height;
    hd.gles_version = gles;
    sh_context* ctx = sh_create(&hd, msg, sizeof msg);
    if (!ctx) {
        fprintf(stderr, "sepal-view: %s\n", msg);
        return 1;
    }
    srt_error err = {};
    srt_caps caps;
    if (srt_query_caps(gles, 0, &caps, &err) != SRT_OK) {
        fprintf(stderr, "sepal-view: %s\n", err.message);
        sh_destroy(ctx);
        return 1;
    }
    // Meshes and textures are loaded once, before drawing; nothing is allocated after.
    static srt_vertex vertices[65 * 33];
    static uint16_t indices[64 * 32 * 6];
    srt_mesh mesh = {vertices, indices, 65 * 33, 64 * 32 * 6};
    static uint8_t checker[64 * 64 * 4];
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const bool dark = ((x / 8) + (y / 8)) % 2;
            uint8_t* p = checker + (y * 64 + x) * 4;
            p[0] = dark ? 150 : 255;
            p[1] = dark ? 160 : 250;
            p[2] = dark ? 190 : 240;
            p[3] = 255;
        }
    srt_preview_desc d = {};
    d.mesh = &mesh;
    const float eye[3] = {0.0f, -3.0f, 1.2f}, target[3] = {0, 0, 0}, up[3] = {0, 0, 1};
    srt_mat4_look_at(eye, target, up, d.model_view);
    srt_mat4_perspective(40.0f, (float)width / (float)height, 0.5f, 10.0f, d.projection);
    d.light_dir_eye[0] = 0.5f;
    d.light_dir_eye[1] = 0.6f;
    d.light_dir_eye[2] = 0.62f;
    d.base_color[0] = 0.88f;
    d.base_color[1] = 0.55f;
    d.base_color[2] = 0.3f;
    d.ambient = 0.12f;
    d.texture = checker;
    d.texture_width = d.texture_height = 64;
    d.clear_color[0] = d.clear_color[1] = d.clear_color[2] = 0.08f;
    d.clear_color[3] = 1.0f;
    if (srt_mesh_sphere(64, 32, &mesh, &err) != SRT_OK ||
        srt_preview_draw(&caps, &d, &err) != SRT_OK) {
        fprintf(stderr, "sepal-view: %s\n", err.message);
        sh_destroy(ctx);
        return 1;
    }
    std::vector<uint8_t> pixels((size_t)width * height * 4);
    const bool read = sh_read_rgba(ctx, pixels.data()) != 0;
    fprintf(stderr, "sepal-view: %s\n", sh_describe(ctx));
    sh_destroy(ctx);
    if (!read || !write_png_atomic(out, width, height, pixels.data())) {
        fprintf(stderr, "sepal-view: could not read back or write %s\n", out);
        return 1;
    }
    printf("%s\n", out);
    return 0;
}
