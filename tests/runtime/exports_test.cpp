// What libsepal holds: the C API, not the GL ES emulator (sepal/internal/sepal_emulate.h),
// which the tools and tests link from libsepal_emulate.a.
#include <doctest/doctest.h>

#include <limits.h>
#include <unistd.h>

#include <string>

#include "test_util.h"

namespace {

// The build folder this test binary sits in (build/bin/sepal-tests, build/asan/bin/...).
std::string build_dir() {
    char exe[PATH_MAX] = {};
    const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    REQUIRE(n > 0);
    std::string build(exe, size_t(n));
    build = build.substr(0, build.rfind('/'));
    return build.substr(0, build.rfind('/'));
}

}  // namespace

TEST_CASE("exports: libsepal (static and shared) defines the C API but not the GL ES emulator") {
    const std::string build = build_dir();
    std::string out;
    // libsepal.a is a copy of the runtime's archive and libsepal.so links the same objects.
    REQUIRE(sepal_test::run("nm -g --defined-only " + build + "/lib/libsepal_runtime.a", &out) == 0);
    CHECK(out.find(" sepal_draw_cpu") != std::string::npos);
    CHECK(out.find(" sepal_asset_eval") != std::string::npos);
    CHECK(out.find("sepal_emulate_draw") == std::string::npos);
    CHECK(out.find("sepal_frame_emulate") == std::string::npos);
    REQUIRE(sepal_test::run("nm -g --defined-only " + build + "/lib/libsepal_emulate.a", &out) == 0);
    CHECK(out.find(" sepal_emulate_draw") != std::string::npos);
    CHECK(out.find(" sepal_frame_emulate") != std::string::npos);
    // The shared library where this build made it (make, not make check).
    if (sepal_test::run("ls " + build + "/dist/libsepal.so.*", &out) == 0) {
        REQUIRE(sepal_test::run("nm -D --defined-only " + build + "/dist/libsepal.so.*", &out) == 0);
        CHECK(out.find(" sepal_draw_cpu") != std::string::npos);
        CHECK(out.find("sepal_emulate") == std::string::npos);
    }
}
