// sepal info (stub, filled in by its issue).
#include "cli.h"

namespace sepal {
int cmd_info(const std::vector<std::string>&, const CommandIO& io) {
    std::fprintf(io.err, "sepal info: not implemented yet\n");
    return kExitBadInput;
}
}  // namespace sepal
