// What libsepal holds: the C API, not the GL ES emulator (sepal/internal/sepal_emulate.h),
// which the tools and tests link from libsepal_emulate.a.
#include <doctest/doctest.h>

#include <string>

#include "test_util.h"

TEST_CASE("exports: libsepal (static and shared) defines the C API but not the GL ES emulator") {
    const std::string build = sepal_test::build_dir();
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
