// docs/cli.md is the CLI reference, generated from the parsers themselves: every command's
// (and subcommand's) --help. This test fails when the file is stale; SEPAL_UPDATE_GOLDENS=1
// (`make update-goldens`) rewrites it, like the golden images.
#include <doctest/doctest.h>

#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/cli.h"
#include "test_util.h"
#include "util/io.h"

namespace {

// app's help under its full command line, then its subcommands' (CLI11's help takes the
// words before the app's own name).
void add_help(const CLI::App* app, const std::string& parent, std::string* md) {
    const std::string path = parent + " " + app->get_name();
    *md += "\n## `" + path + "`\n\n```text\n" + app->help(parent) + "```\n";
    for (const CLI::App* sub : app->get_subcommands([](const CLI::App*) { return true; }))
        add_help(sub, path, md);
}

std::string cli_reference() {
    std::vector<sepal::CommandRun> runs;
    std::unique_ptr<CLI::App> app = sepal::make_sepal_app(&runs);
    std::string md =
        "# sepal command-line reference\n\n"
        "Generated from the parsers (`tests/offline/cli/cli_doc_test.cpp` checks it is current;\n"
        "`make update-goldens` rewrites it). Exit codes: 0 success, 1 a check failed (`diff` with\n"
        "a tolerance, budgets not met), 2 bad usage or input (the message says what and where).\n\n"
        "```text\n" +
        app->help() + "```\n";
    for (const sepal::Command& c : sepal::commands())
        add_help(app->get_subcommand(c.name), "sepal", &md);
    return md;
}

}  // namespace

TEST_CASE("docs/cli.md is the parsers' --help of every command (update: SEPAL_UPDATE_GOLDENS=1)") {
    const std::string path = sepal_test::source_path("docs/cli.md");
    const std::string want = cli_reference();
    std::string err;
    const char* update = std::getenv("SEPAL_UPDATE_GOLDENS");
    if (update && update[0] == '1') {
        REQUIRE_MESSAGE(sepal::write_file_atomic(path, want.data(), want.size(), &err), err);
        return;
    }
    std::vector<uint8_t> bytes;
    const bool read = sepal::read_file(path, &bytes, &err);
    const std::string why = err + " (run `make update-goldens` to write it)";
    REQUIRE_MESSAGE(read, why);
    const std::string have(bytes.begin(), bytes.end());
    CHECK_MESSAGE(have == want, "docs/cli.md is stale: run `make update-goldens` and commit it");
    for (const sepal::Command& c : sepal::commands())
        CHECK_MESSAGE(have.find(std::string("## `sepal ") + c.name + "`") != std::string::npos, c.name);
}
