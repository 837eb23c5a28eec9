// Lafortune fitting: exact recovery, calibrated 95% intervals over 200 random trials,
// rank-deficient data, bad input.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>

#include <glm/glm.hpp>

#include "brdf/brdf.h"
#include "spec/spec.h"
#include "fit/lafortune_fit.h"
#include "util/parallel.h"

namespace {

using glm::dvec3;
using sepal::BrdfSample;
using sepal::LafortuneModel;

constexpr double kPi = 3.14159265358979323846;

double gauss(sepal::SplitMix64& r) {
    const double u = std::max(r.uniform(), 1e-300), v = r.uniform();
    return std::sqrt(-2 * std::log(u)) * std::cos(2 * kPi * v);
}

dvec3 cosine_dir(sepal::SplitMix64& r) {
    const double u = r.uniform(), phi = 2 * kPi * r.uniform();
    const double s = std::sqrt(u);
    return dvec3(s * std::cos(phi), s * std::sin(phi), std::sqrt(std::max(0.0, 1 - u)));
}

// A measurement-like set of direction pairs: half anywhere, half around the mirror
// direction within about the lobe's width (a capture that saw highlights).
std::vector<BrdfSample> make_samples(const LafortuneModel& truth, int count, double sigma, sepal::SplitMix64& r,
                                     bool heteroscedastic = false) {
    std::vector<BrdfSample> s;
    const double width = std::acos(std::pow(0.5, 1.0 / std::max(1.0, truth.lobes[0].n)));
    while (int(s.size()) < count) {
        BrdfSample x;
        x.wi = cosine_dir(r);
        if (s.size() % 2) {
            x.wo = cosine_dir(r);
        } else {
            const dvec3 m(-x.wi.x, -x.wi.y, x.wi.z);
            dvec3 t = glm::normalize(glm::cross(m, std::fabs(m.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0)));
            dvec3 b = glm::cross(m, t);
            const double a = 1.5 * width * std::fabs(gauss(r)), phi = 2 * kPi * r.uniform();
            x.wo = std::cos(a) * m + std::sin(a) * (std::cos(phi) * t + std::sin(phi) * b);
            if (x.wo.z < 0.05) continue;
        }
        const dvec3 f = truth.eval(x.wi, x.wo);
        // Heteroscedastic: a noise floor plus noise proportional to the signal (one std per
        // sample, from its luminance), the weight 1/std known exactly.
        const double sd = heteroscedastic ? sigma * (0.2 + sepal::luminance(f)) : sigma;
        for (int c = 0; c < 3; ++c) x.value[c] = f[c] + sd * gauss(r);
        x.weight = heteroscedastic ? 1.0 / sd : 1.0;
        s.push_back(x);
    }
    return s;
}

LafortuneModel random_truth(sepal::SplitMix64& r) {
    LafortuneModel m;
    m.rho_d = dvec3(0.05 + 0.55 * r.uniform(), 0.05 + 0.55 * r.uniform(), 0.05 + 0.55 * r.uniform());
    const double n = 5 + 45 * r.uniform();
    const double peak = 0.5 + 4.5 * r.uniform();  // lobe value at the mirror direction
    const double cz = std::pow(peak, 1.0 / n);
    const double ratio = -(0.9 + 0.2 * r.uniform());
    m.lobes.push_back({ratio * cz, ratio * cz, cz, n});
    return m;
}

struct Coverage {
    std::vector<int> inside;  // per parameter
    int joint = 0, trials = 0, failed = 0;
};

// Runs `trials` random fits; counts how often each true parameter lies within its reported
// 95% interval, and how often the whole true vector lies in the 95% ellipsoid.
Coverage run_trials(int trials, uint64_t seed, bool heteroscedastic) {
    const int p = 6;
    // chi-square 95% quantile for 6 degrees of freedom.
    const double chi2_95 = 12.5916;
    Coverage cov;
    cov.inside.assign(p, 0);
    cov.trials = trials;
    std::vector<std::vector<int>> in(size_t(trials), std::vector<int>(p + 1, 0));
    std::vector<int> ok(size_t(trials), 0);
    sepal::parallel_for(size_t(trials), 0, [&](size_t t) {
        sepal::SplitMix64 r(seed + t * 7919);
        const LafortuneModel truth = random_truth(r);
        const auto samples = make_samples(truth, 120, 0.02, r, heteroscedastic);
        sepal::LafortuneFitOptions o;
        if (heteroscedastic) o.sigma = 1.0;  // the weights are 1 / std exactly
        sepal::LafortuneFit fit;
        std::string err;
        if (!sepal::fit_lafortune(samples, o, &fit, &err) || fit.rank < p) return;
        ok[t] = 1;
        const Eigen::VectorXd d = fit.params - sepal::lafortune_params(truth, 3, true);
        for (int j = 0; j < p; ++j) in[t][size_t(j)] = std::fabs(d[j]) <= fit.ci95(j);
        in[t][p] = d.dot(fit.cov.ldlt().solve(d)) <= chi2_95;
    });
    for (int t = 0; t < trials; ++t) {
        if (!ok[size_t(t)]) {
            ++cov.failed;
            continue;
        }
        for (int j = 0; j < p; ++j) cov.inside[size_t(j)] += in[size_t(t)][size_t(j)];
        cov.joint += in[size_t(t)][p];
    }
    return cov;
}

void check_coverage(const Coverage& c) {
    const std::vector<std::string> names = sepal::lafortune_param_names(3, 1, true);
    std::string line;
    for (size_t j = 0; j < c.inside.size(); ++j) line += names[j] + " " + std::to_string(c.inside[j]) + " ";
    MESSAGE("inside the 95% intervals, of " << c.trials << ": " << line << "joint " << c.joint);
    CHECK(c.failed == 0);
    for (size_t j = 0; j < c.inside.size(); ++j) {
        INFO(names[j] << ": " << c.inside[j] << " of " << c.trials << " inside the 95% interval");
        // At least 90% (the acceptance bound); at most 99.5%: intervals so wide that they
        // always hold would pass the first check and say nothing.
        CHECK(c.inside[j] >= 0.90 * c.trials);
        CHECK(c.inside[j] <= 0.995 * c.trials);
    }
    INFO("joint 95% ellipsoid: " << c.joint << " of " << c.trials);
    CHECK(c.joint >= 0.90 * c.trials);
    CHECK(c.joint <= 0.995 * c.trials);
}

}  // namespace

TEST_CASE("fit lafortune: noise-free samples give back the model, and its spec renders it") {
    sepal::SplitMix64 r(3);
    LafortuneModel truth;
    truth.rho_d = dvec3(0.3, 0.2, 0.1);
    truth.lobes.push_back({-0.95, -0.95, 0.98, 25});
    const auto samples = make_samples(truth, 200, 0.0, r);
    sepal::LafortuneFit fit;
    std::string err;
    REQUIRE(sepal::fit_lafortune(samples, sepal::LafortuneFitOptions(), &fit, &err));
    const Eigen::VectorXd want = sepal::lafortune_params(truth, 3, true);
    for (int j = 0; j < want.size(); ++j) CHECK(fit.params[j] == doctest::Approx(want[j]).epsilon(1e-6));
    CHECK(fit.rank == 6);
    CHECK(fit.rms < 1e-9);
    // The solver says why it stopped: converged here, well inside its budget; with a budget
    // of 3 evaluations from the same start it runs out and says so.
    CHECK((fit.lm_status == sepal::kLmCost || fit.lm_status == sepal::kLmStep || fit.lm_status == sepal::kLmGradient));
    CHECK(fit.evaluations < 400);
    sepal::LafortuneFitOptions tight;
    tight.max_evaluations = 3;
    LafortuneModel start = truth;
    start.lobes[0].n = 5;
    tight.start = &start;
    sepal::LafortuneFit short_fit;
    REQUIRE(sepal::fit_lafortune(samples, tight, &short_fit, &err));
    CHECK(short_fit.lm_status == sepal::kLmBudget);
    CHECK(short_fit.evaluations == 3);
    auto brdf = sepal::make_brdf(fit.model.spec(), &err);
    REQUIRE(brdf);
    for (const BrdfSample& s : samples) {
        const dvec3 a = brdf->eval(glm::normalize(s.wi), glm::normalize(s.wo)), b = fit.model.eval(s.wi, s.wo);
        CHECK(glm::length(a - b) <= 1e-9 * (1 + glm::length(b)));
    }
}

TEST_CASE("fit lafortune: two lobes and an anisotropic lobe are recovered from clean data") {
    sepal::SplitMix64 r(5);
    LafortuneModel truth;
    truth.rho_d = dvec3(0.1);
    truth.lobes.push_back({-1.0, -1.0, 1.0, 40});       // sharp mirror lobe
    truth.lobes.push_back({0.0, 0.0, 0.75, 2});         // broad lobe toward the normal
    std::vector<BrdfSample> samples = make_samples(truth, 300, 0.0, r);
    sepal::LafortuneFitOptions o;
    o.lobes = 2;
    o.channels = 1;
    sepal::LafortuneFit fit;
    std::string err;
    REQUIRE(sepal::fit_lafortune(samples, o, &fit, &err));
    CHECK(fit.rms < 1e-4);

    LafortuneModel aniso;
    aniso.rho_d = dvec3(0.2);
    aniso.lobes.push_back({-1.02, -0.9, 1.0, 20});
    samples = make_samples(aniso, 300, 0.0, r);
    o.lobes = 1;
    o.isotropic = false;
    REQUIRE(sepal::fit_lafortune(samples, o, &fit, &err));
    CHECK(fit.params.size() == 5);
    CHECK(fit.model.lobes[0].cx == doctest::Approx(-1.02).epsilon(1e-4));
    CHECK(fit.model.lobes[0].cy == doctest::Approx(-0.9).epsilon(1e-4));
}

TEST_CASE("fit lafortune: 95% intervals hold in 90% or more of 200 random noisy trials") {
    check_coverage(run_trials(200, 1000, false));
}

TEST_CASE("fit lafortune: known per-sample noise (weights, sigma given) is calibrated too") {
    check_coverage(run_trials(200, 5000, true));
}

TEST_CASE("fit lafortune: data without a highlight leave the lobe unmeasured, not falsely certain") {
    // Directions far from the mirror direction, where the lobe is ~0: rho_d is measured;
    // the lobe's parameters are not.
    sepal::SplitMix64 r(11);
    LafortuneModel truth;
    truth.rho_d = dvec3(0.4);
    truth.lobes.push_back({-1, -1, 1, 200});
    std::vector<BrdfSample> samples;
    while (samples.size() < 60) {
        BrdfSample s;
        s.wi = cosine_dir(r);
        s.wo = cosine_dir(r);
        if (glm::dot(dvec3(-s.wi.x, -s.wi.y, s.wi.z), s.wo) > 0.7) continue;
        s.value = truth.eval(s.wi, s.wo) + dvec3(0.01 * gauss(r));
        samples.push_back(s);
    }
    sepal::LafortuneFitOptions o;
    o.channels = 1;
    sepal::LafortuneFit fit;
    std::string err;
    REQUIRE(sepal::fit_lafortune(samples, o, &fit, &err));
    CHECK(std::isfinite(fit.ci95(0)));
    CHECK(fit.params[0] == doctest::Approx(0.4).epsilon(0.05));
    // The solver may park a lobe on a few noisy samples; what matters is that the lobe is
    // reported as unknown: unmeasured (rank < 4, infinite variance) or an interval wider
    // than the value itself.
    int unknown = 0;
    for (int j = 1; j < 4; ++j) unknown += !(fit.ci95(j) < std::fabs(fit.params[j]));
    INFO("rank " << fit.rank << ", n = " << fit.params[3] << " +- " << fit.ci95(3));
    CHECK(unknown >= 1);
}

TEST_CASE("fit lafortune: one direction pair seen many times measures one combination only") {
    std::vector<BrdfSample> s(40);
    sepal::SplitMix64 r(2);
    for (auto& x : s) {
        x.wi = glm::normalize(dvec3(0.3, 0.1, 1));
        x.wo = glm::normalize(dvec3(-0.3, -0.1, 1));
        x.value = dvec3(0.5 + 0.01 * gauss(r));
    }
    sepal::LafortuneFitOptions o;
    o.channels = 1;
    sepal::LafortuneFit fit;
    std::string err;
    REQUIRE(sepal::fit_lafortune(s, o, &fit, &err));
    CHECK(fit.rank == 1);
    for (int j = 0; j < 4; ++j) CHECK_FALSE(std::isfinite(fit.ci95(j)));
}

TEST_CASE("fit lafortune: bad input is refused with the sample named") {
    std::vector<BrdfSample> s(10);
    for (auto& x : s) x.value = dvec3(0.1);
    sepal::LafortuneFit fit;
    std::string err;
    s.resize(1);
    CHECK_FALSE(sepal::fit_lafortune(s, sepal::LafortuneFitOptions(), &fit, &err));
    CHECK(err.find("parameters need more") != std::string::npos);
    s.assign(20, BrdfSample());
    s[7].value.y = NAN;
    CHECK_FALSE(sepal::fit_lafortune(s, sepal::LafortuneFitOptions(), &fit, &err));
    CHECK(err.find("sample 7") != std::string::npos);
    s[7].value.y = 0;
    s[3].wo = dvec3(0, 1, -0.1);
    CHECK_FALSE(sepal::fit_lafortune(s, sepal::LafortuneFitOptions(), &fit, &err));
    CHECK(err.find("sample 3") != std::string::npos);
    s[3].wo = dvec3(0, 0, 1);
    s[4].weight = -1;
    CHECK_FALSE(sepal::fit_lafortune(s, sepal::LafortuneFitOptions(), &fit, &err));
    sepal::LafortuneFitOptions o;
    o.lobes = 9;
    CHECK_FALSE(sepal::fit_lafortune(s, o, &fit, &err));
}

TEST_CASE("fit lafortune: tint_lafortune_lobes recovers a coloured highlight; the spec carries it") {
    // A metallic paint's highlight: the lobe coloured (1, 0.7, 0.4) over a grey body.
    LafortuneModel truth;
    truth.rho_d = dvec3(0.3);
    sepal::LafortuneLobe lobe;
    lobe.cx = lobe.cy = -1.0;
    lobe.cz = 1.0;
    lobe.n = 30;
    lobe.colour = dvec3(1.0, 0.7, 0.4);
    truth.lobes = {lobe};
    sepal::SplitMix64 r(41);
    const std::vector<BrdfSample> s = make_samples(truth, 2000, 0.0, r);
    sepal::LafortuneFit fit;
    std::string err;
    REQUIRE_MESSAGE(sepal::fit_lafortune(s, sepal::LafortuneFitOptions(), &fit, &err), err);
    LafortuneModel tinted = fit.model;
    REQUIRE(sepal::tint_lafortune_lobes(s, &tinted));
    const dvec3 t = tinted.lobes[0].colour;
    MESSAGE("white fit rho_d " << fit.model.rho_d.x << " " << fit.model.rho_d.y << " " << fit.model.rho_d.z
                                << ", lobe colour " << t.x << " " << t.y << " " << t.z);
    // The white fit leans its diffuse term towards the highlight's colour, and the tint holds
    // that term: the ratios recover at least half of the way from white to the truth's.
    CHECK(std::fabs(t.y / t.x - 0.7) < 0.5 * (1.0 - 0.7));
    CHECK(std::fabs(t.z / t.x - 0.4) < 0.5 * (1.0 - 0.4));
    CHECK(tinted.rho_d == fit.model.rho_d);  // the body is held
    auto rms = [&](const LafortuneModel& m) {
        double e = 0;
        for (const BrdfSample& x : s) {
            const dvec3 d = m.eval(x.wi, x.wo) - x.value;
            e += glm::dot(d, d);
        }
        return std::sqrt(e / double(s.size()));
    };
    MESSAGE("white lobe RMS " << rms(fit.model) << ", tinted " << rms(tinted));
    CHECK(rms(tinted) < 0.7 * rms(fit.model));
    // The spec (lobe=Cx/Cy/Cz/n/r/g/b) renders what the model evaluates.
    bool clamped = true;
    auto b = sepal::make_brdf(tinted.spec(&clamped), &err);
    CHECK_FALSE(clamped);
    REQUIRE_MESSAGE(b, err);
    for (size_t i = 0; i < s.size(); i += 97) {
        const dvec3 a = b->eval(s[i].wi, s[i].wo), m = tinted.eval(s[i].wi, s[i].wo);
        for (int c = 0; c < 3; ++c) CHECK(a[c] == doctest::Approx(m[c]).epsilon(1e-4));
    }
    // No sample on the lobe: nothing to tint.
    LafortuneModel zero = fit.model;
    zero.lobes[0].cz = 0.0;
    zero.lobes[0].cx = zero.lobes[0].cy = 0.0;
    CHECK_FALSE(sepal::tint_lafortune_lobes(s, &zero));
    CHECK(zero.lobes[0].colour == dvec3(1.0));
}

TEST_CASE("fit lafortune: lafortune_plausible refuses created energy and models their spec would change") {
    auto model = [](glm::dvec3 rho, double cxy, double cz, double n) {
        sepal::LafortuneModel m;
        m.rho_d = rho;
        sepal::LafortuneLobe l;
        l.cx = l.cy = cxy;
        l.cz = cz;
        l.n = n;
        m.lobes = {l};
        return m;
    };
    double a = 0;
    // A specular lobe and a retro-reflective one, both conserving.
    CHECK(sepal::lafortune_plausible(model(glm::dvec3(0.1, 0.2, 0.5), -1, 0.99, 40), &a));
    CHECK(a < 0.61);
    CHECK(sepal::lafortune_plausible(model(glm::dvec3(0.3), 0.5, 0.5, 5), &a));
    // The acquisition bench's gold-paint misfit: a lobe that lives at grazing angles only
    // (Cz < 0), measured nowhere, with an albedo of about 1e8 at 89 degrees.
    CHECK_FALSE(sepal::lafortune_plausible(model(glm::dvec3(0.09, 0.015, 0), -4.4, -4.69, 14.55), &a));
    CHECK(a > 1e6);
    // A negative diffuse colour that a lobe made up for: the spec clamps it to 0, so what
    // renders is not what was fitted.
    CHECK_FALSE(sepal::lafortune_plausible(model(glm::dvec3(-0.1, 0.2, 0.2), -1, 0.99, 40), &a));
    CHECK(a < 1);
    // An anisotropic lobe whose energy is along y only: seen from incidence in the yz plane.
    sepal::LafortuneModel aniso = model(glm::dvec3(0.1), -1, 0.99, 40);
    aniso.lobes[0].cy = -8;
    CHECK_FALSE(sepal::lafortune_plausible(aniso, &a));
    // Just above the bound: a lobe brighter than any surface reflects.
    CHECK_FALSE(sepal::lafortune_plausible(model(glm::dvec3(0.5), -1.2, 1.2, 4), &a));
    CHECK(a > sepal::kPlausibleAlbedo);
}

TEST_CASE("fit lafortune: forward keeps the fit inside its bounds, and gives the free fit where that is inside") {
    sepal::SplitMix64 r(11);
    std::string err;
    sepal::LafortuneFitOptions free_o, fwd_o;
    fwd_o.forward = true;
    // A forward material: the bounds are not active, both fits recover it.
    LafortuneModel specular;
    specular.rho_d = dvec3(0.3, 0.2, 0.1);
    specular.lobes.push_back({-0.95, -0.95, 0.98, 25});
    auto samples = make_samples(specular, 200, 0.0, r);
    sepal::LafortuneFit a, b;
    REQUIRE(sepal::fit_lafortune(samples, free_o, &a, &err));
    REQUIRE(sepal::fit_lafortune(samples, fwd_o, &b, &err));
    for (int j = 0; j < a.params.size(); ++j) CHECK(b.params[j] == doctest::Approx(a.params[j]).epsilon(1e-6));
    // A retro-reflective lobe (Cxy > 0) over a dark blue: the free fit finds it; the forward
    // fit may not leave its bounds, so it explains the data less well but stays inside.
    LafortuneModel retro;
    retro.rho_d = dvec3(0.05, 0.1, 0.4);
    retro.lobes.push_back({0.6, 0.6, 0.5, 4});
    samples = make_samples(retro, 300, 0.002, r);
    REQUIRE(sepal::fit_lafortune(samples, free_o, &a, &err));
    REQUIRE(sepal::fit_lafortune(samples, fwd_o, &b, &err));
    CHECK(a.model.lobes[0].cx > 0.3);
    CHECK(b.rss > a.rss);
    const sepal::LafortuneLobe& l = b.model.lobes[0];
    CHECK(l.cx <= 0);
    CHECK(l.cy <= 0);
    CHECK(l.cz >= 0);
    CHECK(l.n >= 1);
    for (int c = 0; c < 3; ++c) CHECK(b.model.rho_d[c] >= 0);
    CHECK(b.lm_status != sepal::kLmStuck);
    // Two lobes and anisotropic layouts keep the bounds too.
    fwd_o.lobes = 2;
    fwd_o.isotropic = false;
    REQUIRE(sepal::fit_lafortune(samples, fwd_o, &b, &err));
    for (int c = 0; c < 3; ++c) CHECK(b.model.rho_d[c] >= 0);
    for (const sepal::LafortuneLobe& k : b.model.lobes) {
        CHECK(k.cx <= 0);
        CHECK(k.cy <= 0);
        CHECK(k.cz >= 0);
        CHECK(k.n >= 1);
    }
}
