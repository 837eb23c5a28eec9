// sepal eval SPEC|ASSET theta_i phi_i theta_o phi_o [--cos] [--uncapped]: one BRDF value,
// "R G B" (degrees in); for a .sepal asset, the f its factors, diffuse part, white level and
// radiance flag represent (bake/asset_brdf.h).
#include "bake/asset_brdf.h"
#include "brdf/brdf.h"
#include "spec/spec.h"
#include "brdf/brdf_spec.h"
#include "brdf/brdf_util.h"
#include "cli/cli.h"
#include "cli/options.h"
#include "util/io.h"

namespace sepal {
namespace {

struct EvalArgs {
    std::string spec;
    double theta_i = 0, phi_i = 0, theta_o = 0, phi_o = 0;
    bool cos = false, uncapped = false;
};

int run_eval(const EvalArgs& a, const CommandIO& io) {
    std::string err;
    std::unique_ptr<Brdf> f;
    const AssetBrdf* asset = nullptr;
    if (file_extension(a.spec) == "sepal") {
        std::unique_ptr<AssetBrdf> loaded = AssetBrdf::load(a.spec, &err);
        asset = loaded.get();
        f = std::move(loaded);
    } else if (a.uncapped) {
        err = "--uncapped applies to a .sepal asset (got " + a.spec + ")";
    } else {
        f = make_brdf(a.spec, &err);
    }
    if (!f) {
        std::fprintf(io.err, "sepal eval: %s\n", err.c_str());
        return kExitBadInput;
    }
    const glm::dvec3 wi = dir_from_degrees(a.theta_i, a.phi_i), wo = dir_from_degrees(a.theta_o, a.phi_o);
    glm::dvec3 v;
    if (a.uncapped)
        v = asset->drawn_cos(wi, wo) / (a.cos || wi.z <= 0 ? 1.0 : wi.z);
    else if (a.cos)
        v = asset ? asset->eval_cos(wi, wo) : f->eval(wi, wo) * std::max(0.0, wi.z);
    else
        v = f->eval(wi, wo);
    std::fprintf(io.out, "%s %s %s\n", format_number(v.x).c_str(), format_number(v.y).c_str(),
                 format_number(v.z).c_str());
    return kExitOk;
}

}  // namespace

CommandRun setup_eval(CLI::App& app) {
    auto a = std::make_shared<EvalArgs>();
    app.add_option("SPEC", a->spec,
                   "BRDF spec (sepal info --models), measured file, or a .sepal asset: the f its factors, diffuse "
                   "part and profile, white level and radiance flag represent (as the CPU backend draws it, capped "
                   "at the white level)")
        ->required();
    // Polar angles past 90 degrees are below the horizon, where f is 0; past 180 they are a typo.
    app.add_option("theta_i", a->theta_i, "incident polar angle, degrees")->required()->check(finite_range(0, 180));
    app.add_option("phi_i", a->phi_i, "incident azimuth, degrees")->required()->check(finite_range(-1e6, 1e6));
    app.add_option("theta_o", a->theta_o, "outgoing polar angle, degrees")->required()->check(finite_range(0, 180));
    app.add_option("phi_o", a->phi_o, "outgoing azimuth, degrees")->required()->check(finite_range(-1e6, 1e6));
    app.add_flag("--cos", a->cos, "print f cos(theta_i) (what a radiance asset's factors hold) instead of f");
    app.add_flag("--uncapped", a->uncapped,
                 "an asset's value before its white level caps it: the CPU backend's per-pixel sum per unit "
                 "irradiance");
    return [a](const CommandIO& io) { return run_eval(*a, io); };
}

}  // namespace sepal
