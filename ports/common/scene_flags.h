// Scene flags shared by sepal-view and `sepal render`, so both draw the same scene.
//
//   --size WxH              image size (default 512x512)
//   --mesh NAME             sphere (default), torus, wave, or a path to an .obj file
//   --camera X,Y,Z          eye position (default 0,-3.2,1.4), looking at --target
//   --target X,Y,Z          default 0,0,0
//   --fov DEGREES           vertical field of view (default 38)
//   --light point:X,Y,Z[:I or :R,G,B]   a point light (repeat for up to 8; the first
//   --light dir:X,Y,Z[:I or :R,G,B]     replaces the default light); dir gives the
//                                       direction towards the light
//   --background R,G,B      linear RGB (default 0,0,0)
//
// Usage:
//   SceneSetup s;
//   for (i...) { int used = parse_scene_flag(argc, argv, i, &s, &err); if (used < 0) fail;
//                if (used > 0) { i += used - 1; continue; } ... other flags ... }
//   if (!load_scene_mesh(&s, &err)) fail;
// (the sepal tool declares the same flags on its CLI11 parser: offline/cli/scene_options.h)
#pragma once
#include <string>
#include <vector>

#include "sepal/sepal_scene.h"

namespace sepal_ports {

struct SceneSetup {
    sepal_scene scene;
    int width = 512, height = 512;
    std::string mesh_name = "sphere";
    bool lights_given = false;
    bool camera_given = false;  // --camera or --target
    bool framed = false;        // load_scene_mesh framed an OBJ by its bounds (below)
    // Mesh storage, filled by load_scene_mesh; mesh points into it.
    std::vector<sepal_vertex> vertices;
    std::vector<uint16_t> indices;
    sepal_mesh mesh = {};
    sepal_obj_stats obj_stats = {};
    SceneSetup() { sepal_scene_default(&scene); }
};

// Returns how many arguments it consumed at argv[i] (0: not a scene flag), or -1 with
// the reason in *err.
int parse_scene_flag(int argc, char** argv, int i, SceneSetup* s, std::string* err);
// Builds or loads the mesh named by mesh_name and validates the scene. An OBJ mesh is framed
// from its bounding sphere (centre c, radius r) as the default scene frames the unit sphere:
// without --camera/--target the eye is c + r (0, -3.2, 1.4) looking at c; without --light the
// point light is at c + r (2, -2.5, 3) with intensity 60 r^2 (the same irradiance); near and
// far planes always enclose the sphere as seen from the eye.
bool load_scene_mesh(SceneSetup* s, std::string* err);
// Reads a whole file, refusing one larger than max_bytes (used for OBJ meshes and assets).
bool read_bounded_file(const std::string& path, size_t max_bytes, std::vector<uint8_t>* out, std::string* err);
// One line per flag, for usage messages.
const char* scene_flags_help();

}  // namespace sepal_ports
