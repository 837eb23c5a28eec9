// What a scene frame shows at time t: the camera (orbit or fixed), lights that orbit and
// pulse, objects that spin; and the built-in meshes by name. Shared by the scene files'
// reader (offline/cli/scene_file.h, docs/scenes.md) and sepal-view's scene mode, so both
// draw the same frame at the same t.
//
// Usage:
//   sepal_ports::SceneCamera cam;  cam.distance = 8;
//   sepal_camera c = sepal_ports::camera_at(cam, t);
//   sepal_light l[SEPAL_MAX_LIGHTS]; int n = sepal_ports::lights_at(lights.data(), count, t, l);
//   float m[16]; sepal_ports::model_at(transform, t, m);
// z is up; angles in degrees; t in seconds.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "sepal/sepal_scene.h"

namespace sepal_ports {

struct SceneCamera {
    bool orbit = true;
    double target[3] = {0, 0, 0};
    double distance = 5, yaw = 0, pitch = 20, spin = 0;  // yaw 0: on -y; spin: degrees of yaw per second
    double eye[3] = {0, -4, 2};                            // without orbit
    double fov = 40, z_near = 0.1, z_far = 100;
};

struct SceneLight {
    sepal_light_type type = SEPAL_LIGHT_POINT;
    double position[3] = {0, 0, 3};  // point: position; directional: direction towards the light
    double color[3] = {1, 1, 1};
    double intensity = 1;
    // Orbit: turned about the vertical axis through orbit_center (directional: its direction
    // about z) by orbit_phase + 360 t / orbit_period degrees; period 0: still.
    double orbit_period = 0, orbit_phase = 0, orbit_center[3] = {0, 0, 0};
    // Pulse: intensity times 1 - pulse_depth (1 - cos(2 pi t / pulse_period)) / 2.
    double pulse_period = 0, pulse_depth = 0;
};

// M = T Rz(spin t) Rz Ry Rx S: the spin turns the object in place about its own vertical.
struct SceneTransform {
    double translate[3] = {0, 0, 0}, rotate[3] = {0, 0, 0}, scale = 1, spin = 0;
};

sepal_camera camera_at(const SceneCamera& c, double t);
int lights_at(const SceneLight* lights, int count, double t, sepal_light out[SEPAL_MAX_LIGHTS]);
void model_at(const SceneTransform& x, double t, float model[16]);

// sphere (64 x 32), torus (radii 0.72, 0.3; 64 x 32), grid (32 cells), wave (48 cells), or
// floor (a grid of `cells` per side, 1..254). False with the reason for another name.
bool builtin_mesh(const std::string& name, int cells, std::vector<sepal_vertex>* vertices,
                  std::vector<uint16_t>* indices, std::string* err);
bool is_builtin_mesh(const std::string& name);

}  // namespace sepal_ports
