// sepal gen-merl (stub, filled in by its issue).
#include "cli.h"

namespace sepal {
int cmd_gen_merl(const std::vector<std::string>&, const CommandIO& io) {
    std::fprintf(io.err, "sepal gen-merl: not implemented yet\n");
    return kExitBadInput;
}
}  // namespace sepal
