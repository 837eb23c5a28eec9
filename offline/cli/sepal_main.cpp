// sepal: the offline multi-tool. A thin main over the offline library (offline/cli/cli.h).
#include "cli/cli.h"

int main(int argc, char** argv) { return sepal::run_sepal(argc, argv); }
