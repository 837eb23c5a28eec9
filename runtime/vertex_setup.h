// Per-vertex work shared by the material backends (internal): frames, directions,
// texture coordinates of the factors and irradiance per light.
#pragma once
#include "internal.h"
#include "sepal_format.h"
#include "sepal_scene.h"

namespace srt {

// Scratch layout for N vertices and L lights: per light l, at l * 7N: G uv (2N), H uv
// (2N), irradiance RGB (3N); then 4N floats of colours for the pass being drawn.
inline size_t scratch_floats(int vertices, int lights) {
    return (size_t)vertices * (7 * (size_t)lights + 4);
}
inline float* light_g_uv(float* s, int n, int l) { return s + (size_t)l * 7 * n; }
inline float* light_h_uv(float* s, int n, int l) { return s + (size_t)l * 7 * n + 2 * (size_t)n; }
inline float* light_irradiance(float* s, int n, int l) { return s + (size_t)l * 7 * n + 4 * (size_t)n; }
inline float* pass_colors(float* s, int n, int lights) { return s + (size_t)lights * 7 * n; }

struct VertexSetupResult {
    float max_irradiance_sum;     // max over vertices of sum over lights of the max channel
    float max_irradiance_single;  // max over vertices, lights and channels
    int below_horizon;            // vertex-light pairs with light or eye below the horizon
};

VertexSetupResult setup_vertices(srt_param param, srt_hemi_map map, const srt_mesh& mesh,
                                 const srt_scene& scene, float* scratch);

}  // namespace srt
