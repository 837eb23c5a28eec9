// sepal info SPEC [--samples N] | sepal info --models: describe a BRDF or list the models.
#include "brdf/brdf.h"
#include "brdf/brdf_models.h"
#include "brdf/brdf_spec.h"
#include "brdf/brdf_util.h"
#include "cli/cli.h"
#include "cli/options.h"

namespace sepal {
namespace {

struct InfoArgs {
    std::string spec;
    int samples = 128;
    bool models = false;
};

int run_info(const InfoArgs& a, const CommandIO& io) {
    if (a.models) {
        std::fprintf(io.out, "%s", analytic_models_help().c_str());
        return kExitOk;
    }
    std::string err;
    std::unique_ptr<Brdf> f = make_brdf(a.spec, &err);
    if (!f) {
        std::fprintf(io.err, "sepal info: %s\n", err.c_str());
        return kExitBadInput;
    }
    std::fprintf(io.out, "model              %s\n", f->model().c_str());
    std::fprintf(io.out, "spec               %s\n", f->spec().c_str());
    std::fprintf(io.out, "isotropic          %s\n", f->isotropic() ? "yes" : "no");
    std::fprintf(io.out, "energy conserving  %s\n", f->energy_conserving() ? "yes" : "not claimed");
    std::string info = f->info();
    if (!info.empty() && info.back() != '\n') info += '\n';
    std::fprintf(io.out, "%s", info.c_str());
    std::fprintf(io.out, "directional albedo R G B (quadrature samples %d):\n", a.samples);
    const double phis[] = {0.0, 90.0};
    for (double phi : phis) {
        if (phi != 0.0 && f->isotropic()) break;
        for (double theta : {0.0, 30.0, 60.0, 80.0}) {
            const glm::dvec3 v = directional_albedo(*f, deg2rad(theta), a.samples, deg2rad(phi));
            std::fprintf(io.out, "  theta_i %2.0f phi_i %2.0f deg: %.6f %.6f %.6f\n", theta, phi, v.x, v.y, v.z);
        }
    }
    return kExitOk;
}

}  // namespace

CommandRun setup_info(CLI::App& app) {
    auto a = std::make_shared<InfoArgs>();
    CLI::Option* spec = app.add_option("SPEC", a->spec, "BRDF spec (model:param=value,...) or measured file");
    CLI::Option* models = app.add_flag("--models", a->models, "list the analytic models and their parameters");
    spec->excludes(models);
    app.add_option("--samples", a->samples, "quadrature samples per albedo")
        ->check(CLI::Range(8, 4096))
        ->capture_default_str();
    app.callback([spec, models] {
        if (!*spec && !*models) throw CLI::RequiredError("SPEC (or --models)");
    });
    return [a](const CommandIO& io) { return run_info(*a, io); };
}

int cmd_info(const std::vector<std::string>& args, const CommandIO& io) { return run_command("info", args, io); }

}  // namespace sepal
