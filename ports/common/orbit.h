// Mouse-driven camera and light for the interactive ports (the windowed viewer, the web
// page): the camera orbits its target, the first light moves on a sphere around it (a
// point light) or turns (a directional one). z is up, as in sepal_scene_default.
//
// Usage:
//   OrbitView v; v.reset(scene);               // angles from the scene as given
//   v.orbit(dx, dy); v.apply(&scene);          // a drag of (dx, dy) pixels
//
// Rates: kOrbitDegreesPerPixel for both drags (the tests script drags and check them);
// zoom multiplies the distance by 0.9 per step in, 1/0.9 out, within [1.1, 50].
// Elevations stay within +-89 degrees, so the camera's up vector never lines up with it.
#pragma once
#include "sepal/sepal_scene.h"

namespace sepal_ports {

constexpr float kOrbitDegreesPerPixel = 0.5f;

struct Spherical {
    float r = 1, azimuth = 0, elevation = 0;  // degrees
};

class OrbitView {
  public:
    void reset(const sepal_scene& scene);       // takes the camera and first light as they are
    void orbit(float dx, float dy);             // drag right: the camera turns left around the target
    void move_light(float dx, float dy);        // drag right / up: the light goes right / up
    void zoom(int steps);                       // > 0: closer
    void restore() { camera_ = camera0_, light_ = light0_; }  // back to the reset() view
    void apply(sepal_scene* scene) const;       // writes the eye and the first light
    const Spherical& camera() const { return camera_; }
    const Spherical& light() const { return light_; }

  private:
    Spherical camera_, light_, camera0_, light0_;
};

}  // namespace sepal_ports
