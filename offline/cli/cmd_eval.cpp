// sepal eval SPEC theta_i phi_i theta_o phi_o: one BRDF value, "R G B" (degrees in).
#include "brdf/brdf.h"
#include "brdf/brdf_spec.h"
#include "brdf/brdf_util.h"
#include "cli/cli.h"

namespace sepal {

int cmd_eval(const std::vector<std::string>& args, const CommandIO& io) {
    Args a(args, {});
    if (!a.ok() || a.positional().size() != 5) {
        std::fprintf(
            io.err,
            "sepal eval: %s\nusage: sepal eval SPEC theta_i phi_i theta_o phi_o   (degrees)\n",
            a.ok() ? "expected a spec and four angles" : a.error().c_str());
        return kExitBadInput;
    }
    const std::vector<std::string>& p = a.positional();
    static const char* names[] = {"theta_i", "phi_i", "theta_o", "phi_o"};
    double ang[4];
    for (int k = 0; k < 4; ++k) {
        if (!parse_finite(p[k + 1], &ang[k])) {
            std::fprintf(io.err, "sepal eval: %s '%s' is not a finite number (degrees)\n", names[k],
                         p[k + 1].c_str());
            return kExitBadInput;
        }
        // Polar angles past 90 degrees are below the horizon, where f is 0; past 180 they
        // are a typo.
        if ((k == 0 || k == 2) && !(ang[k] >= 0.0 && ang[k] <= 180.0)) {
            std::fprintf(io.err, "sepal eval: %s = %s is outside [0, 180] degrees\n", names[k],
                         p[k + 1].c_str());
            return kExitBadInput;
        }
    }
    std::string err;
    std::unique_ptr<Brdf> f = make_brdf(p[0], &err);
    if (!f) {
        std::fprintf(io.err, "sepal eval: %s\n", err.c_str());
        return kExitBadInput;
    }
    const glm::dvec3 v =
        f->eval(dir_from_degrees(ang[0], ang[1]), dir_from_degrees(ang[2], ang[3]));
    std::fprintf(io.out, "%s %s %s\n", format_number(v.x).c_str(), format_number(v.y).c_str(),
                 format_number(v.z).c_str());
    return kExitOk;
}

}  // namespace sepal
