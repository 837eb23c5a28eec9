// The reverse of scene_flags: a scene as the flags that reproduce it exactly (each float
// in the shortest form that reads back the same), so an interactive port can hand its current view
// to `sepal-view --headless` or `sepal render`.
#pragma once
#include <string>
#include <vector>

#include "common/scene_flags.h"

namespace sepal_ports {

// --size, --mesh, --camera, --target, --fov, every --light, and --background when not black.
std::vector<std::string> scene_args(const SceneSetup& s);
// Arguments joined into one shell-safe line (single quotes where needed).
std::string shell_join(const std::vector<std::string>& args);

}  // namespace sepal_ports
