// sepal gen-merl SPEC -o out.binary: tabulates any BRDF (analytic or measured) into a
// MERL-format file (merl.h). The output is written atomically and is byte-identical for the
// same SPEC.
#include <string>

#include "brdf/brdf.h"
#include "cli/cli.h"
#include "cli/options.h"
#include "measured/merl.h"

namespace sepal {
namespace {

struct GenMerlArgs {
    std::string spec, out;
};

int run_gen_merl(const GenMerlArgs& a, const CommandIO& io) {
    std::string err;
    std::unique_ptr<Brdf> f = make_brdf(a.spec, &err);
    if (!f) {
        std::fprintf(io.err, "sepal gen-merl: %s\n", err.c_str());
        return kExitBadInput;
    }
    if (!f->isotropic())
        std::fprintf(io.err,
                     "sepal gen-merl: warning: %s is anisotropic; MERL holds only the "
                     "phi_h = 0 slice\n",
                     f->spec().c_str());
    if (!write_merl(a.out, *f, &err)) {
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
    return [a](const CommandIO& io) { return run_gen_merl(*a, io); };
}

int cmd_gen_merl(const std::vector<std::string>& args, const CommandIO& io) {
    return run_command("gen-merl", args, io);
}

}  // namespace sepal
