// sepal fit lafortune SAMPLES -o fit.json [--lobes N] [--anisotropic] [--forward] [--grey]
//                      [--sigma S] [--truth SPEC]
//
// A Lafortune model fitted to scattered samples (Lensch et al. 2003, section 4; the library
// is offline/fit/): SAMPLES is a samples.csv (what `sepal measure capture` writes; format in
// measured/samples.h) or a Cornell .brdf file. Prints each parameter with its 95% interval (from
// the covariance at the minimum; "unmeasured" when the samples do not determine it), the
// rank, the residual and the model as a spec that `sepal bake` and `sepal render` take; a
// warning when weighted samples' residual is over twice their stated noise (the model does
// not fit them, and the intervals would be too narrow); the model's largest directional albedo,
// with a warning above kPlausibleAlbedo (fit/lafortune_fit.h: it creates energy).
// fit.json holds the same with the full covariance matrix (null where unmeasured), max_albedo,
// and plausible (lafortune_plausible: no energy created and nothing clamped). --truth SPEC
// (the BRDF the samples came from, when it is known) judges the fit by its picture
// (cli/picture_report.h: exact renders in the default scene and the held-out conditions).
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "cli/cli.h"
#include "cli/options.h"
#include "cli/picture_report.h"
#include "spec/spec.h"
#include "fit/lafortune_fit.h"
#include "measured/samples.h"
#include "util/json.h"

namespace sepal {
namespace {

struct FitArgs {
    std::string samples, out, truth;
    LafortuneFitOptions o;
    bool anisotropic = false, grey = false;
};

// Residuals this many times the stated noise: the model, not the noise, explains them.
constexpr double kMisfitNoiseScale = 2.0;

int run_fit_lafortune(FitArgs& a, const CommandIO& io) {
    const char* who = "sepal fit lafortune";
    std::string err;
    std::vector<BrdfSample> samples;
    if (!read_brdf_samples(a.samples, &samples, &err)) {
        std::fprintf(io.err, "%s: %s\n", who, err.c_str());
        return kExitBadInput;
    }
    a.o.isotropic = !a.anisotropic;
    a.o.channels = a.grey ? 1 : 3;
    LafortuneFit r;
    if (!fit_lafortune(samples, a.o, &r, &err)) {
        std::fprintf(io.err, "%s: %s: %s\n", who, a.samples.c_str(), err.c_str());
        return kExitBadInput;
    }
    bool clamped = false;
    const std::string spec = r.model.spec(&clamped);
    std::fprintf(io.out, "samples    %d (%d residuals), %d parameters, rank %d%s\n", r.samples, r.residuals,
                 int(r.params.size()), r.rank, r.rank < int(r.params.size()) ? " (some parameters unmeasured)" : "");
    std::fprintf(io.out, "%-12s %12s %14s\n", "parameter", "value", "95% interval");
    Json params = Json::array();
    for (int j = 0; j < int(r.params.size()); ++j) {
        const double ci = r.ci95(j);
        if (std::isfinite(ci))
            std::fprintf(io.out, "%-12s %12.6g %14s\n", r.names[size_t(j)].c_str(), r.params(j),
                         ("+-" + std::to_string(ci)).c_str());
        else
            std::fprintf(io.out, "%-12s %12.6g %14s\n", r.names[size_t(j)].c_str(), r.params(j), "unmeasured");
        params.push_back({{"name", r.names[size_t(j)]}, {"value", r.params(j)}, {"ci95", ci}});
    }
    std::fprintf(io.out, "residual   rms %.6g /sr, noise scale %.6g (%s), %d evaluations\n", r.rms, r.sigma,
                 a.o.sigma > 0 ? "given" : "estimated", r.evaluations);
    std::fprintf(io.out, "spec       %s%s\n", spec.c_str(), clamped ? "  (clamped into the spec's ranges)" : "");
    // A lobe fitted where the samples have none (often at grazing angles) can create energy
    // that renders as a glare in views unlike the measured ones.
    double max_albedo = 0;
    const bool plausible = lafortune_plausible(r.model, &max_albedo);
    std::fprintf(io.out, "energy     largest directional albedo %.3g (incidence 0..89 degrees, any channel)\n",
                 max_albedo);
    if (max_albedo > kPlausibleAlbedo)
        std::fprintf(io.out,
                     "warning    the model reflects more light than it receives (albedo above %.1f): a lobe "
                     "grew where the samples have none, or they are not one material; its renders glare where "
                     "nothing was measured. Fit each material's samples apart, or with fewer lobes\n",
                     kPlausibleAlbedo);
    Json picture;
    if (!a.truth.empty()) {
        std::unique_ptr<Brdf> truth = make_brdf(a.truth, &err), fitted = make_brdf(spec, &err);
        if (!truth || !fitted || !report_picture(*truth, *fitted, io.out, &picture, &err)) {
            std::fprintf(io.err, "%s: --truth: %s\n", who, err.c_str());
            return kExitBadInput;
        }
    }
    // Samples that carry weights (`measure capture` writes 1/std) say how large their noise
    // is: an estimated noise scale well above 1 means the residual is not noise but a model
    // that does not describe the samples, and intervals computed as if it did are too narrow.
    bool weighted = false;
    for (const BrdfSample& s : samples) weighted = weighted || s.weight != 1.0;
    const bool misfit = weighted && a.o.sigma <= 0 && r.sigma > kMisfitNoiseScale;
    if (misfit)
        std::fprintf(io.out,
                     "warning    the residual is %.3g x the noise the samples' weights state (1/std): %d lobe%s "
                     "do%s not describe these samples (several materials, or a shape the model lacks), and the "
                     "95%% intervals above assume it does; fit each material's samples apart or try --lobes %d\n",
                     r.sigma, a.o.lobes, a.o.lobes == 1 ? "" : "s", a.o.lobes == 1 ? "es" : "", std::min(4, a.o.lobes + 1));
    if (!a.out.empty()) {
        Json cov = Json::array();
        for (int i = 0; i < int(r.cov.rows()); ++i) {
            Json row = Json::array();
            for (int j = 0; j < int(r.cov.cols()); ++j) row.push_back(r.cov(i, j));  // inf -> null
            cov.push_back(std::move(row));
        }
        Json j = {{"samples_file", a.samples},
                  {"samples", r.samples},
                  {"residuals", r.residuals},
                  {"lobes", a.o.lobes},
                  {"isotropic", a.o.isotropic},
                  {"forward", a.o.forward},
                  {"channels", a.o.channels},
                  {"spec", spec},
                  {"clamped", clamped},
                  {"max_albedo", max_albedo},
                  {"plausible", plausible},
                  {"rank", r.rank},
                  {"rss", r.rss},
                  {"rms", r.rms},
                  {"sigma", r.sigma},
                  {"sigma_given", a.o.sigma > 0},
                  {"model_fits_noise", !misfit},
                  {"evaluations", r.evaluations},
                  {"parameters", std::move(params)},
                  {"covariance", std::move(cov)}};
        if (!picture.is_null()) j["picture"] = picture;
        if (!write_json_file(a.out, j, &err)) {
            std::fprintf(io.err, "%s: %s\n", who, err.c_str());
            return kExitBadInput;
        }
        std::fprintf(io.out, "wrote      %s\n", a.out.c_str());
    }
    return kExitOk;
}

CommandRun setup_fit_lafortune(CLI::App& c) {
    auto a = std::make_shared<FitArgs>();
    c.add_option("SAMPLES", a->samples, "samples.csv (sepal measure capture) or a Cornell .brdf file")->required();
    c.add_option("-o,--output", a->out, "write the fit, its intervals and covariance as JSON");
    c.add_option("--truth", a->truth, "the BRDF the samples came from: the fit's picture against it");
    c.add_option("--lobes", a->o.lobes, "specular lobes")->check(CLI::Range(1, 4))->capture_default_str();
    c.add_flag("--anisotropic", a->anisotropic, "fit Cx and Cy apart (default: Cx = Cy)");
    c.add_flag("--forward", a->o.forward,
               "keep the lobes forward and the diffuse colour >= 0 (Cx, Cy <= 0, Cz >= 0, n >= 1): no grazing or "
               "retro lobe where the samples are sparse");
    c.add_flag("--grey", a->grey, "one grey diffuse value from the samples' luminance (default: RGB)");
    c.add_option("--sigma", a->o.sigma,
                 "the samples' known noise (weights are 1/std relative to it); default: estimated from the residual")
        ->check(positive());
    c.add_option("--max-evaluations", a->o.max_evaluations, "model evaluations of the solver")
        ->check(CLI::Range(10, 1000000))->capture_default_str();
    return [a](const CommandIO& io) { return run_fit_lafortune(*a, io); };
}

}  // namespace

CommandRun setup_fit(CLI::App& app) {
    return setup_subcommands(app, {
        {"lafortune", "fit a Lafortune model with its parameters' covariance", setup_fit_lafortune},
    });
}

}  // namespace sepal
