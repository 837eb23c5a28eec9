// sepal render SPEC_OR_ASSET --backend exact|gles1|gles2|gles2-fused|gles2-fused-pixel|cpu|
//   gles1-model|gles2-model [--mask LIST] [--diffuse PNG] [scene flags] -o out.png [--float out.pfm]
#include <chrono>
#include <cstring>

#include "cli/cli.h"
#include "util/io.h"
#include "reference/render_exact.h"
#include "common/render_gl.h"
#include "common/scene_flags.h"

namespace sepal {

int cmd_render(const std::vector<std::string>& args, const CommandIO& io) {
    sepal_ports::SceneSetup setup;
    std::string backend = "exact", out_path, float_path, mask_text, diffuse_path, err;
    bool float_target = false;
    std::vector<std::string> positional;
    std::vector<char*> argv;
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    const int argc = int(argv.size());
    for (int i = 0; i < argc; ++i) {
        const int used = sepal_ports::parse_scene_flag(argc, argv.data(), i, &setup, &err);
        if (used < 0) {
            std::fprintf(io.err, "sepal render: %s\n", err.c_str());
            return kExitBadInput;
        }
        if (used > 0) {
            i += used - 1;
            continue;
        }
        const std::string a = args[size_t(i)];
        const bool has_value = i + 1 < argc;
        if ((a == "--backend" || a == "-o" || a == "--float" || a == "--mask" || a == "--diffuse") && !has_value) {
            std::fprintf(io.err, "sepal render: %s needs a value\n", a.c_str());
            return kExitBadInput;
        }
        if (a == "--backend") {
            backend = args[size_t(++i)];
        } else if (a == "-o") {
            out_path = args[size_t(++i)];
        } else if (a == "--float") {
            float_path = args[size_t(++i)];
        } else if (a == "--float-target") {
            float_target = true;
        } else if (a == "--mask") {
            mask_text = args[size_t(++i)];
        } else if (a == "--diffuse") {
            diffuse_path = args[size_t(++i)];
        } else if (a.size() > 1 && a[0] == '-') {
            std::fprintf(io.err, "sepal render: unknown option %s\nscene flags:\n%s", a.c_str(),
                         sepal_ports::scene_flags_help());
            return kExitBadInput;
        } else {
            positional.push_back(a);
        }
    }
    if (positional.size() != 1 || (out_path.empty() && float_path.empty())) {
        std::fprintf(io.err,
                     "usage: sepal render SPEC_OR_ASSET --backend exact|gles1|gles2|gles2-fused|"
                     "gles2-fused-pixel|cpu|gles1-model|gles2-model [--mask LIST] [--diffuse PNG] [scene flags] -o out.png "
                     "[--float out.pfm]\nscene flags:\n%s",
                     sepal_ports::scene_flags_help());
        return kExitBadInput;
    }
    sepal_ports::GlRenderOptions opt;
    const bool model = backend == "gles1-model" || backend == "gles2-model";
    if (model) {
        // The GL ES 1.1 emulator: what gles1 (or the gles2 multipass path) shows, on the CPU.
        std::vector<uint8_t> bytes, rgba;
        uint32_t mask = 0;
        sepal_draw_stats stats = {};
        if (!diffuse_path.empty() || !float_path.empty() || float_target || out_path.empty())
            err = backend + " writes an 8-bit PNG (-o) and takes no --diffuse, --float or --float-target";
        if (!err.empty() || !sepal_ports::parse_mask(mask_text, &mask, &err) ||
            !sepal_ports::load_scene_mesh(&setup, &err) || !sepal_ports::read_asset_file(positional[0], &bytes, &err) ||
            !sepal_ports::render_asset_emulated(bytes.data(), bytes.size(), setup, backend == "gles1-model" ? 1 : 2,
                                                mask, &rgba, &err, &stats) ||
            !write_png(out_path, to_rgb(image_from_rgba8(rgba.data(), setup.width, setup.height)), &err)) {
            std::fprintf(io.err, "sepal render: %s\n", err.c_str());
            return kExitBadInput;
        }
        std::fprintf(io.out, "backend    %s (the GL ES pipeline emulated on the CPU), %dx%d, %d doublings\n",
                     backend.c_str(), setup.width, setup.height, stats.doublings);
        std::fprintf(io.out, "png        %s\n", out_path.c_str());
        return kExitOk;
    }
    if (sepal_ports::parse_gl_backend(backend, &opt) || backend == "cpu") {
        std::vector<uint8_t> bytes, rgba;
        sepal_ports::GlRenderInfo info;
        sepal_ports::Rgba8Image diffuse;
        if (!diffuse_path.empty() && !sepal_ports::read_diffuse_png(diffuse_path, &diffuse, &err)) {
            std::fprintf(io.err, "sepal render: %s\n", err.c_str());
            return kExitBadInput;
        }
        opt.diffuse = diffuse_path.empty() ? nullptr : &diffuse;
        opt.float_target = float_target;
        if (float_target && opt.gles_version != 2) err = "--float-target needs a gles2 backend";
        if (!float_path.empty() && backend != "cpu" && !float_target)
            err = "--float: the GL backends render 8-bit images (add --float-target on gles2 backends)";
        if (err.empty() && file_extension(positional[0]) != "sepal")
            err = "backend " + backend + " renders a baked asset (.sepal); '" + positional[0] + "' is not one";
        if (!err.empty() || !sepal_ports::parse_mask(mask_text, &opt.mask, &err) ||
            !sepal_ports::load_scene_mesh(&setup, &err) ||
            !sepal_ports::read_asset_file(positional[0], &bytes, &err)) {
            std::fprintf(io.err, "sepal render: %s\n", err.c_str());
            return kExitBadInput;
        }
        if (backend == "cpu") {
            std::vector<float> rgb;
            double ms = 0;
            if (!sepal_ports::render_asset_cpu(bytes.data(), bytes.size(), setup, opt.diffuse, &rgb, &ms, &err)) {
                std::fprintf(io.err, "sepal render: %s\n", err.c_str());
                return kExitBadInput;
            }
            Image img(setup.width, setup.height, 3);
            img.data = rgb;
            int64_t clipped = 0;
            if ((!out_path.empty() && !write_png(out_path, img, &err, &clipped)) ||
                (!float_path.empty() && !write_pfm(float_path, img, &err))) {
                std::fprintf(io.err, "sepal render: %s\n", err.c_str());
                return kExitBadInput;
            }
            std::fprintf(io.out, "backend    cpu, %dx%d, %.1f ms\n", setup.width, setup.height, ms);
            if (!out_path.empty())
                std::fprintf(io.out, "png        %s (%lld channel values clipped to [0,1])\n", out_path.c_str(),
                             (long long)clipped);
            if (!float_path.empty()) std::fprintf(io.out, "pfm        %s\n", float_path.c_str());
            return kExitOk;
        }
        if (out_path.empty() ||
            !sepal_ports::render_asset_headless(bytes.data(), bytes.size(), setup, opt, &rgba, &info, &err)) {
            std::fprintf(io.err, "sepal render: %s\n", out_path.empty() ? "-o out.png is required" : err.c_str());
            return kExitBadInput;
        }
        const Image img = to_rgb(image_from_rgba8(rgba.data(), setup.width, setup.height));
        Image fimg(setup.width, setup.height, 3);
        fimg.data = info.float_rgb;
        if (!write_png(out_path, img, &err) || (!float_path.empty() && !write_pfm(float_path, fimg, &err))) {
            std::fprintf(io.err, "sepal render: %s\n", err.c_str());
            return kExitBadInput;
        }
        std::fprintf(io.out, "backend    %s, %dx%d, %.2f ms (%s)\n", backend.c_str(), setup.width, setup.height, info.ms,
                     info.device.c_str());
        std::fprintf(io.out, "path       %s: %d draws, %d full-screen passes, %d copies, %d doublings\n",
                     info.path.c_str(), info.stats.draw_calls, info.stats.fullscreen_passes,
                     info.stats.copies, info.stats.doublings);
        std::fprintf(io.out, "png        %s\n", out_path.c_str());
        return kExitOk;
    }
    if (backend != "exact") {
        std::fprintf(io.err, "sepal render: unknown backend '%s' (exact, gles1, gles2, gles2-fused, gles2-fused-pixel, cpu, "
                     "gles1-model, gles2-model)\n",
                     backend.c_str());
        return kExitBadInput;
    }
    if (!mask_text.empty() || !diffuse_path.empty()) {
        std::fprintf(io.err, "sepal render: --mask and --diffuse apply to the baked-asset backends only\n");
        return kExitBadInput;
    }
    std::unique_ptr<Brdf> brdf = make_brdf(positional[0], &err);
    if (!brdf || !sepal_ports::load_scene_mesh(&setup, &err)) {
        std::fprintf(io.err, "sepal render: %s\n", err.c_str());
        return kExitBadInput;
    }
    Image img;
    ExactStats stats;
    const auto start = std::chrono::steady_clock::now();
    if (!render_exact(*brdf, setup.scene, setup.mesh, setup.width, setup.height, &img, &stats, &err)) {
        std::fprintf(io.err, "sepal render: %s\n", err.c_str());
        return kExitBadInput;
    }
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    int64_t clipped = 0;
    if ((!out_path.empty() && !write_png(out_path, img, &err, &clipped)) ||
        (!float_path.empty() && !write_pfm(float_path, img, &err))) {
        std::fprintf(io.err, "sepal render: %s\n", err.c_str());
        return kExitBadInput;
    }
    std::fprintf(io.out, "backend    exact (%s), %dx%d, %.1f ms\n", brdf->spec().c_str(), setup.width,
                 setup.height, ms);
    std::fprintf(io.out, "pixels     %lld covered, %lld back-facing, %lld degenerate frames\n",
                 (long long)stats.covered_pixels, (long long)stats.back_facing_pixels,
                 (long long)stats.degenerate_frames);
    if (!out_path.empty())
        std::fprintf(io.out, "png        %s (%lld channel values clipped to [0,1])\n", out_path.c_str(),
                     (long long)clipped);
    if (!float_path.empty()) std::fprintf(io.out, "pfm        %s\n", float_path.c_str());
    return kExitOk;
}

}  // namespace sepal
