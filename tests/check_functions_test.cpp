// make check-functions (tests/check_functions.sh): no function in offline/ or runtime/ over
// 150 lines. The counter must see a function one line over, and the tree must pass.
#include <doctest/doctest.h>

#include <fstream>
#include <string>

#include "test_util.h"

namespace {

// A function whose body spans `lines` lines from its signature to its closing brace.
std::string function_of(const std::string& name, int lines) {
    std::string s = "int " + name + "(int x) {\n";
    for (int i = 0; i < lines - 2; ++i) s += "    x += " + std::to_string(i) + ";\n";
    return s + "}\n\n";
}

}  // namespace

TEST_CASE("check-functions: a 151-line function is reported, a 150-line one and the tree are not") {
    const std::string dir = sepal_test::temp_dir(), file = dir + "/long.cpp";
    {
        std::ofstream f(file);
        f << "namespace a {\n\n" << function_of("fits", 150) << function_of("too_long", 151)
          << "int wrapped(int x,\n           int y) {\n    return x + y;\n}\n\n}  // namespace a\n";
    }
    std::string out;
    REQUIRE(sepal_test::run("awk -v LIMIT=150 -f " + sepal_test::source_path("tests/function_length.awk") + " " + file,
                            &out) == 0);
    CHECK(out.find("151 lines: int too_long(int x) {") != std::string::npos);
    CHECK(out.find("fits") == std::string::npos);
    CHECK(sepal_test::run("sh " + sepal_test::source_path("tests/check_functions.sh"), &out) == 0);
    CHECK(out.empty());
}
