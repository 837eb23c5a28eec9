// ports/headless and the first chain test: runtime -> GL ES (1.1 and 2.0) -> pixels ->
// golden image.
#include <doctest/doctest.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include <GLES2/gl2.h>

#include "gl_scene.h"
#include "headless/sepal_headless.h"
#include "test_util.h"

namespace {
// llvmpipe renders these bit-exactly run to run; the tolerance leaves room for other
// Mesa versions' rasterization and rounding differences (a few levels on edge pixels).
sepal::Tolerance quad_tolerance() {
    sepal::Tolerance t;
    t.max_diff = 3;      // 8-bit levels per channel
    t.max_share = 0.01;  // 1% of pixels may exceed it (triangle edges, texel centres)
    t.min_psnr = 40;
    return t;
}
}  // namespace

TEST_CASE("headless: GL ES 1.1 and 2.0 contexts clear and read back") {
    for (int version : {1, 2}) {
        CAPTURE(version);
        sepal_headless_desc d = {};
        d.width = 7;  // odd sizes catch row-flip and alignment mistakes
        d.height = 5;
        d.gles_version = version;
        char err[512];
        sepal_headless_context* c = sepal_headless_create(&d, err, sizeof err);
        REQUIRE_MESSAGE(c, err);
        CHECK(std::strstr(sepal_headless_describe(c), version == 1 ? "ES-CM 1.1" : "OpenGL ES") != nullptr);
        glClearColor(1.0f, 0.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        glEnable(GL_SCISSOR_TEST);  // top row (GL's y = 4) green
        glScissor(0, 4, 7, 1);
        glClearColor(0.0f, 1.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        glDisable(GL_SCISSOR_TEST);
        std::vector<uint8_t> px(7 * 5 * 4);
        REQUIRE(sepal_headless_read_rgba(c, px.data()));
        CHECK(px[1] == 255);               // first row read back is the top: green
        CHECK(px[(4 * 7) * 4 + 0] == 255);  // last row: red
        sepal_headless_destroy(c);
    }
}

TEST_CASE("headless: clear errors for bad requests") {
    char err[512];
    sepal_headless_desc d = {};
    d.gles_version = 3;
    CHECK(sepal_headless_create(&d, err, sizeof err) == nullptr);
    CHECK(std::strstr(err, "gles_version 3") != nullptr);
    d = sepal_headless_desc{};
    d.width = -4;
    CHECK(sepal_headless_create(&d, err, sizeof err) == nullptr);
    CHECK(std::strstr(err, "out of range") != nullptr);
    d = sepal_headless_desc{};
    setenv("SEPAL_EGL_PLATFORM", "wayland-please", 1);
    CHECK(sepal_headless_create(&d, err, sizeof err) == nullptr);
    CHECK(std::strstr(err, "SEPAL_EGL_PLATFORM") != nullptr);
    unsetenv("SEPAL_EGL_PLATFORM");
    d.depth_bits = 64;  // no config has that many
    CHECK(sepal_headless_create(&d, err, sizeof err) == nullptr);
    CHECK(std::strstr(err, "64 depth bits") != nullptr);
}

TEST_CASE("golden: lit textured quad on GL ES 1.1") {
    sepal::Image img;
    std::string err;
    REQUIRE_MESSAGE(sepal_test::render_lit_quad(1, 160, 120, &img, &err), err);
    sepal::write_png(sepal_test::output_dir() + "/lit_quad_gles1.png", img, nullptr);
    const std::string msg = sepal_test::check_golden("lit_quad", img, quad_tolerance());
    CHECK_MESSAGE(msg.empty(), msg);
}

TEST_CASE("golden: lit textured quad on GL ES 2.0 matches the same golden") {
    sepal::Image img;
    std::string err;
    REQUIRE_MESSAGE(sepal_test::render_lit_quad(2, 160, 120, &img, &err), err);
    sepal::write_png(sepal_test::output_dir() + "/lit_quad_gles2.png", img, nullptr);
    const std::string msg =
        sepal_test::check_golden("lit_quad", img, quad_tolerance(), /*owner=*/false);
    CHECK_MESSAGE(msg.empty(), msg);
}

TEST_CASE("the chain test can fail: a changed scene is caught") {
    sepal::Image img;
    std::string err;
    REQUIRE_MESSAGE(sepal_test::render_lit_quad(1, 160, 120, &img, &err), err);
    sepal::Image expected;
    REQUIRE(sepal::read_image(sepal_test::source_path("fixtures/golden/lit_quad.png"), &expected,
                              &err));
    // Darken a 20x20 block by 8 levels: 2% of the pixels, beyond quad_tolerance.
    for (int y = 50; y < 70; ++y)
        for (int x = 70; x < 90; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = std::max(0.0f, img.at(x, y, c) - 8.0f / 255.0f);
    std::string why;
    const sepal::Tolerance t = quad_tolerance();
    CHECK_FALSE(sepal::tolerance_holds(sepal::diff_images(expected, img, t.max_diff), t, &why));
}
