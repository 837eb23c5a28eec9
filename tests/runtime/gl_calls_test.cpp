// GL calls per frame on GL ES 1.1 (no redundant state changes), counted by
// tests/gl_counter.h around one sepal_draw: the passes of a plan share their combiner set-up,
// so only the first sets the texture environment, and each further pass costs a bounded
// number of calls.
#include <doctest/doctest.h>

#include <memory>
#include <vector>

#include "bake/asset_file.h"
#include "bake/bake.h"
#include "brdf/brdf.h"
#include "common/scene_draw.h"
#include "common/scene_flags.h"
#include "gl_counter.h"
#include "headless/sepal_headless.h"
#include "material_fixtures.h"
#include "sepal/sepal_material.h"

namespace {

struct FrameCalls {
    long total = 0, tex_env = 0, passes = 0;
    std::string by_name;
};

// A non-negative `terms`-term product plan (factors of f: no diffuse pass), drawn once to
// warm up and once counted.
FrameCalls count_frame(int terms, const sepal_caps& caps, const sepal_ports::SceneSetup& s) {
    const std::vector<uint8_t> bytes = material_fx::encode(
        material_fx::bake_small("blinn:n=40", sepal::Param::GsHalf, sepal::Method::ACLS, terms, false, 16, 16));
    auto asset = std::make_unique<sepal_asset>();
    auto mat = std::make_unique<sepal_material>();
    sepal_error e = {};
    REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), asset.get(), &e) == SEPAL_OK);
    REQUIRE_MESSAGE(sepal_material_create(&caps, asset.get(), s.width, s.height, mat.get(), &e) == SEPAL_OK, e.message);
    std::vector<float> scratch;
    const sepal_draw_desc d = sepal_ports::scene_draw_desc(mat.get(), s, SEPAL_MODE_MULTIPASS, &scratch);
    sepal_draw_stats stats = {};
    REQUIRE_MESSAGE(sepal_draw(&d, &stats, &e) == SEPAL_OK, e.message);
    sepal_test::gl_counts_reset();
    sepal_test::gl_counting(true);
    const sepal_result res = sepal_draw(&d, &stats, &e);
    sepal_test::gl_counting(false);
    REQUIRE_MESSAGE(res == SEPAL_OK, e.message);
    FrameCalls c;
    c.total = sepal_test::gl_calls_total();
    c.tex_env = sepal_test::gl_calls("glTexEnvi");
    c.passes = stats.draw_calls;
    c.by_name = sepal_test::gl_calls_by_name();
    sepal_material_destroy(mat.get());
    return c;
}

}  // namespace

TEST_CASE("GL ES 1.1: a plan's passes share their combiner set-up; each further pass costs at most 22 GL calls") {
    sepal_headless_desc hd = {};
    hd.width = hd.height = 64;
    hd.gles_version = 1;
    char msg[512];
    sepal_headless_context* ctx = sepal_headless_create(&hd, msg, sizeof msg);
    REQUIRE_MESSAGE(ctx, msg);
    sepal_caps caps;
    sepal_error e = {};
    REQUIRE(sepal_query_caps(1, 0, sepal_headless_get_proc_address, &caps, &e) == SEPAL_OK);
    sepal_ports::SceneSetup s;
    s.width = s.height = 64;
    std::string err;
    REQUIRE_MESSAGE(sepal_ports::load_scene_mesh(&s, &err), err);
    const FrameCalls one = count_frame(1, caps, s), four = count_frame(4, caps, s);
    MESSAGE("1 term: " << one.total << " calls, " << one.passes << " mesh passes (" << one.by_name << ")");
    MESSAGE("4 terms: " << four.total << " calls, " << four.passes << " mesh passes (" << four.by_name << ")");
    CHECK(one.total > 0);  // the counter sees the runtime's calls
    // The plan's passes and nothing else: the first pass lays depth, no pre-pass.
    CHECK(one.passes == 1);
    CHECK(four.passes == one.passes + 3);
    // The same two combiner stages for every product pass: set once per frame (before the
    // cache, every pass set them again: 20 more calls each).
    CHECK(four.tex_env == one.tex_env);
    CHECK(four.total - one.total <= 3 * 22);  // measured 64 (glGetError, arrays, units, blend per pass)
    sepal_headless_destroy(ctx);
}
