// sepal render SPEC_OR_ASSET --backend exact|gles1|gles2|gles2-fused|gles2-fused-pixel|cpu|
//   gles1-model|gles2-model [--mask LIST] [--diffuse PNG] [scene flags] -o out.png [--float out.pfm]
// sepal render SPEC --env sky|constant|FILE.hdr [--spp N] [--sampler cosine|factored|FILE.smp] [--seed S] ...
// sepal render --scene FILE.json [--time T] [--backend ...] [--size WxH] -o out.png
#include <chrono>
#include <cstring>
#include <memory>

#include <unistd.h>

#include "cli/cli.h"
#include "cli/options.h"
#include "cli/scene_file.h"
#include "util/io.h"
#include "reference/render_exact.h"
#include "sampling/alternatives.h"
#include "sampling/environment.h"
#include "sampling/factored_fit.h"
#include "sampling/mc_render.h"
#include "sampling/sampler_file.h"
#include "util/image.h"
#include "sepal/sepal_asset.h"
#include "common/render_gl.h"
#include "common/scene_flags.h"
#include "cli/scene_options.h"
#include "spec/spec.h"

namespace sepal {

namespace {

struct RenderArgs {
    sepal_ports::SceneSetup setup;
    std::string input, backend, out_path, float_path, mask_text, diffuse_path, framebuffer;
    bool float_target = false;
    // Monte Carlo under an environment (exact backend): --env picks it.
    std::string env, sampler = "factored", mis = "auto";
    int spp = 16;
    int supersample = kReferenceSupersample;
    uint64_t seed = 1;
    // A scene file (docs/scenes.md) at a time; which scene flags were given.
    std::string scene, cache, export_dir;
    double time = 0;
    std::vector<const CLI::Option*> scene_flags;
};

// --scene: a frame of many objects from a scene file, on any backend or exact.
int run_render_scene(RenderArgs& args, const CommandIO& io) {
    auto fail = [&](const std::string& m) {
        std::fprintf(io.err, "sepal render: %s\n", m.c_str());
        return kExitBadInput;
    };
    bool size_given = false;
    for (const CLI::Option* o : args.scene_flags) {
        if (!o->count()) continue;
        if (o->get_name() == "--size") size_given = true;
        else return fail("--scene: the scene file sets camera, lights, meshes and background; " + o->get_name() + " does not apply (--size does)");
    }
    if (!args.input.empty()) return fail("--scene draws the scene file's materials; give no INPUT ('" + args.input + "')");
    if (!args.env.empty() || !args.diffuse_path.empty() || args.float_target)
        return fail("--scene takes no --env, --diffuse or --float-target");
    const std::string backend = args.backend.empty() ? "gles1" : args.backend;
    std::string err;
    int framebuffer = 8888;
    if (!args.framebuffer.empty()) {
        sepal_ports::GlRenderOptions gl_backend;
        if (!sepal_ports::parse_gl_backend(backend, &gl_backend))
            return fail("--scene: --framebuffer applies to the GL backends (not " + backend + ")");
        if (!sepal_ports::parse_framebuffer(args.framebuffer, &framebuffer, &err)) return fail(err);
    }
    if (!args.export_dir.empty()) {
        SceneFile file;
        LoadedScene scene;
        if (!read_scene_file(args.scene, &file, &err) ||
            !load_scene(file, args.cache.empty() ? default_scene_cache() : args.cache, &scene, &err, io.err) ||
            !export_scene_bundle(scene, args.export_dir, &err))
            return fail(err);
        std::fprintf(io.out, "bundle     %s/scene.txt\n", args.export_dir.c_str());
        return kExitOk;
    }
    if (args.out_path.empty() && args.float_path.empty()) return fail("give -o out.png (or --float out.pfm: exact, cpu)");
    if (!args.float_path.empty() && backend != "exact" && backend != "cpu") return fail("--float: exact and cpu only");
    if (!args.mask_text.empty() && (backend == "exact" || backend == "cpu")) return fail("--mask applies to the GL backends and their models");
    if (args.supersample != kReferenceSupersample && backend != "exact") return fail("--supersample applies to the exact backend");
    if (!check_output("-o", args.out_path, &err) || !check_output("--float", args.float_path, &err)) return fail(err);
    SceneFile file;
    LoadedScene scene;
    SceneFrame fr;
    if (!read_scene_file(args.scene, &file, &err) ||
        !load_scene(file, args.cache.empty() ? default_scene_cache() : args.cache, &scene, &err, io.err))
        return fail(err);
    const int w = size_given ? args.setup.width : file.width, h = size_given ? args.setup.height : file.height;
    if (!scene_frame(scene, args.time, w, h, &fr, &err)) return fail(err);
    std::fprintf(io.out, "scene      %s at t = %g s: %zu objects, %zu materials (%d baked now, %d from the cache), %d lights\n",
                 args.scene.c_str(), args.time, file.objects.size(), file.materials.size(), scene.baked, scene.cached,
                 fr.light_count);
    Image img;
    std::vector<uint8_t> rgba;
    const auto start = std::chrono::steady_clock::now();
    std::string line;
    sepal_ports::GlRenderOptions gl;
    uint32_t mask = 0;
    if (!sepal_ports::parse_mask(args.mask_text, &mask, &err)) return fail(err);
    if (backend == "exact") {
        if (!render_scene_exact(scene, fr, args.supersample, &img, &err)) return fail(err);
        line = std::to_string(args.supersample) + "x" + std::to_string(args.supersample) + " samples per pixel";
    } else if (backend == "cpu") {
        if (!render_scene_cpu(scene, fr, &img, nullptr, &err)) return fail(err);
        line = "the runtime's CPU backend";
    } else if (backend == "gles1-model" || backend == "gles2-model") {
        if (!render_scene_emulated(scene, fr, backend == "gles1-model" ? 1 : 2, mask, &rgba, &err)) return fail(err);
        line = "the GL ES pipeline emulated on the CPU";
    } else if (sepal_ports::parse_gl_backend(backend, &gl)) {
        SceneGlOptions o;
        o.gles_version = gl.gles_version;
        o.mode = gl.mode;
        o.mask = mask;
        o.framebuffer = framebuffer;
        SceneGlInfo info;
        if (!render_scene_gl(scene, fr, o, &rgba, &info, &err)) return fail(err);
        line = info.device + "; " + std::to_string(info.stats.draw_calls) + " draws, " +
               std::to_string(info.stats.doublings) + " doublings in this scene's frame";
        if (framebuffer == 565)
            line += info.accumulates ? "; framebuffer 5/6/5, each object's passes summed in an 8-bit target"
                                     : "; framebuffer 5/6/5, every pass rounded to it";
    } else {
        return fail("unknown backend '" + backend + "'");
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!rgba.empty()) img = to_rgb(image_from_rgba8(rgba.data(), w, h));
    int64_t clipped = 0;
    OutputGuard written;
    if ((!args.out_path.empty() && !write_png(args.out_path, img, &err, &clipped)) ||
        (!args.float_path.empty() && !write_pfm(args.float_path, img, &err)) || !written.commit(&err))
        return fail(err);
    std::fprintf(io.out, "backend    %s, %dx%d, %.1f ms (%s)\n", backend.c_str(), w, h, ms, line.c_str());
    if (!args.out_path.empty()) std::fprintf(io.out, "png        %s\n", args.out_path.c_str());
    if (!args.float_path.empty()) std::fprintf(io.out, "pfm        %s\n", args.float_path.c_str());
    return kExitOk;
}

// The exact backend under distant lighting: a Monte Carlo estimate per pixel with the
// chosen importance sampler (offline/sampling/mc_render.h; unbiased whatever the sampler).
int run_render_mc(RenderArgs& args, const Brdf& brdf, const CommandIO& io) {
    std::string err;
    auto fail = [&](const std::string& m) {
        std::fprintf(io.err, "sepal render: %s\n", m.c_str());
        return kExitBadInput;
    };
    std::unique_ptr<Environment> env = make_environment(args.env, &err);
    if (!env) return fail("--env: " + err);
    SamplerData d;
    Sampler s;
    if (args.sampler == "cosine") {
        d = make_cosine_sampler();
    } else if (args.sampler == "factored") {
        FactoredOptions o;
        if (!fit_factored(brdf, o, &d, nullptr, &err)) return fail("--sampler factored: " + err);
    } else if (!s.read(args.sampler, &err)) {
        return fail("--sampler: not cosine, factored, or a sampler file: " + err);
    }
    if (!s.loaded() && !s.build(d, &err)) return fail(err);
    if (!sepal_ports::load_scene_mesh(&args.setup, &err)) return fail(err);
    McOptions o;
    o.spp = args.spp;
    o.seed = args.seed;
    o.mis = args.mis == "on" ? Mis::On : args.mis == "off" ? Mis::Off : Mis::Auto;
    McResult r;
    if (!render_mc(brdf, s.get(), *env, args.setup.scene, args.setup.mesh, args.setup.width, args.setup.height, o, &r,
                   &err))
        return fail(err);
    int64_t clipped = 0;
    OutputGuard written;
    if ((!args.out_path.empty() && !write_png(args.out_path, r.image, &err, &clipped)) ||
        (!args.float_path.empty() && !write_pfm(args.float_path, r.image, &err)) || !written.commit(&err))
        return fail(err);
    std::fprintf(io.out, "backend    exact, Monte Carlo: %s under %s, %d spp, sampler %s (%zu bytes)%s, seed %llu, %.1f s\n",
                 brdf.spec().c_str(), env->describe().c_str(), args.spp, args.sampler.c_str(), s.bytes(),
                 r.mis ? " + light samples (MIS, balance heuristic)" : "", (unsigned long long)args.seed, r.seconds);
    std::fprintf(io.out, "pixels     %lld shaded, %lld back-facing, %lld degenerate; %lld of %lld samples below the horizon\n",
                 (long long)r.shaded_pixels, (long long)r.back_facing, (long long)r.degenerate,
                 (long long)r.below_horizon, (long long)r.samples);
    if (!args.out_path.empty())
        std::fprintf(io.out, "png        %s (%lld channel values clipped to [0,1])\n", args.out_path.c_str(),
                     (long long)clipped);
    if (!args.float_path.empty()) std::fprintf(io.out, "pfm        %s\n", args.float_path.c_str());
    return kExitOk;
}

// Without --backend: a BRDF renders exactly; an asset on what it was baked for, GL ES 1.1,
// or the CPU backend when its parameterization needs per-pixel evaluation (gles1 refuses it).
bool default_backend(const std::string& input, std::string* backend, std::string* why, std::string* err) {
    if (file_extension(input) != "sepal") {
        *backend = "exact";
        *why = "the default for a BRDF";
        return true;
    }
    std::vector<uint8_t> bytes;
    if (!sepal_ports::read_asset_file(input, &bytes, err)) return false;
    auto asset = std::make_unique<sepal_asset>();
    sepal_error e{};
    if (sepal_asset_parse(bytes.data(), bytes.size(), asset.get(), &e) != SEPAL_OK) {
        *err = input + ": not a valid asset: " + e.message;
        return false;
    }
    const uint32_t p = asset->material.param;
    const bool per_vertex = p == SEPAL_PARAM_IV || p == SEPAL_PARAM_GS_HALF || p == SEPAL_PARAM_VH;
    *backend = per_vertex ? "gles1" : "cpu";
    *why = per_vertex ? "the default for an asset" : "its parameterization needs per-pixel evaluation, which gles1 lacks";
    return true;
}

// Frames above this many pixels are announced on stderr (class 9 above run_render).
constexpr double kLargeFramePixels = double(1 << 21);
// Peak memory of a frame per pixel, measured (exact backend, PNG and PFM written; the
// asset backends need less): what the refusal above is held to.
constexpr double kRenderBytesPerPixel = 40.0;

// --framebuffer: the GL backends' pbuffer, or the bits their models round to (8888 when not
// given).
bool framebuffer_arg(const RenderArgs& args, int* framebuffer, std::string* err) {
    if (args.framebuffer.empty()) return true;
    if (args.backend == "exact" || args.backend == "cpu") {
        *err = "--framebuffer applies to the GL backends and their models (not " + args.backend + ")";
        return false;
    }
    return sepal_ports::parse_framebuffer(args.framebuffer, framebuffer, err);
}

// The GL ES 1.1 emulator (gles1-model, gles2-model): what gles1 (or the gles2 multipass
// path) shows, on the CPU, rounding every pass to the framebuffer's bits (8888 or 565).
int render_model(RenderArgs& args, int framebuffer, const CommandIO& io) {
    sepal_ports::SceneSetup& setup = args.setup;
    const std::string& backend = args.backend;
    std::string err;
    std::vector<uint8_t> bytes, rgba;
    uint32_t mask = 0;
    sepal_draw_stats stats = {};
    if (!args.diffuse_path.empty() || !args.float_path.empty() || args.float_target || args.out_path.empty())
        err = backend + " writes an 8-bit PNG (-o) and takes no --diffuse, --float or --float-target";
    if (!err.empty() || !sepal_ports::parse_mask(args.mask_text, &mask, &err) ||
        !sepal_ports::load_scene_mesh(&setup, &err) || !sepal_ports::read_asset_file(args.input, &bytes, &err) ||
        !sepal_ports::render_asset_emulated(bytes.data(), bytes.size(), setup, backend == "gles1-model" ? 1 : 2,
                                            mask, &rgba, &err, &stats, framebuffer) ||
        !write_png(args.out_path, to_rgb(image_from_rgba8(rgba.data(), setup.width, setup.height)), &err)) {
        std::fprintf(io.err, "sepal render: %s\n", err.c_str());
        return kExitBadInput;
    }
    std::fprintf(io.out, "backend    %s (the GL ES pipeline emulated on the CPU), %dx%d, %d doublings in this scene's frame\n",
                 backend.c_str(), setup.width, setup.height, stats.doublings);
    // Fewer bits: summed in 8 bits unless framebuffer objects are masked (srt::accumulates).
    const bool summed = framebuffer == 565 && !(mask & SEPAL_MASK_FBO);
    std::fprintf(io.out, "framebuffer %s bits per channel, no dithering (modelled)%s\n",
                 framebuffer == 565 ? "5/6/5" : "8/8/8", summed ? ", passes summed in an 8-bit target" : "");
    const std::string dim = sepal_ports::light_range_warning(bytes.data(), bytes.size(), stats, args.input);
    if (!dim.empty()) std::fprintf(io.err, "sepal render: %s\n", dim.c_str());
    // The context the emulator stands for (sepal_emulate_draw's): its framebuffer's bits.
    sepal_caps caps = {};
    caps.gles_version = backend == "gles1-model" ? 1 : 2;
    caps.texture_units = caps.gles_version == 1 ? 2 : 8;
    caps.has_blend_subtract = (mask & SEPAL_MASK_BLEND_SUBTRACT) ? 0 : 1;
    caps.red_bits = caps.blue_bits = framebuffer == 565 ? 5 : 8;
    caps.green_bits = framebuffer == 565 ? 6 : 8;
    const std::string weaker = sepal_ports::profile_warning(bytes.data(), bytes.size(), caps, stats);
    if (!weaker.empty()) std::fprintf(io.err, "sepal render: %s\n", weaker.c_str());
    std::fprintf(io.out, "png        %s\n", args.out_path.c_str());
    return kExitOk;
}

// An asset on a GL backend (headless) or the CPU backend; opt: the GL backend's options.
int render_asset(RenderArgs& args, sepal_ports::GlRenderOptions opt, int framebuffer, const CommandIO& io) {
    sepal_ports::SceneSetup& setup = args.setup;
    const std::string& backend = args.backend;
    const std::string& out_path = args.out_path;
    const std::string& float_path = args.float_path;
    const std::string& mask_text = args.mask_text;
    const std::string& diffuse_path = args.diffuse_path;
    const bool float_target = args.float_target;
    std::string err;
    std::vector<uint8_t> bytes, rgba;
    sepal_ports::GlRenderInfo info;
    sepal_ports::Rgba8Image diffuse;
    if (!diffuse_path.empty() && !sepal_ports::read_diffuse_png(diffuse_path, &diffuse, &err)) {
        std::fprintf(io.err, "sepal render: %s\n", err.c_str());
        return kExitBadInput;
    }
    opt.diffuse = diffuse_path.empty() ? nullptr : &diffuse;
    opt.float_target = float_target;
    opt.framebuffer = framebuffer;
    if (float_target && opt.gles_version != 2) err = "--float-target needs a gles2 backend";
    if (!float_path.empty() && backend != "cpu" && !float_target)
        err = "--float: the GL backends render 8-bit images (add --float-target on gles2 backends)";
    if (err.empty() && file_extension(args.input) != "sepal")
        err = "backend " + backend + " renders a baked asset (.sepal); '" + args.input + "' is not one";
    if (!err.empty() || !sepal_ports::parse_mask(mask_text, &opt.mask, &err) ||
        !sepal_ports::load_scene_mesh(&setup, &err) ||
        !sepal_ports::read_asset_file(args.input, &bytes, &err)) {
        std::fprintf(io.err, "sepal render: %s\n", err.c_str());
        return kExitBadInput;
    }
    if (backend == "cpu") {
        std::vector<float> rgb;
        double ms = 0;
        sepal_draw_stats stats = {};
        if (!sepal_ports::render_asset_cpu(bytes.data(), bytes.size(), setup, opt.diffuse, &rgb, &ms, &err,
                                           &stats)) {
            std::fprintf(io.err, "sepal render: %s\n", err.c_str());
            return kExitBadInput;
        }
        const std::string dim = sepal_ports::light_range_warning(bytes.data(), bytes.size(), stats, args.input);
        if (!dim.empty()) std::fprintf(io.err, "sepal render: %s\n", dim.c_str());
        Image img(setup.width, setup.height, 3);
        img.data = rgb;
        int64_t clipped = 0;
        OutputGuard written;
        if ((!out_path.empty() && !write_png(out_path, img, &err, &clipped)) ||
            (!float_path.empty() && !write_pfm(float_path, img, &err)) || !written.commit(&err)) {
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
    OutputGuard written;
    if (!write_png(out_path, img, &err) || (!float_path.empty() && !write_pfm(float_path, fimg, &err)) ||
        !written.commit(&err)) {
        std::fprintf(io.err, "sepal render: %s\n", err.c_str());
        return kExitBadInput;
    }
    std::fprintf(io.out, "backend    %s, %dx%d, %.2f ms (%s)\n", backend.c_str(), setup.width, setup.height, info.ms,
                 info.device.c_str());
    std::fprintf(io.out, "path       %s: %d draws, %d full-screen passes, %d copies, %d doublings in this scene's frame\n",
                 info.path.c_str(), info.stats.draw_calls, info.stats.fullscreen_passes,
                 info.stats.copies, info.stats.doublings);
    std::fprintf(io.out, "framebuffer %d/%d/%d bits per channel, GL_DITHER %s\n", info.caps.red_bits,
                 info.caps.green_bits, info.caps.blue_bits, info.caps.dither ? "on" : "off");
    std::fprintf(io.out, "png        %s\n", out_path.c_str());
    const std::string dim = sepal_ports::light_range_warning(bytes.data(), bytes.size(), info.stats, args.input);
    if (!dim.empty()) std::fprintf(io.err, "sepal render: %s\n", dim.c_str());
    const std::string weaker = sepal_ports::profile_warning(bytes.data(), bytes.size(), info.caps, info.stats);
    if (!weaker.empty()) std::fprintf(io.err, "sepal render: %s\n", weaker.c_str());
    return kExitOk;
}

// The exact backend: a BRDF spec or measured file per pixel (or Monte Carlo under --env).
int render_exact_backend(RenderArgs& args, bool large, const CommandIO& io) {
    sepal_ports::SceneSetup& setup = args.setup;
    const std::string& out_path = args.out_path;
    const std::string& float_path = args.float_path;
    const std::string& mask_text = args.mask_text;
    const std::string& diffuse_path = args.diffuse_path;
    std::string err;
    if (!mask_text.empty() || !diffuse_path.empty()) {
        std::fprintf(io.err, "sepal render: --mask and --diffuse apply to the baked-asset backends only\n");
        return kExitBadInput;
    }
    std::unique_ptr<Brdf> brdf = make_brdf(args.input, &err);
    if (brdf && !args.env.empty()) return run_render_mc(args, *brdf, io);
    if (brdf && args.env.empty() && (args.spp != 16 || args.sampler != "factored" || args.seed != 1)) {
        std::fprintf(io.err, "sepal render: --spp, --sampler and --seed apply with --env (a Monte Carlo render)\n");
        return kExitBadInput;
    }
    if (!brdf || !sepal_ports::load_scene_mesh(&setup, &err)) {
        std::fprintf(io.err, "sepal render: %s\n", err.c_str());
        return kExitBadInput;
    }
    Image img;
    ExactStats stats;
    const auto start = std::chrono::steady_clock::now();
    if (!render_exact(*brdf, setup.scene, setup.mesh, setup.width, setup.height, &img, &stats, &err,
                      large && isatty(fileno(io.err)), args.supersample)) {
        std::fprintf(io.err, "sepal render: %s\n", err.c_str());
        return kExitBadInput;
    }
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    int64_t clipped = 0;
    OutputGuard written;
    if ((!out_path.empty() && !write_png(out_path, img, &err, &clipped)) ||
        (!float_path.empty() && !write_pfm(float_path, img, &err)) || !written.commit(&err)) {
        std::fprintf(io.err, "sepal render: %s\n", err.c_str());
        return kExitBadInput;
    }
    std::fprintf(io.out, "backend    exact (%s), %dx%d, %dx%d samples per pixel, %.1f ms\n", brdf->spec().c_str(),
                 setup.width, setup.height, args.supersample, args.supersample, ms);
    std::fprintf(io.out, "pixels     %lld covered, %lld back-facing, %lld degenerate frames\n",
                 (long long)stats.covered_pixels, (long long)stats.back_facing_pixels,
                 (long long)stats.degenerate_frames);
    if (!out_path.empty())
        std::fprintf(io.out, "png        %s (%lld channel values clipped to [0,1])\n", out_path.c_str(),
                     (long long)clipped);
    if (!float_path.empty()) std::fprintf(io.out, "pfm        %s\n", float_path.c_str());
    return kExitOk;
}

int run_render(RenderArgs& args, const CommandIO& io) {
    sepal_ports::SceneSetup& setup = args.setup;
    std::string chosen_why;
    if (args.backend.empty()) {
        std::string err;
        if (!default_backend(args.input, &args.backend, &chosen_why, &err)) {
            std::fprintf(io.err, "sepal render: %s\n", err.c_str());
            return kExitBadInput;
        }
        if (args.backend != "exact")  // an asset: say which of several backends it got
            std::fprintf(io.out, "backend    %s: %s (--backend picks another)\n", args.backend.c_str(),
                         chosen_why.c_str());
    } else if (args.backend == "exact" && file_extension(args.input) == "sepal") {
        std::fprintf(io.err,
                     "sepal render: %s is a baked asset; --backend exact renders a BRDF spec or measured file. "
                     "Give an asset backend (gles1, gles2, gles2-fused, gles2-fused-pixel, cpu, gles1-model, gles2-model) or leave "
                     "--backend out\n",
                     args.input.c_str());
        return kExitBadInput;
    }
    if (args.supersample != kReferenceSupersample && (args.backend != "exact" || !args.env.empty())) {
        std::fprintf(io.err, "sepal render: --supersample applies to the exact backend without --env (got %s%s)\n",
                     args.backend.c_str(), args.env.empty() ? "" : " with --env");
        return kExitBadInput;
    }
    const std::string& backend = args.backend;
    const std::string& out_path = args.out_path;
    const std::string& float_path = args.float_path;
    std::string err;
    // A frame over 2 Mpixels takes seconds (the exact backend shades about
    // 1.3 Mpixels a second on 2 cores: 8192x8192 is close to a minute) and memory in
    // proportion: said on stderr before it starts, with progress on a terminal, and refused
    // when its buffers cannot fit in this machine's memory.
    const double pixels = double(setup.width) * double(setup.height);
    const double need_mb = pixels * kRenderBytesPerPixel / (1024.0 * 1024.0);
    const double physical_mb = physical_memory_mb();
    if (physical_mb > 0 && need_mb > physical_mb) {
        std::fprintf(io.err, "sepal render: --size %dx%d needs about %.0f MB; this machine has %.0f MB of memory\n",
                     setup.width, setup.height, need_mb, physical_mb);
        return kExitBadInput;
    }
    const bool large = pixels > kLargeFramePixels;
    if (large)
        std::fprintf(io.err, "sepal render: %dx%d is %.1f Mpixels (about %.0f MB): this can take a minute%s\n",
                     setup.width, setup.height, pixels / 1e6, need_mb,
                     isatty(fileno(io.err)) ? "" : " (progress is shown on a terminal)");
    if (out_path.empty() && float_path.empty()) {
        std::fprintf(io.err, "sepal render: give -o out.png or --float out.pfm\n");
        return kExitBadInput;
    }
    int framebuffer = 8888;
    if (!check_output("-o", out_path, &err) || !check_output("--float", float_path, &err) ||
        !framebuffer_arg(args, &framebuffer, &err)) {
        std::fprintf(io.err, "sepal render: %s\n", err.c_str());
        return kExitBadInput;
    }
    if (backend == "gles1-model" || backend == "gles2-model") return render_model(args, framebuffer, io);
    sepal_ports::GlRenderOptions opt;
    if (sepal_ports::parse_gl_backend(backend, &opt) || backend == "cpu") return render_asset(args, opt, framebuffer, io);
    if (backend != "exact") {
        std::fprintf(io.err, "sepal render: unknown backend '%s' (exact, gles1, gles2, gles2-fused, gles2-fused-pixel, cpu, "
                     "gles1-model, gles2-model)\n",
                     backend.c_str());
        return kExitBadInput;
    }
    return render_exact_backend(args, large, io);
}

// A scene file, or one material in a scene of flags.
int run_render_any(RenderArgs& args, const CommandIO& io) {
    if (!args.scene.empty()) return run_render_scene(args, io);
    if (args.input.empty()) {
        std::fprintf(io.err, "sepal render: give INPUT (a BRDF spec, measured file or .sepal asset) or --scene FILE\n");
        return kExitBadInput;
    }
    if (args.time != 0 || !args.cache.empty() || !args.export_dir.empty()) {
        std::fprintf(io.err, "sepal render: --time, --cache and --export apply with --scene\n");
        return kExitBadInput;
    }
    return run_render(args, io);
}

}  // namespace

CommandRun setup_render(CLI::App& app) {
    auto a = std::make_shared<RenderArgs>();
    app.add_option("INPUT", a->input,
                   "a BRDF spec or measured file (exact backend), or a baked .sepal asset (required without --scene)");
    app.add_option("--scene", a->scene,
                   "a scene file (JSON, docs/scenes.md): many objects, materials, moving lights, a camera; drawn on "
                   "--backend (default gles1) or exact");
    app.add_option("--time", a->time, "with --scene: the time in seconds (moving lights, orbiting camera, spinning objects)")
        ->check(CLI::Range(-1e6, 1e6));
    app.add_option("--export", a->export_dir,
                   "with --scene: write the scene as a bundle into this folder (scene.txt, baked assets, meshes) for "
                   "sepal-view --scene, and render nothing");
    app.add_option("--cache", a->cache,
                   "with --scene: the folder for the scene's baked materials (default: build/cache/scenes beside the "
                   "binary)");
    app.add_option("--backend", a->backend,
                   "exact: the BRDF per pixel on the CPU; gles1, gles2, gles2-fused, gles2-fused-pixel: a baked "
                   "asset on GL ES (headless); cpu: a baked asset on the runtime's CPU backend; gles1-model, "
                   "gles2-model: the GL ES pipeline emulated on the CPU (8-bit texels, the framebuffer of --framebuffer). Default: "
                   "exact for a BRDF, gles1 for an asset (cpu when its parameterization is per-pixel only)")
        ->check(CLI::IsMember(
            {"exact", "gles1", "gles2", "gles2-fused", "gles2-fused-pixel", "cpu", "gles1-model", "gles2-model"}));
    app.add_option("-o,--output", a->out_path, "the PNG to write (8-bit, clipped to [0,1])");
    app.add_option("--float", a->float_path, "also write linear floats as PFM (exact, cpu; GL with --float-target)");
    app.add_flag("--float-target", a->float_target, "gles2 backends: draw into a half-float target");
    app.add_option("--framebuffer", a->framebuffer,
                   "the colour buffer's bits: 8888 (default) or 565 (RGB565, as older phones and kiosk boards "
                   "render); the GL backends draw into such a pbuffer (a --scene too), gles1-model and "
                   "gles2-model model one (each object's passes summed in 8 bits and written once, rounded; "
                   "every pass rounded with --mask fbo)");
    app.add_option("--mask", a->mask_text,
                   "hide GL capabilities to force fallback paths: subtract, multitexture, fbo, npot, third-unit "
                   "(comma-separated)");
    app.add_option("--diffuse", a->diffuse_path, "a diffuse texture map (PNG, power-of-two sides) modulating the material");
    app.add_option("--env", a->env,
                   "exact backend, Monte Carlo under distant light: constant[:V|:R,G,B], sky[:key=value,...] or a "
                   "latitude-longitude FILE.hdr");
    app.add_option("--supersample", a->supersample,
                   "exact backend: S x S samples per pixel, averaged (coverage stays the pixel centre's, as on GL); "
                   "1 shades the centre only, which aliases where shading changes fast")
        ->check(CLI::Range(1, kMaxExactSupersample))
        ->capture_default_str();
    app.add_option("--spp", a->spp, "with --env: samples per pixel")->check(CLI::Range(1, 1000000))->capture_default_str();
    app.add_option("--sampler", a->sampler, "with --env: cosine, factored (fitted now), or a file from `sepal sampler`")
        ->capture_default_str();
    app.add_option("--seed", a->seed, "with --env: the sample sequence's seed")->capture_default_str();
    app.add_option("--mis", a->mis,
                   "with --env: also sample the environment's luminance and weight both by the balance heuristic "
                   "(auto: on unless the environment is constant)")
        ->check(CLI::IsMember({"auto", "on", "off"}))
        ->capture_default_str();
    sepal::add_scene_options(app, &a->setup);
    for (const char* f : {"--size", "--mesh", "--camera", "--target", "--fov", "--background", "--light"})
        a->scene_flags.push_back(app.get_option(f));
    return [a](const CommandIO& io) { return run_render_any(*a, io); };
}

}  // namespace sepal
