// Frames of many objects (sepal_frame.h): what the engine drew before is kept bit for bit
// where no object covers it, objects occlude each other and the engine's own geometry
// correctly in either draw order, and the frame matches the exact renderer's image of the
// same description on every backend.
#include <GLES2/gl2.h>

#include <algorithm>
#include <cmath>

#include "bake/plan.h"
#include "frame_fixtures.h"
#include "material_fixtures.h"
#include "reference/render_exact.h"
#include "spec/spec.h"
#include "test_util.h"

using namespace frame_fx;
using namespace material_fx;

namespace {

// The scissor box of the engine's rectangle (window coordinates, rows from the bottom).
constexpr int kRectX = 14, kRectY = 34, kRectW = 22, kRectH = 16;

// The engine's frame before sepal's objects: its clear colour, and a rectangle nearer
// than the objects (depth 0.5).
void engine_draws(const float clear[3], const float rect[3]) {
    frame_fx::engine_draws(clear, rect, kRectX, kRectY, kRectW, kRectH, 0.5f);
}

bool in_rect(size_t pixel) {  // pixel: top row first
    const int x = int(pixel % kWidth), y = kHeight - 1 - int(pixel / kWidth);
    return x >= kRectX && x < kRectX + kRectW && y >= kRectY && y < kRectY + kRectH;
}

std::vector<uint8_t> gl_frame(Gl& gl, const Scene& sc, const sepal_material* const m[2], sepal_draw_mode mode,
                              bool reversed, bool clear) {
    sepal_frame_desc fd = sc.frame;
    fd.caps = &gl.caps;
    fd.clear = clear ? 1 : 0;
    sepal_frame f;
    sepal_error e = {};
    REQUIRE_MESSAGE(sepal_frame_begin(&f, &fd, &e) == SEPAL_OK, e.message);
    for (int i = 0; i < 2; ++i) {
        const int k = reversed ? 1 - i : i;
        const sepal_object o = sc.object(k, m[k], nullptr, mode);
        sepal_draw_stats stats = {};
        REQUIRE_MESSAGE(sepal_frame_draw(&f, &o, &stats, &e) == SEPAL_OK, e.message);
    }
    REQUIRE_MESSAGE(sepal_frame_end(&f, &e) == SEPAL_OK, e.message);
    return gl.read();
}

sepal::Image rgb(const std::vector<uint8_t>& rgba) {
    return sepal::to_rgb(sepal::image_from_rgba8(rgba.data(), kWidth, kHeight));
}

// G = 0.5 q, H = 0.25 q with q = 1: f = 0.125 everywhere (a plan of one product pass).
sepal::AssetData constant_asset() {
    sepal::AssetData a = base_asset(SEPAL_PARAM_IV, 1);
    a.textures.push_back(make_texture(8, SEPAL_ROLE_G, 0, 0.5f, [](float, float, int) { return 1.0f; }));
    a.textures.push_back(make_texture(8, SEPAL_ROLE_H, 0, 0.25f, [](float, float, int) { return 1.0f; }));
    std::string err;
    REQUIRE_MESSAGE(sepal::build_plan(&a, &err), err);
    return a;
}

}  // namespace

TEST_CASE("frame: pixels the objects do not cover keep what the engine drew, bit for bit; either draw order") {
    // Object 0 a signed plan (subtractions; inversions without blend subtract; the single-unit
    // path's running sum), object 1 an add-only one: every framebuffer-wide operation the
    // runtime has is in the frame.
    const std::vector<uint8_t> signed_bytes = encode(signed_asset()), constant_bytes = encode(constant_asset());
    const Scene sc;
    struct Case {
        int version;
        uint32_t mask;
        sepal_draw_mode mode;
    };
    const Case cases[] = {
        {1, 0, SEPAL_MODE_MULTIPASS},
        {1, SEPAL_MASK_BLEND_SUBTRACT, SEPAL_MODE_MULTIPASS},
        {1, SEPAL_MASK_MULTITEXTURE, SEPAL_MODE_MULTIPASS},
        {1, SEPAL_MASK_MULTITEXTURE | SEPAL_MASK_BLEND_SUBTRACT, SEPAL_MODE_MULTIPASS},
        {2, 0, SEPAL_MODE_MULTIPASS},
        {2, SEPAL_MASK_BLEND_SUBTRACT, SEPAL_MODE_MULTIPASS},
        {2, 0, SEPAL_MODE_FUSED_VERTEX},
        {2, 0, SEPAL_MODE_FUSED_PIXEL},
    };
    for (const Case& c : cases) {
        CAPTURE(c.version);
        CAPTURE(c.mask);
        CAPTURE(int(c.mode));
        Gl gl(c.version);
        const sepal_material* m[2] = {gl.material(signed_bytes, c.mask), gl.material(constant_bytes, c.mask)};
        const float clear_a[3] = {0.2f, 0.3f, 0.4f}, rect_a[3] = {0.9f, 0.1f, 0.1f};
        const float clear_b[3] = {0.6f, 0.5f, 0.1f}, rect_b[3] = {0.1f, 0.8f, 0.2f};
        engine_draws(clear_a, rect_a);
        const std::vector<uint8_t> before_a = gl.read();
        const std::vector<uint8_t> a = gl_frame(gl, sc, m, c.mode, false, false);
        engine_draws(clear_b, rect_b);
        const std::vector<uint8_t> before_b = gl.read();
        const std::vector<uint8_t> b = gl_frame(gl, sc, m, c.mode, false, false);
        engine_draws(clear_a, rect_a);
        const std::vector<uint8_t> reversed = gl_frame(gl, sc, m, c.mode, true, false);
        const std::vector<uint8_t> cleared = gl_frame(gl, sc, m, c.mode, false, true);
        // A pixel is kept (equal to what the engine drew, under both engine frames) or the
        // objects' (equal under both: their pixels do not depend on what was there).
        size_t kept = 0, covered = 0, neither = 0, rect_covered_alone = 0, rect_kept = 0, rect = 0;
        for (size_t p = 0; p < size_t(kWidth) * kHeight; ++p) {
            auto same = [p](const std::vector<uint8_t>& x, const std::vector<uint8_t>& y) {
                return std::equal(x.begin() + 4 * p, x.begin() + 4 * p + 4, y.begin() + 4 * p);
            };
            const bool k = same(a, before_a) && same(b, before_b);
            kept += k;
            covered += !k && same(a, b);
            neither += !k && !same(a, b);
            if (in_rect(p)) {
                ++rect;
                rect_kept += k;
                // Without the rectangle (a cleared frame), an object is there.
                rect_covered_alone += cleared[4 * p] + cleared[4 * p + 1] + cleared[4 * p + 2] > 0;
            }
        }
        CAPTURE(kept);
        CAPTURE(covered);
        CAPTURE(rect_covered_alone);
        CHECK(neither == 0);
        CHECK(covered > 800);
        CHECK(kept > 2000);
        CHECK(rect_kept == rect);         // the engine's nearer rectangle hides the objects
        CHECK(rect_covered_alone > 40);   // which are behind it
        CHECK(reversed == a);             // depth, not the order, decides
    }
}

TEST_CASE("frame: two objects against the exact renderer of the same description, every backend") {
    // Object 0 a constant f, object 1 an anisotropic Ward (radiance factors, 2 NMF terms)
    // turned by its model matrix, scaled by 1/2 and in front of 0 where they overlap. Broad
    // enough that this small bake's own error stays below the frame's (a narrow one costs
    // every backend alike, the CPU's factored BRDF included).
    const char* const ward = "ward:rho_d=0.5,rho_s=0.2,ax=0.5,ay=0.3";
    const sepal::AssetData ward_asset = bake_small(ward, sepal::Param::GsHalf, sepal::Method::NMF, 2, true, 32, 64);
    const std::vector<uint8_t> bytes[2] = {encode(constant_asset()), encode(ward_asset)};
    std::string err;
    std::unique_ptr<sepal::Brdf> ward_brdf = sepal::make_brdf(ward, &err);
    REQUIRE_MESSAGE(ward_brdf, err);
    const ConstantBrdf constant(0.125);
    const sepal::Brdf* brdf[2] = {&constant, ward_brdf.get()};
    const Scene sc;
    sepal_asset assets[2];
    sepal_error e = {};
    for (int k = 0; k < 2; ++k) REQUIRE(sepal_asset_parse(bytes[k].data(), bytes[k].size(), &assets[k], &e) == SEPAL_OK);

    sepal::Image exact(kWidth, kHeight, 3);
    std::vector<float> depth(size_t(kWidth) * kHeight, 1.0f);
    for (int k = 0; k < 2; ++k) {
        const sepal_object o = sc.object(k, nullptr, &assets[k], SEPAL_MODE_MULTIPASS);
        sepal_scene scene;
        float clip[16];
        REQUIRE(sepal_object_scene(&sc.frame, &o, &scene, clip, &e) == SEPAL_OK);
        REQUIRE_MESSAGE(sepal::render_exact_object(*brdf[k], scene, sc.mesh, clip, kWidth, kHeight, &exact, &depth,
                                                   nullptr, &err, sepal::kReferenceSupersample),
                        err);
    }
    // Shading in object space (eye and lights moved by the inverse model matrix) against the
    // same objects moved into world space on the CPU (positions by the model matrix, normals
    // by its inverse transpose, tangents by it) and shaded there: the same image.
    {
        sepal::Image world(kWidth, kHeight, 3);
        std::vector<float> world_depth(size_t(kWidth) * kHeight, 1.0f);
        for (int k = 0; k < 2; ++k) {
            const float* m = sc.model[k];
            std::vector<sepal_vertex> v(sc.mesh.vertices, sc.mesh.vertices + sc.mesh.vertex_count);
            const float s2 = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
            for (sepal_vertex& x : v) {
                const sepal_vertex o = x;
                for (int r = 0; r < 3; ++r) {
                    x.position[r] = m[r] * o.position[0] + m[4 + r] * o.position[1] + m[8 + r] * o.position[2] + m[12 + r];
                    // inverse transpose of s R is R / s: normals turn with the tangents
                    x.normal[r] = (m[r] * o.normal[0] + m[4 + r] * o.normal[1] + m[8 + r] * o.normal[2]) / s2;
                    x.tangent[r] = m[r] * o.tangent[0] + m[4 + r] * o.tangent[1] + m[8 + r] * o.tangent[2];
                }
            }
            const sepal_mesh world_mesh = {v.data(), sc.mesh.indices, sc.mesh.vertex_count, sc.mesh.index_count};
            sepal_object o = sc.object(k, nullptr, &assets[k], SEPAL_MODE_MULTIPASS);
            sepal_model_identity(o.model);
            sepal_scene scene;
            float clip[16];
            REQUIRE(sepal_object_scene(&sc.frame, &o, &scene, clip, &e) == SEPAL_OK);
            REQUIRE(sepal::render_exact_object(*brdf[k], scene, world_mesh, clip, kWidth, kHeight, &world, &world_depth,
                                               nullptr, &err, sepal::kReferenceSupersample));
        }
        const sepal::ImageDiff d = sepal::diff_images(exact, world, 0);
        CAPTURE(d.psnr);
        CHECK(d.psnr >= 60.0);
        MESSAGE("exact, object space against world space: " << d.psnr << " dB");
    }
    for (float& v : exact.data) v = std::round(std::min(1.0f, std::max(0.0f, v)) * 255.0f) / 255.0f;
    size_t both = 0;  // pixels of object 1 in front of object 0: the overlap is real
    {
        std::vector<float> d0(size_t(kWidth) * kHeight, 1.0f), d1 = d0;
        sepal::Image scratch_image(kWidth, kHeight, 3);
        for (int k = 0; k < 2; ++k) {
            const sepal_object o = sc.object(k, nullptr, &assets[k], SEPAL_MODE_MULTIPASS);
            sepal_scene scene;
            float clip[16];
            REQUIRE(sepal_object_scene(&sc.frame, &o, &scene, clip, &e) == SEPAL_OK);
            REQUIRE(sepal::render_exact_object(*brdf[k], scene, sc.mesh, clip, kWidth, kHeight, &scratch_image,
                                               k == 0 ? &d0 : &d1, nullptr, &err));
        }
        for (size_t p = 0; p < d0.size(); ++p) both += d0[p] < 1.0f && d1[p] < d0[p];
    }
    CHECK(both > 100);

    auto check = [&](const sepal::Image& img, const std::string& name) {
        const sepal::ImageDiff d = sepal::diff_images(exact, img, 0);
        CAPTURE(name);
        CAPTURE(d.psnr);
        sepal::write_png(sepal_test::output_dir() + "/frame_" + name + ".png", img, nullptr);
        CHECK(d.psnr >= 38.0);
        MESSAGE("two-object frame, " << name << " against exact: " << d.psnr << " dB");
    };
    sepal::write_png(sepal_test::output_dir() + "/frame_exact.png", exact, nullptr);
    sepal::Image gles1_image;
    for (int version : {1, 2})
        for (sepal_draw_mode mode : {SEPAL_MODE_MULTIPASS, SEPAL_MODE_FUSED_VERTEX, SEPAL_MODE_FUSED_PIXEL}) {
            if (version == 1 && mode != SEPAL_MODE_MULTIPASS) continue;
            Gl gl(version);
            const sepal_material* m[2] = {gl.material(bytes[0], 0), gl.material(bytes[1], 0)};
            const sepal::Image img = rgb(gl_frame(gl, sc, m, mode, false, true));
            if (version == 1) gles1_image = img;
            check(img, version == 1 ? "gles1" : mode == SEPAL_MODE_MULTIPASS ? "gles2" : mode == SEPAL_MODE_FUSED_VERTEX
                                                                                        ? "gles2-fused-vertex"
                                                                                        : "gles2-fused-pixel");
        }
    // The CPU backend and the emulator, object by object into their own buffers.
    sepal::Image cpu(kWidth, kHeight, 3);
    std::vector<float> cpu_depth(size_t(kWidth) * kHeight);
    std::vector<uint8_t> emu(size_t(kWidth) * kHeight * 4, 0);
    std::vector<float> emu_depth(size_t(kWidth) * kHeight);
    sepal_frame_clear_cpu(kWidth, kHeight, nullptr, cpu.data.data(), cpu_depth.data());
    sepal_frame_clear_cpu(kWidth, kHeight, nullptr, nullptr, emu_depth.data());
    for (int k = 0; k < 2; ++k) {
        const sepal_object o = sc.object(k, nullptr, &assets[k], SEPAL_MODE_MULTIPASS);
        std::vector<float> scratch(sepal_cpu_scratch_floats(sc.mesh.vertex_count));
        REQUIRE_MESSAGE(sepal_frame_draw_cpu(&sc.frame, &o, cpu.data.data(), cpu_depth.data(), scratch.data(),
                                             scratch.size(), nullptr, &e) == SEPAL_OK,
                        e.message);
        scratch.resize(sepal_emulate_scratch_floats(kWidth, kHeight, sc.mesh.vertex_count, 2));
        REQUIRE_MESSAGE(sepal_frame_emulate(&sc.frame, &o, 1, 0, emu.data(), emu_depth.data(), scratch.data(),
                                            scratch.size(), nullptr, &e) == SEPAL_OK,
                        e.message);
    }
    for (float& v : cpu.data) v = std::min(1.0f, std::max(0.0f, v));
    check(cpu, "cpu");
    // The emulator is what GL ES 1.1 shows (as for single objects: tests/ports/emulate_test.cpp).
    const sepal::ImageDiff de = sepal::diff_images(gles1_image, rgb(emu), 8);
    CAPTURE(de.psnr);
    CHECK(de.psnr >= 45.0);
    CHECK(de.share_over <= 0.001);
}

TEST_CASE("frame: arguments are checked") {
    const std::vector<uint8_t> bytes = encode(constant_asset());
    Gl gl(1);
    const sepal_material* m = gl.material(bytes, 0);
    const Scene sc;
    sepal_frame_desc fd = sc.frame;
    fd.caps = &gl.caps;
    sepal_frame f = {};
    sepal_error e = {};
    sepal_object o = sc.object(0, m, nullptr, SEPAL_MODE_MULTIPASS);
    CHECK(sepal_frame_draw(&f, &o, nullptr, &e) == SEPAL_ERR_INVALID_ARGUMENT);  // before begin
    REQUIRE(sepal_frame_begin(&f, &fd, &e) == SEPAL_OK);
    o.model[0] = 2.0f;  // a non-uniform scale: shading in object space would be wrong
    CHECK(sepal_frame_draw(&f, &o, nullptr, &e) == SEPAL_ERR_INVALID_ARGUMENT);
    CHECK(std::string(e.message).find("similarity") != std::string::npos);
    o = sc.object(0, m, nullptr, SEPAL_MODE_MULTIPASS);
    o.light_count = SEPAL_MAX_LIGHTS + 1;
    CHECK(sepal_frame_draw(&f, &o, nullptr, &e) == SEPAL_ERR_INVALID_ARGUMENT);
    CHECK(sepal_frame_end(&f, &e) == SEPAL_OK);
    CHECK(sepal_frame_end(&f, &e) == SEPAL_ERR_INVALID_ARGUMENT);
}
