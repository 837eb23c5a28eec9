// sepal factor: separable factors of a BRDF with the error per number of terms.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "brdf/brdf.h"
#include "spec/spec.h"
#include "brdf/brdf_capped.h"
#include "bake/export.h"
#include "cli/cli.h"
#include "cli/options.h"
#include "factor/factor.h"
#include "factor/factor_error.h"
#include "util/image.h"
#include "util/io.h"
#include "util/json.h"
#include "util/plot.h"

namespace sepal {

namespace {
struct FactorArgs {
    std::string spec, report, plot, export_dir;
    double cap = -1;
    bool p_given = false;
    bool param_given = false, map_given = false, terms_given = false;
    FactorOptions o;
};

Json report(const std::string& spec, const FactorOptions& o, const FactorResult& r,
            const std::vector<TermError>& errors, const ErrorEvaluator& ev) {
    Json j;
    j["spec"] = spec;
    j["brdf"] = r.factored.source;
    j["options"] = {{"param", param_name(o.param)},
                    {"map", angle_textures(o.param) ? "angles" : map_name(o.map)},
                    {"res", o.res},
                    {"terms", o.terms},
                    {"method", method_name(o.method)},
                    {"colour", colour_name(o.colour)},
                    {"supersample", o.supersample},
                    {"nd_p", o.nd_p},
                    {"svd_weighted", o.svd_weighted},
                    {"horizon_weight", o.horizon_weight},
                    {"acls_constant", o.acls_constant},
                    {"acls_monotonic", o.acls_monotonic},
                    {"max_memory_mb", o.max_memory_mb}};
    j["matrix"] = {{"rows", r.rows}, {"cols", r.cols}, {"memory_mb", r.memory_mb}, {"evaluations", r.evaluations}};
    // Every clamp or fallback of the engine, zeros included (the notes say the same in words).
    j["counts"] = {{"negative_clamped", int64_t(r.clamped_negative)},
                   {"frame_fallbacks", r.frame_fallbacks},
                   {"solver_fallbacks", r.solver_fallbacks}};
    j["colour_ratio"] = {r.factored.ratio.x, r.factored.ratio.y, r.factored.ratio.z};
    j["non_negative"] = r.factored.non_negative();
    const ErrorOptions& eo = ev.options();
    j["metric"] = {{"name", "cosine-weighted RMS of the luminance, (f~ - f) cos(theta_i)"},
                   {"mc_pairs", eo.mc_pairs},
                   {"mc_seed", int64_t(eo.seed)},
                   {"dense_pairs", int64_t(eo.dense) * eo.dense * eo.dense * eo.dense},
                   {"reference_rms", ev.reference_rms()}};
    j["errors"] = Json::array();
    for (const TermError& t : errors)
        j["errors"].push_back({{"terms", t.terms},
                               {"rms", t.e.rms},
                               {"relative", t.e.relative},
                               {"rms_rgb", t.e.rms_rgb},
                               {"dense_rms", t.e.dense_rms},
                               {"dense_relative", t.e.dense_relative},
                               {"matrix_rms", t.matrix_rms}});
    j["notes"] = r.notes;
    // Timings vary from run to run; everything above does not.
    j["timing"] = {{"sample_seconds", r.sample_seconds},
                   {"factor_seconds", r.factor_seconds},
                   {"iterations", r.iterations}};
    return j;
}

int run_factor(FactorArgs& args, const CommandIO& io) {
    FactorOptions& o = args.o;
    std::string err;
    if (o.svd_weighted && o.method != Method::SVD && o.method != Method::WSVD)
        err = "--svd-weighted needs --method svd (it makes it wsvd)";
    if (args.p_given && o.method != Method::ND) err = "--p needs --method nd";
    // Homomorphic factors are p(wi) q(h) p(wo): vh on the parabolic map, one term, unless given.
    if (o.method == Method::Homomorphic) {
        if (!args.param_given) o.param = Param::ViewHalf;
        if (!args.map_given) o.map = HemiMap::Parabolic;
        if (!args.terms_given) o.terms = 1;
    }
    if (!err.empty() || !validate_factor_options(o, &err)) {
        std::fprintf(io.err, "sepal factor: %s\n", err.c_str());
        return kExitBadInput;
    }
    o.progress = isatty(fileno(io.err)) != 0;
    const std::string& spec = args.spec;
    std::unique_ptr<Brdf> brdf = make_brdf(spec, &err);
    if (!brdf) {
        std::fprintf(io.err, "sepal factor: %s\n", err.c_str());
        return kExitBadInput;
    }
    // --cap as in bake: the factors fit the capped f, the error is measured against f itself.
    const CappedBrdf capped(*brdf, args.cap > 0 ? args.cap : INFINITY);
    FactorResult r;
    if (!factor_brdf(args.cap > 0 ? static_cast<const Brdf&>(capped) : *brdf, o, &r, &err)) {
        std::fprintf(io.err, "sepal factor: %s\n", err.c_str());
        return kExitBadInput;
    }
    ErrorOptions eo;
    eo.threads = o.threads;
    ErrorEvaluator ev(*brdf, eo);
    if (!ev.init(&err)) {
        std::fprintf(io.err, "sepal factor: %s\n", err.c_str());
        return kExitBadInput;
    }
    const std::vector<TermError> errors = measure_terms(ev, r);

    std::fprintf(io.out, "factor %s\n", r.factored.source.c_str());
    std::fprintf(io.out, "  %s%s, %s map, %d x %d texels, %s, colour %s%s\n", param_name(o.param),
                 hardware_compatible(o.param) ? "" : " (per-pixel backends only)",
                 angle_textures(o.param) ? "angle" : map_name(o.map), o.res, o.res,
                 method_name(o.method), colour_name(o.colour),
                 r.factored.non_negative() ? ", non-negative factors" : ", signed factors");
    if (o.colour == ColourMode::Luminance)
        std::fprintf(io.out, "  colour ratio %.6g %.6g %.6g\n", r.factored.ratio.x,
                     r.factored.ratio.y, r.factored.ratio.z);
    std::fprintf(io.out, "  matrix %d x %d, about %.0f MB; sampled in %.2f s, factored in %.2f s\n",
                 r.rows, r.cols, r.memory_mb, r.sample_seconds, r.factor_seconds);
    if (args.cap > 0)
        std::fprintf(io.out, "  cap: f clamped at %g in %.3f%% of the samples the factors were fitted to\n", args.cap,
                     100.0 * capped.share());
    for (const std::string& n : r.notes) std::fprintf(io.out, "  note: %s\n", n.c_str());
    std::fprintf(io.out,
                 "  error: cosine-weighted RMS of the luminance over %d Monte Carlo pairs "
                 "(relative to %.6g) and over %d^4 dense pairs\n",
                 eo.mc_pairs, ev.reference_rms(), eo.dense);
    std::fprintf(io.out, "  %5s  %12s  %10s  %12s  %10s  %12s\n", "terms", "rms", "relative",
                 "dense rms", "dense rel", "matrix rms");
    for (const TermError& t : errors)
        std::fprintf(io.out, "  %5d  %12.6g  %10.6f  %12.6g  %10.6f  %12.6g\n", t.terms, t.e.rms,
                     t.e.relative, t.e.dense_rms, t.e.dense_relative, t.matrix_rms);

    if (!args.report.empty()) {
        Json j = report(spec, o, r, errors, ev);
        j["options"]["cap"] = args.cap > 0 ? Json(args.cap) : Json(nullptr);
        j["capped_share"] = capped.share();
        if (!write_json_file(args.report, j, &err)) {
            std::fprintf(io.err, "sepal factor: %s\n", err.c_str());
            return kExitBadInput;
        }
    }
    if (!args.plot.empty()) {
        PlotPanel p;
        p.title = r.factored.source.size() > 60 ? brdf->model() : r.factored.source;
        p.x_label = "terms";
        p.y_label = std::string("cos-weighted RMS, ") + method_name(o.method) + " " +
                    param_name(o.param) + " " + std::to_string(o.res) + "x" + std::to_string(o.res);
        PlotSeries mc{"Monte Carlo", {}, {}, plot_colour(0)}, dense{"dense", {}, {}, plot_colour(1)};
        for (const TermError& t : errors) {
            mc.x.push_back(t.terms), mc.y.push_back(t.e.rms);
            dense.x.push_back(t.terms), dense.y.push_back(t.e.dense_rms);
        }
        p.series = {mc, dense};
        if (!write_plot(args.plot, {p}, 1, 480, 360, &err)) {
            std::fprintf(io.err, "sepal factor: %s\n", err.c_str());
            return kExitBadInput;
        }
    }
    if (!args.export_dir.empty() && !export_factored(r.factored, args.export_dir, &err)) {
        std::fprintf(io.err, "sepal factor: %s\n", err.c_str());
        return kExitBadInput;
    }
    return kExitOk;
}

}  // namespace

CommandRun setup_factor(CLI::App& app) {
    auto a = std::make_shared<FactorArgs>();
    FactorOptions& o = a->o;
    o.terms = 4;
    app.add_option("SPEC", a->spec, "BRDF spec (sepal info --models) or measured file (.binary, .brdf)")->required();
    app.add_option("--param", o.param, "parameterization")->transform(param_names())->capture_default_str();
    app.add_option("--map", o.map, "hemisphere map")->transform(map_names())->capture_default_str();
    app.add_option("--res", o.res, "texels per side of each factor")->check(CLI::Range(1, 256))->capture_default_str();
    app.add_option("--terms", o.terms, "terms to factor (errors are reported for 1..K)")
        ->check(CLI::Range(1, 16))->capture_default_str();
    app.add_option("--method", o.method, "factorization method (homomorphic: p(wi) q(h) p(wo), McCool 2001; vh, parabolic, 1 term unless given)")->transform(method_names())->capture_default_str();
    app.add_option("--colour", o.colour, "rgb: per channel; luminance: one factor and a colour ratio")
        ->transform(colour_names())->capture_default_str();
    app.add_option("--supersample", o.supersample, "S x S sub-samples per texel of each factor")
        ->check(CLI::Range(1, 4))->capture_default_str();
    CLI::Option* p = app.add_option("--p", o.nd_p, "nd: the p-norm")->check(finite_range(1, 16))->capture_default_str();
    app.add_flag("--svd-weighted", o.svd_weighted, "svd: fit valid entries by their weight (per term count); the same as --method wsvd");
    app.add_option("--horizon-weight", o.horizon_weight,
                   "weight of entries wholly below the horizon in weighted fits (nmf, acls, --svd-weighted)")
        ->check(finite_range(0, 1))->capture_default_str();
    app.add_flag("--acls-constant", o.acls_constant, "acls: term 1's half-angle factor held constant");
    app.add_flag("--acls-monotonic", o.acls_monotonic, "acls: half-angle factors non-increasing in theta_h");
    app.add_option("--iters", o.iterations, "nmf/acls/weighted svd: most iterations per term count")
        ->check(CLI::Range(0, 100000));
    app.add_option("--tolerance", o.tolerance, "nmf/acls/weighted svd: stop when the error falls by less")
        ->check(finite_range(0, 1));
    app.add_option("--cap", a->cap, "clamp f above this value per steradian before factoring (as sepal bake)")
        ->check(positive());
    app.add_option("--max-memory", o.max_memory_mb, "refuse matrix methods above this estimate, MB")
        ->check(positive())->capture_default_str();
    app.add_option("--threads", o.threads, "worker threads, 0 = all cores (results do not depend on it)")
        ->check(CLI::Range(0, 256))->capture_default_str();
    app.add_option("--report", a->report, "write every option, the errors and timings as JSON");
    app.add_option("--plot", a->plot, "write the error against the number of terms as a plot (SVG for a .svg name, else PNG)");
    app.add_option("--export", a->export_dir, "write every factor as 16-bit PNG codes and PFM floats, and manifest.json, into DIR (the layout of sepal bake --export)");
    CLI::Option* param = app.get_option("--param");
    CLI::Option* map = app.get_option("--map");
    CLI::Option* terms = app.get_option("--terms");
    return [a, p, param, map, terms](const CommandIO& io) {
        a->p_given = p->count() > 0;
        a->param_given = param->count() > 0;
        a->map_given = map->count() > 0;
        a->terms_given = terms->count() > 0;
        return run_factor(*a, io);
    };
}

}  // namespace sepal
