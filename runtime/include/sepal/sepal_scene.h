// sepal_scene.h - what every backend draws: a camera, 1 to 8 lights, a mesh in world space.
//
// Usage:
//   sepal_scene s;
//   sepal_scene_default(&s);                 // camera on -y looking at the origin, one light
//   s.lights[0].intensity[0] = 2.0f;
//   float view[16], proj[16];
//   sepal_scene_matrices(&s, width, height, view, proj, &err);
//
// The mesh is in world space (no model matrix). Radiance reaching the camera from a
// surface point p with BRDF f is, summed over the lights,
//   point light:       f(wi, wo) * max(cos theta_i, 0) * intensity / |light - p|^2
//   directional light: f(wi, wo) * max(cos theta_i, 0) * intensity
// with wi towards the light and wo towards the eye. Every backend (exact, GL ES 1.1,
// GL ES 2, CPU) computes this same quantity, so their images can be pixel-compared.
// Limits: at most SEPAL_MAX_LIGHTS lights; intensities finite and >= 0.
//
// Thread safety: sepal_scene_default, _validate and _matrices keep no state: any threads at
// once (a scene is only read by them and by the draw functions).
#pragma once
#include "sepal/sepal_rt.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SEPAL_MAX_LIGHTS 8

typedef enum sepal_light_type { SEPAL_LIGHT_POINT = 0, SEPAL_LIGHT_DIRECTIONAL = 1 } sepal_light_type;

typedef struct sepal_light {
    sepal_light_type type;
    float position[3];   // point: world position; directional: direction towards the light
    float intensity[3];  // linear RGB
} sepal_light;

typedef struct sepal_camera {
    float eye[3], target[3], up[3];
    float fovy_degrees;  // vertical field of view
    float z_near, z_far;
} sepal_camera;

typedef struct sepal_scene {
    sepal_camera camera;
    sepal_light lights[SEPAL_MAX_LIGHTS];
    int light_count;
    float background[3];  // linear RGB behind the mesh
} sepal_scene;

void sepal_scene_default(sepal_scene* s);
// Checks the scene (light count, finite values, camera not degenerate).
sepal_result sepal_scene_validate(const sepal_scene* s, sepal_error* err);
// View and projection matrices (column-major) for an image of width x height.
sepal_result sepal_scene_matrices(const sepal_scene* s, int width, int height, float view[16],
                              float projection[16], sepal_error* err);

#ifdef __cplusplus
}
#endif
