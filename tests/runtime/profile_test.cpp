// The device profile an asset was judged for (format 2.4's PROF chunk) and
// sepal_profile_check (runtime/src/profile.cpp): what the reader fills without the chunk,
// what it refuses, and what of a context the check calls weaker.
#include <doctest/doctest.h>

#include <cstring>
#include <memory>
#include <string>

#include "bake/asset_file.h"
#include "material_fixtures.h"
#include "sepal/sepal_material.h"

namespace {

sepal_fmt_profile profile(const char* name, uint32_t r, uint32_t g, uint32_t b, uint32_t limit, uint32_t flags) {
    sepal_fmt_profile p{};
    std::strncpy(p.name, name, sizeof p.name - 1);
    p.red_bits = r, p.green_bits = g, p.blue_bits = b;
    p.texture_units = 2;
    p.max_texture_size = limit;
    p.flags = flags;
    return p;
}

sepal_caps caps(int r, int g, int b) {
    sepal_caps c = {};
    c.gles_version = 1;
    c.texture_units = 2;
    c.max_texture_size = 2048;
    c.has_blend_subtract = 1;
    c.red_bits = r, c.green_bits = g, c.blue_bits = b;
    return c;
}

bool contains(const char* s, const char* part) { return std::strstr(s, part) != nullptr; }

}  // namespace

TEST_CASE("profile: without PROF an asset reads as judged for the default profile; with it, 2.4 round-trips") {
    const sepal::AssetData a = material_fx::signed_asset();  // 16x16 textures, subtracting passes
    std::vector<uint8_t> bytes = material_fx::encode(a);
    auto asset = std::make_unique<sepal_asset>();
    sepal_error e = {};
    REQUIRE_MESSAGE(sepal_asset_parse(bytes.data(), bytes.size(), asset.get(), &e) == SEPAL_OK, e.message);
    CHECK(asset->has_profile == 0);
    CHECK(std::string(asset->profile.name) == "default");
    CHECK(asset->profile.red_bits == 8);
    CHECK(asset->profile.green_bits == 8);
    CHECK(asset->profile.blue_bits == 8);
    CHECK(asset->profile.texture_units == 2);
    CHECK(asset->profile.max_texture_size == 16);  // its own largest texture
    CHECK(asset->profile.flags == SEPAL_PROFILE_BLEND_SUBTRACT);
    CHECK(asset->header.version_minor < SEPAL_FMT_VERSION_MINOR_PROFILE);
    sepal::AssetData p = a;
    p.has_profile = true;
    p.profile = profile("mali400", 5, 6, 5, 64, 0);
    bytes = material_fx::encode(p);
    REQUIRE_MESSAGE(sepal_asset_parse(bytes.data(), bytes.size(), asset.get(), &e) == SEPAL_OK, e.message);
    CHECK(asset->header.version_major == 2);
    CHECK(asset->header.version_minor == SEPAL_FMT_VERSION_MINOR_PROFILE);
    CHECK(asset->has_profile == 1);
    CHECK(std::memcmp(&asset->profile, &p.profile, sizeof p.profile) == 0);
    // What the reader refuses (and so the writer, which parses what it wrote).
    std::string err;
    const struct {
        sepal_fmt_profile prof;
        const char* message;
    } bad[] = {{profile("mali400", 5, 6, 5, 8, 0), "over its profile mali400's limit 8"},
               {profile("Mali", 5, 6, 5, 64, 0), "name is not 1..15 characters"},
               {profile("", 5, 6, 5, 64, 0), "name is not 1..15 characters"},
               {profile("x", 9, 6, 5, 64, 0), "9 framebuffer bits"},
               {profile("x", 5, 6, 5, 48, 0), "texture limit 48"},
               {profile("x", 5, 6, 5, 64, 2), "unknown flags"}};
    for (const auto& b : bad) {
        CAPTURE(b.message);
        p.profile = b.prof;
        CHECK_FALSE(sepal::encode_asset(p, &bytes, &err));
        CHECK(err.find(b.message) != std::string::npos);
    }
}

TEST_CASE("profile: sepal_profile_check names what of the context is weaker than the asset's profile") {
    sepal::AssetData a = material_fx::signed_asset();
    std::vector<uint8_t> bytes = material_fx::encode(a);
    auto asset = std::make_unique<sepal_asset>();
    sepal_error e = {};
    REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), asset.get(), &e) == SEPAL_OK);
    uint32_t weaker = 99;
    sepal_caps c = caps(8, 8, 8);
    CHECK(sepal_profile_check(&c, asset.get(), &weaker, &e) == SEPAL_OK);
    CHECK(weaker == 0);
    c = caps(0, 0, 0);  // not reported: not weaker
    CHECK(sepal_profile_check(&c, asset.get(), &weaker, &e) == SEPAL_OK);
    c = caps(5, 6, 5);
    CHECK(sepal_profile_check(&c, asset.get(), &weaker, &e) == SEPAL_ERR_UNSUPPORTED);
    CHECK(weaker == SEPAL_WEAKER_BITS);
    CHECK(contains(e.message, "weaker than the device profile 'default'"));
    CHECK(contains(e.message, "framebuffer 5/6/5 bits (the profile's 8/8/8)"));
    c = caps(8, 8, 8);
    c.max_texture_size = 8;
    c.texture_units = 1;
    c.has_blend_subtract = 0;
    CHECK(sepal_profile_check(&c, asset.get(), &weaker, &e) == SEPAL_ERR_UNSUPPORTED);
    CHECK(weaker == (SEPAL_WEAKER_TEXTURE_SIZE | SEPAL_WEAKER_UNITS | SEPAL_WEAKER_SUBTRACT));
    CHECK(contains(e.message, "texture limit 8 (the profile's 16)"));
    CHECK(contains(e.message, "1 texture unit (the profile's 2)"));
    CHECK(contains(e.message, "no blend subtraction"));
    // Judged on 5/6/5 without subtraction: a 565 context without it holds it, an 8888 one too.
    a.has_profile = true;
    a.profile = profile("gles1-minimum", 5, 6, 5, 16, 0);
    bytes = material_fx::encode(a);
    REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), asset.get(), &e) == SEPAL_OK);
    for (int bits : {565, 888}) {
        CAPTURE(bits);
        c = bits == 565 ? caps(5, 6, 5) : caps(8, 8, 8);
        c.has_blend_subtract = 0;
        CHECK(sepal_profile_check(&c, asset.get(), &weaker, &e) == SEPAL_OK);
        CHECK(weaker == 0);
    }
    c = caps(4, 4, 4);
    CHECK(sepal_profile_check(&c, asset.get(), &weaker, &e) == SEPAL_ERR_UNSUPPORTED);
    CHECK(contains(e.message, "'gles1-minimum'"));
    CHECK(sepal_profile_check(nullptr, asset.get(), &weaker, &e) == SEPAL_ERR_INVALID_ARGUMENT);
}
