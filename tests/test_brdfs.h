// BRDFs defined for the factorization tests and benchmarks, independent of the model
// library: a function that is exactly rank 1 in a chosen parameterization, a normalized
// Blinn-Phong lobe, and one that returns NaN somewhere (for the refusal paths).
#pragma once
#include <cmath>
#include <limits>
#include <string>

#include <glm/geometric.hpp>

#include "brdf/brdf.h"
#include "factor/param.h"

namespace sepal_test {

// f(wi, wo) = g(x) h(y) with smooth, positive g and h of the texture coordinates (x, y) of
// `param` / `map`: exactly separable there, so a 1-term SVD must reproduce its samples.
class Rank1Brdf : public sepal::Brdf {
  public:
    Rank1Brdf(sepal::Param p, sepal::HemiMap m) : p_(p), m_(m) {}
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override {
        sepal::TexCoords tc;
        if (!sepal::param_forward(p_, m_, wi, wo, &tc)) return glm::dvec3(0);
        const double g = 0.5 + tc.x.x * tc.x.x + 0.25 * std::sin(3 * tc.x.y);
        const double h = 0.75 + 0.5 * tc.y.x * tc.y.y + 0.2 * std::cos(2 * tc.y.x);
        return glm::dvec3(1.0, 0.8, 0.6) * (g * h);
    }
    std::string spec() const override { return std::string("rank1:") + sepal::param_name(p_); }
    std::string model() const override { return "rank1"; }
    std::string info() const override { return "test: rank 1 in " + spec(); }
    bool isotropic() const override { return false; }

  private:
    sepal::Param p_;
    sepal::HemiMap m_;
};

// Normalized Blinn-Phong: kd/pi + ks (n + 8)/(8 pi) cos^n(theta_h).
class BlinnBrdf : public sepal::Brdf {
  public:
    explicit BlinnBrdf(double exponent, double kd = 0.0, double ks = 1.0)
        : n_(exponent), kd_(kd), ks_(ks) {}
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override {
        if (!(wi.z > 0) || !(wo.z > 0)) return glm::dvec3(0);
        const glm::dvec3 h = glm::normalize(wi + wo);
        const double pi = 3.14159265358979323846;
        const double spec = ks_ * (n_ + 8) / (8 * pi) * std::pow(std::max(h.z, 0.0), n_);
        return glm::dvec3(kd_ / pi + spec);
    }
    std::string spec() const override { return "test-blinn:n=" + std::to_string(n_); }
    std::string model() const override { return "test-blinn"; }
    std::string info() const override { return spec(); }
    bool isotropic() const override { return true; }

  private:
    double n_, kd_, ks_;
};

// Ward's anisotropic model (1992), coloured diffuse: a stand-in for benchmarks and tests
// that must not depend on the model library.
class WardTestBrdf : public sepal::Brdf {
  public:
    WardTestBrdf(glm::dvec3 rho_d, double rho_s, double ax, double ay)
        : rho_d_(rho_d), rho_s_(rho_s), ax_(ax), ay_(ay) {}
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override {
        if (!(wi.z > 0) || !(wo.z > 0)) return glm::dvec3(0);
        const double pi = 3.14159265358979323846;
        const glm::dvec3 h = glm::normalize(wi + wo);
        const double e = -((h.x / ax_) * (h.x / ax_) + (h.y / ay_) * (h.y / ay_)) / (h.z * h.z);
        const double spec = rho_s_ * std::exp(e) / (4 * pi * ax_ * ay_ * std::sqrt(wi.z * wo.z));
        return rho_d_ / pi + glm::dvec3(spec);
    }
    std::string spec() const override { return "test-ward"; }
    std::string model() const override { return "test-ward"; }
    std::string info() const override { return spec(); }
    bool isotropic() const override { return ax_ == ay_; }

  private:
    glm::dvec3 rho_d_;
    double rho_s_, ax_, ay_;
};

// NaN for wi.x > 0.5: the engine must refuse it, not crash or write output.
class NanBrdf : public sepal::Brdf {
  public:
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override {
        if (!(wi.z > 0) || !(wo.z > 0)) return glm::dvec3(0);
        if (wi.x > 0.5) return glm::dvec3(std::numeric_limits<double>::quiet_NaN());
        return glm::dvec3(0.3);
    }
    std::string spec() const override { return "test-nan"; }
    std::string model() const override { return "test-nan"; }
    std::string info() const override { return spec(); }
    bool isotropic() const override { return true; }
};

}  // namespace sepal_test
