// The scene flags (ports/common/scene_flags.h) on the sepal tool's CLI11 parser: the ports
// parse them by hand (no CLI11, no exceptions in ports/); this binding reuses that parser, so
// the checks and messages are the same everywhere.
#pragma once
#include <CLI/CLI.hpp>

#include "common/scene_flags.h"

namespace sepal {

// Declares --size --mesh --camera --target --fov --light --background in a group "Scene";
// values are checked as they are parsed (a bad value is a CLI::ValidationError naming the flag).
void add_scene_options(CLI::App& app, sepal_ports::SceneSetup* s);

}  // namespace sepal
