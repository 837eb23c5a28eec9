// GL ES 1.1 multipass rendering of baked materials (runtime/include/sepal/sepal_material.h): absolute
// correctness against the exact backend, and every capability-masked path against the
// full one.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <vector>

#include "bake/asset_file.h"
#include "bake/bake.h"
#include "spec/spec.h"
#include "material_fixtures.h"
#include "reference/render_exact.h"
#include "bake/plan.h"
#include "common/render_gl.h"
#include "common/scene_flags.h"
#include "headless/sepal_headless.h"
#include "sepal/sepal_material.h"
#include "test_util.h"

using namespace material_fx;

TEST_CASE("gles1 and cpu: a constant BRDF matches the exact backend's render") {
    // G = 0.5 q, H = 0.25 q with q = 1: f = 0.125 per steradian everywhere.
    const double f = 0.125;
    sepal::AssetData a = base_asset(SEPAL_PARAM_IV, 1);
    a.textures.push_back(make_texture(8, SEPAL_ROLE_G, 0, 0.5f, [](float, float, int) { return 1.0f; }));
    a.textures.push_back(make_texture(8, SEPAL_ROLE_H, 0, 0.25f, [](float, float, int) { return 1.0f; }));
    std::string err;
    REQUIRE_MESSAGE(sepal::build_plan(&a, &err), err);
    for (int lights : {1, 3}) {
        CAPTURE(lights);
        sepal_ports::SceneSetup s = test_scene("sphere", lights);
        const Rendered gl = render(a, 0, s);
        sepal::Image exact;
        REQUIRE(sepal::render_exact(ConstantBrdf(f), s.scene, s.mesh, s.width, s.height, &exact, nullptr, &err));
        sepal::write_png(sepal_test::output_dir() + "/gles1_constant_" + std::to_string(lights) + ".png",
                         gl.image, nullptr);
        const sepal::ImageDiff diff = sepal::diff_images(exact, gl.image, 3.0);
        CAPTURE(diff.psnr);
        CAPTURE(diff.max_diff);
        CAPTURE(gl.stats.doublings);
        // Per-vertex (Gouraud) irradiance against per-pixel: a few levels on a 64x32 sphere.
        CHECK(diff.psnr > 38.0);
        CHECK(diff.share_over < 0.02);
        // The CPU backend evaluates per pixel in float: it matches the exact render.
        const sepal::Image cpu = render_cpu(a, s);
        const sepal::ImageDiff dc = sepal::diff_images(exact, cpu, 0.01);
        CAPTURE(dc.max_diff);
        CHECK(dc.max_diff < 0.01);  // 8-bit units: float against double, ~1e-5 relative
    }
}

TEST_CASE("gles1 material: every capability-masked path renders the full path's image") {
    // Two signed terms with varying factors (biased textures), in gs-half.
    sepal::AssetData a = signed_asset();
    for (const char* mesh : {"sphere", "torus"}) {
        const std::string mesh_name = mesh;
        CAPTURE(mesh_name);
        sepal_ports::SceneSetup s = test_scene(mesh, 2);
        const Rendered full = render(a, 0, s);
        CHECK(full.stats.copies == 0);
        sepal::write_png(sepal_test::output_dir() + "/gles1_paths_full_" + mesh + ".png", full.image, nullptr);
        double brightest = 0;
        for (float v : full.image.data) brightest = std::max<double>(brightest, v);
        CHECK(brightest > 0.3);  // the scene is lit: the comparison means something
        // Against the CPU backend (per-pixel coordinates, float): the price of per-vertex
        // coordinates and an 8-bit framebuffer.
        const sepal::Image cpu = render_cpu(a, s);
        sepal::write_png(sepal_test::output_dir() + "/cpu_signed_" + mesh_name + ".png", cpu, nullptr);
        const sepal::ImageDiff dc = sepal::diff_images(cpu, full.image, 4.0);
        CAPTURE(dc.psnr);
        CAPTURE(dc.max_diff);
        CAPTURE(dc.share_over);
        CHECK(dc.psnr > 30.0);
        const uint32_t masks[] = {SEPAL_MASK_BLEND_SUBTRACT, SEPAL_MASK_MULTITEXTURE,
                                  SEPAL_MASK_MULTITEXTURE | SEPAL_MASK_BLEND_SUBTRACT, SEPAL_MASK_FBO | SEPAL_MASK_NPOT};
        for (uint32_t mask : masks) {
            CAPTURE(mask);
            const Rendered r = render(a, mask, s);
            if (mask & SEPAL_MASK_MULTITEXTURE) CHECK(r.stats.copies > 0);
            // 8-bit tolerance. The blend units and the texture combiners round products
            // differently (llvmpipe blends in 8-bit fixed point), by up to a level per
            // pass and light in the framebuffer; 8 pass-light steps here. A framebuffer
            // level becomes 2^doublings levels in the image. Structural mistakes (an
            // offset copy, a wrong sign) cost tens of levels and fail this.
            const double level = std::ldexp(1.0, full.stats.doublings);
            const sepal::ImageDiff d = sepal::diff_images(full.image, r.image, 4 * level);
            CAPTURE(d.max_diff);
            CAPTURE(d.psnr);
            CAPTURE(full.stats.doublings);
            CHECK(d.share_over == 0.0);
            CHECK(d.psnr > 45.0);
            if (d.share_over > 0.0)
                sepal::write_png(sepal_test::output_dir() + "/gles1_paths_mask" + std::to_string(mask) + ".png",
                                 r.image, nullptr);
        }
    }
}

namespace {
// The asset is written as version 2.`minor`, and the same file patched to one minor version
// older is refused with `message` (patched minor version and header CRC).
void check_version_gate(const sepal::AssetData& a, uint16_t minor, const char* message) {
    std::vector<uint8_t> bytes;
    std::string err;
    REQUIRE_MESSAGE(sepal::encode_asset(a, &bytes, &err), err);
    auto parsed = std::make_unique<sepal_asset>();
    sepal_error e{};
    REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), parsed.get(), &e) == SEPAL_OK);
    CHECK(parsed->header.version_major == 2);
    CHECK(parsed->header.version_minor == minor);
    sepal_fmt_header h;
    memcpy(&h, bytes.data(), sizeof h);
    h.version_minor = uint16_t(minor - 1);
    h.header_crc = 0;
    memcpy(bytes.data(), &h, sizeof h);
    const uint32_t crc = sepal_crc32(0, bytes.data(), sizeof h);
    h.header_crc = sepal_crc32(crc, bytes.data() + sizeof h, h.chunk_count * sizeof(sepal_fmt_chunk));
    memcpy(bytes.data(), &h, sizeof h);
    CHECK(sepal_asset_parse(bytes.data(), bytes.size(), parsed.get(), &e) != SEPAL_OK);
    CHECK(std::string(e.message).find(message) != std::string::npos);
}
}  // namespace

TEST_CASE("gles1 material: gs-mirror draws Phong's lobe in one product per vertex; format 2.6 only for it") {
    // G at the mirror direction r, H at the eye about it (offline/factor/param.h): Phong's
    // lobe times cos(theta_i) is one product there. Baked with one term, drawn per vertex.
    const std::string spec = "phong:rho_d=0,rho_s=0.8,n=200";
    std::string err;
    std::unique_ptr<sepal::Brdf> f = sepal::make_brdf(spec, &err);
    REQUIRE_MESSAGE(f, err);
    sepal::BakeOptions o;
    o.params = {sepal::Param::GsMirror};
    o.resolutions = {64};
    o.smooth_resolutions = {16};
    o.terms = {1};
    o.held_out = false;
    sepal::BakeResult r;
    REQUIRE_MESSAGE(sepal::bake(*f, o, &r, &err), err);
    const sepal::AssetData& a = r.asset;
    CHECK(a.material.param == SEPAL_PARAM_GS_MIRROR);
    CHECK(a.material.terms == 1);
    sepal_ports::SceneSetup s = test_scene("sphere", 2);
    sepal::Image cpu = render_cpu(a, s);
    const Rendered gl = render(a, 0, s);
    sepal::Image exact;
    REQUIRE(sepal::render_exact(*f, s.scene, s.mesh, s.width, s.height, &exact, nullptr, &err,
                                false, sepal::kReferenceSupersample));
    // What a framebuffer shows: the highlight's centre is above white.
    for (sepal::Image* im : {&cpu, &exact})
        for (float& v : im->data) v = std::min(v, 1.0f);
    const sepal::ImageDiff d = sepal::diff_images(cpu, gl.image, 3.0), dx = sepal::diff_images(exact, gl.image, 3.0);
    CAPTURE(d.psnr);
    CAPTURE(d.share_over);
    CAPTURE(dx.psnr);
    // Per-vertex against per-pixel coordinates and 8-bit passes, and the one term against
    // the exact render: measured 58.9 and 46.0 dB. gs-half's one term at the same sizes is
    // 38.9 dB (the lobe is no product there).
    CHECK(d.psnr > 50.0);
    CHECK(d.share_over < 0.02);
    CHECK(dx.psnr > 43.0);
    o.params = {sepal::Param::GsHalf};
    sepal::BakeResult half;
    REQUIRE_MESSAGE(sepal::bake(*f, o, &half, &err), err);
    const Rendered gh = render(half.asset, 0, s);
    const sepal::ImageDiff dh = sepal::diff_images(exact, gh.image, 3.0);
    CAPTURE(dh.psnr);
    CHECK(dh.psnr < dx.psnr - 6.0);
    CHECK(image_peak(cpu) > 0.1);
    // Written as 2.6; a 2.5 header cannot hold it.
    check_version_gate(a, SEPAL_FMT_VERSION_MINOR_MIRROR, "gs-mirror parameterization needs version 2.6");
}

TEST_CASE("gles1 material: the axis parameterization is drawn per vertex; format 2.2 only for it") {
    // Angles about the tangent (offline/factor/param.h): smooth above the horizon, so GL
    // interpolates per-vertex coordinates as it does iv's. The non-negative term of the
    // fixture (every texel valid: the whole square is above the horizon).
    sepal::AssetData a = base_asset(SEPAL_PARAM_AXIS, 1);
    a.textures.push_back(make_texture(16, SEPAL_ROLE_G, 0, 1.0f, [](float u, float v, int c) {
        // a cylinder-like lobe along alpha_i + alpha_o = 0 (the anti-diagonal)
        const float d = u + v - 1.0f;
        return 0.1f + std::exp(-d * d * 30.0f) * (0.8f + 0.1f * c);
    }));
    a.textures.push_back(make_texture(16, SEPAL_ROLE_H, 0, 0.3f, [](float u, float v, int) { return 0.5f + 0.5f * u * v; }));
    std::string err;
    REQUIRE_MESSAGE(sepal::build_plan(&a, &err), err);
    sepal_ports::SceneSetup s = test_scene("sphere", 2);
    const sepal::Image cpu = render_cpu(a, s);
    const Rendered gl = render(a, 0, s);
    const sepal::ImageDiff d = sepal::diff_images(cpu, gl.image, 3.0);
    CAPTURE(d.psnr);
    CAPTURE(d.share_over);
    // Per-vertex against per-pixel coordinates and 8-bit passes, as for the others.
    CHECK(d.psnr > 38.0);
    CHECK(d.share_over < 0.02);
    CHECK(image_peak(cpu) > 0.1);
    // Written as 2.2; a 2.1 header cannot hold it.
    check_version_gate(a, SEPAL_FMT_VERSION_MINOR_AXIS, "axis parameterization needs version 2.2");
    // The other parameterizations stay where they were (gs-half: 1.0).
    a.material.param = SEPAL_PARAM_GS_HALF;
    std::vector<uint8_t> bytes;
    auto parsed = std::make_unique<sepal_asset>();
    sepal_error e{};
    REQUIRE(sepal::encode_asset(a, &bytes, &err));
    REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), parsed.get(), &e) == SEPAL_OK);
    CHECK(parsed->header.version_major == 1);
}

TEST_CASE("gles1 material: refusals") {
    sepal::AssetData a = base_asset(SEPAL_PARAM_RUSINKIEWICZ, 1);
    a.textures.push_back(make_texture(4, SEPAL_ROLE_G, 0, 1, [](float, float, int) { return 1.0f; }));
    a.textures.push_back(make_texture(4, SEPAL_ROLE_H, 0, 1, [](float, float, int) { return 1.0f; }));
    std::vector<uint8_t> bytes;
    std::string err;
    REQUIRE_MESSAGE(sepal::build_plan(&a, &err), err);
    REQUIRE(sepal::encode_asset(a, &bytes, &err));
    auto asset = std::make_unique<sepal_asset>();
    sepal_error e{};
    REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), asset.get(), &e) == SEPAL_OK);
    sepal_headless_desc hd = {};
    char msg[256];
    sepal_headless_context* ctx = sepal_headless_create(&hd, msg, sizeof msg);
    REQUIRE(ctx);
    sepal_caps caps;
    REQUIRE(sepal_query_caps(1, 0, sepal_headless_get_proc_address, &caps, &e) == SEPAL_OK);
    auto mat = std::make_unique<sepal_material>();
    CHECK(sepal_material_create(&caps, asset.get(), 64, 64, mat.get(), &e) == SEPAL_ERR_UNSUPPORTED);
    CHECK(std::string(e.message).find("per-pixel") != std::string::npos);
    // A good material, then a draw with too little scratch and too big a viewport.
    asset->material.param = SEPAL_PARAM_IV;
    REQUIRE(sepal_material_create(&caps, asset.get(), 64, 64, mat.get(), &e) == SEPAL_OK);
    sepal_ports::SceneSetup s = test_scene("sphere", 1);
    std::vector<float> scratch(10);
    sepal_draw_desc d = {};
    d.material = mat.get();
    d.mesh = &s.mesh;
    d.scene = &s.scene;
    d.width = d.height = 64;
    d.scratch = scratch.data();
    d.scratch_floats = scratch.size();
    CHECK(sepal_draw(&d, nullptr, &e) == SEPAL_ERR_CAPACITY);
    d.width = 65;
    CHECK(sepal_draw(&d, nullptr, &e) == SEPAL_ERR_INVALID_ARGUMENT);
    CHECK(std::string(e.message).find("viewport") != std::string::npos);
    sepal_material_destroy(mat.get());
    sepal_headless_destroy(ctx);
}

TEST_CASE("gles1 material: sepal render and sepal-view draw the same asset the same way") {
    sepal::AssetData a = base_asset(SEPAL_PARAM_VH, 1);
    a.textures.push_back(make_texture(8, SEPAL_ROLE_G, 0, 1, [](float u, float, int) { return 0.2f + 0.8f * u; }));
    a.textures.push_back(make_texture(8, SEPAL_ROLE_H, 0, 1, [](float, float v, int c) { return 0.3f + 0.2f * c + 0.4f * v; }));
    const std::string dir = sepal_test::temp_dir();
    std::string err, out;
    REQUIRE_MESSAGE(sepal::build_plan(&a, &err), err);
    REQUIRE_MESSAGE(sepal::write_asset(dir + "/m.sepal", a, &err), err);
    const std::string flags = " --size 80x60 --mesh torus --light point:1,-2,2:15 ";
    REQUIRE(sepal_test::run(sepal_test::bin("sepal") + " render " + dir + "/m.sepal --backend gles1" + flags +
                                "-o " + dir + "/r.png", &out) == 0);
    CHECK(out.find("two texture units") != std::string::npos);
    REQUIRE(sepal_test::run(sepal_test::bin("sepal-view") + " --headless " + dir + "/m.sepal" + flags + "-o " +
                                dir + "/v.png", &out) == 0);
    REQUIRE(sepal_test::run(sepal_test::bin("sepal-view") + " --headless " + dir + "/m.sepal --mask multitexture" +
                                flags + "-o " + dir + "/v1.png", &out) == 0);
    CHECK(out.find("one texture unit") != std::string::npos);
    sepal::Image r, v, v1;
    REQUIRE(sepal::read_image(dir + "/r.png", &r, &err));
    REQUIRE(sepal::read_image(dir + "/v.png", &v, &err));
    REQUIRE(sepal::read_image(dir + "/v1.png", &v1, &err));
    CHECK(sepal::diff_images(r, v, 0).max_diff == 0);
    CHECK(sepal::diff_images(r, v1, 0).max_diff <= 4);
    CHECK(image_peak(r) > 0.2);
    // On an RGB565 pbuffer too, GL ES 1.1 and 2 alike (the passes summed in 8 bits).
    for (const char* backend : {"gles1", "gles2"}) {
        CAPTURE(backend);
        const std::string b = std::string(" --backend ") + backend + " --framebuffer 565";
        REQUIRE(sepal_test::run(sepal_test::bin("sepal") + " render " + dir + "/m.sepal" + b + flags + "-o " + dir +
                                    "/r565.png", &out) == 0);
        REQUIRE(sepal_test::run(sepal_test::bin("sepal-view") + " --headless " + dir + "/m.sepal" + b + flags + "-o " +
                                    dir + "/v565.png", &out) == 0);
        CHECK(out.find("passes summed in an 8-bit target") != std::string::npos);
        sepal::Image r565, v565;
        REQUIRE(sepal::read_image(dir + "/r565.png", &r565, &err));
        REQUIRE(sepal::read_image(dir + "/v565.png", &v565, &err));
        CHECK(sepal::diff_images(r565, v565, 0).max_diff == 0);
        CHECK(sepal::diff_images(r, v565, 0).max_diff > 0);  // 565, not the 8888 image
        CHECK(sepal::diff_images(r, v565, 0).max_diff <= 9);  // within a 5-bit step of it
    }
    // Refusals: not an asset, a corrupt asset, a bad mask.
    CHECK(sepal_test::run(sepal_test::bin("sepal") + " render ward --backend gles1 -o " + dir + "/x.png", &out) == 2);
    CHECK(out.find("baked asset") != std::string::npos);
    std::FILE* f = std::fopen((dir + "/bad.sepal").c_str(), "wb");
    std::fputs("SEPALBRD but not really", f);
    std::fclose(f);
    CHECK(sepal_test::run(sepal_test::bin("sepal-view") + " --headless " + dir + "/bad.sepal -o " + dir + "/x.png",
                          &out) == 1);
    CHECK(out.find("too short") != std::string::npos);
    CHECK(sepal_test::run(sepal_test::bin("sepal-view") + " --headless " + dir + "/m.sepal --mask bogus -o " + dir +
                              "/x.png", &out) == 2);
    CHECK(sepal_test::run(sepal_test::bin("sepal-view") + " --headless " + dir + "/m.sepal --framebuffer 555 -o " +
                              dir + "/x.png", &out) == 2);
    CHECK(out.find("give 8888") != std::string::npos);
    CHECK(sepal_test::run(sepal_test::bin("sepal-view") + " " + dir + "/m.sepal --framebuffer 565", &out) == 2);
    CHECK(out.find("--framebuffer applies with --headless") != std::string::npos);
    std::FILE* none = std::fopen((dir + "/x.png").c_str(), "rb");
    CHECK(none == nullptr);  // nothing half-written
    if (none) std::fclose(none);
}

TEST_CASE("gles1 and cpu: a diffuse texture map modulates the material (Fig. 13)") {
    sepal::AssetData a = signed_asset();
    sepal_ports::SceneSetup s = test_scene("sphere", 2);
    sepal_ports::Rgba8Image grey;
    grey.width = grey.height = 4;
    grey.pixels.assign(4 * 4 * 4, 128);
    const Rendered plain = render(a, 0, s), halved = render(a, 0, s, &grey);
    sepal::Image half = plain.image;
    for (float& v : half.data) v *= 128.0f / 255.0f;
    const sepal::ImageDiff d = sepal::diff_images(half, halved.image, 1.0);
    CAPTURE(d.max_diff);
    CHECK(d.share_over == 0.0);  // within one level of x 128/255
    // A checker on both backends: the same pattern in the same place.
    sepal_ports::Rgba8Image checker;
    checker.width = checker.height = 8;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            for (int c = 0; c < 4; ++c) checker.pixels.push_back(((x / 2 + y / 2) % 2) ? 255 : 40);
    const Rendered gl = render(a, 0, s, &checker);
    const sepal::Image cpu = render_cpu(a, s, &checker);
    sepal::write_png(sepal_test::output_dir() + "/gles1_diffuse_checker.png", gl.image, nullptr);
    const sepal::ImageDiff dc = sepal::diff_images(cpu, gl.image, 8.0);
    CAPTURE(dc.psnr);
    CHECK(dc.psnr > 30.0);
    const sepal::ImageDiff against_plain = sepal::diff_images(plain.image, gl.image, 8.0);
    CHECK(against_plain.share_over > 0.05);  // the map really changed the picture
}

TEST_CASE("gles1 material: the horizon window ends a lit crescent at the horizon; format 2.7 only for it") {
    CHECK(sepal_horizon_window(0.1f, 0.05f) == doctest::Approx(0.5f));
    CHECK(sepal_horizon_window(0.1f, 0.2f) == 1.0f);
    CHECK(sepal_horizon_window(0.0f, 0.01f) == 1.0f);
    CHECK(sepal_horizon_window(0.1f, 0.0f) == 0.0f);
    CHECK(sepal_horizon_window(0.1f, -0.5f) == 0.0f);
    CHECK(sepal_horizon_window(0.1f, NAN) == 0.0f);
    // gold-metallic-paint scatters back at grazing light: f cos(theta_i) at 89 degrees is a
    // fifth of its value at 85, a fall the factors' last texels do not make (measured 3 to
    // 10 times the truth from 88 degrees on without the window).
    const std::string spec = "nbrdf:gold-metallic-paint";
    std::string err;
    std::unique_ptr<sepal::Brdf> f = sepal::make_brdf(spec, &err);
    REQUIRE_MESSAGE(f, err);
    auto bake = [&](double horizon) {
        sepal::BakeOptions o;
        o.params = {sepal::Param::GsHalf};
        o.resolutions = {32};
        o.smooth_resolutions = {16};
        o.terms = {4};
        o.held_out = false;
        o.horizon = horizon;
        sepal::BakeResult r;
        REQUIRE_MESSAGE(sepal::bake(*f, o, &r, &err), err);
        CHECK(r.horizon == horizon);
        CHECK(r.asset.material.horizon == float(horizon));
        return r.asset;
    };
    const sepal::AssetData none = bake(0.0), windowed = bake(0.1);
    const std::vector<uint8_t> bn = encode(none), bw = encode(windowed);
    sepal_asset an{}, aw{};
    sepal_error e{};
    REQUIRE(sepal_asset_parse(bn.data(), bn.size(), &an, &e) == SEPAL_OK);
    REQUIRE(sepal_asset_parse(bw.data(), bw.size(), &aw, &e) == SEPAL_OK);
    CHECK(an.header.version_minor < SEPAL_FMT_VERSION_MINOR_HORIZON);
    // The step: |asset - f cos| summed over back, side and forward eyes at 88 to 89.5 degrees.
    double step_none = 0, step_window = 0, truth = 0;
    const double deg = 3.14159265358979 / 180;
    for (double ti : {88.0, 89.0, 89.5})
        for (double po : {0.0, 90.0, 180.0}) {
            const glm::dvec3 wi(std::sin(ti * deg), 0, std::cos(ti * deg));
            const glm::dvec3 wo(std::sin(45 * deg) * std::cos(po * deg), std::sin(45 * deg) * std::sin(po * deg),
                                std::cos(45 * deg));
            const float i[3] = {float(wi.x), float(wi.y), float(wi.z)}, o[3] = {float(wo.x), float(wo.y), float(wo.z)};
            float cn[3], cw[3];
            REQUIRE(sepal_asset_eval(&an, i, o, cn) == 1);
            REQUIRE(sepal_asset_eval(&aw, i, o, cw) == 1);
            const glm::dvec3 t = f->eval(wi, wo) * wi.z;
            for (int c = 0; c < 3; ++c) {
                step_none += std::fabs(cn[c] - t[c]);
                step_window += std::fabs(cw[c] - t[c]);
                truth += t[c];
            }
        }
    CAPTURE(step_none / truth);
    CAPTURE(step_window / truth);
    // Measured: 4.1 and 0.16 times the truth's sum.
    CHECK(step_none > truth);
    CHECK(step_window < 0.5 * truth);
    // The GL backend's per-vertex window against the CPU backend's per-pixel one, under a
    // light low over the sphere's side (a crescent ending at the horizon).
    sepal_ports::SceneSetup s = test_scene("sphere", 1);
    s.scene.lights[0] = {SEPAL_LIGHT_POINT, {4.0f, 0.5f, 1.0f}, {30.0f, 30.0f, 30.0f}};
    const sepal::Image cpu = render_cpu(windowed, s);
    CHECK(image_peak(cpu) > 0.05);
    for (int mode = 0; mode < 4; ++mode) {
        // GL ES 1.1's passes, and GL ES 2's passes, fused per vertex and per pixel (the shader's window).
        const Rendered gl = mode == 0 ? render(windowed, 0, s)
                                      : render(windowed, 0, s, nullptr, 2, sepal_draw_mode(mode - 1));
        const sepal::ImageDiff d = sepal::diff_images(cpu, gl.image, 3.0);
        CAPTURE(mode);
        CAPTURE(d.psnr);
        CAPTURE(d.share_over);
        // Measured on gles1 53.2 dB, 0.12% of pixels over 3 levels (the crescent's end drawn
        // without the window: 51.6 dB, 1.17%).
        CHECK(d.psnr > 45.0);
        CHECK(d.share_over < 0.005);
    }
    // Written as 2.7; a 2.6 header cannot hold it, nor a material a window outside (0, 1]
    // or one that is not a radiance material.
    check_version_gate(windowed, SEPAL_FMT_VERSION_MINOR_HORIZON, "horizon window needs version 2.7");
    std::vector<uint8_t> bytes;
    sepal::AssetData bad = windowed;
    bad.material.horizon = 1.5f;
    CHECK_FALSE(sepal::encode_asset(bad, &bytes, &err));
    CHECK(err.find("horizon window 1.5 outside (0, 1]") != std::string::npos);
    bad.material.horizon = 0.1f;
    bad.material.flags = 0;
    bad.material.diffuse[0] = bad.material.diffuse[1] = bad.material.diffuse[2] = 0.0f;
    err.clear();
    CHECK_FALSE(sepal::encode_asset(bad, &bytes, &err));
    CHECK(err.find("not a radiance one") != std::string::npos);
}
