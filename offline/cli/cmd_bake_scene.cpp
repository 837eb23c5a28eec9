// sepal bake-scene scene.json -o DIR [--threads N] [--force]
//
// A scene file lists the materials a scene needs, each with its own budget:
//   {"materials": [
//     {"name": "brushed_steel", "spec": "ward:rho_d=0.1,rho_s=0.5,ax=0.4,ay=0.1",
//      "max_error": 0.7, "max_passes": 4, "max_bytes": 200000,
//      "param": ["gs-half"], "res": [32], "terms": [1, 2], "method": ["nmf"],
//      "bits": 8, "cap": 2},
//     {"name": "paint", "spec": "cornell/garnet_red.brdf"}]}
// Only "name" and "spec" are required; the rest default as in `sepal bake`, plus "target"
// ("gles1", "gles2", "cpu"), "min_psnr" (dB), "white" (a number, "auto" or "none") and
// "horizon" (the horizon window, 0..1: --horizon).
// Optional top-level "views": the scene's views the bake judges candidates by (and takes its
// white level from) instead of the default scene and its grazing twin, each a name and
// scene flags as `sepal render` takes them:
//   "views": [{"name": "hall", "flags": "--mesh torus --camera 0,-4,1.5 --light point:3,1,2:40"}]
// "lights" (per material, or top-level for every material without one): the light range the
// asset must hold under, as `sepal bake`'s --light-range etc.: {"ratio": 8, "irradiance_max":
// 3.12, "cone": 90, "count": 2, "meshes": ["sphere", "torus"]}, each optional.
// A relative measured-file spec is read relative to the scene file. Each material becomes
// DIR/<name>.sepal; one whose asset already holds the same bake key (a checksum of the
// canonical spec, the measured file's bytes, the options and the format version) is
// skipped. A failing material does not stop the others; the exit code says whether all
// succeeded.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

#include "bake/bake.h"
#include "cli/bake_scene.h"
#include "cli/cli.h"
#include "cli/options.h"
#include "common/scene_flags.h"
#include "util/io.h"
#include "util/json.h"
#include "sepal/sepal_asset.h"
#include "spec/spec.h"

namespace sepal {
namespace {

bool valid_name(const std::string& n) {
    if (n.empty() || n.size() > 64) return false;
    for (char c : n)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
    return true;
}

// A member that is one value or an array of them, each parsed by fn(value, where, &t, err).
template <typename T, typename Fn>
bool list(const JsonField& f, const char* key, Fn parse, std::vector<T>* out, std::string* err) {
    if (!f.object.contains(key)) return true;
    const Json& v = f.object[key];
    const std::string where = f.where + "." + key;
    const Json items = v.is_array() ? v : Json::array({v});
    if (items.empty()) return *err = where + ": empty list", false;
    out->clear();
    for (size_t i = 0; i < items.size(); ++i) {
        T t;
        if (!parse(items[i], v.is_array() ? where + "[" + std::to_string(i) + "]" : where, &t, err)) return false;
        out->push_back(t);
    }
    return true;
}

// A string member parsed by a name parser (parse_param, ...); accepted names in the message.
template <typename T>
auto named(bool (*parse)(const std::string&, T*), const char* accepted) {
    return [parse, accepted](const Json& x, const std::string& where, T* out, std::string* err) {
        if (x.is_string() && parse(x.get<std::string>(), out)) return true;
        *err = where + ": " + x.dump() + " is not one of " + accepted;
        return false;
    };
}

bool int_item(const Json& x, const std::string& where, int* out, std::string* err) {
    int64_t v = 0;
    if (!json_to_int(x, where, 1, 1 << 20, &v, err)) return false;
    *out = int(v);
    return true;
}

}  // namespace

std::string scene_bake_key(const Brdf& brdf, const BakeOptions& o, const std::string& views_key,
                           const std::vector<uint8_t>& measured) {
    // Everything that decides the asset's bytes.
    std::string desc = "sepal-bake format " + std::to_string(SEPAL_FMT_VERSION_MAJOR) + "." +
                       std::to_string(SEPAL_FMT_VERSION_MINOR) + "|" + brdf.spec() + "|";
    for (Param p : o.params) desc += std::string(param_name(p)) + ",";
    for (HemiMap p : o.maps) desc += std::string(map_name(p)) + ",";
    for (Method p : o.methods) desc += std::string(method_name(p)) + ",";
    for (int r : o.resolutions) desc += std::to_string(r) + ",";
    for (int t : o.terms) desc += std::to_string(t) + ",";
    char tail[176];
    std::snprintf(tail, sizeof tail, "|%.9g|%d|%lld|%d|%.9g|%s|%.9g|%.9g|mips %d|", o.max_error, o.max_passes,
                  (long long)o.max_bytes, o.bits[0], o.cap, target_name(o.target), o.white, o.min_psnr, int(o.mips));
    char range[160];
    std::snprintf(range, sizeof range, "|lights %.9g %.9g %.9g %d|", o.light_range.ratio, o.light_range.irradiance_max,
                  o.light_range.cone_degrees, o.light_range.max_lights);
    desc += tail + views_key + range;
    for (const std::string& m : o.light_range.meshes) desc += m + ",";
    if (o.judge_size != BakeOptions().judge_size) desc += "|judge " + std::to_string(o.judge_size);
    if (o.horizon != BakeOptions().horizon) {
        char horizon[48];
        std::snprintf(horizon, sizeof horizon, "|horizon %.9g", o.horizon);
        desc += horizon;
    }
    uint32_t crc = sepal_crc32(0, desc.data(), desc.size());
    crc = sepal_crc32(crc, measured.data(), measured.size());
    char key[16];
    std::snprintf(key, sizeof key, "%08x", crc);
    return key;
}

// The bake key already in DIR/name.sepal, or "" if there is none (or it is invalid).
std::string existing_bake_key(const std::string& path) {
    std::vector<uint8_t> bytes;
    if (!read_file(path, &bytes, nullptr, SEPAL_FMT_MAX_FILE_BYTES)) return "";
    auto a = std::make_unique<sepal_asset>();
    if (sepal_asset_parse(bytes.data(), bytes.size(), a.get(), nullptr) != SEPAL_OK || !a->meta) return "";
    Json v;
    std::string key;
    if (!parse_json(std::string(a->meta, a->meta_bytes), path + " META", &v, nullptr) ||
        !json_string(JsonField{v, ""}, "bake_key", &key, nullptr))
        return "";
    return key;
}

bool scene_light_range(const JsonField& f, LightRange* out, std::string* err) {
    if (!f.object.is_object()) return *err = f.where + ": expected an object {ratio, irradiance_max, cone, count, meshes}", false;
    static const char* const kKnown[] = {"ratio", "irradiance_max", "cone", "count", "meshes"};
    for (const auto& member : f.object.items()) {
        bool known = false;
        for (const char* k : kKnown) known = known || member.key() == k;
        if (!known)
            return *err = f.where + ": unknown key \"" + member.key() + "\" (known: ratio, irradiance_max, cone, count, meshes)",
                   false;
    }
    LightRange& r = *out;
    auto mesh_item = [](const Json& v, const std::string& where, std::string* m, std::string* e) {
        if (!v.is_string()) return *e = where + ": expected a mesh name (sphere, torus, wave)", false;
        *m = v.get<std::string>();
        return true;
    };
    return json_number(f, "ratio", 1, 1e6, &r.ratio, err) && json_number(f, "irradiance_max", 0, 1e6, &r.irradiance_max, err) &&
           json_number(f, "cone", 1, 180, &r.cone_degrees, err) && json_int(f, "count", 1, SEPAL_MAX_LIGHTS, &r.max_lights, err) &&
           list<std::string>(f, "meshes", mesh_item, &r.meshes, err) && validate_light_range(r, err);
}

bool scene_material_options(const JsonField& f, BakeOptions* out, std::string* err) {
    BakeOptions& o = *out;
    const Json& mat = f.object;
    std::string& perr = *err;
    static const char* const kKnown[] = {"name",       "spec",      "param", "map",  "method", "res",
                                         "terms",      "max_error", "max_passes", "max_bytes", "bits", "cap",
                                         "target",     "white",     "min_psnr", "lights", "horizon"};
    bool ok = true;
    for (const auto& member : mat.items()) {
        bool known = false;
        for (const char* k : kKnown) known = known || member.key() == k;
        if (!known && ok) {
            ok = false;
            perr = f.where + ": unknown key \"" + member.key() + "\" (known: name, spec, param, map, method, "
                   "res, terms, max_error, max_passes, max_bytes, bits, cap, target, white, min_psnr, lights, horizon)";
        }
    }
    int bits = 8;
    ok = ok && list<Param>(f, "param", named(parse_param, "gs-half, iv, vh, axis, gs-mirror, rusinkiewicz, elev-azim"), &o.params, &perr) &&
         list<HemiMap>(f, "map", named(parse_map, "xy, parabolic"), &o.maps, &perr) &&
         list<Method>(f, "method", named(parse_method, "acls, wsvd, svd, nmf, nd"), &o.methods, &perr) &&
         list<int>(f, "res", int_item, &o.resolutions, &perr) && list<int>(f, "terms", int_item, &o.terms, &perr) &&
         json_number(f, "max_error", 1e-12, 1e12, &o.max_error, &perr) &&
         json_int(f, "max_passes", 1, 1 << 20, &o.max_passes, &perr) &&
         json_int(f, "max_bytes", int64_t(1), int64_t(1) << 40, &o.max_bytes, &perr) &&
         json_int(f, "bits", 8, 16, &bits, &perr) && json_number(f, "cap", 1e-12, 1e30, &o.cap, &perr) &&
         json_number(f, "min_psnr", 1e-3, 1e3, &o.min_psnr, &perr) &&
         json_number(f, "horizon", 0, 1, &o.horizon, &perr);
    std::string target, white;
    if (ok && json_string(f, "target", &target, &perr) && !target.empty() && !parse_target(target, &o.target))
        ok = false, perr = f.where + ".target: \"" + target + "\" is not one of gles1, gles2, cpu";
    if (ok && mat.contains("white")) {
        if (mat["white"].is_string()) {
            if (!json_string(f, "white", &white, &perr)) ok = false;
            else if (white == "auto" || white == "none") o.white = white == "none" ? -1 : 0;
            else ok = false, perr = f.where + ".white: \"" + white + "\" is not auto, none or a number > 0";
        } else {
            ok = json_number(f, "white", 1e-12, 1e30, &o.white, &perr);
        }
    }
    if (ok && mat.contains("lights") && !scene_light_range({mat["lights"], f.where + ".lights"}, &o.light_range, &perr))
        ok = false;
    if (ok && bits != 8 && bits != 16) ok = false, perr = f.where + ".bits: " + std::to_string(bits) + " is not 8 or 16";
    o.bits = {bits};
    return ok;
}

namespace {

struct BakeSceneArgs {
    std::string scene, dir;
    int threads = 0;
    bool force = false;
};

int run_bake_scene(const BakeSceneArgs& args, const CommandIO& io) {
    auto bad = [&](const std::string& m) {
        std::fprintf(io.err, "sepal bake-scene: %s\n", m.c_str());
        return kExitBadInput;
    };
    const std::string& scene_path = args.scene;
    const std::string& dir = args.dir;
    const int threads = args.threads;
    std::string err;
    Json scene;
    if (!read_json_file(scene_path, &scene, &err, 1u << 20)) return bad(err);
    if (!scene.is_object() || !scene.contains("materials") || !scene["materials"].is_array() ||
        scene["materials"].empty())
        return bad(scene_path + ": expected {\"materials\": [ ... ]} with at least one material");
    // A misspelt key ("view") would otherwise drop what it holds without a word.
    for (auto member = scene.begin(); member != scene.end(); ++member)
        if (member.key() != "materials" && member.key() != "views")
            return bad(scene_path + ": unknown top-level key \"" + member.key() + "\" (known: materials, views)");
    const Json& mats = scene["materials"];
    if (mats.size() > 256) return bad(scene_path + ": more than 256 materials");
    // The scene's own views, shared by every material (and part of each bake key).
    std::vector<BakeView> views;
    std::string views_key;
    if (scene.contains("views")) {
        const Json& vs = scene["views"];
        if (!vs.is_array() || vs.empty() || vs.size() > 8)
            return bad(scene_path + ": \"views\" must be a list of 1..8 {\"name\", \"flags\"} objects");
        for (size_t i = 0; i < vs.size(); ++i) {
            const JsonField vf{vs[i], scene_path + ": views[" + std::to_string(i) + "]"};
            std::string vname, flags;
            if (vs[i].is_object())
                for (auto member = vs[i].begin(); member != vs[i].end(); ++member)
                    if (member.key() != "name" && member.key() != "flags")
                        return bad(vf.where + ": unknown key \"" + member.key() + "\" (known: name, flags)");
            if (!vs[i].is_object() || !json_string(vf, "name", &vname, &err, true) ||
                !json_string(vf, "flags", &flags, &err, true) || !valid_name(vname))
                return bad(vf.where + ": needs a \"name\" (1-64 letters, digits, '_' or '-') and a \"flags\" string");
            sepal_ports::SceneSetup setup;
            std::vector<std::string> words;
            for (size_t a = 0; a < flags.size();) {
                const size_t e = flags.find(' ', a);
                const std::string w = flags.substr(a, e == std::string::npos ? std::string::npos : e - a);
                if (!w.empty()) words.push_back(w);
                if (e == std::string::npos) break;
                a = e + 1;
            }
            std::vector<char*> argv;
            for (std::string& w : words) argv.push_back(&w[0]);
            std::string ferr;
            for (int k = 0; k < int(argv.size());) {
                const int used = sepal_ports::parse_scene_flag(int(argv.size()), argv.data(), k, &setup, &ferr);
                if (used <= 0)
                    return bad(vf.where + ": " + (used < 0 ? ferr : "'" + words[size_t(k)] + "' is not a scene flag"));
                k += used;
            }
            if (!sepal_ports::load_scene_mesh(&setup, &ferr)) return bad(vf.where + ": " + ferr);
            BakeView bv;
            bv.name = vname;
            bv.scene = setup.scene;
            bv.vertices.assign(setup.mesh.vertices, setup.mesh.vertices + setup.mesh.vertex_count);
            bv.indices.assign(setup.mesh.indices, setup.mesh.indices + setup.mesh.index_count);
            views.push_back(std::move(bv));
            views_key += vname + "=" + flags + ";";
        }
    }
    if (!make_dirs(dir, &err)) return bad(err);
    const size_t slash = scene_path.find_last_of('/');
    const std::string base = slash == std::string::npos ? "" : scene_path.substr(0, slash + 1);
    int failed = 0, baked = 0, skipped = 0;
    std::vector<std::string> seen;
    for (size_t m = 0; m < mats.size(); ++m) {
        const Json& mat = mats[m];
        std::string label = "material " + std::to_string(m);
        const JsonField f{mat, scene_path + ": materials[" + std::to_string(m) + "]"};
        auto material_fail = [&](const std::string& why) {
            // The table line on stdout, the error itself on stderr (bad_input_test.cpp, class 10).
            std::fprintf(io.out, "%-20s FAILED (see stderr)\n", label.c_str());
            std::fprintf(io.err, "sepal bake-scene: %s: %s\n", label.c_str(), why.c_str());
            ++failed;
        };
        std::string name, spec_text, perr;
        if (!json_string(f, "name", &name, &perr, true) || !json_string(f, "spec", &spec_text, &perr, true)) {
            material_fail(perr);
            continue;
        }
        label = name;
        if (!valid_name(name)) {
            material_fail("name must be 1-64 letters, digits, '_' or '-'");
            continue;
        }
        if (std::find(seen.begin(), seen.end(), name) != seen.end()) {
            material_fail("duplicate name");
            continue;
        }
        seen.push_back(name);
        const std::string ext = file_extension(spec_text);
        std::vector<uint8_t> measured;
        if (spec_text.find(':') == std::string::npos && (ext == "binary" || ext == "brdf")) {
            if (!spec_text.empty() && spec_text[0] != '/') spec_text = base + spec_text;
            if (!read_file(spec_text, &measured, &err, uint64_t(1) << 30)) {
                material_fail(err);
                continue;
            }
        }
        BakeOptions o;
        o.threads = int(threads);
        o.views = views;
        if (scene.contains("lights") && !scene_light_range({scene["lights"], scene_path + ": lights"}, &o.light_range, &perr)) {
            material_fail(perr);
            continue;
        }
        const bool ok = scene_material_options(f, &o, &perr);
        if (!ok) {
            material_fail(perr);
            continue;
        }
        std::unique_ptr<Brdf> brdf = make_brdf(spec_text, &err);
        if (!brdf) {
            material_fail(err);
            continue;
        }
        o.key = scene_bake_key(*brdf, o, views_key, measured);
        const std::string out_path = dir + "/" + name + ".sepal";
        if (!args.force && existing_bake_key(out_path) == o.key) {
            std::fprintf(io.out, "%-20s up to date (%s)\n", label.c_str(), out_path.c_str());
            ++skipped;
            continue;
        }
        // A material's search can take a minute (bad_input_test.cpp, class 9): said before it starts,
        // with the bake's own progress line on a terminal.
        std::fprintf(io.err, "sepal bake-scene: baking %s (%zu of %zu)\n", label.c_str(), m + 1, mats.size());
        std::fflush(io.err);
        o.progress = true;
        BakeResult r;
        if (!bake(*brdf, o, &r, &err) || !write_asset(out_path, r.asset, &err)) {
            material_fail(err);
            continue;
        }
        const BakeCandidate& w = r.candidates[size_t(r.winner)];
        std::fprintf(io.out, "%-20s baked %s: %s, %.2f dB on %s, %d passes, %lld bytes (%.1f s)\n", label.c_str(),
                     out_path.c_str(), w.label().c_str(), w.psnr, target_name(r.target), w.passes, (long long)w.bytes,
                     r.seconds);
        // Clamps, replacements and fallbacks (bake.h, BakeCounts): never silent.
        for (const std::string& n : r.notes) std::fprintf(io.out, "%-20s note: %s\n", "", n.c_str());
        ++baked;
    }
    std::fprintf(io.out, "%d baked, %d up to date, %d failed\n", baked, skipped, failed);
    return failed ? kExitCheckFailed : kExitOk;
}

}  // namespace

CommandRun setup_bake_scene(CLI::App& app) {
    auto a = std::make_shared<BakeSceneArgs>();
    app.add_option("SCENE", a->scene, "scene file (JSON): {\"materials\": [{\"name\", \"spec\", budgets...}]}")
        ->required();
    app.add_option("-o,--output", a->dir, "folder for the assets (DIR/<name>.sepal)")->required();
    app.add_option("--threads", a->threads, "worker threads, 0 = all cores")
        ->check(CLI::Range(0, 256))
        ->capture_default_str();
    app.add_flag("--force", a->force, "bake every material, even the up-to-date ones");
    return [a](const CommandIO& io) { return run_bake_scene(*a, io); };
}

}  // namespace sepal
