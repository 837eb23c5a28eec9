#include <doctest/doctest.h>

#include "brdf/cie.h"

// Sharma, Wu and Dalal (2005), "The CIEDE2000 color-difference formula: implementation notes,
// supplementary test data": pairs that exercise the hue wrap-around, the achromatic case and
// the rotation term (their pairs 1, 2, 7, 8, 13, 17, 19, 25).
TEST_CASE("ciede2000 reproduces Sharma et al.'s test pairs") {
    struct Pair {
        double l1, a1, b1, l2, a2, b2, de;
    };
    const Pair pairs[] = {{50.0, 2.6772, -79.7751, 50.0, 0.0, -82.7485, 2.0425},
                          {50.0, 3.1571, -77.2803, 50.0, 0.0, -82.7485, 2.8615},
                          {50.0, 0.0, 0.0, 50.0, -1.0, 2.0, 2.3669},
                          {50.0, -1.0, 2.0, 50.0, 0.0, 0.0, 2.3669},
                          {50.0, 2.49, -0.001, 50.0, -2.49, 0.0009, 7.1792},
                          {50.0, 2.5, 0.0, 73.0, 25.0, -18.0, 27.1492},
                          {50.0, 2.5, 0.0, 50.0, 3.1736, 0.5854, 1.0000},
                          {60.2574, -34.0099, 36.2677, 60.4626, -34.1751, 39.4387, 1.2644}};
    for (const Pair& p : pairs) {
        CAPTURE(p.de);
        const double d = sepal::ciede2000({p.l1, p.a1, p.b1}, {p.l2, p.a2, p.b2});
        CHECK(d == doctest::Approx(p.de).epsilon(1e-4).scale(1.0));
        CHECK(sepal::ciede2000({p.l2, p.a2, p.b2}, {p.l1, p.a1, p.b1}) == doctest::Approx(d).epsilon(1e-9));
    }
    CHECK(sepal::ciede2000({40, 10, -5}, {40, 10, -5}) == 0.0);
}

TEST_CASE("srgb_display_to_lab: white, black, grey and a primary") {
    const glm::dvec3 w = sepal::srgb_display_to_lab({1, 1, 1});
    CHECK(w.x == doctest::Approx(100.0).epsilon(1e-4));
    CHECK(std::abs(w.y) < 0.05);
    CHECK(std::abs(w.z) < 0.05);
    const glm::dvec3 k = sepal::srgb_display_to_lab({0, 0, 0});
    CHECK(k.x == doctest::Approx(0.0).scale(1.0));
    // sRGB 0.5 is 21.4% linear: L* 53.39 (CIE 15).
    CHECK(sepal::srgb_display_to_lab({0.5, 0.5, 0.5}).x == doctest::Approx(53.39).epsilon(1e-3));
    // Pure sRGB red: L* 53.24, a* 80.09, b* 67.20 (the standard's primaries, D65).
    const glm::dvec3 r = sepal::srgb_display_to_lab({1, 0, 0});
    CHECK(r.x == doctest::Approx(53.24).epsilon(2e-3));
    CHECK(r.y == doctest::Approx(80.09).epsilon(2e-3));
    CHECK(r.z == doctest::Approx(67.20).epsilon(2e-3));
    // Out-of-range display values are clamped, not extrapolated.
    CHECK(sepal::srgb_display_to_lab({2, -1, 0}).x == doctest::Approx(r.x));
}
