// The command line as a whole (offline/cli/cli.h): every command's --help lists every flag
// it accepts (walked from the parser's own flag table), --version, exit codes of bad usage.
#include <doctest/doctest.h>

#include <CLI/CLI.hpp>

#include "cli/cli.h"
#include "common/scene_flags.h"
#include "cli/scene_options.h"
#include "sepal/sepal_format.h"
#include "sepal/sepal_version.h"
#include "test_util.h"

namespace {
bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// Every name an option answers to (--res, -o, --output, SPEC) appears in the help text,
// and the option says what it is for.
void check_help_lists_options(const CLI::App& app, const std::string& help) {
    for (const CLI::Option* opt : app.get_options()) {
        CAPTURE(opt->get_name());
        CHECK_MESSAGE(!opt->get_description().empty(), "an option without a description");
        for (const std::string& l : opt->get_lnames()) CHECK_MESSAGE(contains(help, "--" + l), help);
        for (const std::string& s : opt->get_snames()) CHECK_MESSAGE(contains(help, "-" + s), help);
        if (opt->get_positional()) CHECK_MESSAGE(contains(help, opt->get_name(true)), help);
    }
}
}  // namespace

TEST_CASE("cli: every command's --help lists every flag in its parser's table") {
    std::vector<sepal::CommandRun> runs;
    std::unique_ptr<CLI::App> app = sepal::make_sepal_app(&runs);
    REQUIRE(runs.size() == sepal::commands().size());
    int options = 0;
    for (const sepal::Command& c : sepal::commands()) {
        CAPTURE(c.name);
        const CLI::App* sub = app->get_subcommand(c.name);
        // The help a user sees: through the command's own entry point, as the shell runs it.
        std::string help;
        REQUIRE(sepal_test::run_cmd(c.name, {"--help"}, &help) == 0);
        CHECK(contains(help, std::string("sepal ") + c.name));
        check_help_lists_options(*sub, help);
        options += int(sub->get_options().size());
        // The table's entry point runs this command, not another.
        std::string out;
        CHECK(sepal_test::run_cmd(c.name, {"--no-such-flag"}, &out) == 2);
        CHECK_MESSAGE(contains(out, std::string("sepal ") + c.name + ": "), out);
    }
    CHECK(options > 60);  // the walk saw the tables (not an empty app)
    // The scene flags shared with sepal-view, on a parser of their own.
    CLI::App scene;
    sepal_ports::SceneSetup setup;
    sepal::add_scene_options(scene, &setup);
    std::string help;
    REQUIRE(sepal_test::run_cmd("render", {"--help"}, &help) == 0);
    check_help_lists_options(scene, help);
    CHECK(scene.get_options().size() >= 8u);
}

TEST_CASE("cli: sepal --version, help, and errors that name the flag") {
    std::string out;
    const std::string bin = sepal_test::bin("sepal");
    REQUIRE(sepal_test::run(bin + " --version", &out) == 0);
    CHECK(out == "sepal " SEPAL_VERSION_STRING " (asset format " + std::to_string(SEPAL_FMT_VERSION_MAJOR) + "." +
                     std::to_string(SEPAL_FMT_VERSION_MINOR) + ")\n");
    CHECK(sepal_test::run(bin + " help", &out) == 0);
    for (const sepal::Command& c : sepal::commands()) CHECK(contains(out, c.name));
    CHECK(sepal_test::run(bin, &out) == 2);  // no command: the list, on stderr, exit 2
    CHECK(contains(out, "bake-scene"));
    CHECK(sepal_test::run(bin + " frobnicate", &out) == 2);
    CHECK(sepal_test::run_cmd("factor", {"lambert", "--res", "0"}, &out) == 2);
    CHECK_MESSAGE(contains(out, "sepal factor: --res: Value 0 not in range 1 to 256"), out);
    CHECK_MESSAGE(contains(out, "run 'sepal factor --help'"), out);
    CHECK(sepal_test::run_cmd("eval", {"lambert", "nan", "0", "0", "0"}, &out) == 2);
    CHECK_MESSAGE(contains(out, "theta_i: 'nan' is not a finite number"), out);
    CHECK(sepal_test::run_cmd("bake", {"lambert", "-o", "x.sepal", "--cap", "-1"}, &out) == 2);
    CHECK_MESSAGE(contains(out, "--cap: -1 is not > 0"), out);
    // A repeated --light takes one value each: the positional after it stays the input.
    REQUIRE(sepal_test::run(bin + " render --light point:1,2,3 lambert --light dir:0,0,1 --size 8x8 -o " +
                                sepal_test::temp_dir() + "/l.png",
                            &out) == 0);
    CHECK(contains(out, "backend    exact"));
}
