#include "common/orbit.h"

#include <math.h>

namespace sepal_ports {
namespace {

constexpr float kPi = 3.14159265358979f;

Spherical to_spherical(const float v[3]) {
    Spherical s;
    s.r = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(s.r > 0.0f)) return Spherical{};
    s.azimuth = atan2f(v[1], v[0]) * 180.0f / kPi;
    s.elevation = asinf(fmaxf(-1.0f, fminf(1.0f, v[2] / s.r))) * 180.0f / kPi;
    return s;
}

void from_spherical(const Spherical& s, const float origin[3], float out[3]) {
    const float az = s.azimuth * kPi / 180.0f, el = s.elevation * kPi / 180.0f;
    out[0] = origin[0] + s.r * cosf(el) * cosf(az);
    out[1] = origin[1] + s.r * cosf(el) * sinf(az);
    out[2] = origin[2] + s.r * sinf(el);
}

float clamp_elevation(float e) { return fmaxf(-89.0f, fminf(89.0f, e)); }

}  // namespace

void OrbitView::reset(const sepal_scene& scene) {
    const sepal_camera& cam = scene.camera;
    const float to_eye[3] = {cam.eye[0] - cam.target[0], cam.eye[1] - cam.target[1], cam.eye[2] - cam.target[2]};
    camera0_ = camera_ = to_spherical(to_eye);
    const sepal_light& light = scene.lights[0];
    float to_light[3] = {light.position[0], light.position[1], light.position[2]};
    if (light.type == SEPAL_LIGHT_POINT)
        for (int c = 0; c < 3; ++c) to_light[c] -= cam.target[c];
    light0_ = light_ = to_spherical(to_light);
}

void OrbitView::orbit(float dx, float dy) {
    camera_.azimuth -= dx * kOrbitDegreesPerPixel;
    camera_.elevation = clamp_elevation(camera_.elevation + dy * kOrbitDegreesPerPixel);
}

void OrbitView::move_light(float dx, float dy) {
    light_.azimuth += dx * kOrbitDegreesPerPixel;
    light_.elevation = clamp_elevation(light_.elevation - dy * kOrbitDegreesPerPixel);
}

void OrbitView::zoom(int steps) {
    for (; steps > 0; --steps) camera_.r *= 0.9f;
    for (; steps < 0; ++steps) camera_.r /= 0.9f;
    camera_.r = fmaxf(1.1f, fminf(50.0f, camera_.r));
}

void OrbitView::apply(sepal_scene* scene) const {
    sepal_camera& cam = scene->camera;
    from_spherical(camera_, cam.target, cam.eye);
    sepal_light& light = scene->lights[0];
    static const float kOrigin[3] = {0, 0, 0};
    from_spherical(light_, light.type == SEPAL_LIGHT_POINT ? cam.target : kOrigin, light.position);
}

}  // namespace sepal_ports
