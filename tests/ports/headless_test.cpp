// ports/headless and the first chain test: runtime -> GL ES (1.1 and 2.0) -> pixels ->
// golden image.
#include <doctest/doctest.h>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include <GLES/gl.h>
#include <GLES2/gl2.h>

#include "common/scene_draw.h"
#include "gl_scene.h"
#include "headless/sepal_headless.h"
#include "material_fixtures.h"
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

// A horizontal ramp of vertex colours, 0 at the left edge to 1 at the right, over the
// viewport (GL ES 1.1, identity matrices).
void draw_color_ramp_gles1() {
    static const float kPos[] = {-1, -1, 1, -1, -1, 1, 1, 1};
    static const float kColor[] = {0, 0, 0, 1, 1, 1, 1, 1, 0, 0, 0, 1, 1, 1, 1, 1};
    glClear(GL_COLOR_BUFFER_BIT);
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_COLOR_ARRAY);
    glVertexPointer(2, GL_FLOAT, 0, kPos);
    glColorPointer(4, GL_FLOAT, 0, kColor);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glDisableClientState(GL_VERTEX_ARRAY);
    glDisableClientState(GL_COLOR_ARRAY);
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
        // "OpenGL ES-CM 1.1" on Mesa, "OpenGL ES 1.1" on NVIDIA.
        CHECK(std::strstr(sepal_headless_describe(c), version == 1 ? " 1.1 " : "OpenGL ES") != nullptr);
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

TEST_CASE("headless: context loss: the material forgets its GL objects and is restored from the loaded asset") {
    // A fault a phone has: EGL_CONTEXT_LOST. The context is destroyed and a new one
    // created; the same parsed asset is uploaded again and draws the same pixels.
    const sepal::AssetData a = material_fx::signed_asset();  // every kind of pass, subtractions included
    std::vector<uint8_t> bytes;
    std::string msg;
    REQUIRE_MESSAGE(sepal::encode_asset(a, &bytes, &msg), msg);
    auto asset = std::make_unique<sepal_asset>();
    auto material = std::make_unique<sepal_material>();
    sepal_error e = {};
    REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), asset.get(), &e) == SEPAL_OK);
    const sepal_ports::SceneSetup setup = material_fx::test_scene("sphere", 2);
    struct Case {
        int gles;
        uint32_t mask;
        sepal_draw_mode mode;
    };
    for (const Case c : {Case{1, 0, SEPAL_MODE_MULTIPASS}, Case{1, SEPAL_MASK_MULTITEXTURE | SEPAL_MASK_BLEND_SUBTRACT,
                                                                 SEPAL_MODE_MULTIPASS},
                         Case{2, 0, SEPAL_MODE_MULTIPASS}, Case{2, 0, SEPAL_MODE_FUSED_PIXEL}}) {
        CAPTURE(c.gles);
        CAPTURE(c.mask);
        CAPTURE(int(c.mode));
        sepal_headless_desc hd = {};
        hd.width = setup.width;
        hd.height = setup.height;
        hd.gles_version = c.gles;
        char err[512];
        auto frame = [&](sepal_headless_context* ctx, std::vector<uint8_t>* rgba) {
            std::vector<float> scratch;
            sepal_draw_desc d = sepal_ports::scene_draw_desc(material.get(), setup, c.mode, &scratch);
            REQUIRE_MESSAGE(sepal_draw(&d, nullptr, &e) == SEPAL_OK, e.message);
            rgba->resize(size_t(setup.width) * setup.height * 4);
            REQUIRE(sepal_headless_read_rgba(ctx, rgba->data()));
        };
        sepal_headless_context* ctx = sepal_headless_create(&hd, err, sizeof err);
        REQUIRE_MESSAGE(ctx, err);
        sepal_caps caps;
        REQUIRE(sepal_query_caps(c.gles, c.mask, sepal_headless_get_proc_address, &caps, &e) == SEPAL_OK);
        REQUIRE_MESSAGE(sepal_material_create(&caps, asset.get(), setup.width, setup.height, material.get(), &e) ==
                            SEPAL_OK,
                        e.message);
        std::vector<uint8_t> before, after;
        frame(ctx, &before);
        // Restoring a live material would leak its objects: refused.
        CHECK(sepal_material_restore(material.get(), &caps, asset.get(), &e) == SEPAL_ERR_INVALID_ARGUMENT);
        CHECK(std::strstr(e.message, "was not lost") != nullptr);
        // The context goes away under the material.
        sepal_material_context_lost(material.get());
        sepal_headless_destroy(ctx);
        std::vector<float> scratch;
        sepal_draw_desc lost = sepal_ports::scene_draw_desc(material.get(), setup, c.mode, &scratch);
        CHECK(sepal_draw(&lost, nullptr, &e) == SEPAL_ERR_INVALID_ARGUMENT);
        CHECK(std::strstr(e.message, "context was lost") != nullptr);
        // A new context, its caps, the same asset.
        ctx = sepal_headless_create(&hd, err, sizeof err);
        REQUIRE_MESSAGE(ctx, err);
        REQUIRE(sepal_query_caps(c.gles, c.mask, sepal_headless_get_proc_address, &caps, &e) == SEPAL_OK);
        auto other = std::make_unique<sepal_asset>();
        *other = *asset;
        other->passes[0].color[0] *= 0.5f;
        CHECK(sepal_material_restore(material.get(), &caps, other.get(), &e) == SEPAL_ERR_INVALID_ARGUMENT);
        CHECK(std::strstr(e.message, "not the one the material was created from") != nullptr);
        REQUIRE_MESSAGE(sepal_material_restore(material.get(), &caps, asset.get(), &e) == SEPAL_OK, e.message);
        sepal_material_info mi;
        sepal_material_get_info(material.get(), &mi);
        CHECK(mi.context_lost == 0);
        CHECK(mi.created == 1);
        frame(ctx, &after);
        CHECK(before == after);
        sepal_material_destroy(material.get());
        sepal_headless_destroy(ctx);
    }
    // A lost material can also just be destroyed: no GL call, no context needed.
    sepal_headless_desc hd = {};
    char err[512];
    sepal_headless_context* ctx = sepal_headless_create(&hd, err, sizeof err);
    REQUIRE_MESSAGE(ctx, err);
    sepal_caps caps;
    REQUIRE(sepal_query_caps(1, 0, sepal_headless_get_proc_address, &caps, &e) == SEPAL_OK);
    REQUIRE(sepal_material_create(&caps, asset.get(), 64, 64, material.get(), &e) == SEPAL_OK);
    sepal_material_context_lost(material.get());
    sepal_headless_destroy(ctx);
    sepal_material_destroy(material.get());
    sepal_material_info mi;
    sepal_material_get_info(material.get(), &mi);
    CHECK(mi.created == 0);
}

TEST_CASE("headless: an RGB565 pbuffer, and the caps read its 5/6/5 bits and GL_DITHER") {
    for (int version : {1, 2})
        for (int framebuffer : {565, 8888, 0}) {
            CAPTURE(version);
            CAPTURE(framebuffer);
            sepal_headless_desc d = {};
            d.width = 8;
            d.height = 4;
            d.gles_version = version;
            d.framebuffer = framebuffer;
            char err[512];
            sepal_headless_context* c = sepal_headless_create(&d, err, sizeof err);
            REQUIRE_MESSAGE(c, err);
            sepal_caps caps;
            sepal_error e = {};
            REQUIRE_MESSAGE(sepal_query_caps(version, 0, sepal_headless_get_proc_address, &caps, &e) == SEPAL_OK,
                            e.message);
            const bool rgb565 = framebuffer == 565;
            CHECK(caps.red_bits == (rgb565 ? 5 : 8));
            CHECK(caps.green_bits == (rgb565 ? 6 : 8));
            CHECK(caps.blue_bits == (rgb565 ? 5 : 8));
            CHECK(caps.dither == 1);  // GL ES starts with GL_DITHER on
            glDisable(GL_DITHER);
            REQUIRE(sepal_query_caps(version, 0, sepal_headless_get_proc_address, &caps, &e) == SEPAL_OK);
            CHECK(caps.dither == 0);
            // A clear of 0.5 reads back as the channel stores it: 15 of 31 widened to 123
            // (5 bits), 31 of 63 to 125 (6 bits); 128 in 8 bits.
            glClearColor(0.5f, 0.5f, 0.5f, 1.0f);
            glClear(GL_COLOR_BUFFER_BIT);
            std::vector<uint8_t> px(8 * 4 * 4);
            REQUIRE(sepal_headless_read_rgba(c, px.data()));
            CAPTURE(int(px[0]));
            CAPTURE(int(px[1]));
            if (rgb565) {
                CHECK((px[0] == 123 || px[0] == 132));  // 15 or 16 of 31: GL leaves the rounding open
                CHECK((px[1] == 125 || px[1] == 130));
            } else {
                CHECK((px[0] == 127 || px[0] == 128));
            }
            sepal_headless_destroy(c);
        }
    // GL_DITHER on llvmpipe: a smooth ramp drawn with it on and off stores the same values
    // (GL leaves dithering to the implementation; llvmpipe truncates either way).
    sepal_headless_desc r = {};
    r.width = 256;
    r.height = 4;
    r.framebuffer = 565;
    char msg[512];
    sepal_headless_context* c = sepal_headless_create(&r, msg, sizeof msg);
    REQUIRE_MESSAGE(c, msg);
    std::vector<uint8_t> on(256 * 4 * 4), off(on.size());
    for (std::vector<uint8_t>* px : {&on, &off}) {
        if (px == &off) glDisable(GL_DITHER);
        draw_color_ramp_gles1();
        REQUIRE(sepal_headless_read_rgba(c, px->data()));
    }
    sepal_headless_destroy(c);
    if (sepal_test::reference_renderer()) CHECK(on == off);
    int levels = 0;
    for (int i = 1; i < 256; ++i) levels += on[4 * i] != on[4 * (i - 1)];
    CHECK(levels == 31);  // 32 values of a 5-bit channel across the ramp
    sepal_headless_desc d = {};
    d.framebuffer = 4444;
    char err[512];
    CHECK(sepal_headless_create(&d, err, sizeof err) == nullptr);
    CHECK(std::strstr(err, "framebuffer 4444 is not 8888 or 565") != nullptr);
}
