// Command lines of the benchmark programs (tests/bench/<name>.cpp -> sepal-bench-<name>):
// CLI11, with the flags every bench shares.
//
// Usage:
//   int main(int argc, char** argv) {
//       BenchCli cli("sepal-bench-foo", "what it measures");
//       int frames = 7;
//       cli.app.add_option("--frames", frames, "frames per measurement")->check(CLI::Range(1, 100));
//       if (int code = cli.parse(argc, argv); code >= 0) return code;
//       ... cli.out (default build/bench, created), cli.build (default build) ...
//   }
// parse returns -1 to go on, or the exit code: 0 after --help or --version, 2 after a bad
// flag (the message names it), 2 when the output folder cannot be made; 0 right after
// parsing when SEPAL_BENCH_PARSE_ONLY is set (tests/make_bench_test.cpp runs tests/bench/run.sh so).
// SEPAL_BENCH_PARSE_ONLY=quiet also holds a quiet section (quiet.h) until stdin ends, so the
// test can watch a real bench stop and resume the other lanes.
#pragma once
#include <cstdio>
#include <cstdlib>
#include <string>

#include <CLI/CLI.hpp>

#include "bench/quiet.h"
#include "sepal/sepal_version.h"
#include "util/io.h"

struct BenchCli {
    CLI::App app;
    std::string out = "build/bench", build = "build";

    BenchCli(const std::string& name, const std::string& description) : app(description, name) {
        app.set_version_flag("--version", name + " " SEPAL_VERSION_STRING);
        app.get_formatter()->column_width(30);
        app.add_option("--out", out, "folder for the JSON and figures")->capture_default_str();
        app.add_option("--build", build, "the build folder whose binaries are measured")->capture_default_str();
    }

    // The usual pair of a bench over named materials: --only NAME and --threads N.
    std::string only;
    int threads = 0;
    void add_only_and_threads(const std::string& only_help) {
        app.add_option("--only", only, only_help);
        app.add_option("--threads", threads, "threads, 0 = all cores")->check(CLI::Range(0, 256));
    }

    int parse(int argc, char** argv) {
        try {
            app.parse(argc, argv);
        } catch (const CLI::ParseError& e) {
            if (e.get_exit_code() == 0) return app.exit(e);
            std::fprintf(stderr, "%s: %s\nrun '%s --help' for the accepted flags\n", app.get_name().c_str(), e.what(),
                         app.get_name().c_str());
            return 2;
        }
        // The make-bench smoke test: every line of tests/bench/run.sh parses, then stops.
        if (const char* only = std::getenv("SEPAL_BENCH_PARSE_ONLY")) {
            if (std::string(only) == "quiet") {
                BenchQuiet quiet;
                std::puts("quiet");
                std::fflush(stdout);
                while (std::getchar() != EOF) {
                }
            }
            return 0;
        }
        std::string err;
        if (!sepal::make_dirs(out, &err)) {
            std::fprintf(stderr, "%s: %s\n", app.get_name().c_str(), err.c_str());
            return 2;
        }
        return -1;
    }
};
