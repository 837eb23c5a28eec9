// bake-scene's scene file through the project's JSON reader (util/json.h: parse_json with
// its stricter rules, then the typed readers as cmd_bake_scene.cpp calls them): every
// material's name, spec and options. An accepted option is inside the range bake-scene
// documents; a refusal names the member.
#include <cmath>
#include <string>

#include "cli/bake_scene.h"
#include "fuzz/fuzz.h"
#include "util/json.h"

extern "C" int sepal_fuzz_scene_json(const uint8_t* data, size_t size) {
    const char* h = "scene_json";
    sepal::Json scene;
    std::string err;
    if (!sepal::parse_json(std::string(reinterpret_cast<const char*>(data), size), "scene.json", &scene, &err)) {
        sepal_fuzz::check(err.compare(0, 11, "scene.json:") == 0, h, "a JSON refusal that does not name the file");
        return 0;
    }
    if (!scene.is_object() || !scene.contains("materials") || !scene["materials"].is_array()) return 0;
    const sepal::Json& mats = scene["materials"];
    for (size_t m = 0; m < mats.size() && m < 256; ++m) {
        if (!mats[m].is_object()) continue;
        const sepal::JsonField f{mats[m], "scene.json: materials[" + std::to_string(m) + "]"};
        std::string name, spec;
        err.clear();
        if (!sepal::json_string(f, "name", &name, &err, true) || !sepal::json_string(f, "spec", &spec, &err, true)) {
            sepal_fuzz::check(!err.empty(), h, "a refusal without a message");
            continue;
        }
        sepal::BakeOptions o;
        if (!sepal::scene_material_options(f, &o, &err)) {
            sepal_fuzz::check(err.compare(0, f.where.size(), f.where) == 0, h, "a refusal that does not name the material");
            continue;
        }
        sepal_fuzz::check(o.max_passes == -1 || (o.max_passes >= 1 && o.max_passes <= (1 << 20)), h, "max_passes out of range");
        sepal_fuzz::check(o.max_bytes == -1 || (o.max_bytes >= 1 && o.max_bytes <= (int64_t(1) << 40)), h, "max_bytes out of range");
        sepal_fuzz::check(std::isfinite(o.max_error) && std::isfinite(o.cap) && std::isfinite(o.white) &&
                              std::isfinite(o.min_psnr),
                          h, "a non-finite option");
        for (int r : o.resolutions) sepal_fuzz::check(r >= 1 && r <= (1 << 20), h, "res out of range");
        for (int t : o.terms) sepal_fuzz::check(t >= 1 && t <= (1 << 20), h, "terms out of range");
        for (int b : o.bits) sepal_fuzz::check(b == 8 || b == 16, h, "bits not 8 or 16");
    }
    return 0;
}
