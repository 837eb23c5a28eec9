// glTF 2.0 meshes (offline/mesh/gltf_mesh.h): the fixture as .gltf and .glb, node transforms,
// tangents derived from the UVs when the file has none, and clear errors on bad files.
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>

#include "mesh/gltf_mesh.h"
#include "test_util.h"
#include "util/json.h"

namespace {

const std::string kVase = sepal_test::source_path("fixtures/gltf/vase.gltf");

sepal::Json vase_json() {
    sepal::Json j;
    std::string err;
    REQUIRE_MESSAGE(sepal::read_json_file(kVase, &j, &err), err);
    return j;
}

// Writes j as a .gltf in a fresh folder and loads it; returns the loader's verdict.
bool load_edited(const sepal::Json& j, sepal::GltfMesh* m, std::string* err) {
    const std::string path = sepal_test::temp_dir() + "/edited.gltf";
    std::ofstream(path) << j.dump();
    return sepal::load_gltf_mesh(path, m, err);
}

float len3(const float* v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

}  // namespace

TEST_CASE("gltf: the fixture's vertices, as .gltf and .glb, under its node's transform") {
    sepal::GltfMesh a, b;
    std::string err;
    REQUIRE_MESSAGE(sepal::load_gltf_mesh(kVase, &a, &err), err);
    REQUIRE_MESSAGE(sepal::load_gltf_mesh(sepal_test::source_path("fixtures/gltf/vase.glb"), &b, &err), err);
    CHECK(a.vertices.size() == 33 * 25);
    CHECK(a.indices.size() == 32 * 24 * 6);
    CHECK(a.primitives == 1);
    CHECK(a.derived_tangents == 0);
    REQUIRE(b.vertices.size() == a.vertices.size());
    CHECK(std::memcmp(a.vertices.data(), b.vertices.data(), a.vertices.size() * sizeof(sepal_vertex)) == 0);
    CHECK(a.indices == b.indices);
    float zmin = 1e9f, zmax = -1e9f;
    for (const sepal_vertex& v : a.vertices) {
        zmin = std::min(zmin, v.position[2]);
        zmax = std::max(zmax, v.position[2]);
        CHECK(std::fabs(len3(v.normal) - 1.0f) < 1e-5f);
        CHECK(std::fabs(len3(v.tangent) - 1.0f) < 1e-5f);
        CHECK(std::fabs(v.normal[0] * v.tangent[0] + v.normal[1] * v.tangent[1] + v.normal[2] * v.tangent[2]) < 1e-5f);
        CHECK(std::fabs(v.tangent[3]) == 1.0f);
    }
    // height 1.1 cos theta, scaled by 0.8 and lifted by 0.1
    CHECK(zmin == doctest::Approx(-1.1 * 0.8 + 0.1).epsilon(1e-3));
    CHECK(zmax == doctest::Approx(1.1 * 0.8 + 0.1).epsilon(1e-3));
    // counter-clockwise seen from outside: the first triangle's face normal agrees with its normals
    const sepal_vertex &p = a.vertices[a.indices[0]], &q = a.vertices[a.indices[1]], &r = a.vertices[a.indices[2]];
    const float e1[3] = {q.position[0] - p.position[0], q.position[1] - p.position[1], q.position[2] - p.position[2]};
    const float e2[3] = {r.position[0] - p.position[0], r.position[1] - p.position[1], r.position[2] - p.position[2]};
    const float fn[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    CHECK(fn[0] * p.normal[0] + fn[1] * p.normal[1] + fn[2] * p.normal[2] > 0.0f);
}

TEST_CASE("gltf: without TANGENT, tangents come from the UV gradients and agree with the file's") {
    sepal::GltfMesh file, derived;
    std::string err;
    REQUIRE(sepal::load_gltf_mesh(kVase, &file, &err));
    sepal::Json j = vase_json();
    j["meshes"][0]["primitives"][0]["attributes"].erase("TANGENT");
    REQUIRE_MESSAGE(load_edited(j, &derived, &err), err);
    CHECK(derived.derived_tangents == int(derived.vertices.size()));
    // Away from the poles (whose rings are tiny) the directions and handedness match.
    int agree = 0, total = 0;
    for (size_t i = 33 * 2; i < derived.vertices.size() - 33 * 2; ++i) {
        const float* t = file.vertices[i].tangent;
        const float* d = derived.vertices[i].tangent;
        ++total;
        agree += t[0] * d[0] + t[1] * d[1] + t[2] * d[2] > 0.99f && t[3] == d[3];
    }
    CHECK(agree == total);
}

TEST_CASE("gltf: bad files are refused with what is missing and where") {
    sepal::GltfMesh m;
    std::string err;
    struct Case {
        const char* what;
        std::function<void(sepal::Json&)> edit;
        const char* says;
    };
    const Case cases[] = {
        {"no NORMAL", [](sepal::Json& j) { j["meshes"][0]["primitives"][0]["attributes"].erase("NORMAL"); },
         "meshes[0] (vase).primitives[0]: has no NORMAL attribute"},
        {"no POSITION", [](sepal::Json& j) { j["meshes"][0]["primitives"][0]["attributes"].erase("POSITION"); },
         "has no POSITION attribute"},
        {"no TANGENT nor UVs",
         [](sepal::Json& j) {
             j["meshes"][0]["primitives"][0]["attributes"].erase("TANGENT");
             j["meshes"][0]["primitives"][0]["attributes"].erase("TEXCOORD_0");
         },
         "has neither TANGENT nor TEXCOORD_0"},
        {"lines", [](sepal::Json& j) { j["meshes"][0]["primitives"][0]["mode"] = 1; }, "mode 1 is not triangles"},
        {"past the buffer", [](sepal::Json& j) { j["accessors"][1]["count"] = 100000; }, "NORMAL: 100000 elements reach past"},
        {"normals as VEC2", [](sepal::Json& j) { j["accessors"][1]["type"] = "VEC2"; }, "NORMAL: expected VEC3"},
        {"index past the vertices", [](sepal::Json& j) { j["accessors"][0]["count"] = 10, j["accessors"][1]["count"] = 10,
                                                         j["accessors"][2]["count"] = 10, j["accessors"][3]["count"] = 10; },
         "indices: index"},
        {"Draco", [](sepal::Json& j) { j["extensionsRequired"] = {"KHR_draco_mesh_compression"}; j["extensionsUsed"] = {"KHR_draco_mesh_compression"}; },
         "needs extension KHR_draco_mesh_compression"},
        {"no triangles", [](sepal::Json& j) { j["scenes"][0]["nodes"] = sepal::Json::array(); }, "no triangles"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.what);
        sepal::Json j = vase_json();
        c.edit(j);
        CHECK_FALSE(load_edited(j, &m, &err));
        CAPTURE(err);
        CHECK(err.find(c.says) != std::string::npos);
    }
    const std::string dir = sepal_test::temp_dir();
    std::ofstream(dir + "/junk.gltf") << "{ not json";
    CHECK_FALSE(sepal::load_gltf_mesh(dir + "/junk.gltf", &m, &err));
    CHECK(err.find("not a valid glTF 2.0 file") != std::string::npos);
    std::ofstream(dir + "/junk.glb") << "glTF\x02\0\0\0 truncated";
    CHECK_FALSE(sepal::load_gltf_mesh(dir + "/junk.glb", &m, &err));
    CHECK(err.find("not a valid glTF 2.0 binary") != std::string::npos);
    CHECK_FALSE(sepal::load_gltf_mesh(dir + "/absent.gltf", &m, &err));
    CHECK(err.find("absent.gltf") != std::string::npos);
}
