// The test-SVBRDF generator (ist/generate.h): its true blends, determinism, truth files.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "ist/generate.h"
#include "spec/spec.h"
#include "test_util.h"

using namespace sepal;

TEST_CASE("ist generate: true weights are a partition of unity with real blends, bases conserve energy") {
    GenerateOptions g;
    g.width = g.height = 32;
    g.materials = 6;
    g.preset = "analytic";
    SvbrdfSamples s;
    BlendSvbrdf t;
    std::string err;
    REQUIRE_MESSAGE(generate_svbrdf(g, &s, &t, &err), err);
    REQUIRE(t.maps.count == 6);
    int blended = 0;
    std::vector<double> area(6, 0.0);
    for (int i = 0; i < s.texels(); ++i) {
        double sum = 0, top = 0;
        for (int j = 0; j < 6; ++j) {
            const double w = t.maps.at(i, j);
            CHECK(w >= 0);
            sum += w;
            top = std::max(top, w);
            area[size_t(j)] += w;
        }
        CHECK(sum == doctest::Approx(1.0).epsilon(1e-6));
        blended += top < 0.95;
    }
    for (double a : area) CHECK(a > 0.02 * s.texels());  // every material is present
    CHECK(blended > s.texels() / 10);                    // soft transitions and halftones
    // Albedo weights: a partition of each view's hemisphere; the quadrature albedo of
    // every true basis stays at or below 1 (what the energy constraint asks of the fit).
    std::vector<double> per_view(size_t(g.views), 0.0);
    for (const DirPair& p : s.pairs) {
        CHECK(p.wi.z > 0);
        CHECK(p.wo.z > 0);
        per_view[size_t(p.view)] += p.albedo_weight;
    }
    for (double w : per_view) CHECK(w == doctest::Approx(2 * M_PI).epsilon(1e-9));
    for (const std::string& spec : t.specs) {
        std::unique_ptr<Brdf> b = make_brdf(spec, &err);
        REQUIRE(b);
        for (int v = 0; v < g.views; ++v) {
            glm::dvec3 a(0);
            for (const DirPair& p : s.pairs)
                if (p.view == v) a += p.albedo_weight * b->eval(p.wi, p.wo) * p.wi.z;
            CAPTURE(spec);
            CHECK(std::max({a.x, a.y, a.z}) <= 1.0);
        }
    }
}

TEST_CASE("ist generate: deterministic, with the requested share of missing samples and bad options refused") {
    GenerateOptions g;
    g.width = g.height = 8;
    g.views = 3;
    g.lights = 8;
    g.missing = 0.4;
    g.preset = "analytic";
    SvbrdfSamples a, b;
    std::string err;
    REQUIRE(generate_svbrdf(g, &a, nullptr, &err));
    REQUIRE(generate_svbrdf(g, &b, nullptr, &err));
    CHECK(a.values == b.values);
    CHECK(a.conf == b.conf);
    const double share = double(count_samples(a).missing) / double(count_samples(a).samples);
    CHECK(share == doctest::Approx(0.4).epsilon(0.1));
    g.seed = 2;
    REQUIRE(generate_svbrdf(g, &b, nullptr, &err));
    CHECK(a.values != b.values);

    GenerateOptions bad = g;
    bad.materials = 7;
    CHECK_FALSE(generate_svbrdf(bad, &a, nullptr, &err));
    bad = g;
    bad.preset = "nope";
    CHECK_FALSE(generate_svbrdf(bad, &a, nullptr, &err));
    CHECK(err.find("preset") != std::string::npos);
    bad = g;
    bad.bases = {"lambert", "no-such-model"};
    CHECK_FALSE(generate_svbrdf(bad, &a, nullptr, &err));
    CHECK(err.find("basis 1") != std::string::npos);
    bad = g;
    bad.missing = 1.0;
    CHECK_FALSE(generate_svbrdf(bad, &a, nullptr, &err));
    for (double h : {-0.1, 1.5, std::nan("")}) {
        bad = g;
        bad.halftone = h;
        err.clear();
        CHECK_FALSE(generate_svbrdf(bad, &a, nullptr, &err));
        CHECK(err.find("halftone") != std::string::npos);
    }
}

TEST_CASE("ist generate: an opaque halftone mixes materials only along edges") {
    // Texels whose largest true weight is under 0.95, on the default (45%) and opaque prints.
    auto blended_share = [](double halftone) {
        GenerateOptions g;
        g.width = g.height = 64;
        g.views = 1;
        g.lights = 4;
        g.lobe_lights = 0;
        g.preset = "analytic";
        g.halftone = halftone;
        SvbrdfSamples s;
        BlendSvbrdf t;
        std::string err;
        REQUIRE_MESSAGE(generate_svbrdf(g, &s, &t, &err), err);
        int blended = 0;
        for (int i = 0; i < s.texels(); ++i) {
            double top = 0;
            for (int j = 0; j < t.maps.count; ++j) top = std::max(top, double(t.maps.at(i, j)));
            blended += top < 0.95;
        }
        return double(blended) / s.texels();
    };
    const double half = blended_share(0.45), opaque = blended_share(1.0);
    CAPTURE(half);
    CAPTURE(opaque);
    CHECK(opaque < 0.7 * half);
    CHECK(opaque > 0.02);  // the edges stay soft
}

TEST_CASE("ist generate: truth files round trip and render like the SVBRDF they describe") {
    GenerateOptions g;
    g.width = g.height = 8;
    g.views = 2;
    g.lights = 6;
    g.noise = 0;
    g.misregistration = 0;
    g.preset = "analytic";
    SvbrdfSamples s;
    BlendSvbrdf t;
    std::string err;
    REQUIRE(generate_svbrdf(g, &s, &t, &err));
    const std::string dir = sepal_test::temp_dir();
    REQUIRE(write_truth(dir, t, &err));
    BlendSvbrdf r;
    REQUIRE_MESSAGE(read_truth(dir, &r, &err), err);
    CHECK(r.specs == t.specs);
    CHECK(r.names == t.names);
    CHECK(r.maps.w == t.maps.w);
    // The truth evaluated at a texel centre is the noiseless sample there.
    const BlendSvbrdf* b = &r;
    for (int texel : {0, 9, 27, 63})
        for (int p = 0; p < s.pair_count(); p += 3) {
            const glm::dvec2 uv(((texel % 8) + 0.5) / 8, ((texel / 8) + 0.5) / 8);
            const glm::dvec3 f = b->eval(uv, s.pairs[size_t(p)].wi, s.pairs[size_t(p)].wo), v = s.value(texel, p);
            CHECK(f.y == doctest::Approx(v.y).epsilon(1e-5));
        }
}
