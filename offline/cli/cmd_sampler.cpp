// sepal sampler SPEC -o mat.smp [--kind factored|cosine|lafortune|as|tabulated|analytic]
//   [--terms J,K] [--report r.json]
//
// An importance sampler for a BRDF (Lawrence et al. 2004; the library is offline/sampling/,
// the reader sepal_sampler.h in the runtime): fits it, writes the SEPALSMP file a path tracer
// loads with sepal_sampler_parse, and prints what it costs and how well it samples: bytes,
// the estimator's relative variance of f cos / pdf at the judge views (lower is better; the
// cosine sampler's beside it), and the fit's own figures. `sepal render SPEC --env ...
// --sampler mat.smp` renders with it.
#include <cstdio>
#include <unistd.h>
#include <memory>
#include <string>

#include "brdf/brdf.h"
#include "spec/spec.h"
#include "cli/cli.h"
#include "cli/options.h"
#include "sampling/alternatives.h"
#include "sampling/factored_fit.h"
#include "sampling/metrics.h"
#include "sampling/sampler_file.h"
#include "util/io.h"
#include "util/json.h"

namespace sepal {
namespace {

struct SamplerArgs {
    std::string spec, out, kind = "factored", report;
    int lobes = 1;
    int iterations = 0;
};

int run_sampler(const SamplerArgs& a, const CommandIO& io) {
    const char* who = "sepal sampler";
    std::string err;
    auto fail = [&](const std::string& m) {
        std::fprintf(io.err, "%s: %s\n", who, m.c_str());
        return kExitBadInput;
    };
    if (!check_output("-o", a.out, &err) || !check_output("--report", a.report, &err)) return fail(err);
    std::unique_ptr<Brdf> brdf = make_brdf(a.spec, &err);
    if (!brdf) return fail(err);
    SamplerData d;
    Json fit = Json::object();
    if (a.kind == "factored") {
        FactoredOptions o;
        o.iterations = a.iterations;
        o.progress = isatty(2) != 0;  // a progress line on a terminal only
        FactoredReport r;
        if (!fit_factored(*brdf, o, &d, &r, &err)) return fail(err);
        fit = {{"param", r.param}, {"axis", r.axis}, {"phi_frame", r.phi_frame}, {"J", r.J}, {"K", r.K},
               {"kl_total", r.kl_total}, {"iterations", {r.iterations1, r.iterations2}},
               {"sample_seconds", r.sample_seconds}, {"factor_seconds", r.factor_seconds},
               {"seconds", r.sample_seconds + r.factor_seconds}, {"notes", r.notes}};
        std::fprintf(io.out, "fit        factored, %s parameterization about %s, %s frame, %d x %d terms, KL %.4g, %.1f s\n",
                     r.param.c_str(), r.axis.c_str(), r.phi_frame.c_str(), r.J, r.K, r.kl_total,
                     r.sample_seconds + r.factor_seconds);
        for (const std::string& n : r.notes) std::fprintf(io.out, "note       %s\n", n.c_str());
    } else if (a.kind == "cosine") {
        d = make_cosine_sampler();
    } else if (a.kind == "analytic") {
        if (!make_analytic_sampler(*brdf, &d, &err)) return fail(err);
    } else if (a.kind == "tabulated") {
        if (!make_tabulated_sampler(*brdf, TabulatedOptions{}, &d, &err)) return fail(err);
    } else {
        LobeFitReport r;
        const bool ok = a.kind == "lafortune" ? fit_lafortune_sampler(*brdf, a.lobes, &d, &r, &err)
                                              : fit_as_sampler(*brdf, &d, &r, &err);
        if (!ok) return fail(err);
        fit = {{"spec", r.spec}, {"rms_relative", r.rms_relative}};
        std::fprintf(io.out, "fit        %s lobes: %s (relative RMS of sqrt(f cos) %.4g)\n", a.kind.c_str(),
                     r.spec.c_str(), r.rms_relative);
    }
    Sampler s, cosine;
    if (!s.build(d, &err) || !cosine.build(make_cosine_sampler(), &err)) return fail(err);
    const std::vector<glm::dvec3> views = judge_views(brdf->isotropic());
    const double var = relative_variance(*brdf, s.get(), views, 4096, 1);
    const double var_cos = relative_variance(*brdf, cosine.get(), views, 4096, 1);
    std::fprintf(io.out, "sampler    %s, %zu bytes\n", a.kind.c_str(), s.bytes());
    std::fprintf(io.out, "variance   relative variance of f cos / pdf over %zu views: %.4g (cosine sampling: %.4g, %.3gx)\n",
                 views.size(), var, var_cos, var > 0 ? var_cos / var : 0.0);
    OutputGuard written;
    if (!write_sampler(a.out, d, &err)) return fail(err);
    if (!a.report.empty()) {
        const Json j = {{"spec", brdf->spec()}, {"kind", a.kind},       {"bytes", s.bytes()},
                        {"views", views.size()}, {"relative_variance", var}, {"cosine_relative_variance", var_cos},
                        {"fit", fit}};
        if (!write_json_file(a.report, j, &err)) return fail(err);
    }
    if (!written.commit(&err)) return fail(err);
    std::fprintf(io.out, "wrote      %s\n", a.out.c_str());
    return kExitOk;
}

}  // namespace

CommandRun setup_sampler(CLI::App& app) {
    auto a = std::make_shared<SamplerArgs>();
    app.add_option("SPEC", a->spec, "BRDF spec or measured file")->required();
    app.add_option("-o,--output", a->out, "the sampler file to write (.smp)")->required();
    app.add_option("--kind", a->kind,
                   "factored (Lawrence 2004), cosine, lafortune or as (fitted lobes), tabulated (Matusik's CDFs), "
                   "analytic (the model's own lobe)")
        ->check(CLI::IsMember({"factored", "cosine", "lafortune", "as", "tabulated", "analytic"}))
        ->capture_default_str();
    app.add_option("--lobes", a->lobes, "lafortune: lobes to fit")->check(CLI::Range(1, 4))->capture_default_str();
    app.add_option("--iterations", a->iterations,
                   "factored: KL-NMF iterations at most (0: 2000 about the normal, 500 about t or s)")
        ->check(CLI::Range(0, 1000000))
        ->capture_default_str();
    app.add_option("--report", a->report, "write the figures as JSON");
    return [a](const CommandIO& io) { return run_sampler(*a, io); };
}

}  // namespace sepal
