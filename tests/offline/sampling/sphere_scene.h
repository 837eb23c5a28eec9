// The paper's test scene for the sampling tests and bench: the default camera and a unit
// sphere (header-only, doctest-free, shared by tests/offline/sampling and tests/bench).
#pragma once
#include <vector>

#include "sepal/sepal_rt.h"
#include "sepal/sepal_scene.h"

namespace sepal_test {

struct SphereScene {
    sepal_scene scene;
    std::vector<sepal_vertex> v;
    std::vector<uint16_t> idx;
    sepal_mesh mesh;
    explicit SphereScene(int slices = 48) : v(SEPAL_SPHERE_MAX_VERTICES), idx(SEPAL_SPHERE_MAX_INDICES) {
        sepal_scene_default(&scene);
        mesh = {v.data(), idx.data(), int(v.size()), int(idx.size())};
        sepal_error e{};
        sepal_mesh_sphere(slices, slices / 2, &mesh, &e);
    }
};

}  // namespace sepal_test
