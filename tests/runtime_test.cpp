// runtime/: capabilities and masks, meshes, argument checks, and sepal-view end to end.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "image.h"
#include "sepal_headless.h"
#include "sepal_rt.h"
#include "test_util.h"

TEST_CASE("caps: detected per GL ES version, and every mask bit hides its capability") {
    for (int version : {1, 2}) {
        CAPTURE(version);
        sh_desc d = {};
        d.gles_version = version;
        char msg[512];
        sh_context* c = sh_create(&d, msg, sizeof msg);
        REQUIRE_MESSAGE(c, msg);
        srt_error err = {};
        srt_caps caps;
        REQUIRE_MESSAGE(srt_query_caps(version, 0, sh_get_proc_address, &caps, &err) == SRT_OK, err.message);
        CHECK(caps.gles_version == version);
        CHECK(caps.texture_units >= 2);  // Mesa has at least 2
        CHECK(caps.max_texture_size >= 64);
        CHECK(caps.has_blend_subtract == 1);  // Mesa has GL_OES_blend_subtract / ES 2 core
        CHECK(bool(caps.blend_equation));  // found through the port's loader
        CHECK(caps.has_fbo == 1);
        srt_caps masked;
        REQUIRE(srt_query_caps(version, SRT_MASK_BLEND_SUBTRACT | SRT_MASK_MULTITEXTURE | SRT_MASK_FBO |
                                   SRT_MASK_NPOT, sh_get_proc_address,
                               &masked, &err) == SRT_OK);
        CHECK(masked.texture_units == 1);
        CHECK(masked.has_blend_subtract == 0);
        CHECK_FALSE(bool(masked.blend_equation));
        CHECK(masked.has_fbo == 0);
        CHECK(masked.has_npot == 0);
        // Asking for the other version's paths is refused with the context named.
        CHECK(srt_query_caps(3 - version, 0, sh_get_proc_address, &caps, &err) == SRT_ERR_UNSUPPORTED);
        CHECK(std::string(err.message).find("current context") != std::string::npos);
        sh_destroy(c);
    }
}

TEST_CASE("meshes: sphere normals are unit, tangents orthogonal; capacity is checked") {
    std::vector<srt_vertex> v(17 * 9);
    std::vector<uint16_t> idx(16 * 8 * 6);
    srt_mesh mesh = {v.data(), idx.data(), int(v.size()), int(idx.size())};
    srt_error err = {};
    REQUIRE(srt_mesh_sphere(16, 8, &mesh, &err) == SRT_OK);
    CHECK(mesh.vertex_count == 17 * 9);
    CHECK(mesh.index_count == 16 * 7 * 6);
    for (int i = 0; i < mesh.vertex_count; ++i) {
        const srt_vertex& p = v[size_t(i)];
        const float nn = p.normal[0] * p.normal[0] + p.normal[1] * p.normal[1] + p.normal[2] * p.normal[2];
        const float nt = p.normal[0] * p.tangent[0] + p.normal[1] * p.tangent[1] + p.normal[2] * p.tangent[2];
        CHECK(nn == doctest::Approx(1.0f).epsilon(1e-5));
        CHECK(std::fabs(nt) < 1e-5f);
    }
    for (int i = 0; i < mesh.index_count; ++i) CHECK(idx[size_t(i)] < mesh.vertex_count);
    srt_mesh small = {v.data(), idx.data(), 10, 10};
    CHECK(srt_mesh_sphere(16, 8, &small, &err) == SRT_ERR_CAPACITY);
    CHECK(std::string(err.message).find("needs") != std::string::npos);
    CHECK(srt_mesh_sphere(2, 8, &mesh, &err) == SRT_ERR_INVALID_ARGUMENT);
    CHECK(srt_mesh_grid(0, &mesh, &err) == SRT_ERR_INVALID_ARGUMENT);
    srt_mesh null_mesh = {nullptr, nullptr, 100, 100};
    CHECK(srt_mesh_grid(2, &null_mesh, &err) == SRT_ERR_INVALID_ARGUMENT);
}

TEST_CASE("preview: bad descriptions are refused before any GL call") {
    srt_caps caps = {};
    caps.gles_version = 1;
    caps.max_texture_size = 1024;
    std::vector<srt_vertex> v(4);
    std::vector<uint16_t> idx(6);
    srt_mesh mesh = {v.data(), idx.data(), 4, 6};
    srt_error err = {};
    REQUIRE(srt_mesh_grid(1, &mesh, &err) == SRT_OK);
    srt_preview_desc d = {};
    d.mesh = &mesh;
    CHECK(srt_preview_draw(&caps, &d, &err) == SRT_ERR_INVALID_ARGUMENT);  // zero light
    CHECK(std::string(err.message).find("light") != std::string::npos);
    d.light_dir_eye[2] = 1;
    uint8_t px[12 * 4] = {};
    d.texture = px;
    d.texture_width = 3;
    d.texture_height = 4;
    CHECK(srt_preview_draw(&caps, &d, &err) == SRT_ERR_INVALID_ARGUMENT);  // not a power of 2
    CHECK(std::string(err.message).find("powers of two") != std::string::npos);
    CHECK(srt_preview_draw(nullptr, &d, &err) == SRT_ERR_INVALID_ARGUMENT);
}

TEST_CASE("sepal-view renders a PNG headless on GL ES 1.1 and 2, and explains bad usage") {
    const std::string dir = sepal_test::temp_dir();
    const std::string view = sepal_test::bin("sepal-view");
    for (int version : {1, 2}) {
        const std::string out = dir + "/view" + std::to_string(version) + ".png";
        std::string text;
        REQUIRE(sepal_test::run(view + " --headless --gles " + std::to_string(version) +
                                    " --size 64x48 -o " + out,
                                &text) == 0);
        CHECK(text.find(out) != std::string::npos);
        sepal::Image img;
        REQUIRE(sepal::read_image(out, &img, nullptr));
        CHECK(img.width == 64);
        CHECK(img.height == 48);
        CHECK(img.at(32, 24, 0) > img.at(1, 1, 0));  // the sphere is brighter than the background
    }
    std::string text;
    CHECK(sepal_test::run(view + " -o " + dir + "/x.png", &text) == 2);
    CHECK(text.find("--headless") != std::string::npos);
    CHECK(sepal_test::run(view + " --headless --gles 7 -o " + dir + "/x.png") == 2);
    CHECK(sepal_test::run(view + " --headless --bogus") == 2);
}
