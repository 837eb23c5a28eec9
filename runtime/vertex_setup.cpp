// Per-vertex frames, factor texture coordinates and irradiance (see vertex_setup.h).
#include "vertex_setup.h"

#include <math.h>

namespace srt {
namespace {
inline float dot3(const float* a, const float* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline bool normalize3(float* v) {
    const float l = sqrtf(dot3(v, v));
    if (!(l > 1e-20f)) return false;
    v[0] /= l, v[1] /= l, v[2] /= l;
    return true;
}
}  // namespace

VertexSetupResult setup_vertices(srt_param param, srt_hemi_map map, const srt_mesh& mesh,
                                 const srt_scene& scene, float* scratch) {
    VertexSetupResult r = {0.0f, 0.0f, 0};
    const int n = mesh.vertex_count;
    for (int i = 0; i < n; ++i) {
        const srt_vertex& v = mesh.vertices[i];
        // Frame (t, s, n): Gram-Schmidt the tangent against the normal; any perpendicular
        // when the tangent is degenerate.
        float nn[3] = {v.normal[0], v.normal[1], v.normal[2]};
        if (!normalize3(nn)) nn[0] = 0, nn[1] = 0, nn[2] = 1;
        float t[3] = {v.tangent[0], v.tangent[1], v.tangent[2]};
        float d = dot3(t, nn);
        for (int k = 0; k < 3; ++k) t[k] -= d * nn[k];
        if (!normalize3(t)) {
            const float axis[3] = {fabsf(nn[0]) < 0.9f ? 1.0f : 0.0f, fabsf(nn[0]) < 0.9f ? 0.0f : 1.0f, 0.0f};
            d = dot3(axis, nn);
            for (int k = 0; k < 3; ++k) t[k] = axis[k] - d * nn[k];
            normalize3(t);
        }
        const float hand = v.tangent[3] < 0.0f ? -1.0f : 1.0f;
        const float s[3] = {hand * (nn[1] * t[2] - nn[2] * t[1]), hand * (nn[2] * t[0] - nn[0] * t[2]),
                            hand * (nn[0] * t[1] - nn[1] * t[0])};
        float to_eye[3] = {scene.camera.eye[0] - v.position[0], scene.camera.eye[1] - v.position[1],
                           scene.camera.eye[2] - v.position[2]};
        normalize3(to_eye);
        const float wo[3] = {dot3(to_eye, t), dot3(to_eye, s), dot3(to_eye, nn)};
        float sum = 0.0f;
        for (int l = 0; l < scene.light_count; ++l) {
            const srt_light& light = scene.lights[l];
            float to_light[3];
            float falloff = 1.0f;
            if (light.type == SRT_LIGHT_POINT) {
                for (int k = 0; k < 3; ++k) to_light[k] = light.position[k] - v.position[k];
                const float d2 = dot3(to_light, to_light);
                falloff = d2 > 1e-12f ? 1.0f / d2 : 0.0f;
            } else {
                for (int k = 0; k < 3; ++k) to_light[k] = light.position[k];
            }
            normalize3(to_light);
            const float wi[3] = {dot3(to_light, t), dot3(to_light, s), dot3(to_light, nn)};
            float* g = light_g_uv(scratch, n, l) + 2 * (size_t)i;
            float* h = light_h_uv(scratch, n, l) + 2 * (size_t)i;
            float* e = light_irradiance(scratch, n, l) + 3 * (size_t)i;
            const int above = srt_param_texcoords(param, map, wi, wo, g, h);
            const float cosine = above > 0 ? wi[2] : 0.0f;
            if (above <= 0) ++r.below_horizon;
            float peak = 0.0f;
            for (int k = 0; k < 3; ++k) {
                e[k] = light.intensity[k] * cosine * falloff;
                if (e[k] > peak) peak = e[k];
            }
            sum += peak;
            if (peak > r.max_irradiance_single) r.max_irradiance_single = peak;
        }
        if (sum > r.max_irradiance_sum) r.max_irradiance_sum = sum;
    }
    return r;
}

}  // namespace srt
