// sepal_scene.h - what every backend draws: a camera, 1 to 8 lights, a mesh in world space.
//
// Usage:
//   srt_scene s;
//   srt_scene_default(&s);                 // camera on -y looking at the origin, one light
//   s.lights[0].intensity[0] = 2.0f; ...
//   float view[16], proj[16];
//   srt_scene_matrices(&s, width, height, view, proj, &err);
//
// The mesh is in world space (no model matrix). Radiance reaching the camera from a
// surface point p with BRDF f is, summed over the lights,
//   point light:       f(wi, wo) * max(cos theta_i, 0) * intensity / |light - p|^2
//   directional light: f(wi, wo) * max(cos theta_i, 0) * intensity
// with wi towards the light and wo towards the eye. Every backend (exact, GL ES 1.1,
// GL ES 2, CPU) computes this same quantity, so their images can be pixel-compared.
// Limits: at most SRT_MAX_LIGHTS lights; intensities finite and >= 0.
#pragma once
#include "sepal_rt.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SRT_MAX_LIGHTS 8

typedef enum srt_light_type { SRT_LIGHT_POINT = 0, SRT_LIGHT_DIRECTIONAL = 1 } srt_light_type;

typedef struct srt_light {
    srt_light_type type;
    float position[3];   // point: world position; directional: direction towards the light
    float intensity[3];  // linear RGB
} srt_light;

typedef struct srt_camera {
    float eye[3], target[3], up[3];
    float fovy_degrees;  // vertical field of view
    float z_near, z_far;
} srt_camera;

typedef struct srt_scene {
    srt_camera camera;
    srt_light lights[SRT_MAX_LIGHTS];
    int light_count;
    float background[3];  // linear RGB behind the mesh
} srt_scene;

void srt_scene_default(srt_scene* s);
// Checks the scene (light count, finite values, camera not degenerate).
srt_result srt_scene_validate(const srt_scene* s, srt_error* err);
// View and projection matrices (column-major) for an image of width x height.
srt_result srt_scene_matrices(const srt_scene* s, int width, int height, float view[16],
                              float projection[16], srt_error* err);

#ifdef __cplusplus
}
#endif
