// runtime/: capabilities and masks, meshes, argument checks, and sepal-view end to end.
#include <doctest/doctest.h>

#include <GLES2/gl2.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "util/image.h"
#include "headless/sepal_headless.h"
#include "sepal/sepal_rt.h"
#include "sepal/sepal_version.h"
#include "test_util.h"
#include "internal.h"

TEST_CASE("version: the library answers the version its headers define") {
    CHECK(sepal_version() == (uint32_t)SEPAL_VERSION);
    CHECK((sepal_version() >> 16) == SEPAL_VERSION_MAJOR);
    CHECK(((sepal_version() >> 8) & 0xFFu) == SEPAL_VERSION_MINOR);
    CHECK((sepal_version() & 0xFFu) == SEPAL_VERSION_PATCH);
    REQUIRE(sepal_version_string() != nullptr);
    CHECK(std::strcmp(sepal_version_string(), SEPAL_VERSION_STRING) == 0);
    char packed[32];
    std::snprintf(packed, sizeof packed, "%u.%u.%u", sepal_version() >> 16, (sepal_version() >> 8) & 0xFFu,
                  sepal_version() & 0xFFu);
    CHECK(std::strcmp(packed, sepal_version_string()) == 0);
}

TEST_CASE("caps: GL_VERSION strings of real drivers give their GL ES major version") {
    struct Case {
        const char* version;
        int major;
    };
    const Case cases[] = {
        {"OpenGL ES-CM 1.1 Mesa 22.3.6", 1},       // the spec's spelling (Mesa)
        {"OpenGL ES-CL 1.0", 1},
        {"OpenGL ES 1.1 NVIDIA 580.159.04", 1},    // NVIDIA drops the profile
        {"OpenGL ES 2.0 (ANGLE 2.1.0 git hash: x)", 2},
        {"OpenGL ES 3.2 NVIDIA 580.159.04", 3},
        {"OpenGL ES 3.2 Mesa 22.3.6", 3},
        {"4.6.0 NVIDIA 580.159.04", 0},            // desktop GL
        {"OpenGL ES", 0},
        {"OpenGL ES-XX 1.1", 0},
        {"OpenGL ES x.1", 0},
        {"", 0},
        {nullptr, 0},
    };
    for (const Case& c : cases) {
        CAPTURE(c.version ? c.version : "(null)");
        CHECK(srt::gles_major_version(c.version) == c.major);
    }
}

TEST_CASE("caps: detected per GL ES version, and every mask bit hides its capability") {
    for (int version : {1, 2}) {
        CAPTURE(version);
        sepal_headless_desc d = {};
        d.gles_version = version;
        char msg[512];
        sepal_headless_context* c = sepal_headless_create(&d, msg, sizeof msg);
        REQUIRE_MESSAGE(c, msg);
        sepal_error err = {};
        sepal_caps caps;
        REQUIRE_MESSAGE(sepal_query_caps(version, 0, sepal_headless_get_proc_address, &caps, &err) == SEPAL_OK, err.message);
        CHECK(caps.gles_version == version);
        CHECK(caps.texture_units >= 2);  // Mesa has at least 2
        CHECK(caps.max_texture_size >= 64);
        // Core in ES 2; an extension on ES 1.1 that Mesa lists and NVIDIA's driver does not
        // (the runtime then draws its no-subtraction paths).
        const char* ext = (const char*)glGetString(GL_EXTENSIONS);
        const bool subtract = version == 2 || (ext && std::strstr(ext, "GL_OES_blend_subtract"));
        CHECK(caps.has_blend_subtract == int(subtract));
        if (sepal_test::reference_renderer()) CHECK(subtract);  // CI's llvmpipe covers the subtract path
        CHECK(bool(caps.blend_equation) == subtract);  // found through the port's loader
        CHECK(caps.has_fbo == 1);
        sepal_caps masked;
        REQUIRE_MESSAGE(sepal_query_caps(version, SEPAL_MASK_BLEND_SUBTRACT | SEPAL_MASK_MULTITEXTURE | SEPAL_MASK_FBO |
                                           SEPAL_MASK_NPOT, sepal_headless_get_proc_address,
                                       &masked, &err) == SEPAL_OK,
                        err.message);
        CHECK(masked.texture_units == 1);
        CHECK(masked.has_blend_subtract == 0);
        CHECK_FALSE(bool(masked.blend_equation));
        CHECK(masked.has_fbo == 0);
        CHECK(masked.has_npot == 0);
        // Asking for the other version's paths is refused with the context named.
        CHECK(sepal_query_caps(3 - version, 0, sepal_headless_get_proc_address, &caps, &err) == SEPAL_ERR_UNSUPPORTED);
        CHECK(std::string(err.message).find("current context") != std::string::npos);
        sepal_headless_destroy(c);
    }
}

TEST_CASE("meshes: sphere normals are unit, tangents orthogonal; capacity is checked") {
    std::vector<sepal_vertex> v(17 * 9);
    std::vector<uint16_t> idx(16 * 8 * 6);
    sepal_mesh mesh = {v.data(), idx.data(), int(v.size()), int(idx.size())};
    sepal_error err = {};
    REQUIRE(sepal_mesh_sphere(16, 8, &mesh, &err) == SEPAL_OK);
    CHECK(mesh.vertex_count == 17 * 9);
    CHECK(mesh.index_count == 16 * 7 * 6);
    for (int i = 0; i < mesh.vertex_count; ++i) {
        const sepal_vertex& p = v[size_t(i)];
        const float nn = p.normal[0] * p.normal[0] + p.normal[1] * p.normal[1] + p.normal[2] * p.normal[2];
        const float nt = p.normal[0] * p.tangent[0] + p.normal[1] * p.tangent[1] + p.normal[2] * p.tangent[2];
        CHECK(nn == doctest::Approx(1.0f).epsilon(1e-5));
        CHECK(std::fabs(nt) < 1e-5f);
    }
    for (int i = 0; i < mesh.index_count; ++i) CHECK(idx[size_t(i)] < mesh.vertex_count);
    sepal_mesh small = {v.data(), idx.data(), 10, 10};
    CHECK(sepal_mesh_sphere(16, 8, &small, &err) == SEPAL_ERR_CAPACITY);
    CHECK(std::string(err.message).find("needs") != std::string::npos);
    CHECK(sepal_mesh_sphere(2, 8, &mesh, &err) == SEPAL_ERR_INVALID_ARGUMENT);
    CHECK(sepal_mesh_grid(0, &mesh, &err) == SEPAL_ERR_INVALID_ARGUMENT);
    sepal_mesh null_mesh = {nullptr, nullptr, 100, 100};
    CHECK(sepal_mesh_grid(2, &null_mesh, &err) == SEPAL_ERR_INVALID_ARGUMENT);
}

TEST_CASE("preview: bad descriptions are refused before any GL call") {
    sepal_caps caps = {};
    caps.gles_version = 1;
    caps.max_texture_size = 1024;
    std::vector<sepal_vertex> v(4);
    std::vector<uint16_t> idx(6);
    sepal_mesh mesh = {v.data(), idx.data(), 4, 6};
    sepal_error err = {};
    REQUIRE(sepal_mesh_grid(1, &mesh, &err) == SEPAL_OK);
    sepal_preview_desc d = {};
    d.mesh = &mesh;
    CHECK(sepal_preview_draw(&caps, &d, &err) == SEPAL_ERR_INVALID_ARGUMENT);  // zero light
    CHECK(std::string(err.message).find("light") != std::string::npos);
    d.light_dir_eye[2] = 1;
    uint8_t px[12 * 4] = {};
    d.texture = px;
    d.texture_width = 3;
    d.texture_height = 4;
    CHECK(sepal_preview_draw(&caps, &d, &err) == SEPAL_ERR_INVALID_ARGUMENT);  // not a power of 2
    CHECK(std::string(err.message).find("powers of two") != std::string::npos);
    CHECK(sepal_preview_draw(nullptr, &d, &err) == SEPAL_ERR_INVALID_ARGUMENT);
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
