// sepal gen-merl SPEC -o out.binary: tabulates any BRDF (analytic or measured) into a
// MERL-format file (merl.h). The output is written atomically and is byte-identical for the
// same SPEC.
#include <string>

#include "brdf/brdf.h"
#include "cli/cli.h"
#include "measured/merl.h"

namespace sepal {
int cmd_gen_merl(const std::vector<std::string>& args, const CommandIO& io) {
    std::string spec, out;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "-o" || a == "--output") {
            if (i + 1 >= args.size()) {
                std::fprintf(io.err, "sepal gen-merl: option %s needs a value\n", a.c_str());
                return kExitBadInput;
            }
            out = args[++i];
        } else if (a.size() > 1 && a[0] == '-') {
            std::fprintf(io.err, "sepal gen-merl: unknown option %s\n", a.c_str());
            return kExitBadInput;
        } else if (spec.empty()) {
            spec = a;
        } else {
            std::fprintf(io.err, "sepal gen-merl: unexpected argument '%s'\n", a.c_str());
            return kExitBadInput;
        }
    }
    if (spec.empty() || out.empty()) {
        std::fprintf(io.err, "sepal gen-merl: usage: sepal gen-merl SPEC -o out.binary\n");
        return kExitBadInput;
    }
    std::string err;
    std::unique_ptr<Brdf> f = make_brdf(spec, &err);
    if (!f) {
        std::fprintf(io.err, "sepal gen-merl: %s\n", err.c_str());
        return kExitBadInput;
    }
    if (!f->isotropic())
        std::fprintf(io.err,
                     "sepal gen-merl: warning: %s is anisotropic; MERL holds only the "
                     "phi_h = 0 slice\n",
                     f->spec().c_str());
    if (!write_merl(out, *f, &err)) {
        std::fprintf(io.err, "sepal gen-merl: %s\n", err.c_str());
        return kExitBadInput;
    }
    std::fprintf(io.out, "wrote %s: MERL %d x %d x %d, %llu bytes, from %s\n", out.c_str(),
                 kMerlThetaH, kMerlThetaD, kMerlPhiD, (unsigned long long)kMerlFileBytes,
                 f->spec().c_str());
    return kExitOk;
}
}  // namespace sepal
