// sepal gen-merl SPEC -o out.binary [--force]: tabulates an isotropic BRDF (analytic or
// measured) into a MERL-format file (merl.h). An anisotropic one is refused unless --force
// (MERL has no phi_h), saying how the file would differ. The output is written atomically
// and is byte-identical for the same SPEC.
#include <string>

#include "brdf/brdf.h"
#include "spec/spec.h"
#include "brdf/brdf_util.h"
#include "util/io.h"
#include "cli/cli.h"
#include "cli/options.h"
#include "measured/merl.h"

namespace sepal {
namespace {

struct GenMerlArgs {
    std::string spec, out;
    bool force = false;
};

int run_gen_merl(const GenMerlArgs& a, const CommandIO& io) {
    std::string err;
    std::unique_ptr<Brdf> f = make_brdf(a.spec, &err);
    if (!f) {
        std::fprintf(io.err, "sepal gen-merl: %s\n", err.c_str());
        return kExitBadInput;
    }
    std::vector<uint8_t> bytes;
    if (!encode_merl(*f, &bytes, &err)) {
        std::fprintf(io.err, "sepal gen-merl: %s\n", err.c_str());
        return kExitBadInput;
    }
    if (!f->isotropic()) {
        // MERL's table has no phi_h: the file holds the phi_h = 0 slice, another material.
        // Say how different, by the albedo a viewer sees, before writing anything.
        std::unique_ptr<Brdf> table = make_merl_brdf(bytes, a.out, &err);
        if (!table) {
            std::fprintf(io.err, "sepal gen-merl: %s\n", err.c_str());
            return kExitBadInput;
        }
        std::string how = "MERL tables are isotropic: the file would hold " + f->spec() +
                          " at phi_h = 0 only; directional albedo (mean of R G B)";
        for (double theta : {0.0, 60.0}) {
            const glm::dvec3 s = directional_albedo(*f, deg2rad(theta)), t = directional_albedo(*table, deg2rad(theta));
            char buf[128];
            std::snprintf(buf, sizeof buf, "%s at theta_i %.0f: %.3f -> %.3f", theta == 0 ? "" : ",", theta,
                          (s.x + s.y + s.z) / 3, (t.x + t.y + t.z) / 3);
            how += buf;
        }
        if (!a.force) {
            std::fprintf(io.err, "sepal gen-merl: %s is anisotropic. %s. Nothing written; --force writes it anyway\n",
                         f->spec().c_str(), how.c_str());
            return kExitBadInput;
        }
        std::fprintf(io.out, "reduced: %s\n", how.c_str());
    }
    if (!write_file_atomic(a.out, bytes.data(), bytes.size(), &err)) {
        std::fprintf(io.err, "sepal gen-merl: %s\n", err.c_str());
        return kExitBadInput;
    }
    std::fprintf(io.out, "wrote %s: MERL %d x %d x %d, %llu bytes, from %s\n", a.out.c_str(), kMerlThetaH,
                 kMerlThetaD, kMerlPhiD, (unsigned long long)kMerlFileBytes, f->spec().c_str());
    return kExitOk;
}

}  // namespace

CommandRun setup_gen_merl(CLI::App& app) {
    auto a = std::make_shared<GenMerlArgs>();
    app.add_option("SPEC", a->spec, "BRDF spec or measured file")->required();
    app.add_option("-o,--output", a->out, "the MERL .binary to write")->required();
    app.add_flag("--force", a->force,
                 "write an anisotropic BRDF too (MERL keeps its phi_h = 0 slice; the albedo change is printed)");
    return [a](const CommandIO& io) { return run_gen_merl(*a, io); };
}

}  // namespace sepal
