// Image-first baking's pieces that need no GL context (docs/fidelity.md): format 2 (radiance materials, the diffuse part
// and its profile) written and refused, the radiance fit and the diffuse estimates, the image
// judge, and the bake's command line for them. The GL comparisons are tests/ports/emulate_test.cpp.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <memory>

#include "bake/asset_file.h"
#include "bake/bake.h"
#include "bake/image_score.h"
#include "bake/radiance.h"
#include "cli/cli.h"
#include "fuzz/fuzz.h"
#include "util/io.h"
#include "util/parallel.h"
#include "sepal/sepal_asset.h"
#include "spec/spec.h"
#include "test_util.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

std::unique_ptr<sepal::Brdf> brdf(const std::string& spec) {
    std::string err;
    std::unique_ptr<sepal::Brdf> f = sepal::make_brdf(spec, &err);
    REQUIRE_MESSAGE(f, err);
    return f;
}

// A 1-term radiance asset: 2x2 zero textures, the DIFFUSE pass, optionally a profile.
sepal::AssetData radiance_asset(bool profile) {
    sepal::AssetData a;
    a.material.param = SEPAL_PARAM_GS_HALF;
    a.material.map = SEPAL_MAP_XY;
    a.material.terms = 1;
    a.material.channels = 3;
    a.material.ratio[0] = a.material.ratio[1] = a.material.ratio[2] = 1.0f;
    a.material.flags = SEPAL_MATERIAL_RADIANCE;
    a.material.diffuse[0] = 0.2f, a.material.diffuse[1] = 0.1f, a.material.diffuse[2] = 0.05f;
    for (uint32_t role = 0; role < 2; ++role) {
        sepal::AssetTexture t;
        t.desc.width = t.desc.height = 2;
        t.desc.levels = 1;
        t.desc.channels = 3;
        t.desc.bits = 8;
        t.desc.role = role;
        t.data.assign(12, 0);
        a.textures.push_back(t);
    }
    a.plan.peak_partial_sum = 0.2f;
    sepal_fmt_pass p{};
    p.op = SEPAL_OP_DIFFUSE;
    p.blend = SEPAL_BLEND_ADD;
    p.tex0 = p.tex1 = SEPAL_FMT_NO_TEXTURE;
    for (int c = 0; c < 3; ++c) p.color[c] = a.material.diffuse[c];
    p.rgb_scale = 1;
    a.passes.push_back(p);
    if (profile) {
        a.diffuse_side = 4;
        for (int k = 0; k < 4 * 4 * 3; ++k) a.diffuse_profile.push_back(float(k % 7) / 6.0f);
    }
    return a;
}

std::string refusal(const sepal::AssetData& a) {
    std::vector<uint8_t> bytes;
    std::string err;
    CHECK_FALSE(sepal::encode_asset(a, &bytes, &err));
    return err;
}

}  // namespace

TEST_CASE("format 2: radiance materials, the diffuse part and its profile round-trip; version 1 stays 1.0") {
    for (bool profile : {false, true}) {
        CAPTURE(profile);
        const sepal::AssetData a = radiance_asset(profile);
        std::vector<uint8_t> bytes;
        std::string err;
        REQUIRE_MESSAGE(sepal::encode_asset(a, &bytes, &err), err);
        auto parsed = std::make_unique<sepal_asset>();
        sepal_error e{};
        REQUIRE_MESSAGE(sepal_asset_parse(bytes.data(), bytes.size(), parsed.get(), &e) == SEPAL_OK, e.message);
        CHECK(parsed->header.version_major == 2);
        CHECK(parsed->material.flags == SEPAL_MATERIAL_RADIANCE);
        CHECK(parsed->material.diffuse[1] == 0.1f);
        CHECK(parsed->diffuse_side == (profile ? 4u : 0u));
        CHECK((parsed->diffuse_profile != nullptr) == profile);
        // The lookup: nodes exactly (to the 16 bits stored: 2.5), bilinear between them, 1
        // without a profile.
        if (profile) {
            CHECK(parsed->header.version_minor == SEPAL_FMT_VERSION_MINOR_DIFFUSE16);
            CHECK(parsed->diffuse_layout == SEPAL_FMT_DIFFUSE_RGB_U16);  // its channels differ
            const uint32_t l = parsed->diffuse_layout;
            CHECK(std::fabs(sepal_diffuse_profile(parsed->diffuse_profile, 4, l, 1.0f / 3.0f, 0.0f, 2) -
                            a.diffuse_profile[5]) <= 0.5f / 65535.0f + 1e-7f);
            const float mid = sepal_diffuse_profile(parsed->diffuse_profile, 4, l, 0.5f, 0.0f, 0);
            CHECK(mid == doctest::Approx(0.5 * (a.diffuse_profile[3] + a.diffuse_profile[6])).epsilon(1e-4));
        } else {
            CHECK(sepal_diffuse_profile(nullptr, 0, SEPAL_FMT_DIFFUSE_RGB_U16, 0.3f, 0.7f, 1) == 1.0f);
        }
    }
    // Without version-2 features the writer writes 1.0 (earlier assets stay byte-identical).
    sepal::AssetData v1 = radiance_asset(false);
    v1.material.flags = 0;
    v1.material.diffuse[0] = v1.material.diffuse[1] = v1.material.diffuse[2] = 0.0f;
    v1.passes[0].op = SEPAL_OP_CONSTANT;
    for (float& c : v1.passes[0].color) c = 0.0f;  // what the factors (all 0) and no diffuse part say
    CHECK_FALSE(sepal::asset_needs_version2(v1));
    std::vector<uint8_t> bytes;
    std::string err;
    REQUIRE_MESSAGE(sepal::encode_asset(v1, &bytes, &err), err);
    uint16_t major = 0;
    std::memcpy(&major, bytes.data() + 8, 2);
    CHECK(major == 1);
}

TEST_CASE("format 2.5: a grey diffuse profile is stored once in 16 bits, an RGB one per channel; 2.0's floats still read") {
    // Grey: 16 + 4 x 4 x 2 bytes of DIFF payload (floats took 16 + 4 x 4 x 12), read back as
    // the writer's values q / 65535, the bake's own rounding (diffuse_u16_value).
    sepal::AssetData a = radiance_asset(true);
    for (size_t k = 0; k < a.diffuse_profile.size(); ++k)
        a.diffuse_profile[k] = sepal::diffuse_u16_value(uint16_t(1000 * (k / 3) + 7));
    std::vector<uint8_t> grey, rgb;
    std::string err;
    REQUIRE_MESSAGE(sepal::encode_asset(a, &grey, &err), err);
    a.diffuse_profile[4] = sepal::diffuse_u16_value(3);  // one channel of one sample differs
    REQUIRE_MESSAGE(sepal::encode_asset(a, &rgb, &err), err);
    CHECK(rgb.size() - grey.size() == 4 * 4 * 4);  // 6 bytes a sample instead of 2, 8-byte aligned
    auto parsed = std::make_unique<sepal_asset>();
    sepal_error e{};
    REQUIRE(sepal_asset_parse(grey.data(), grey.size(), parsed.get(), &e) == SEPAL_OK);
    CHECK(parsed->diffuse_layout == SEPAL_FMT_DIFFUSE_GREY_U16);
    for (int c = 0; c < 3; ++c)  // node (1, 2): sample 9
        CHECK(sepal_diffuse_profile(parsed->diffuse_profile, 4, parsed->diffuse_layout, 1.0f / 3.0f, 2.0f / 3.0f, c) ==
              sepal::diffuse_u16_value(9007));
    REQUIRE(sepal_asset_parse(rgb.data(), rgb.size(), parsed.get(), &e) == SEPAL_OK);
    CHECK(parsed->diffuse_layout == SEPAL_FMT_DIFFUSE_RGB_U16);
    CHECK(sepal_diffuse_profile(parsed->diffuse_profile, 4, parsed->diffuse_layout, 1.0f / 3.0f, 0.0f, 1) ==
          sepal::diffuse_u16_value(3));

    // A 16-bit layout in a 2.4 header, or an unknown layout, is refused by name (the grey
    // file patched, its checksums fixed so the field checks behind them are reached).
    auto patched = [&](uint16_t minor, uint32_t layout) {
        std::vector<uint8_t> b = grey;
        std::memcpy(b.data() + 10, &minor, 2);
        const sepal_fmt_header* h = reinterpret_cast<const sepal_fmt_header*>(b.data());
        for (uint32_t i = 0; i < h->chunk_count; ++i) {
            sepal_fmt_chunk c;
            std::memcpy(&c, b.data() + sizeof(sepal_fmt_header) + i * sizeof c, sizeof c);
            if (c.tag == SEPAL_FMT_TAG_DIFFUSE) std::memcpy(b.data() + c.offset + 4, &layout, 4);
        }
        sepal_fuzz::fix_asset_checksums(&b);
        sepal_error pe{};
        auto out = std::make_unique<sepal_asset>();
        CHECK(sepal_asset_parse(b.data(), b.size(), out.get(), &pe) != SEPAL_OK);
        return std::string(pe.message);
    };
    CHECK(patched(SEPAL_FMT_VERSION_MINOR_PROFILE, SEPAL_FMT_DIFFUSE_GREY_U16).find("layout 2") != std::string::npos);
    CHECK(patched(SEPAL_FMT_VERSION_MINOR_DIFFUSE16, 7).find("layout 7") != std::string::npos);

    // 2.0 assets (RGB floats) read as they always did.
    std::vector<uint8_t> old;
    REQUIRE(sepal::read_file(sepal_test::source_path("fixtures/fuzz-seeds/asset/ct_rus.sepal"), &old, &err));
    REQUIRE_MESSAGE(sepal_asset_parse(old.data(), old.size(), parsed.get(), &e) == SEPAL_OK, e.message);
    CHECK(parsed->header.version_minor == 0);
    CHECK(parsed->diffuse_layout == SEPAL_FMT_DIFFUSE_RGB_F32);
    float first;
    std::memcpy(&first, parsed->diffuse_profile, 4);
    CHECK(sepal_diffuse_profile(parsed->diffuse_profile, parsed->diffuse_side, parsed->diffuse_layout, 0.0f, 0.0f, 0) ==
          first);
}

TEST_CASE("format 2: the reader refuses inconsistent radiance materials, naming the problem") {
    sepal::AssetData a = radiance_asset(true);
    a.material.flags = 0x80;
    CHECK(refusal(a).find("unknown material flags") != std::string::npos);
    a = radiance_asset(false);
    a.material.diffuse[2] = -0.1f;
    CHECK(refusal(a).find("diffuse") != std::string::npos);
    a = radiance_asset(false);
    a.passes[0].blend = SEPAL_BLEND_SUBTRACT;
    CHECK(refusal(a).find("subtracts the diffuse part") != std::string::npos);
    a = radiance_asset(false);
    a.passes[0].op = SEPAL_OP_CONSTANT;  // a diffuse part with no DIFFUSE pass
    CHECK(refusal(a).find("DIFFUSE passes") != std::string::npos);
    a = radiance_asset(false);
    a.passes[0].op = SEPAL_OP_RECIPROCAL;  // only in reciprocal materials (format 2.1)
    CHECK(refusal(a).find("op 3 in a non-reciprocal material") != std::string::npos);
    a = radiance_asset(false);
    a.passes[0].op = SEPAL_OP_COUNT;
    CHECK(refusal(a).find("unknown op 5") != std::string::npos);
    a = radiance_asset(true);
    a.diffuse_profile[5] = 1.5f;
    CHECK(refusal(a).find("outside [0,1]") != std::string::npos);
    a = radiance_asset(true);
    a.diffuse_side = 40;
    a.diffuse_profile.resize(40 * 40 * 3, 0.5f);
    CHECK(refusal(a).find("diffuse profile of side 40") != std::string::npos);
    a = radiance_asset(true);
    a.material.diffuse[0] = a.material.diffuse[1] = a.material.diffuse[2] = 0.0f;
    a.passes[0].op = SEPAL_OP_CONSTANT;
    CHECK(refusal(a).find("profile without a diffuse part") != std::string::npos);
}

TEST_CASE("radiance fit: f cos capped at white, minus the diffuse part, never negative; counted") {
    const auto ward = brdf("ward:rho_d=0.4,rho_s=0.5,ax=0.4,ay=0.15");
    sepal::RadianceTarget t;
    t.white = 0.4;
    t.diffuse.scale = glm::dvec3(0.4 / kPi);
    const sepal::RadianceBrdf g(*ward, t);
    sepal::SplitMix64 rng(7);
    auto dir = [&]() {
        const double z = rng.uniform(), phi = 2 * kPi * rng.uniform(), r = std::sqrt(1 - z * z);
        return glm::dvec3(r * std::cos(phi), r * std::sin(phi), z);
    };
    for (int k = 0; k < 2000; ++k) {
        const glm::dvec3 wi = dir(), wo = dir();
        const glm::dvec3 f = ward->eval(wi, wo), v = g.eval(wi, wo);
        for (int c = 0; c < 3; ++c) {
            const double want = std::max(0.0, std::min(f[c] * wi.z, 0.4) - 0.4 / kPi * wi.z);
            CHECK(v[c] == doctest::Approx(want).epsilon(1e-12));
        }
    }
    CHECK(g.evaluations() == 2000);
    CHECK(g.capped() > 0);   // the highlight
    CHECK(g.floored() == 0);  // rho_d / pi is Ward's floor
    CHECK(g.eval(glm::dvec3(0, 0, -1), glm::dvec3(0, 0, 1)) == glm::dvec3(0));
}

TEST_CASE("diffuse part: Ward's floor is rho_d / pi, Ashikhmin-Shirley's a profile at or below f") {
    const sepal::DiffusePart w = sepal::estimate_diffuse_profile(*brdf("ward:rho_d=0.3/0.2/0.1"));
    CHECK(w.side == 0);  // flat: a constant
    CHECK(w.scale.x == doctest::Approx(0.3 / kPi).epsilon(1e-3));
    CHECK(w.scale.z == doctest::Approx(0.1 / kPi).epsilon(1e-3));
    CHECK(sepal::estimate_diffuse(*brdf("ward:rho_d=0.3")).x == doctest::Approx(0.3 / kPi).epsilon(1e-3));
    const auto as = brdf("ashikhmin-shirley");
    const sepal::DiffusePart d = sepal::estimate_diffuse_profile(*as);
    REQUIRE(d.side == 16);
    // Lambert-like in the middle, falling towards grazing: the profile varies.
    CHECK(d.eval(0, 1.0, 1.0) > 3 * d.eval(0, 0.05, 0.05));
    // At or below f everywhere (the residual the factors fit stays non-negative).
    sepal::SplitMix64 rng(3);
    int above = 0;
    double worst = 0;
    for (int k = 0; k < 5000; ++k) {
        const double zi = 0.02 + 0.98 * rng.uniform(), zo = 0.02 + 0.98 * rng.uniform();
        const double pi = 2 * kPi * rng.uniform(), po = 2 * kPi * rng.uniform();
        const glm::dvec3 wi(std::sqrt(1 - zi * zi) * std::cos(pi), std::sqrt(1 - zi * zi) * std::sin(pi), zi);
        const glm::dvec3 wo(std::sqrt(1 - zo * zo) * std::cos(po), std::sqrt(1 - zo * zo) * std::sin(po), zo);
        const double ratio = d.eval(1, zi, zo) / as->eval(wi, wo).y;
        worst = std::max(worst, ratio);
        above += ratio > 1 + 1e-3;
    }
    CAPTURE(worst);
    CHECK(above == 0);
}

TEST_CASE("image judge: a Lambert material is its diffuse pass, exact on every target") {
    const auto lambert = brdf("lambert:rho=0.6");
    sepal::BakeOptions o;
    o.params = {sepal::Param::GsHalf};
    o.resolutions = {4};
    o.terms = {1};
    o.judge_size = 64;
    for (sepal::Target t : {sepal::Target::Gles1, sepal::Target::Gles2, sepal::Target::Cpu}) {
        CAPTURE(sepal::target_name(t));
        o.target = t;
        sepal::BakeResult r;
        std::string err;
        REQUIRE_MESSAGE(sepal::bake(*lambert, o, &r, &err), err);
        CHECK(r.diffuse.scale.x == doctest::Approx(0.6 / kPi).epsilon(1e-3));
        const sepal::BakeCandidate& w = r.candidates[size_t(r.winner)];
        // The CPU backend is exact; GL ES draws the cosine per vertex (Gouraud on the
        // judge's 64 x 32 sphere at 64 x 64 pixels: measured 42.7 dB).
        CHECK(w.psnr >= (t == sepal::Target::Cpu ? 50.0 : 41.0));
        CHECK(r.asset.material.flags == SEPAL_MATERIAL_RADIANCE);
        REQUIRE(r.views.size() == 5);  // the default light range's training conditions
        CHECK(w.psnr_views.size() == 5);
    }
}

TEST_CASE("sepal bake: --target, --white, --fit, --min-psnr; the candidate table shows PSNR first") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    const std::vector<std::string> base = {"blinn:n=50", "--param", "gs-half", "--res", "16", "--terms", "1,2",
                                           "--judge-size", "32"};
    auto args = [&](std::vector<std::string> extra) {
        std::vector<std::string> a = base;
        a.insert(a.end(), extra.begin(), extra.end());
        return a;
    };
    REQUIRE(sepal_test::run_cmd("bake", args({"-o", dir + "/a.sepal", "--target", "cpu"}), &out) == 0);
    CHECK(out.find("PSNR dB worst dB err quant") != std::string::npos);
    CHECK(out.find("on cpu against the exact render") != std::string::npos);
    REQUIRE(sepal_test::run_cmd("bake", args({"-o", dir + "/b.sepal", "--white", "none"}), &out) == 0);
    CHECK(out.find("not capped") != std::string::npos);
    REQUIRE(sepal_test::run_cmd("bake", args({"-o", dir + "/c.sepal", "--fit", "brdf"}), &out) == 0);
    REQUIRE(sepal_test::run_cmd("inspect", {dir + "/c.sepal"}, &out) == 0);
    CHECK(out.find("format 1.0") != std::string::npos);
    REQUIRE(sepal_test::run_cmd("inspect", {dir + "/a.sepal"}, &out) == 0);
    CHECK(out.find("format 2.5") != std::string::npos);  // the light range (2.3) and a 16-bit diffuse profile (2.5)
    CHECK(out.find("lights      holds for irradiance") != std::string::npos);
    CHECK(out.find("image       held-out") != std::string::npos);
    CHECK(out.find("diffuse") != std::string::npos);
    // A PSNR no candidate reaches is refused, naming the best image.
    CHECK(sepal_test::run_cmd("bake", args({"-o", dir + "/d.sepal", "--min-psnr", "90"}), &out) == 2);
    CHECK(out.find("best image") != std::string::npos);
    for (const std::vector<std::string>& bad : {std::vector<std::string>{"--target", "vulkan"},
                                                {"--white", "-1"}, {"--fit", "f"}, {"--min-psnr", "0"}}) {
        CAPTURE(bad[0]);
        CHECK(sepal_test::run_cmd("bake", args({"-o", dir + "/e.sepal", bad[0], bad[1]}), &out) == 2);
    }
}
