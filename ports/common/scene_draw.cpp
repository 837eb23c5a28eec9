#include "common/scene_draw.h"

namespace sepal_ports {

sepal_draw_desc scene_draw_desc(const sepal_material* material, const SceneSetup& setup, sepal_draw_mode mode,
                                std::vector<float>* scratch) {
    scratch->resize(sepal_draw_scratch_floats(setup.mesh.vertex_count, setup.scene.light_count));
    sepal_draw_desc d = {};
    d.material = material;
    d.mesh = &setup.mesh;
    d.scene = &setup.scene;
    d.width = setup.width;
    d.height = setup.height;
    d.scratch = scratch->data();
    d.scratch_floats = scratch->size();
    d.mode = mode;
    return d;
}

sepal_cpu_desc scene_cpu_desc(const sepal_asset* asset, const SceneSetup& setup, CpuFrame* frame,
                              sepal_draw_stats* stats) {
    const size_t pixels = size_t(setup.width) * size_t(setup.height);
    frame->rgb.assign(pixels * 3, 0.0f);
    frame->depth.resize(pixels);
    frame->scratch.resize(sepal_cpu_scratch_floats(setup.mesh.vertex_count));
    sepal_cpu_desc d = {};
    d.asset = asset;
    d.mesh = &setup.mesh;
    d.scene = &setup.scene;
    d.width = setup.width;
    d.height = setup.height;
    d.color = frame->rgb.data();
    d.depth = frame->depth.data();
    d.scratch = frame->scratch.data();
    d.scratch_floats = frame->scratch.size();
    d.stats = stats;
    return d;
}

sepal_emulate_desc scene_emulate_desc(const sepal_asset* asset, const SceneSetup& setup, int gles_version,
                                      uint32_t mask, EmulatedFrame* frame, sepal_draw_stats* stats) {
    frame->rgba.assign(size_t(setup.width) * setup.height * 4, 0);
    frame->scratch.resize(
        sepal_emulate_scratch_floats(setup.width, setup.height, setup.mesh.vertex_count, setup.scene.light_count));
    sepal_emulate_desc d = {};
    d.asset = asset;
    d.mesh = &setup.mesh;
    d.scene = &setup.scene;
    d.width = setup.width;
    d.height = setup.height;
    d.gles_version = gles_version;
    d.mask = mask;
    d.rgba = frame->rgba.data();
    d.scratch = frame->scratch.data();
    d.scratch_floats = frame->scratch.size();
    d.stats = stats;
    return d;
}

}  // namespace sepal_ports
