// Scene defaults, validation and matrices (see sepal_scene.h).
#include <math.h>
#include <string.h>

#include "internal.h"
#include "sepal/sepal_scene.h"

namespace {
bool finite3(const float* v) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }
float length3(const float* v) { return sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }
}  // namespace

extern "C" void sepal_scene_default(sepal_scene* s) {
    if (!s) return;
    memset(s, 0, sizeof *s);
    const float eye[3] = {0.0f, -3.2f, 1.4f}, up[3] = {0.0f, 0.0f, 1.0f};
    memcpy(s->camera.eye, eye, sizeof eye);
    memcpy(s->camera.up, up, sizeof up);
    s->camera.fovy_degrees = 38.0f;
    s->camera.z_near = 0.5f;
    s->camera.z_far = 20.0f;
    s->light_count = 1;
    s->lights[0].type = SEPAL_LIGHT_POINT;
    const float light[3] = {2.0f, -2.5f, 3.0f};
    memcpy(s->lights[0].position, light, sizeof light);
    // Irradiance about pi at the object (intensity / distance^2, distance ~4.4): a white
    // Lambertian surface facing the light shows as 1.
    s->lights[0].intensity[0] = s->lights[0].intensity[1] = s->lights[0].intensity[2] = 60.0f;
    s->background[0] = s->background[1] = s->background[2] = 0.0f;
}

extern "C" sepal_result sepal_scene_validate(const sepal_scene* s, sepal_error* err) {
    if (!s) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "scene is NULL");
    const sepal_camera& c = s->camera;
    if (!finite3(c.eye) || !finite3(c.target) || !finite3(c.up))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "camera: eye, target or up not finite");
    const float d[3] = {c.target[0] - c.eye[0], c.target[1] - c.eye[1], c.target[2] - c.eye[2]};
    const float cr[3] = {d[1] * c.up[2] - d[2] * c.up[1], d[2] * c.up[0] - d[0] * c.up[2],
                         d[0] * c.up[1] - d[1] * c.up[0]};
    if (!(length3(d) > 1e-6f) || !(length3(cr) > 1e-6f * length3(d)))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "camera: eye equals target, or up is parallel to the view direction");
    if (!(c.fovy_degrees > 1.0f && c.fovy_degrees < 170.0f))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "camera: fov %g outside (1, 170) degrees, both ends excluded",
                         (double)c.fovy_degrees);
    if (!(c.z_near > 0.0f) || !(c.z_far > c.z_near) || !isfinite(c.z_far))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "camera: need 0 < near < far");
    if (s->light_count < 1 || s->light_count > SEPAL_MAX_LIGHTS)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "scene: %d lights (1..%d)",
                         s->light_count, SEPAL_MAX_LIGHTS);
    for (int i = 0; i < s->light_count; ++i) {
        const sepal_light& l = s->lights[i];
        if (l.type != SEPAL_LIGHT_POINT && l.type != SEPAL_LIGHT_DIRECTIONAL)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "light %d: unknown type %d", i,
                             (int)l.type);
        if (!finite3(l.position) ||
            (l.type == SEPAL_LIGHT_DIRECTIONAL && !(length3(l.position) > 1e-6f)))
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "light %d: position/direction not finite or zero", i);
        for (int k = 0; k < 3; ++k)
            if (!(l.intensity[k] >= 0.0f) || !isfinite(l.intensity[k]))
                return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                                 "light %d: intensity must be finite and >= 0", i);
    }
    if (!finite3(s->background))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "scene: background not finite");
    return srt::ok(err);
}

extern "C" sepal_result sepal_scene_matrices(const sepal_scene* s, int width, int height,
                                         float view[16], float projection[16], sepal_error* err) {
    sepal_result r = sepal_scene_validate(s, err);
    if (r != SEPAL_OK) return r;
    if (width < 1 || height < 1 || !view || !projection)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "scene matrices: bad image size %dx%d",
                         width, height);
    sepal_mat4_look_at(s->camera.eye, s->camera.target, s->camera.up, view);
    sepal_mat4_perspective(s->camera.fovy_degrees, (float)width / (float)height, s->camera.z_near,
                         s->camera.z_far, projection);
    return srt::ok(err);
}
