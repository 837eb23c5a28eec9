// Error metrics of a separable approximation against its BRDF.
//
// Usage:
//   sepal::ErrorEvaluator ev(*brdf);                  // evaluates the BRDF once per pair
//   if (!ev.init(&err)) ...                           // fails on a non-finite BRDF value
//   sepal::ApproxError e = ev.measure(result.by_terms[0]);
//   std::vector<sepal::TermError> t = sepal::measure_terms(ev, result);  // per term count
//
// The metric is that of Kautz and McCool (1999, section 5.2, Figure 5): the RMS of the
// outgoing radiance error (f~ - f) cos(theta_i), "cosine-weighted RMS", over direction pairs
// uniform over both hemispheres: 8000 Monte Carlo pairs with a fixed seed, plus a dense
// deterministic version over D^4 pairs (wi and wo each on the centres of a D x D grid
// equal in area, over cos(theta) and phi; D = 20 gives 160,000 pairs). Errors are of the
// luminance (as in the paper's figure); rms_rgb averages the squared errors of R, G, B.
// relative = rms / RMS of f cos(theta_i) itself over the same pairs. The approximation is
// reconstructed by the shared bilinear evaluator (factored.h).
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "brdf/brdf.h"
#include "factor/factor.h"
#include "factor/factored.h"

namespace sepal {

struct ErrorOptions {
    int mc_pairs = 8000;
    uint64_t seed = 0x4b6d31393939ULL;  // fixed: the same pairs in every run
    int dense = 20;                     // D; 0 leaves the dense metric out
    int threads = 0;
};

struct ApproxError {
    double rms = 0, relative = 0, rms_rgb = 0;  // Monte Carlo
    double dense_rms = 0, dense_relative = 0;   // dense grid (0 when dense == 0)
};

struct TermError {
    int terms = 0;
    ApproxError e;
    double matrix_rms = 0;  // at the sample points (FactorResult::matrix_rms)
};

class ErrorEvaluator {
  public:
    explicit ErrorEvaluator(const Brdf& brdf, const ErrorOptions& o = ErrorOptions{});
    // Samples the BRDF at every pair; false with a message on a non-finite value.
    bool init(std::string* err);
    ApproxError measure(const Factored& f) const;
    // RMS of luminance(f) cos(theta_i) over the Monte Carlo pairs.
    double reference_rms() const { return ref_rms_; }
    const ErrorOptions& options() const { return o_; }
    // The k-th pair of either set (also used by tests).
    static void mc_pair(uint64_t seed, int64_t k, glm::dvec3* wi, glm::dvec3* wo);
    static void dense_pair(int d, int64_t k, glm::dvec3* wi, glm::dvec3* wo);

  private:
    const Brdf& brdf_;
    ErrorOptions o_;
    std::vector<glm::dvec3> mc_f_, dense_f_;
    double ref_rms_ = 0, ref_dense_ = 0;
    bool ready_ = false;
};

// The same metric at measured samples (raw Cornell data) instead of direction pairs:
// sqrt(sum ((f~ - f) cos theta_i)^2 / sum (f cos theta_i)^2) (f~ cos theta_i from
// evaluate_radiance: factors of f and radiance factors alike) over the samples whose half
// angle is at least min_half_angle_deg (5 degrees leaves a mirror peak out: "off-peak"),
// of the luminance, or of R, G and B together (rgb). 0 when no sample qualifies.
double sample_relative_rms(const Factored& f, const std::vector<BrdfSample>& samples,
                           double min_half_angle_deg, bool rgb);
// The same for any stand-in of f cos theta_i (per channel), e.g. the dense table a bake fits,
// capped at its white level: the floor no factors of that table can go below.
using RadianceFn = std::function<glm::dvec3(const glm::dvec3& wi, const glm::dvec3& wo)>;
double sample_relative_rms(const RadianceFn& radiance, const std::vector<BrdfSample>& samples,
                           double min_half_angle_deg, bool rgb);

// Errors of result.by_terms[k-1] for k = 1..K, with the matrix RMS filled in.
std::vector<TermError> measure_terms(const ErrorEvaluator& ev, const FactorResult& result);

}  // namespace sepal
