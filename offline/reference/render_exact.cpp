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
                  int height, Image* out, ExactStats* stats, std::string* err, bool progress, int supersample) {
    return render_exact_spatial(Uniform(brdf), scene, mesh, width, height, out, stats, err, progress, supersample);
}

namespace {

enum SampleFlags { kBackFacing = 1, kDegenerate = 2 };

// Radiance at one surface sample; false where the normal is bad (not shaded).
bool shade(const SpatialBrdf& brdf, const sepal_scene& scene, const glm::dvec3& eye, const SurfaceBuffer& g,
           size_t p, glm::dvec3* radiance, int* flags) {
    SurfacePoint sp;
    const FrameStatus fs = surface_point(g, p, &sp);
    if (fs == FrameStatus::BadNormal) {
        *flags |= kDegenerate;
        return false;
    }
    if (fs == FrameStatus::TangentFallback) *flags |= kDegenerate;
    const glm::dvec3 pos = sp.position;
    const glm::dvec3 wo = sp.local(glm::normalize(eye - pos));
    if (wo.z <= 0) *flags |= kBackFacing;
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
    *radiance = sum;
    return true;
}

}  // namespace

namespace {

// One mesh seen through clip_from_mesh, shaded with scene (the mesh's space). kept_depth
// NULL: out starts as the background; else out and kept_depth hold a frame, and only
// pixels where the mesh is in front (LESS, at the pixel centre) change.
bool render_core(const SpatialBrdf& brdf, const sepal_scene& scene, const sepal_mesh& mesh,
                 const float clip_from_mesh[16], int width, int height, Image* out, std::vector<float>* kept_depth,
                 ExactStats* stats, std::string* err, bool progress, int supersample) {
    if (supersample < 1 || supersample > kMaxExactSupersample) {
        *err = "exact render: supersample " + std::to_string(supersample) + " (1.." +
               std::to_string(kMaxExactSupersample) + ")";
        return false;
    }
    const int S = supersample;
    // Coverage is GL's (pixel centres, g); shading averages S x S stratified samples over the
    // pixel that lie on the surface (one rasterization per offset, sub): the pixel's mean
    // radiance, not one point of it.
    SurfaceBuffer g, sub;
    if (!rasterize_surface_clip(clip_from_mesh, mesh, width, height, &g, err)) return false;
    const size_t pixels = size_t(width) * height;
    const bool keep = kept_depth != nullptr;
    if (!keep) {
        *out = Image(width, height, 3);
    } else if (out->width != width || out->height != height || out->channels != 3 || kept_depth->size() != pixels) {
        *err = "exact render: the frame's image or depth is not " + std::to_string(width) + "x" +
               std::to_string(height);
        return false;
    }
    // A pixel is this mesh's where it covers the centre in front of what the frame holds.
    for (size_t p = 0; keep && p < pixels; ++p)
        if (g.covered[p] && !(g.depth[p] < (*kept_depth)[p])) g.covered[p] = 0;
    std::vector<double> sum(S > 1 ? pixels * 3 : 0);
    std::vector<int> count(S > 1 ? pixels : 0), flags(pixels, 0);
    const glm::dvec3 eye(scene.camera.eye[0], scene.camera.eye[1], scene.camera.eye[2]);
    const int threads = int(std::max(1u, std::min(8u, std::thread::hardware_concurrency())));
    // Rows are shaded in interleaved order by each thread; every pixel is written by
    // exactly one thread, so the image does not depend on the thread count.
    auto parallel_rows = [&](auto&& row) {
        std::vector<std::thread> pool;
        for (int i = 1; i < threads; ++i)
            pool.emplace_back([&, i] {
                for (int y = i; y < height; y += threads) row(y);
            });
        for (int y = 0; y < height; y += threads) row(y);
        for (std::thread& th : pool) th.join();
    };
    Progress rows_done(progress, "sepal render: exact", size_t(height) * S * S);
    for (int k = 0; S > 1 && k < S * S; ++k) {
        const float dx = (float(k % S) + 0.5f) / float(S) - 0.5f, dy = (float(k / S) + 0.5f) / float(S) - 0.5f;
        if (!rasterize_surface_clip(clip_from_mesh, mesh, width, height, &sub, err, dx, dy)) return false;
        parallel_rows([&](int y) {
            for (int x = 0; x < width; ++x) {
                const size_t p = size_t(y) * width + x;
                glm::dvec3 v;
                if (g.covered[p] && sub.covered[p] && shade(brdf, scene, eye, sub, p, &v, &flags[p])) {
                    for (int c = 0; c < 3; ++c) sum[p * 3 + c] += v[c];
                    ++count[p];
                }
            }
            rows_done.advance();
        });
    }
    parallel_rows([&](int y) {
        for (int x = 0; x < width; ++x) {
            const size_t p = size_t(y) * width + x;
            float* rgb = &out->data[p * 3];
            if (!keep) std::copy(scene.background, scene.background + 3, rgb);
            if (!g.covered[p]) continue;
            if (keep) {
                (*kept_depth)[p] = g.depth[p];
                std::fill(rgb, rgb + 3, 0.0f);
            }
            glm::dvec3 v;
            if (S > 1 && count[p] > 0) {
                for (int c = 0; c < 3; ++c) rgb[c] = float(sum[p * 3 + c] / count[p]);
            } else if (shade(brdf, scene, eye, g, p, &v, &flags[p])) {
                // S = 1, or no subsample on the surface (a sliver): the centre.
                for (int c = 0; c < 3; ++c) rgb[c] = float(v[c]);
            }
            // else a zero or non-finite normal: the runtime skips such triangles; so does this.
        }
        if (S == 1) rows_done.advance();
    });
    int64_t covered = 0, back_facing = 0, degenerate = 0;
    for (size_t p = 0; p < pixels; ++p) {
        covered += g.covered[p];
        back_facing += (flags[p] & kBackFacing) != 0;
        degenerate += (flags[p] & kDegenerate) != 0;
    }
    if (stats) {
        stats->covered_pixels = covered;
        stats->back_facing_pixels = back_facing;
        stats->degenerate_frames = degenerate;
    }
    return true;
}

}  // namespace

bool render_exact_spatial(const SpatialBrdf& brdf, const sepal_scene& scene, const sepal_mesh& mesh,
                          int width, int height, Image* out, ExactStats* stats, std::string* err, bool progress,
                          int supersample) {
    float clip_from_world[16];
    if (!clip_from_scene(scene, width, height, clip_from_world, err)) return false;
    return render_core(brdf, scene, mesh, clip_from_world, width, height, out, nullptr, stats, err, progress,
                       supersample);
}

bool render_exact_object(const Brdf& brdf, const sepal_scene& object_scene, const sepal_mesh& mesh,
                         const float clip_from_object[16], int width, int height, Image* frame,
                         std::vector<float>* depth, ExactStats* stats, std::string* err, int supersample) {
    if (!depth) {
        *err = "exact render: a frame's object needs the frame's depth";
        return false;
    }
    return render_core(Uniform(brdf), object_scene, mesh, clip_from_object, width, height, frame, depth, stats, err,
                       false, supersample);
}

bool render_exact_frame_object(const Brdf& brdf, const sepal_frame_desc& frame, const sepal_object& object,
                               Image* image, std::vector<float>* depth, ExactStats* stats, std::string* err,
                               int supersample) {
    const int count = object.vertices ? object.vertices->vertex_count : object.mesh ? object.mesh->vertex_count : 0;
    std::vector<sepal_vertex> vertices(count > 0 ? size_t(count) : 1);
    sepal_scene scene;
    float clip[16];
    int loaded = 0;
    sepal_error e = {};
    if (sepal_object_shading(&frame, &object, &scene, clip, vertices.data(), count, &loaded, &e) != SEPAL_OK) {
        *err = std::string("exact render: ") + e.message;
        return false;
    }
    // The indices are only read.
    uint16_t* indices = const_cast<uint16_t*>(object.vertices ? object.vertices->indices : object.mesh->indices);
    const int index_count = object.vertices ? object.vertices->index_count : object.mesh->index_count;
    const sepal_mesh mesh = {vertices.data(), indices, loaded, index_count};
    return render_exact_object(brdf, scene, mesh, clip, frame.viewport[2], frame.viewport[3], image, depth, stats, err,
                               supersample);
}

}  // namespace sepal
