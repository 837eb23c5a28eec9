// The lighting a bake models: the range of lights its asset must hold under, and the
// conditions drawn from it that rank candidates (training) and report the result (held out).
//
// Usage:
//   sepal::LightRange r;                       // default: 8:1, any direction above the horizon, 2 lights
//   r.ratio = 4;
//   std::vector<sepal::LightCondition> train = sepal::training_conditions(r);
//   std::vector<sepal::LightCondition> held = sepal::held_out_conditions(r);
//   sepal::BakeView v;  sepal::condition_view(train[0], &v, &err);
//
// Irradiance is measured as the runtime's draw stats measure it (sepal_format.h's light
// range): a light's largest channel over its squared distance to the centre of the mesh's
// bounds. Every condition keeps sepal render's camera and puts its point lights at the
// default light's distance from the object (4.39), so the intensity is the irradiance times
// 19.25; directions lie in the cone about the scene's up (+z), drawn uniformly over its
// solid angle, lights behind the object included (their highlights sit on the visible rim,
// where the eye is grazing: the hardest place for a factorization), all but those within
// about 25 degrees of straight behind it (they light a sliver the camera cannot resolve).
// Training conditions (seed): the default scene's light at the brightest irradiance, the
// grazing light (from the side and behind) and one drawn direction at the dimmest, a rim
// light (a drawn direction behind the object, at a drawn irradiance), and with two lights or more, two drawn
// lights at drawn irradiances (log-uniform in the range); the torus or wave as one more
// condition when listed in meshes.
// Held-out conditions (another seed): a drawn direction at the dimmest irradiance, one at a
// drawn irradiance, the torus, two lights (with max_lights >= 2), each of the listed meshes
// other than the sphere and torus: directions, intensities and a mesh the search never saw.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "bake/image_score.h"

namespace sepal {

struct LightRange {
    double ratio = 8;           // brightest : dimmest irradiance, >= 1
    double irradiance_max = 0;  // the brightest light's irradiance at the object; 0: the default scene's (60 / 19.25)
    double cone_degrees = 90;   // directions within this of the scene's up: 90 = anywhere above the horizon
    int max_lights = 2;         // lights at once, 1..SEPAL_MAX_LIGHTS
    std::vector<std::string> meshes = {"sphere"};  // sphere, torus, wave
    uint64_t seed = 1;          // the training draws; held-out draws use another stream
};

// The irradiance of the default scene's light at the unit sphere's centre (60 / 19.25).
double default_irradiance();
double range_irradiance_max(const LightRange& r);
double range_irradiance_min(const LightRange& r);
// Checks the range (ratio >= 1, irradiance, cone in (0, 180], 1..SEPAL_MAX_LIGHTS lights,
// known meshes); false with the reason.
bool validate_light_range(const LightRange& r, std::string* err);
// "8:1, 0.39..3.12 at the object, cone 90 deg, up to 2 lights, sphere"
std::string describe_light_range(const LightRange& r);

struct LightCondition {
    std::string name;  // "default", "dim", "two lights", "torus", ...
    std::string mesh;  // sphere, torus, wave
    std::vector<sepal_light> lights;
    // The scene flags that render it (`sepal render --mesh torus --light point:...`).
    std::string flags() const;
};

std::vector<LightCondition> training_conditions(const LightRange& r);
std::vector<LightCondition> held_out_conditions(const LightRange& r);
// The condition as a judged view (sepal render's camera, its mesh and lights).
bool condition_view(const LightCondition& c, BakeView* out, std::string* err);
bool condition_views(const std::vector<LightCondition>& cs, std::vector<BakeView>* out, std::string* err);

}  // namespace sepal
