// A BRDF clamped at a cap: what `sepal bake --cap` and `sepal factor --cap` fit.
//
// Usage:
//   sepal::CappedBrdf capped(*brdf, 2.0);   // f per steradian above 2 is clamped, per channel
//   factor_brdf(capped, options, &result, &err);
//   double share = capped.share();          // of the evaluations, the share clamped
//
// GL ES 1.1 draws through an 8-bit framebuffer whose scale-up multiplies its step by the
// largest factor product: BRDFs with huge grazing peaks (Ward, Cook-Torrance) lose every
// mid-tone there unless the peaks, white on screen anyway, are capped. Counting is
// thread-safe (factoring is parallel) and the totals do not depend on the order.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <string>

#include "brdf/brdf.h"

namespace sepal {

class CappedBrdf : public Brdf {
  public:
    CappedBrdf(const Brdf& f, double cap) : f_(f), cap_(cap) {}
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override {
        glm::dvec3 v = f_.eval(wi, wo);
        ++calls_;
        if (v.x > cap_ || v.y > cap_ || v.z > cap_) {
            ++capped_;
            v = glm::dvec3(std::min(v.x, cap_), std::min(v.y, cap_), std::min(v.z, cap_));
        }
        return v;
    }
    std::string spec() const override { return f_.spec(); }
    std::string model() const override { return f_.model(); }
    std::string info() const override { return f_.info(); }
    bool isotropic() const override { return f_.isotropic(); }
    InputCounts input_counts() const override { return f_.input_counts(); }
    double share() const { return calls_ ? double(capped_) / double(calls_) : 0.0; }
    int64_t capped() const { return capped_; }

  private:
    const Brdf& f_;
    double cap_;
    mutable std::atomic<int64_t> calls_{0}, capped_{0};
};

}  // namespace sepal
