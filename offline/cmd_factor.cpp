// sepal factor (stub, filled in by its issue).
#include "cli.h"

namespace sepal {
int cmd_factor(const std::vector<std::string>&, const CommandIO& io) {
    std::fprintf(io.err, "sepal factor: not implemented yet\n");
    return kExitBadInput;
}
}  // namespace sepal
