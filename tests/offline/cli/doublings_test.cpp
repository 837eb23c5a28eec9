// "Doublings" means one thing in every command: the framebuffer doublings a frame draws (the
// plan's own 2^k scale and the lights' exposure together), so the bake's table, inspect and
// render agree for the same asset and scene.
#include <doctest/doctest.h>

#include <cstdlib>
#include <string>

#include "test_util.h"
#include "util/json.h"

namespace {
int after(const std::string& text, const std::string& label) {
    const size_t at = text.find(label);
    return at == std::string::npos ? -1 : std::atoi(text.c_str() + at + label.size());
}
int before(const std::string& text, const std::string& label) {
    const size_t at = text.find(label);
    if (at == std::string::npos) return -1;
    size_t b = at;
    while (b > 0 && text[b - 1] >= '0' && text[b - 1] <= '9') --b;
    return std::atoi(text.c_str() + b);
}
}  // namespace

TEST_CASE("doublings: the bake's winner, inspect and render print the same count for the default scene") {
    const std::string dir = sepal_test::temp_dir(), asset = dir + "/ct.sepal", report = dir + "/r.json";
    std::string out, err;
    // A bright lobe under the default 8:1 range: its frames need doublings.
    REQUIRE(sepal_test::run_cmd("bake", {"cook-torrance:m=0.15", "--param", "gs-half", "--res", "32", "--terms", "2",
                                         "--method", "acls", "-o", asset, "--report", report},
                                &out) == 0);
    // Each count says which frame it is of, and each PSNR what it pools.
    CHECK(out.find("dbl: framebuffer doublings of the default view's frame on gles1") != std::string::npos);
    CHECK(out.find("pooled over the training views") != std::string::npos);
    sepal::Json j;
    REQUIRE_MESSAGE(sepal::read_json_file(report, &j, &err), err);
    const int winner = j["winner"].get<int>();
    REQUIRE(winner >= 0);
    const int baked = j["candidates"][size_t(winner)]["doublings"].get<int>();
    REQUIRE(sepal_test::run_cmd("inspect", {asset}, &out) == 0);
    INFO(out);
    const int inspected = after(out, "doublings   ");
    CHECK(out.find("in the default scene's frame on gles1") != std::string::npos);
    CHECK(out.find("pooled over its training views (sepal diff: one image pair)") != std::string::npos);
    REQUIRE(sepal_test::run_cmd("render", {asset, "--backend", "gles1-model", "-o", dir + "/m.png"}, &out) == 0);
    INFO(out);
    const int rendered = before(out, " doublings");
    CHECK(out.find(" doublings in this scene's frame") != std::string::npos);
    CHECK(inspected >= 0);
    CHECK(inspected == baked);
    CHECK(rendered == inspected);
}
