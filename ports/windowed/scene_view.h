// sepal-view's scene mode: a scene file (docs/scenes.md) in a window, its lights and camera
// moving with the clock, or one frame of it headless.
//
//   sepal-view --scene FILE.json|BUNDLE [--backend B] [--time T] [--frames N --shot PNG] [--sepal PATH]
//   sepal-view --scene FILE.json|BUNDLE --headless [--backend B] [--time T] -o out.png
//
// FILE.json is handed to the `sepal` tool (`sepal render --scene FILE --export DIR`: the
// materials are baked or taken from its cache, glTF and OBJ meshes resolved) and the bundle
// it writes is read (ports/common/scene_bundle.h); BUNDLE is such a folder or its scene.txt.
// Backends: gles1 (default), gles2, gles2-fused, gles2-fused-pixel. --time fixes the time
// (default: the seconds since start; headless: 0). --frames N draws N frames, prints the
// median frame time and exits; --shot writes the last one's pixels (a PNG).
// Keys: left drag orbits the camera, b / B next / previous backend, space pauses the clock,
// q or Esc quits.
#pragma once

namespace sepal_ports {

// Returns the exit code: 0, 1 when drawing failed, 2 on bad flags or input.
int run_scene_view(int argc, char** argv);

}  // namespace sepal_ports
