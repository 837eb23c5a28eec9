// sepal eval SPEC theta_i phi_i theta_o phi_o: one BRDF value, "R G B" (degrees in).
#include "brdf/brdf.h"
#include "spec/spec.h"
#include "brdf/brdf_spec.h"
#include "brdf/brdf_util.h"
#include "cli/cli.h"
#include "cli/options.h"

namespace sepal {
namespace {

struct EvalArgs {
    std::string spec;
    double theta_i = 0, phi_i = 0, theta_o = 0, phi_o = 0;
};

int run_eval(const EvalArgs& a, const CommandIO& io) {
    std::string err;
    std::unique_ptr<Brdf> f = make_brdf(a.spec, &err);
    if (!f) {
        std::fprintf(io.err, "sepal eval: %s\n", err.c_str());
        return kExitBadInput;
    }
    const glm::dvec3 v = f->eval(dir_from_degrees(a.theta_i, a.phi_i), dir_from_degrees(a.theta_o, a.phi_o));
    std::fprintf(io.out, "%s %s %s\n", format_number(v.x).c_str(), format_number(v.y).c_str(),
                 format_number(v.z).c_str());
    return kExitOk;
}

}  // namespace

CommandRun setup_eval(CLI::App& app) {
    auto a = std::make_shared<EvalArgs>();
    app.add_option("SPEC", a->spec, "BRDF spec (sepal info --models) or measured file")->required();
    // Polar angles past 90 degrees are below the horizon, where f is 0; past 180 they are a typo.
    app.add_option("theta_i", a->theta_i, "incident polar angle, degrees")->required()->check(finite_range(0, 180));
    app.add_option("phi_i", a->phi_i, "incident azimuth, degrees")->required()->check(finite_range(-1e6, 1e6));
    app.add_option("theta_o", a->theta_o, "outgoing polar angle, degrees")->required()->check(finite_range(0, 180));
    app.add_option("phi_o", a->phi_o, "outgoing azimuth, degrees")->required()->check(finite_range(-1e6, 1e6));
    return [a](const CommandIO& io) { return run_eval(*a, io); };
}

}  // namespace sepal
