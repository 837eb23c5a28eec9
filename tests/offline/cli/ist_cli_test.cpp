// sepal ist (offline/cli/cmd_ist.cpp): each subcommand's --help lists its flags; bad usage
// exits 2 naming what is wrong; generate -> decompose -> edit -> render end to end, small.
#include <doctest/doctest.h>

#include <CLI/CLI.hpp>

#include "cli/cli.h"
#include "test_util.h"
#include "util/image.h"
#include "util/io.h"

namespace {
bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }
int ist(const std::vector<std::string>& args, std::string* out) { return sepal_test::run_cmd("ist", args, out); }
}  // namespace

TEST_CASE("ist cli: every subcommand's --help lists its flags") {
    std::vector<sepal::CommandRun> runs;
    std::unique_ptr<CLI::App> app = sepal::make_sepal_app(&runs);
    const CLI::App* cmd = app->get_subcommand("ist");
    int subs = 0;
    for (const CLI::App* sub : cmd->get_subcommands([](const CLI::App*) { return true; })) {
        CAPTURE(sub->get_name());
        std::string help;
        REQUIRE(ist({sub->get_name(), "--help"}, &help) == 0);
        for (const CLI::Option* opt : sub->get_options()) {
            CHECK(!opt->get_description().empty());
            for (const std::string& l : opt->get_lnames()) CHECK_MESSAGE(contains(help, "--" + l), help);
        }
        ++subs;
    }
    CHECK(subs == 4);
}

TEST_CASE("ist cli: bad usage exits 2 and says what") {
    std::string out;
    CHECK(ist({}, &out) == 2);
    CHECK(ist({"frobnicate"}, &out) == 2);
    CHECK(contains(out, "generate"));
    CHECK(ist({"generate"}, &out) == 2);  // -o is required
    CHECK(contains(out, "--output"));
    CHECK(ist({"generate", "-o", "x", "--materials", "9"}, &out) == 2);
    CHECK(contains(out, "--materials"));
    CHECK(ist({"generate", "-o", "x", "--noise", "nan"}, &out) == 2);
    CHECK(ist({"decompose", "/no/such/svbrdf", "-o", "t"}, &out) == 2);
    CHECK(contains(out, "sepal ist decompose: "));
    CHECK(ist({"decompose", "d", "-o", "t", "--method", "svd"}, &out) == 2);
    CHECK(contains(out, "--method"));
    // The library takes 1..8 terms: the flags say so themselves (they took 0..16).
    CHECK(ist({"decompose", "d", "-o", "t", "--terms", "9"}, &out) == 2);
    CHECK(contains(out, "--terms"));
    CHECK(ist({"decompose", "d", "-o", "t", "--max-terms", "9"}, &out) == 2);
    CHECK(contains(out, "--max-terms"));
    CHECK(ist({"render", "/no/such/tree", "-o", "x.png", "--backend", "gles7"}, &out) == 2);
    CHECK(contains(out, "--backend"));
    CHECK(ist({"render", "/no/such/tree", "-o", "x.png"}, &out) == 2);
    CHECK(contains(out, "sepal ist render: "));
    CHECK(ist({"edit", "/no/such/tree", "--swap", "0=lambert"}, &out) == 2);
}

TEST_CASE("ist cli: generate, decompose, edit and render a small SVBRDF") {
    const std::string dir = sepal_test::temp_dir();
    const std::string svbrdf = dir + "/card", tree = dir + "/card.tree", edited = dir + "/edited.tree";
    std::string out;
    REQUIRE_MESSAGE(ist({"generate", "-o", svbrdf, "--size", "12", "--materials", "2", "--seed", "3"}, &out) == 0, out);
    CHECK(contains(out, "12x12 texels"));
    REQUIRE_MESSAGE(ist({"decompose", svbrdf, "-o", tree, "--terms", "2", "--res", "16"}, &out) == 0, out);
    CHECK(contains(out, "sacls, 2 terms"));
    // Edits: a bad basis index, a bad spec, then a good swap into a new folder.
    CHECK(ist({"edit", tree, "--swap", "5=lambert"}, &out) == 2);
    CHECK(contains(out, "0..1"));
    CHECK(ist({"edit", tree, "--swap", "0=no-such-model"}, &out) == 2);
    CHECK(ist({"edit", tree}, &out) == 2);
    REQUIRE_MESSAGE(ist({"edit", tree, "--swap", "0=lambert:rho=0.3/0.6/0.2", "-o", edited}, &out) == 0, out);
    for (const char* backend : {"exact", "cpu"}) {
        CAPTURE(backend);
        const std::string png = dir + "/" + backend + ".png";
        REQUIRE_MESSAGE(ist({"render", edited, "-o", png, "--backend", backend, "--size", "32x32"}, &out) == 0, out);
        sepal::Image img;
        std::string err;
        REQUIRE_MESSAGE(sepal::read_png(png, &img, &err), err);
        CHECK(img.width == 32);
        double sum = 0;
        for (float v : img.data) sum += v;
        CHECK(sum > 0);  // something lit
    }
}
