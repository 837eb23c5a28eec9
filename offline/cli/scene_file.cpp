#include "cli/scene_file.h"

#include <cmath>
#include <cstring>
#include <functional>
#include <initializer_list>

#include "bake/asset_file.h"
#include "cli/bake_scene.h"
#include "common/scene_bundle.h"
#include "mesh/gltf_mesh.h"
#include "reference/render_exact.h"
#include "spec/spec.h"
#include "util/io.h"
#include "util/json.h"
#include "sepal/internal/sepal_emulate.h"

namespace sepal {
namespace {

constexpr size_t kMaxSceneBytes = size_t(1) << 20;
constexpr size_t kMaxMeshFileBytes = size_t(256) << 20;

// Refuses members outside `keys`, naming the first one and the accepted ones.
bool known_keys(const JsonField& f, std::initializer_list<const char*> keys, std::string* err) {
    if (!f.object.is_object()) return *err = f.where + ": expected an object, got " + json_kind(f.object), false;
    for (const auto& m : f.object.items()) {
        bool known = false;
        for (const char* k : keys) known = known || m.key() == k;
        if (known) continue;
        std::string list;
        for (const char* k : keys) list += (list.empty() ? "" : ", ") + std::string(k);
        return *err = f.where + ": unknown key \"" + m.key() + "\" (known: " + list + ")", false;
    }
    return true;
}

std::string where_of(const JsonField& f, const char* key) {
    return f.where + (f.where.empty() || f.where.back() == ' ' ? "" : ".") + key;
}

JsonField member(const JsonField& f, const char* key) { return {f.object[key], where_of(f, key)}; }

bool numbers3(const JsonField& f, const char* key, double* out, std::string* err, bool required = false) {
    return json_numbers(f, key, 3, out, err, required);
}

bool colour(const JsonField& f, const char* key, double* out, std::string* err) {
    if (!numbers3(f, key, out, err)) return false;
    for (int c = 0; c < 3; ++c)
        if (!(out[c] >= 0 && out[c] <= 1e6))
            return *err = where_of(f, key) + ": components must be in 0..1e6", false;
    return true;
}

std::string resolve(const std::string& dir, const std::string& p) {
    return p.empty() || p[0] == '/' || dir.empty() ? p : dir + "/" + p;
}

bool parse_camera(const JsonField& f, SceneCamera* c, std::string* err) {
    if (!known_keys(f, {"orbit", "eye", "target", "fov", "near", "far"}, err)) return false;
    const bool orbit = f.object.contains("orbit"), eye = f.object.contains("eye");
    if (orbit == eye) return *err = f.where + ": give either \"orbit\" or \"eye\" (with \"target\")", false;
    c->orbit = orbit;
    if (orbit) {
        const JsonField o = member(f, "orbit");
        if (!known_keys(o, {"target", "distance", "yaw", "pitch", "spin"}, err) || !numbers3(o, "target", c->target, err) ||
            !json_number(o, "distance", 1e-3, 1e4, &c->distance, err, true) || !json_number(o, "yaw", -1e4, 1e4, &c->yaw, err) ||
            !json_number(o, "pitch", -89, 89, &c->pitch, err) || !json_number(o, "spin", -1e4, 1e4, &c->spin, err))
            return false;
        if (f.object.contains("target")) return *err = f.where + ".target: with \"orbit\", give the target inside it", false;
    } else if (!numbers3(f, "eye", c->eye, err, true) || !numbers3(f, "target", c->target, err, true)) {
        return false;
    }
    if (!json_number(f, "fov", 1, 170, &c->fov, err) || !json_number(f, "near", 1e-6, 1e6, &c->z_near, err) ||
        !json_number(f, "far", 1e-6, 1e9, &c->z_far, err))
        return false;
    if (!(c->z_far > c->z_near)) return *err = f.where + ": far must be beyond near", false;
    return true;
}

bool parse_light(const JsonField& f, SceneLight* l, std::string* err) {
    if (!known_keys(f, {"type", "position", "direction", "color", "intensity", "orbit", "pulse"}, err)) return false;
    std::string type = "point";
    if (!json_string(f, "type", &type, err)) return false;
    if (type != "point" && type != "directional")
        return *err = f.where + ".type: \"" + type + "\" is not point or directional", false;
    l->type = type == "point" ? SEPAL_LIGHT_POINT : SEPAL_LIGHT_DIRECTIONAL;
    const char* where = l->type == SEPAL_LIGHT_POINT ? "position" : "direction";
    const char* wrong = l->type == SEPAL_LIGHT_POINT ? "direction" : "position";
    if (f.object.contains(wrong))
        return *err = f.where + "." + wrong + ": a " + type + " light takes \"" + where + "\"", false;
    if (!numbers3(f, where, l->position, err, true) || !colour(f, "color", l->color, err) ||
        !json_number(f, "intensity", 0, 1e6, &l->intensity, err))
        return false;
    if (l->type == SEPAL_LIGHT_DIRECTIONAL &&
        !(l->position[0] * l->position[0] + l->position[1] * l->position[1] + l->position[2] * l->position[2] > 0))
        return *err = f.where + ".direction: must not be zero", false;
    if (f.object.contains("orbit")) {
        const JsonField o = member(f, "orbit");
        if (!known_keys(o, {"period", "phase", "center"}, err) ||
            !json_number(o, "period", 1e-3, 1e6, &l->orbit_period, err, true) ||
            !json_number(o, "phase", -1e4, 1e4, &l->orbit_phase, err) || !numbers3(o, "center", l->orbit_center, err))
            return false;
    }
    if (f.object.contains("pulse")) {
        const JsonField o = member(f, "pulse");
        if (!known_keys(o, {"period", "depth"}, err) || !json_number(o, "period", 1e-3, 1e6, &l->pulse_period, err, true) ||
            !json_number(o, "depth", 0, 1, &l->pulse_depth, err, true))
            return false;
    }
    return true;
}

// The scene's bake defaults: one parameterization, one resolution, two terms, a small judged
// image (a second or two per material; a file's options replace any of them).
BakeOptions scene_bake_defaults() {
    BakeOptions o;
    o.params = {Param::GsHalf};
    o.resolutions = {32};
    o.terms = {2};
    o.methods = {Method::ACLS};
    o.judge_size = 64;
    return o;
}

bool parse_material(const JsonField& f, const std::string& dir, SceneMaterial* m, std::string* err) {
    // bake-scene's options, plus "asset"; "lights" and "views" belong to bake-scene.
    if (!f.object.is_object()) return *err = f.where + ": expected an object, got " + json_kind(f.object), false;
    Json copy = f.object;
    std::string asset;
    if (!json_string(f, "name", &m->name, err, true) || !json_string(f, "spec", &m->spec, err, true) ||
        !json_string(f, "asset", &asset, err))
        return false;
    copy.erase("asset");
    const JsonField opts{copy, f.where};
    if (copy.contains("lights")) return *err = f.where + ".lights: the scene's lights are its own (give none here)", false;
    m->options = scene_bake_defaults();
    if (!scene_material_options(opts, &m->options, err)) return false;
    m->asset = asset.empty() ? "" : resolve(dir, asset);
    const std::string ext = file_extension(m->spec);
    if (m->spec.find(':') == std::string::npos && (ext == "binary" || ext == "brdf")) {
        m->spec = resolve(dir, m->spec);
        if (!read_file(m->spec, &m->measured, err, uint64_t(1) << 30)) return *err = f.where + ".spec: " + *err, false;
    }
    return true;
}

bool parse_transform(const JsonField& f, SceneObject* o, std::string* err) {
    return numbers3(f, "translate", o->translate, err) && numbers3(f, "rotate", o->rotate, err) &&
           json_number(f, "scale", 1e-4, 1e4, &o->scale, err) && json_number(f, "spin", -1e4, 1e4, &o->spin, err);
}

bool material_index(const JsonField& f, const SceneFile& s, int* out, std::string* err) {
    std::string name;
    if (!json_string(f, "material", &name, err, true)) return false;
    for (size_t k = 0; k < s.materials.size(); ++k)
        if (s.materials[k].name == name) return *out = int(k), true;
    return *err = f.where + ".material: no material named \"" + name + "\"", false;
}

bool parse_object(const JsonField& f, const SceneFile& s, const std::string& dir, SceneObject* o, std::string* err) {
    if (!known_keys(f, {"name", "material", "mesh", "translate", "rotate", "scale", "spin"}, err) ||
        !json_string(f, "name", &o->name, err) || !material_index(f, s, &o->material, err) ||
        !json_string(f, "mesh", &o->mesh, err, true) || !parse_transform(f, o, err))
        return false;
    const std::string& m = o->mesh;
    if (m == "sphere" || m == "torus" || m == "grid" || m == "wave") return true;
    const std::string ext = file_extension(m);
    if (ext != "obj" && ext != "gltf" && ext != "glb")
        return *err = f.where + ".mesh: \"" + m + "\" is not sphere, torus, grid, wave or an .obj, .gltf or .glb file", false;
    o->mesh = resolve(dir, m);
    return true;
}

bool parse_floor(const JsonField& f, const SceneFile& s, SceneObject* o, std::string* err) {
    double size = 8, height = 0;
    if (!known_keys(f, {"material", "size", "height", "cells"}, err) || !material_index(f, s, &o->material, err) ||
        !json_number(f, "size", 1e-3, 1e4, &size, err) || !json_number(f, "height", -1e4, 1e4, &height, err))
        return false;
    o->floor_cells = 64;
    if (!json_int(f, "cells", 1, 254, &o->floor_cells, err)) return false;
    o->name = "floor";
    o->mesh = "floor";
    o->scale = size / 2;  // the grid spans [-1,1]^2
    o->translate[2] = height;
    return true;
}

bool parse_list(const JsonField& f, const char* key, size_t lo, size_t hi, bool required,
                const std::function<bool(const JsonField&)>& each, std::string* err) {
    const Json* a = nullptr;
    if (!json_array(f, key, lo, hi, &a, err, required)) return false;
    if (!a) return true;
    for (size_t i = 0; i < a->size(); ++i)
        if (!each(JsonField{(*a)[i], where_of(f, key) + "[" + std::to_string(i) + "]"}))
            return false;
    return true;
}

}  // namespace

bool parse_scene_text(const std::string& text, const std::string& source, const std::string& dir, SceneFile* out,
                      std::string* err) {
    *out = SceneFile();
    out->path = source;
    Json j;
    if (!parse_json(text, source, &j, err)) return false;
    const JsonField f{j, source + ": "};
    const JsonField top{j, source};
    if (!known_keys(top, {"size", "background", "camera", "lights", "materials", "floor", "objects"}, err)) return false;
    double size[2] = {double(out->width), double(out->height)};
    if (!json_numbers(f, "size", 2, size, err)) return false;
    for (int k = 0; k < 2; ++k)
        if (!(size[k] >= 8 && size[k] <= 8192 && size[k] == std::floor(size[k])))
            return *err = source + ": size: width and height must be whole numbers in 8..8192", false;
    out->width = int(size[0]), out->height = int(size[1]);
    if (!colour(f, "background", out->background, err)) return false;
    if (!j.contains("camera")) return *err = source + ": camera: missing (an \"orbit\" or \"eye\"/\"target\")", false;
    if (!parse_camera(JsonField{j["camera"], source + ": camera"}, &out->camera, err)) return false;
    SceneFile& s = *out;
    if (!parse_list(f, "lights", 1, SEPAL_MAX_LIGHTS, true,
                    [&](const JsonField& e) { return s.lights.emplace_back(), parse_light(e, &s.lights.back(), err); }, err) ||
        !parse_list(f, "materials", 1, kSceneMaxMaterials, true,
                    [&](const JsonField& e) {
                        s.materials.emplace_back();
                        if (!parse_material(e, dir, &s.materials.back(), err)) return false;
                        for (size_t k = 0; k + 1 < s.materials.size(); ++k)
                            if (s.materials[k].name == s.materials.back().name)
                                return *err = e.where + ".name: \"" + s.materials[k].name + "\" is used twice", false;
                        return true;
                    },
                    err))
        return false;
    if (j.contains("floor")) {
        s.objects.emplace_back();
        if (!parse_floor(JsonField{j["floor"], source + ": floor"}, s, &s.objects.back(), err)) return false;
    }
    if (!parse_list(f, "objects", 1, kSceneMaxObjects, true,
                    [&](const JsonField& e) { return s.objects.emplace_back(), parse_object(e, s, dir, &s.objects.back(), err); },
                    err))
        return false;
    size_t files = 0;
    for (size_t i = 0; i < s.objects.size(); ++i) {
        bool seen = false;
        for (size_t k = 0; k < i; ++k) seen = seen || s.objects[k].mesh == s.objects[i].mesh;
        files += !seen && file_extension(s.objects[i].mesh) != "";
    }
    if (files > size_t(kSceneMaxMeshFiles))
        return *err = source + ": objects: more than " + std::to_string(kSceneMaxMeshFiles) + " distinct mesh files", false;
    return true;
}

bool read_scene_file(const std::string& path, SceneFile* out, std::string* err) {
    std::vector<uint8_t> bytes;
    if (!read_file(path, &bytes, err, kMaxSceneBytes)) return false;
    const size_t slash = path.find_last_of('/');
    return parse_scene_text(std::string(bytes.begin(), bytes.end()), path,
                            slash == std::string::npos ? "" : path.substr(0, slash), out, err);
}

sepal_camera scene_camera_at(const SceneFile& f, double t) { return sepal_ports::camera_at(f.camera, t); }

int scene_lights_at(const SceneFile& f, double t, sepal_light lights[SEPAL_MAX_LIGHTS]) {
    return sepal_ports::lights_at(f.lights.data(), int(f.lights.size()), t, lights);
}

void scene_model_at(const SceneObject& o, double t, float model[16]) { sepal_ports::model_at(o, t, model); }

sepal_mesh SceneMesh::mesh() const {
    return {const_cast<sepal_vertex*>(vertices.data()), const_cast<uint16_t*>(indices.data()), int(vertices.size()),
            int(indices.size())};
}

size_t LoadedScene::max_vertices() const {
    size_t n = 0;
    for (const SceneMesh& m : meshes) n = std::max(n, m.vertices.size());
    return n;
}

std::string default_scene_cache() {
    // build/bin/sepal -> build/cache/scenes (the tests and benches sit in build/bin too).
    std::string dir = executable_dir();
    const size_t slash = dir.find_last_of('/');
    dir = dir.empty() || slash == std::string::npos ? std::string("build") : dir.substr(0, slash);
    return dir + "/cache/scenes";
}

namespace {

bool build_mesh(const SceneObject& o, SceneMesh* m, std::string* err) {
    const std::string& n = o.mesh;
    m->name = n;
    if (sepal_ports::is_builtin_mesh(n)) return sepal_ports::builtin_mesh(n, o.floor_cells, &m->vertices, &m->indices, err);
    if (file_extension(n) != "obj") {
        GltfMesh g;
        if (!load_gltf_mesh(n, &g, err)) return false;
        m->vertices = std::move(g.vertices);
        m->indices = std::move(g.indices);
        return true;
    }
    std::vector<uint8_t> bytes;
    if (!read_file(n, &bytes, err, kMaxMeshFileBytes)) return false;
    const std::vector<char> text(bytes.begin(), bytes.end());
    sepal_obj_info info;
    sepal_error e = {};
    sepal_result r = sepal_obj_measure(text.data(), text.size(), &info, &e);
    if (r == SEPAL_OK) {
        m->vertices.resize(size_t(info.max_vertices));
        m->indices.resize(size_t(info.max_indices));
        sepal_mesh mesh = {m->vertices.data(), m->indices.data(), info.max_vertices, info.max_indices};
        std::vector<char> scratch(info.scratch_bytes);
        sepal_obj_stats stats;
        r = sepal_obj_load(text.data(), text.size(), &mesh, scratch.data(), scratch.size(), &stats, &e);
        m->vertices.resize(size_t(mesh.vertex_count));
        m->indices.resize(size_t(mesh.index_count));
    }
    if (r != SEPAL_OK) return *err = n + ": " + e.message, false;
    return true;
}

bool load_material(const SceneMaterial& m, const std::string& cache_dir, std::vector<uint8_t>* bytes, bool* baked,
                   std::string* err, FILE* log) {
    *baked = false;
    if (!m.asset.empty()) return read_file(m.asset, bytes, err, SEPAL_FMT_MAX_FILE_BYTES);
    std::unique_ptr<Brdf> brdf = make_brdf(m.spec, err);
    if (!brdf) return false;
    BakeOptions o = m.options;
    o.key = scene_bake_key(*brdf, o, "", m.measured);
    const std::string path = cache_dir + "/" + m.name + "-" + o.key + ".sepal";
    if (existing_bake_key(path) == o.key) return read_file(path, bytes, err, SEPAL_FMT_MAX_FILE_BYTES);
    if (log) std::fprintf(log, "sepal: baking material %s (%s) into %s\n", m.name.c_str(), m.spec.c_str(), path.c_str());
    BakeResult r;
    if (!make_dirs(cache_dir, err) || !bake(*brdf, o, &r, err) || !write_asset(path, r.asset, err)) return false;
    *baked = true;
    return read_file(path, bytes, err, SEPAL_FMT_MAX_FILE_BYTES);
}

}  // namespace

bool load_scene(const SceneFile& f, const std::string& cache_dir, LoadedScene* out, std::string* err, FILE* log) {
    LoadedScene& s = *out;
    s = LoadedScene();
    s.file = f;
    for (const SceneMaterial& m : f.materials) {
        const std::string where = f.path + ": material " + m.name + ": ";
        s.asset_bytes.emplace_back();
        bool baked = false;
        if (!load_material(m, cache_dir, &s.asset_bytes.back(), &baked, err, log)) return *err = where + *err, false;
        (baked ? s.baked : s.cached) += m.asset.empty();
        s.assets.push_back(std::make_unique<sepal_asset>());
        sepal_error e = {};
        const std::vector<uint8_t>& b = s.asset_bytes.back();
        if (sepal_asset_parse(b.data(), b.size(), s.assets.back().get(), &e) != SEPAL_OK)
            return *err = where + "not a valid asset: " + e.message, false;
        s.brdfs.push_back(make_brdf(m.spec, err));
        if (!s.brdfs.back()) return *err = where + *err, false;
    }
    for (const SceneObject& o : f.objects) {
        int found = -1;
        for (size_t k = 0; k < s.meshes.size(); ++k)
            if (s.meshes[k].name == o.mesh) found = int(k);
        if (found < 0) {
            s.meshes.emplace_back();
            if (!build_mesh(o, &s.meshes.back(), err)) return *err = f.path + ": object " + o.name + ": " + *err, false;
            found = int(s.meshes.size()) - 1;
        }
        s.object_mesh.push_back(found);
    }
    return true;
}

bool scene_frame(const LoadedScene& s, double t, int width, int height, SceneFrame* out, std::string* err) {
    SceneFrame& fr = *out;
    fr = SceneFrame();
    sepal_scene sc;
    sepal_scene_default(&sc);
    sc.camera = scene_camera_at(s.file, t);
    fr.light_count = scene_lights_at(s.file, t, fr.lights);
    sepal_error e = {};
    if (!std::isfinite(t) || sepal_scene_matrices(&sc, width, height, fr.desc.view, fr.desc.projection, &e) != SEPAL_OK)
        return *err = s.file.path + ": camera at t = " + std::to_string(t) + ": " + (std::isfinite(t) ? e.message : "t is not finite"), false;
    fr.desc.viewport[2] = width;
    fr.desc.viewport[3] = height;
    for (int c = 0; c < 3; ++c) fr.desc.clear_color[c] = float(s.file.background[c]);
    fr.desc.clear_color[3] = 1.0f;
    for (size_t i = 0; i < s.file.objects.size(); ++i) {
        const SceneObject& so = s.file.objects[i];
        sepal_object o = {};
        o.asset = s.assets[size_t(so.material)].get();
        o.mesh = nullptr;  // set by the renderers from object_mesh (the meshes outlive the frame)
        scene_model_at(so, t, o.model);
        o.lights = fr.lights;
        o.light_count = fr.light_count;
        fr.objects.push_back(o);
    }
    return true;
}

namespace {
// The object with its mesh; `lights` from the frame object `fr` (copied frames keep theirs).
sepal_object object_of(const LoadedScene& s, const SceneFrame& fr, size_t i, sepal_mesh* mesh) {
    *mesh = s.meshes[size_t(s.object_mesh[i])].mesh();
    sepal_object o = fr.objects[i];
    o.mesh = mesh;
    o.lights = fr.lights;
    return o;
}
}  // namespace

bool export_scene_bundle(const LoadedScene& s, const std::string& dir, std::string* err) {
    if (!make_dirs(dir, err)) return false;
    const SceneFile& f = s.file;
    std::string t = "sepal-scene 1\n";
    char line[512];
    std::snprintf(line, sizeof line, "size %d %d\nbackground %.9g %.9g %.9g\n", f.width, f.height, f.background[0],
                  f.background[1], f.background[2]);
    t += line;
    const SceneCamera& c = f.camera;
    if (c.orbit)
        std::snprintf(line, sizeof line, "camera orbit %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", c.target[0],
                      c.target[1], c.target[2], c.distance, c.yaw, c.pitch, c.spin, c.fov, c.z_near, c.z_far);
    else
        std::snprintf(line, sizeof line, "camera eye %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", c.eye[0], c.eye[1],
                      c.eye[2], c.target[0], c.target[1], c.target[2], c.fov, c.z_near, c.z_far);
    t += line;
    for (const SceneLight& l : f.lights) {
        std::snprintf(line, sizeof line,
                      "light %s %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n",
                      l.type == SEPAL_LIGHT_POINT ? "point" : "directional", l.position[0], l.position[1], l.position[2],
                      l.color[0], l.color[1], l.color[2], l.intensity, l.orbit_period, l.orbit_phase, l.orbit_center[0],
                      l.orbit_center[1], l.orbit_center[2], l.pulse_period, l.pulse_depth);
        t += line;
    }
    for (size_t k = 0; k < s.asset_bytes.size(); ++k) {
        const std::string name = "material-" + std::to_string(k) + ".sepal";
        if (!write_file_atomic(dir + "/" + name, s.asset_bytes[k].data(), s.asset_bytes[k].size(), err)) return false;
        t += "material " + name + "\n";
    }
    for (size_t k = 0; k < s.meshes.size(); ++k) {
        const SceneMesh& m = s.meshes[k];
        int cells = 0;
        for (size_t i = 0; i < f.objects.size(); ++i)
            if (s.object_mesh[i] == int(k)) cells = f.objects[i].floor_cells;
        if (sepal_ports::is_builtin_mesh(m.name)) {
            t += "mesh " + m.name + (m.name == "floor" ? " " + std::to_string(cells) : "") + "\n";
            continue;
        }
        const std::string name = "mesh-" + std::to_string(k) + ".mesh";
        const std::vector<uint8_t> b = sepal_ports::encode_bundle_mesh(m.mesh());
        if (!write_file_atomic(dir + "/" + name, b.data(), b.size(), err)) return false;
        t += "mesh " + name + "\n";
    }
    for (size_t i = 0; i < f.objects.size(); ++i) {
        const SceneObject& o = f.objects[i];
        std::snprintf(line, sizeof line, "object %d %d %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", o.material,
                      s.object_mesh[i], o.translate[0], o.translate[1], o.translate[2], o.rotate[0], o.rotate[1],
                      o.rotate[2], o.scale, o.spin);
        t += line;
    }
    return write_file_atomic(dir + "/scene.txt", t.data(), t.size(), err);
}

bool render_scene_exact(const LoadedScene& s, const SceneFrame& fr, int supersample, Image* out, std::string* err) {
    const int w = fr.desc.viewport[2], h = fr.desc.viewport[3];
    *out = Image(w, h, 3);
    for (size_t p = 0; p < size_t(w) * h; ++p)
        for (int c = 0; c < 3; ++c) out->data[3 * p + size_t(c)] = fr.desc.clear_color[c];
    std::vector<float> depth(size_t(w) * h, 1.0f);
    for (size_t i = 0; i < fr.objects.size(); ++i) {
        sepal_mesh mesh;
        const sepal_object o = object_of(s, fr, i, &mesh);
        sepal_scene scene;
        float clip[16];
        sepal_error e = {};
        if (sepal_object_scene(&fr.desc, &o, &scene, clip, &e) != SEPAL_OK)
            return *err = "object " + s.file.objects[i].name + ": " + e.message, false;
        if (!render_exact_object(*s.brdfs[size_t(s.file.objects[i].material)], scene, mesh, clip, w, h, out, &depth,
                                 nullptr, err, supersample))
            return *err = "object " + s.file.objects[i].name + ": " + *err, false;
    }
    return true;
}

bool render_scene_cpu(const LoadedScene& s, const SceneFrame& fr, Image* out, sepal_draw_stats* stats,
                      std::string* err) {
    const int w = fr.desc.viewport[2], h = fr.desc.viewport[3];
    *out = Image(w, h, 3);
    std::vector<float> depth(size_t(w) * h);
    sepal_frame_clear_cpu(w, h, fr.desc.clear_color, out->data.data(), depth.data());
    std::vector<float> scratch(sepal_cpu_scratch_floats(int(s.max_vertices())));
    for (size_t i = 0; i < fr.objects.size(); ++i) {
        sepal_mesh mesh;
        const sepal_object o = object_of(s, fr, i, &mesh);
        sepal_draw_stats st = {};
        sepal_error e = {};
        if (sepal_frame_draw_cpu(&fr.desc, &o, out->data.data(), depth.data(), scratch.data(), scratch.size(), &st, &e) !=
            SEPAL_OK)
            return *err = "object " + s.file.objects[i].name + ": " + e.message, false;
        if (stats) stats->draw_calls += st.draw_calls, stats->dim_lights += st.dim_lights;
    }
    return true;
}

bool render_scene_emulated(const LoadedScene& s, const SceneFrame& fr, int gles_version, uint32_t mask,
                           std::vector<uint8_t>* rgba, std::string* err) {
    const int w = fr.desc.viewport[2], h = fr.desc.viewport[3];
    rgba->assign(size_t(w) * h * 4, 255);
    for (size_t p = 0; p < size_t(w) * h; ++p)
        for (int c = 0; c < 3; ++c)
            (*rgba)[4 * p + size_t(c)] = uint8_t(std::lround(std::min(1.0f, std::max(0.0f, fr.desc.clear_color[c])) * 255.0f));
    std::vector<float> depth(size_t(w) * h);
    sepal_frame_clear_cpu(w, h, nullptr, nullptr, depth.data());
    std::vector<float> scratch(sepal_emulate_scratch_floats(w, h, int(s.max_vertices()), fr.light_count));
    for (size_t i = 0; i < fr.objects.size(); ++i) {
        sepal_mesh mesh;
        const sepal_object o = object_of(s, fr, i, &mesh);
        sepal_error e = {};
        if (sepal_frame_emulate(&fr.desc, &o, gles_version, mask, rgba->data(), depth.data(), scratch.data(),
                                scratch.size(), nullptr, &e) != SEPAL_OK)
            return *err = "object " + s.file.objects[i].name + ": " + e.message, false;
    }
    return true;
}

}  // namespace sepal
