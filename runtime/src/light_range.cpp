// The draw stats' dim_lights: lights dimmer than the asset's declared light range.
#include <math.h>

#include "draw_internal.h"

namespace srt {

int dim_lights(const sepal_fmt_material& m, const MeshView& mesh, const sepal_scene& scene) {
    if (!(m.irradiance_min > 0.0f) || !mesh.attr[MeshView::kPosition] || mesh.vertex_count < 1) return 0;
    // The centre of the usable vertices' bounds: where "the light at the object" is measured,
    // as the bake declared its range (cheap, and the same for any tessellation).
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < mesh.vertex_count; ++i) {
        sepal_vertex v;
        mesh.load(i, &v);
        const float* p = v.position;
        if (!(isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]))) continue;
        for (int k = 0; k < 3; ++k) lo[k] = fminf(lo[k], p[k]), hi[k] = fmaxf(hi[k], p[k]);
    }
    if (!(lo[0] <= hi[0])) return 0;
    int dim = 0;
    for (int l = 0; l < scene.light_count && l < SEPAL_MAX_LIGHTS; ++l) {
        const sepal_light& light = scene.lights[l];
        // A coloured light is as dim as its dimmest lit channel: that channel's highlight is
        // the one the white level flattens (a (1, 0.5, 0.2) light's blue at a fifth of its red).
        float peak = 0.0f;
        for (int k = 0; k < 3; ++k)
            if (light.intensity[k] > 0.0f && (peak == 0.0f || light.intensity[k] < peak)) peak = light.intensity[k];
        float e = peak;
        if (light.type == SEPAL_LIGHT_POINT) {
            float d2 = 0.0f;
            for (int k = 0; k < 3; ++k) {
                const float t = light.position[k] - 0.5f * (lo[k] + hi[k]);
                d2 += t * t;
            }
            e = d2 > 0.0f ? peak / d2 : INFINITY;
        }
        // A relative margin: a light exactly at the declared bound is in range.
        if (e > 0.0f && e < m.irradiance_min * (1.0f - 1e-4f)) ++dim;
    }
    return dim;
}

}  // namespace srt
