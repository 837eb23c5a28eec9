/* sepal's version: the one place it is defined (sepal --version, sepal-view --version,
 * the benchmarks' --version and their JSON). Semantic versioning: the major number changes
 * when the runtime's C API or the asset format breaks compatibility (the asset format has
 * its own version, SEPAL_FMT_VERSION_* in sepal_format.h, checked on load).
 * Thread safety: constants only. */
#ifndef SEPAL_VERSION_H
#define SEPAL_VERSION_H

#define SEPAL_VERSION_MAJOR 0
#define SEPAL_VERSION_MINOR 9
#define SEPAL_VERSION_PATCH 0
#define SEPAL_VERSION_STRING "0.9.0"
/* Packed: major << 16 | minor << 8 | patch (what sepal_version() returns at run time). */
#define SEPAL_VERSION ((SEPAL_VERSION_MAJOR << 16) | (SEPAL_VERSION_MINOR << 8) | SEPAL_VERSION_PATCH)

#endif
