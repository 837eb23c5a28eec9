// Device profiles (offline/bake/devices.h) and bakes judged on one (bake.h's profile): the
// table, a bake for the 64-texel profile, and the runtime's weaker-context counter on the
// real RGB565 pbuffer for assets baked for 8888 and for 565.
#include <doctest/doctest.h>

#include <memory>
#include <set>
#include <string>
#include <vector>

#include "bake/bake.h"
#include "bake/devices.h"
#include "common/render_gl.h"
#include "spec/spec.h"
#include "test_util.h"
#include "util/io.h"

namespace {

// A small search (one parameterization, up to two terms, small judged images, no held-out
// stage): the profile's effects, not the image, are under test here.
sepal::AssetData bake_for(const std::string& profile, int64_t* bytes_out = nullptr) {
    sepal::BakeOptions o;
    o.params = {sepal::Param::GsHalf};
    o.terms = {1, 2};
    o.judge_size = 32;
    o.held_out = false;
    o.profile = profile;
    std::string err;
    std::unique_ptr<sepal::Brdf> f = sepal::make_brdf("ward:rho_d=0.4,rho_s=0.5,ax=0.4,ay=0.15", &err);
    REQUIRE_MESSAGE(f, err);
    sepal::BakeResult r;
    REQUIRE_MESSAGE(sepal::bake(*f, o, &r, &err), err);
    if (bytes_out) *bytes_out = r.candidates[size_t(r.winner)].bytes;
    return r.asset;
}

sepal_draw_stats draw_on(const std::vector<uint8_t>& bytes, int framebuffer) {
    sepal_ports::SceneSetup setup;
    setup.width = setup.height = 32;
    std::string err;
    REQUIRE_MESSAGE(sepal_ports::load_scene_mesh(&setup, &err), err);
    sepal_ports::GlRenderOptions opt;
    opt.framebuffer = framebuffer;
    std::vector<uint8_t> rgba;
    sepal_ports::GlRenderInfo info;
    REQUIRE_MESSAGE(sepal_ports::render_asset_headless(bytes.data(), bytes.size(), setup, opt, &rgba, &info, &err), err);
    return info.stats;
}

}  // namespace

TEST_CASE("devices: one row per family, each with a source; default is today's 8-bit bake") {
    const std::vector<sepal::DeviceProfile>& all = sepal::device_profiles();
    REQUIRE(all.size() >= 7);
    CHECK(std::string(all.front().name) == "default");
    std::set<std::string> names;
    for (const sepal::DeviceProfile& p : all) {
        CAPTURE(p.name);
        CHECK(names.insert(p.name).second);
        CHECK(std::string(p.source).size() > 4);
        CHECK(sepal::find_device_profile(p.name) == &p);
        const sepal::ProfileLimits l = sepal::profile_limits(p);
        CHECK(l.texture_limit <= sepal::kBakeMaxTexture);
        CHECK(l.texture_units == 2);
        const sepal_fmt_profile rec = sepal::profile_record(p);
        CHECK(std::string(rec.name) == p.name);
    }
    for (const char* family : {"mali400", "adreno200", "sgx530", "videocore4", "tegra2", "gles1-minimum"})
        CHECK(sepal::find_device_profile(family) != nullptr);
    const sepal::ProfileLimits d = sepal::profile_limits(sepal::default_device_profile());
    CHECK(d.bits[0] == 8);
    CHECK(d.bits[1] == 8);
    CHECK(d.bits[2] == 8);
    CHECK(d.blend_subtract);
    CHECK(sepal::find_device_profile("mali-400") == nullptr);
}

TEST_CASE("devices: a bake for the 64-texel profile keeps every texture at or under 64 and records it; the "
          "counter: an 8888 asset on the RGB565 pbuffer counts a weaker context, a 565 one does not") {
    const sepal::AssetData small = bake_for("gles1-minimum");
    REQUIRE_FALSE(small.textures.empty());
    for (const sepal::AssetTexture& t : small.textures) {
        CHECK(t.desc.width <= 64);
        CHECK(t.desc.height <= 64);
    }
    CHECK(small.has_profile);
    CHECK(std::string(small.profile.name) == "gles1-minimum");
    CHECK(small.profile.red_bits == 5);
    CHECK(small.profile.green_bits == 6);
    CHECK(small.profile.max_texture_size == 64);
    CHECK(small.meta.find("\"target\":\"gles1:gles1-minimum\"") != std::string::npos);
    // The default bake records nothing: no PROF chunk, its META's target plain gles1.
    const sepal::AssetData full = bake_for("");
    CHECK_FALSE(full.has_profile);
    CHECK(full.meta.find("\"target\":\"gles1\"") != std::string::npos);
    std::vector<uint8_t> bytes_565, bytes_8888;
    std::string err;
    REQUIRE_MESSAGE(sepal::encode_asset(small, &bytes_565, &err), err);
    REQUIRE_MESSAGE(sepal::encode_asset(full, &bytes_8888, &err), err);
    CHECK(draw_on(bytes_8888, 565).weaker_context == 1);
    CHECK(draw_on(bytes_8888, 8888).weaker_context == 0);
    CHECK(draw_on(bytes_565, 565).weaker_context == 0);
    // --res over the profile's limit is refused, naming both.
    sepal::BakeOptions o;
    o.profile = "gles1-minimum";
    o.resolutions = {128};
    std::unique_ptr<sepal::Brdf> f = sepal::make_brdf("ward:rho_d=0.4,rho_s=0.5,ax=0.4,ay=0.15", &err);
    REQUIRE(f);
    sepal::BakeResult r;
    CHECK_FALSE(sepal::bake(*f, o, &r, &err));
    CHECK(err.find("--res 128 is over profile gles1-minimum's texture limit 64") != std::string::npos);
}

TEST_CASE("devices: docs/devices.md's table is the profiles' table, figure for figure") {
    std::vector<uint8_t> bytes;
    const std::string path = sepal_test::source_path("docs/devices.md");
    REQUIRE(sepal::read_file(path, &bytes, nullptr));
    const std::string text(bytes.begin(), bytes.end());
    const auto shown = [](int v) { return v == sepal::kUnknown ? std::string("?") : std::to_string(v); };
    const auto yes_no = [](int v) { return v == sepal::kUnknown ? std::string("?") : v ? std::string("yes") : std::string("no"); };
    const auto or_unknown = [](const char* s) { return std::string(s) == "unknown" ? std::string("?") : std::string(s); };
    size_t rows = 0;
    for (const sepal::DeviceProfile& p : sepal::device_profiles()) {
        CAPTURE(p.name);
        const std::string start = std::string("| `") + p.name + "` |";
        const size_t at = text.find(start);
        REQUIRE(at != std::string::npos);
        std::vector<std::string> cells;
        size_t i = at + 1;
        const size_t end = text.find('\n', at);
        while (i < end) {
            const size_t bar = text.find('|', i);
            if (bar == std::string::npos || bar > end) break;
            std::string c = text.substr(i, bar - i);
            c.erase(0, c.find_first_not_of(' '));
            c.erase(c.find_last_not_of(' ') + 1);
            cells.push_back(c);
            i = bar + 1;
        }
        REQUIRE(cells.size() == 10);
        CHECK(cells[2].rfind(std::to_string(p.red_bits) + "/" + std::to_string(p.green_bits) + "/" + std::to_string(p.blue_bits), 0) == 0);
        CHECK(cells[3] == shown(p.texture_units));
        CHECK(cells[4] == shown(p.max_texture_size));
        CHECK(cells[6] == yes_no(p.blend_subtract));
        CHECK(cells[7] == yes_no(p.fbo));
        if (std::string(p.name) != "default") {  // its family, NPOT, formats and throughput: in words
            CHECK(cells[1] == p.family);
            CHECK(cells[5] == yes_no(p.npot));
            CHECK(cells[8] == or_unknown(p.compressed));
            CHECK(cells[9] == or_unknown(p.throughput));
        }
        ++rows;
    }
    CHECK(rows == sepal::device_profiles().size());
}

TEST_CASE("devices: with framebuffer objects a 565 profile ranks on the 8-bit sum; without them every pass rounds") {
    // The runtime sums the passes in an 8-bit target and writes the sum to the 5/6/5
    // framebuffer once: that rounding is every candidate's, so mali400 (framebuffer objects)
    // ranks as the default profile does (same figures, same winner), and reports its held-out
    // figure on 5/6/5.
    // gles1-minimum (none) rounds every pass, which the plans decide.
    std::string err;
    std::unique_ptr<sepal::Brdf> f = sepal::make_brdf("blinn", &err);
    REQUIRE_MESSAGE(f, err);
    auto bake = [&](const char* profile) {
        sepal::BakeOptions o;
        o.params = {sepal::Param::GsHalf};
        o.resolutions = {16};
        o.terms = {1, 2};
        o.judge_size = 32;
        o.profile = profile;
        sepal::BakeResult r;
        REQUIRE_MESSAGE(sepal::bake(*f, o, &r, &err), err);
        return r;
    };
    const sepal::BakeResult def = bake("default"), mali = bake("mali400"), minimum = bake("gles1-minimum");
    REQUIRE(def.candidates.size() == mali.candidates.size());
    REQUIRE(def.candidates.size() == minimum.candidates.size());
    bool minimum_differs = false;
    for (size_t i = 0; i < def.candidates.size(); ++i) {
        CAPTURE(i);
        CHECK(mali.candidates[i].psnr == def.candidates[i].psnr);
        minimum_differs = minimum_differs || minimum.candidates[i].psnr < def.candidates[i].psnr - 0.5;
    }
    CHECK(minimum_differs);
    CHECK(mali.winner == def.winner);
    CHECK(mali.held_out_psnr != def.held_out_psnr);  // the device's 5/6/5 frame
}
