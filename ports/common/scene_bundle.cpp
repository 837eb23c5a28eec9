#include "common/scene_bundle.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sstream>

#include "common/scene_flags.h"

namespace sepal_ports {

namespace {

constexpr size_t kMaxText = size_t(1) << 20;
constexpr size_t kMaxMeshBytes = size_t(64) << 20;

bool numbers(std::istringstream& in, double* out, int n) {
    for (int i = 0; i < n; ++i)
        if (!(in >> out[i])) return false;
    return true;
}

bool plain_name(const std::string& n) {
    return !n.empty() && n.find('/') == std::string::npos && n != "." && n != "..";
}

bool decode_mesh(const std::vector<uint8_t>& b, SceneBundle::Mesh* m, std::string* err) {
    uint32_t nv = 0, ni = 0;
    if (b.size() < 16 || memcmp(b.data(), "SEPALMSH", 8) != 0) return *err = "not a bundle mesh (no SEPALMSH)", false;
    memcpy(&nv, b.data() + 8, 4);
    memcpy(&ni, b.data() + 12, 4);
    if (nv == 0 || nv > 65535 || ni == 0 || ni % 3 || b.size() != 16 + size_t(nv) * sizeof(sepal_vertex) + size_t(ni) * 2)
        return *err = "sizes do not match its " + std::to_string(b.size()) + " bytes", false;
    m->vertices.resize(nv);
    m->indices.resize(ni);
    memcpy(m->vertices.data(), b.data() + 16, size_t(nv) * sizeof(sepal_vertex));
    memcpy(m->indices.data(), b.data() + 16 + size_t(nv) * sizeof(sepal_vertex), size_t(ni) * 2);
    for (uint16_t i : m->indices)
        if (i >= nv) return *err = "index " + std::to_string(i) + " past its " + std::to_string(nv) + " vertices", false;
    return true;
}

bool camera_record(std::istringstream& in, SceneCamera* c) {
    std::string kind;
    in >> kind;
    double v[10];
    c->orbit = kind == "orbit";
    if (c->orbit) {
        if (!numbers(in, v, 10)) return false;
        for (int k = 0; k < 3; ++k) c->target[k] = v[k];
        c->distance = v[3], c->yaw = v[4], c->pitch = v[5], c->spin = v[6], c->fov = v[7], c->z_near = v[8], c->z_far = v[9];
        return c->distance > 0;
    }
    if (kind != "eye" || !numbers(in, v, 9)) return false;
    for (int k = 0; k < 3; ++k) c->eye[k] = v[k], c->target[k] = v[3 + k];
    c->fov = v[6], c->z_near = v[7], c->z_far = v[8];
    return true;
}

bool light_record(std::istringstream& in, SceneLight* l) {
    std::string type;
    double v[14];
    if (!(in >> type) || (type != "point" && type != "directional") || !numbers(in, v, 14)) return false;
    l->type = type == "point" ? SEPAL_LIGHT_POINT : SEPAL_LIGHT_DIRECTIONAL;
    for (int k = 0; k < 3; ++k) l->position[k] = v[k], l->color[k] = v[3 + k], l->orbit_center[k] = v[9 + k];
    l->intensity = v[6], l->orbit_period = v[7], l->orbit_phase = v[8], l->pulse_period = v[12], l->pulse_depth = v[13];
    return true;
}

}  // namespace

size_t SceneBundle::max_vertices() const {
    size_t n = 0;
    for (const Mesh& m : meshes) n = m.vertices.size() > n ? m.vertices.size() : n;
    return n;
}

std::vector<uint8_t> encode_bundle_mesh(const sepal_mesh& mesh) {
    std::vector<uint8_t> b(16 + size_t(mesh.vertex_count) * sizeof(sepal_vertex) + size_t(mesh.index_count) * 2);
    const uint32_t nv = uint32_t(mesh.vertex_count), ni = uint32_t(mesh.index_count);
    memcpy(b.data(), "SEPALMSH", 8);
    memcpy(b.data() + 8, &nv, 4);
    memcpy(b.data() + 12, &ni, 4);
    memcpy(b.data() + 16, mesh.vertices, size_t(nv) * sizeof(sepal_vertex));
    memcpy(b.data() + 16 + size_t(nv) * sizeof(sepal_vertex), mesh.indices, size_t(ni) * 2);
    return b;
}

bool load_scene_bundle(const std::string& path, SceneBundle* out, std::string* err) {
    std::vector<uint8_t> bytes;
    if (!read_bounded_file(path, kMaxText, &bytes, err)) return false;
    const size_t slash = path.find_last_of('/');
    const std::string dir = slash == std::string::npos ? "." : path.substr(0, slash);
    return parse_scene_bundle(std::string(bytes.begin(), bytes.end()), path,
                              [&dir](const std::string& name, size_t max, std::vector<uint8_t>* o, std::string* e) {
                                  return read_bounded_file(dir + "/" + name, max, o, e);
                              },
                              out, err);
}

bool parse_scene_bundle(const std::string& text, const std::string& path, const BundleReader& read, SceneBundle* out,
                        std::string* err) {
    SceneBundle& b = *out;
    b = SceneBundle();
    if (text.size() > kMaxText) return *err = path + ": over 1 MiB", false;
    std::istringstream lines(text);
    std::string line;
    int number = 0;
    auto fail = [&](const std::string& why) {
        *err = path + ": line " + std::to_string(number) + ": " + why;
        return false;
    };
    while (std::getline(lines, line)) {
        ++number;
        std::istringstream in(line);
        std::string rec;
        if (!(in >> rec)) continue;
        if (number == 1 && rec != "sepal-scene") return fail("not a scene bundle (no 'sepal-scene 1')");
        double v[3];
        std::string name;
        if (rec == "sepal-scene") {
            if (!(in >> name) || name != "1") return fail("version '" + name + "' (this reader knows 1)");
        } else if (rec == "size") {
            if (!numbers(in, v, 2) || !(v[0] >= 8 && v[0] <= 8192 && v[1] >= 8 && v[1] <= 8192)) return fail("size W H, 8..8192");
            b.width = int(v[0]), b.height = int(v[1]);
        } else if (rec == "background") {
            if (!numbers(in, v, 3)) return fail("background R G B");
            for (int k = 0; k < 3; ++k) b.background[k] = float(v[k]);
        } else if (rec == "camera") {
            if (!camera_record(in, &b.camera)) return fail("camera orbit (10 numbers) or camera eye (9 numbers)");
        } else if (rec == "light") {
            if (b.lights.size() >= SEPAL_MAX_LIGHTS) return fail("more than 8 lights");
            b.lights.emplace_back();
            if (!light_record(in, &b.lights.back())) return fail("light point|directional and 14 numbers");
        } else if (rec == "material") {
            if (!(in >> name) || !plain_name(name) || b.assets.size() >= 64) return fail("material FILE.sepal (64 at most)");
            b.asset_bytes.emplace_back();
            if (!read(name, SEPAL_FMT_MAX_FILE_BYTES, &b.asset_bytes.back(), err)) return fail(*err);
            b.assets.push_back(std::make_unique<sepal_asset>());
            sepal_error e = {};
            const std::vector<uint8_t>& a = b.asset_bytes.back();
            if (sepal_asset_parse(a.data(), a.size(), b.assets.back().get(), &e) != SEPAL_OK) return fail(name + ": " + e.message);
        } else if (rec == "mesh") {
            if (!(in >> name) || b.meshes.size() >= 256) return fail("mesh NAME (256 at most)");
            b.meshes.emplace_back();
            SceneBundle::Mesh& m = b.meshes.back();
            int cells = 0;
            if (name == "floor" && !(in >> cells)) return fail("mesh floor CELLS");
            if (is_builtin_mesh(name)) {
                if (!builtin_mesh(name, cells, &m.vertices, &m.indices, err)) return fail(*err);
            } else {
                std::vector<uint8_t> mb;
                if (!plain_name(name)) return fail("mesh NAME: a file beside scene.txt");
                if (!read(name, kMaxMeshBytes, &mb, err)) return fail(*err);
                if (!decode_mesh(mb, &m, err)) return fail(name + ": " + *err);
            }
        } else if (rec == "object") {
            double n[2], x[8];
            if (!numbers(in, n, 2) || !numbers(in, x, 8)) return fail("object MATERIAL MESH and 8 numbers");
            if (!(n[0] >= 0 && n[0] < double(b.assets.size()) && n[1] >= 0 && n[1] < double(b.meshes.size())))
                return fail("object: material or mesh index out of range (records above this line)");
            if (!(x[6] > 0) || b.objects.size() >= 256) return fail("object: scale must be > 0 (256 objects at most)");
            SceneBundle::Object o;
            o.material = int(n[0]), o.mesh = int(n[1]);
            for (int k = 0; k < 3; ++k) o.transform.translate[k] = x[k], o.transform.rotate[k] = x[3 + k];
            o.transform.scale = x[6], o.transform.spin = x[7];
            b.objects.push_back(o);
        } else {
            return fail("unknown record '" + rec + "'");
        }
    }
    if (b.objects.empty() || b.lights.empty()) return *err = path + ": no objects or no lights", false;
    return true;
}

bool bundle_frame(const SceneBundle& b, double t, double yaw, double pitch, int width, int height,
                  sepal_frame_desc* desc, sepal_light lights[SEPAL_MAX_LIGHTS], int* light_count,
                  std::vector<sepal_object>* objects, std::string* err) {
    SceneCamera cam = b.camera;
    cam.yaw += yaw;
    cam.pitch = cam.pitch + pitch > 89 ? 89 : cam.pitch + pitch < -89 ? -89 : cam.pitch + pitch;
    sepal_scene sc;
    sepal_scene_default(&sc);
    sc.camera = camera_at(cam, t);
    *desc = sepal_frame_desc{};
    sepal_error e = {};
    if (sepal_scene_matrices(&sc, width, height, desc->view, desc->projection, &e) != SEPAL_OK) return *err = e.message, false;
    desc->viewport[2] = width;
    desc->viewport[3] = height;
    for (int k = 0; k < 3; ++k) desc->clear_color[k] = b.background[k];
    desc->clear_color[3] = 1.0f;
    *light_count = lights_at(b.lights.data(), int(b.lights.size()), t, lights);
    objects->clear();
    for (const SceneBundle::Object& bo : b.objects) {
        sepal_object o = {};
        o.asset = b.assets[size_t(bo.material)].get();
        model_at(bo.transform, t, o.model);
        o.lights = lights;
        o.light_count = *light_count;
        objects->push_back(o);
    }
    return true;
}

}  // namespace sepal_ports
