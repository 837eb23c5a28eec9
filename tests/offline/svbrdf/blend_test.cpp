// The SVBRDF model (svbrdf/blend.h): weights between texels, evaluation, rendering, refusals.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "reference/render_exact.h"
#include "svbrdf/blend.h"
#include "util/image.h"

using namespace sepal;

TEST_CASE("svbrdf blend: weights between texel centres are bilinear and repeat; both samplers agree") {
    BlendMaps m;
    m.width = 3;
    m.height = 2;
    m.count = 2;
    for (int t = 0; t < 6; ++t) m.w.insert(m.w.end(), {float(t) / 5, 1 - float(t) / 5});
    float all[2];
    for (double u : {0.0, 1 / 6.0, 0.3, 0.5, 0.99})
        for (double v : {0.0, 0.25, 0.6, 0.75}) {
            m.sample_all(u, v, all);
            for (int j = 0; j < 2; ++j) CHECK(all[j] == doctest::Approx(m.sample(j, u, v)).epsilon(1e-6));
        }
    CHECK(m.sample(0, 1 / 6.0, 0.25) == doctest::Approx(0.0));       // texel (0, 0)'s centre
    CHECK(m.sample(0, 5 / 6.0, 0.75) == doctest::Approx(1.0));       // texel (2, 1)'s centre
    CHECK(m.sample(0, 0.0, 0.25) == doctest::Approx((0.0 + 0.4) / 2));  // halfway to texel (2, 0) across the border
}

TEST_CASE("svbrdf blend: a texel evaluates its weighted bases; bad bases and sizes are refused") {
    BlendMaps m;
    m.width = m.height = 1;
    m.count = 2;
    m.w = {0.25f, 0.75f};
    BlendSvbrdf s;
    std::string err;
    REQUIRE_MESSAGE(make_blend_svbrdf(m, {"lambert:rho=0.8", "lambert:rho=0.4"}, &s, &err), err);
    const glm::dvec3 wi(0, 0, 1), wo(0.6, 0, 0.8);
    const glm::dvec3 f = s.eval(0, wi, wo);
    CHECK(f.x == doctest::Approx((0.25 * 0.8 + 0.75 * 0.4) / M_PI));
    CHECK(s.eval(glm::dvec2(0.3, 0.9), wi, wo).x == doctest::Approx(f.x));
    CHECK_FALSE(make_blend_svbrdf(m, {"lambert", "no-such-model"}, &s, &err));
    CHECK(err.find("no-such-model") != std::string::npos);
    CHECK_FALSE(make_blend_svbrdf(m, {"lambert"}, &s, &err));  // two maps, one basis
    CHECK(err.find("1 bases for 2 weight maps") != std::string::npos);
    m.w.pop_back();
    CHECK_FALSE(make_blend_svbrdf(m, {"lambert", "lambert"}, &s, &err));
}

TEST_CASE("svbrdf blend: one that does not vary renders exactly as its BRDF, and its maps show") {
    sepal_scene sc;
    sepal_scene_default(&sc);
    const float eye[3] = {0.0f, -1.9f, 2.3f};  // above the wave, which lies in the xy plane
    std::copy(eye, eye + 3, sc.camera.eye);
    std::vector<sepal_vertex> v(size_t(33 * 33));
    std::vector<uint16_t> idx(size_t(32 * 32 * 6));
    sepal_mesh mesh = {v.data(), idx.data(), int(v.size()), int(idx.size())};
    sepal_error e = {};
    REQUIRE(sepal_mesh_wave(32, &mesh, &e) == SEPAL_OK);
    std::string err;
    BlendMaps one;
    one.width = one.height = 2;
    one.count = 2;
    one.w = {1, 0, 1, 0, 0, 1, 0, 1};  // top row basis 0, bottom row basis 1
    BlendSvbrdf same, split;
    REQUIRE_MESSAGE(make_blend_svbrdf(one, {"lambert:rho=0.8", "lambert:rho=0.8"}, &same, &err), err);
    Image a, b;
    REQUIRE(render_exact_spatial(same, sc, mesh, 48, 48, &a, nullptr, &err));
    REQUIRE(render_exact(*same.basis[0], sc, mesh, 48, 48, &b, nullptr, &err));
    REQUIRE(a.data.size() == b.data.size());
    double worst = 0;
    for (size_t i = 0; i < a.data.size(); ++i) worst = std::max(worst, double(std::fabs(a.data[i] - b.data[i])));
    CHECK(worst < 1e-6);
    CHECK(*std::max_element(b.data.begin(), b.data.end()) > 0.05f);  // the wave is in view and lit
    REQUIRE_MESSAGE(make_blend_svbrdf(one, {"lambert:rho=0.8", "lambert:rho=0.1"}, &split, &err), err);
    Image s;
    REQUIRE(render_exact_spatial(split, sc, mesh, 48, 48, &s, nullptr, &err));
    CHECK(s.data != b.data);
}
