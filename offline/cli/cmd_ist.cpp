// sepal ist: inverse shade trees (Lawrence et al. 2006; offline/ist/, docs/ist.md). Subcommands:
//   sepal ist generate -o DIR [--size N] [--materials N] [--preset P] [--noise S]
//                      [--misregistration S] [--missing SHARE] [--halftone A] [--seed S]
//   sepal ist decompose DIR -o TREE [--method sacls|acls|pca|nmf|kmeans] [--terms K] [--max-terms K]
//                      [--sparsity L] [--normalization M] [--curve-terms N] [--res N] [--seed S]
//   sepal ist edit TREE [--curve BASIS.CURVE=FILE.csv] [--blend J=IMAGE.png] [--swap J=SPEC] [-o OUT]
//   sepal ist render TREE -o out.png [--backend exact|cpu|gles1|gles2|gles2-fused-pixel] [scene flags]
// Thin mains over offline/ist: every check and message is the library's.
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/cli.h"
#include "cli/options.h"
#include "cli/scene_options.h"
#include "common/render_tree.h"
#include "ist/decompose.h"
#include "ist/figures.h"
#include "ist/generate.h"
#include "svbrdf/samples.h"
#include "ist/tree.h"
#include "ist/tree_asset.h"
#include "reference/render_exact.h"
#include "util/image.h"
#include "util/io.h"

namespace sepal {
namespace {

int fail(const CommandIO& io, const char* who, const std::string& err) {
    std::fprintf(io.err, "sepal ist %s: %s\n", who, err.c_str());
    return kExitBadInput;
}

struct GenerateArgs {
    GenerateOptions o;
    std::string out;
    int size = 64;
};

int run_generate(GenerateArgs a, const CommandIO& io) {
    a.o.width = a.o.height = a.size;
    SvbrdfSamples s;
    BlendSvbrdf truth;
    std::string err;
    if (!generate_svbrdf(a.o, &s, &truth, &err) || !write_svbrdf(a.out, s, &err) || !write_truth(a.out, truth, &err))
        return fail(io, "generate", err);
    const SvbrdfCounts n = count_samples(s);
    std::fprintf(io.out, "svbrdf     %s: %dx%d texels, %d direction pairs, %d bases (%s preset)\n", a.out.c_str(),
                 s.width, s.height, s.pair_count(), truth.maps.count, a.o.preset.c_str());
    std::fprintf(io.out, "samples    %lld, %lld missing\n", (long long)n.samples, (long long)n.missing);
    return kExitOk;
}

struct DecomposeArgs {
    DecomposeOptions d;
    TreeOptions t;
    std::string in, out, method = "sacls";
};

int run_decompose(DecomposeArgs a, const CommandIO& io) {
    std::string err;
    if (!parse_ist_method(a.method, &a.d.method)) return fail(io, "decompose", "--method '" + a.method + "': unknown");
    SvbrdfSamples s;
    if (!read_svbrdf(a.in, &s, &err)) return fail(io, "decompose", err);
    Decomposition dec;
    ShadeTree tree;
    if (!decompose_svbrdf(s, a.d, &dec, &err) || !build_tree(dec, a.t, &tree, &err) || !write_tree(a.out, tree, &err))
        return fail(io, "decompose", err);
    std::fprintf(io.out, "top level  %s, %d terms, RMS %.4g (1/sr), %.1f s\n", ist_method_name(dec.method), dec.terms,
                 dec.rms, dec.seconds);
    for (size_t j = 0; j < tree.level_errors.size(); ++j)
        std::fprintf(io.out, "basis %zu    tabular %.4g, factors %.4g, curves %.4g (relative RMS)\n", j,
                     tree.level_errors[j].tabular, tree.level_errors[j].factors, tree.level_errors[j].curves);
    std::fprintf(io.out, "tree       %s\n", a.out.c_str());
    return kExitOk;
}

// "J=VALUE" -> J and VALUE; false when J is not an integer in [0, count).
bool split_edit(const std::string& text, int count, int* j, std::string* value, std::string* err) {
    const size_t eq = text.find('=');
    char* end = nullptr;
    const long v = eq == std::string::npos ? -1 : std::strtol(text.c_str(), &end, 10);
    if (eq == std::string::npos || end != text.c_str() + eq || v < 0 || v >= count) {
        *err = "'" + text + "': expected J=VALUE with J a basis in 0.." + std::to_string(count - 1);
        return false;
    }
    *j = int(v);
    *value = text.substr(eq + 1);
    return true;
}

struct EditArgs {
    std::string tree, out;
    std::vector<std::string> curves, blends, swaps;
};

int run_edit(const EditArgs& a, const CommandIO& io) {
    std::string err;
    ShadeTree t;
    if (!read_tree(a.tree, &t, &err)) return fail(io, "edit", err);
    if (a.curves.empty() && a.blends.empty() && a.swaps.empty())
        return fail(io, "edit", "nothing to do: give --curve, --blend or --swap");
    for (const std::string& c : a.curves) {
        // BASIS.CURVE=FILE: curve 0..3 of the basis's term list, flattened (term * 4 + i).
        const size_t dot = c.find('.');
        int j = 0, k = 0;
        std::string path, rest;
        if (dot == std::string::npos || !split_edit(c.substr(0, dot) + "=", t.basis_count(), &j, &rest, &err) ||
            !split_edit(c.substr(dot + 1), 1 << 20, &k, &path, &err))
            return fail(io, "edit", "--curve '" + c + "': expected BASIS.CURVE=FILE.csv (" + err + ")");
        const int term = k / 4, which = k % 4;
        if (term >= int(t.bases[size_t(j)].terms.size()))
            return fail(io, "edit", "--curve '" + c + "': basis " + std::to_string(j) + " has " +
                                        std::to_string(4 * t.bases[size_t(j)].terms.size()) + " curves");
        Curve cv;
        if (!read_curve_csv(path, which % 2 == 1, &cv, &err) || !t.set_curve(j, k, cv, &err))
            return fail(io, "edit", err);
    }
    for (const std::string& b : a.blends) {
        int j = 0;
        std::string path;
        Image img;
        if (!split_edit(b, t.basis_count(), &j, &path, &err) || !read_image(path, &img, &err) || !t.set_blend(j, img, &err))
            return fail(io, "edit", "--blend: " + err);
    }
    TreeOptions o;
    o.param = t.param;
    o.map = t.map;
    o.res = t.res;
    for (const std::string& s : a.swaps) {
        int j = 0;
        std::string spec;
        if (!split_edit(s, t.basis_count(), &j, &spec, &err) || !t.swap_basis(j, spec, o, &err))
            return fail(io, "edit", "--swap: " + err);
    }
    const std::string out = a.out.empty() ? a.tree : a.out;
    if (!write_tree(out, t, &err)) return fail(io, "edit", err);
    std::fprintf(io.out, "edited     %zu curves, %zu blend maps, %zu bases swapped\n", a.curves.size(), a.blends.size(),
                 a.swaps.size());
    std::fprintf(io.out, "tree       %s\n", out.c_str());
    return kExitOk;
}

struct RenderArgs {
    std::string tree, out, backend = "gles1";
    sepal_ports::SceneSetup setup;
};

int run_render(RenderArgs a, const CommandIO& io) {
    std::string err;
    ShadeTree t;
    if (!read_tree(a.tree, &t, &err)) return fail(io, "render", err);
    if (!sepal_ports::load_scene_mesh(&a.setup, &err)) return fail(io, "render", err);
    const int w = a.setup.width, h = a.setup.height;
    Image img(w, h, 3);
    const auto t0 = std::chrono::steady_clock::now();
    std::string path = "exact (the tree's curves per pixel)";
    if (a.backend == "exact") {
        if (!render_exact_spatial(TreeSvbrdf(t), a.setup.scene, a.setup.mesh, w, h, &img, nullptr, &err))
            return fail(io, "render", err);
    } else {
        std::vector<uint8_t> bytes;
        if (!encode_tree_asset(t, TreeAssetOptions(), &bytes, nullptr, &err)) return fail(io, "render", err);
        if (a.backend == "cpu") {
            if (!sepal_ports::render_tree_cpu(bytes.data(), bytes.size(), a.setup, &img.data, nullptr, &err))
                return fail(io, "render", err);
            path = "cpu";
        } else {
            sepal_ports::GlRenderOptions o;
            o.gles_version = a.backend == "gles1" ? 1 : 2;
            o.mode = a.backend == "gles2-fused-pixel" ? SEPAL_MODE_FUSED_PIXEL : SEPAL_MODE_MULTIPASS;
            std::vector<uint8_t> rgba;
            sepal_ports::GlRenderInfo info;
            if (!sepal_ports::render_tree_headless(bytes.data(), bytes.size(), a.setup, o, &rgba, &info, &err))
                return fail(io, "render", err);
            img = to_rgb(image_from_rgba8(rgba.data(), w, h));
            char buf[256];
            std::snprintf(buf, sizeof buf, "%s, %d draws, %d full-screen passes, %.2f ms (%s)", info.path.c_str(),
                          info.stats.draw_calls, info.stats.fullscreen_passes, info.ms, info.device.c_str());
            path = buf;
        }
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (!write_png(a.out, img, &err)) return fail(io, "render", err);
    std::fprintf(io.out, "backend    %s: %s, %dx%d, %.1f ms in all\n", a.backend.c_str(), path.c_str(), w, h, ms);
    std::fprintf(io.out, "png        %s\n", a.out.c_str());
    return kExitOk;
}

CommandRun setup_generate(CLI::App& c) {
    auto a = std::make_shared<GenerateArgs>();
    c.add_option("-o,--output", a->out, "the SVBRDF folder to write")->required();
    c.add_option("--size", a->size, "texels per side")->check(CLI::Range(4, 1024))->capture_default_str();
    c.add_option("--materials", a->o.materials, "basis materials blended (2..6)")
        ->check(CLI::Range(2, 6))->capture_default_str();
    c.add_option("--preset", a->o.preset, "the basis materials' preset")->capture_default_str();
    c.add_option("--noise", a->o.noise, "relative measurement noise")
        ->check(finite_range(0, 1))->capture_default_str();
    c.add_option("--misregistration", a->o.misregistration, "misregistration, texels")
        ->check(finite_range(0, 4))->capture_default_str();
    c.add_option("--missing", a->o.missing, "share of samples missing (confidence 0)")
        ->check(finite_range(0, 0.95))->capture_default_str();
    c.add_option("--halftone", a->o.halftone, "opacity of the gold stripes (1: materials mix only along edges)")
        ->check(finite_range(0, 1))->capture_default_str();
    c.add_option("--seed", a->o.seed, "random seed")->capture_default_str();
    return [a](const CommandIO& io) { return run_generate(*a, io); };
}

CommandRun setup_decompose(CLI::App& c) {
    auto a = std::make_shared<DecomposeArgs>();
    c.add_option("SVBRDF", a->in, "an SVBRDF folder (sepal ist generate, docs/ist.md)")->required();
    c.add_option("-o,--output", a->out, "the tree folder to write")->required();
    c.add_option("--method", a->method, "top level: sacls, acls, pca, nmf or kmeans")
        ->check(CLI::IsMember({"sacls", "acls", "pca", "nmf", "kmeans"}))->capture_default_str();
    // The library's bounds (decompose.h: terms 1..8), so the flag is refused by name.
    c.add_option("--terms", a->d.terms, "basis materials; 0: chosen by error")
        ->check(CLI::Range(0, 8))->capture_default_str();
    c.add_option("--max-terms", a->d.max_terms, "most basis materials tried when choosing")
        ->check(CLI::Range(1, 8))->capture_default_str();
    c.add_option("--sparsity", a->d.sparsity, "SACLS's l (one material per texel)")
        ->check(finite_range(0, 1e6))->capture_default_str();
    c.add_option("--normalization", a->d.normalization, "SACLS's m (weights sum to one)")
        ->check(finite_range(0, 1e6))->capture_default_str();
    c.add_option("--curve-terms", a->t.terms, "separable terms per basis (second level)")
        ->check(CLI::Range(1, 8))->capture_default_str();
    c.add_option("--res", a->t.res, "factor texture side per basis")->check(CLI::Range(4, 256))->capture_default_str();
    c.add_option("--seed", a->d.seed, "random seed (restarts)")->capture_default_str();
    return [a](const CommandIO& io) { return run_decompose(*a, io); };
}

CommandRun setup_edit(CLI::App& c) {
    auto a = std::make_shared<EditArgs>();
    c.add_option("TREE", a->tree, "a tree folder (sepal ist decompose)")->required();
    c.add_option("-o,--output", a->out, "the edited tree's folder (default: in place)");
    c.add_option("--curve", a->curves, "BASIS.CURVE=FILE.csv: curve 4*term+i (g theta, g phi, h theta, h phi)");
    c.add_option("--blend", a->blends, "J=IMAGE.png: basis J's blend map (grey)");
    c.add_option("--swap", a->swaps, "J=SPEC: basis J replaced by any BRDF spec or measured file");
    return [a](const CommandIO& io) { return run_edit(*a, io); };
}

CommandRun setup_render_tree(CLI::App& c) {
    auto a = std::make_shared<RenderArgs>();
    c.add_option("TREE", a->tree, "a tree folder")->required();
    c.add_option("-o,--output", a->out, "the PNG to write")->required();
    c.add_option("--backend", a->backend, "exact, cpu, gles1, gles2 or gles2-fused-pixel")
        ->check(CLI::IsMember({"exact", "cpu", "gles1", "gles2", "gles2-fused-pixel"}))->capture_default_str();
    // The scene (figures.h): the wave mesh lit for the shiny bases' highlights; flags override.
    a->setup.mesh_name = "wave";
    a->setup.width = a->setup.height = 256;
    ist_default_scene(&a->setup.scene);
    add_scene_options(c, &a->setup);
    return [a](const CommandIO& io) { return run_render(*a, io); };
}

}  // namespace

CommandRun setup_ist(CLI::App& app) {
    return setup_subcommands(app, {
        {"generate", "a test SVBRDF with known truth: regions blending basis materials", setup_generate},
        {"decompose", "SVBRDF -> blend maps x basis BRDFs -> 1D curves (a tree folder)", setup_decompose},
        {"edit", "edit a tree: replace a curve, a blend map or a basis BRDF", setup_edit},
        {"render",
         "draw a tree: exact, cpu, gles1, gles2 or gles2-fused-pixel (headless); scene defaults here: wave mesh, "
         "256x256, the lights of ist/figures.h (not the defaults listed under Scene)",
         setup_render_tree},
    });
}

}  // namespace sepal
