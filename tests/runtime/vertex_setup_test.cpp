// The per-vertex set-up (runtime/src/vertex_setup.cpp): the batched, vectorized path gives
// the one-vertex-at-a-time reference's results bit for bit, on meshes where every branch of
// the reference is taken (unusable vertices, fallback frames, the eye and a light at a
// vertex, the horizon band, overflowing irradiance) and for every parameterization, map,
// light kind and count, swapped or not.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "sepal/sepal_scene.h"
#include "mesh_view.h"
#include "vertex_setup.h"

namespace {

struct Mesh {
    std::vector<sepal_vertex> v;
    std::vector<uint16_t> i;
    sepal_mesh mesh() {
        sepal_mesh m = {};
        m.vertices = v.data();
        m.vertex_count = int(v.size());
        m.indices = i.data();
        m.index_count = int(i.size());
        return m;
    }
};

Mesh sphere(int slices, int stacks) {
    Mesh m;
    m.v.resize(size_t(slices + 1) * size_t(stacks + 1));
    m.i.resize(size_t(slices) * size_t(stacks) * 6);
    sepal_mesh sm = {};
    sm.vertices = m.v.data();
    sm.vertex_count = int(m.v.size());
    sm.indices = m.i.data();
    sm.index_count = int(m.i.size());
    sepal_error e = {};
    REQUIRE(sepal_mesh_sphere(slices, stacks, &sm, &e) == SEPAL_OK);
    m.v.resize(size_t(sm.vertex_count));
    m.i.resize(size_t(sm.index_count));
    return m;
}

// A sphere with odd vertices mixed in: each kind the reference handles by a branch.
Mesh odd_sphere(const sepal_scene& scene, uint32_t seed) {
    Mesh m = sphere(24, 12);
    std::mt19937 rng(seed);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    for (size_t k = 0; k < m.v.size(); ++k) {
        sepal_vertex& v = m.v[k];
        switch (rng() % 24) {
            case 0: v.normal[1] = nan; break;                      // unusable
            case 1: v.position[2] = inf; break;                    // unusable
            case 2: v.normal[0] = v.normal[1] = v.normal[2] = 0.0f; break;
            case 3: for (int c = 0; c < 3; ++c) v.tangent[c] = 0.0f; break;  // tangent fallback
            case 4: for (int c = 0; c < 3; ++c) v.tangent[c] = v.normal[c]; break;
            case 5: v.tangent[3] = nan; break;                     // handedness fallback
            case 6: v.tangent[3] = -1.0f; break;
            case 7: for (int c = 0; c < 3; ++c) v.position[c] = scene.camera.eye[c]; break;   // eye at the vertex
            case 8: for (int c = 0; c < 3; ++c) v.position[c] = scene.lights[0].position[c]; break;  // light at it
            case 9: for (int c = 0; c < 3; ++c) v.position[c] = scene.lights[0].position[c] + 1e-7f; break;
            case 10: for (int c = 0; c < 3; ++c) v.normal[c] *= 1e-16f; break;  // tiny, still usable
            case 11: for (int c = 0; c < 3; ++c) v.normal[c] *= 1e18f; break;
            case 12: for (int c = 0; c < 3; ++c) v.position[c] = scene.lights[3].position[c] + 0.01f; break;  // E overflows
            default: break;
        }
    }
    return m;
}

void expect_same(const srt::VertexSetupResult& a, const srt::VertexSetupResult& b, const std::vector<float>& sa,
                 const std::vector<float>& sb) {
    CHECK(a.max_irradiance_sum == b.max_irradiance_sum);
    CHECK(a.max_irradiance_single == b.max_irradiance_single);
    CHECK(a.max_lit_sum == b.max_lit_sum);
    CHECK(a.max_lit_single == b.max_lit_single);
    CHECK(a.below_horizon == b.below_horizon);
    CHECK(a.fallback_tangents == b.fallback_tangents);
    CHECK(a.bad_vertices == b.bad_vertices);
    CHECK(a.param_fallbacks == b.param_fallbacks);
    CHECK(a.nonfinite_clamped == b.nonfinite_clamped);
    REQUIRE(sa.size() == sb.size());
    size_t differ = 0, first = 0;
    for (size_t k = 0; k < sa.size(); ++k)
        if (std::memcmp(&sa[k], &sb[k], sizeof(float)) != 0 && differ++ == 0) first = k;
    CHECK_MESSAGE(differ == 0, differ, " scratch floats differ, the first at ", first, ": ", sa[first], " vs ",
                  sb[first]);
}

// Runs both paths on the same scratch contents (sentinels where neither writes) and compares.
void compare(const srt::MeshView& mesh, const sepal_scene& scene, sepal_param p, sepal_hemi_map m, bool swapped) {
    const size_t floats = srt::scratch_floats(mesh.vertex_count, scene.light_count);
    std::vector<float> a(floats, -7.0f), b(floats, -7.0f);
    const srt::VertexSetupResult ra = srt::setup_vertices(p, m, mesh, scene, a.data(), swapped);
    const srt::VertexSetupResult rb = srt::setup_vertices_reference(p, m, mesh, scene, b.data(), swapped);
    expect_same(ra, rb, a, b);
}

}  // namespace

TEST_CASE("vertex set-up: the batched path is the reference's, bit for bit") {
    sepal_scene scene;
    sepal_scene_default(&scene);
    scene.light_count = 4;
    for (int l = 0; l < 4; ++l) {
        scene.lights[l].type = l == 2 ? SEPAL_LIGHT_DIRECTIONAL : SEPAL_LIGHT_POINT;
        scene.lights[l].position[0] = 2.0f * std::cos(float(l));
        scene.lights[l].position[1] = -2.5f + float(l);
        scene.lights[l].position[2] = 2.0f - float(l);
        for (int c = 0; c < 3; ++c) scene.lights[l].intensity[c] = 10.0f * float(c + 1);
    }
    scene.lights[3].intensity[1] = 3e38f;  // overflows over a short distance
    const sepal_param params[] = {SEPAL_PARAM_IV, SEPAL_PARAM_GS_HALF, SEPAL_PARAM_VH, SEPAL_PARAM_RUSINKIEWICZ,
                                  SEPAL_PARAM_ELEV_AZIM, SEPAL_PARAM_AXIS, SEPAL_PARAM_GS_MIRROR};
    const sepal_hemi_map maps[] = {SEPAL_MAP_XY, SEPAL_MAP_PARABOLIC};
    for (uint32_t seed : {1u, 2u, 3u}) {
        Mesh odd = odd_sphere(scene, seed);
        // 325 vertices: batches of 32 and a remainder.
        for (int lights : {1, 2, 4}) {
            sepal_scene s = scene;
            s.light_count = lights;
            for (sepal_param p : params)
                for (sepal_hemi_map m : maps)
                    for (bool swapped : {false, true}) {
                        CAPTURE(seed);
                        CAPTURE(lights);
                        CAPTURE(int(p));
                        CAPTURE(int(m));
                        CAPTURE(swapped);
                        compare(odd.mesh(), s, p, m, swapped);
                    }
        }
    }
    // The default scene's sphere (the benchmark's), where nearly every lane takes the batch.
    Mesh big = sphere(SEPAL_SCENE_SPHERE_SLICES, SEPAL_SCENE_SPHERE_STACKS);
    sepal_scene s;
    sepal_scene_default(&s);
    for (sepal_param p : {SEPAL_PARAM_IV, SEPAL_PARAM_GS_HALF, SEPAL_PARAM_VH, SEPAL_PARAM_AXIS, SEPAL_PARAM_GS_MIRROR})
        compare(big.mesh(), s, p, SEPAL_MAP_XY, false);
    // Counts the batches leave to the reference are still counted: an odd mesh's statistics
    // are not zero (the comparison above would pass trivially if both were).
    Mesh odd = odd_sphere(scene, 1);
    std::vector<float> scratch(srt::scratch_floats(odd.mesh().vertex_count, 4));
    const srt::VertexSetupResult r =
        srt::setup_vertices(SEPAL_PARAM_GS_HALF, SEPAL_MAP_XY, odd.mesh(), scene, scratch.data());
    CHECK(r.bad_vertices > 0);
    CHECK(r.fallback_tangents > 0);
    CHECK(r.below_horizon > 0);
    CHECK(r.nonfinite_clamped > 0);
    CHECK(r.max_irradiance_sum > 0.0f);
}

TEST_CASE("vertex set-up: an empty mesh and a mesh of one vertex") {
    sepal_scene s;
    sepal_scene_default(&s);
    Mesh one = sphere(3, 2);
    one.v.resize(1);
    one.i.clear();
    compare(one.mesh(), s, SEPAL_PARAM_GS_HALF, SEPAL_MAP_XY, false);
    Mesh none;
    std::vector<float> scratch(1);
    const srt::VertexSetupResult r =
        srt::setup_vertices(SEPAL_PARAM_GS_HALF, SEPAL_MAP_XY, none.mesh(), s, scratch.data());
    CHECK(r.bad_vertices == 0);
    CHECK(r.max_irradiance_sum == 0.0f);
}

TEST_CASE("vertex set-up: the engine's strided vertices under an affine model, batched and reference alike") {
    sepal_scene scene;
    sepal_scene_default(&scene);
    scene.light_count = 2;
    scene.lights[1].type = SEPAL_LIGHT_DIRECTIONAL;
    for (int c = 0; c < 3; ++c) scene.lights[1].position[c] = 0.3f * float(c + 1), scene.lights[1].intensity[c] = 2.0f;
    Mesh odd = odd_sphere(scene, 7);
    // The vertices interleaved with foreign fields: 20 floats a vertex, sepal's 12 spread out.
    const int n = int(odd.v.size()), stride = 20;
    std::vector<float> buffer(size_t(n) * stride, std::numeric_limits<float>::quiet_NaN());
    for (int i = 0; i < n; ++i) {
        float* b = buffer.data() + size_t(i) * stride;
        std::memcpy(b + 1, odd.v[size_t(i)].position, 3 * sizeof(float));
        std::memcpy(b + 5, odd.v[size_t(i)].normal, 3 * sizeof(float));
        std::memcpy(b + 9, odd.v[size_t(i)].tangent, 4 * sizeof(float));
        std::memcpy(b + 15, odd.v[size_t(i)].uv, 2 * sizeof(float));
    }
    sepal_vertex_data d = {};
    const int bytes = stride * int(sizeof(float));
    d.position = {buffer.data(), 4, bytes};
    d.normal = {buffer.data(), 20, bytes};
    d.tangent = {buffer.data(), 36, bytes};
    d.uv = {buffer.data(), 60, bytes};
    d.vertex_count = n;
    d.indices = odd.i.data();
    d.index_count = int(odd.i.size());
    srt::MeshView strided;
    sepal_error e = {};
    REQUIRE_MESSAGE(srt::mesh_view(d, &strided, &e) == SEPAL_OK, e.message);
    CHECK(strided.direct == nullptr);
    // Untransformed, the strided view is the sepal_mesh's, bit for bit.
    {
        const srt::MeshView direct(odd.mesh());
        const size_t floats = srt::scratch_floats(n, scene.light_count);
        std::vector<float> a(floats, -7.0f), b(floats, -7.0f);
        const srt::VertexSetupResult ra = srt::setup_vertices(SEPAL_PARAM_GS_HALF, SEPAL_MAP_XY, strided, scene, a.data());
        const srt::VertexSetupResult rb = srt::setup_vertices(SEPAL_PARAM_GS_HALF, SEPAL_MAP_XY, direct, scene, b.data());
        expect_same(ra, rb, a, b);
    }
    // A shear and a non-uniform scale: every vertex moved as it is read, in the batch and
    // in the reference alike.
    srt::MeshView moved = strided;
    moved.transform = true;
    const float m[12] = {0.8f, 0.1f, 0.0f, 0.3f, 0.5f, 0.0f, 0.0f, 0.2f, 1.3f, 0.1f, -0.2f, 0.3f};
    std::memcpy(moved.m, m, sizeof m);
    // The inverse transpose of m's 3 x 3 (any invertible matrix: the set-up takes it as given).
    const float n9[9] = {1.3f, -0.2f, 0.05f, -0.1f, 2.1f, -0.3f, 0.0f, 0.0f, 0.8f};
    std::memcpy(moved.n, n9, sizeof n9);
    for (sepal_param p : {SEPAL_PARAM_IV, SEPAL_PARAM_GS_HALF, SEPAL_PARAM_VH, SEPAL_PARAM_AXIS, SEPAL_PARAM_GS_MIRROR})
        for (sepal_hemi_map map : {SEPAL_MAP_XY, SEPAL_MAP_PARABOLIC}) {
            CAPTURE(int(p));
            CAPTURE(int(map));
            compare(moved, scene, p, map, false);
        }
    // The moved vertex is the model's image of the given one.
    sepal_vertex v;
    moved.load(3, &v);
    const float* q = odd.v[3].position;
    for (int r = 0; r < 3; ++r)
        CHECK(v.position[r] == doctest::Approx(m[r] * q[0] + m[3 + r] * q[1] + m[6 + r] * q[2] + m[9 + r]));
}
