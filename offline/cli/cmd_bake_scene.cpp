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
// ("gles1", "gles2", "cpu"), "min_psnr" (dB) and "white" (a number, "auto" or "none").
// Optional top-level "views": the scene's views the bake judges candidates by (and takes its
// white level from) instead of the default scene and its grazing twin, each a name and
// scene flags as `sepal render` takes them:
//   "views": [{"name": "hall", "flags": "--mesh torus --camera 0,-4,1.5 --light point:3,1,2:40"}]
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
#include "cli/cli.h"
#include "common/scene_flags.h"
#include "util/io.h"
#include "util/json_read.h"
#include "sepal/sepal_format.h"

namespace sepal {
namespace {

bool valid_name(const std::string& n) {
    if (n.empty() || n.size() > 64) return false;
    for (char c : n)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
    return true;
}

template <typename T, typename Fn>
bool list(const JsonValue* v, Fn parse, std::vector<T>* out, std::string* err, const char* what) {
    if (!v) return true;
    out->clear();
    const std::vector<JsonValue> one = {*v};
    const std::vector<JsonValue>& items = v->kind == JsonValue::Array ? v->array : one;
    for (const JsonValue& x : items) {
        T t;
        if (!parse(x, &t)) {
            *err = std::string("bad \"") + what + "\" value";
            return false;
        }
        out->push_back(t);
    }
    return !out->empty() || (*err = std::string("empty \"") + what + "\" list", false);
}

// The bake key already in DIR/name.sepal, or "" if there is none (or it is invalid).
std::string existing_key(const std::string& path) {
    std::vector<uint8_t> bytes;
    if (!read_file(path, &bytes, nullptr, SEPAL_FMT_MAX_FILE_BYTES)) return "";
    auto a = std::make_unique<sepal_asset>();
    if (sepal_asset_parse(bytes.data(), bytes.size(), a.get(), nullptr) != SEPAL_OK || !a->meta) return "";
    const std::string meta(a->meta, a->meta_bytes);
    JsonValue v;
    if (!parse_json(meta, &v, nullptr)) return "";
    const JsonValue* k = v.find("bake_key");
    return k && k->kind == JsonValue::String ? k->string : "";
}

}  // namespace

int cmd_bake_scene(const std::vector<std::string>& argv, const CommandIO& io) {
    std::vector<std::string> fixed;
    for (const std::string& a : argv) fixed.push_back(a == "-o" ? "--o" : a);
    Args args(fixed, {"o", "threads"}, {"force"});
    auto bad = [&](const std::string& m) {
        std::fprintf(io.err, "sepal bake-scene: %s\n", m.c_str());
        return kExitBadInput;
    };
    if (!args.ok()) return bad(args.error());
    if (args.positional().size() != 1 || !args.has("o"))
        return bad("usage: sepal bake-scene scene.json -o DIR [--threads N] [--force]");
    long threads = 0;
    if (args.has("threads") && (!args.integer("threads", &threads) || threads < 0 || threads > 256))
        return bad("--threads: 0..256");
    const std::string scene_path = args.positional()[0], dir = args.get("o");
    std::vector<uint8_t> bytes;
    std::string err;
    if (!read_file(scene_path, &bytes, &err, 1u << 20)) return bad(err);
    JsonValue scene;
    if (!parse_json(std::string(bytes.begin(), bytes.end()), &scene, &err)) return bad(scene_path + ": " + err);
    const JsonValue* mats = scene.find("materials");
    if (scene.kind != JsonValue::Object || !mats || mats->kind != JsonValue::Array || mats->array.empty())
        return bad(scene_path + ": expected {\"materials\": [ ... ]} with at least one material");
    if (mats->array.size() > 256) return bad(scene_path + ": more than 256 materials");
    // The scene's own views, shared by every material (and part of each bake key).
    std::vector<BakeView> views;
    std::string views_key;
    if (const JsonValue* vs = scene.find("views")) {
        if (vs->kind != JsonValue::Array || vs->array.empty() || vs->array.size() > 8)
            return bad(scene_path + ": \"views\" must be a list of 1..8 {\"name\", \"flags\"} objects");
        for (size_t i = 0; i < vs->array.size(); ++i) {
            const JsonValue& v = vs->array[i];
            const JsonValue* vname = v.find("name");
            const JsonValue* flags = v.find("flags");
            const std::string where = scene_path + ": views[" + std::to_string(i) + "]";
            if (v.kind != JsonValue::Object || !vname || vname->kind != JsonValue::String || !flags ||
                flags->kind != JsonValue::String || !valid_name(vname->string))
                return bad(where + ": needs a \"name\" (1-64 letters, digits, '_' or '-') and a \"flags\" string");
            sepal_ports::SceneSetup setup;
            std::vector<std::string> words;
            for (size_t a = 0; a < flags->string.size();) {
                const size_t b = flags->string.find(' ', a);
                const std::string w = flags->string.substr(a, b == std::string::npos ? std::string::npos : b - a);
                if (!w.empty()) words.push_back(w);
                if (b == std::string::npos) break;
                a = b + 1;
            }
            std::vector<char*> argv;
            for (std::string& w : words) argv.push_back(&w[0]);
            std::string ferr;
            for (int k = 0; k < int(argv.size());) {
                const int used = sepal_ports::parse_scene_flag(int(argv.size()), argv.data(), k, &setup, &ferr);
                if (used <= 0) return bad(where + ": " + (used < 0 ? ferr : "'" + words[size_t(k)] + "' is not a scene flag"));
                k += used;
            }
            if (!sepal_ports::load_scene_mesh(&setup, &ferr)) return bad(where + ": " + ferr);
            BakeView bv;
            bv.name = vname->string;
            bv.scene = setup.scene;
            bv.vertices.assign(setup.mesh.vertices, setup.mesh.vertices + setup.mesh.vertex_count);
            bv.indices.assign(setup.mesh.indices, setup.mesh.indices + setup.mesh.index_count);
            views.push_back(std::move(bv));
            views_key += vname->string + "=" + flags->string + ";";
        }
    }
    if (!make_dirs(dir, &err)) return bad(err);
    const size_t slash = scene_path.find_last_of('/');
    const std::string base = slash == std::string::npos ? "" : scene_path.substr(0, slash + 1);
    int failed = 0, baked = 0, skipped = 0;
    std::vector<std::string> seen;
    for (size_t m = 0; m < mats->array.size(); ++m) {
        const JsonValue& mat = mats->array[m];
        const JsonValue* name = mat.find("name");
        const JsonValue* spec = mat.find("spec");
        std::string label = "material " + std::to_string(m);
        auto material_fail = [&](const std::string& why) {
            std::fprintf(io.out, "%-20s FAILED: %s\n", label.c_str(), why.c_str());
            ++failed;
        };
        if (mat.kind != JsonValue::Object || !name || name->kind != JsonValue::String || !spec ||
            spec->kind != JsonValue::String) {
            material_fail("needs string \"name\" and \"spec\"");
            continue;
        }
        label = name->string;
        if (!valid_name(name->string)) {
            material_fail("name must be 1-64 letters, digits, '_' or '-'");
            continue;
        }
        if (std::find(seen.begin(), seen.end(), name->string) != seen.end()) {
            material_fail("duplicate name");
            continue;
        }
        seen.push_back(name->string);
        std::string spec_text = spec->string;
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
        std::string perr;
        auto num = [](const JsonValue& x, double* d) {
            if (x.kind != JsonValue::Number) return false;
            *d = x.number;
            return true;
        };
        auto integer = [](const JsonValue& x, int* v) {
            if (x.kind != JsonValue::Number || x.number != std::floor(x.number) || std::fabs(x.number) > 1e6) return false;
            *v = int(x.number);
            return true;
        };
        auto str = [](auto fn) {
            return [fn](const JsonValue& x, auto* out) { return x.kind == JsonValue::String && fn(x.string, out); };
        };
        double d = 0;
        bool ok = list<Param>(mat.find("param"), str(parse_param), &o.params, &perr, "param") &&
                  list<HemiMap>(mat.find("map"), str(parse_map), &o.maps, &perr, "map") &&
                  list<Method>(mat.find("method"), str(parse_method), &o.methods, &perr, "method") &&
                  list<int>(mat.find("res"), integer, &o.resolutions, &perr, "res") &&
                  list<int>(mat.find("terms"), integer, &o.terms, &perr, "terms");
        if (const JsonValue* t = mat.find("target"))
            if (ok && (t->kind != JsonValue::String || !parse_target(t->string, &o.target)))
                ok = false, perr = "\"target\" must be \"gles1\", \"gles2\" or \"cpu\"";
        if (const JsonValue* w = mat.find("white")) {
            if (w->kind == JsonValue::String && (w->string == "auto" || w->string == "none")) o.white = w->string == "none" ? -1 : 0;
            else if (!num(*w, &d) || !(d > 0)) ok = false, perr = "\"white\" must be a number > 0, \"auto\" or \"none\"";
            else o.white = d;
        }
        for (const char* key : {"max_error", "max_passes", "max_bytes", "bits", "cap", "min_psnr"}) {
            const JsonValue* v = mat.find(key);
            if (!ok || !v) continue;
            if (!num(*v, &d) || !(d > 0)) {
                ok = false;
                perr = std::string("\"") + key + "\" must be a number > 0";
                break;
            }
            if (!std::strcmp(key, "max_error")) o.max_error = d;
            if (!std::strcmp(key, "max_passes")) o.max_passes = int(d);
            if (!std::strcmp(key, "max_bytes")) o.max_bytes = int64_t(d);
            if (!std::strcmp(key, "cap")) o.cap = d;
            if (!std::strcmp(key, "min_psnr")) o.min_psnr = d;
            if (!std::strcmp(key, "bits")) {
                if (d != 8 && d != 16) ok = false, perr = "\"bits\" must be 8 or 16";
                o.bits = {int(d)};
            }
        }
        for (const auto& member : mat.object) {
            static const char* const kKnown[] = {"name",      "spec",       "param",     "map",  "method",
                                                 "res",       "terms",      "max_error", "max_passes",
                                                 "max_bytes", "bits",       "cap",       "target", "white",
                                                 "min_psnr"};
            bool known = false;
            for (const char* k : kKnown) known = known || member.first == k;
            if (!known && ok) ok = false, perr = "unknown key \"" + member.first + "\"";
        }
        if (!ok) {
            material_fail(perr);
            continue;
        }
        std::unique_ptr<Brdf> brdf = make_brdf(spec_text, &err);
        if (!brdf) {
            material_fail(err);
            continue;
        }
        // The key: everything that decides the asset's bytes.
        std::string desc = "sepal-bake format " + std::to_string(SEPAL_FMT_VERSION_MAJOR) + "." +
                           std::to_string(SEPAL_FMT_VERSION_MINOR) + "|" + brdf->spec() + "|";
        for (Param p : o.params) desc += std::string(param_name(p)) + ",";
        for (HemiMap p : o.maps) desc += std::string(map_name(p)) + ",";
        for (Method p : o.methods) desc += std::string(method_name(p)) + ",";
        for (int r : o.resolutions) desc += std::to_string(r) + ",";
        for (int t : o.terms) desc += std::to_string(t) + ",";
        char tail[160];
        std::snprintf(tail, sizeof tail, "|%.9g|%d|%lld|%d|%.9g|%s|%.9g|%.9g|", o.max_error, o.max_passes,
                      (long long)o.max_bytes, o.bits[0], o.cap, target_name(o.target), o.white, o.min_psnr);
        desc += tail + views_key;
        uint32_t crc = sepal_crc32(0, desc.data(), desc.size());
        crc = sepal_crc32(crc, measured.data(), measured.size());
        char key[16];
        std::snprintf(key, sizeof key, "%08x", crc);
        o.key = key;
        const std::string out_path = dir + "/" + name->string + ".sepal";
        if (!args.has("force") && existing_key(out_path) == key) {
            std::fprintf(io.out, "%-20s up to date (%s)\n", label.c_str(), out_path.c_str());
            ++skipped;
            continue;
        }
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

}  // namespace sepal
