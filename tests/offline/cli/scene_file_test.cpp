// Scene files (offline/cli/scene_file.h): the kiosk's contents, motion over time, materials
// and meshes loaded once, and bad input refused with the file and the JSON path.
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>

#include "brdf/brdf.h"
#include "cli/bake_scene.h"
#include "cli/scene_file.h"
#include "spec/spec.h"
#include "test_util.h"
#include "util/json.h"

namespace {

const char* const kMinimal = R"({
  "camera": {"orbit": {"target": [0, 0, 0], "distance": 4, "yaw": 0, "pitch": 0}},
  "lights": [{"type": "point", "position": [2, 0, 1], "intensity": 10,
              "orbit": {"period": 8, "center": [1, 0, 0]}, "pulse": {"period": 2, "depth": 0.5}}],
  "materials": [{"name": "m", "spec": "lambert"}],
  "objects": [{"material": "m", "mesh": "sphere"}]
})";

sepal::Json minimal() {
    sepal::Json j;
    std::string err;
    REQUIRE(sepal::parse_json(kMinimal, "minimal", &j, &err));
    return j;
}

bool parse(const sepal::Json& j, sepal::SceneFile* f, std::string* err) {
    return sepal::parse_scene_text(j.dump(), "scene.json", "", f, err);
}

}  // namespace

TEST_CASE("scene file: the kiosk holds what the showcase promises; shared materials and meshes load once") {
    sepal::SceneFile f;
    std::string err;
    REQUIRE_MESSAGE(sepal::read_scene_file(sepal_test::source_path("examples/kiosk.json"), &f, &err), err);
    CHECK(f.objects.size() >= 10);  // a floor and at least 9 objects
    CHECK(f.objects[0].mesh == "floor");
    CHECK(f.materials.size() >= 5);
    CHECK(f.lights.size() >= 2);
    CHECK(f.lights.size() <= 4);
    CHECK(f.camera.orbit);
    bool measured = false, nbrdf = false, aniso = false, gltf = false, moving = true, coloured = true;
    for (const sepal::SceneMaterial& m : f.materials) {
        measured = measured || !m.measured.empty();
        nbrdf = nbrdf || m.spec.rfind("nbrdf:", 0) == 0;
        aniso = aniso || m.spec.rfind("ward:", 0) == 0;
    }
    for (const sepal::SceneObject& o : f.objects) gltf = gltf || o.mesh.find(".gl") != std::string::npos;
    for (const sepal::SceneLight& l : f.lights) {
        moving = moving && (l.orbit_period > 0 || l.pulse_period > 0);
        coloured = coloured && !(l.color[0] == l.color[1] && l.color[1] == l.color[2]);
    }
    CHECK(measured);
    CHECK(nbrdf);
    CHECK(aniso);
    CHECK(gltf);
    CHECK(moving);
    CHECK(coloured);
    sepal::LoadedScene s;
    REQUIRE_MESSAGE(sepal::load_scene(f, sepal::default_scene_cache(), &s, &err), err);
    CHECK(s.assets.size() == f.materials.size());
    CHECK(s.meshes.size() < f.objects.size());  // sphere, torus and the vases once each
    CHECK(s.baked + s.cached == int(f.materials.size()));
    // A second load finds every material in the cache.
    sepal::LoadedScene again;
    REQUIRE(sepal::load_scene(f, sepal::default_scene_cache(), &again, &err));
    CHECK(again.baked == 0);
    CHECK(again.asset_bytes == s.asset_bytes);
}

TEST_CASE("scene file: lights orbit and pulse, the camera spins, objects spin") {
    sepal::SceneFile f;
    std::string err;
    sepal::Json j = minimal();
    j["camera"]["orbit"]["spin"] = 90;
    j["objects"][0]["spin"] = 45;
    j["objects"][0]["translate"] = {1, 2, 3};
    j["objects"][0]["scale"] = 2;
    REQUIRE_MESSAGE(parse(j, &f, &err), err);
    sepal_light l[SEPAL_MAX_LIGHTS];
    REQUIRE(sepal::scene_lights_at(f, 0, l) == 1);
    CHECK(l[0].position[0] == doctest::Approx(2));
    CHECK(l[0].intensity[0] == doctest::Approx(10));
    sepal::scene_lights_at(f, 2, l);  // a quarter turn about (1, 0): (2, 0) -> (1, 1); pulse at its full period
    CHECK(l[0].position[0] == doctest::Approx(1).epsilon(1e-5));
    CHECK(l[0].position[1] == doctest::Approx(1).epsilon(1e-5));
    CHECK(l[0].position[2] == doctest::Approx(1));
    CHECK(l[0].intensity[0] == doctest::Approx(10));
    sepal::scene_lights_at(f, 1, l);  // half the pulse's period: its dimmest
    CHECK(l[0].intensity[1] == doctest::Approx(5));
    const sepal_camera c0 = sepal::scene_camera_at(f, 0), c1 = sepal::scene_camera_at(f, 1);
    CHECK(c0.eye[1] == doctest::Approx(-4));  // yaw 0: on -y
    CHECK(c1.eye[0] == doctest::Approx(4));   // a quarter turn a second
    float m[16];
    sepal::scene_model_at(f.objects[0], 2, m);  // 90 degrees about z, scale 2
    CHECK(m[0] == doctest::Approx(0).epsilon(1e-6));
    CHECK(m[1] == doctest::Approx(2));
    CHECK(m[10] == doctest::Approx(2));
    CHECK(m[12] == 1);
    CHECK(m[14] == 3);
}

TEST_CASE("scene file: bad input is refused with the JSON path") {
    struct Case {
        const char* what;
        std::function<void(sepal::Json&)> edit;
        const char* says;
    };
    const Case cases[] = {
        {"unknown top-level key", [](sepal::Json& j) { j["objets"] = 1; }, "scene.json: unknown key \"objets\""},
        {"unknown object key", [](sepal::Json& j) { j["objects"][0]["colour"] = 1; },
         "scene.json: objects[0]: unknown key \"colour\""},
        {"negative scale", [](sepal::Json& j) { j["objects"][0]["scale"] = -1; }, "objects[0].scale"},
        {"no such material", [](sepal::Json& j) { j["objects"][0]["material"] = "x"; },
         "objects[0].material: no material named \"x\""},
        {"bad mesh", [](sepal::Json& j) { j["objects"][0]["mesh"] = "cube"; }, "objects[0].mesh: \"cube\" is not"},
        {"no objects", [](sepal::Json& j) { j.erase("objects"); }, "objects"},
        {"spot light", [](sepal::Json& j) { j["lights"][0]["type"] = "spot"; }, "lights[0].type: \"spot\""},
        {"point light with a direction", [](sepal::Json& j) { j["lights"][0]["direction"] = {0, 0, 1}; },
         "lights[0].direction: a point light takes \"position\""},
        {"orbit without period", [](sepal::Json& j) { j["lights"][0]["orbit"].erase("period"); },
         "lights[0].orbit: missing \"period\""},
        {"pulse too deep", [](sepal::Json& j) { j["lights"][0]["pulse"]["depth"] = 2; }, "lights[0].pulse.depth"},
        {"negative colour", [](sepal::Json& j) { j["lights"][0]["color"] = {1, -1, 1}; }, "lights[0].color"},
        {"nine lights", [](sepal::Json& j) { for (int i = 0; i < 8; ++i) j["lights"].push_back(j["lights"][0]); }, "lights"},
        {"orbit and eye", [](sepal::Json& j) { j["camera"]["eye"] = {0, -4, 1}; }, "camera: give either"},
        {"pitch 95", [](sepal::Json& j) { j["camera"]["orbit"]["pitch"] = 95; }, "camera.orbit.pitch"},
        {"no camera", [](sepal::Json& j) { j.erase("camera"); }, "camera: missing"},
        {"far before near", [](sepal::Json& j) { j["camera"]["near"] = 5, j["camera"]["far"] = 1; }, "far must be beyond near"},
        {"material option", [](sepal::Json& j) { j["materials"][0]["res"] = "big"; }, "materials[0].res"},
        {"material key", [](sepal::Json& j) { j["materials"][0]["colour"] = 1; }, "materials[0]: unknown key \"colour\""},
        {"material horizon", [](sepal::Json& j) { j["materials"][0]["horizon"] = 1.5; }, "materials[0].horizon"},
        {"material name twice", [](sepal::Json& j) { j["materials"].push_back(j["materials"][0]); },
         "materials[1].name: \"m\" is used twice"},
        {"measured file missing", [](sepal::Json& j) { j["materials"][0]["spec"] = "absent.brdf"; }, "materials[0].spec"},
        {"floor key", [](sepal::Json& j) { j["floor"] = {{"material", "m"}, {"tiles", 3}}; }, "floor: unknown key \"tiles\""},
        {"size", [](sepal::Json& j) { j["size"] = {4, 100}; }, "size: width and height"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.what);
        sepal::Json j = minimal();
        c.edit(j);
        sepal::SceneFile f;
        std::string err;
        CHECK_FALSE(parse(j, &f, &err));
        CAPTURE(err);
        CHECK(err.find(c.says) != std::string::npos);
    }
    sepal::SceneFile f;
    std::string err;
    CHECK_FALSE(sepal::parse_scene_text("{\"camera\": [1,}", "scene.json", "", &f, &err));
    CHECK(err.find("scene.json: line 1") != std::string::npos);
    // Errors found while loading name the object or material.
    sepal::Json j = minimal();
    j["objects"][0]["mesh"] = "absent.glb";
    j["objects"][0]["name"] = "chair";
    REQUIRE(parse(j, &f, &err));
    sepal::LoadedScene s;
    CHECK_FALSE(sepal::load_scene(f, sepal_test::temp_dir(), &s, &err));
    CHECK(err.find("object chair: absent.glb") != std::string::npos);
}

TEST_CASE("render --scene: flags that do not apply are refused") {
    const std::string kiosk = sepal_test::source_path("examples/kiosk.json");
    const std::string out = sepal_test::temp_dir() + "/k.png";
    std::string text;
    CHECK(sepal_test::run_cmd("render", {"--scene", kiosk, "--mesh", "torus", "-o", out}, &text) == 2);
    CHECK(text.find("--mesh does not apply") != std::string::npos);
    CHECK(sepal_test::run_cmd("render", {"cook-torrance", "--scene", kiosk, "-o", out}, &text) == 2);
    CHECK(text.find("give no INPUT") != std::string::npos);
    CHECK(sepal_test::run_cmd("render", {"-o", out}, &text) == 2);
    CHECK(text.find("or --scene FILE") != std::string::npos);
    CHECK(sepal_test::run_cmd("render", {"cook-torrance", "--time", "2", "-o", out}, &text) == 2);
    CHECK(text.find("--time, --cache and --export apply with --scene") != std::string::npos);
}

TEST_CASE("scene file: a material's horizon window reaches its bake and its bake key") {
    std::string err;
    std::unique_ptr<sepal::Brdf> f = sepal::make_brdf("cook-torrance", &err);
    REQUIRE_MESSAGE(f, err);
    const sepal::Json plain = {{"name", "m"}, {"spec", "cook-torrance"}};
    sepal::Json windowed = plain, zero = plain;
    windowed["horizon"] = 0.1;
    zero["horizon"] = 0;
    sepal::BakeOptions a, b, c;
    REQUIRE(sepal::scene_material_options({plain, "materials[0]"}, &a, &err));
    REQUIRE(sepal::scene_material_options({windowed, "materials[0]"}, &b, &err));
    REQUIRE(sepal::scene_material_options({zero, "materials[0]"}, &c, &err));
    CHECK(a.horizon == 0.0);
    CHECK(b.horizon == 0.1);
    // Another window is another asset; none (0, the default) keeps the key assets already hold.
    const std::string ka = sepal::scene_bake_key(*f, a, "", {}), kb = sepal::scene_bake_key(*f, b, "", {});
    CHECK(ka != kb);
    CHECK(sepal::scene_bake_key(*f, c, "", {}) == ka);
}
