#include "acquire/object.h"

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "sepal/sepal_raster.h"

namespace sepal {

glm::vec3 SurfaceAtlas::local(int texel, const glm::dvec3& d) const {
    const glm::vec3 w(d);
    const size_t i = size_t(texel);
    return glm::vec3(glm::dot(w, tangent[i]), glm::dot(w, bitangent[i]), glm::dot(w, normal[i]));
}

int SurfaceAtlas::step(int texel, int dx, int dy) const {
    int x = texel % res + dx, y = texel / res + dy;
    if (x < 0 || x >= res) {
        if (!wrap_u) return -1;
        x = (x % res + res) % res;
    }
    if (y < 0 || y >= res) {
        if (!wrap_v) return -1;
        y = (y % res + res) % res;
    }
    return y * res + x;
}

sepal_mesh AcqObject::mesh() const {
    sepal_mesh m;
    m.vertices = const_cast<sepal_vertex*>(vertices.data());
    m.indices = const_cast<uint16_t*>(indices.data());
    m.vertex_count = int(vertices.size());
    m.index_count = int(indices.size());
    return m;
}

namespace {

// Sets texel i to the surface frame at barycentric weights w of triangle v; leaves it unset
// where the normal vanishes.
void atlas_texel(const sepal_vertex* const v[3], const double w[3], SurfaceAtlas* a, size_t i) {
    glm::vec3 pos(0), nrm(0), tan(0);
    float hand = 0;
    for (int k = 0; k < 3; ++k) {
        pos += float(w[k]) * glm::vec3(v[k]->position[0], v[k]->position[1], v[k]->position[2]);
        nrm += float(w[k]) * glm::vec3(v[k]->normal[0], v[k]->normal[1], v[k]->normal[2]);
        tan += float(w[k]) * glm::vec3(v[k]->tangent[0], v[k]->tangent[1], v[k]->tangent[2]);
        hand += float(w[k]) * v[k]->tangent[3];
    }
    if (!(glm::dot(nrm, nrm) > 1e-12f)) return;
    nrm = glm::normalize(nrm);
    tan -= nrm * glm::dot(nrm, tan);
    if (!(glm::dot(tan, tan) > 1e-12f)) {
        tan = std::fabs(nrm.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
        tan = tan - nrm * glm::dot(nrm, tan);
    }
    tan = glm::normalize(tan);
    a->position[i] = pos;
    a->normal[i] = nrm;
    a->tangent[i] = tan;
    a->bitangent[i] = (hand < 0 ? -1.0f : 1.0f) * glm::cross(nrm, tan);
    a->valid[i] = 1;
}

// The point of triangle (p0, p1, p2) closest to c, as barycentric weights; its distance.
double closest_on_triangle(const glm::dvec2& p0, const glm::dvec2& p1, const glm::dvec2& p2, const glm::dvec2& c,
                           double w[3]) {
    const glm::dvec2 p[3] = {p0, p1, p2};
    double best = 1e300;
    for (int e = 0; e < 3; ++e) {
        const glm::dvec2 a = p[e], b = p[(e + 1) % 3], ab = b - a;
        const double len2 = glm::dot(ab, ab);
        const double t = len2 > 0 ? std::min(1.0, std::max(0.0, glm::dot(c - a, ab) / len2)) : 0.0;
        const double d = glm::length(a + t * ab - c);
        if (d < best) {
            best = d;
            w[e] = 1 - t, w[(e + 1) % 3] = t, w[(e + 2) % 3] = 0;
        }
    }
    return best;
}

}  // namespace

bool build_atlas(const sepal_mesh& mesh, int res, SurfaceAtlas* out, std::string* err) {
    if (res < 8 || res > 1024) {
        if (err) *err = "atlas: resolution " + std::to_string(res) + " is outside 8..1024";
        return false;
    }
    SurfaceAtlas a;
    a.res = res;
    const size_t n = size_t(res) * res;
    a.position.assign(n, glm::vec3(0));
    a.normal.assign(n, glm::vec3(0, 0, 1));
    a.tangent.assign(n, glm::vec3(1, 0, 0));
    a.bitangent.assign(n, glm::vec3(0, 1, 0));
    a.valid.assign(n, 0);
    // Texels a triangle overlaps without holding their centre (its nearest point within half a
    // texel's diagonal): filled after every centre is taken, from the nearest triangle. Without
    // them the sliver triangles at the sphere's poles left texels the renders look up unset,
    // drawn unlit in photographs.
    struct Nearest {
        double dist = 0.7072;  // half a texel's diagonal, and a little
        int triangle = -1;
        double w[3] = {0, 0, 0};
    };
    std::vector<Nearest> edge(n);
    auto corners = [&mesh](int t, const sepal_vertex* v[3]) {
        for (int k = 0; k < 3; ++k) v[k] = &mesh.vertices[mesh.indices[t + k]];
    };
    for (int t = 0; t + 2 < mesh.index_count; t += 3) {
        const sepal_vertex* v[3];
        corners(t, v);
        const glm::dvec2 p0(v[0]->uv[0] * res, v[0]->uv[1] * res), p1(v[1]->uv[0] * res, v[1]->uv[1] * res),
            p2(v[2]->uv[0] * res, v[2]->uv[1] * res);
        const double area = (p1.x - p0.x) * (p2.y - p0.y) - (p2.x - p0.x) * (p1.y - p0.y);
        if (!(std::fabs(area) > 1e-12)) continue;  // degenerate in UV: no texel
        const int x0 = std::max(0, int(std::floor(std::min({p0.x, p1.x, p2.x}))) - 1);
        const int x1 = std::min(res - 1, int(std::ceil(std::max({p0.x, p1.x, p2.x}))));
        const int y0 = std::max(0, int(std::floor(std::min({p0.y, p1.y, p2.y}))) - 1);
        const int y1 = std::min(res - 1, int(std::ceil(std::max({p0.y, p1.y, p2.y}))));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const size_t i = size_t(y) * res + x;
                if (a.valid[i]) continue;
                const glm::dvec2 c(x + 0.5, y + 0.5);
                // Barycentric weights; a small slack so centres on shared edges are taken.
                double w[3];
                w[0] = ((p1.x - c.x) * (p2.y - c.y) - (p2.x - c.x) * (p1.y - c.y)) / area;
                w[1] = ((p2.x - c.x) * (p0.y - c.y) - (p0.x - c.x) * (p2.y - c.y)) / area;
                w[2] = 1 - w[0] - w[1];
                if (w[0] >= -1e-9 && w[1] >= -1e-9 && w[2] >= -1e-9) {
                    atlas_texel(v, w, &a, i);
                    continue;
                }
                Nearest& e = edge[i];
                const double d = closest_on_triangle(p0, p1, p2, c, w);
                if (d < e.dist) e.dist = d, e.triangle = t, std::copy(w, w + 3, e.w);
            }
    }
    for (size_t i = 0; i < n; ++i)
        if (!a.valid[i] && edge[i].triangle >= 0) {
            const sepal_vertex* v[3];
            corners(edge[i].triangle, v);
            atlas_texel(v, edge[i].w, &a, i);
        }
    for (size_t i = 0; i < n; ++i)
        if (a.valid[i]) a.texels.push_back(int(i));
    if (a.texels.empty()) {
        if (err) *err = "atlas: no triangle covers a texel (missing or degenerate UVs)";
        return false;
    }
    *out = std::move(a);
    return true;
}

bool make_object(const std::string& name, int atlas_res, AcqObject* out, std::string* err) {
    AcqObject o;
    o.name = name;
    sepal_error e = {};
    sepal_result r;
    // Tessellations fine enough that the flat triangles do not show in 256^2 renders.
    if (name == "sphere") {
        o.vertices.resize(65 * 33);
        o.indices.resize(64 * 32 * 6);
        sepal_mesh m = {o.vertices.data(), o.indices.data(), int(o.vertices.size()), int(o.indices.size())};
        r = sepal_mesh_sphere(64, 32, &m, &e);
        o.vertices.resize(size_t(m.vertex_count));
        o.indices.resize(size_t(m.index_count));
        o.radius = 1.0;
    } else if (name == "torus") {
        o.vertices.resize(97 * 49);
        o.indices.resize(96 * 48 * 6);
        sepal_mesh m = {o.vertices.data(), o.indices.data(), int(o.vertices.size()), int(o.indices.size())};
        r = sepal_mesh_torus(0.7f, 0.3f, 96, 48, &m, &e);
        o.vertices.resize(size_t(m.vertex_count));
        o.indices.resize(size_t(m.index_count));
        o.radius = 1.0;
    } else if (name == "wave") {
        o.vertices.resize(65 * 65);
        o.indices.resize(64 * 64 * 6);
        sepal_mesh m = {o.vertices.data(), o.indices.data(), int(o.vertices.size()), int(o.indices.size())};
        r = sepal_mesh_wave(64, &m, &e);
        o.vertices.resize(size_t(m.vertex_count));
        o.indices.resize(size_t(m.index_count));
        o.radius = std::sqrt(2.0 + 0.35 * 0.35);
        o.closed = false;
    } else {
        if (err) *err = "object: unknown object '" + name + "' (sphere, torus, wave)";
        return false;
    }
    if (r != SEPAL_OK) {
        if (err) *err = std::string("object: ") + e.message;
        return false;
    }
    if (!build_atlas(o.mesh(), atlas_res, &o.atlas, err)) return false;
    o.atlas.wrap_u = name != "wave";
    o.atlas.wrap_v = name == "torus";
    *out = std::move(o);
    return true;
}

namespace {

struct DepthTarget {
    int res;
    glm::vec3 point;
    std::vector<float> dist;  // distance to the point, row 0 = top
};

// The distance is interpolated as a varying: exact at the vertices, and within a small
// fraction of a triangle's size between them, far below the bias.
void store_distance(void* user, int x, int y, float, const float* v) {
    auto* t = static_cast<DepthTarget*>(user);
    t->dist[size_t(y) * t->res + x] = v[0];
}

}  // namespace

void view_from_point(const AcqObject& obj, const glm::dvec3& point, int depth_res, PointView* out) {
    const SurfaceAtlas& a = obj.atlas;
    const size_t n = a.position.size();
    out->point = point;
    out->ok.assign(n, 0);
    out->local.assign(n, glm::vec3(0));
    out->dist2.assign(n, 0.0f);
    const int res = std::min(4096, std::max(64, depth_res > 0 ? depth_res : kDefaultDepthRes));
    const double d = glm::length(point);
    if (!(d > obj.radius * 1.01)) return;  // inside the bounding sphere: no view
    // A square frustum just around the bounding sphere.
    const double half = std::asin(obj.radius / d) * 1.05;
    const glm::dvec3 up = std::fabs(point.z) < 0.99 * d ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
    const glm::dmat4 view = glm::lookAt(point, glm::dvec3(0), up);
    const double z_near = std::max(1e-3, d - obj.radius * 1.02), z_far = d + obj.radius * 1.02;
    const glm::dmat4 proj = glm::perspective(2 * half, 1.0, z_near, z_far);
    const glm::dmat4 clip_from_world = proj * view;

    const sepal_mesh mesh = obj.mesh();
    std::vector<float> clip(size_t(mesh.vertex_count) * 4), vary(size_t(mesh.vertex_count));
    for (int i = 0; i < mesh.vertex_count; ++i) {
        const float* p = mesh.vertices[i].position;
        const glm::dvec4 c = clip_from_world * glm::dvec4(p[0], p[1], p[2], 1.0);
        for (int k = 0; k < 4; ++k) clip[size_t(i) * 4 + size_t(k)] = float(c[k]);
        vary[size_t(i)] = float(glm::length(glm::dvec3(p[0], p[1], p[2]) - point));
    }
    DepthTarget target{res, glm::vec3(point), std::vector<float>(size_t(res) * res, 1e30f)};
    std::vector<float> depth(size_t(res) * res);
    sepal_raster_target rt = {res, res, depth.data()};
    sepal_raster_clear_depth(&rt);
    sepal_raster_desc rd = {};
    rd.clip = clip.data();
    rd.vertex_count = mesh.vertex_count;
    rd.varyings = vary.data();
    rd.varying_count = 1;
    rd.varying_stride = 1;
    rd.indices = mesh.indices;
    rd.index_count = mesh.index_count;
    // Closed meshes hide behind their front faces; an open surface (the wave) also with its back.
    rd.cull = obj.closed ? SEPAL_CULL_BACK : SEPAL_CULL_NONE;
    rd.depth_func = SEPAL_DEPTH_LEQUAL;
    rd.fragment = store_distance;
    rd.user = &target;
    sepal_error e = {};
    if (sepal_raster_triangles(&rt, &rd, &e) != SEPAL_OK) return;  // nothing visible

    // Bias: a few depth-map pixels' worth of surface, so a texel does not hide itself.
    const double pixel = 2 * d * std::tan(half) / res;
    for (int i : a.texels) {
        const size_t t = size_t(i);
        const glm::dvec3 p(a.position[t]);
        const glm::dvec3 to = point - p;
        const double len2 = glm::dot(to, to);
        const glm::dvec3 dir = to / std::sqrt(len2);
        const glm::vec3 l = a.local(i, dir);
        if (!(l.z > 0)) continue;
        const glm::dvec4 c = clip_from_world * glm::dvec4(p, 1.0);
        if (!(c.w > 0)) continue;
        const double nx = c.x / c.w, ny = c.y / c.w;
        if (std::fabs(nx) >= 1 || std::fabs(ny) >= 1) continue;
        const double fx = (nx + 1) * 0.5 * res - 0.5, fy = (1 - ny) * 0.5 * res - 0.5;
        const int x0 = std::max(0, std::min(res - 2, int(std::floor(fx))));
        const int y0 = std::max(0, std::min(res - 2, int(std::floor(fy))));
        // The farthest of the 2x2 nearest map pixels: lenient at the object's own silhouette.
        float far = 0;
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) far = std::max(far, target.dist[size_t(y0 + dy) * res + size_t(x0 + dx)]);
        const double dist = std::sqrt(len2);
        const double bias = 0.005 * obj.radius + 2 * pixel * dist / d / std::max(0.2, double(l.z));
        if (dist > double(far) + bias) continue;
        out->ok[t] = 1;
        out->local[t] = l;
        out->dist2[t] = float(len2);
    }
}

}  // namespace sepal
