#include "common/scene_args.h"

#include <stdio.h>
#include <stdlib.h>

namespace sepal_ports {
namespace {
// The shortest %g form that reads back as the same float (3.2, not 3.20000005).
std::string shortest(float v) {
    char buf[32];
    for (int digits = 6; digits <= 9; ++digits) {
        snprintf(buf, sizeof buf, "%.*g", digits, (double)v);
        if (strtof(buf, nullptr) == v) break;
    }
    return buf;
}

std::string floats(const float* v, int n) {
    std::string s;
    for (int i = 0; i < n; ++i) s += (i ? "," : "") + shortest(v[i]);
    return s;
}
}  // namespace

std::vector<std::string> scene_args(const SceneSetup& s) {
    const sepal_scene& sc = s.scene;
    std::vector<std::string> a = {"--size", std::to_string(s.width) + "x" + std::to_string(s.height),
                                  "--mesh", s.mesh_name,
                                  "--camera", floats(sc.camera.eye, 3),
                                  "--target", floats(sc.camera.target, 3),
                                  "--fov", floats(&sc.camera.fovy_degrees, 1)};
    for (int l = 0; l < sc.light_count; ++l) {
        const sepal_light& light = sc.lights[l];
        a.push_back("--light");
        a.push_back(std::string(light.type == SEPAL_LIGHT_POINT ? "point:" : "dir:") + floats(light.position, 3) + ":" +
                    floats(light.intensity, 3));
    }
    if (sc.background[0] != 0.0f || sc.background[1] != 0.0f || sc.background[2] != 0.0f) {
        a.push_back("--background");
        a.push_back(floats(sc.background, 3));
    }
    return a;
}

std::string shell_join(const std::vector<std::string>& args) {
    static const char kPlain[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_.,:/=+@%";
    std::string out;
    for (const std::string& a : args) {
        if (!out.empty()) out += ' ';
        if (!a.empty() && a.find_first_not_of(kPlain) == std::string::npos) {
            out += a;
            continue;
        }
        out += '\'';
        for (char c : a) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
        out += '\'';
    }
    return out;
}

}  // namespace sepal_ports
