// sepal-view: the runtime's own viewer. Built from runtime/ and ports/ only (no offline
// code). With an asset it draws the baked material; without one, the runtime's preview
// (a lit, textured mesh).
//
//   sepal-view --headless [ASSET.sepal] [--backend B | --gles 1|2 --mode M] [--mask LIST]
//              [--diffuse PNG] [scene flags] -o out.png        (sepal-view --help lists them)
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "common/render_gl.h"
#include "common/scene_flags.h"
#include "headless/sepal_headless.h"
#include "sepal/sepal_rt.h"
#include "sepal/sepal_version.h"

#include <CLI/CLI.hpp>

#include <stb/stb_image_write.h>  // compiled once: third_party/stb/stb.cpp

namespace {

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
    int gles = 1;
    uint32_t mask = 0;
    sepal_draw_mode mode = SEPAL_MODE_MULTIPASS;
    std::string backend, out_text, asset_text, diffuse_text, mode_text, mask_text;
    sepal_ports::SceneSetup setup;
    std::string flag_err;
    CLI::App app("sepal-view: the runtime's own viewer. With an asset it draws the baked material; without one, "
                 "the runtime's preview (a lit, textured mesh).",
                 "sepal-view");
    app.set_version_flag("--version", "sepal-view " SEPAL_VERSION_STRING);
    app.get_formatter()->column_width(34);
    app.add_option("ASSET", asset_text, "a baked material (.sepal); without one: the runtime's preview");
    app.add_flag("--headless", headless, "render offscreen through EGL (the only mode in this build)");
    CLI::Option* gles_opt = app.add_option("--gles", gles, "GL ES version: 1 (fixed function) or 2")
                                ->check(CLI::IsMember({1, 2}))
                                ->capture_default_str();
    CLI::Option* mode_opt =
        app.add_option("--mode", mode_text, "GL ES 2: multipass (default), fused (per-vertex coordinates) or fused-pixel")
            ->check(CLI::IsMember({"multipass", "fused", "fused-pixel"}));
    app.add_option("--backend", backend, "gles1, gles2, gles2-fused, gles2-fused-pixel or cpu (sets --gles and --mode; "
                                         "cpu draws without GL)")
        ->check(CLI::IsMember({"gles1", "gles2", "gles2-fused", "gles2-fused-pixel", "cpu"}))
        ->excludes(gles_opt)
        ->excludes(mode_opt);
    app.add_option("--diffuse", diffuse_text, "a diffuse texture map modulating the material (PNG, Fig. 13)");
    app.add_option("--mask", mask_text,
                   "hide capabilities to force fallback paths: subtract, multitexture, fbo, npot (comma-separated)");
    app.add_option("-o,--output", out_text, "output PNG")->required();
    sepal_ports::add_scene_options(app, &setup);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
        fprintf(stderr, "sepal-view: %s\nrun 'sepal-view --help' for the accepted flags\n", e.what());
        return 2;
    }
    if (!backend.empty() && backend != "cpu") {
        sepal_ports::GlRenderOptions o;
        sepal_ports::parse_gl_backend(backend, &o);
        gles = o.gles_version;
        mode = o.mode;
    }
    if (mode_text == "fused") mode = SEPAL_MODE_FUSED_VERTEX;
    if (mode_text == "fused-pixel") mode = SEPAL_MODE_FUSED_PIXEL;
    if (!mask_text.empty() && !sepal_ports::parse_mask(mask_text, &mask, &flag_err)) {
        fprintf(stderr, "sepal-view: %s\n", flag_err.c_str());
        return 2;
    }
    const char* out = out_text.c_str();
    const char* asset_path = asset_text.empty() ? nullptr : asset_text.c_str();
    const char* diffuse_path = diffuse_text.empty() ? nullptr : diffuse_text.c_str();
    if (!headless) {
        fprintf(stderr, "sepal-view: this build has only the headless port; pass --headless\n");
        return 2;
    }
    if (!sepal_ports::load_scene_mesh(&setup, &flag_err)) {
        fprintf(stderr, "sepal-view: %s\n", flag_err.c_str());
        return 2;
    }
    const int width = setup.width, height = setup.height;
    if (asset_path) {
        std::vector<uint8_t> bytes, rgba;
        sepal_ports::GlRenderInfo info;
        sepal_ports::Rgba8Image diffuse;
        if (!sepal_ports::read_asset_file(asset_path, &bytes, &flag_err) ||
            (diffuse_path && !sepal_ports::read_diffuse_png(diffuse_path, &diffuse, &flag_err))) {
            fprintf(stderr, "sepal-view: %s\n", flag_err.c_str());
            return 2;
        }
        if (backend == "cpu") {
            std::vector<float> rgb;
            double ms = 0;
            sepal_draw_stats stats = {};
            if (!sepal_ports::render_asset_cpu(bytes.data(), bytes.size(), setup, diffuse_path ? &diffuse : nullptr,
                                               &rgb, &ms, &flag_err, &stats)) {
                fprintf(stderr, "sepal-view: %s: %s\n", asset_path, flag_err.c_str());
                return 1;
            }
            rgba.resize(size_t(width) * height * 4);
            for (size_t p = 0; p < size_t(width) * height; ++p) {
                for (int c = 0; c < 3; ++c) {
                    const float v = rgb[p * 3 + c];
                    rgba[p * 4 + c] = (uint8_t)(v <= 0.0f ? 0 : v >= 1.0f ? 255 : (int)(v * 255.0f + 0.5f));
                }
                rgba[p * 4 + 3] = 255;
            }
            fprintf(stderr, "sepal-view: cpu backend, %.1f ms; counters: %s\n", ms,
                    sepal_ports::describe_counters(stats).c_str());
            if (!write_png_atomic(out, width, height, rgba.data())) {
                fprintf(stderr, "sepal-view: could not write %s\n", out);
                return 1;
            }
            printf("%s\n", out);
            return 0;
        }
        sepal_ports::GlRenderOptions opt;
        opt.gles_version = gles;
        opt.mask = mask;
        opt.mode = mode;
        opt.diffuse = diffuse_path ? &diffuse : nullptr;
        if (!sepal_ports::render_asset_headless(bytes.data(), bytes.size(), setup, opt, &rgba, &info, &flag_err)) {
            fprintf(stderr, "sepal-view: %s: %s\n", asset_path, flag_err.c_str());
            return 1;
        }
        fprintf(stderr, "sepal-view: %s | %s | %d draws, %d full-screen passes, %d copies, %.2f ms; counters: %s\n",
                info.device.c_str(), info.path.c_str(), info.stats.draw_calls,
                info.stats.fullscreen_passes, info.stats.copies, info.ms,
                sepal_ports::describe_counters(info.stats).c_str());
        if (!write_png_atomic(out, width, height, rgba.data())) {
            fprintf(stderr, "sepal-view: could not write %s\n", out);
            return 1;
        }
        printf("%s\n", out);
        return 0;
    }

    char msg[512];
    sepal_headless_desc hd = {};
    hd.width = width;
    hd.height = height;
    hd.gles_version = gles;
    sepal_headless_context* ctx = sepal_headless_create(&hd, msg, sizeof msg);
    if (!ctx) {
        fprintf(stderr, "sepal-view: %s\n", msg);
        return 1;
    }
    sepal_error err = {};
    sepal_caps caps;
    if (sepal_query_caps(gles, 0, sepal_headless_get_proc_address, &caps, &err) != SEPAL_OK) {
        fprintf(stderr, "sepal-view: %s\n", err.message);
        sepal_headless_destroy(ctx);
        return 1;
    }
    // Textures are made once, before drawing; nothing is allocated after.
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
    sepal_preview_desc d = {};
    d.mesh = &setup.mesh;
    if (sepal_scene_matrices(&setup.scene, width, height, d.model_view, d.projection, &err) != SEPAL_OK) {
        fprintf(stderr, "sepal-view: %s\n", err.message);
        sepal_headless_destroy(ctx);
        return 2;
    }
    // The preview has one directional light: the first light's direction seen from the
    // origin, in eye space.
    const sepal_light& light = setup.scene.lights[0];
    for (int r = 0; r < 3; ++r)
        d.light_dir_eye[r] = d.model_view[r] * light.position[0] +
                             d.model_view[4 + r] * light.position[1] +
                             d.model_view[8 + r] * light.position[2];
    d.base_color[0] = 0.88f;
    d.base_color[1] = 0.55f;
    d.base_color[2] = 0.3f;
    d.ambient = 0.12f;
    d.texture = checker;
    d.texture_width = d.texture_height = 64;
    for (int c = 0; c < 3; ++c) d.clear_color[c] = setup.scene.background[c];
    d.clear_color[3] = 1.0f;
    if (sepal_preview_draw(&caps, &d, &err) != SEPAL_OK) {
        fprintf(stderr, "sepal-view: %s\n", err.message);
        sepal_headless_destroy(ctx);
        return 1;
    }
    std::vector<uint8_t> pixels((size_t)width * height * 4);
    const bool read = sepal_headless_read_rgba(ctx, pixels.data()) != 0;
    fprintf(stderr, "sepal-view: %s\n", sepal_headless_describe(ctx));
    sepal_headless_destroy(ctx);
    if (!read || !write_png_atomic(out, width, height, pixels.data())) {
        fprintf(stderr, "sepal-view: could not read back or write %s\n", out);
        return 1;
    }
    printf("%s\n", out);
    return 0;
}
