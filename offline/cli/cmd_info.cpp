// sepal info SPEC [--samples N] | sepal info --models: describe a BRDF or list the models.
#include "brdf/brdf.h"
#include "brdf/brdf_models.h"
#include "brdf/brdf_spec.h"
#include "brdf/brdf_util.h"
#include "cli/cli.h"

namespace sepal {

int cmd_info(const std::vector<std::string>& args, const CommandIO& io) {
    Args a(args, {"samples"}, {"models"});
    const char* usage = "usage: sepal info SPEC [--samples N]   |   sepal info --models\n";
    if (!a.ok()) {
        std::fprintf(io.err, "sepal info: %s\n%s", a.error().c_str(), usage);
        return kExitBadInput;
    }
    if (a.has("models")) {
        if (!a.positional().empty()) {
            std::fprintf(io.err, "sepal info: --models takes no spec\n%s", usage);
            return kExitBadInput;
        }
        std::fprintf(io.out, "%s", analytic_models_help().c_str());
        return kExitOk;
    }
    if (a.positional().size() != 1) {
        std::fprintf(io.err, "sepal info: expected one spec\n%s", usage);
        return kExitBadInput;
    }
    long samples = 128;
    if (a.has("samples") && !a.integer("samples", &samples)) {
        std::fprintf(io.err, "sepal info: %s\n", a.error().c_str());
        return kExitBadInput;
    }
    if (samples < 8 || samples > 4096) {
        std::fprintf(io.err, "sepal info: --samples %ld is outside [8, 4096]\n", samples);
        return kExitBadInput;
    }
    std::string err;
    std::unique_ptr<Brdf> f = make_brdf(a.positional()[0], &err);
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
    std::fprintf(io.out, "directional albedo R G B (quadrature samples %ld):\n", samples);
    const double phis[] = {0.0, 90.0};
    for (double phi : phis) {
        if (phi != 0.0 && f->isotropic()) break;
        for (double theta : {0.0, 30.0, 60.0, 80.0}) {
            const glm::dvec3 v = directional_albedo(*f, deg2rad(theta), int(samples), deg2rad(phi));
            std::fprintf(io.out, "  theta_i %2.0f phi_i %2.0f deg: %.6f %.6f %.6f\n", theta, phi,
                         v.x, v.y, v.z);
        }
    }
    return kExitOk;
}

}  // namespace sepal
