// Per-pixel surface points of a mesh seen by the scene's camera: what the exact renderer and
// the Monte Carlo renderer (offline/sampling/mc_render.h) shade.
//
// Usage:
//   sepal::SurfaceBuffer sb; std::string err;
//   if (!sepal::rasterize_surface(scene, mesh, 256, 256, &sb, &err)) ...
//   sepal::SurfacePoint sp;
//   if (sb.covered[p] && sepal::surface_point(sb, p, &sp) != sepal::FrameStatus::BadNormal) ...
//
// The mesh is rasterized by runtime/include/sepal/sepal_raster.h, so pixels line up with GL's;
// vertex positions, normals and tangents (with handedness) are interpolated
// perspective-correctly and the frame is re-orthonormalized per pixel (Gram-Schmidt).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "sepal/sepal_scene.h"

namespace sepal {

struct SurfaceBuffer {
    static constexpr int kVaryings = 12;  // position 3, normal 3, tangent 4, uv 2
    int width = 0, height = 0;
    std::vector<float> varyings;  // kVaryings per pixel
    std::vector<uint8_t> covered;
    std::vector<float> depth;     // window depth in [0, 1] where covered (1 elsewhere)
};

// dx, dy: where in each pixel to sample, in pixels from its centre (|d| < 0.5; a supersampled
// exact render rasterizes once per offset: memory stays one buffer of the image's size).
bool rasterize_surface(const sepal_scene& scene, const sepal_mesh& mesh, int width, int height,
                       SurfaceBuffer* out, std::string* err, float dx = 0.0f, float dy = 0.0f);
// The scene camera's clip-from-world matrix (projection x view) for width x height.
bool clip_from_scene(const sepal_scene& scene, int width, int height, float out[16], std::string* err);
// The same with the clip-from-mesh matrix given (column-major; a frame's object:
// sepal_object_scene): positions, normals and tangents stay in the mesh's space.
bool rasterize_surface_clip(const float clip_from_mesh[16], const sepal_mesh& mesh, int width, int height,
                            SurfaceBuffer* out, std::string* err, float dx = 0.0f, float dy = 0.0f);

struct SurfacePoint {
    glm::dvec3 position, t, s, n;  // world space; (t, s, n) orthonormal
    glm::dvec2 uv;                 // texture coordinates (spatially varying BRDFs)
    glm::dvec3 local(const glm::dvec3& w) const;  // world direction -> local frame
    glm::dvec3 world(const glm::dvec3& w) const;  // local direction -> world
};
enum class FrameStatus {
    Ok,
    TangentFallback,  // tangent parallel to the normal or not finite: an axis made perpendicular
    BadNormal,        // zero or non-finite normal: not shaded (the runtime skips such triangles)
};
FrameStatus surface_point(const SurfaceBuffer& sb, size_t pixel, SurfacePoint* out);

}  // namespace sepal
