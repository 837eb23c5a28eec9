// sample_relative_rms: the off-peak error at measured samples (docs/homomorphic.md's metric),
// by hand on a few samples, and its Factored form against its function form.
#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "brdf/brdf.h"
#include "spec/spec.h"
#include "factor/factor.h"
#include "factor/factor_error.h"

using namespace sepal;

namespace {

glm::dvec3 dir(double theta_deg, double phi_deg) {
    const double t = theta_deg * 3.14159265358979323846 / 180, p = phi_deg * 3.14159265358979323846 / 180;
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

BrdfSample sample(const glm::dvec3& wi, const glm::dvec3& wo, double v) {
    BrdfSample s;
    s.wi = wi, s.wo = wo, s.value = glm::dvec3(v);
    return s;
}

}  // namespace

TEST_CASE("factor/sample_relative_rms: by hand, the peak's cone left out, a cap's floor") {
    // Grey values, so luminance = the value. Off-peak pairs (half angle 20-45 deg) and one
    // mirror pair (half angle 0).
    const std::vector<BrdfSample> s = {sample(dir(60, 0), dir(20, 0), 2.0), sample(dir(30, 0), dir(60, 90), 0.5),
                                       sample(dir(40, 0), dir(40, 180), 9.0)};
    auto exact = [&](const glm::dvec3& wi, const glm::dvec3& wo) {
        for (const BrdfSample& x : s)
            if (glm::length(x.wi - wi) < 1e-12 && glm::length(x.wo - wo) < 1e-12) return x.value * wi.z;
        return glm::dvec3(0);
    };
    CHECK(sample_relative_rms(exact, s, 5.0, false) == doctest::Approx(0.0));
    // Twice everything: a relative error of 1 whatever the weights.
    auto twice = [&](const glm::dvec3& wi, const glm::dvec3& wo) { return 2.0 * exact(wi, wo); };
    CHECK(sample_relative_rms(twice, s, 5.0, false) == doctest::Approx(1.0));
    CHECK(sample_relative_rms(twice, s, 5.0, true) == doctest::Approx(1.0));
    // Wrong only at the mirror pair: off-peak (>= 5 deg) sees nothing, all samples (0 deg) do.
    auto wrong_peak = [&](const glm::dvec3& wi, const glm::dvec3& wo) {
        return wi.z > 0.76 && wi.z < 0.77 && wo.z > 0.76 ? glm::dvec3(0) : exact(wi, wo);
    };
    CHECK(sample_relative_rms(wrong_peak, s, 5.0, false) == doctest::Approx(0.0));
    const double b0 = 2.0 * 0.5, b1 = 0.5 * std::cos(0.5236), b2 = 9.0 * std::cos(0.6981);
    CHECK(sample_relative_rms(wrong_peak, s, 0.0, false) ==
          doctest::Approx(std::sqrt(b2 * b2 / (b0 * b0 + b1 * b1 + b2 * b2))).epsilon(1e-3));
    // Capped at 0.5 (f cos theta_i): only the first off-peak pair (1.0) is above it.
    auto capped = [&](const glm::dvec3& wi, const glm::dvec3& wo) { return glm::min(exact(wi, wo), glm::dvec3(0.5)); };
    CHECK(sample_relative_rms(capped, s, 5.0, false) ==
          doctest::Approx(std::sqrt(0.5 * 0.5 / (b0 * b0 + b1 * b1))).epsilon(1e-3));
    // No sample off the peak: 0, not a division by zero.
    CHECK(sample_relative_rms(exact, {s[2]}, 5.0, false) == 0.0);
}

TEST_CASE("factor/sample_relative_rms: a Factored is measured as its f~ cos theta_i") {
    std::string err;
    std::unique_ptr<Brdf> b = make_brdf("blinn", &err);
    REQUIRE(b);
    FactorOptions o;
    o.res = 8, o.terms = 1, o.threads = 1;
    FactorResult r;
    REQUIRE(factor_brdf(*b, o, &r, &err));
    std::vector<BrdfSample> s;
    for (int i = 0; i < 40; ++i) s.push_back(sample(dir(5 + 2 * i, 9 * i), dir(80 - 1.5 * i, 200 - 7 * i), 0.3 + 0.01 * i));
    const Factored& f = r.factored;
    const double by_factored = sample_relative_rms(f, s, 5.0, false);
    const double by_function = sample_relative_rms(
        [&](const glm::dvec3& wi, const glm::dvec3& wo) { return evaluate_radiance(f, wi, wo); }, s, 5.0, false);
    CHECK(by_factored == by_function);
    CHECK(by_factored > 0);
}
