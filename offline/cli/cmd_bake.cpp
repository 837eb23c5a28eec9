// sepal bake SPEC -o out.sepal [factor options] [--bits 8,16] [--target gles1|gles2|cpu]
//   [--white auto|none|W] [--fit radiance|brdf] [--min-psnr D] [--max-error E]
//   [--max-passes P] [--max-bytes B] [--backend B] [--timings tradeoff.json]
//   [--report r.json] [--export DIR] [--threads N]
#include <cmath>
#include <cstring>

#include "bake/bake.h"
#include "cli/cli.h"
#include "util/image.h"
#include "util/io.h"
#include "util/json.h"
#include "bake/quantize.h"

namespace sepal {
namespace {

// Splits "a,b,c" and parses each with fn; false with *err naming the option.
template <typename T, typename Fn>
bool parse_list(const std::string& option, const std::string& text, Fn fn, std::vector<T>* out, std::string* err) {
    out->clear();
    size_t start = 0;
    while (start <= text.size()) {
        const size_t comma = text.find(',', start);
        const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        T v;
        if (item.empty() || !fn(item, &v)) {
            *err = "--" + option + ": '" + item + "' is not valid";
            return false;
        }
        out->push_back(v);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return true;
}

bool parse_int(const std::string& s, int* v) {
    char* end = nullptr;
    const long x = std::strtol(s.c_str(), &end, 10);
    if (*end || x < -1000000 || x > 1000000) return false;
    *v = int(x);
    return true;
}

// One PNG per texture (level 0; signed values shown through their scale and bias as
// stored) and the manifest, for people and tools.
bool export_asset(const AssetData& a, const std::string& dir, std::string* err) {
    if (!make_dirs(dir, err)) return false;
    for (size_t i = 0; i < a.textures.size(); ++i) {
        const AssetTexture& t = a.textures[i];
        Image img(int(t.desc.width), int(t.desc.height), int(t.desc.channels));
        const size_t count = img.data.size();
        for (size_t k = 0; k < count; ++k) img.data[k] = float(texel_q(t, k));
        // Image rows go top first; texture row 0 is v = 0: flip so v grows upwards.
        Image flipped = img;
        const size_t row = size_t(img.width) * img.channels;
        for (int y = 0; y < img.height; ++y)
            std::copy(img.data.begin() + long(size_t(img.height - 1 - y) * row),
                      img.data.begin() + long(size_t(img.height - y) * row), flipped.data.begin() + long(size_t(y) * row));
        const std::string name = dir + "/term" + std::to_string(t.desc.term) + (t.desc.role == SEPAL_ROLE_G ? "_G" : "_H") + ".png";
        if (!write_png(name, flipped, err)) return false;
    }
    return write_file_atomic(dir + "/manifest.json", a.meta.data(), a.meta.size(), err);
}

// BakeResult::counts and notes: every clamp or fallback, zeros included (never silent).
void write_counts_json(const BakeResult& r, JsonWriter* j) {
    const BakeCounts& c = r.counts;
    j->key("counts").begin_object();
    j->key("evaluations").value(c.evaluations).key("capped").value(c.capped);
    j->key("negative_clamped").value(c.negative_clamped).key("frame_fallbacks").value(c.frame_fallbacks);
    j->key("solver_fallbacks").value(c.solver_fallbacks).key("zero_textures").value(c.zero_textures);
    j->key("zero_scale_channels").value(c.zero_scale_channels).key("quantize_clamped").value(c.quantize_clamped);
    j->key("all_zero").value(c.all_zero);
    j->key("input").begin_object();
    j->key("values").value(c.input.values).key("nonfinite").value(c.input.nonfinite);
    j->key("negative").value(c.input.negative).key("huge").value(c.input.huge);
    j->key("missing").value(c.input.missing).key("filled").value(c.input.filled);
    j->key("clamped").value(c.input.clamped).end_object();
    j->end_object();
    j->key("notes").begin_array();
    for (const std::string& n : r.notes) j->value(n);
    j->end_array();
}

void print_counts(const BakeResult& r, std::FILE* out) {
    const BakeCounts& c = r.counts;
    std::fprintf(out,
                 "counts: %lld evaluations, %lld capped, %lld negative entries clamped, %lld frame fallbacks, "
                 "%lld solver fallbacks; %d zero textures, %d zero-scale channels, %lld codes clamped%s\n",
                 (long long)c.evaluations, (long long)c.capped, (long long)c.negative_clamped,
                 (long long)c.frame_fallbacks, (long long)c.solver_fallbacks, c.zero_textures, c.zero_scale_channels,
                 (long long)c.quantize_clamped, c.all_zero ? "; all zero" : "");
    if (c.input.values)
        std::fprintf(out,
                     "input: %lld values; %lld NaN or inf, %lld negative, %lld beyond float range (missing: %lld); "
                     "%lld filled, %lld clamped\n",
                     (long long)c.input.values, (long long)c.input.nonfinite, (long long)c.input.negative,
                     (long long)c.input.huge, (long long)c.input.missing, (long long)c.input.filled,
                     (long long)c.input.clamped);
    for (const std::string& n : r.notes) std::fprintf(out, "note: %s\n", n.c_str());
}

}  // namespace

int cmd_bake(const std::vector<std::string>& argv, const CommandIO& io) {
    // The output is given as "-o": the parser knows long options only.
    std::vector<std::string> fixed;
    for (const std::string& a : argv) fixed.push_back(a == "-o" ? "--o" : a);
    Args args(fixed, {"o", "param", "map", "res", "terms", "method", "colour", "bits", "max-error", "max-passes",
                        "max-bytes", "report", "export", "threads", "supersample", "max-memory", "cap", "backend",
                        "timings", "target", "white", "fit", "min-psnr", "iters", "smooth-res", "diffuse-quantile", "judge-size"},
              {"no-mips"});
    BakeOptions o;
    std::string err;
    auto bad = [&](const std::string& m) {
        std::fprintf(io.err, "sepal bake: %s\n", m.c_str());
        return kExitBadInput;
    };
    if (!args.ok()) return bad(args.error());
    if (args.positional().size() != 1 || !args.has("o"))
        return bad("usage: sepal bake SPEC -o out.sepal [--param P,..] [--map M,..] [--res N,..] [--terms K,..] "
                   "[--method M,..] [--colour rgb|luminance] [--bits 8,16] [--target gles1|gles2|cpu] "
                   "[--white auto|none|W] [--fit radiance|brdf] [--min-psnr D] [--max-error E] [--max-passes P] "
                   "[--max-bytes B] [--backend gles1|gles2-fused|cpu] [--timings tradeoff.json] [--report r.json] "
                   "[--export DIR] [--threads N]");
    if (args.has("param") && !parse_list<Param>("param", args.get("param"), parse_param, &o.params, &err)) return bad(err);
    if (args.has("map") && !parse_list<HemiMap>("map", args.get("map"), parse_map, &o.maps, &err)) return bad(err);
    if (args.has("method") && !parse_list<Method>("method", args.get("method"), parse_method, &o.methods, &err))
        return bad(err);
    if (args.has("res") && !parse_list<int>("res", args.get("res"), parse_int, &o.resolutions, &err)) return bad(err);
    if (args.has("smooth-res") &&
        !parse_list<int>("smooth-res", args.get("smooth-res"), parse_int, &o.smooth_resolutions, &err))
        return bad(err);
    if (args.has("terms") && !parse_list<int>("terms", args.get("terms"), parse_int, &o.terms, &err)) return bad(err);
    if (args.has("colour") && !parse_colour(args.get("colour"), &o.colour)) return bad("--colour: rgb or luminance");
    long v = 0;
    double d = 0;
    if (args.has("bits")) {
        if (!parse_list<int>("bits", args.get("bits"), parse_int, &o.bits, &err)) return bad(err);
        for (int b : o.bits)
            if (b != 8 && b != 16) return bad("--bits: 8, 16 or 8,16");
    }
    // The frame-time model the winner minimizes: measured by `make bench` on the target
    // (--timings), else the built-in one for the backend.
    const std::string backend = args.has("backend") ? args.get("backend") : "gles1";
    if (args.has("timings") ? !read_cost_model(args.get("timings"), backend, &o.cost, &err)
                            : !default_cost_model(backend, &o.cost, &err))
        return bad(err);
    // The image that decides (the shipping backend), and what the factors hold.
    if (args.has("target") && !parse_target(args.get("target"), &o.target))
        return bad("--target: gles1, gles2 or cpu");
    if (args.has("white")) {
        const std::string w = args.get("white");
        if (w == "auto") o.white = 0;
        else if (w == "none") o.white = -1;
        else if (!args.number("white", &d) || d <= 0) return bad("--white: auto, none, or f cos(theta_i) per steradian > 0");
        else o.white = d;
    }
    if (args.has("fit")) {
        if (args.get("fit") != "radiance" && args.get("fit") != "brdf") return bad("--fit: radiance or brdf");
        o.radiance = args.get("fit") == "radiance";
    }
    if (args.has("min-psnr")) {
        if (!args.number("min-psnr", &d) || d <= 0) return bad("--min-psnr: dB > 0, e.g. 35");
        o.min_psnr = d;
    }
    if (args.has("diffuse-quantile")) {
        if (!args.number("diffuse-quantile", &d) || d < 0 || d > 1) return bad("--diffuse-quantile: 0..1");
        o.diffuse_quantile = d;
    }
    if (args.has("judge-size")) {
        if (!args.integer("judge-size", &v) || v < 8 || v > 2048) return bad("--judge-size: pixels per side, 8..2048");
        o.judge_size = int(v);
    }
    if (args.has("iters")) {
        if (!args.integer("iters", &v) || v < 1 || v > 100000) return bad("--iters: 1..100000");
        o.iterations = int(v);
    }
    if (args.has("max-error")) {
        if (!args.number("max-error", &d) || d <= 0) return bad("--max-error: a relative error > 0, e.g. 0.1");
        o.max_error = d;
    }
    if (args.has("max-passes")) {
        if (!args.integer("max-passes", &v) || v < 1) return bad("--max-passes: an integer >= 1");
        o.max_passes = int(v);
    }
    if (args.has("max-bytes")) {
        if (!args.integer("max-bytes", &v) || v < 1) return bad("--max-bytes: an integer >= 1");
        o.max_bytes = v;
    }
    if (args.has("threads")) {
        if (!args.integer("threads", &v) || v < 0 || v > 256) return bad("--threads: 0 (all cores) .. 256");
        o.threads = int(v);
    }
    if (args.has("supersample")) {
        if (!args.integer("supersample", &v) || v < 1 || v > 4) return bad("--supersample: 1..4");
        o.supersample = int(v);
    }
    if (args.has("max-memory")) {
        if (!args.number("max-memory", &d) || d <= 0) return bad("--max-memory: megabytes > 0");
        o.max_memory_mb = d;
    }
    if (args.has("cap")) {
        if (!args.number("cap", &d) || d <= 0) return bad("--cap: a value of f per steradian > 0");
        o.cap = d;
    }
    o.mips = !args.has("no-mips");
    o.progress = true;  // shown only when stderr is a terminal
    std::unique_ptr<Brdf> brdf = make_brdf(args.positional()[0], &err);
    if (!brdf) return bad(err);
    BakeResult r;
    const bool ok = bake(*brdf, o, &r, &err);
    // The candidates, for people, whether or not one won: the image first, the direction-
    // space error as a diagnostic.
    if (!r.candidates.empty())
        std::fprintf(io.out, "%-34s %8s %9s %7s %5s %8s %8s %7s %s\n", "candidate", "PSNR dB", "err quant", "passes",
                     "dbl", "bytes", "ms", "fit s", "(* on the front)");
    for (size_t i = 0; i < r.candidates.size(); ++i) {
        const BakeCandidate& c = r.candidates[i];
        const std::string label = c.label() + (c.coarse ? " (c)" : "");
        if (!c.ok) {
            std::fprintf(io.out, "%-34s  skipped: %s\n", label.c_str(), c.note.c_str());
            continue;
        }
        std::fprintf(io.out, "%-34s %8.2f %9.4f %7d %5d %8lld %8.2f %7.2f %s %s%s\n", label.c_str(), c.psnr,
                     c.error_quantized, c.passes, c.doublings, (long long)c.bytes, c.ms, c.factor_seconds,
                     c.on_front ? "*" : " ",
                     int(i) == r.winner ? "<- winner" : c.meets ? "meets budgets" : "",
                     c.non_negative ? "" : (int(i) == r.winner ? " (signed)" : ""));
    }
    if (!r.views.empty()) {
        std::string names;
        for (const std::string& v : r.views) names += (names.empty() ? "" : ", ") + v;
        std::fprintf(io.out, "PSNR: on %s against the exact render, pooled over the views %s; (c): coarse stage\n",
                     target_name(r.target), names.c_str());
    }
    if (args.has("report")) {
        JsonWriter j;
        j.begin_object().key("spec").value(brdf->spec()).key("seconds").value(r.seconds);
        j.key("target").value(target_name(r.target)).key("white_level").value(r.white);
        j.key("diffuse").begin_array().value(r.diffuse.scale.x).value(r.diffuse.scale.y).value(r.diffuse.scale.z).end_array();
        j.key("diffuse_profile_side").value(r.diffuse.side);
        j.key("views").begin_array();
        for (const std::string& v : r.views) j.value(v);
        j.end_array();
        j.key("budgets").begin_object();
        j.key("max_error").value(o.max_error).key("max_passes").value(o.max_passes).key("max_bytes").value(o.max_bytes);
        j.key("min_psnr").value(o.min_psnr);
        j.end_object();
        j.key("cost_model").begin_object().key("backend").value(r.cost.backend).key("device").value(r.cost.device);
        j.key("base_ms").value(r.cost.base_ms).key("per_pass_ms").value(r.cost.per_pass_ms);
        j.key("per_term_ms").value(r.cost.per_term_ms).key("per_kib_ms").value(r.cost.per_kib_ms);
        j.key("fit_error").value(r.cost.fit_error).end_object();
        j.key("winner").value(r.winner).key("why").value(r.why);
        j.key("candidates").begin_array();
        for (const BakeCandidate& c : r.candidates) {
            j.begin_object().key("label").value(c.label()).key("param").value(param_name(c.param));
            j.key("map").value(map_name(c.map)).key("res").value(c.res).key("res_h").value(c.res_h > 0 ? c.res_h : c.res);
            j.key("terms").value(c.terms).key("bits").value(c.bits);
            j.key("method").value(method_name(c.method)).key("ok").value(c.ok).key("coarse").value(c.coarse);
            j.key("psnr").value(c.psnr);
            j.key("psnr_views").begin_array();
            for (double p : c.psnr_views) j.value(p);
            j.end_array();
            if (!c.ok) j.key("note").value(c.note);
            j.key("error_float_relative").value(c.error_float).key("error_quantized_relative").value(c.error_quantized);
            j.key("rms_quantized").value(c.rms_quantized).key("passes").value(c.passes);
            j.key("doublings").value(c.doublings).key("non_negative").value(c.non_negative);
            j.key("bytes").value(c.bytes).key("ms_predicted").value(c.ms).key("on_front").value(c.on_front);
            j.key("factor_seconds").value(c.factor_seconds);
            j.key("meets").value(c.meets).end_object();
        }
        j.end_array();
        write_counts_json(r, &j);
        j.end_object();
        std::string werr;
        if (!write_file_atomic(args.get("report"), j.str().data(), j.str().size(), &werr)) return bad(werr);
    }
    if (!ok) return bad(err);
    if (!write_asset(args.get("o"), r.asset, &err)) return bad(err);
    if (args.has("export") && !export_asset(r.asset, args.get("export"), &err)) return bad(err);
    if (o.cap > 0)
        std::fprintf(io.out, "cap: f clamped at %g in %.3f%% of the samples the factors were fitted to\n", o.cap,
                     100.0 * r.capped_share);
    print_counts(r, io.out);
    std::fprintf(io.out, "winner: %s\nwrote %s (%.1f s)\n", r.why.c_str(), args.get("o").c_str(), r.seconds);
    return kExitOk;
}

}  // namespace sepal
