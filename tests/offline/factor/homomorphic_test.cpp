// Homomorphic factorization (factor/homomorphic.h): recovery of an exactly separable
// p(wi) q(h) p(wo), reciprocity, the smoothness term, determinism, refusals, and the
// factor_brdf / `sepal factor` paths (raw Cornell samples and dense samples).
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "cli/cli.h"
#include "factor/factor.h"
#include "factor/homomorphic.h"
#include "factor/param.h"
#include "measured/measured.h"
#include "spec/spec.h"
#include "util/parallel.h"
#include "test_util.h"

using namespace sepal;

namespace {

glm::dvec3 random_dir(SplitMix64& r, double min_z = 0.05) {
    const double z = min_z + (1 - min_z) * r.uniform(), phi = 6.283185307179586 * r.uniform();
    const double s = std::sqrt(1 - z * z);
    return {s * std::cos(phi), s * std::sin(phi), z};
}

// Smooth positive p and q: p(w) like a Fresnel-ish rise, q(h) a broad lobe plus a floor;
// p carries a tangent-dependent ripple so the test is not rotation-symmetric.
double p_true(const glm::dvec3& w) { return 0.6 + 0.3 * (1 - w.z) * (1 - w.z) + 0.05 * w.x; }
double q_true(const glm::dvec3& h) { return 0.3 + 2.0 * std::exp(-8.0 * (1 - h.z)); }

class SeparableBrdf : public Brdf {
  public:
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override {
        if (!(wi.z > 0) || !(wo.z > 0)) return glm::dvec3(0);
        const double v = p_true(wi) * q_true(glm::normalize(wi + wo)) * p_true(wo);
        return glm::dvec3(1.0, 0.7, 0.4) * v;
    }
    std::string spec() const override { return "test-separable"; }
    std::string model() const override { return "test-separable"; }
    std::string info() const override { return spec(); }
    bool isotropic() const override { return false; }
};

std::vector<BrdfSample> scattered(const Brdf& b, int count, uint64_t seed, double min_z = 0.05) {
    SplitMix64 r(seed);
    std::vector<BrdfSample> s;
    for (int i = 0; i < count; ++i) {
        const glm::dvec3 wi = random_dir(r, min_z), wo = random_dir(r, min_z);
        s.push_back({wi, wo, b.eval(wi, wo)});
    }
    return s;
}

// Relative RMS of the fit against f at held-out random pairs (all channels).
double held_out_error(const Factored& f, const Brdf& b, uint64_t seed, double min_z = 0.1) {
    SplitMix64 r(seed);
    double num = 0, den = 0;
    for (int i = 0; i < 4000; ++i) {
        const glm::dvec3 wi = random_dir(r, min_z), wo = random_dir(r, min_z);
        const glm::dvec3 d = evaluate(f, wi, wo) - b.eval(wi, wo), v = b.eval(wi, wo);
        num += glm::dot(d, d), den += glm::dot(v, v);
    }
    return std::sqrt(num / den);
}

Factored fit_ok(const std::vector<BrdfSample>& s, const HomomorphicOptions& o, HomomorphicStats* st = nullptr) {
    Factored f;
    std::string err;
    const bool ok = factor_homomorphic(s, o, &f, st, &err);
    INFO(err);
    REQUIRE(ok);
    return f;
}

// p and q given as texels: f = exp(bilinear log P(wi) + bilinear log Q(h) + bilinear log
// P(wo)), GL_LINEAR's weights on the logs. Exactly the fit's model, so its solution is the
// truth up to the one free constant.
class GridBrdf : public Brdf {
  public:
    explicit GridBrdf(int n) : lp_(n, 1), lq_(n, 1) {
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double u = (i + 0.5) / n, v = (j + 0.5) / n;
                lp_.at(i, j, 0) = float(0.3 * std::sin(3 * u) + 0.2 * v * v);
                lq_.at(i, j, 0) = float(1.5 * std::exp(-12 * ((u - 0.5) * (u - 0.5) + (v - 0.5) * (v - 0.5))) - 0.4 * u);
            }
    }
    double log_p(const glm::dvec3& w) const { return look(lp_, w); }
    double log_q(const glm::dvec3& h) const { return look(lq_, h); }
    const FactorTexture& lp() const { return lp_; }
    const FactorTexture& lq() const { return lq_; }
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override {
        if (!(wi.z > 0) || !(wo.z > 0)) return glm::dvec3(0);
        return glm::dvec3(std::exp(log_p(wi) + log_q(glm::normalize(wi + wo)) + log_p(wo)));
    }
    std::string spec() const override { return "test-grid"; }
    std::string model() const override { return "test-grid"; }
    std::string info() const override { return spec(); }
    bool isotropic() const override { return false; }

  private:
    static double look(const FactorTexture& t, const glm::dvec3& w) {
        double v;
        bilinear_lookup(t, map_forward(HemiMap::Parabolic, w), false, &v);
        return v;
    }
    FactorTexture lp_, lq_;
};

}  // namespace

TEST_CASE("homomorphic: an exactly separable p(wi) q(h) p(wo) is recovered") {
    HomomorphicOptions o;
    o.res = 32;
    o.isotropic = false;
    o.weight_exponent = 0;  // the paper's plain log fit
    o.smoothness = 1e-3;    // exact data: the smoothness only has to fill unreached texels
    SUBCASE("texels given: the log fit returns them (dense samples)") {
        const GridBrdf b(o.res);
        std::vector<BrdfSample> s;
        std::string err;
        REQUIRE(homomorphic_dense_samples(b, o.res, 8, &s, &err));
        HomomorphicStats st;
        const Factored f = fit_ok(s, o, &st);
        CHECK(f.form == Form::Reciprocal);
        CHECK(f.param == Param::ViewHalf);
        CHECK(f.map == HemiMap::Parabolic);
        CHECK(f.non_negative());
        // log p^ - log p = c and log q^ - log q = -2c at every texel some sample reaches
        // (the one free constant); compared inside the disk, away from its rim.
        double c = 0, worst = 0;
        int count = 0;
        for (int j = 0; j < o.res; ++j)
            for (int i = 0; i < o.res; ++i) {
                const glm::dvec2 uv((i + 0.5) / o.res, (j + 0.5) / o.res);
                if (glm::length(uv - glm::dvec2(0.5)) > 0.42) continue;
                c += std::log(f.terms[0].g.at(i, j, 0)) - b.lp().at(i, j, 0);
                ++count;
            }
        c /= count;
        for (int j = 0; j < o.res; ++j)
            for (int i = 0; i < o.res; ++i) {
                const glm::dvec2 uv((i + 0.5) / o.res, (j + 0.5) / o.res);
                if (glm::length(uv - glm::dvec2(0.5)) > 0.42) continue;
                worst = std::max(worst, std::fabs(std::log(f.terms[0].g.at(i, j, 0)) - b.lp().at(i, j, 0) - c));
                worst = std::max(worst, std::fabs(std::log(f.terms[0].h.at(i, j, 0)) - b.lq().at(i, j, 0) + 2 * c));
            }
        MESSAGE("grid truth: largest texel log error " << worst << ", log rms " << st.log_rms);
        CHECK(worst < 1e-4);
        CHECK(st.log_rms < 1e-4);
    }
    SUBCASE("smooth p and q: within the interpolation error of the maps") {
        const SeparableBrdf b;
        std::vector<BrdfSample> dense;
        std::string err;
        REQUIRE(homomorphic_dense_samples(b, o.res, 8, &dense, &err));
        const double e_dense = held_out_error(fit_ok(dense, o), b, 7);
        const double e_scattered = held_out_error(fit_ok(scattered(b, 40000, 3), o), b, 8);
        MESSAGE("smooth truth at 32 x 32: held-out relative RMS " << e_dense << " (dense), " << e_scattered
                                                                  << " (scattered)");
        CHECK(e_dense < 1e-2);
        CHECK(e_scattered < 1e-2);
        // Luminance mode: one channel and the colour ratio (1, 0.7, 0.4) / luminance.
        HomomorphicOptions lum = o;
        lum.colour = ColourMode::Luminance;
        const Factored g = fit_ok(scattered(b, 40000, 3), lum);
        CHECK(g.channels == 1);
        CHECK(held_out_error(g, b, 8) < 1e-2);
    }
}

TEST_CASE("homomorphic: the result is reciprocal") {
    const SeparableBrdf b;
    HomomorphicOptions o;
    o.res = 16;
    o.isotropic = false;
    // Fit data that is NOT reciprocal: f(wi, wo) * (1 + 0.5 wi.x); the model stays reciprocal.
    std::vector<BrdfSample> s = scattered(b, 5000, 11);
    for (BrdfSample& x : s) x.value *= 1 + 0.5 * x.wi.x;
    const Factored f = fit_ok(s, o);
    SplitMix64 r(5);
    double worst = 0;
    for (int i = 0; i < 2000; ++i) {
        const glm::dvec3 wi = random_dir(r), wo = random_dir(r);
        const glm::dvec3 a = evaluate(f, wi, wo), c = evaluate(f, wo, wi);
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::fabs(a[k] - c[k]) / std::max(1e-30, std::fabs(a[k])));
    }
    CHECK(worst < 1e-12);
}

TEST_CASE("homomorphic: the smoothness term fills texels no sample reaches") {
    const SeparableBrdf b;
    HomomorphicOptions o;
    o.res = 32;
    o.isotropic = false;
    // Every direction (wi, wo and so h) has x > 0.2: the x < 0 half of both textures is
    // never sampled.
    std::vector<BrdfSample> s;
    SplitMix64 r(21);
    while (s.size() < 6000) {
        const glm::dvec3 wi = random_dir(r), wo = random_dir(r);
        if (wi.x > 0.2 && wo.x > 0.2) s.push_back({wi, wo, b.eval(wi, wo)});
    }
    HomomorphicStats st;
    const Factored f = fit_ok(s, o, &st);
    CHECK(st.unreached_p > 200);
    CHECK(st.unreached_q > 200);
    const FactorTexture& p = f.terms[0].g;
    double lo = 1e30, hi = 0;  // range of the sampled half
    for (int j = 0; j < o.res; ++j)
        for (int i = o.res / 2 + 4; i < o.res; ++i) lo = std::min(lo, double(p.at(i, j, 0))), hi = std::max(hi, double(p.at(i, j, 0)));
    double worst_step = 0;
    for (int j = 0; j < o.res; ++j)
        for (int i = 0; i < o.res / 2; ++i) {
            const double v = p.at(i, j, 0);
            REQUIRE(std::isfinite(v));
            CHECK(v >= 0.5 * lo);
            CHECK(v <= 2.0 * hi);
            worst_step = std::max(worst_step, std::fabs(std::log(p.at(i + 1, j, 0) / v)));
        }
    MESSAGE("unreached p " << st.unreached_p << ", q " << st.unreached_q << ", largest log step " << worst_step);
    CHECK(worst_step < 0.1);  // smooth: no texel-to-texel jump above 10%
    // Where the samples are, the fit still holds.
    double num = 0, den = 0;
    for (const BrdfSample& x : s) {
        const glm::dvec3 d = evaluate(f, x.wi, x.wo) - x.value;
        num += glm::dot(d, d), den += glm::dot(x.value, x.value);
    }
    CHECK(std::sqrt(num / den) < 2e-2);
}

TEST_CASE("homomorphic: deterministic, whatever the thread count") {
    const SeparableBrdf b;
    HomomorphicOptions o;
    o.res = 16;
    const std::vector<BrdfSample> s = scattered(b, 3000, 4);
    o.threads = 1;
    const Factored a = fit_ok(s, o);
    o.threads = 3;
    const Factored c = fit_ok(s, o);
    CHECK(a.terms[0].g.data == c.terms[0].g.data);
    CHECK(a.terms[0].h.data == c.terms[0].h.data);
}

TEST_CASE("homomorphic: bad input is refused with a message") {
    HomomorphicOptions o;
    o.res = 8;
    Factored f;
    std::string err;
    CHECK_FALSE(factor_homomorphic({}, o, &f, nullptr, &err));
    CHECK(err.find("no samples") != std::string::npos);
    const glm::dvec3 up(0, 0, 1), slant = glm::normalize(glm::dvec3(0.3, 0, 1));
    std::vector<BrdfSample> s = {{up, slant, glm::dvec3(0.1)}, {slant, up, glm::dvec3(NAN, 0.1, 0.1)}};
    CHECK_FALSE(factor_homomorphic(s, o, &f, nullptr, &err));
    CHECK(err.find("sample 1") != std::string::npos);
    CHECK(err.find("non-finite") != std::string::npos);
    s[1].value = glm::dvec3(INFINITY);
    CHECK_FALSE(factor_homomorphic(s, o, &f, nullptr, &err));
    s[1].value = glm::dvec3(-0.1);
    CHECK_FALSE(factor_homomorphic(s, o, &f, nullptr, &err));
    CHECK(err.find("negative") != std::string::npos);
    s[1].value = glm::dvec3(0.1);
    s[1].wi = glm::dvec3(0, 0, 2);
    CHECK_FALSE(factor_homomorphic(s, o, &f, nullptr, &err));
    CHECK(err.find("unit") != std::string::npos);
    const std::vector<BrdfSample> below = {{glm::dvec3(0, 0, -1), up, glm::dvec3(0.1)}};
    CHECK_FALSE(factor_homomorphic(below, o, &f, nullptr, &err));
    CHECK(err.find("horizon") != std::string::npos);
    o.res = 24;
    CHECK_FALSE(factor_homomorphic({{up, up, glm::dvec3(1)}}, o, &f, nullptr, &err));
    CHECK(err.find("power of two") != std::string::npos);
    // An all-zero channel is not an error: its factors are exactly 0.
    o.res = 8;
    const Factored z = fit_ok({{up, slant, glm::dvec3(0.2, 0, 0.1)}, {slant, up, glm::dvec3(0.3, 0, 0.1)}}, o);
    for (float v : z.terms[0].g.data) CHECK(std::isfinite(v));
    CHECK(evaluate(z, up, slant).y == 0.0);
}

TEST_CASE("homomorphic: factor_brdf takes raw Cornell samples or dense ones") {
    std::string err;
    const auto cornell = make_brdf(sepal_test::source_path("fixtures/cornell/garnet_red.brdf"), &err);
    REQUIRE(cornell);
    std::vector<BrdfSample> raw;
    REQUIRE(cornell->scattered_samples(&raw));
    CHECK(raw.size() > 1000);
    FactorOptions o;
    o.method = Method::Homomorphic;
    o.param = Param::ViewHalf;
    o.map = HemiMap::Parabolic;
    o.res = 16;
    FactorResult r;
    REQUIRE(factor_brdf(*cornell, o, &r, &err));
    CHECK(r.factored.form == Form::Reciprocal);
    CHECK(r.notes.at(0).find("raw scattered") != std::string::npos);
    CHECK(r.evaluations == 0);  // the table was never looked up
    o.samples = FactorOptions::Samples::Dense;
    REQUIRE(factor_brdf(*cornell, o, &r, &err));
    CHECK(r.notes.at(0).find("dense") != std::string::npos);
    CHECK(r.evaluations > 0);
    // An analytic model has no raw samples; gs-half is not the model's parameterization.
    const SeparableBrdf b;
    o.samples = FactorOptions::Samples::Raw;
    CHECK_FALSE(factor_brdf(b, o, &r, &err));
    CHECK(err.find("--samples raw") != std::string::npos);
    o.samples = FactorOptions::Samples::Auto;
    o.param = Param::GsHalf;
    CHECK_FALSE(factor_brdf(b, o, &r, &err));
    CHECK(err.find("--param vh --map parabolic") != std::string::npos);
}

TEST_CASE("homomorphic: sepal factor --method homomorphic") {
    const std::string spec = sepal_test::source_path("fixtures/cornell/krylon_blue.brdf");
    std::string out;
    const int code = sepal_test::run_cmd("factor", {spec, "--method", "homomorphic", "--res", "16"}, &out);
    INFO(out);
    CHECK(code == 0);
    CHECK(out.find("vh, parabolic map, 16 x 16 texels, homomorphic") != std::string::npos);
    CHECK(out.find("raw scattered") != std::string::npos);
    // Format 2.1's bounds: 64 texels a side, 2 terms.
    CHECK(sepal_test::run_cmd("factor", {spec, "--method", "homomorphic", "--res", "128"}, &out) == 2);
    CHECK(out.find("at most --res 64") != std::string::npos);
}
