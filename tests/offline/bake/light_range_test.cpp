// The light range (offline/bake/light_range.h, format 2.3): training and held-out
// conditions, the header fields and older assets, the runtime's dim-light counter and
// `sepal render`'s warning, and a coloured light's highlight hue.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <tuple>

#include "bake/asset_file.h"
#include "bake/bake.h"
#include "bake/light_range.h"
#include "common/render_gl.h"
#include "common/scene_flags.h"
#include "reference/render_exact.h"
#include "sepal/sepal_asset.h"
#include "sepal/sepal_material.h"
#include "spec/spec.h"
#include "test_util.h"
#include "util/image.h"
#include "util/io.h"

namespace {

std::unique_ptr<sepal::Brdf> brdf(const std::string& spec) {
    std::string err;
    std::unique_ptr<sepal::Brdf> f = sepal::make_brdf(spec, &err);
    REQUIRE_MESSAGE(f, err);
    return f;
}

// A small search (seconds): the tests are about the range, not the search.
sepal::BakeOptions small_bake(double ratio) {
    sepal::BakeOptions o;
    o.params = {sepal::Param::GsHalf};
    o.resolutions = {32};
    o.smooth_resolutions = {16};
    o.terms = {1, 2};
    o.judge_size = 48;
    o.light_range.ratio = ratio;
    return o;
}

sepal::BakeResult bake(const std::string& spec, const sepal::BakeOptions& o) {
    std::string err;
    sepal::BakeResult r;
    REQUIRE_MESSAGE(sepal::bake(*brdf(spec), o, &r, &err), err);
    return r;
}

sepal::BakeView default_view_with(float intensity_r, float intensity_g, float intensity_b) {
    sepal_scene s;
    sepal_scene_default(&s);
    s.lights[0].intensity[0] = intensity_r, s.lights[0].intensity[1] = intensity_g, s.lights[0].intensity[2] = intensity_b;
    return sepal::sphere_view("v", s);
}

// The emulated GL ES 1.1 frame of an asset in a view (the sphere), 8-bit, and its draw stats.
sepal::Image draw_gles1(const std::vector<uint8_t>& bytes, const sepal::BakeView& v, int size, sepal_draw_stats* stats) {
    sepal_ports::SceneSetup s;
    s.scene = v.scene;
    s.width = s.height = size;
    std::string err;
    std::vector<uint8_t> rgba;
    REQUIRE_MESSAGE(sepal_ports::load_scene_mesh(&s, &err), err);
    REQUIRE_MESSAGE(sepal_ports::render_asset_emulated(bytes.data(), bytes.size(), s, 1, 0, &rgba, &err, stats), err);
    return sepal::to_rgb(sepal::image_from_rgba8(rgba.data(), size, size));
}

}  // namespace

TEST_CASE("light range: training and held-out conditions differ, lie in the range, and are deterministic") {
    sepal::LightRange r;  // the default: 8:1, the hemisphere, two lights
    const auto train = sepal::training_conditions(r), held = sepal::held_out_conditions(r);
    REQUIRE(train.size() == 5);
    REQUIRE(held.size() == 4);
    CHECK(train[0].name == "default");
    // Lights from behind the object (as the default camera sees it) are part of the range:
    // training has its rim light, and the drawn directions reach behind.
    sepal_scene scene;
    sepal_scene_default(&scene);
    auto behind = [&](const sepal_light& l) {
        return double(l.position[0]) * scene.camera.eye[0] + double(l.position[1]) * scene.camera.eye[1] +
                   double(l.position[2]) * scene.camera.eye[2] < 0.0;
    };
    CHECK(train[3].name == "rim");
    CHECK(behind(train[3].lights[0]));
    int drawn_behind = 0;
    for (uint64_t seed = 1; seed <= 8; ++seed) {
        sepal::LightRange rs;
        rs.seed = seed;
        for (const auto& c : sepal::held_out_conditions(rs))
            for (const sepal_light& l : c.lights) drawn_behind += behind(l);
    }
    CHECK(drawn_behind >= 4);
    bool torus = false, two = false;
    const double lo = sepal::range_irradiance_min(r), hi = sepal::range_irradiance_max(r);
    CHECK(hi / lo == doctest::Approx(8.0));
    for (const auto& c : held) {
        torus = torus || c.mesh == "torus";
        two = two || c.lights.size() == 2;
        for (const sepal_light& l : c.lights) {
            const double d2 = double(l.position[0]) * l.position[0] + double(l.position[1]) * l.position[1] +
                              double(l.position[2]) * l.position[2];
            const double e = l.intensity[0] / d2;
            CHECK(e >= lo * (1 - 1e-5));
            CHECK(e <= hi * (1 + 1e-5));
            CHECK(l.position[2] >= 0.0f);  // above the horizon
            for (const auto& t : train)
                for (const sepal_light& m : t.lights) CHECK(std::memcmp(l.position, m.position, sizeof m.position) != 0);
        }
    }
    CHECK(torus);
    CHECK(two);
    CHECK(sepal::held_out_conditions(r)[1].flags() == held[1].flags());
    CHECK(held[2].flags().rfind("--mesh torus --light point:", 0) == 0);
    r.max_lights = 1;
    r.cone_degrees = 30;
    for (const auto& c : sepal::held_out_conditions(r)) {
        CHECK(c.lights.size() == 1);
        const sepal_light& l = c.lights[0];
        const double len = std::sqrt(double(l.position[0]) * l.position[0] + double(l.position[1]) * l.position[1] +
                                     double(l.position[2]) * l.position[2]);
        CHECK(l.position[2] / len >= std::cos(30.0 * M_PI / 180.0) - 1e-6);
    }
    std::string err;
    r.ratio = 0.5;
    CHECK_FALSE(sepal::validate_light_range(r, &err));
    CHECK(err.find("ratio") != std::string::npos);
}

TEST_CASE("light range: the white level follows the dimmest light; the header says the range; held out reported") {
    const sepal::BakeResult wide = bake("blinn:n=200", small_bake(8)), narrow = bake("blinn:n=200", small_bake(1));
    const double e_max = sepal::default_irradiance();
    CHECK(narrow.white == doctest::Approx(1.25 / e_max));
    CHECK(wide.white == doctest::Approx(8 * 1.25 / e_max));
    const sepal_fmt_material& m = wide.asset.material;
    CHECK(m.white_level == doctest::Approx(wide.white));
    CHECK(m.irradiance_min == doctest::Approx(e_max / 8));
    CHECK(m.irradiance_max == doctest::Approx(e_max));
    CHECK(m.cone_degrees == 90.0f);
    CHECK(m.max_lights == 2u);
    REQUIRE(wide.held_out_views.size() == 4);
    CHECK(wide.held_out_psnr_views.size() == 4);
    CHECK(wide.held_out_share16.size() == 4);
    CHECK(wide.held_out_psnr > 20.0);
    std::vector<uint8_t> bytes;
    std::string err;
    REQUIRE(sepal::encode_asset(wide.asset, &bytes, &err));
    auto a = std::make_unique<sepal_asset>();
    sepal_error e = {};
    REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), a.get(), &e) == SEPAL_OK);
    // 2.3 for the range; 2.5 when it also has a diffuse profile (16 bits).
    CHECK(a->header.version_minor == (wide.asset.diffuse_profile.empty() ? SEPAL_FMT_VERSION_MINOR_LIGHT_RANGE
                                                                         : SEPAL_FMT_VERSION_MINOR_DIFFUSE16));
    CHECK(std::string(a->meta, a->meta_bytes).find("\"held_out_psnr\"") != std::string::npos);
    // The printed flags reproduce each condition's figure (the judge's size, not render's 512).
    const std::string dir = sepal_test::temp_dir(), path = dir + "/wide.sepal";
    REQUIRE(sepal::write_asset(path, wide.asset, &err));
    for (size_t i = 0; i < wide.held_out_flags.size(); i += 2) {
        const std::string& flags = wide.held_out_flags[i];
        CAPTURE(flags);
        CHECK(flags.find(" --size 48x48") != std::string::npos);
        std::vector<std::string> exact = {"blinn:n=200", "--backend", "exact"}, model = {path, "--backend", "gles1-model"};
        for (size_t p = 0, q; p < flags.size(); p = q + 1) {
            q = flags.find(' ', p);
            if (q == std::string::npos) q = flags.size();
            exact.push_back(flags.substr(p, q - p));
            model.push_back(flags.substr(p, q - p));
        }
        exact.insert(exact.end(), {"-o", dir + "/e.png"});
        model.insert(model.end(), {"-o", dir + "/m.png"});
        std::string out;
        REQUIRE(sepal_test::run_cmd("render", exact) == 0);
        REQUIRE(sepal_test::run_cmd("render", model) == 0);
        REQUIRE(sepal_test::run_cmd("diff", {dir + "/e.png", dir + "/m.png"}, &out) == 0);
        const size_t at = out.find("psnr");
        REQUIRE(at != std::string::npos);
        CHECK(std::strtod(out.c_str() + at + 4, nullptr) == doctest::Approx(wide.held_out_psnr_views[i]).epsilon(0.002));
    }
    // --white none: nothing capped, so no light is too dim; the rest of the range stays.
    sepal::BakeOptions none = small_bake(8);
    none.white = -1;
    const sepal::BakeResult n = bake("blinn:n=200", none);
    CHECK(n.asset.material.white_level == 0.0f);
    CHECK(n.asset.material.irradiance_min == 0.0f);
    CHECK(n.asset.material.max_lights == 2u);
}

TEST_CASE("format 2.3: older assets load as before, their white level from META; bad ranges refused") {
    sepal::BakeOptions o = small_bake(4);
    o.held_out = false;
    sepal::BakeResult r = bake("blinn:n=200", o);
    sepal::AssetData old = r.asset;
    sepal_fmt_material& m = old.material;
    m.white_level = m.irradiance_min = m.irradiance_max = m.cone_degrees = 0.0f;
    m.max_lights = 0;
    old.diffuse_profile.clear();  // a 16-bit profile is 2.5's; the constant part is 2.0's
    old.diffuse_side = 0;
    old.meta = "{\"spec\":\"blinn\",\"fit\":{\"white_level\":0.5,\"psnr\":40}}";
    std::vector<uint8_t> bytes;
    std::string err;
    REQUIRE_MESSAGE(sepal::encode_asset(old, &bytes, &err), err);
    auto a = std::make_unique<sepal_asset>();
    sepal_error e = {};
    REQUIRE_MESSAGE(sepal_asset_parse(bytes.data(), bytes.size(), a.get(), &e) == SEPAL_OK, e.message);
    CHECK(a->header.version_minor == 0);  // 2.0, 64-byte MATL: byte-identical to the older writer
    CHECK(a->material.white_level == 0.5f);
    CHECK(a->material.irradiance_min == doctest::Approx(2.0));
    // Without META: no white level, no range, nothing counted.
    old.meta.clear();
    REQUIRE(sepal::encode_asset(old, &bytes, &err));
    REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), a.get(), &e) == SEPAL_OK);
    CHECK(a->material.white_level == 0.0f);
    CHECK(a->material.irradiance_min == 0.0f);
    // A range the reader refuses: min above max, a cone past 180 degrees, too many lights.
    for (int bad = 0; bad < 3; ++bad) {
        sepal::AssetData b = r.asset;
        if (bad == 0) b.material.irradiance_min = b.material.irradiance_max * 2;
        if (bad == 1) b.material.cone_degrees = 200;
        if (bad == 2) b.material.max_lights = 99;
        CHECK_FALSE(sepal::encode_asset(b, &bytes, &err));
        CHECK(err.find("light range") != std::string::npos);
    }
}

TEST_CASE("dim lights: a 4:1 asset at 1/8 of its brightest light is counted and `sepal render` warns; at 1/2 not") {
    sepal::BakeOptions o = small_bake(4);
    o.held_out = false;
    const sepal::BakeResult r = bake("blinn:n=200", o);
    std::vector<uint8_t> bytes;
    std::string err;
    REQUIRE(sepal::encode_asset(r.asset, &bytes, &err));
    const std::string dir = sepal_test::temp_dir(), path = dir + "/b4.sepal";
    REQUIRE(sepal::write_asset(path, r.asset, &err));
    for (double fraction : {1.0 / 8, 1.0 / 2, 1.0}) {
        CAPTURE(fraction);
        const float i = float(60.0 * fraction);
        sepal_draw_stats stats = {};
        draw_gles1(bytes, default_view_with(i, i, i), 32, &stats);
        CHECK(stats.dim_lights == (fraction < 0.25 ? 1 : 0));
        // The CPU backend counts the same way.
        auto a = std::make_unique<sepal_asset>();
        sepal_error e = {};
        REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), a.get(), &e) == SEPAL_OK);
        const sepal::BakeView v = default_view_with(i, i, i);
        const sepal_mesh mesh = v.mesh();
        sepal::Image img(32, 32, 3);
        std::vector<float> depth(32 * 32), scratch(sepal_cpu_scratch_floats(mesh.vertex_count));
        sepal_cpu_desc d = {};
        sepal_draw_stats cpu_stats = {};
        d.asset = a.get();
        d.mesh = &mesh;
        d.scene = &v.scene;
        d.width = d.height = 32;
        d.color = img.data.data();
        d.depth = depth.data();
        d.scratch = scratch.data();
        d.scratch_floats = scratch.size();
        d.stats = &cpu_stats;
        REQUIRE(sepal_draw_cpu(&d, &e) == SEPAL_OK);
        CHECK(cpu_stats.dim_lights == stats.dim_lights);
        std::string out;
        char light[64];
        std::snprintf(light, sizeof light, "point:2,-2.5,3:%g", double(i));
        REQUIRE(sepal_test::run_cmd("render", {path, "--backend", "gles1-model", "--size", "32x32", "--light", light,
                                               "-o", dir + "/b4.png"},
                                    &out) == 0);
        CHECK((out.find("warning: 1 light is dimmer than") != std::string::npos) == (fraction < 0.25));
        if (fraction < 0.25) CHECK(out.find("0.779..3.12") != std::string::npos);
    }
    // A second light in range does not hide the dim one.
    sepal::BakeView two = default_view_with(60, 60, 60);
    two.scene.light_count = 2;
    two.scene.lights[1] = two.scene.lights[0];
    for (int k = 0; k < 3; ++k) two.scene.lights[1].intensity[k] = 60.0f / 8;
    sepal_draw_stats stats = {};
    draw_gles1(bytes, two, 32, &stats);
    CHECK(stats.dim_lights == 1);
}

TEST_CASE("coloured light: a (1, 0.5, 0.2) light keeps the highlight's hue (the default 8:1 range)") {
    // Cook-Torrance: a coloured Fresnel, factored per channel, whose blue highlight a white
    // level too low for the light flattens towards grey-green.
    const std::string spec = "cook-torrance";
    sepal::BakeOptions o = small_bake(8);
    o.held_out = false;
    const sepal::BakeResult r = bake(spec, o);
    std::vector<uint8_t> bytes;
    std::string err;
    REQUIRE(sepal::encode_asset(r.asset, &bytes, &err));
    const int size = 96;
    // The light's intensity: the highlight's brightest channel just below white in the exact
    // render (a clipped channel has no hue), within the range (its blue at least the dimmest).
    sepal::BakeView v = default_view_with(60.0f, 30.0f, 12.0f);
    sepal::Image exact;
    REQUIRE(sepal::render_exact(*brdf(spec), v.scene, v.mesh(), size, size, &exact, nullptr, &err, false,
                                sepal::kReferenceSupersample));
    size_t best = 0;
    for (size_t p = 0; p < size_t(size) * size; ++p)
        if (exact.data[3 * p] + exact.data[3 * p + 1] + exact.data[3 * p + 2] >
            exact.data[3 * best] + exact.data[3 * best + 1] + exact.data[3 * best + 2])
            best = p;
    const float peak = std::max({exact.data[3 * best], exact.data[3 * best + 1], exact.data[3 * best + 2]});
    const float scale = 0.9f / peak;
    const double blue = 12.0 * scale / 19.25;
    CAPTURE(scale);
    REQUIRE(blue >= r.asset.material.irradiance_min);
    v = default_view_with(60.0f * scale, 30.0f * scale, 12.0f * scale);
    REQUIRE(sepal::render_exact(*brdf(spec), v.scene, v.mesh(), size, size, &exact, nullptr, &err, false,
                                sepal::kReferenceSupersample));
    sepal_draw_stats stats = {};
    const sepal::Image got = draw_gles1(bytes, v, size, &stats);
    CHECK(stats.dim_lights == 0);
    auto ratios = [&](const sepal::Image& img) {
        double c[3];
        for (int k = 0; k < 3; ++k) c[k] = std::round(std::min(1.0f, img.data[3 * best + size_t(k)]) * 255.0f);
        const double top = std::max({c[0], c[1], c[2]});
        return std::make_tuple(c[0] / top, c[1] / top, c[2] / top);
    };
    const auto want = ratios(exact), have = ratios(got);
    CAPTURE(std::get<0>(want));
    CAPTURE(std::get<1>(want));
    CAPTURE(std::get<2>(want));
    CAPTURE(std::get<0>(have));
    CAPTURE(std::get<1>(have));
    CAPTURE(std::get<2>(have));
    CHECK(std::get<0>(have) == doctest::Approx(std::get<0>(want)).epsilon(0.05));
    CHECK(std::get<1>(have) == doctest::Approx(std::get<1>(want)).epsilon(0.05));
    CHECK(std::get<2>(have) == doctest::Approx(std::get<2>(want)).epsilon(0.05));
    // Baked for 2:1 the same light's green and blue are dimmer than the asset holds for:
    // counted, and the capped highlight loses its hue.
    sepal::BakeOptions narrow = o;
    narrow.light_range.ratio = 2;
    const sepal::BakeResult n = bake(spec, narrow);
    REQUIRE(sepal::encode_asset(n.asset, &bytes, &err));
    const sepal::Image flat = draw_gles1(bytes, v, size, &stats);
    CHECK(stats.dim_lights == 1);
    const auto lost = ratios(flat);
    // (measured: blue 0.715 of red against the exact 0.791, 10% off: the check above fails it)
    CAPTURE(std::get<2>(lost));
    CHECK(std::fabs(std::get<2>(lost) / std::get<2>(want) - 1.0) > 0.05);
}
