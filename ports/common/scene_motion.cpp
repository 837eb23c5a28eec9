#include "common/scene_motion.h"

#include <math.h>
#include <string.h>

namespace sepal_ports {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

sepal_camera camera_at(const SceneCamera& c, double t) {
    sepal_camera cam{};
    double eye[3];
    if (c.orbit) {
        const double yaw = (c.yaw + c.spin * t) * kPi / 180, pitch = c.pitch * kPi / 180;
        eye[0] = c.target[0] + c.distance * cos(pitch) * sin(yaw);
        eye[1] = c.target[1] - c.distance * cos(pitch) * cos(yaw);
        eye[2] = c.target[2] + c.distance * sin(pitch);
    } else {
        memcpy(eye, c.eye, sizeof eye);
    }
    for (int k = 0; k < 3; ++k) cam.eye[k] = float(eye[k]), cam.target[k] = float(c.target[k]), cam.up[k] = k == 2;
    cam.fovy_degrees = float(c.fov);
    cam.z_near = float(c.z_near);
    cam.z_far = float(c.z_far);
    return cam;
}

int lights_at(const SceneLight* lights, int count, double t, sepal_light out[SEPAL_MAX_LIGHTS]) {
    int n = 0;
    for (int i = 0; i < count && n < SEPAL_MAX_LIGHTS; ++i) {
        const SceneLight& l = lights[i];
        sepal_light& o = out[n++];
        o = sepal_light{};
        o.type = l.type;
        double p[3] = {l.position[0], l.position[1], l.position[2]};
        if (l.orbit_period > 0) {
            const double a = (l.orbit_phase + 360.0 * t / l.orbit_period) * kPi / 180, ca = cos(a), sa = sin(a);
            const double* c = l.type == SEPAL_LIGHT_POINT ? l.orbit_center : nullptr;
            const double x = p[0] - (c ? c[0] : 0), y = p[1] - (c ? c[1] : 0);
            p[0] = ca * x - sa * y + (c ? c[0] : 0);
            p[1] = sa * x + ca * y + (c ? c[1] : 0);
        }
        const double pulse = l.pulse_period > 0 ? 1 - l.pulse_depth * 0.5 * (1 - cos(2 * kPi * t / l.pulse_period)) : 1;
        for (int k = 0; k < 3; ++k) o.position[k] = float(p[k]), o.intensity[k] = float(l.color[k] * l.intensity * pulse);
    }
    return n;
}

void model_at(const SceneTransform& o, double t, float model[16]) {
    const double rx = o.rotate[0] * kPi / 180, ry = o.rotate[1] * kPi / 180, rz = (o.rotate[2] + o.spin * t) * kPi / 180;
    const double cx = cos(rx), sx = sin(rx), cy = cos(ry), sy = sin(ry), cz = cos(rz), sz = sin(rz);
    const double r[3][3] = {{cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx},
                            {sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx},
                            {-sy, cy * sx, cy * cx}};
    for (int c = 0; c < 3; ++c) {
        for (int row = 0; row < 3; ++row) model[4 * c + row] = float(r[row][c] * o.scale);
        model[4 * c + 3] = 0.0f;
        model[12 + c] = float(o.translate[c]);
    }
    model[15] = 1.0f;
}

bool is_builtin_mesh(const std::string& n) {
    return n == "sphere" || n == "torus" || n == "grid" || n == "wave" || n == "floor";
}

bool builtin_mesh(const std::string& n, int cells, std::vector<sepal_vertex>* v, std::vector<uint16_t>* idx,
                  std::string* err) {
    auto sized = [&](size_t nv, size_t ni) {
        v->resize(nv);
        idx->resize(ni);
        return sepal_mesh{v->data(), idx->data(), int(nv), int(ni)};
    };
    sepal_mesh mesh{};
    sepal_error e = {};
    sepal_result r;
    if (n == "sphere") mesh = sized(65 * 33, 64 * 32 * 6), r = sepal_mesh_sphere(64, 32, &mesh, &e);
    else if (n == "torus") mesh = sized(65 * 33, 64 * 32 * 6), r = sepal_mesh_torus(0.72f, 0.3f, 64, 32, &mesh, &e);
    else if (n == "grid") mesh = sized(33 * 33, 32 * 32 * 6), r = sepal_mesh_grid(32, &mesh, &e);
    else if (n == "wave") mesh = sized(49 * 49, 48 * 48 * 6), r = sepal_mesh_wave(48, &mesh, &e);
    else if (n == "floor" && cells >= 1 && cells <= 254)
        mesh = sized(size_t(cells + 1) * size_t(cells + 1), size_t(cells) * size_t(cells) * 6),
        r = sepal_mesh_grid(cells, &mesh, &e);
    else
        return *err = "\"" + n + "\" is not a built-in mesh (sphere, torus, grid, wave, floor with 1..254 cells)", false;
    if (r != SEPAL_OK) return *err = n + ": " + e.message, false;
    v->resize(size_t(mesh.vertex_count));
    idx->resize(size_t(mesh.index_count));
    return true;
}

}  // namespace sepal_ports
