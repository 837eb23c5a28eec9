// GL ES 2 rendering of baked materials: the plan with tiny shaders (against GL ES 1.1),
// fused shaders per vertex and per pixel (against the CPU backend), every
// parameterization per pixel.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "material_fixtures.h"
#include "bake/plan.h"
#include "test_util.h"

using namespace material_fx;

namespace {
sepal::ImageDiff compare(const sepal::Image& a, const sepal::Image& b, double threshold, const std::string& name) {
    const sepal::ImageDiff d = sepal::diff_images(a, b, threshold);
    if (d.share_over > 0) {
        sepal::write_png(sepal_test::output_dir() + "/" + name + ".png", b, nullptr);
        sepal::write_png(sepal_test::output_dir() + "/" + name + ".reference.png", a, nullptr);
        sepal::write_png(sepal_test::output_dir() + "/" + name + ".heatmap.png",
                         sepal::diff_heatmap(a, b, d.max_diff > 0 ? d.max_diff : 1), nullptr);
    }
    return d;
}
}  // namespace

TEST_CASE("gles2 multipass matches gles1, with and without blend subtract") {
    const sepal::AssetData a = signed_asset();
    for (const char* mesh : {"sphere", "torus"}) {
        const std::string mesh_name = mesh;
        CAPTURE(mesh_name);
        sepal_ports::SceneSetup s = test_scene(mesh, 2);
        const Rendered es1 = render(a, 0, s);
        for (uint32_t mask : {0u, uint32_t(SEPAL_MASK_BLEND_SUBTRACT)}) {
            CAPTURE(mask);
            const Rendered es2 = render(a, mask, s, nullptr, 2, SEPAL_MODE_MULTIPASS);
            CHECK(es2.path.find("GL ES 2 multipass") != std::string::npos);
            // Same plan, same 8-bit framebuffer: fixed-function and shader arithmetic may
            // round a product differently, by a level per pass and light at most.
            const double level = std::ldexp(1.0, es1.stats.doublings);
            const sepal::ImageDiff d = compare(es1.image, es2.image, 4 * level, "gles2_vs_gles1_" + mesh_name);
            CAPTURE(d.max_diff);
            CAPTURE(d.psnr);
            CHECK(d.share_over == 0.0);
            CHECK(d.psnr > 45.0);
        }
    }
}

TEST_CASE("gles2 fused shaders against the CPU backend") {
    const sepal::AssetData a = signed_asset();
    sepal_ports::SceneSetup s = test_scene("torus", 3);
    const sepal::Image cpu = render_cpu(a, s);
    const Rendered vertex = render(a, 0, s, nullptr, 2, SEPAL_MODE_FUSED_VERTEX);
    const Rendered pixel = render(a, 0, s, nullptr, 2, SEPAL_MODE_FUSED_PIXEL);
    const Rendered multi = render(a, 0, s, nullptr, 2, SEPAL_MODE_MULTIPASS);
    // No depth pre-pass: the first draw lays depth (the torus occludes itself, so a wrong
    // fold would add hidden surfaces and fail the comparisons below).
    CHECK(vertex.stats.draw_calls == 3);  // one pass per light
    CHECK(pixel.stats.draw_calls == 1);   // one pass for all lights
    const sepal::ImageDiff dp = compare(cpu, pixel.image, 3.0, "gles2_fused_pixel_vs_cpu");
    const sepal::ImageDiff dv = compare(cpu, vertex.image, 8.0, "gles2_fused_vertex_vs_cpu");
    const sepal::ImageDiff dm = compare(cpu, multi.image, 8.0, "gles2_multipass_vs_cpu");
    CAPTURE(dp.psnr);
    CAPTURE(dp.max_diff);
    CAPTURE(dv.psnr);
    CAPTURE(dm.psnr);
    // Per pixel in float on both sides; what differs is the 8-bit output and MIP
    // filtering: GL picks coarser levels where the factor coordinates change fast across
    // pixels (near silhouettes), the CPU reads level 0. Measured: PSNR 40.4 dB, 0.7% of
    // pixels over 3 levels, all in that band (without MIP maps the two agree: checked
    // by hand with GL_LINEAR minification).
    CHECK(dp.psnr > 38.0);
    CHECK(dp.share_over < 0.01);
    // Per-vertex coordinates cost accuracy; the fused pass rounds once, the plan per pass.
    CHECK(dv.psnr > 30.0);
    CHECK(dm.psnr > 30.0);
    CHECK(dv.psnr >= dm.psnr - 1.0);
}

TEST_CASE("gles2 fused-pixel takes every parameterization; per-vertex modes refuse the per-pixel ones") {
    for (sepal_param param : {SEPAL_PARAM_IV, SEPAL_PARAM_GS_HALF, SEPAL_PARAM_VH, SEPAL_PARAM_RUSINKIEWICZ, SEPAL_PARAM_ELEV_AZIM,
                              SEPAL_PARAM_AXIS, SEPAL_PARAM_GS_MIRROR}) {
        CAPTURE(int(param));
        const sepal::AssetData a = signed_asset(param);
        sepal_ports::SceneSetup s = test_scene("sphere", 2);
        const sepal::Image cpu = render_cpu(a, s);
        const Rendered pixel = render(a, 0, s, nullptr, 2, SEPAL_MODE_FUSED_PIXEL);
        const sepal::ImageDiff d = compare(cpu, pixel.image, 3.0, "gles2_param" + std::to_string(int(param)));
        CAPTURE(d.psnr);
        CAPTURE(d.max_diff);
        CHECK(d.psnr > 40.0);
        CHECK(image_peak(cpu) > 0.1);
    }
}

TEST_CASE("sepal render and sepal-view: every asset backend, same images") {
    const sepal::AssetData a = signed_asset();
    const std::string dir = sepal_test::temp_dir();
    std::string err, out;
    REQUIRE(sepal::write_asset(dir + "/m.sepal", a, &err));
    const std::string flags = " --size 64x48 --mesh sphere ";
    for (const char* backend : {"gles1", "gles2", "gles2-fused", "gles2-fused-pixel", "cpu"}) {
        const std::string b = backend;
        CAPTURE(b);
        REQUIRE(sepal_test::run(sepal_test::bin("sepal") + " render " + dir + "/m.sepal --backend " + b + flags +
                                    "-o " + dir + "/r_" + b + ".png", &out) == 0);
        REQUIRE(sepal_test::run(sepal_test::bin("sepal-view") + " --headless " + dir + "/m.sepal --backend " + b +
                                    flags + "-o " + dir + "/v_" + b + ".png", &out) == 0);
        sepal::Image r, v;
        REQUIRE(sepal::read_image(dir + "/r_" + b + ".png", &r, &err));
        REQUIRE(sepal::read_image(dir + "/v_" + b + ".png", &v, &err));
        CHECK(sepal::diff_images(r, v, 0).max_diff <= 1.0);  // cpu: two roundings of one float
    }
    CHECK(sepal_test::run(sepal_test::bin("sepal") + " render " + dir + "/m.sepal --backend cpu" + flags + "--float " +
                          dir + "/r.pfm -o " + dir + "/r.png") == 0);
    sepal::Image pfm;
    CHECK(sepal::read_image(dir + "/r.pfm", &pfm, &err));
    CHECK(sepal_test::run(sepal_test::bin("sepal-view") + " --headless " + dir + "/m.sepal --backend metal -o " + dir +
                          "/x.png") == 2);
}

TEST_CASE("luminance materials: one channel times a colour ratio, on every backend") {
    sepal::AssetData a = base_asset(SEPAL_PARAM_GS_HALF, 1);
    a.material.color_mode = SEPAL_COLOR_LUMINANCE;
    a.material.channels = 1;
    a.material.ratio[0] = 1.0f;
    a.material.ratio[1] = 0.5f;
    a.material.ratio[2] = 0.25f;
    a.textures.push_back(make_texture(16, SEPAL_ROLE_G, 0, 1.0f, [](float u, float v, int) {
        return std::exp(-((u - 0.5f) * (u - 0.5f) + (v - 0.5f) * (v - 0.5f)) * 10.0f); }, 0.0f, 1));
    a.textures.push_back(make_texture(16, SEPAL_ROLE_H, 0, 0.4f, [](float u, float, int) { return 0.5f + 0.5f * u; }, 0.0f, 1));
    std::string err;
    REQUIRE_MESSAGE(sepal::build_plan(&a, &err), err);
    sepal_ports::SceneSetup s = test_scene("sphere", 2);
    for (int l = 0; l < 2; ++l)  // white lights, so the image's colour is the ratio
        for (int c = 0; c < 3; ++c) s.scene.lights[l].intensity[c] = s.scene.lights[l].intensity[0];
    const sepal::Image cpu = render_cpu(a, s);
    const Rendered es1 = render(a, 0, s), fused = render(a, 0, s, nullptr, 2, SEPAL_MODE_FUSED_PIXEL);
    CHECK(sepal::diff_images(cpu, es1.image, 4.0).psnr > 35.0);
    CHECK(sepal::diff_images(cpu, fused.image, 3.0).psnr > 40.0);
    // The ratio shows: red : green : blue = 4 : 2 : 1 where the image is bright.
    int checked = 0;
    for (int p = 0; p < s.width * s.height; ++p)
        if (cpu.data[size_t(p) * 3] > 0.3f) {
            CHECK(cpu.data[size_t(p) * 3 + 1] == doctest::Approx(cpu.data[size_t(p) * 3] * 0.5f).epsilon(1e-4));
            CHECK(es1.image.data[size_t(p) * 3 + 2] == doctest::Approx(es1.image.data[size_t(p) * 3] * 0.25f).epsilon(0.05));
            ++checked;
        }
    CHECK(checked > 50);
}
