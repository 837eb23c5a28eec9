// The C API's argument checks: out-of-range sizes answered before any pixel is written, assets
// that sepal_asset_parse never filled, a material with no current context, unknown enums,
// negative counts. Each returns an error (or its documented value), never crashes or draws.
#include <doctest/doctest.h>

#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "headless/sepal_headless.h"
#include "material_fixtures.h"
#include "material_state.h"
#include "sepal/sepal.h"
#include "sepal/internal/sepal_emulate.h"

using namespace material_fx;

namespace {

// A parsed asset and the bytes it points into.
struct Parsed {
    std::vector<uint8_t> bytes;
    std::unique_ptr<sepal_asset> asset = std::make_unique<sepal_asset>();
    Parsed() {
        bytes = encode(signed_asset());
        sepal_error e = {};
        REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), asset.get(), &e) == SEPAL_OK);
    }
};

}  // namespace

TEST_CASE("api: sepal_draw_cpu checks its size limit before writing a pixel") {
    Parsed p;
    sepal_ports::SceneSetup s = test_scene("sphere", 1);
    std::vector<float> color(3, 7.0f), depth(1), scratch(sepal_cpu_scratch_floats(s.mesh.vertex_count));
    sepal_cpu_desc d = {};
    d.asset = p.asset.get();
    d.mesh = &s.mesh;
    d.scene = &s.scene;
    d.color = color.data();
    d.depth = depth.data();
    d.scratch = scratch.data();
    d.scratch_floats = scratch.size();
    sepal_error e = {};
    for (int side : {46341, 8193, 0, -5}) {
        d.width = d.height = side;
        CHECK(sepal_draw_cpu(&d, &e) == SEPAL_ERR_INVALID_ARGUMENT);
        CHECK(std::string(e.message).find("out of range 1..8192") != std::string::npos);
        CHECK(color[0] == 7.0f);  // nothing written
    }
    // A zeroed asset that sepal_asset_parse never filled draws nothing and says so.
    sepal_asset zeroed;
    std::memset(&zeroed, 0, sizeof zeroed);
    d.asset = &zeroed;
    d.width = d.height = 1;
    CHECK(sepal_draw_cpu(&d, &e) == SEPAL_ERR_INVALID_ARGUMENT);
    CHECK(std::string(e.message).find("not filled by sepal_asset_parse") != std::string::npos);
    CHECK(color[0] == 7.0f);
}

TEST_CASE("api: sepal_material_create refuses a never-parsed asset, a float target without one, a missing context") {
    Parsed p;
    sepal_headless_desc hd = {};
    char msg[256];
    sepal_headless_context* ctx = sepal_headless_create(&hd, msg, sizeof msg);
    if (!ctx) {
        MESSAGE("no headless GL context here: " << msg);
        return;
    }
    sepal_caps caps;
    sepal_error e = {};
    REQUIRE(sepal_query_caps(1, 0, sepal_headless_get_proc_address, &caps, &e) == SEPAL_OK);
    auto mat = std::make_unique<sepal_material>();
    sepal_asset zeroed;
    std::memset(&zeroed, 0, sizeof zeroed);
    CHECK(sepal_material_create(&caps, &zeroed, 64, 64, mat.get(), &e) == SEPAL_ERR_INVALID_ARGUMENT);
    CHECK(std::string(e.message).find("not filled by sepal_asset_parse") != std::string::npos);
    // A half-float target is asked for, not a field of the caps: GL ES 1.1 has none.
    CHECK(sepal_material_create_float_target(&caps, p.asset.get(), 64, 64, mat.get(), &e) == SEPAL_ERR_UNSUPPORTED);
    CHECK(std::string(e.message).find("no half-float render target") != std::string::npos);
    REQUIRE(sepal_material_create(&caps, p.asset.get(), 64, 64, mat.get(), &e) == SEPAL_OK);
    sepal_material_info mi;
    sepal_material_get_info(mat.get(), &mi);
    CHECK(mi.created == 1);
    CHECK(mi.float_target == 0);
    CHECK(mi.gles_version == 1);
    CHECK(mi.max_width == 64);
    sepal_material_destroy(mat.get());
    sepal_headless_destroy(ctx);  // no context is current now
    CHECK(sepal_material_create(&caps, p.asset.get(), 64, 64, mat.get(), &e) == SEPAL_ERR_INVALID_ARGUMENT);
    CHECK(std::string(e.message).find("no current GL context") != std::string::npos);
}

TEST_CASE("api: unknown maps and parameterizations, negative counts") {
    const float wi[3] = {0, 0, 1}, wo[3] = {0.6f, 0, 0.8f};
    float g[2] = {5, 5}, h[2] = {5, 5};
    CHECK(sepal_param_texcoords(SEPAL_PARAM_GS_HALF, sepal_hemi_map(99), wi, wo, g, h) == -1);
    CHECK(sepal_param_texcoords(sepal_param(99), SEPAL_MAP_XY, wi, wo, g, h) == -1);
    CHECK(sepal_param_texcoords_pixel(SEPAL_PARAM_GS_HALF, sepal_hemi_map(99), wi, wo, g, h) == -1);
    CHECK(g[0] == 5.0f);  // nothing written
    CHECK(sepal_param_texcoords(SEPAL_PARAM_GS_HALF, SEPAL_MAP_XY, wi, wo, g, h) == 1);
    CHECK(sepal_draw_scratch_floats(-1, -1) == 0);
    CHECK(sepal_draw_scratch_floats(100, 0) == 0);
    CHECK(sepal_draw_scratch_floats(100, 1) > 0);
    CHECK(sepal_cpu_scratch_floats(-1) == 0);
    CHECK(sepal_emulate_scratch_floats(-1, -1, -1, -1) == 0);
}

TEST_CASE("api: sepal_material is opaque storage of a fixed size, with room for the runtime's state to grow") {
    CHECK(sizeof(sepal_material) == SEPAL_MATERIAL_BYTES);
    CHECK(sizeof(srt::Material) <= sizeof(sepal_material));
    // The room left: what the state may grow by before the ABI's size must change.
    CHECK(sizeof(sepal_material) - sizeof(srt::Material) >= 4096);
    MESSAGE("sepal_material: " << sizeof(sepal_material) << " bytes, the runtime's state " << sizeof(srt::Material));
    sepal_material never_created = {};
    sepal_material_info mi;
    sepal_material_get_info(&never_created, &mi);
    CHECK(mi.created == 0);
    sepal_material_get_info(nullptr, &mi);
    CHECK(mi.created == 0);
}
