#include "reference/surface.h"

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "sepal/sepal_raster.h"

namespace sepal {
namespace {

void store_fragment(void* user, int x, int y, float depth, const float* v) {
    auto* g = static_cast<SurfaceBuffer*>(user);
    const size_t p = size_t(y) * g->width + x;
    std::copy(v, v + SurfaceBuffer::kVaryings, g->varyings.begin() + p * SurfaceBuffer::kVaryings);
    g->covered[p] = 1;
    g->depth[p] = depth;
}

}  // namespace

glm::dvec3 SurfacePoint::local(const glm::dvec3& w) const {
    return glm::dvec3(glm::dot(w, t), glm::dot(w, s), glm::dot(w, n));
}
glm::dvec3 SurfacePoint::world(const glm::dvec3& w) const { return w.x * t + w.y * s + w.z * n; }

bool rasterize_surface(const sepal_scene& scene, const sepal_mesh& mesh, int width, int height,
                       SurfaceBuffer* out, std::string* err, float dx, float dy) {
    float clip_from_world[16];
    if (!clip_from_scene(scene, width, height, clip_from_world, err)) return false;
    return rasterize_surface_clip(clip_from_world, mesh, width, height, out, err, dx, dy);
}

bool clip_from_scene(const sepal_scene& scene, int width, int height, float out[16], std::string* err) {
    float view[16], proj[16];
    sepal_error e = {};
    if (sepal_scene_matrices(&scene, width, height, view, proj, &e) != SEPAL_OK) {
        if (err) *err = e.message;
        return false;
    }
    const glm::mat4 clip = glm::make_mat4(proj) * glm::make_mat4(view);
    std::copy(glm::value_ptr(clip), glm::value_ptr(clip) + 16, out);
    return true;
}

bool rasterize_surface_clip(const float clip_from_mesh[16], const sepal_mesh& mesh, int width, int height,
                            SurfaceBuffer* out, std::string* err, float dx, float dy) {
    constexpr int kV = SurfaceBuffer::kVaryings;
    sepal_error e = {};
    if (!mesh.vertices || !mesh.indices || mesh.vertex_count < 1) {
        if (err) *err = "render exact: empty mesh";
        return false;
    }
    const glm::mat4 clip_from_world = glm::make_mat4(clip_from_mesh);
    std::vector<float> clip(size_t(mesh.vertex_count) * 4), vary(size_t(mesh.vertex_count) * kV);
    for (int i = 0; i < mesh.vertex_count; ++i) {
        const sepal_vertex& v = mesh.vertices[i];
        glm::vec4 c = clip_from_world * glm::vec4(v.position[0], v.position[1], v.position[2], 1.0f);
        // Sampling at the pixel centre + (dx, dy) is sampling the centre of a shifted image.
        c.x -= 2.0f * dx / float(width) * c.w;
        c.y -= 2.0f * dy / float(height) * c.w;
        std::copy(&c.x, &c.x + 4, clip.begin() + size_t(i) * 4);
        float* dst = &vary[size_t(i) * kV];
        std::copy(v.position, v.position + 3, dst);
        std::copy(v.normal, v.normal + 3, dst + 3);
        std::copy(v.tangent, v.tangent + 4, dst + 6);
        std::copy(v.uv, v.uv + 2, dst + 10);
    }
    out->width = width;
    out->height = height;
    out->varyings.assign(size_t(width) * height * kV, 0.0f);
    out->covered.assign(size_t(width) * height, 0);
    out->depth.assign(size_t(width) * height, 1.0f);
    std::vector<float> depth(size_t(width) * height);
    sepal_raster_target target = {width, height, depth.data()};
    sepal_raster_clear_depth(&target);
    sepal_raster_desc rd = {};
    rd.clip = clip.data();
    rd.vertex_count = mesh.vertex_count;
    rd.varyings = vary.data();
    rd.varying_count = kV;
    rd.varying_stride = kV;
    rd.indices = mesh.indices;
    rd.index_count = mesh.index_count;
    rd.cull = SEPAL_CULL_BACK;
    rd.depth_func = SEPAL_DEPTH_LEQUAL;
    rd.fragment = store_fragment;
    rd.user = out;
    if (sepal_raster_triangles(&target, &rd, &e) != SEPAL_OK) {
        if (err) *err = e.message;
        return false;
    }
    return true;
}

FrameStatus surface_point(const SurfaceBuffer& sb, size_t pixel, SurfacePoint* out) {
    const float* v = &sb.varyings[pixel * SurfaceBuffer::kVaryings];
    out->position = glm::dvec3(v[0], v[1], v[2]);
    out->uv = glm::dvec2(v[10], v[11]);
    const glm::dvec3 n_raw(v[3], v[4], v[5]);
    if (!(glm::dot(n_raw, n_raw) > 1e-24) || !std::isfinite(glm::dot(n_raw, n_raw))) return FrameStatus::BadNormal;
    const glm::dvec3 n = glm::normalize(n_raw);
    glm::dvec3 t(v[6], v[7], v[8]);
    t -= n * glm::dot(n, t);
    FrameStatus status = FrameStatus::Ok;
    if (!(glm::dot(t, t) >= 1e-12) || !std::isfinite(glm::dot(t, t))) {  // NaN tangents too
        status = FrameStatus::TangentFallback;  // any tangent: an axis not parallel to n
        t = std::fabs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        t = glm::normalize(t - n * glm::dot(n, t));
    } else {
        t = glm::normalize(t);
    }
    out->n = n;
    out->t = t;
    out->s = (v[9] < 0 ? -1.0 : 1.0) * glm::cross(n, t);
    return status;
}

}  // namespace sepal
