// `sepal measure plan | simulate | reconstruct`: the whole loop in-process on a 3-material
// database on the MERL grid (the database tests' cache), and what bad input gets.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "cli/cli.h"
#include "measured/merl.h"
#include "util/io.h"
#include "test_util.h"

namespace {
const std::string kMaterials = "gold-paint,dark-red-paint,white-fabric";

int measure(const std::vector<std::string>& args, std::string* out = nullptr) {
    return sepal_test::run_cmd("measure", args, out);
}
}  // namespace

TEST_CASE("sepal measure: plan, simulate and reconstruct a material left out of the database") {
    const std::string dir = sepal_test::temp_dir();
    const std::string plan = dir + "/plan.json", samples = dir + "/samples.csv", merl = dir + "/new.binary",
                      report = dir + "/r.json";
    std::string out;
    REQUIRE(measure({"plan", "--samples", "40", "-o", plan, "--materials", kMaterials, "--exclude", "gold-paint"},
                    &out) == 0);
    CHECK(out.find("condition") != std::string::npos);
    CHECK(out.find("a random plan of the same size") != std::string::npos);
    REQUIRE(measure({"simulate", "nbrdf:gold-paint", plan, "-o", samples, "--noise", "0.01", "--materials",
                     kMaterials},
                    &out) == 0);
    CHECK(out.find("simulated  40 samples of nbrdf:gold-paint") != std::string::npos);
    REQUIRE(measure({"reconstruct", plan, samples, "-o", merl, "--materials", kMaterials, "--truth",
                     "nbrdf:gold-paint", "--report", report},
                    &out) == 0);
    INFO(out);
    CHECK(out.find("log-space combination of 2 database materials") != std::string::npos);
    CHECK(out.find("relative RMS against nbrdf:gold-paint") != std::string::npos);
    // Judged by the picture first: the default scene, then the held-out conditions.
    CHECK(out.find("picture    default scene") != std::string::npos);
    CHECK(out.find("mean Delta E") != std::string::npos);
    sepal::Tabulated t;
    sepal::MerlStats st;
    std::string err;
    CHECK_MESSAGE(sepal::read_merl(merl, &t, &st, &err), err);
    std::vector<uint8_t> r;
    REQUIRE(sepal::read_file(report, &r, &err));
    const std::string rs(r.begin(), r.end());
    CHECK(rs.find("\"excluded\"") != std::string::npos);
    CHECK(rs.find("\"gold-paint\"") != std::string::npos);  // excluded through the plan
    CHECK(rs.find("\"relative_rms_vs_truth\"") != std::string::npos);
    CHECK(rs.find("\"mean_delta_e2000\"") != std::string::npos);
    CHECK(rs.find("\"held-out two lights\"") != std::string::npos);
    CHECK(rs.find("\"space\": \"log\"") != std::string::npos);
    // The paper's linear model on request.
    REQUIRE(measure({"reconstruct", plan, samples, "-o", merl, "--materials", kMaterials, "--space", "linear"}, &out) == 0);
    CHECK(out.find("linear combination of 2 database materials") != std::string::npos);
    CHECK(measure({"reconstruct", plan, samples, "-o", merl, "--materials", kMaterials, "--space", "cubic"}, &out) == 2);

    // The same samples against another plan are refused; so are bad flags.
    const std::string plan2 = dir + "/plan2.json";
    REQUIRE(measure({"plan", "--samples", "40", "--method", "random", "-o", plan2, "--materials", kMaterials}) == 0);
    CHECK(measure({"reconstruct", plan2, samples, "-o", merl, "--materials", kMaterials}, &out) == 2);
    CHECK(out.find("do not belong together") != std::string::npos);
    CHECK(measure({"reconstruct", plan, samples, "-o", merl, "--solver", "magic", "--materials", kMaterials}, &out) == 2);
    CHECK(out.find("--solver: magic not in {ls,nnls}") != std::string::npos);
    CHECK(measure({"plan", "--samples", "40", "-o", plan, "--method", "best", "--materials", kMaterials}, &out) == 2);
    CHECK(out.find("--method: best not in {greedy,picture,random,uniform}") != std::string::npos);
    CHECK(measure({"plan", "--samples", "40", "-o", plan, "--exclude", "nope", "--materials", kMaterials}, &out) == 2);
    CHECK(out.find("--exclude nope") != std::string::npos);
    CHECK(measure({"simulate", "nbrdf:gold-paint", plan, "-o", samples, "--noise", "2", "--materials", kMaterials},
                  &out) == 2);
    CHECK(measure({"simulate", "nosuchmodel", plan, "-o", samples}, &out) == 2);
    CHECK(measure({}, &out) == 2);
    CHECK(measure({"bogus"}, &out) == 2);
    CHECK(out.find("unknown subcommand 'bogus' (one of plan, simulate, reconstruct, capture)") != std::string::npos);
}
