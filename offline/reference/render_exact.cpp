#include "reference/render_exact.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "sepal/sepal_raster.h"

namespace sepal {
namespace {

constexpr int kVaryings = 12;  // position 3, normal 3, tangent 4, uv 2

struct GBuffer {
    int width;
    std::vector<float> varyings;  // kVaryings per pixel
    std::vector<uint8_t> covered;
};

void store_fragment(void* user, int x, int y, float, const float* v) {
    auto* g = static_cast<GBuffer*>(user);
    const size_t p = size_t(y) * g->width + x;
    std::copy(v, v + kVaryings, g->varyings.begin() + p * kVaryings);
    g->covered[p] = 1;
}

// A spatially constant BRDF.
class Uniform : public SpatialBrdf {
  public:
    explicit Uniform(const Brdf& b) : b_(b) {}
    glm::dvec3 eval(const glm::dvec2&, const glm::dvec3& wi, const glm::dvec3& wo) const override {
        return b_.eval(wi, wo);
    }

  private:
    const Brdf& b_;
};

}  // namespace

bool render_exact(const Brdf& brdf, const sepal_scene& scene, const sepal_mesh& mesh, int width,
                  int height, Image* out, ExactStats* stats, std::string* err) {
    return render_exact_spatial(Uniform(brdf), scene, mesh, width, height, out, stats, err);
}

bool render_exact_spatial(const SpatialBrdf& brdf, const sepal_scene& scene, const sepal_mesh& mesh,
                          int width, int height, Image* out, ExactStats* stats, std::string* err) {
    float view[16], proj[16];
    sepal_error e = {};
    if (sepal_scene_matrices(&scene, width, height, view, proj, &e) != SEPAL_OK) {
        if (err) *err = e.message;
        return false;
    }
    if (!mesh.vertices || !mesh.indices || mesh.vertex_count < 1) {
        if (err) *err = "render exact: empty mesh";
        return false;
    }
    const glm::mat4 clip_from_world = glm::make_mat4(proj) * glm::make_mat4(view);
    std::vector<float> clip(size_t(mesh.vertex_count) * 4), vary(size_t(mesh.vertex_count) * kVaryings);
    for (int i = 0; i < mesh.vertex_count; ++i) {
        const sepal_vertex& v = mesh.vertices[i];
        const glm::vec4 c = clip_from_world * glm::vec4(v.position[0], v.position[1], v.position[2], 1.0f);
        std::copy(&c.x, &c.x + 4, clip.begin() + size_t(i) * 4);
        float* dst = &vary[size_t(i) * kVaryings];
        std::copy(v.position, v.position + 3, dst);
        std::copy(v.normal, v.normal + 3, dst + 3);
        std::copy(v.tangent, v.tangent + 4, dst + 6);
        std::copy(v.uv, v.uv + 2, dst + 10);
    }
    GBuffer g{width, std::vector<float>(size_t(width) * height * kVaryings),
              std::vector<uint8_t>(size_t(width) * height)};
    std::vector<float> depth(size_t(width) * height);
    sepal_raster_target target = {width, height, depth.data()};
    sepal_raster_clear_depth(&target);
    sepal_raster_desc rd = {};
    rd.clip = clip.data();
    rd.vertex_count = mesh.vertex_count;
    rd.varyings = vary.data();
    rd.varying_count = kVaryings;
    rd.varying_stride = kVaryings;
    rd.indices = mesh.indices;
    rd.index_count = mesh.index_count;
    rd.cull = SEPAL_CULL_BACK;
    rd.depth_func = SEPAL_DEPTH_LEQUAL;
    rd.fragment = store_fragment;
    rd.user = &g;
    if (sepal_raster_triangles(&target, &rd, &e) != SEPAL_OK) {
        if (err) *err = e.message;
        return false;
    }

    *out = Image(width, height, 3);
    const glm::dvec3 eye(scene.camera.eye[0], scene.camera.eye[1], scene.camera.eye[2]);
    std::atomic<int64_t> back_facing{0}, degenerate{0}, covered{0};
    // Rows are shaded in interleaved order by each thread; every pixel is written by
    // exactly one thread, so the image does not depend on the thread count.
    auto shade_rows = [&](int first, int step) {
        int64_t bf = 0, dg = 0, cv = 0;
        for (int y = first; y < height; y += step)
            for (int x = 0; x < width; ++x) {
                const size_t p = size_t(y) * width + x;
                float* rgb = &out->data[p * 3];
                if (!g.covered[p]) {
                    std::copy(scene.background, scene.background + 3, rgb);
                    continue;
                }
                ++cv;
                const float* v = &g.varyings[p * kVaryings];
                const glm::dvec3 pos(v[0], v[1], v[2]);
                const glm::dvec3 n_raw(v[3], v[4], v[5]);
                if (!(glm::dot(n_raw, n_raw) > 1e-24) || !std::isfinite(glm::dot(n_raw, n_raw))) {
                    // A zero or non-finite normal: the runtime skips such triangles; so does this.
                    ++dg;
                    std::copy(scene.background, scene.background + 3, rgb);
                    continue;
                }
                const glm::dvec3 n = glm::normalize(n_raw);
                glm::dvec3 t(v[6], v[7], v[8]);
                t -= n * glm::dot(n, t);
                if (!(glm::dot(t, t) >= 1e-12) || !std::isfinite(glm::dot(t, t))) {  // NaN tangents too
                    ++dg;  // any tangent: pick an axis not parallel to n
                    t = std::fabs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
                    t = glm::normalize(t - n * glm::dot(n, t));
                } else {
                    t = glm::normalize(t);
                }
                const glm::dvec3 s = (v[9] < 0 ? -1.0 : 1.0) * glm::cross(n, t);
                auto local = [&](const glm::dvec3& w) {
                    return glm::dvec3(glm::dot(w, t), glm::dot(w, s), glm::dot(w, n));
                };
                const glm::dvec3 wo = local(glm::normalize(eye - pos));
                const glm::dvec2 uv(v[10], v[11]);
                if (wo.z <= 0) ++bf;
                glm::dvec3 sum(0.0);
                for (int l = 0; l < scene.light_count; ++l) {
                    const sepal_light& light = scene.lights[l];
                    const glm::dvec3 lp(light.position[0], light.position[1], light.position[2]);
                    glm::dvec3 to_light;
                    double falloff = 1.0;
                    if (light.type == SEPAL_LIGHT_POINT) {
                        to_light = lp - pos;
                        const double d2 = glm::dot(to_light, to_light);
                        if (!(d2 > 1e-12)) continue;
                        falloff = 1.0 / d2;
                    } else {
                        to_light = lp;
                    }
                    const glm::dvec3 wi = local(glm::normalize(to_light));
                    if (wi.z <= 0 || wo.z <= 0) continue;
                    const glm::dvec3 intensity(light.intensity[0], light.intensity[1], light.intensity[2]);
                    sum += brdf.eval(uv, wi, wo) * wi.z * falloff * intensity;
                }
                for (int c = 0; c < 3; ++c) rgb[c] = float(sum[c]);
            }
        back_facing += bf;
        degenerate += dg;
        covered += cv;
    };
    const int threads = int(std::max(1u, std::min(8u, std::thread::hardware_concurrency())));
    std::vector<std::thread> pool;
    for (int i = 1; i < threads; ++i) pool.emplace_back(shade_rows, i, threads);
    shade_rows(0, threads);
    for (std::thread& th : pool) th.join();
    if (stats) {
        stats->covered_pixels = covered;
        stats->back_facing_pixels = back_facing;
        stats->degenerate_frames = degenerate;
    }
    return true;
}

}  // namespace sepal
