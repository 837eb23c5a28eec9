// sepal-view: the runtime's own viewer. Built from runtime/ and ports/ only (no offline
// code). With an asset it draws the baked material; without one, the runtime's preview
// (a lit, textured mesh). Without --headless it opens a window (ports/windowed/viewer.h).
//
//   sepal-view --headless [ASSET.sepal] [--gles 1|2] [--mask LIST] [--framebuffer 565] [scene flags] -o out.png
//   sepal-view ASSET.sepal|FOLDER|SPEC [--backend B] [--mask LIST] [viewer flags] [scene flags]
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "common/png_write.h"
#include "common/render_gl.h"
#include "common/scene_flags.h"
#include "sepal/sepal_version.h"
#include "headless/sepal_headless.h"
#include "sepal/sepal_rt.h"
#include "windowed/scene_view.h"
#include "windowed/viewer.h"

namespace {

int usage(FILE* f, int code) {
    fprintf(f,
            "usage: sepal-view --headless [ASSET.sepal] [--backend B | --gles 1|2 --mode M] [--mask LIST] [--diffuse PNG] [--framebuffer 565] [scene flags] -o out.png\n"
            "       sepal-view ASSET.sepal|FOLDER|SPEC [--backend B] [--mask LIST] [viewer flags] [scene flags]\n"
            "       sepal-view --scene FILE.json|BUNDLE [--headless [--framebuffer 565] -o out.png] [--backend B] [--time T] [--frames N --shot PNG]\n"
            "  --scene FILE          a scene file (docs/scenes.md): many objects, moving lights; in a window, or\n"
            "                        one frame with --headless (ports/windowed/scene_view.h)\n"
            "  ASSET.sepal           a baked material (without one: the runtime's preview)\n"
            "  --headless            render offscreen through EGL; without it: a window (X11),\n"
            "                        keys and mouse as `h` prints there\n"
            "  --gles N              GL ES version: 1 (fixed function, default) or 2\n"
            "  --mode M              GL ES 2: multipass (default), fused (per-vertex\n"
            "                        coordinates) or fused-pixel\n"
            "  --backend B           gles1, gles2, gles2-fused, gles2-fused-pixel or cpu\n"
            "                        (sets --gles and --mode; cpu draws without GL)\n"
            "  --diffuse PNG         a diffuse texture map modulating the material (Fig. 13)\n"
            "  --mask LIST           hide capabilities to force fallback paths: subtract,\n"
            "                        multitexture, fbo, npot, third-unit (comma-separated)\n"
            "  --framebuffer F       headless: 8888 (default) or 565, an RGB565 pbuffer as\n"
            "                        older phones and kiosk boards render (docs/ports.md)\n"
            "  -o PATH               output PNG\n"
            "viewer flags (window only):\n%s"
            "scene flags:\n%s",
            sepal_ports::viewer_flags_help(), sepal_ports::scene_flags_help());
    return code;
}

// The end of a headless render: the light-range warning, the PNG, its path on stdout.
int finish_headless(const std::vector<uint8_t>& bytes, const sepal_draw_stats& stats, const char* asset_path,
                    const char* out, int width, int height, const std::vector<uint8_t>& rgba) {
    const std::string dim = sepal_ports::light_range_warning(bytes.data(), bytes.size(), stats, asset_path);
    if (!dim.empty()) fprintf(stderr, "sepal-view: %s\n", dim.c_str());
    if (!sepal_ports::write_png_atomic(out, width, height, rgba.data())) {
        fprintf(stderr, "sepal-view: could not write %s\n", out);
        return 1;
    }
    printf("%s\n", out);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i)
        if (!strcmp(argv[i], "--scene")) return sepal_ports::run_scene_view(argc, argv);
    bool headless = false;
    int gles = 1;
    uint32_t mask = 0;
    int framebuffer = 8888;
    bool framebuffer_given = false;
    sepal_draw_mode mode = SEPAL_MODE_MULTIPASS;
    std::string backend;
    const char* out = nullptr;
    const char* asset_path = nullptr;
    const char* diffuse_path = nullptr;
    sepal_ports::SceneSetup setup;
    sepal_ports::ViewerOptions viewer;
    std::string flag_err;
    for (int i = 1; i < argc; ++i) {
        int used = sepal_ports::parse_scene_flag(argc, argv, i, &setup, &flag_err);
        if (used == 0) used = sepal_ports::parse_viewer_flag(argc, argv, i, &viewer, &flag_err);
        if (used < 0) {
            fprintf(stderr, "sepal-view: %s\n", flag_err.c_str());
            return 2;
        }
        if (used > 0) {
            i += used - 1;
            continue;
        }
        const char* a = argv[i];
        const bool has_value = i + 1 < argc;
        if (!strcmp(a, "--headless")) {
            headless = true;
        } else if (!strcmp(a, "--gles") && has_value) {
            gles = atoi(argv[++i]);
        } else if (!strcmp(a, "-o") && has_value) {
            out = argv[++i];
        } else if (!strcmp(a, "--backend") && has_value) {
            sepal_ports::GlRenderOptions o;
            backend = argv[++i];
            if (sepal_ports::parse_gl_backend(backend, &o)) {
                gles = o.gles_version;
                mode = o.mode;
            } else if (backend != "cpu") {
                fprintf(stderr, "sepal-view: --backend '%s': gles1, gles2, gles2-fused, gles2-fused-pixel or cpu\n",
                        backend.c_str());
                return 2;
            }
        } else if (!strcmp(a, "--mode") && has_value) {
            const char* m = argv[++i];
            if (!strcmp(m, "multipass")) mode = SEPAL_MODE_MULTIPASS;
            else if (!strcmp(m, "fused")) mode = SEPAL_MODE_FUSED_VERTEX;
            else if (!strcmp(m, "fused-pixel")) mode = SEPAL_MODE_FUSED_PIXEL;
            else {
                fprintf(stderr, "sepal-view: --mode '%s': multipass, fused or fused-pixel\n", m);
                return 2;
            }
        } else if (!strcmp(a, "--diffuse") && has_value) {
            diffuse_path = argv[++i];
        } else if (!strcmp(a, "--mask") && has_value) {
            if (!sepal_ports::parse_mask(argv[++i], &mask, &flag_err)) {
                fprintf(stderr, "sepal-view: %s\n", flag_err.c_str());
                return 2;
            }
        } else if (!strcmp(a, "--framebuffer") && has_value) {
            framebuffer_given = true;
            if (!sepal_ports::parse_framebuffer(argv[++i], &framebuffer, &flag_err)) {
                fprintf(stderr, "sepal-view: %s\n", flag_err.c_str());
                return 2;
            }
        } else if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            return usage(stdout, 0);
        } else if (!strcmp(a, "--version")) {
            printf("sepal-view " SEPAL_VERSION_STRING "\n");
            return 0;
        } else if (a[0] != '-' && !asset_path) {
            asset_path = a;
        } else {
            fprintf(stderr, "sepal-view: unknown or incomplete argument '%s'\n", a);
            return usage(stderr, 2);
        }
    }
    if (!headless && (out || diffuse_path || framebuffer_given)) {
        fprintf(stderr, "sepal-view: %s --headless; without it sepal-view opens a window\n",
                out ? "-o writes a PNG with" : diffuse_path ? "--diffuse is drawn only with" : "--framebuffer applies with");
        return 2;
    }
    if (framebuffer_given && backend == "cpu") {
        fprintf(stderr, "sepal-view: --framebuffer applies to the GL backends (not cpu)\n");
        return 2;
    }
    if (!headless) {
        viewer.input = asset_path ? asset_path : "";
        viewer.backend = !backend.empty() ? backend : gles == 1 ? "gles1" : mode == SEPAL_MODE_MULTIPASS ? "gles2"
                                                     : mode == SEPAL_MODE_FUSED_VERTEX ? "gles2-fused" : "gles2-fused-pixel";
        viewer.mask = mask;
        return sepal_ports::run_viewer(viewer, &setup);
    }
    if (!out) return usage(stderr, 2);
    if (gles != 1 && gles != 2) {
        fprintf(stderr, "sepal-view: --gles %d: use 1 or 2\n", gles);
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
            sepal_ports::rgb_to_rgba8(rgb.data(), size_t(width) * height, rgba.data());
            fprintf(stderr, "sepal-view: cpu backend, %.1f ms; counters: %s\n", ms,
                    sepal_ports::describe_counters(stats).c_str());
            return finish_headless(bytes, stats, asset_path, out, width, height, rgba);
        }
        sepal_ports::GlRenderOptions opt;
        opt.gles_version = gles;
        opt.mask = mask;
        opt.mode = mode;
        opt.framebuffer = framebuffer;
        opt.diffuse = diffuse_path ? &diffuse : nullptr;
        if (!sepal_ports::render_asset_headless(bytes.data(), bytes.size(), setup, opt, &rgba, &info, &flag_err)) {
            fprintf(stderr, "sepal-view: %s: %s\n", asset_path, flag_err.c_str());
            return 1;
        }
        fprintf(stderr, "sepal-view: %s | %s | %d draws, %d full-screen passes, %d copies, %.2f ms; counters: %s\n",
                info.device.c_str(), info.path.c_str(), info.stats.draw_calls,
                info.stats.fullscreen_passes, info.stats.copies, info.ms,
                sepal_ports::describe_counters(info.stats).c_str());
        const std::string weaker = sepal_ports::profile_warning(bytes.data(), bytes.size(), info.caps, info.stats);
        if (!weaker.empty()) fprintf(stderr, "sepal-view: %s\n", weaker.c_str());
        return finish_headless(bytes, info.stats, asset_path, out, width, height, rgba);
    }

    char msg[512];
    sepal_headless_desc hd = {};
    hd.width = width;
    hd.height = height;
    hd.gles_version = gles;
    hd.framebuffer = framebuffer;
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
    if (!read || !sepal_ports::write_png_atomic(out, width, height, pixels.data())) {
        fprintf(stderr, "sepal-view: could not read back or write %s\n", out);
        return 1;
    }
    printf("%s\n", out);
    return 0;
}
