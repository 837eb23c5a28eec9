// A scene bundle: a scene file (docs/scenes.md) with its materials baked and its meshes
// resolved, in files the ports read without the offline tools. `sepal render --scene FILE
// --export DIR` writes one; sepal-view's scene mode reads it.
//
// Usage:
//   sepal_ports::SceneBundle b;
//   std::string err;
//   if (!sepal_ports::load_scene_bundle("DIR/scene.txt", &b, &err)) fail(err);  // "scene.txt: line 4: ..."
//   sepal_frame_desc fd; std::vector<sepal_object> objs; sepal_light lights[SEPAL_MAX_LIGHTS];
//   sepal_ports::bundle_frame(b, t, 0, 0, b.width, b.height, &fd, lights, &objs, &err);
//
// DIR/scene.txt, one record a line, words separated by spaces, numbers as C reads them:
//   sepal-scene 1
//   size W H
//   background R G B
//   camera orbit TX TY TZ DISTANCE YAW PITCH SPIN FOV NEAR FAR
//   camera eye EX EY EZ TX TY TZ FOV NEAR FAR
//   light point|directional X Y Z R G B INTENSITY ORBIT_PERIOD ORBIT_PHASE CX CY CZ PULSE_PERIOD PULSE_DEPTH
//   material FILE.sepal                       (a baked asset beside scene.txt)
//   mesh sphere|torus|grid|wave | mesh floor CELLS | mesh FILE.mesh
//   object MATERIAL MESH TX TY TZ RX RY RZ SCALE SPIN   (indices of the records above, from 0)
// FILE.mesh: the bytes "SEPALMSH", uint32 vertex count, uint32 index count (little-endian),
// the sepal_vertex array (12 floats each), the uint16 indices.
// Limits: 8 lights, 64 materials, 256 meshes and objects, 1 MiB of text; names without
// spaces or '/', read from the bundle's folder only.
#pragma once
#include <stdint.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/scene_motion.h"
#include "sepal/sepal_format.h"
#include "sepal/sepal_frame.h"

namespace sepal_ports {

struct SceneBundle {
    int width = 640, height = 480;
    float background[3] = {0, 0, 0};
    SceneCamera camera;
    std::vector<SceneLight> lights;
    std::vector<std::vector<uint8_t>> asset_bytes;  // per material (each asset points into its bytes)
    std::vector<std::unique_ptr<sepal_asset>> assets;
    struct Mesh {
        std::vector<sepal_vertex> vertices;
        std::vector<uint16_t> indices;
        sepal_mesh mesh() { return {vertices.data(), indices.data(), int(vertices.size()), int(indices.size())}; }
    };
    std::vector<Mesh> meshes;
    struct Object {
        SceneTransform transform;
        int material = 0, mesh = 0;
    };
    std::vector<Object> objects;
    size_t max_vertices() const;
};

bool load_scene_bundle(const std::string& path, SceneBundle* out, std::string* err);
// The same from scene.txt's text (`source` names it in messages); `read` gives the bytes of
// a file it names, at most max_bytes (the web port hands over what the page fetched).
using BundleReader = std::function<bool(const std::string& name, size_t max_bytes, std::vector<uint8_t>* out,
                                        std::string* err)>;
bool parse_scene_bundle(const std::string& text, const std::string& source, const BundleReader& read,
                        SceneBundle* out, std::string* err);

// The frame at time t, the orbit camera turned by extra yaw and pitch (degrees; the viewer's
// drags), at width x height: view, projection and viewport in *desc (clear 0, the caller sets
// caps and scratch), lights, and one object per bundle object (asset set; mesh, material null:
// set them per backend).
bool bundle_frame(const SceneBundle& b, double t, double yaw, double pitch, int width, int height,
                  sepal_frame_desc* desc, sepal_light lights[SEPAL_MAX_LIGHTS], int* light_count,
                  std::vector<sepal_object>* objects, std::string* err);

// FILE.mesh's bytes for a mesh (the writer: sepal render --scene --export).
std::vector<uint8_t> encode_bundle_mesh(const sepal_mesh& mesh);

}  // namespace sepal_ports
