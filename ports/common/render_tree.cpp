#include "common/render_tree.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

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
    sepal_error pe = {};
    if (sepal_tree_parse(bytes, size, asset.get(), &pe) != SEPAL_OK) {
        *err = pe.message;
        return false;
    }
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
    HeadlessJob job;
    job.create = [&](sepal_caps* caps, sepal_error* e) {
        return sepal_tree_create(caps, asset.get(), setup.width, setup.height, tree.get(), e) == SEPAL_OK;
    };
    job.draw = [&](sepal_draw_stats* stats, sepal_error* e) { return sepal_tree_draw(&d, stats, e) == SEPAL_OK; };
    job.finish = [&](sepal_error*) {
        info->path = std::string(options.gles_version == 2 ? "GL ES 2 " : "GL ES 1.1 ") +
                     (options.mode == SEPAL_MODE_FUSED_PIXEL ? "fused tree shader" : "bases composed") + ", " +
                     std::to_string(tree->basis_count) + " bases";
        return true;
    };
    job.destroy = [&] { sepal_tree_destroy(tree.get()); };
    return run_headless(setup, options, job, rgba, info, err);
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
