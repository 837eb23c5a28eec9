// `make bench` as tests/bench/run.sh runs it, without the hour: every program accepts the
// flags its line gives (a refusal stops the script there, `set -e`: sepal-bench-extremes
// refused --out and nothing after it ever ran), and every tests/bench/<name>.cpp has a line;
// and the quiet sections (tests/bench/quiet.h) that keep timings alone while two lanes run, seen
// from outside: a bench program holds one (SEPAL_BENCH_PARSE_ONLY=quiet, bench_cli.h) while this
// test watches a stand-in lane. The test binary includes nothing of tests/bench.
#include <doctest/doctest.h>

#include <dirent.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <sstream>
#include <string>

#include "test_util.h"

TEST_CASE("make bench: tests/bench/run.sh runs every bench, and each accepts its flags") {
    const std::string build = sepal_test::build_dir();
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

namespace {
// The state letter of /proc/PID/stat ('T' stopped, 'S' sleeping, ...).
char proc_state(pid_t pid) {
    std::ifstream f("/proc/" + std::to_string(pid) + "/stat");
    std::string line;
    std::getline(f, line);
    const size_t close = line.rfind(')');
    return close != std::string::npos && close + 2 < line.size() ? line[close + 2] : '?';
}
// Polls every 10 ms, `tries` times at most (the default: 2 s).
char wait_state(pid_t pid, char want, int tries = 200) {
    char s = '?';
    for (int i = 0; i < tries && (s = proc_state(pid)) != want; ++i) usleep(10000);
    return s;
}
}  // namespace

TEST_CASE("make bench: a bench's quiet section stops the other lanes' process groups and resumes them") {
    // A stand-in lane: a child in its own process group, sleeping.
    const pid_t child = fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        setpgid(0, 0);
        for (;;) pause();
    }
    setpgid(child, child);
    const std::string list = sepal_test::temp_dir() + "/lanes";
    {
        std::ofstream(list) << child << "\n" << getpgrp() << "\n";  // the bench's own group is skipped
    }
    REQUIRE(wait_state(child, 'S') == 'S');
    const std::string bench = sepal_test::build_dir() + "/bin/sepal-bench-cost";
    REQUIRE_MESSAGE(access(bench.c_str(), X_OK) == 0, bench << " is not built (make test builds it)");
    // The bench holds its section until its stdin closes.
    FILE* p = popen(("SEPAL_BENCH_PARSE_ONLY=quiet SEPAL_BENCH_LANES='" + list + "' " + bench + " > /dev/null").c_str(), "w");
    REQUIRE(p);
    CHECK(wait_state(child, 'T', 3000) == 'T');
    CHECK(pclose(p) == 0);
    CHECK(wait_state(child, 'S') == 'S');
    // Without the lane list it stops nothing.
    p = popen(("SEPAL_BENCH_PARSE_ONLY=quiet " + bench + " > /dev/null").c_str(), "w");
    REQUIRE(p);
    usleep(500000);
    CHECK(proc_state(child) == 'S');
    CHECK(pclose(p) == 0);
    kill(child, SIGKILL);
    waitpid(child, nullptr, 0);
}
