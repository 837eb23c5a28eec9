// Device profiles (offline/bake/devices.h) and bakes judged on one (bake.h's profile): the
// table, a bake for the 64-texel profile, and the runtime's weaker-context counter on the
// real RGB565 pbuffer for assets baked for 8888 and for 565.
#include <doctest/doctest.h>

#include <memory>
#include <set>
#include <string>

#include "bake/bake.h"
#include "bake/devices.h"
#include "common/render_gl.h"
#include "spec/spec.h"
#include "test_util.h"

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
