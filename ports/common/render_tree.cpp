#include "common/render_tree.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include <GLES/gl.h>

#include "headless/sepal_headless.h"
#include "sepal/sepal_tree.h"

namespace sepal_ports {

namespace {
double ms_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

bool render_tree_headless(const void* bytes, size_t size, const SceneSetup& setup, const GlRenderOptions& options,
                          std::vector<uint8_t>* rgba, GlRenderInfo* info, std::string* err) {
    // The runtime's structs are large (a material per basis): on the heap, in port code.
    auto asset = std::make_unique<sepal_tree_asset>();
    auto tree = std::make_unique<sepal_tree>();
    sepal_error e = {};
    if (sepal_tree_parse(bytes, size, asset.get(), &e) != SEPAL_OK) {
        *err = e.message;
        return false;
    }
    sepal_headless_desc hd = {};
    hd.width = setup.width;
    hd.height = setup.height;
    hd.gles_version = options.gles_version;
    char msg[512];
    sepal_headless_context* ctx = sepal_headless_create(&hd, msg, sizeof msg);
    if (!ctx) {
        *err = msg;
        return false;
    }
    sepal_caps caps;
    bool ok = sepal_query_caps(options.gles_version, options.mask, sepal_headless_get_proc_address, &caps, &e) == SEPAL_OK &&
              sepal_tree_create(&caps, asset.get(), setup.width, setup.height, tree.get(), &e) == SEPAL_OK;
    if (ok) {
        std::vector<float> scratch(sepal_draw_scratch_floats(setup.mesh.vertex_count, setup.scene.light_count));
        sepal_tree_draw_desc d = {};
        d.tree = tree.get();
        d.mesh = &setup.mesh;
        d.scene = &setup.scene;
        d.width = setup.width;
        d.height = setup.height;
        d.scratch = scratch.data();
        d.scratch_floats = scratch.size();
        d.mode = options.mode;
        const int warm = options.frames > 1 ? 2 : 0, frames = warm + std::max(1, options.frames);
        std::vector<double> times;
        for (int i = 0; ok && i < frames; ++i) {
            const auto start = std::chrono::steady_clock::now();
            ok = sepal_tree_draw(&d, &info->stats, &e) == SEPAL_OK;
            glFinish();
            if (i >= warm) times.push_back(ms_since(start));
        }
        std::sort(times.begin(), times.end());
        info->ms = times.empty() ? 0.0 : times[times.size() / 2];
        rgba->resize(size_t(setup.width) * setup.height * 4);
        if (ok && !sepal_headless_read_rgba(ctx, rgba->data())) {
            ok = false;
            std::snprintf(e.message, sizeof e.message, "reading the framebuffer back failed");
        }
        info->device = sepal_headless_describe(ctx);
        info->path = std::string(options.gles_version == 2 ? "GL ES 2 " : "GL ES 1.1 ") +
                     (options.mode == SEPAL_MODE_FUSED_PIXEL ? "fused tree shader" : "bases composed") + ", " +
                     std::to_string(tree->basis_count) + " bases";
        sepal_tree_destroy(tree.get());
    }
    sepal_headless_destroy(ctx);
    if (!ok) *err = e.message;
    return ok;
}

bool render_tree_cpu(const void* bytes, size_t size, const SceneSetup& setup, std::vector<float>* rgb, double* ms,
                     std::string* err, sepal_draw_stats* stats) {
    auto asset = std::make_unique<sepal_tree_asset>();
    sepal_error e = {};
    if (sepal_tree_parse(bytes, size, asset.get(), &e) != SEPAL_OK) {
        *err = e.message;
        return false;
    }
    const size_t pixels = size_t(setup.width) * setup.height;
    rgb->assign(pixels * 3, 0.0f);
    std::vector<float> accum(pixels * 3), depth(pixels), scratch(sepal_cpu_scratch_floats(setup.mesh.vertex_count));
    std::vector<uint8_t> blend(size_t(asset->header.blend_width) * asset->header.blend_height * 4);
    sepal_tree_cpu_desc d = {};
    d.asset = asset.get();
    d.mesh = &setup.mesh;
    d.scene = &setup.scene;
    d.width = setup.width;
    d.height = setup.height;
    d.color = rgb->data();
    d.accum = accum.data();
    d.depth = depth.data();
    d.blend_rgba = blend.data();
    d.scratch = scratch.data();
    d.scratch_floats = scratch.size();
    d.stats = stats;
    const auto start = std::chrono::steady_clock::now();
    const bool ok = sepal_tree_draw_cpu(&d, &e) == SEPAL_OK;
    if (ms) *ms = ms_since(start);
    if (!ok) *err = e.message;
    return ok;
}

}  // namespace sepal_ports
