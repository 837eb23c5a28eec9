// runtime meshes: torus and the curved test model (analytic frames), OBJ loading.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "sepal/sepal_rt.h"

namespace {

float dot(const float* a, const float* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Checks every vertex has a unit normal and a unit tangent perpendicular to it.
void check_frames(const sepal_mesh& m) {
    for (int i = 0; i < m.vertex_count; ++i) {
        const sepal_vertex& v = m.vertices[i];
        CHECK(dot(v.normal, v.normal) == doctest::Approx(1.0f).epsilon(1e-5));
        CHECK(dot(v.tangent, v.tangent) == doctest::Approx(1.0f).epsilon(1e-5));
        CHECK(std::fabs(dot(v.normal, v.tangent)) < 1e-5f);
        CHECK(std::fabs(v.tangent[3]) == 1.0f);
    }
}

struct ObjMesh {
    std::vector<sepal_vertex> v;
    std::vector<uint16_t> idx;
    sepal_mesh mesh{};
    sepal_obj_stats stats{};
    sepal_error err{};
    sepal_result load(const std::string& text) {
        sepal_obj_info info;
        sepal_result r = sepal_obj_measure(text.data(), text.size(), &info, &err);
        if (r != SEPAL_OK) return r;
        v.resize(size_t(info.max_vertices));
        idx.resize(size_t(info.max_indices));
        std::vector<char> scratch(info.scratch_bytes);
        mesh = {v.data(), idx.data(), int(v.size()), int(idx.size())};
        return sepal_obj_load(text.data(), text.size(), &mesh, scratch.data(), scratch.size(), &stats, &err);
    }
};

}  // namespace

TEST_CASE("torus and wave: analytic frames, outward normals, consistent winding") {
    std::vector<sepal_vertex> v(33 * 17);
    std::vector<uint16_t> idx(32 * 16 * 6);
    sepal_mesh m = {v.data(), idx.data(), int(v.size()), int(idx.size())};
    sepal_error err = {};
    REQUIRE(sepal_mesh_torus(1.0f, 0.4f, 32, 16, &m, &err) == SEPAL_OK);
    check_frames(m);
    for (int t = 0; t < m.index_count; t += 3) {  // triangle normal agrees with vertex normals
        const float* a = v[idx[size_t(t)]].position;
        const float* b = v[idx[size_t(t) + 1]].position;
        const float* c = v[idx[size_t(t) + 2]].position;
        const float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                            e1[0] * e2[1] - e1[1] * e2[0]};
        CHECK(dot(n, v[idx[size_t(t)]].normal) > 0);
    }
    CHECK(sepal_mesh_torus(0.3f, 0.4f, 32, 16, &m, &err) == SEPAL_ERR_INVALID_ARGUMENT);

    m = {v.data(), idx.data(), int(v.size()), int(idx.size())};
    REQUIRE(sepal_mesh_wave(16, &m, &err) == SEPAL_OK);
    check_frames(m);
    // The normal is perpendicular to the surface: compare with finite differences of the
    // neighbouring vertices of an interior vertex.
    const int row = 17, i = 5 * row + 7;
    const float* p = v[size_t(i)].position;
    const float* px = v[size_t(i) + 1].position;
    const float* py = v[size_t(i) + row].position;
    const float dx[3] = {px[0] - p[0], px[1] - p[1], px[2] - p[2]};
    const float dy[3] = {py[0] - p[0], py[1] - p[1], py[2] - p[2]};
    CHECK(std::fabs(dot(dx, v[size_t(i)].normal)) < 0.02f);
    CHECK(std::fabs(dot(dy, v[size_t(i)].normal)) < 0.02f);
}

TEST_CASE("obj: shared corners unify, quads fan, tangents follow the UVs") {
    ObjMesh o;
    const std::string quad =
        "# a quad in the xy plane, u along +x, v along +y\n"
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "vn 0 0 1\n"
        "f 1/1/1 2/2/1 3/3/1 4/4/1\n";
    REQUIRE_MESSAGE(o.load(quad) == SEPAL_OK, o.err.message);
    CHECK(o.mesh.vertex_count == 4);
    CHECK(o.mesh.index_count == 6);
    CHECK(o.stats.fallback_tangents == 0);
    CHECK(o.stats.computed_normals == 0);
    for (int i = 0; i < 4; ++i) {
        CHECK(o.v[size_t(i)].tangent[0] == doctest::Approx(1.0f));
        CHECK(o.v[size_t(i)].tangent[3] == 1.0f);
    }
    // Mirrored UVs (u along -x): the tangent flips and so does the handedness.
    const std::string mirrored =
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 1 0\nvt 0 0\nvt 0 1\nvt 1 1\n"
        "f 1/1 2/2 3/3 4/4\n";
    REQUIRE(o.load(mirrored) == SEPAL_OK);
    CHECK(o.stats.computed_normals == 4);
    CHECK(o.v[0].normal[2] == doctest::Approx(1.0f));
    CHECK(o.v[0].tangent[0] == doctest::Approx(-1.0f));
    CHECK(o.v[0].tangent[3] == -1.0f);
}

TEST_CASE("obj: negative indices, missing UVs counted, degenerate faces counted") {
    ObjMesh o;
    const std::string text =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n"
        "v 2 0 0\nv 3 0 0\nv 4 0 0\nf 4 5 6\n";  // collinear: zero area
    REQUIRE_MESSAGE(o.load(text) == SEPAL_OK, o.err.message);
    CHECK(o.mesh.vertex_count == 6);
    CHECK(o.stats.fallback_tangents == 6);  // no UVs anywhere
    CHECK(o.stats.degenerate_triangles == 1);
    check_frames(o.mesh);
}

TEST_CASE("obj: bad input is refused with the line named") {
    ObjMesh o;
    struct Case {
        const char* text;
        const char* expect;
    } cases[] = {
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "line 4: position index 4 out of range"},
        {"v 0 0 0\nv 1 0 0\nf 1 2\n", "line 3: a face needs at least 3 corners"},
        {"v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "line 1: expected 3 finite numbers"},
        {"v 0 0 1,5\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "line 1: expected 3 finite numbers"},
        {"v 0 0 1e999\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "line 1: expected 3 finite numbers"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 0\nf 1//1 2//1 3//1\n", "zero-length normal"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/x 2 3\n", "malformed face corner"},
        {"v 0 0 0\n", "no faces"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "out of range"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.text);
        CHECK(o.load(c.text) != SEPAL_OK);
        CHECK_MESSAGE(std::string(o.err.message).find(c.expect) != std::string::npos, o.err.message);
    }
    // Too little storage is a capacity error, not an overflow.
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    sepal_obj_info info;
    sepal_error err;
    REQUIRE(sepal_obj_measure(tri.data(), tri.size(), &info, &err) == SEPAL_OK);
    std::vector<sepal_vertex> v(2);
    std::vector<uint16_t> idx(3);
    std::vector<char> scratch(info.scratch_bytes);
    sepal_mesh m = {v.data(), idx.data(), 2, 3};
    CHECK(sepal_obj_load(tri.data(), tri.size(), &m, scratch.data(), scratch.size(), nullptr, &err) ==
          SEPAL_ERR_CAPACITY);
    m.vertex_count = 3;
    CHECK(sepal_obj_load(tri.data(), tri.size(), &m, scratch.data(), 8, nullptr, &err) == SEPAL_ERR_CAPACITY);
}

TEST_CASE("obj: a UTF-8 byte order mark and CR-only line endings read like plain LF") {
    const std::string lf = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\nf 1//1 2//1 3//1\nf 1//1 3//1 4//1\n";
    ObjMesh plain;
    REQUIRE(plain.load(lf) == SEPAL_OK);
    std::string cr = lf, crlf;
    for (char& c : cr)
        if (c == '\n') c = '\r';
    for (char c : lf) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    for (const std::string& text : {"\xEF\xBB\xBF" + lf, cr, "\xEF\xBB\xBF" + cr, crlf}) {
        ObjMesh m;
        REQUIRE_MESSAGE(m.load(text) == SEPAL_OK, m.err.message);
        REQUIRE(m.mesh.vertex_count == plain.mesh.vertex_count);
        REQUIRE(m.mesh.index_count == plain.mesh.index_count);
        for (int i = 0; i < m.mesh.vertex_count; ++i)
            for (int k = 0; k < 3; ++k) CHECK(m.v[size_t(i)].position[k] == plain.v[size_t(i)].position[k]);
        for (int i = 0; i < m.mesh.index_count; ++i) CHECK(m.idx[size_t(i)] == plain.idx[size_t(i)]);
    }
    // Line numbers in messages count CR-only lines too.
    ObjMesh bad;
    CHECK(bad.load("v 0 0 0\rv 1 0 0\rf 1 2 7\r") != SEPAL_OK);
    CHECK_MESSAGE(std::string(bad.err.message).find("obj line 3") != std::string::npos, bad.err.message);
}
