// The exact backend: a scene drawn with the original BRDF evaluated per pixel.
//
// Usage:
//   sepal::Image img; std::string err;
//   sepal::ExactStats stats;
//   if (!sepal::render_exact(*brdf, scene, mesh, 512, 512, &img, &stats, &err)) ...
//   // a spatially varying BRDF (ist/generate.h, ist/tree.h): f depends on the mesh's UV
//   if (!sepal::render_exact_spatial(svbrdf, scene, mesh, 512, 512, &img, &stats, &err)) ...
//
// The reference every GL and CPU image is compared with (Kautz-McCool Fig. 10, top
// right): the mesh is rasterized by runtime/include/sepal/sepal_raster.h, so its pixels line up with
// GL's; vertex frames (position, normal, tangent with handedness) are interpolated
// perspective-correctly across triangles and re-orthonormalized per pixel (Gram-Schmidt),
// UVs perspective-correctly too;
// radiance follows sepal_scene.h. Output: linear RGB floats, top row first, background
// where no triangle covers the pixel. Shading runs on all cores; the result does not
// depend on the thread count.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "brdf/brdf.h"
#include "util/image.h"
#include "sepal/sepal_frame.h"
#include "sepal/sepal_scene.h"

namespace sepal {

struct ExactStats {
    int64_t covered_pixels = 0;
    int64_t back_facing_pixels = 0;  // the view is below the interpolated frame's horizon
    int64_t degenerate_frames = 0;   // tangent parallel to the normal or not finite: fallback tangent used;
                                     // zero or non-finite normal: background (the runtime skips those triangles)
};

// A BRDF that varies over the surface with the mesh's texture coordinates (u, v).
class SpatialBrdf {
  public:
    virtual ~SpatialBrdf() = default;
    // Same conventions as Brdf::eval, at surface point uv; safe to call from several threads.
    virtual glm::dvec3 eval(const glm::dvec2& uv, const glm::dvec3& wi, const glm::dvec3& wo) const = 0;
};

// progress: a percentage line on stderr while the rows are shaded (util/progress.h).
// supersample S (1..kMaxExactSupersample): each covered pixel (coverage at the pixel centre,
// as GL rasterizes) holds the mean radiance of S x S stratified samples over its area that
// lie on the surface, S^2 times the shading cost. 1 shades the centre only, which aliases
// where shading changes by several levels per pixel (a sphere's grazing ring): against a
// 4 x 4 reference a point-sampled exact render of oren-nayar is 40.6 dB, below what the
// backends reach, so image errors are measured against S = 4 (docs/fidelity.md).
constexpr int kMaxExactSupersample = 8;
constexpr int kReferenceSupersample = 4;
bool render_exact_spatial(const SpatialBrdf& brdf, const sepal_scene& scene, const sepal_mesh& mesh,
                          int width, int height, Image* out, ExactStats* stats, std::string* err,
                          bool progress = false, int supersample = 1);

bool render_exact(const Brdf& brdf, const sepal_scene& scene, const sepal_mesh& mesh, int width,
                  int height, Image* out, ExactStats* stats, std::string* err, bool progress = false,
                  int supersample = 1);

// One object of a frame of many (runtime/include/sepal/sepal_frame.h): object_scene and
// clip_from_object from sepal_object_scene, so the exact image is the frame the runtime
// draws. frame (width x height x 3) and depth (width x height, 1 = far) hold the frame so
// far: pixels whose centre the object covers in front of depth get its radiance and depth,
// the others keep theirs.
bool render_exact_object(const Brdf& brdf, const sepal_scene& object_scene, const sepal_mesh& mesh,
                         const float clip_from_object[16], int width, int height, Image* frame,
                         std::vector<float>* depth, ExactStats* stats, std::string* err, int supersample = 1);

// The same straight from a frame's description (sepal_object_shading): a sepal_mesh or the
// engine's vertex data, any affine model with a positive determinant, the frame's viewport
// size. The vertices are copied into the shading space here (the exact renderer may
// allocate; the runtime does not).
bool render_exact_frame_object(const Brdf& brdf, const sepal_frame_desc& frame, const sepal_object& object,
                               Image* image, std::vector<float>* depth, ExactStats* stats, std::string* err,
                               int supersample = 1);

}  // namespace sepal
