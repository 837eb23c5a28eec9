// Per-vertex frames, factor texture coordinates and irradiance (see vertex_setup.h).
#include "vertex_setup.h"

#include <math.h>

namespace srt {

VertexSetupResult setup_vertices(srt_param param, srt_hemi_map map, const srt_mesh& mesh,
                                 const srt_scene& scene, float* scratch) {
    VertexSetupResult r = {0.0f, 0.0f, 0};
    const int n = mesh.vertex_count;
    for (int i = 0; i < n; ++i) {
        const srt_vertex& v = mesh.vertices[i];
        ShadingFrame fr;
        shading_frame(v.normal, v.tangent, &fr);
        float to_eye[3] = {scene.camera.eye[0] - v.position[0], scene.camera.eye[1] - v.position[1],
                           scene.camera.eye[2] - v.position[2]};
        normalize3(to_eye);
        float wo[3];
        fr.to_local(to_eye, wo);
        float sum = 0.0f;
        for (int l = 0; l < scene.light_count; ++l) {
            const srt_light& light = scene.lights[l];
            float to_light[3];
            const float falloff = light_direction(light, v.position, to_light);
            float wi[3];
            fr.to_local(to_light, wi);
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
