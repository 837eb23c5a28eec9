// Doctest-free pieces shared by the test fixtures (material_fixtures.h, which REQUIREs) and
// the extreme cases (extremes_runtime_cases.h, also linked into sepal-bench-extremes).
#pragma once
#include <cmath>
#include <string>

#include <glm/vec3.hpp>

#include "bake/asset_file.h"
#include "brdf/brdf.h"
#include "sepal/sepal_scene.h"

namespace test_fx {

// An asset with no textures or passes yet: xy map, RGB, unit colour ratio, errors unknown.
inline sepal::AssetData base_asset(sepal_param param, uint32_t terms) {
    sepal::AssetData a;
    a.material.param = param;
    a.material.map = SEPAL_MAP_XY;
    a.material.terms = terms;
    a.material.channels = 3;
    a.material.ratio[0] = a.material.ratio[1] = a.material.ratio[2] = 1.0f;
    a.material.error_quantized = a.material.error_float = a.material.error_relative = NAN;
    return a;
}

// The material tests' lights: `lights` of them, alternating a point light up and to the
// right and a dim directional light from the lower left.
inline void test_lights(sepal_scene* scene, int lights) {
    scene->light_count = lights;
    for (int l = 0; l < lights; ++l) {
        sepal_light& light = scene->lights[l];
        light.type = l % 2 ? SEPAL_LIGHT_DIRECTIONAL : SEPAL_LIGHT_POINT;
        light.position[0] = l % 2 ? -0.5f : 2.0f;
        light.position[1] = l % 2 ? -1.0f : -2.5f;
        light.position[2] = l % 2 ? 0.6f : 3.0f;
        for (int c = 0; c < 3; ++c) light.intensity[c] = l % 2 ? 0.7f : 18.0f + 2.0f * c;
    }
}

// f = v above the horizon, for exact renders of constant assets.
class ConstantBrdf : public sepal::Brdf {
  public:
    explicit ConstantBrdf(double v) : v_(v) {}
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override {
        return wi.z > 0 && wo.z > 0 ? glm::dvec3(v_) : glm::dvec3(0.0);
    }
    std::string spec() const override { return "constant"; }
    std::string model() const override { return "constant"; }
    std::string info() const override { return ""; }
    bool isotropic() const override { return true; }

  private:
    double v_;
};

}  // namespace test_fx
