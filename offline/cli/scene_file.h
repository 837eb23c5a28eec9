// Scene files (docs/scenes.md): a frame of many objects described in JSON, drawn by
// `sepal render --scene` on every backend and by the exact renderer.
//
// Usage:
//   sepal::SceneFile f;
//   std::string err;
//   if (!sepal::read_scene_file("examples/kiosk.json", &f, &err)) fail(err);  // err names the JSON path
//   sepal::LoadedScene s;
//   if (!sepal::load_scene(f, sepal::default_scene_cache(), &s, &err, stderr)) fail(err);  // bakes or reuses
//   sepal::SceneFrame fr;
//   sepal::scene_frame(s, /*t=*/2.5, 160, 120, &fr, &err);     // camera, lights, objects at t
//   sepal::Image exact;  sepal::render_scene_exact(s, fr, 4, &exact, &err);
//
// A file holds "camera" (orbit or eye/target), 1-8 "lights" (point or directional, colour and
// intensity, optional orbit and pulse over time t), "materials" (each baked once however many
// objects use it, or read from an asset), an optional "floor" and 1-256 "objects" (a material,
// a mesh: sphere, torus, grid, wave, an OBJ or a glTF 2.0 file; translate, rotate, uniform
// scale, optional spin). Unknown keys, wrong kinds and values out of range are refused with
// the file and the JSON path ("kiosk.json: objects[3].scale: -1 is outside ...").
// Limits: 256 objects, 64 materials, 16 distinct mesh files, 8 lights (every light reaches
// every object), scene files up to 1 MiB.
#pragma once
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bake/bake.h"
#include "brdf/brdf.h"
#include "common/scene_motion.h"
#include "sepal/sepal_frame.h"
#include "util/image.h"

namespace sepal {

constexpr int kSceneMaxObjects = 256;
constexpr int kSceneMaxMaterials = 64;
constexpr int kSceneMaxMeshFiles = 16;

// The camera, lights and transforms with their motion over time (shared with sepal-view's
// scene mode: ports/common/scene_motion.h).
using SceneCamera = sepal_ports::SceneCamera;
using SceneLight = sepal_ports::SceneLight;

struct SceneMaterial {
    std::string name, spec;  // spec: what the exact renderer draws and the bake bakes
    std::string asset;       // a baked asset to use instead of baking (path), or ""
    BakeOptions options;     // the scene's low-cost defaults, then the file's options
    std::vector<uint8_t> measured;  // a measured file's bytes (part of the bake key)
};

struct SceneObject : sepal_ports::SceneTransform {
    std::string name;
    int material = 0;
    std::string mesh;  // sphere, torus, grid, wave, floor (the floor's grid), or a file path
    int floor_cells = 0;
};

struct SceneFile {
    std::string path;
    int width = 640, height = 480;
    double background[3] = {0, 0, 0};
    SceneCamera camera;
    std::vector<SceneLight> lights;
    std::vector<SceneMaterial> materials;
    std::vector<SceneObject> objects;  // the floor first, when the file has one
};

bool read_scene_file(const std::string& path, SceneFile* out, std::string* err);
// The same from text; `source` names it in messages, relative paths resolve against `dir`.
bool parse_scene_text(const std::string& text, const std::string& source, const std::string& dir, SceneFile* out,
                      std::string* err);

// What the frame at time t shows: the camera, the lights, each object's model matrix.
sepal_camera scene_camera_at(const SceneFile& f, double t);
int scene_lights_at(const SceneFile& f, double t, sepal_light lights[SEPAL_MAX_LIGHTS]);
void scene_model_at(const SceneObject& o, double t, float model[16]);

struct SceneMesh {
    std::string name;
    std::vector<sepal_vertex> vertices;
    std::vector<uint16_t> indices;
    sepal_mesh mesh() const;
};

struct LoadedScene {
    SceneFile file;
    std::vector<std::vector<uint8_t>> asset_bytes;    // per material (the asset points into them)
    std::vector<std::unique_ptr<sepal_asset>> assets;
    std::vector<std::unique_ptr<Brdf>> brdfs;          // per material, for the exact renderer
    std::vector<SceneMesh> meshes;                     // each distinct mesh once
    std::vector<int> object_mesh;                      // per object
    int baked = 0, cached = 0;                         // materials baked now, found in the cache
    size_t max_vertices() const;
};

// build/cache/scenes beside the sepal binary's build/bin.
std::string default_scene_cache();
// Bakes each material once (or reads it from cache_dir, keyed as bake-scene keys its assets,
// or from its "asset"), builds or loads each mesh once. log (optional) hears each bake.
bool load_scene(const SceneFile& f, const std::string& cache_dir, LoadedScene* out, std::string* err,
                FILE* log = nullptr);

struct SceneFrame {
    sepal_frame_desc desc{};
    sepal_light lights[SEPAL_MAX_LIGHTS]{};
    int light_count = 0;
    std::vector<sepal_object> objects;  // asset set, material null (GL renders fill it)
};
bool scene_frame(const LoadedScene& s, double t, int width, int height, SceneFrame* out, std::string* err);

// A scene bundle (ports/common/scene_bundle.h) in dir: scene.txt, each material's asset,
// each mesh file's vertices (built-in meshes by name): what sepal-view's scene mode reads.
bool export_scene_bundle(const LoadedScene& s, const std::string& dir, std::string* err);

// The exact renderer, object by object over the background (linear RGB).
bool render_scene_exact(const LoadedScene& s, const SceneFrame& fr, int supersample, Image* out, std::string* err);
// The runtime's CPU backend (linear RGB, unclamped).
bool render_scene_cpu(const LoadedScene& s, const SceneFrame& fr, Image* out, sepal_draw_stats* stats,
                      std::string* err);

// The GL ES pipeline emulated on the CPU (sepal_frame_emulate): RGBA8, top row first, over
// the background rounded to 8 bits.
bool render_scene_emulated(const LoadedScene& s, const SceneFrame& fr, int gles_version, uint32_t mask,
                           std::vector<uint8_t>* rgba, std::string* err);

// A GL ES backend through a headless context (ports/headless): `before` draws the engine's
// frame first (default: a clear to the background colour, depth 1), then one sepal frame
// (sepal_frame_begin, every object, sepal_frame_end) that keeps what it drew. With frames > 1,
// two warm-up frames and info->ms the median frame (before() included, glFinish each).
struct SceneGlOptions {
    int gles_version = 1;
    uint32_t mask = 0;
    sepal_draw_mode mode = SEPAL_MODE_MULTIPASS;
    int framebuffer = 8888;  // the pbuffer's colour buffer: 8888 or 565
    int frames = 1;
    std::function<void()> before;
    std::vector<int> order;  // the objects to draw, in this order (empty: all, in the file's)
};
struct SceneGlInfo {
    sepal_draw_stats stats{};  // summed over the objects of the last frame
    std::string device;
    double ms = 0;
    bool accumulates = false;  // every material sums its passes in an 8-bit target
};
bool render_scene_gl(const LoadedScene& s, const SceneFrame& fr, const SceneGlOptions& opt, std::vector<uint8_t>* rgba,
                     SceneGlInfo* info, std::string* err);

}  // namespace sepal
