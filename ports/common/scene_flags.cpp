#include "common/scene_flags.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace sepal_ports {
namespace {

// Parses exactly n comma-separated finite floats.
bool parse_floats(const std::string& text, int n, float* out) {
    const char* p = text.c_str();
    for (int k = 0; k < n; ++k) {
        char* end = nullptr;
        errno = 0;
        const float v = std::strtof(p, &end);
        if (end == p || errno == ERANGE || !std::isfinite(v)) return false;
        out[k] = v;
        p = end;
        if (k + 1 < n) {
            if (*p != ',') return false;
            ++p;
        }
    }
    return *p == '\0';
}

// A side of --size: decimal digits for 1..8192, ending at `end`.
bool parse_side(const std::string& text, char end, int* out) {
    long long v = 0;
    size_t i = 0;
    for (; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i) {
        v = v * 10 + (text[i] - '0');
        if (v > 8192) return false;
    }
    if (i == 0 || v < 1 || (end ? i >= text.size() || text[i] != end : i != text.size())) return false;
    *out = int(v);
    return true;
}

bool parse_light(const std::string& text, sepal_light* l, std::string* err) {
    const size_t c1 = text.find(':');
    if (c1 == std::string::npos) {
        *err = "--light '" + text + "': expected point:X,Y,Z[:I] or dir:X,Y,Z[:I]";
        return false;
    }
    const std::string type = text.substr(0, c1);
    const size_t c2 = text.find(':', c1 + 1);
    const std::string pos = text.substr(c1 + 1, c2 == std::string::npos ? std::string::npos : c2 - c1 - 1);
    *l = sepal_light{};
    if (type == "point") {
        l->type = SEPAL_LIGHT_POINT;
    } else if (type == "dir") {
        l->type = SEPAL_LIGHT_DIRECTIONAL;
    } else {
        *err = "--light '" + text + "': type must be point or dir";
        return false;
    }
    if (!parse_floats(pos, 3, l->position)) {
        *err = "--light '" + text + "': position/direction must be three numbers X,Y,Z";
        return false;
    }
    // Default intensity: irradiance about pi at distance 4.4 for points, pi for directional
    // lights (a white Lambertian surface facing the light shows as 1).
    float i3[3] = {3.14159265f, 3.14159265f, 3.14159265f};
    if (l->type == SEPAL_LIGHT_POINT) i3[0] = i3[1] = i3[2] = 60.0f;
    if (c2 != std::string::npos) {
        const std::string in = text.substr(c2 + 1);
        if (parse_floats(in, 1, i3)) {
            i3[1] = i3[2] = i3[0];
        } else if (!parse_floats(in, 3, i3)) {
            *err = "--light '" + text + "': intensity must be I or R,G,B";
            return false;
        }
    }
    std::memcpy(l->intensity, i3, sizeof i3);
    return true;
}

}  // namespace

const char* scene_flags_help() {
    return "  --size WxH            image size (default 512x512)\n"
           "  --mesh NAME           sphere (default), torus, wave, or PATH.obj\n"
           "  --camera X,Y,Z        eye position (default 0,-3.2,1.4)\n"
           "  --target X,Y,Z        look-at point (default 0,0,0)\n"
           "  --fov DEGREES         vertical field of view (default 38)\n"
           "  --light point:X,Y,Z[:I|:R,G,B]  point light (up to 8; default point:2,-2.5,3:60)\n"
           "  --light dir:X,Y,Z[:I|:R,G,B]    directional light, towards the light\n"
           "  --background R,G,B    linear background colour (default 0,0,0)\n";
}

int parse_scene_flag(int argc, char** argv, int i, SceneSetup* s, std::string* err) {
    const std::string flag = argv[i];
    static const char* const kFlags[] = {"--size", "--mesh", "--camera", "--target",
                                         "--fov",  "--light", "--background"};
    bool known = false;
    for (const char* f : kFlags) known = known || flag == f;
    if (!known) return 0;
    if (i + 1 >= argc) {
        *err = flag + " needs a value";
        return -1;
    }
    const std::string value = argv[i + 1];
    sepal_camera& cam = s->scene.camera;
    if (flag == "--size") {
        // Each side checked as a 64-bit value before it becomes an int (sscanf's %d wraps
        // 4294967297 to 1).
        int w = 0, h = 0;
        if (!parse_side(value, 'x', &w) || !parse_side(value.substr(value.find('x') + 1), '\0', &h)) {
            *err = "--size '" + value + "': expected WxH with sides 1..8192";
            return -1;
        }
        s->width = w;
        s->height = h;
    } else if (flag == "--mesh") {
        s->mesh_name = value;
    } else if (flag == "--camera" || flag == "--target" || flag == "--background") {
        if (flag != "--background") s->camera_given = true;
        float* dst = flag == "--camera" ? cam.eye : flag == "--target" ? cam.target : s->scene.background;
        if (!parse_floats(value, 3, dst)) {
            *err = flag + " '" + value + "': expected three numbers X,Y,Z";
            return -1;
        }
        if (flag == "--background" && !(dst[0] >= 0 && dst[1] >= 0 && dst[2] >= 0)) {
            *err = "--background '" + value + "': linear RGB, each channel >= 0";
            return -1;
        }
    } else if (flag == "--fov") {
        if (!parse_floats(value, 1, &cam.fovy_degrees)) {
            *err = "--fov '" + value + "': expected a number of degrees";
            return -1;
        }
    } else if (flag == "--light") {
        if (!s->lights_given) s->scene.light_count = 0;
        s->lights_given = true;
        if (s->scene.light_count >= SEPAL_MAX_LIGHTS) {
            *err = "at most " + std::to_string(SEPAL_MAX_LIGHTS) + " --light flags";
            return -1;
        }
        if (!parse_light(value, &s->scene.lights[s->scene.light_count], err)) return -1;
        ++s->scene.light_count;
    }
    return 2;
}

bool read_bounded_file(const std::string& path, size_t max_bytes, std::vector<uint8_t>* out, std::string* err) {
    FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) {
        *err = path + ": " + std::strerror(errno);
        return false;
    }
    out->clear();
    uint8_t buf[65536];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) {
        out->insert(out->end(), buf, buf + n);
        if (out->size() > max_bytes) {
            std::fclose(f);
            *err = path + ": larger than the limit of " + std::to_string(max_bytes) + " bytes";
            return false;
        }
    }
    const bool failed = std::ferror(f) != 0;
    std::fclose(f);
    if (failed) *err = path + ": read error";
    return !failed;
}

namespace {
// See load_scene_mesh in the header. Built-in meshes keep the default scene (the goldens).
// False (with the reason) when the frame it computes does not fit in floats: a mesh of huge
// coordinates, or a small one far from the origin, whose eye would round onto its target.
bool frame_by_bounds(SceneSetup* s, std::string* err) {
    const sepal_mesh& m = s->mesh;
    if (m.vertex_count < 1) return true;
    double lo[3], hi[3];
    for (int k = 0; k < 3; ++k) lo[k] = hi[k] = m.vertices[0].position[k];
    for (int i = 0; i < m.vertex_count; ++i)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::fmin(lo[k], m.vertices[i].position[k]);
            hi[k] = std::fmax(hi[k], m.vertices[i].position[k]);
        }
    const double c[3] = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
    double r2 = 0;
    for (int i = 0; i < m.vertex_count; ++i) {
        double d2 = 0;
        for (int k = 0; k < 3; ++k) d2 += (m.vertices[i].position[k] - c[k]) * (m.vertices[i].position[k] - c[k]);
        r2 = std::fmax(r2, d2);
    }
    const double r = std::fmax(std::sqrt(r2), 1e-6);
    sepal_camera& cam = s->scene.camera;
    if (!s->camera_given) {
        static const double kEye[3] = {0.0, -3.2, 1.4};
        for (int k = 0; k < 3; ++k) cam.eye[k] = float(c[k] + r * kEye[k]), cam.target[k] = float(c[k]);
    }
    if (!s->lights_given && s->scene.light_count == 1 && s->scene.lights[0].type == SEPAL_LIGHT_POINT) {
        static const double kLight[3] = {2.0, -2.5, 3.0};
        sepal_light& l = s->scene.lights[0];
        for (int k = 0; k < 3; ++k) l.position[k] = float(c[k] + r * kLight[k]), l.intensity[k] *= float(r * r);
    }
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += (cam.eye[k] - c[k]) * (cam.eye[k] - c[k]);
    const double d = std::sqrt(d2);
    // The sphere lies between d - r and d + r from the eye; 1% slack, and a near plane at
    // most 1000 times closer than the far one (depth precision) when the eye is inside.
    cam.z_far = float((d + r) * 1.01);
    cam.z_near = float(std::fmax((d - r) * 0.99, cam.z_far * 1e-3));
    s->framed = true;
    if (s->camera_given && s->lights_given) return true;
    bool fits = std::isfinite(cam.z_far) && std::isfinite(cam.z_near) && cam.z_near > 0.0f;
    for (int k = 0; k < 3; ++k)
        fits = fits && std::isfinite(cam.eye[k]) && std::isfinite(s->scene.lights[0].position[k]) &&
               std::isfinite(s->scene.lights[0].intensity[k]);
    if (fits && !s->camera_given) {
        // The view direction as the floats have it (rounding can take it off the framing
        // direction, or to 0), against the up vector, as sepal_scene_validate will judge it.
        const double d[3] = {double(cam.target[0]) - cam.eye[0], double(cam.target[1]) - cam.eye[1],
                             double(cam.target[2]) - cam.eye[2]};
        const double x[3] = {d[1] * cam.up[2] - d[2] * cam.up[1], d[2] * cam.up[0] - d[0] * cam.up[2],
                             d[0] * cam.up[1] - d[1] * cam.up[0]};
        const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        fits = len > 1e-3 * r && std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) > 0.1 * len;
    }
    if (fits) return true;
    char m_text[320];
    std::snprintf(m_text, sizeof m_text,
                  "%s: the mesh's bounding sphere (radius %g about %g, %g, %g) is too large or too far from the "
                  "origin to frame %s in floats; scale or centre the model%s",
                  s->mesh_name.c_str(), r, c[0], c[1], c[2], s->camera_given ? "the light" : "a camera",
                  s->camera_given ? ", or give --light" : ", or give --camera and --light");
    *err = m_text;
    return false;
}
}  // namespace

bool load_scene_mesh(SceneSetup* s, std::string* err) {
    sepal_error e = {};
    sepal_result r;
    const std::string& name = s->mesh_name;
    if (name == "sphere" || name == "torus" || name == "wave") {
        const int sl = SEPAL_SCENE_SPHERE_SLICES, st = SEPAL_SCENE_SPHERE_STACKS;
        s->vertices.resize(name == "sphere" ? size_t(sl + 1) * (st + 1) : name == "torus" ? 97 * 49 : 65 * 65);
        s->indices.resize(name == "sphere" ? size_t(sl) * st * 6 : name == "torus" ? 96 * 48 * 6 : 64 * 64 * 6);
        s->mesh = {s->vertices.data(), s->indices.data(), int(s->vertices.size()), int(s->indices.size())};
        r = name == "sphere" ? sepal_mesh_sphere(sl, st, &s->mesh, &e)
            : name == "torus" ? sepal_mesh_torus(0.72f, 0.3f, 96, 48, &s->mesh, &e)
                              : sepal_mesh_wave(64, &s->mesh, &e);
    } else {
        std::vector<uint8_t> bytes;
        if (!read_bounded_file(name, size_t(256) << 20, &bytes, err)) {
            *err = "--mesh: not sphere, torus or wave, and " + *err;
            return false;
        }
        const std::vector<char> text(bytes.begin(), bytes.end());
        sepal_obj_info info;
        r = sepal_obj_measure(text.data(), text.size(), &info, &e);
        if (r == SEPAL_OK) {
            s->vertices.resize(size_t(info.max_vertices));
            s->indices.resize(size_t(info.max_indices));
            std::vector<char> scratch(info.scratch_bytes);
            s->mesh = {s->vertices.data(), s->indices.data(), int(s->vertices.size()),
                       int(s->indices.size())};
            r = sepal_obj_load(text.data(), text.size(), &s->mesh, scratch.data(), scratch.size(),
                             &s->obj_stats, &e);
        }
        if (r != SEPAL_OK) {
            *err = name + ": " + e.message;
            return false;
        }
        if (!frame_by_bounds(s, err)) return false;
    }
    if (r != SEPAL_OK || sepal_scene_validate(&s->scene, &e) != SEPAL_OK) {
        *err = e.message;
        return false;
    }
    return true;
}

}  // namespace sepal_ports
