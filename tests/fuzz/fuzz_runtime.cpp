// The runtime's loader past the parser: an asset sepal_asset_parse accepts (checksums fixed
// up, fuzz.h) is planned for GL ES 1.1 (two units and the one-unit path, with and without
// blend subtract) and GL ES 2 (srt::material_plan: everything sepal_material_create does
// but the GL calls), drawn by the CPU backend and by the GL ES 1.1 / ES 2 emulator on a
// small sphere. One validity definition: what the reader accepts, every
// backend draws, and the CPU backend's radiance is finite and >= 0.
#include <cmath>
#include <cstring>
#include <vector>

#include "draw_internal.h"
#include "fuzz/fuzz.h"
#include "sepal/sepal_material.h"
#include "sepal/internal/sepal_emulate.h"

namespace {

constexpr int kSide = 12;

struct Scene {
    std::vector<sepal_vertex> vertices;
    std::vector<uint16_t> indices;
    sepal_mesh mesh = {};
    sepal_scene scene = {};
    Scene() : vertices(64), indices(512) {
        mesh = {vertices.data(), indices.data(), int(vertices.size()), int(indices.size())};
        sepal_error err = {};
        sepal_fuzz::check(sepal_mesh_sphere(6, 4, &mesh, &err) == SEPAL_OK, "runtime", err.message);
        sepal_scene_default(&scene);
    }
};

}  // namespace

extern "C" int sepal_fuzz_runtime(const uint8_t* data, size_t size) {
    const char* h = "runtime";
    std::vector<uint8_t> bytes(data, data + size);
    sepal_fuzz::fix_asset_checksums(&bytes);
    static sepal_asset asset;
    static sepal_material material;
    sepal_error err = {};
    if (sepal_asset_parse(bytes.data(), bytes.size(), &asset, &err) != SEPAL_OK) return 0;
    struct Caps {
        int version, units, subtract;
    };
    for (const Caps c : {Caps{1, 2, 1}, Caps{1, 1, 0}, Caps{2, 8, 1}}) {
        sepal_caps caps = {};
        caps.gles_version = c.version;
        caps.texture_units = c.units;
        caps.max_texture_size = 2048;
        caps.has_blend_subtract = c.subtract;
        caps.has_fbo = 1;
        const sepal_result r = srt::material_plan(&caps, &asset, kSide, kSide, srt::material(&material), &err);
        // GL ES 1.1 draws only the per-vertex parameterizations; anything else the reader
        // accepted, every GL backend must take.
        const bool per_vertex = srt::param_per_vertex(sepal_param(asset.material.param));
        if (c.version == 2 || per_vertex) sepal_fuzz::check(r == SEPAL_OK, h, err.message);
        else sepal_fuzz::check(r == SEPAL_ERR_UNSUPPORTED && err.message[0], h, "per-pixel asset on GL ES 1.1 not refused");
    }
    static Scene s;
    static std::vector<float> color(kSide * kSide * 3), depth(kSide * kSide),
        scratch(sepal_cpu_scratch_floats(s.mesh.vertex_count));
    sepal_draw_stats stats = {};
    sepal_cpu_desc d = {};
    d.asset = &asset;
    d.mesh = &s.mesh;
    d.scene = &s.scene;
    d.width = d.height = kSide;
    d.color = color.data();
    d.depth = depth.data();
    d.scratch = scratch.data();
    d.scratch_floats = scratch.size();
    d.stats = &stats;
    sepal_fuzz::check(sepal_draw_cpu(&d, &err) == SEPAL_OK, h, err.message);
    for (float v : color) sepal_fuzz::check(std::isfinite(v) && v >= 0.0f, h, "CPU radiance not finite or negative");
    sepal_fuzz::check(stats.nonfinite_clamped == 0, h, "the CPU backend clamped a non-finite radiance");
    static std::vector<uint8_t> rgba(kSide * kSide * 4);
    static std::vector<float> escratch(sepal_emulate_scratch_floats(kSide, kSide, s.mesh.vertex_count, 1));
    for (int version : {1, 2}) {
        // GL ES 1.1 and GL ES 2's multipass need per-vertex coordinates.
        if (!srt::param_per_vertex(sepal_param(asset.material.param))) continue;
        sepal_emulate_desc e = {};
        e.asset = &asset;
        e.mesh = &s.mesh;
        e.scene = &s.scene;
        e.width = e.height = kSide;
        e.gles_version = version;
        e.rgba = rgba.data();
        e.scratch = escratch.data();
        e.scratch_floats = escratch.size();
        sepal_fuzz::check(sepal_emulate_draw(&e, &err) == SEPAL_OK, h, err.message);
    }
    return 0;
}
