// The one BRDF evaluation interface of the encoder.
//
// Usage:
//   std::string err;
//   std::unique_ptr<sepal::Brdf> f = sepal::make_brdf("ward:rho_d=0.1,rho_s=1.2,ax=0.2,ay=0.02", &err);  // spec/spec.h
//   if (!f) { fprintf(stderr, "%s\n", err.c_str()); return 2; }
//   glm::dvec3 rgb = f->eval(wi, wo);
//
// Conventions: both directions are unit vectors in the local frame (normal n = +z, primary
// tangent t = +x, s = n x t = +y), both pointing away from the surface. eval returns linear
// RGB reflectance per steradian (the cosine factor is NOT included), and exactly 0 when
// either direction is at or below the horizon (z <= 0). Implementations never return NaN
// or inf and are safe to call from several threads at once.
// Implementations: the analytic models (brdf_models.h) and measured data (measured/); the
// factory that builds any of them from a spec string is spec/spec.h's make_brdf.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace sepal {

// What a measured loader did to its input, for reports (bake's counts, sepal info): every
// value it could not use as data, and what it put in its place. All 0 for analytic models.
struct InputCounts {
    int64_t values = 0;     // values read (MERL: 3 per cell; Cornell: the spectral values)
    int64_t nonfinite = 0;  // NaN or inf values: treated as missing
    // Negative values (MERL's marker for no data) or, for Cornell, sample lines holding one:
    // treated as missing.
    int64_t negative = 0;
    int64_t huge = 0;       // values beyond float range: treated as missing
    int64_t missing = 0;    // cells (MERL) or samples (Cornell) left without data by the above
    // MERL: cells below the horizon marked -1 (no data by geometry): in none of the above.
    int64_t horizon = 0;
    int64_t filled = 0;     // table cells given a push-pull value, for lookups only
    int64_t clamped = 0;    // values clamped into range (Cornell: negative RGB set to 0, and
                            // angles within rounding slack of [0, pi/2])
};

// One BRDF measurement in the local frame (normal +z), directions as in eval: the value
// per steradian (linear RGB), and how much it counts (1 / its standard deviation, up to a
// common factor; 0 drops it). The Lafortune fit and the homomorphic fit take these.
struct BrdfSample {
    glm::dvec3 wi{0, 0, 1}, wo{0, 0, 1};
    glm::dvec3 value{0.0};
    double weight = 1;
};

class Brdf {
  public:
    virtual ~Brdf() = default;
    virtual glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const = 0;
    // Canonical spec: make_brdf(spec()) rebuilds an equal BRDF.
    virtual std::string spec() const = 0;
    // Model or file kind, e.g. "ward", "merl", "cornell".
    virtual std::string model() const = 0;
    // Human-readable lines: parameters with their values, and for measured data the
    // sample counts, missing samples and coverage. Used by `sepal info`.
    virtual std::string info() const = 0;
    // True when f depends on the azimuths only through phi_i - phi_o.
    virtual bool isotropic() const = 0;
    // True when the model conserves energy at these parameters (albedo <= 1 expected).
    virtual bool energy_conserving() const { return false; }
    // Measured data: what the loader counted (see InputCounts).
    virtual InputCounts input_counts() const { return InputCounts{}; }
    // Scattered measured data as it was read (Cornell: the raw samples, before the dense
    // table eval() looks up): true and *out filled, or false when there are none (analytic
    // models, dense tables). Fits that take scattered data (homomorphic) use them directly.
    virtual bool scattered_samples(std::vector<BrdfSample>* out) const {
        (void)out;
        return false;
    }
};

}  // namespace sepal
