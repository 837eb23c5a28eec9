// doctest runner for every suite in tests/ (one binary: build/bin/sepal-tests).
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>
