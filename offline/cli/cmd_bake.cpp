// sepal bake SPEC -o out.sepal [factor options] [--bits 8,16] [--target gles1|gles2|cpu|gles1:PROFILE]
//   [--light-range R] [--light-max E] [--light-cone DEG] [--lights N] [--meshes LIST]
//   [--white auto|none|W] [--fit radiance|brdf] [--fit-weight display|uniform] [--min-psnr D] [--max-error E]
//   [--max-passes P] [--max-bytes B] [--bytes-db D] [--backend B] [--timings tradeoff.json]
//   [--report r.json] [--export DIR] [--threads N]
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "bake/bake.h"
#include "bake/devices.h"
#include "bake/export.h"
#include "cli/cli.h"
#include "cli/options.h"
#include "util/image.h"
#include "util/io.h"
#include "util/json.h"
#include "bake/quantize.h"
#include "spec/spec.h"

namespace sepal {
namespace {

// BakeResult::counts and notes: every clamp or fallback, zeros included (never silent).
void add_counts_json(const BakeResult& r, Json* j) {
    const BakeCounts& c = r.counts;
    (*j)["counts"] = {{"evaluations", c.evaluations},
                      {"capped", c.capped},
                      {"negative_clamped", c.negative_clamped},
                      {"frame_fallbacks", c.frame_fallbacks},
                      {"solver_fallbacks", c.solver_fallbacks},
                      {"zero_textures", c.zero_textures},
                      {"zero_scale_channels", c.zero_scale_channels},
                      {"quantize_clamped", c.quantize_clamped},
                      {"all_zero", c.all_zero},
                      {"input",
                       {{"values", c.input.values},
                        {"nonfinite", c.input.nonfinite},
                        {"negative", c.input.negative},
                        {"huge", c.input.huge},
                        {"missing", c.input.missing},
                        {"horizon", c.input.horizon},
                        {"filled", c.input.filled},
                        {"clamped", c.input.clamped}}}};
    (*j)["notes"] = r.notes;
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
                     "%lld cells below the horizon (no data by geometry); %lld filled, %lld clamped\n",
                     (long long)c.input.values, (long long)c.input.nonfinite, (long long)c.input.negative,
                     (long long)c.input.huge, (long long)c.input.missing, (long long)c.input.horizon,
                     (long long)c.input.filled, (long long)c.input.clamped);
    for (const std::string& n : r.notes) std::fprintf(out, "note: %s\n", n.c_str());
}

// The candidates, for people, whether or not one won: the image first, the direction-
// space error as a diagnostic.
void print_candidates(const BakeResult& r, FILE* out) {
    if (!r.candidates.empty())
        std::fprintf(out, "%-34s %8s %8s %9s %7s %5s %8s %8s %7s %s\n", "candidate", "PSNR dB", "worst dB", "err quant",
                     "passes", "dbl", "bytes", "ms", "fit s", "(* on the front)");
    for (size_t i = 0; i < r.candidates.size(); ++i) {
        const BakeCandidate& c = r.candidates[i];
        const std::string label = c.label() + (c.coarse ? " (c)" : c.unranked ? " (u)" : "");
        if (!c.ok) {
            std::fprintf(out, "%-34s  skipped: %s\n", label.c_str(), c.note.c_str());
            continue;
        }
        std::fprintf(out, "%-34s %8.2f %8.2f %9.4f %7d %5d %8lld %8.2f %7.2f %s %s%s\n", label.c_str(), c.psnr, c.worst_view(),
                     c.error_quantized, c.passes, c.doublings, (long long)c.bytes, c.ms, c.factor_seconds,
                     c.on_front ? "*" : " ",
                     int(i) == r.winner ? "<- winner" : c.meets ? "meets budgets" : "",
                     c.non_negative ? "" : (int(i) == r.winner ? " (signed)" : ""));
    }
    if (!r.views.empty()) {
        std::string names;
        for (const std::string& v : r.views) names += (names.empty() ? "" : ", ") + v;
        std::fprintf(out,
                     "PSNR: on %s against the exact render, pooled over the training views %s (sepal diff's PSNR is "
                     "of one image pair); worst: the worst of those views; dbl: framebuffer doublings of the %s "
                     "view's frame on %s (as sepal inspect prints); (c): coarse stage%s\n",
                     r.target_label.c_str(), names.c_str(), r.views.front().c_str(), r.target_label.c_str(),
                     std::any_of(r.candidates.begin(), r.candidates.end(), [](const BakeCandidate& c) { return c.unranked; })
                         ? "; (u): judged at the first size only, not ranked (the fine judge's note)"
                         : "");
    }
}

struct BakeArgs {
    std::string spec, out, report, export_dir, backend = "gles1", timings, target = "gles1";
    std::string white = "auto", fit = "radiance", colour = "auto", fit_weight = "display";
    bool mips = false;
    BakeOptions o;
};

int run_bake(BakeArgs& args, const CommandIO& io) {
    BakeOptions& o = args.o;
    std::string err;
    auto bad = [&](const std::string& m) {
        std::fprintf(io.err, "sepal bake: %s\n", m.c_str());
        return kExitBadInput;
    };
    // --target gles1|gles2|cpu, or gles1:PROFILE (a device profile, bake/devices.h).
    const size_t colon = args.target.find(':');
    const std::string backend_name = args.target.substr(0, colon);
    if (!parse_target(backend_name, &o.target))
        return bad("--target " + args.target + ": gles1, gles2, cpu or gles1:PROFILE");
    if (colon != std::string::npos) {
        o.profile = args.target.substr(colon + 1);
        if (o.target != Target::Gles1 || !find_device_profile(o.profile))
            return bad("--target " + args.target + ": device profiles are gles1:PROFILE with PROFILE one of " +
                       device_profile_names() + " (sepal info --devices)");
    }
    // The frame-time model the winner minimizes: measured by `make bench` on the target
    // (--timings), else the built-in one for the backend.
    if (!args.timings.empty() ? !read_cost_model(args.timings, args.backend, &o.cost, &err)
                              : !default_cost_model(args.backend, &o.cost, &err))
        return bad(err);
    // What the factors hold (the image that decides is o.target).
    if (args.white == "auto") o.white = 0;
    else if (args.white == "none") o.white = -1;
    else {
        char* end = nullptr;
        const double w = std::strtod(args.white.c_str(), &end);
        if (args.white.empty() || *end || !std::isfinite(w) || w <= 0)
            return bad("--white " + args.white + ": auto, none, or f cos(theta_i) per steradian > 0");
        o.white = w;
    }
    o.radiance = args.fit == "radiance";
    o.fit_weight = args.fit_weight == "uniform" ? BakeOptions::FitWeight::Uniform : BakeOptions::FitWeight::Display;
    o.colour_auto = args.colour == "auto";
    if (!o.colour_auto) parse_colour(args.colour, &o.colour);
    o.mips = args.mips;
    o.progress = true;  // shown only when stderr is a terminal
    std::unique_ptr<Brdf> brdf = make_brdf(args.spec, &err);
    if (!brdf) return bad(err);
    // Every output is checked before the search, which can take minutes.
    if (!check_output("-o", args.out, &err) || !check_output("--report", args.report, &err) ||
        !check_output_dir("--export", args.export_dir, &err))
        return bad(err);
    BakeResult r;
    const bool ok = bake(*brdf, o, &r, &err);
    print_candidates(r, io.out);
    if (!args.report.empty()) {
        Json j;
        j["spec"] = brdf->spec();
        j["seconds"] = r.seconds;
        j["target"] = target_name(r.target);
        j["profile"] = o.profile.empty() ? "default" : o.profile;
        j["white_level"] = r.white;
        j["horizon"] = r.horizon;
        j["judge_size"] = r.judge_size;
        j["colour"] = colour_name(r.colour);
        j["colour_residual"] = r.colour_residual;
        j["diffuse"] = {r.diffuse.scale.x, r.diffuse.scale.y, r.diffuse.scale.z};
        j["diffuse_profile_side"] = r.diffuse.side;
        j["views"] = r.views;
        j["light_range"] = {{"ratio", o.light_range.ratio},
                            {"irradiance_min", range_irradiance_min(o.light_range)},
                            {"irradiance_max", range_irradiance_max(o.light_range)},
                            {"cone_degrees", o.light_range.cone_degrees},
                            {"max_lights", o.light_range.max_lights},
                            {"meshes", o.light_range.meshes}};
        if (ok && r.winner >= 0) {
            j["psnr_in_sample"] = r.candidates[size_t(r.winner)].psnr;
            j["psnr_held_out"] = r.held_out_psnr;
            Json held = Json::array();
            for (size_t i = 0; i < r.held_out_views.size(); ++i)
                held.push_back({{"name", r.held_out_views[i]},
                                {"flags", r.held_out_flags[i]},
                                {"psnr", r.held_out_psnr_views[i]},
                                {"share_over_16", r.held_out_share16[i]}});
            j["held_out"] = held;
        }
        j["budgets"] = {{"max_error", o.max_error},
                        {"max_passes", o.max_passes},
                        {"max_bytes", o.max_bytes},
                        {"min_psnr", o.min_psnr}};
        j["cost_model"] = {{"backend", r.cost.backend},         {"device", r.cost.device},
                           {"base_ms", r.cost.base_ms},         {"per_pass_ms", r.cost.per_pass_ms},
                           {"per_term_ms", r.cost.per_term_ms}, {"per_kib_ms", r.cost.per_kib_ms},
                           {"fit_error", r.cost.fit_error}};
        j["winner"] = r.winner;
        j["why"] = r.why;
        j["candidates"] = Json::array();
        for (const BakeCandidate& c : r.candidates) {
            Json x = {{"label", c.label()}, {"param", param_name(c.param)}, {"map", map_name(c.map)},
                      {"res", c.res},       {"res_h", c.res_h > 0 ? c.res_h : c.res},
                      {"terms", c.terms},   {"bits", c.bits},
                      {"method", method_name(c.method)}, {"ok", c.ok}, {"coarse", c.coarse}};
            x["psnr"] = c.psnr;
            x["psnr_views"] = c.psnr_views;
            if (!c.ok) x["note"] = c.note;
            x["error_float_relative"] = c.error_float;
            x["error_quantized_relative"] = c.error_quantized;
            x["rms_quantized"] = c.rms_quantized;
            x["passes"] = c.passes;
            x["doublings"] = c.doublings;
            x["non_negative"] = c.non_negative;
            x["bytes"] = c.bytes;
            x["ms_predicted"] = c.ms;
            x["on_front"] = c.on_front;
            x["unranked"] = c.unranked;
            x["factor_seconds"] = c.factor_seconds;
            x["meets"] = c.meets;
            j["candidates"].push_back(std::move(x));
        }
        add_counts_json(r, &j);
        std::string werr;
        if (!write_json_file(args.report, j, &werr)) return bad(werr);
    }
    if (!ok) return bad(err);
    // The asset and its export succeed or fail together (the report above is written either
    // way: it says why a bake failed).
    OutputGuard written;
    if (!write_asset(args.out, r.asset, &err) ||
        (!args.export_dir.empty() && !export_asset(r.asset, args.export_dir, &err)) || !written.commit(&err))
        return bad(err);
    if (o.cap > 0)
        std::fprintf(io.out, "cap: f clamped at %g in %.3f%% of the samples the factors were fitted to\n", o.cap,
                     100.0 * r.capped_share);
    print_counts(r, io.out);
    std::fprintf(io.out, "winner: %s\n", r.why.c_str());
    if (!r.held_out_views.empty()) {
        // The headline: conditions the search never saw, drawn from the same light range.
        const BakeCandidate& w = r.candidates[size_t(r.winner)];
        const double worst = *std::min_element(r.held_out_psnr_views.begin(), r.held_out_psnr_views.end());
        std::fprintf(io.out,
                     "held-out: %.2f dB on %s at %dx%d pooled over the %zu conditions below (worst %.2f dB; in-sample "
                     "%.2f dB, pooled over the training views) for lights %s\n",
                     r.held_out_psnr, r.target_label.c_str(), r.judge_size, r.judge_size, r.held_out_views.size(), worst,
                     w.psnr,
                     describe_light_range(o.light_range).c_str());
        for (size_t i = 0; i < r.held_out_views.size(); ++i)
            std::fprintf(io.out, "  %-20s %6.2f dB, %.2f%% of pixels over 16 levels  (%s)\n", r.held_out_views[i].c_str(),
                         r.held_out_psnr_views[i], 100.0 * r.held_out_share16[i], r.held_out_flags[i].c_str());
    }
    std::fprintf(io.out, "wrote %s (%.1f s)\n", args.out.c_str(), r.seconds);
    return kExitOk;
}

}  // namespace

CommandRun setup_bake(CLI::App& app) {
    auto a = std::make_shared<BakeArgs>();
    BakeOptions& o = a->o;
    app.add_option("SPEC", a->spec, "BRDF spec (sepal info --models) or measured file (.binary, .brdf)")->required();
    app.add_option("-o,--output", a->out, "the asset to write (.sepal)")->required();
    // The search space: every combination is factored once (bake.h).
    app.add_option("--param", o.params, "parameterizations to try")
        ->delimiter(',')->transform(param_names())->capture_default_str();
    app.add_option("--map", o.maps, "hemisphere maps to try")->delimiter(',')->transform(map_names())->capture_default_str();
    app.add_option("--res", o.resolutions, "texels per side to try (powers of two; default: a ladder from 32)")
        ->delimiter(',')->check(CLI::Range(1, 256));
    app.add_option("--terms", o.terms, "term counts to try (default: 1..4, more while below 40 dB)")
        ->delimiter(',')->check(CLI::Range(1, 16));
    app.add_option("--method", o.methods,
                   "factorization methods to try (default: acls and homomorphic on gles1/gles2; acls, wsvd and homomorphic on cpu)")
        ->delimiter(',')->transform(method_names());
    app.add_option("--smooth-res", o.smooth_resolutions,
                   "with --res: the other (smooth) factor's sides to try, each not above --res")
        ->delimiter(',')->check(CLI::Range(1, 256));
    // The image that decides and what the factors hold (bake.h, radiance.h).
    app.add_option("--target", a->target,
                   "the backend the asset ships on (gles1, gles2, cpu), or gles1:PROFILE, a device profile "
                   "(sepal info --devices); candidates are ranked by PSNR there")
        ->capture_default_str();
    app.add_option("--fit", a->fit, "radiance: factor f cos(theta_i) capped at the white level, diffuse apart "
                                    "(format 2); brdf: factor f (format 1)")
        ->check(CLI::IsMember({"radiance", "brdf"}))->capture_default_str();
    app.add_option("--fit-weight", a->fit_weight, "the radiance fit's weights: display (each value's error as it shows "
                                               "under the light range) or uniform")
        ->check(CLI::IsMember({"display", "uniform"}))->capture_default_str();
    app.add_option("--white", a->white, "the radiance fit's cap: auto (from the light range's dimmest light), none, or "
                                        "f cos per steradian")
        ->capture_default_str();
    app.add_option("--horizon", o.horizon,
                   "the radiance fit's horizon window: below this cos(theta_i) the vertex colour, not the factors, "
                   "takes the light to 0 at the horizon (format 2.7; 0: none, e.g. 0.1)")
        ->check(finite_range(0, 1))->capture_default_str();
    // The lighting the asset must hold under (light_range.h): ranked on training conditions
    // drawn from it, reported on held-out ones; the white level follows from its dimmest light.
    app.add_option("--light-range", o.light_range.ratio,
                   "brightest : dimmest light the asset must hold under (1: only the brightest)")
        ->check(finite_range(1, 1e6))->capture_default_str();
    app.add_option("--light-max", o.light_range.irradiance_max,
                   "the brightest light's irradiance at the object, I / d^2 (0: the default scene's, 3.12)")
        ->check(finite_range(0, 1e6))->capture_default_str();
    app.add_option("--light-cone", o.light_range.cone_degrees,
                   "light directions within this many degrees of the scene's up (90: anywhere above the horizon)")
        ->check(finite_range(1, 180))->capture_default_str();
    app.add_option("--lights", o.light_range.max_lights, "lights at once")->check(CLI::Range(1, 8))->capture_default_str();
    app.add_option("--meshes", o.light_range.meshes, "meshes the training conditions use (sphere, torus, wave)")
        ->delimiter(',')->check(CLI::IsMember({"sphere", "torus", "wave"}))->capture_default_str();
    app.add_option("--diffuse-quantile", o.diffuse_quantile, "the quantile of f taken as the constant diffuse part")
        ->check(finite_range(0, 1))->capture_default_str();
    app.add_option("--judge-size", o.judge_size, "pixels per side of the judged images")
        ->check(CLI::Range(8, 2048))->capture_default_str();
    app.add_option("--fine-judge-texels", o.fine_judge_texels,
                   "judge every candidate again at twice --judge-size when one's sharp factor has this many texels "
                   "a side (0: never)")
        ->check(CLI::Range(0, 4096))->capture_default_str();
    app.add_option("--iters", o.iterations, "nmf/acls outer iterations per term count (0: the method's default)")
        ->check(CLI::Range(0, 100000))->capture_default_str();
    app.add_option("--min-psnr", o.min_psnr, "budget: dB on the target, e.g. 35")->check(positive());
    app.add_option("--colour", a->colour, "rgb: factors per channel; luminance: one factor and a colour ratio (a "
                                          "third of the bytes); auto: luminance where f's colour is one ratio")
        ->check(CLI::IsMember({"auto", "rgb", "luminance"}))->capture_default_str();
    app.add_option("--bits", o.bits, "bits per texel channel to try: 8, 16 or 8,16")
        ->delimiter(',')->check(CLI::IsMember({8, 16}))->capture_default_str();
    app.add_option("--supersample", o.supersample, "S x S sub-samples per texel")
        ->check(CLI::Range(1, 4))->capture_default_str();
    app.add_option("--cap", o.cap, "clamp f above this value per steradian before factoring (see bake.h)")
        ->check(positive());
    app.add_flag("--mips,!--no-mips", a->mips,
                 "store a full MIP chain (default: level 0 only; GL's MIP selection blurs the "
                 "direction-space factors where the view grazes: docs/fidelity.md)");
    // Budgets and the frame-time model the winner minimizes.
    app.add_option("--max-error", o.max_error, "budget: relative cosine-weighted RMS after quantization, e.g. 0.1")
        ->check(positive());
    app.add_option("--max-passes", o.max_passes, "budget: plan passes per light")->check(CLI::Range(1, 1 << 20));
    app.add_option("--bytes-db", o.bytes_db, "the winner's trade: a candidate of twice the bytes must render this "
                                             "many dB better to win")
        ->check(CLI::Range(0.0, 10.0))->capture_default_str();
    app.add_option("--max-bytes", o.max_bytes, "budget: encoded asset size in bytes")
        ->check(CLI::Range(int64_t(1), int64_t(1) << 40));
    // Not a fixed list: a --timings file may hold a model of any backend its sweep measured.
    app.add_option("--backend", a->backend,
                   "the backend whose frame time the winner minimizes: gles1, gles2-fused, cpu (built-in models) "
                   "or one in --timings")
        ->capture_default_str();
    app.add_option("--timings", a->timings, "a trade-off JSON from `make bench` with measured cost models");
    // Resources and outputs.
    app.add_option("--threads", o.threads, "worker threads, 0 = all cores (results do not depend on it)")
        ->check(CLI::Range(0, 256))->capture_default_str();
    app.add_option("--max-memory", o.max_memory_mb, "refuse factorizations above this estimate, MB")
        ->check(positive())->capture_default_str();
    app.add_option("--report", a->report, "write every candidate, the budgets and the counts as JSON");
    app.add_option("--export", a->export_dir, "write every texture as PNG per MIP level (16-bit for --bits 16), level 0 as PFM, the diffuse profile as PFM, and manifest.json (flags, diffuse part, white level, light range, the evaluation formula: docs/format.md) into DIR");
    return [a](const CommandIO& io) { return run_bake(*a, io); };
}

}  // namespace sepal
