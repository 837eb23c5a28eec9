// Measured data: CIE conversion, the (theta_h, theta_d, phi_d) table and push-pull.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include <glm/geometric.hpp>

#include "cie.h"
#include "tabulated.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

glm::dvec3 dir(double theta, double phi) {
    return glm::dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                      std::cos(theta));
}

bool contains(const std::string& s, const std::string& part) {
    return s.find(part) != std::string::npos;
}

}  // namespace

// ---- CIE -----------------------------------------------------------------------------------

TEST_CASE("measured: CIE 1931 table values, D65 white and flat-spectrum normalization") {
    // Spot values of CIE 015 table T.4 / T.1.
    CHECK(sepal::cie1931_cmf(600).x == doctest::Approx(1.0622));
    CHECK(sepal::cie1931_cmf(550).y == doctest::Approx(0.99495));
    CHECK(sepal::cie1931_cmf(450).z == doctest::Approx(1.77211));
    CHECK(sepal::cie1931_cmf(555).y == doctest::Approx(0.5 * (0.99495 + 0.995)));  // interp.
    CHECK(sepal::cie1931_cmf(900).y == 0.0);
    CHECK(sepal::cie_d65(560) == 100.0);
    // The sRGB matrix maps D65 white to (1, 1, 1).
    const glm::dvec3 w = sepal::xyz_to_linear_srgb(glm::dvec3(0.95047, 1.0, 1.08883));
    CHECK(w.x == doctest::Approx(1.0).epsilon(1e-3));
    CHECK(w.y == doctest::Approx(1.0).epsilon(1e-3));
    CHECK(w.z == doctest::Approx(1.0).epsilon(1e-3));

    std::vector<double> nm;
    for (int l = 400; l <= 700; l += 10) nm.push_back(l);
    sepal::SpectrumToRgb conv;
    std::string err;
    REQUIRE_MESSAGE(conv.init(nm, &err), err);
    const std::vector<double> flat(nm.size(), 0.25);
    const glm::dvec3 g = conv.convert(flat.data());
    CHECK(g.x == doctest::Approx(0.25).epsilon(1e-12));
    CHECK(g.y == doctest::Approx(0.25).epsilon(1e-12));
    CHECK(g.z == doctest::Approx(0.25).epsilon(1e-12));
    // Long wavelengths only: red; short only: blue.
    std::vector<double> red(nm.size(), 0.0), blue(nm.size(), 0.0);
    for (size_t i = 0; i < nm.size(); ++i) {
        red[i] = nm[i] >= 600 ? 1.0 : 0.0;
        blue[i] = nm[i] <= 470 ? 1.0 : 0.0;
    }
    const glm::dvec3 r = conv.convert(red.data()), b = conv.convert(blue.data());
    CHECK(r.x > 3 * std::max(r.y, r.z));
    CHECK(b.z > 3 * std::max(b.x, b.y));

    CHECK_FALSE(conv.init({500, 500}, &err));
    CHECK(contains(err, "strictly increasing"));
    CHECK_FALSE(conv.init({200, 400}, &err));
    CHECK(contains(err, "outside 300..1000"));
    CHECK_FALSE(conv.init({900, 950}, &err));
    CHECK(contains(err, "visible range"));
    CHECK_FALSE(conv.init({}, &err));
}

// ---- half/difference angles and the table ----------------------------------------------------

TEST_CASE("measured: half/difference conversion follows NOTES.md and inverts") {
    // Mirror pair: h = n, theta_d = the incidence angle (phi_d is undefined there: the
    // Rusinkiewicz singularity, harmless for isotropic BRDFs).
    sepal::HalfDiff a = sepal::to_half_diff(dir(0.6, 0.0), dir(0.6, kPi));
    CHECK(a.theta_h == doctest::Approx(0.0));
    CHECK(a.theta_d == doctest::Approx(0.6));
    // In the x-z plane, off the mirror direction: h tilts by the half difference, phi_d = 0.
    a = sepal::to_half_diff(dir(0.6, 0.0), dir(0.2, kPi));
    CHECK(a.theta_h == doctest::Approx(0.2));
    CHECK(a.theta_d == doctest::Approx(0.4));
    CHECK(a.phi_d == doctest::Approx(0.0));
    // Retro-reflection: theta_d = 0, theta_h = the direction's elevation.
    a = sepal::to_half_diff(dir(0.7, 1.0), dir(0.7, 1.0));
    CHECK(a.theta_h == doctest::Approx(0.7));
    CHECK(a.theta_d == doctest::Approx(0.0));

    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int k = 0; k < 500; ++k) {
        sepal::HalfDiff in;
        in.theta_h = u(rng) * kPi / 2;
        in.theta_d = u(rng) * kPi / 2;
        in.phi_d = (2 * u(rng) - 1) * kPi;
        glm::dvec3 wi, wo;
        sepal::from_half_diff(in, &wi, &wo);
        CHECK(glm::length(wi) == doctest::Approx(1.0));
        CHECK(glm::length(wo) == doctest::Approx(1.0));
        const sepal::HalfDiff back = sepal::to_half_diff(wi, wo);
        CHECK(back.theta_h == doctest::Approx(in.theta_h).epsilon(1e-9));
        CHECK(back.theta_d == doctest::Approx(in.theta_d).epsilon(1e-9));
        CHECK(std::remainder(back.phi_d - in.phi_d, 2 * kPi) == doctest::Approx(0.0));
        // Reciprocity: swapping the directions keeps theta_h, theta_d and adds pi to phi_d.
        const sepal::HalfDiff swapped = sepal::to_half_diff(wo, wi);
        CHECK(swapped.theta_h == doctest::Approx(back.theta_h));
        CHECK(swapped.theta_d == doctest::Approx(back.theta_d));
        CHECK(std::remainder(swapped.phi_d - back.phi_d - kPi, 2 * kPi) ==
              doctest::Approx(0.0).epsilon(1e-9));
    }
}

TEST_CASE("measured: MERL indexing (non-linear theta_h, phi_d folding, clamping)") {
    const sepal::Tabulated t = sepal::Tabulated::merl();
    CHECK(t.size() == 1458000u);
    auto idx = [&](double th, double td, double pd) {
        sepal::HalfDiff a;
        a.theta_h = th;
        a.theta_d = td;
        a.phi_d = pd;
        return t.cell_index(a);
    };
    // NOTES.md: theta_h_idx = int(sqrt(theta_h/(pi/2))*90), theta_d_idx = int(theta_d/(pi/2)*90),
    // phi_d += pi when negative, idx = int(phi_d/pi*180); index = p + d*180 + h*180*90.
    const double th = 0.3, td = 0.9, pd = -2.0;
    const int ih = int(std::sqrt(th / (kPi / 2)) * 90), id = int(td / (kPi / 2) * 90),
              ip = int((pd + kPi) / kPi * 180);
    CHECK(idx(th, td, pd) == size_t(ip + id * 180 + ih * 180 * 90));
    CHECK(idx(-0.1, 0.0, 0.0) == 0u);                 // theta_h <= 0 -> 0
    CHECK(idx(kPi / 2, kPi / 2, kPi) == 1458000u - 1);  // clamped at the top
    CHECK(idx(0.0, 0.0, -1e-9) == 179u);              // just below 0 folds to the end
    // Every cell's centre maps back to the cell.
    for (size_t i = 0; i < t.size(); i += 997) CHECK(t.cell_index(t.cell_center(i)) == i);
    // The linear mapping is available for other resolutions.
    sepal::Tabulated lin;
    std::string err;
    REQUIRE(lin.init(10, 5, 8, sepal::ThetaHMapping::kLinear, &err));
    sepal::HalfDiff a;
    a.theta_h = 0.5 * kPi / 2;
    CHECK(lin.cell_index(a) == lin.index(5, 0, 0));
    CHECK_FALSE(lin.init(0, 5, 8, sepal::ThetaHMapping::kLinear, &err));
    CHECK(contains(err, "outside 1..4096"));
    CHECK_FALSE(lin.init(4096, 4096, 4096, sepal::ThetaHMapping::kLinear, &err));
    CHECK(contains(err, "over the limit"));
}

TEST_CASE("measured: table lookups interpolate, wrap phi_d and skip missing cells") {
    sepal::Tabulated t;
    REQUIRE(t.init(8, 6, 10, sepal::ThetaHMapping::kLinear, nullptr));
    // A field linear in the index coordinates: trilinear reproduces it inside the table.
    for (int h = 0; h < 8; ++h)
        for (int d = 0; d < 6; ++d)
            for (int p = 0; p < 10; ++p)
                t.set(t.index(h, d, p), glm::dvec3(h, 2.0 * d, 0.5 * p + 1.0));
    sepal::HalfDiff a;
    a.theta_h = (3.25 + 0.5) / 8 * kPi / 2;  // index coordinate 3.25
    a.theta_d = (1.5 + 0.5) / 6 * kPi / 2;   // 1.5
    a.phi_d = (4.75 + 0.5) / 10 * kPi;        // 4.75
    glm::dvec3 v;
    REQUIRE(t.trilinear(a, &v));
    CHECK(v.x == doctest::Approx(3.25));
    CHECK(v.y == doctest::Approx(3.0));
    CHECK(v.z == doctest::Approx(0.5 * 4.75 + 1.0));
    REQUIRE(t.nearest(a, &v));  // the cell containing the point: bin k covers [k-0.5, k+0.5)
    CHECK(v.x == 3.0);
    CHECK(v.y == 4.0);
    CHECK(v.z == 0.5 * 5 + 1.0);
    // phi_d = 0 sits halfway between the last and the first phi cell (pi periodicity).
    a.phi_d = 0.0;
    REQUIRE(t.trilinear(a, &v));
    CHECK(v.z == doctest::Approx(0.5 * ((0.5 * 9 + 1.0) + 1.0)));

    // Missing corners are skipped and the rest renormalized, never read as zeros.
    a.phi_d = (4.75 + 0.5) / 10 * kPi;
    for (int h = 3; h <= 4; ++h)
        for (int d = 1; d <= 2; ++d) t.set_missing(t.index(h, d, 5));
    REQUIRE(t.trilinear(a, &v));
    CHECK(v.z == doctest::Approx(0.5 * 4 + 1.0));  // only the p = 4 corners remain
    CHECK(v.x == doctest::Approx(3.25));
    // With all 8 corners missing the lookup falls back to... nothing: report false.
    for (int h = 3; h <= 4; ++h)
        for (int d = 1; d <= 2; ++d) t.set_missing(t.index(h, d, 4));
    CHECK_FALSE(t.trilinear(a, &v));
    CHECK_FALSE(t.nearest(a, &v));
    glm::dvec3 wi, wo;
    sepal::from_half_diff(a, &wi, &wo);
    CHECK(t.eval(wi, wo) == glm::dvec3(0.0));
    // Below the horizon and NaN directions give exactly 0.
    CHECK(t.eval(dir(1.0, 0.0), glm::dvec3(0, 0, -1)) == glm::dvec3(0.0));
    CHECK(t.eval(glm::dvec3(std::nan("")), dir(0.2, 0.0)) == glm::dvec3(0.0));
    // After push-pull every cell is usable again and measured cells are untouched.
    const size_t filled = t.fill_missing(sepal::Tabulated::FillDomain::kLinear);
    CHECK(filled == 8u);
    REQUIRE(t.trilinear(a, &v));
    CHECK(v.z > 1.0);
    CHECK(v.z < 0.5 * 9 + 1.0);
    CHECK(t.value(t.index(0, 0, 0)) == glm::dvec3(0.0, 0.0, 1.0));
    CHECK(t.state(t.index(3, 1, 4)) == sepal::Tabulated::State::kFilled);
    CHECK(t.confidence(t.index(3, 1, 4)) == 0.0f);
}

TEST_CASE("measured: push-pull fills scattered data within the data's range") {
    for (auto domain : {sepal::Tabulated::FillDomain::kLinear,
                        sepal::Tabulated::FillDomain::kLog1p}) {
        CAPTURE(int(domain));
        sepal::Tabulated t;
        REQUIRE(t.init(16, 12, 20, sepal::ThetaHMapping::kSqrt, nullptr));
        std::mt19937 rng(3);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        // A smooth field sampled at 150 scattered points (about 4% of the cells).
        auto field = [](const sepal::HalfDiff& a) {
            return glm::dvec3(1.0 + a.theta_d, 2.0 - a.theta_h, 0.5 + 0.1 * std::cos(2 * a.phi_d));
        };
        for (int k = 0; k < 150; ++k) {
            sepal::HalfDiff a;
            a.theta_h = u(rng) * kPi / 2;
            a.theta_d = u(rng) * kPi / 2;
            a.phi_d = u(rng) * kPi;
            t.splat(a, field(a), 1.0,
                    k % 2 ? sepal::Tabulated::Kernel::kTent : sepal::Tabulated::Kernel::kNearest);
        }
        t.finish_splats();
        const sepal::Tabulated::Counts before = t.counts();
        CHECK(before.occupied > 100u);
        CHECK(before.measured >= before.occupied);
        CHECK(before.missing == t.size() - before.measured);
        CHECK(t.fill_missing(domain) == before.missing);
        const sepal::Tabulated::Counts after = t.counts();
        CHECK(after.missing == 0u);
        CHECK(after.filled == before.missing);
        // Convex combinations of the data: inside its range (the field spans these bounds).
        double err2 = 0.0, ref2 = 0.0;
        for (size_t i = 0; i < t.size(); ++i) {
            const glm::dvec3 v = t.value(i);
            CHECK_MESSAGE((v.x >= 1.0 - 1e-5 && v.x <= 1.0 + kPi / 2 + 1e-5), i);
            CHECK_MESSAGE((v.y >= 2.0 - kPi / 2 - 1e-5 && v.y <= 2.0 + 1e-5), i);
            const glm::dvec3 d = v - field(t.cell_center(i));
            err2 += glm::dot(d, d);
            ref2 += glm::dot(field(t.cell_center(i)), field(t.cell_center(i)));
        }
        // A smooth field is reconstructed to a few percent from 4% of the cells.
        CHECK(std::sqrt(err2 / ref2) < 0.08);
    }
    // A constant survives the log1p round trip.
    sepal::Tabulated c;
    REQUIRE(c.init(4, 4, 4, sepal::ThetaHMapping::kLinear, nullptr));
    c.set(c.index(1, 2, 3), glm::dvec3(0.3, 7.0, 250.0));
    CHECK(c.fill_missing() == 63u);
    CHECK(c.value(c.index(3, 0, 0)).x == doctest::Approx(0.3).epsilon(1e-5));
    CHECK(c.value(c.index(3, 0, 0)).z == doctest::Approx(250.0).epsilon(1e-5));
    // Nothing measured: nothing to fill.
    sepal::Tabulated e;
    REQUIRE(e.init(4, 4, 4, sepal::ThetaHMapping::kLinear, nullptr));
    CHECK(e.fill_missing() == 0u);
    CHECK(e.counts().missing == 64u);
}
