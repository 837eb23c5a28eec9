// `make bench` as tests/bench/run.sh runs it, without the hour: every program accepts the
// flags its line gives (a refusal stops the script there, `set -e`: sepal-bench-extremes
// refused --out and nothing after it ever ran), and every tests/bench/<name>.cpp has a line.
#include <doctest/doctest.h>

#include <dirent.h>
#include <limits.h>
#include <unistd.h>

#include <fstream>
#include <sstream>
#include <string>

#include "test_util.h"

TEST_CASE("make bench: tests/bench/run.sh runs every bench, and each accepts its flags") {
    // The build folder this test binary sits in (build/bin/sepal-tests, build/asan/bin/...).
    char exe[PATH_MAX] = {};
    const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    REQUIRE(n > 0);
    std::string build(exe, size_t(n));
    build = build.substr(0, build.rfind('/'));  // .../bin
    build = build.substr(0, build.rfind('/'));
    const std::string script = sepal_test::source_path("tests/bench/run.sh");
    std::ifstream in(script);
    std::stringstream text;
    text << in.rdbuf();
    DIR* d = opendir(sepal_test::source_path("tests/bench").c_str());
    REQUIRE(d);
    int benches = 0;
    while (dirent* e = readdir(d)) {
        const std::string name = e->d_name;
        if (name.size() < 5 || name.compare(name.size() - 4, 4, ".cpp") != 0) continue;
        ++benches;
        const std::string program = "sepal-bench-" + name.substr(0, name.size() - 4);
        CAPTURE(program);
        CHECK(text.str().find("/" + program + "\"") != std::string::npos);
    }
    closedir(d);
    CHECK(benches >= 12);
    std::string out;
    const int code = sepal_test::run("SEPAL_BENCH_PARSE_ONLY=1 sh " + script + " " + build + " " +
                                         sepal_test::temp_dir() + "/bench",
                                     &out);
    INFO(out);
    CHECK(code == 0);
}
