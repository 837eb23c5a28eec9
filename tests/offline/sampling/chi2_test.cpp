// Statistical tests of every sampler: chi-square goodness of fit (pbrt-v4's method) on
// analytic and measured materials at normal, oblique and grazing views, the pdf's integral,
// and unbiasedness of the estimator f cos / pdf against the deterministic directional albedo.
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <memory>

#include "brdf/brdf.h"
#include "spec/spec.h"
#include "brdf/brdf_util.h"
#include "offline/sampling/chi2.h"
#include "sampling/alternatives.h"
#include "sampling/factored_fit.h"
#include "sampling/sampler_file.h"
#include "test_util.h"
#include "util/parallel.h"

using namespace sepal;

namespace {

// Materials and their samplers, built once for the whole suite.
struct Material {
    std::unique_ptr<Brdf> brdf;
    std::map<std::string, std::unique_ptr<Sampler>> samplers;
};

Material& material(const std::string& spec) {
    static std::map<std::string, Material> cache;
    auto it = cache.find(spec);
    if (it != cache.end()) return it->second;
    Material m;
    std::string err;
    m.brdf = make_brdf(spec, &err);
    REQUIRE_MESSAGE(m.brdf, err);
    auto add = [&](const std::string& name, const SamplerData& d) {
        auto s = std::make_unique<Sampler>();
        REQUIRE_MESSAGE(s->build(d, &err), (name + ": " + err));
        m.samplers[name] = std::move(s);
    };
    FactoredOptions fo;
    fo.J = 2, fo.K = 2;
    fo.param = SampleParam::Half;
    fo.axis = SampleAxis::Normal;
    if (!m.brdf->isotropic()) fo.n_theta_p = 32, fo.n_phi_p = 32;
    SamplerData d;
    REQUIRE_MESSAGE(fit_factored(*m.brdf, fo, &d, nullptr, &err), err);
    add("factored", d);
    if (!m.brdf->isotropic()) {
        // Angles about the tangent and the bitangent (format 1.2), both parameterizations,
        // and about them in the view's turned frame (1.3, half vector only).
        for (SampleAxis a : {SampleAxis::Tangent, SampleAxis::Bitangent, SampleAxis::TangentView, SampleAxis::BitangentView,
                             SampleAxis::TangentMirror, SampleAxis::BitangentMirror})
            for (SampleParam p : {SampleParam::Half, SampleParam::Incident}) {
                const bool view_axis = a == SampleAxis::TangentView || a == SampleAxis::BitangentView;
                const bool mirror_axis = a == SampleAxis::TangentMirror || a == SampleAxis::BitangentMirror;
                if ((view_axis && p != SampleParam::Half) || (mirror_axis && p != SampleParam::Incident)) continue;
                FactoredOptions ao = fo;
                ao.axis = a, ao.param = p;
                REQUIRE_MESSAGE(fit_factored(*m.brdf, ao, &d, nullptr, &err), err);
                const uint32_t want = a == SampleAxis::Tangent         ? SEPAL_SMP_AXIS_T
                                      : a == SampleAxis::Bitangent     ? SEPAL_SMP_AXIS_S
                                      : a == SampleAxis::TangentView   ? SEPAL_SMP_AXIS_T_VIEW
                                      : a == SampleAxis::BitangentView ? SEPAL_SMP_AXIS_S_VIEW
                                      : a == SampleAxis::TangentMirror ? SEPAL_SMP_AXIS_T_MIRROR
                                                                       : SEPAL_SMP_AXIS_S_MIRROR;
                REQUIRE(d.desc.axis == want);
                add(std::string("factored-") + sample_param_name(p) + "-" + sample_axis_name(a), d);
            }
    }
    fo.param = SampleParam::Incident;
    REQUIRE_MESSAGE(fit_factored(*m.brdf, fo, &d, nullptr, &err), err);
    add("factored-incident", d);
    add("cosine", make_cosine_sampler());
    if (make_analytic_sampler(*m.brdf, &d, &err)) add("analytic", d);
    TabulatedOptions to;
    to.n_theta_o = 16, to.n_phi_o = 8, to.n_theta_i = 32, to.n_phi_i = 64;
    REQUIRE_MESSAGE(make_tabulated_sampler(*m.brdf, to, &d, &err), err);
    add("tabulated", d);
    return cache.emplace(spec, std::move(m)).first->second;
}

void add_fits(Material& m) {
    if (m.samplers.count("lafortune")) return;
    std::string err;
    SamplerData d;
    LobeFitReport rep;
    REQUIRE_MESSAGE(fit_lafortune_sampler(*m.brdf, 2, &d, &rep, &err), err);
    m.samplers["lafortune"] = std::make_unique<Sampler>();
    REQUIRE(m.samplers["lafortune"]->build(d, &err));
    REQUIRE_MESSAGE(fit_as_sampler(*m.brdf, &d, &rep, &err), err);
    m.samplers["as"] = std::make_unique<Sampler>();
    REQUIRE(m.samplers["as"]->build(d, &err));
}

const std::string kCt = "cook-torrance";
const std::string kWard = "ward:rho_d=0.1,rho_s=0.8,ax=0.2,ay=0.05";
const std::string kPf = "poulin-fournier";
std::string cornell() { return sepal_test::source_path("fixtures/cornell/garnet_red.brdf"); }

// Every chi-square test of this suite shares the significance level (Sidak).
constexpr int kTests = 51;  // 18 + 5 + 21 + 6 + 1 spare
constexpr int kSamples = 1000000;

sepal_test::Chi2Result run_chi2(const Sampler& s, const glm::dvec3& wo, uint64_t seed) {
    const float w[3] = {float(wo.x), float(wo.y), float(wo.z)};
    sepal_sampler_view v;
    sepal_sampler_set_view(&s.get(), w, &v);
    return sepal_test::chi2_test(
        [&](int i, glm::dvec3* out) {
            const float u[2] = {float(counter_uniform(seed, 2 * uint64_t(i))),
                                float(counter_uniform(seed, 2 * uint64_t(i) + 1))};
            float wi[3], pdf;
            if (sepal_sampler_sample(&v, u, wi, &pdf) < 0) return false;
            *out = glm::dvec3(wi[0], wi[1], wi[2]);
            return true;
        },
        [&](const glm::dvec3& wi) {
            const float f[3] = {float(wi.x), float(wi.y), float(wi.z)};
            return double(sepal_sampler_pdf(&v, f));
        },
        kSamples, kTests);
}

void check_chi2(const std::string& spec, const std::string& sampler, double theta_deg, double phi_deg = 30) {
    Material& m = material(spec);
    if (sampler == "lafortune" || sampler == "as") add_fits(m);
    REQUIRE(m.samplers.count(sampler));
    const auto r = run_chi2(*m.samplers[sampler], dir_from_degrees(theta_deg, phi_deg), 1000 + uint64_t(theta_deg));
    INFO(spec << " / " << sampler << " at theta_o " << theta_deg << ": " << r.message);
    CHECK(r.pass);
    CHECK(r.pdf_integral == doctest::Approx(1.0).epsilon(0.01));
}

}  // namespace

TEST_CASE("sampling: chi-square, every sampler on Cook-Torrance at 0, 45 and 85 degrees") {
    for (const char* s : {"factored", "cosine", "analytic", "tabulated", "lafortune", "as"})
        for (double t : {0.0, 45.0, 85.0}) check_chi2(kCt, s, t);
}

TEST_CASE("sampling: chi-square, anisotropic Ward (absolute phi) and the incident parameterization") {
    for (double t : {45.0, 85.0}) {
        check_chi2(kWard, "factored", t);
        check_chi2(kWard, "analytic", t);
    }
    check_chi2(kCt, "factored-incident", 60.0);
}

TEST_CASE("sampling: chi-square, factored samplers about the tangent and the bitangent, fixed, view-turned and mirror-centred (Ward, Poulin-Fournier)") {
    for (const char* s : {"factored-half-t", "factored-half-s", "factored-incident-t", "factored-incident-s",
                          "factored-half-t-view", "factored-half-s-view", "factored-incident-t-mirror",
                          "factored-incident-s-mirror"})
        for (double t : {45.0, 85.0}) check_chi2(kWard, s, t);
    check_chi2(kPf, "factored-half-t", 60.0);
    // The view axes turn the frame by half the view's angle about the axis: views on both
    // sides of the normal (phi_o 90 and 270: that angle's sign).
    check_chi2(kPf, "factored-half-t-view", 60.0, 90.0);
    check_chi2(kPf, "factored-half-t-view", 30.0, 270.0);
    // The mirror axes map wi.t piecewise linearly about -wo.t: views with wo.t of both signs.
    check_chi2(kPf, "factored-incident-t-mirror", 60.0, 20.0);
    check_chi2(kPf, "factored-incident-t-mirror", 40.0, 160.0);
}

TEST_CASE("sampling: chi-square, measured materials (Cornell garnet_red, MERL nickel)") {
    for (double t : {10.0, 80.0}) {
        check_chi2(cornell(), "factored", t);
        check_chi2(cornell(), "tabulated", t);
        check_chi2("nbrdf:nickel", "factored", t);
    }
}

TEST_CASE("sampling: the chi-square test rejects a sampler whose pdf is wrong") {
    // A cosine sampler judged against a uniform pdf: the test must fail (a test that cannot
    // fail is a defect).
    Sampler s;
    std::string err;
    REQUIRE(s.build(make_cosine_sampler(), &err));
    sepal_sampler_view v;
    const float wo[3] = {0, 0, 1};
    sepal_sampler_set_view(&s.get(), wo, &v);
    const auto r = sepal_test::chi2_test(
        [&](int i, glm::dvec3* out) {
            const float u[2] = {float(counter_uniform(5, 2 * uint64_t(i))), float(counter_uniform(5, 2 * uint64_t(i) + 1))};
            float wi[3], pdf;
            sepal_sampler_sample(&v, u, wi, &pdf);
            *out = glm::dvec3(wi[0], wi[1], wi[2]);
            return true;
        },
        [](const glm::dvec3& w) { return w.z > 0 ? 1 / (2 * kPi) : 0.0; }, 100000, 1);
    CHECK_FALSE(r.pass);
    CHECK(sepal_test::chi2_cdf(3.84, 1) == doctest::Approx(0.95).epsilon(1e-3));
    CHECK(sepal_test::chi2_cdf(18.307, 10) == doctest::Approx(0.95).epsilon(1e-3));
}

TEST_CASE("sampling: every estimator is unbiased (mean of f cos / pdf vs the directional albedo)") {
    struct Case {
        std::string spec;
        double theta;
    };
    for (const Case& c : {Case{kCt, 0}, Case{kCt, 70}, Case{kWard, 45}, Case{kPf, 50}, Case{cornell(), 60},
                          Case{"nbrdf:nickel", 40}}) {
        Material& m = material(c.spec);
        if (c.spec == kCt) add_fits(m);
        const glm::dvec3 wo = dir_from_degrees(c.theta, 30);
        const double truth = luminance(directional_albedo(*m.brdf, deg2rad(c.theta), 64, deg2rad(30)));
        for (auto& [name, s] : m.samplers) {
            const float w[3] = {float(wo.x), float(wo.y), float(wo.z)};
            sepal_sampler_view v;
            sepal_sampler_set_view(&s->get(), w, &v);
            const int n = 100000;
            double sum = 0, sq = 0;
            for (int i = 0; i < n; ++i) {
                const float u[2] = {float(counter_uniform(77, 2 * uint64_t(i))), float(counter_uniform(77, 2 * uint64_t(i) + 1))};
                float wi[3], pdf;
                double x = 0;
                if (sepal_sampler_sample(&v, u, wi, &pdf) == 1)
                    x = luminance(m.brdf->eval(glm::dvec3(wi[0], wi[1], wi[2]), wo)) * wi[2] / pdf;
                sum += x, sq += x * x;
            }
            const double mean = sum / n, se = std::sqrt(std::max(0.0, sq / n - mean * mean) / n);
            INFO(c.spec << " / " << name << " at " << c.theta << ": mean " << mean << " +- " << se << ", albedo "
                        << truth);
            // 4.5 standard errors (30-odd comparisons), plus the quadrature's 1e-4 relative.
            CHECK(std::fabs(mean - truth) <= 4.5 * se + 1e-4 * truth);
        }
    }
}
