// sepal eval (stub, filled in by its issue).
#include "cli.h"

namespace sepal {
int cmd_eval(const std::vector<std::string>&, const CommandIO& io) {
    std::fprintf(io.err, "sepal eval: not implemented yet\n");
    return kExitBadInput;
}
}  // namespace sepal
