// Reciprocal (homomorphic) materials, format 2.1: f = sum_k G_k(x) H_k(y) G_k(x~). The
// plan, the reader's rules, and every backend drawing the CPU backend's image: GL ES 1.1
// (two units, and the one-unit fallback forced by its mask; without blend subtract),
// GL ES 2 multipass and fused (vertex and pixel), and the GL ES emulator the bake ranks
// with against the real GL ES 1.1 render.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>

#include "bake/plan.h"
#include "common/render_gl.h"
#include "material_fixtures.h"
#include "test_util.h"

using namespace material_fx;

namespace {

// p(w): brighter towards grazing (u, v far from the centre); q(h): a lobe at the centre.
float p_tex(float u, float v, int c) {
    const float r2 = (u - 0.5f) * (u - 0.5f) + (v - 0.5f) * (v - 0.5f);
    return 0.45f + 1.5f * r2 + 0.05f * c;
}
float q_tex(float u, float v, int c) {
    const float r2 = (u - 0.5f) * (u - 0.5f) + (v - 0.5f) * (v - 0.5f);
    return 0.15f + 0.85f * std::exp(-r2 * 40.0f) * (1.0f - 0.2f * c);
}

sepal::AssetData reciprocal_asset(sepal_param param, int terms) {
    sepal::AssetData a = base_asset(param, uint32_t(terms));
    a.material.flags = SEPAL_MATERIAL_RECIPROCAL;
    a.material.map = SEPAL_MAP_PARABOLIC;
    for (int k = 0; k < terms; ++k) {
        a.textures.push_back(make_texture(32, SEPAL_ROLE_G, uint32_t(k), 1.2f - 0.4f * k, p_tex));
        a.textures.push_back(make_texture(32, SEPAL_ROLE_H, uint32_t(k), 0.8f + 0.3f * k, [k](float u, float v, int c) {
            return k ? 0.3f + 0.2f * u : q_tex(u, v, c);
        }));
    }
    std::string err;
    REQUIRE_MESSAGE(sepal::build_plan(&a, &err), err);
    return a;
}

double psnr(const sepal::Image& a, const sepal::Image& b, const std::string& name) {
    const sepal::ImageDiff d = sepal::diff_images(a, b, 3.0);
    if (d.psnr < 40) {
        sepal::write_png(sepal_test::output_dir() + "/" + name + ".png", b, nullptr);
        sepal::write_png(sepal_test::output_dir() + "/" + name + ".reference.png", a, nullptr);
    }
    return d.psnr;
}

}  // namespace

TEST_CASE("reciprocal plan: one pass per term, colour ratio sG^2 sH, values G H G") {
    sepal::AssetData a = reciprocal_asset(SEPAL_PARAM_VH, 2);
    REQUIRE(a.passes.size() == 2);
    for (const sepal_fmt_pass& p : a.passes) {
        CHECK(p.op == SEPAL_OP_RECIPROCAL);
        CHECK(p.blend == SEPAL_BLEND_ADD);
        CHECK(a.textures[p.tex0].desc.role == SEPAL_ROLE_G);
        CHECK(a.textures[p.tex1].desc.role == SEPAL_ROLE_H);
    }
    // plan_value at decoded texel values q (per texture) and q~ (G at the swapped pair).
    const double q[4] = {0.5, 0.7, 0.25, 0.9}, qs[4] = {0.8, 0.0, 0.6, 0.0};
    for (int c = 0; c < 3; ++c) {
        double want = 0;
        for (int k = 0; k < 2; ++k) {
            const auto& g = a.textures[size_t(2 * k)].desc;
            const auto& h = a.textures[size_t(2 * k + 1)].desc;
            want += g.scale[c] * q[2 * k] * h.scale[c] * q[2 * k + 1] * g.scale[c] * qs[2 * k];
        }
        CHECK(sepal::plan_value(a, q, c, qs) == doctest::Approx(want).epsilon(1e-5));
    }
    // A bias cannot be drawn in a triple product.
    a.textures[1].desc.bias[0] = -0.1f;
    std::string err;
    CHECK_FALSE(sepal::build_plan(&a, &err));
    CHECK(err.find("bias 0") != std::string::npos);
}

TEST_CASE("reciprocal asset: version 2.1 only when used; the reader's rules and bounds") {
    const sepal::AssetData a = reciprocal_asset(SEPAL_PARAM_VH, 1);
    std::vector<uint8_t> bytes = encode(a);
    auto parsed = std::make_unique<sepal_asset>();
    sepal_error e{};
    REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), parsed.get(), &e) == SEPAL_OK);
    CHECK(parsed->header.version_major == 2);
    CHECK(parsed->header.version_minor == 1);
    CHECK(parsed->material.flags == SEPAL_MATERIAL_RECIPROCAL);
    std::string err;
    // The same plan in a material without the flag: refused (the op needs the material).
    sepal::AssetData plain = a;
    plain.material.flags = 0;
    CHECK_FALSE(sepal::encode_asset(plain, &bytes, &err));
    CHECK(err.find("non-reciprocal") != std::string::npos);
    // A product plan (no reciprocal pass, its colours those of G H): stays 1.0.
    REQUIRE_MESSAGE(sepal::build_plan(&plain, &err), err);
    REQUIRE(plain.passes[0].op == SEPAL_OP_PRODUCT);
    bytes = encode(plain);
    REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), parsed.get(), &e) == SEPAL_OK);
    CHECK(parsed->header.version_major == 1);
    CHECK(parsed->header.version_minor == 0);
    sepal::AssetData bad = a;
    bad.passes[0].blend = SEPAL_BLEND_SUBTRACT;
    CHECK_FALSE(sepal::encode_asset(bad, &bytes, &err));
    CHECK(err.find("must add one term") != std::string::npos);
    bad = a;
    std::swap(bad.passes[0].tex0, bad.passes[0].tex1);
    CHECK_FALSE(sepal::encode_asset(bad, &bytes, &err));
    CHECK(err.find("must add one term") != std::string::npos);
    bad = a;
    bad.passes[0].op = SEPAL_OP_PRODUCT;
    CHECK_FALSE(sepal::encode_asset(bad, &bytes, &err));
    CHECK(err.find("in a reciprocal material") != std::string::npos);
    bad = a;
    bad.material.flags |= SEPAL_MATERIAL_RADIANCE;
    CHECK_FALSE(sepal::encode_asset(bad, &bytes, &err));
    CHECK(err.find("reciprocal material needs version 2.1") != std::string::npos);
    // Bounds: at most SEPAL_FMT_MAX_RECIPROCAL_TERMS terms, G at most 64 texels a side.
    bad = reciprocal_asset(SEPAL_PARAM_VH, SEPAL_FMT_MAX_RECIPROCAL_TERMS);
    bad.material.terms = SEPAL_FMT_MAX_RECIPROCAL_TERMS + 1;
    bad.textures.push_back(make_texture(8, SEPAL_ROLE_G, SEPAL_FMT_MAX_RECIPROCAL_TERMS, 1.0f, p_tex));
    bad.textures.push_back(make_texture(8, SEPAL_ROLE_H, SEPAL_FMT_MAX_RECIPROCAL_TERMS, 1.0f, q_tex));
    REQUIRE(sepal::build_plan(&bad, &err));
    CHECK_FALSE(sepal::encode_asset(bad, &bytes, &err));
    CHECK(err.find("at most 2 terms") != std::string::npos);
    bad = a;
    bad.textures[0] = make_texture(2 * SEPAL_FMT_MAX_RECIPROCAL_SIDE, SEPAL_ROLE_G, 0, 1.0f, p_tex);
    CHECK_FALSE(sepal::encode_asset(bad, &bytes, &err));
    CHECK(err.find("reciprocal G texture") != std::string::npos);
    // A version-2.0 header cannot hold it: patch the minor version (and the header CRC).
    bytes = encode(a);
    sepal_fmt_header h;
    memcpy(&h, bytes.data(), sizeof h);
    h.version_minor = 0;
    h.header_crc = 0;
    memcpy(bytes.data(), &h, sizeof h);
    uint32_t crc = sepal_crc32(0, bytes.data(), sizeof h);
    crc = sepal_crc32(crc, bytes.data() + sizeof h, h.chunk_count * sizeof(sepal_fmt_chunk));
    h.header_crc = crc;
    memcpy(bytes.data(), &h, sizeof h);
    CHECK(sepal_asset_parse(bytes.data(), bytes.size(), parsed.get(), &e) != SEPAL_OK);
    CHECK(std::string(e.message).find("version 2.1") != std::string::npos);
}

TEST_CASE("reciprocal material: every backend and fallback draws the CPU backend's image") {
    for (int terms : {1, 2}) {
        CAPTURE(terms);
        const sepal::AssetData a = reciprocal_asset(SEPAL_PARAM_VH, terms);
        const sepal_ports::SceneSetup s = test_scene("sphere", 2);
        const sepal::Image cpu = render_cpu(a, s);
        double lit = 0;
        for (float v : cpu.data) lit = std::max(lit, double(v));
        CHECK(lit > 0.3);  // the test lights the sphere visibly
        const std::string name = "reciprocal_x" + std::to_string(terms);
        const Rendered es1 = render(a, 0, s);
        // One two-unit pass per term and light; the first lays depth (no pre-pass).
        CHECK(es1.stats.draw_calls == terms * 2);
        const double p1 = psnr(cpu, es1.image, name + "_gles1");
        const double p1u = psnr(cpu, render(a, SEPAL_MASK_MULTITEXTURE, s).image, name + "_gles1_one_unit");
        const double p1s = psnr(cpu, render(a, SEPAL_MASK_BLEND_SUBTRACT, s).image, name + "_gles1_no_subtract");
        const double p2 = psnr(cpu, render(a, 0, s, nullptr, 2).image, name + "_gles2");
        const double pv = psnr(cpu, render(a, 0, s, nullptr, 2, SEPAL_MODE_FUSED_VERTEX).image, name + "_vertex");
        const double pp = psnr(cpu, render(a, 0, s, nullptr, 2, SEPAL_MODE_FUSED_PIXEL).image, name + "_pixel");
        MESSAGE("PSNR against cpu: gles1 " << p1 << " (one unit " << p1u << ", no subtract " << p1s
                                           << "), gles2 multipass " << p2 << ", fused vertex " << pv << ", fused pixel "
                                           << pp);
        CHECK(p1 > 38.0);
        CHECK(p1u > 36.0);
        CHECK(p1s == doctest::Approx(p1));  // nothing subtracts: the mask changes nothing
        CHECK(p2 > 38.0);
        CHECK(pv > 38.0);
        CHECK(pp > 40.0);
    }
}

TEST_CASE("reciprocal material: the GL ES emulator matches GL ES 1.1 and 2; iv is drawn too") {
    for (sepal_param param : {SEPAL_PARAM_VH, SEPAL_PARAM_IV}) {
        CAPTURE(int(param));
        const std::vector<uint8_t> bytes = encode(reciprocal_asset(param, 2));
        const sepal_ports::SceneSetup s = test_scene("sphere", 2);
        for (int version : {1, 2}) {
            CAPTURE(version);
            sepal_ports::GlRenderOptions opt;
            opt.gles_version = version;
            std::vector<uint8_t> real, emu;
            sepal_ports::GlRenderInfo info;
            std::string err;
            REQUIRE_MESSAGE(sepal_ports::render_asset_headless(bytes.data(), bytes.size(), s, opt, &real, &info, &err), err);
            REQUIRE_MESSAGE(sepal_ports::render_asset_emulated(bytes.data(), bytes.size(), s, version, 0, &emu, &err), err);
            const sepal::ImageDiff d = sepal::diff_images(sepal::to_rgb(sepal::image_from_rgba8(real.data(), s.width, s.height)),
                                                          sepal::to_rgb(sepal::image_from_rgba8(emu.data(), s.width, s.height)), 8);
            CAPTURE(d.psnr);
            CHECK(d.psnr >= 45.0);
            CHECK(d.share_over <= 0.001);
        }
    }
}
