// An asset read back as the BRDF it represents (bake/asset_brdf.h, sepal_asset_eval): the
// CPU backend's pixel at the same direction pair, the white level's cap, and `sepal eval`.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "bake/asset_brdf.h"
#include "bake/export.h"
#include "brdf/brdf_util.h"
#include "material_fixtures.h"
#include "sepal/sepal_material.h"
#include "spec/spec.h"
#include "test_util.h"
#include "util/image.h"
#include "util/io.h"
#include "util/json.h"

namespace {

// A radiance asset with a diffuse profile (Ashikhmin-Shirley's diffuse is not Lambert) and
// a white level, baked once and written where `sepal eval` can read it.
const char* kSpec = "ashikhmin-shirley";

struct Baked {
    sepal::AssetData data;
    std::string path;
};

const Baked& baked() {
    static const Baked b = [] {
        Baked r;
        r.data = material_fx::bake_small(kSpec, sepal::Param::GsHalf, sepal::Method::ACLS, 2, true, 16, 32);
        r.path = sepal_test::temp_dir() + "/as.sepal";
        std::string err;
        REQUIRE_MESSAGE(sepal::write_asset(r.path, r.data, &err), err);
        return r;
    }();
    return b;
}

std::unique_ptr<sepal::AssetBrdf> load(const std::string& path) {
    std::string err;
    std::unique_ptr<sepal::AssetBrdf> a = sepal::AssetBrdf::load(path, &err);
    REQUIRE_MESSAGE(a, err);
    return a;
}

// The CPU backend's pixel at the centre of a 33 x 33 view of a flat square (normal +z,
// tangent +x) centred on the camera's target, under one directional light of intensity 1
// towards wi: the surface point is the origin, so wo is the direction to the eye.
glm::dvec3 cpu_pixel(const sepal::AssetData& a, const glm::dvec3& wi, const glm::dvec3& wo) {
    const std::vector<uint8_t> bytes = material_fx::encode(a);
    sepal_asset asset;
    sepal_error err = {};
    REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), &asset, &err) == SEPAL_OK);
    std::vector<sepal_vertex> v(4);
    std::vector<uint16_t> idx(6);
    sepal_mesh mesh = {v.data(), idx.data(), 4, 6};
    REQUIRE(sepal_mesh_grid(1, &mesh, &err) == SEPAL_OK);
    sepal_scene scene;
    sepal_scene_default(&scene);
    for (int k = 0; k < 3; ++k) {
        scene.camera.eye[k] = float(3.0 * wo[k]);
        scene.camera.target[k] = 0.0f;
        scene.camera.up[k] = k == 1 ? 1.0f : 0.0f;
        scene.background[k] = 0.0f;
    }
    scene.light_count = 1;
    scene.lights[0].type = SEPAL_LIGHT_DIRECTIONAL;
    for (int k = 0; k < 3; ++k) scene.lights[0].position[k] = float(wi[k]), scene.lights[0].intensity[k] = 1.0f;
    const int n = 33;
    std::vector<float> color(size_t(n) * n * 3), depth(size_t(n) * n), scratch(sepal_cpu_scratch_floats(4));
    sepal_cpu_desc d = {};
    d.asset = &asset;
    d.mesh = &mesh;
    d.scene = &scene;
    d.width = d.height = n;
    d.color = color.data();
    d.depth = depth.data();
    d.scratch = scratch.data();
    d.scratch_floats = scratch.size();
    REQUIRE_MESSAGE(sepal_draw_cpu(&d, &err) == SEPAL_OK, err.message);
    const float* p = &color[(size_t(n / 2) * n + n / 2) * 3];
    return glm::dvec3(p[0], p[1], p[2]);
}

// Direction pairs over the hemisphere: near the mirror, off it, grazing, retro.
std::vector<std::pair<glm::dvec3, glm::dvec3>> pairs() {
    const double deg[][4] = {{0, 0, 30, 90},   {30, 0, 30, 180}, {45, 20, 40, 200},  {60, 0, 10, 90},
                             {75, 0, 75, 180}, {20, 0, 70, 0},   {50, 130, 55, 310}, {85, 0, 84, 180}};
    std::vector<std::pair<glm::dvec3, glm::dvec3>> out;
    for (const auto& d : deg) out.push_back({sepal::dir_from_degrees(d[0], d[1]), sepal::dir_from_degrees(d[2], d[3])});
    return out;
}

}  // namespace

TEST_CASE("asset eval: the value at a direction pair is the CPU backend's pixel there") {
    const Baked& b = baked();
    REQUIRE((b.data.material.flags & SEPAL_MATERIAL_RADIANCE) != 0);
    REQUIRE(b.data.diffuse_side > 0);  // the profile is part of what is compared
    const std::unique_ptr<sepal::AssetBrdf> a = load(b.path);
    for (const auto& [wi, wo] : pairs()) {
        CAPTURE(wi);
        CAPTURE(wo);
        const glm::dvec3 pixel = cpu_pixel(b.data, wi, wo), drawn = a->drawn_cos(wi, wo);
        CHECK(pixel.x > 0.0);
        // The pixel's frame and directions are interpolated in float: a few ulps of the
        // directions, not of the value.
        for (int c = 0; c < 3; ++c) CHECK(drawn[c] == doctest::Approx(pixel[c]).epsilon(2e-3));
        // f is f cos over cos(theta_i); below the white level the cap changes nothing.
        const glm::dvec3 fc = a->eval_cos(wi, wo);
        for (int c = 0; c < 3; ++c) {
            CHECK(fc[c] == std::min(drawn[c], double(b.data.material.white_level)));
            CHECK(a->eval(wi, wo)[c] == doctest::Approx(fc[c] / wi.z).epsilon(1e-12));
        }
    }
    // Below the horizon: 0, as the backend draws nothing there.
    CHECK(a->eval(sepal::dir_from_degrees(95, 0), sepal::dir_from_degrees(30, 0)) == glm::dvec3(0.0));
    const float up[3] = {0, 0, 1}, down[3] = {0, 0, -1};
    float out[3] = {7, 7, 7};
    CHECK(sepal_asset_eval(&a->asset(), down, up, out) == 0);
    CHECK(out[0] == 0.0f);
    static const sepal_asset zeroed = {};  // not filled by sepal_asset_parse
    CHECK(sepal_asset_eval(&zeroed, up, up, out) == -1);
    CHECK(sepal_asset_eval(nullptr, up, up, out) == -1);
    CHECK(sepal_asset_eval(&a->asset(), up, up, nullptr) == -1);
}

TEST_CASE("asset eval: the white level caps what the asset represents, as the display does under its lights") {
    // The baked asset with its white level lowered below its highlight: the factors still
    // hold more, which the cap must remove; under the range's dimmest light (irradiance
    // 1 / white) the display clips the CPU pixel to the same value.
    Baked low = baked();
    const glm::dvec3 wi = sepal::dir_from_degrees(30, 0), wo = sepal::dir_from_degrees(30, 180);  // the mirror pair
    const double peak = load(low.path)->drawn_cos(wi, wo).x;
    REQUIRE(peak > 0.0);
    const float white = float(0.5 * peak);
    low.data.material.white_level = white;
    low.data.material.irradiance_min = 1.0f / white;
    low.data.material.irradiance_max = std::max(low.data.material.irradiance_max, low.data.material.irradiance_min);
    low.path = sepal_test::temp_dir() + "/low.sepal";
    std::string err;
    REQUIRE_MESSAGE(sepal::write_asset(low.path, low.data, &err), err);
    const std::unique_ptr<sepal::AssetBrdf> a = load(low.path);
    CHECK(a->drawn_cos(wi, wo).x == doctest::Approx(peak));
    CHECK(a->eval_cos(wi, wo).x == doctest::Approx(white));  // fails when the cap is ignored
    CHECK(a->eval(wi, wo).x == doctest::Approx(white / wi.z));
    const double e = 1.0 / white;
    for (const auto& [i, o] : pairs()) {
        const glm::dvec3 pixel = cpu_pixel(low.data, i, o), fc = a->eval_cos(i, o);
        for (int c = 0; c < 3; ++c)
            CHECK(std::min(1.0, e * fc[c]) == doctest::Approx(std::min(1.0, e * pixel[c])).epsilon(2e-3));
    }
}

TEST_CASE("asset eval: the asset stands for its source capped at the white level") {
    // Against the source, what the asset represents is min(f cos, white): over pairs where
    // the source's f cos passes the white level the capped source is the closer one.
    const Baked& b = baked();
    const std::unique_ptr<sepal::AssetBrdf> a = load(b.path);
    std::string err;
    const std::unique_ptr<sepal::Brdf> src = sepal::make_brdf(kSpec, &err);
    REQUIRE_MESSAGE(src, err);
    CHECK(a->source() == src->spec());
    const double white = b.data.material.white_level;
    REQUIRE(white > 0);
    double capped = 0, uncapped = 0;
    int over = 0;
    for (int ti = 60; ti <= 88; ti += 4)
        for (int to = 60; to <= 88; to += 4) {
            const glm::dvec3 wi = sepal::dir_from_degrees(ti, 0), wo = sepal::dir_from_degrees(to, 180);
            const double s = src->eval(wi, wo).y * wi.z, v = a->eval_cos(wi, wo).y;
            if (s <= white) continue;
            ++over;
            capped += std::fabs(v - white);
            uncapped += std::fabs(v - s);
        }
    MESSAGE(over << " pairs over the white level " << white << ": mean |asset - min(f cos, white)| " << capped / over
                 << ", |asset - f cos| " << uncapped / over);
    REQUIRE(over >= 4);
    CHECK(capped < 0.25 * uncapped);
}

TEST_CASE("sepal eval ASSET prints the asset's f, f cos and uncapped value; sepal info describes it") {
    const Baked& b = baked();
    const std::unique_ptr<sepal::AssetBrdf> a = load(b.path);
    const glm::dvec3 wi = sepal::dir_from_degrees(40, 10), wo = sepal::dir_from_degrees(35, 200);
    auto eval_cli = [&](const std::vector<std::string>& extra) {
        std::vector<std::string> args = {b.path, "40", "10", "35", "200"};
        args.insert(args.end(), extra.begin(), extra.end());
        std::string out;
        REQUIRE(sepal_test::run_cmd("eval", args, &out) == 0);
        double r = -1, g = -1, bl = -1;
        REQUIRE_MESSAGE(std::sscanf(out.c_str(), "%lf %lf %lf", &r, &g, &bl) == 3, out);
        return glm::dvec3(r, g, bl);
    };
    const glm::dvec3 f = eval_cli({}), fc = eval_cli({"--cos"}), pixel = cpu_pixel(b.data, wi, wo);
    for (int c = 0; c < 3; ++c) {
        CHECK(f[c] == doctest::Approx(a->eval(wi, wo)[c]).epsilon(1e-9));
        CHECK(fc[c] == doctest::Approx(pixel[c]).epsilon(2e-3));
    }
    CHECK(eval_cli({"--cos", "--uncapped"}) == a->drawn_cos(wi, wo));
    std::string out;
    CHECK(sepal_test::run_cmd("eval", {kSpec, "40", "10", "35", "200", "--uncapped"}, &out) == 2);
    CHECK(out.find("--uncapped applies to a .sepal asset") != std::string::npos);
    REQUIRE(sepal_test::run_cmd("info", {b.path, "--samples", "16"}, &out) == 0);
    CHECK(out.find("source             ashikhmin-shirley") != std::string::npos);
    CHECK(out.find("white level ") != std::string::npos);
    CHECK(out.find("profile over (cos_i, cos_o)") != std::string::npos);
    CHECK(out.find("directional albedo") != std::string::npos);
}

namespace {

// One texture of the export as its level-0 values (term<k>_<G|H>.pfm, flipped: image row y
// is texture row h - 1 - y), sampled as GL_LINEAR does.
struct Exported {
    sepal::Image img;
    double at(int i, int j, int c) const {
        return img.data[(size_t(img.height - 1 - j) * img.width + i) * img.channels + c];
    }
    double sample(const float uv[2], int c, bool wrap) const {
        const int w = img.width, h = img.height;
        const double x = uv[0] * w - 0.5, y = uv[1] * h - 0.5, fx = std::floor(x), fy = std::floor(y);
        auto fix = [wrap](int k, int n) { return wrap ? ((k % n) + n) % n : std::clamp(k, 0, n - 1); };
        const int x0 = fix(int(fx), w), x1 = fix(int(fx) + 1, w), y0 = fix(int(fy), h), y1 = fix(int(fy) + 1, h);
        const double ax = x - fx, ay = y - fy;
        return (1 - ay) * ((1 - ax) * at(x0, y0, c) + ax * at(x1, y0, c)) +
               ay * ((1 - ax) * at(x0, y1, c) + ax * at(x1, y1, c));
    }
};

// f cos(theta_i) from `bake --export`'s files alone, by the manifest's "evaluation".
glm::dvec3 from_export(const std::string& dir, const glm::dvec3& wi, const glm::dvec3& wo) {
    std::string text, err;
    std::vector<uint8_t> bytes;
    REQUIRE_MESSAGE(sepal::read_file(dir + "/manifest.json", &bytes, &err), err);
    sepal::Json m;
    REQUIRE_MESSAGE(sepal::parse_json(std::string(bytes.begin(), bytes.end()), "manifest.json", &m, &err), err);
    const char* params[] = {"iv", "gs-half", "vh", "rusinkiewicz", "elev-azim", "axis"};
    int param = 0;
    while (param < 6 && m["param"] != params[param]) ++param;
    REQUIRE(param < 6);
    const sepal_hemi_map map = m["map"] == "parabolic" ? SEPAL_MAP_PARABOLIC : SEPAL_MAP_XY;
    const float i3[3] = {float(wi.x), float(wi.y), float(wi.z)}, o3[3] = {float(wo.x), float(wo.y), float(wo.z)};
    float guv[2], huv[2];
    if (sepal_param_texcoords_pixel(sepal_param(param), map, i3, o3, guv, huv) != 1) return glm::dvec3(0.0);
    REQUIRE(m["reciprocal"] == false);  // the reciprocal G~ lookup is not needed here
    glm::dvec3 sum(0.0);
    const int terms = m["terms"];
    for (int k = 0; k < terms; ++k) {
        Exported g, h;
        for (const auto& t : m["textures"])
            if (t["term"] == k)
                REQUIRE(sepal::read_pfm(dir + "/term" + std::to_string(k) + "_" + t["role"].get<std::string>() + ".pfm",
                                        t["role"] == "G" ? &g.img : &h.img, &err));
        for (int c = 0; c < 3; ++c) {
            const int cc = g.img.channels == 1 ? 0 : c;
            sum[c] += g.sample(guv, cc, false) * h.sample(huv, cc, param == SEPAL_PARAM_ELEV_AZIM);
        }
    }
    glm::dvec3 out;
    for (int c = 0; c < 3; ++c) {
        // Radiance factors: times the horizon window when the manifest has one (format 2.7).
        const double window = m["horizon"].is_null() ? 1.0 : std::min(1.0, wi.z / double(m["horizon"]));
        const double s = std::max(0.0, double(m["ratio"][c]) * sum[c]) * (m["radiance"] == true ? window : wi.z);
        double profile = 1;
        if (!m["diffuse_profile"].is_null()) {
            Exported p;
            REQUIRE(sepal::read_pfm(dir + "/" + m["diffuse_profile"]["file"].get<std::string>(), &p.img, &err));
            const int n = m["diffuse_profile"]["side"];
            REQUIRE(p.img.width == n);
            // Nodes at cos = i / (n - 1): as texel centres of a texture of side n stretched by n / (n - 1).
            const float uv[2] = {float((wi.z * (n - 1) + 0.5) / n), float((wo.z * (n - 1) + 0.5) / n)};
            profile = p.sample(uv, c, false);
        }
        out[c] = s + double(m["diffuse"][c]) * wi.z * profile;
        if (!m["white_level"].is_null()) out[c] = std::min(out[c], double(m["white_level"]));
    }
    return out;
}

}  // namespace

TEST_CASE("bake --export holds everything the asset draws: its files recompute sepal eval's value") {
    // The asset, and the same factors read under a horizon window (format 2.7; the pairs'
    // 85-degree light is inside it).
    for (float horizon : {0.0f, 0.2f}) {
        CAPTURE(horizon);
        sepal::AssetData data = baked().data;
        data.material.horizon = horizon;
        const std::string path = sepal_test::temp_dir() + "/h" + std::to_string(int(horizon * 10)) + ".sepal";
        const std::string dir = sepal_test::temp_dir() + "/x" + std::to_string(int(horizon * 10));
        std::string err;
        REQUIRE_MESSAGE(sepal::write_asset(path, data, &err), err);
        REQUIRE_MESSAGE(sepal::export_asset(data, dir, &err), err);
        const std::unique_ptr<sepal::AssetBrdf> a = load(path);
        double peak = 0;
        for (const auto& [wi, wo] : pairs()) {
            CAPTURE(wi);
            CAPTURE(wo);
            const glm::dvec3 fc = a->eval_cos(wi, wo), x = from_export(dir, wi, wo);
            for (int c = 0; c < 3; ++c) CHECK(x[c] == doctest::Approx(fc[c]).epsilon(1e-4));
            peak = std::max(peak, fc.x);
        }
        CHECK(peak > 0.0);
    }
}
