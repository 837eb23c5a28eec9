#include "reference/render_exact.h"
#include "util/progress.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "reference/surface.h"

namespace sepal {
namespace {

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
                  int height, Image* out, ExactStats* stats, std::string* err, bool progress) {
    return render_exact_spatial(Uniform(brdf), scene, mesh, width, height, out, stats, err, progress);
}

bool render_exact_spatial(const SpatialBrdf& brdf, const sepal_scene& scene, const sepal_mesh& mesh,
                          int width, int height, Image* out, ExactStats* stats, std::string* err, bool progress) {
    SurfaceBuffer g;
    if (!rasterize_surface(scene, mesh, width, height, &g, err)) return false;
    *out = Image(width, height, 3);
    const glm::dvec3 eye(scene.camera.eye[0], scene.camera.eye[1], scene.camera.eye[2]);
    std::atomic<int64_t> back_facing{0}, degenerate{0}, covered{0};
    // Rows are shaded in interleaved order by each thread; every pixel is written by
    // exactly one thread, so the image does not depend on the thread count.
    Progress rows_done(progress, "sepal render: exact", size_t(height));
    auto shade_rows = [&](int first, int step) {
        int64_t bf = 0, dg = 0, cv = 0;
        for (int y = first; y < height; rows_done.advance(), y += step)
            for (int x = 0; x < width; ++x) {
                const size_t p = size_t(y) * width + x;
                float* rgb = &out->data[p * 3];
                if (!g.covered[p]) {
                    std::copy(scene.background, scene.background + 3, rgb);
                    continue;
                }
                ++cv;
                SurfacePoint sp;
                const FrameStatus fs = surface_point(g, p, &sp);
                if (fs == FrameStatus::BadNormal) {
                    // A zero or non-finite normal: the runtime skips such triangles; so does this.
                    ++dg;
                    std::copy(scene.background, scene.background + 3, rgb);
                    continue;
                }
                if (fs == FrameStatus::TangentFallback) ++dg;
                const glm::dvec3 pos = sp.position;
                const glm::dvec3 wo = sp.local(glm::normalize(eye - pos));
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
                    const glm::dvec3 wi = sp.local(glm::normalize(to_light));
                    if (wi.z <= 0 || wo.z <= 0) continue;
                    const glm::dvec3 intensity(light.intensity[0], light.intensity[1], light.intensity[2]);
                    sum += brdf.eval(sp.uv, wi, wo) * wi.z * falloff * intensity;
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
