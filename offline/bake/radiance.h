// What the bake's factors approximate: reflected radiance, bounded where a display is white.
//
// Usage:
//   sepal::RadianceTarget t;
//   t.white = 0.5;                                   // f cos(theta_i) above this shows white
//   t.diffuse = sepal::estimate_diffuse(*brdf);      // the floor, drawn untextured
//   sepal::RadianceBrdf g(*brdf, t);                 // g = max(0, min(f cos_i, white) - D cos_i)
//   factor_brdf(g, options, &result, &err);          // factors of g; Factored::radiance set by the bake
//
// Why: a light of irradiance E (= I / d^2) shows f cos(theta_i) E, clipped at 1 by the
// display. Beyond white = 1 / E_min no view can show a difference, so values above it are
// spent precision: grazing peaks of Ward or Cook-Torrance (f ~ 1/cos) are 10-1000 times
// what a sphere shows and, left in, set the textures' scale and the framebuffer doublings.
// Fitting f cos(theta_i) (not f) also spends the factors' rank where light lands, and the
// diffuse part D(cos theta_i, cos theta_o) is exact and free as an untextured pass whose
// vertex colour carries it (format 2): a constant rho_d / pi, or a profile over the two
// cosines (Ashikhmin-Shirley's and Oren-Nayar's diffuse, measured paints), which no
// half-angle factorization holds in few terms.
// Limits: white and diffuse are per bake; an asset renders its clipped highlights grey under
// a light dimmer than its declared light range's dimmest (light_range.h; the header records
// both, format 2.3, and the runtime counts such lights: sepal_draw_stats.dim_lights;
// `sepal bake --white none` keeps everything).
#pragma once
#include <atomic>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "brdf/brdf.h"

namespace sepal {

// The diffuse part: D_c(cos_i, cos_o) = scale_c * profile_c(cos_i, cos_o), the profile in
// [0,1] on a side x side grid (the format's DIFF chunk, sepal_diffuse_profile's lookup), or
// constant (side 0).
struct DiffusePart {
    glm::dvec3 scale{0, 0, 0};
    int side = 0;
    std::vector<float> profile;  // side * side * 3, sample (i, j) at cos_i = i/(side-1), cos_o = j/(side-1)
    double eval(int c, double cos_i, double cos_o) const;
    bool any() const { return scale.x > 0 || scale.y > 0 || scale.z > 0; }
};

struct RadianceTarget {
    double white = 0;      // cap on f cos(theta_i), per steradian; <= 0: none
    DiffusePart diffuse;   // subtracted times cos(theta_i)
    // The horizon window's c0 (format 2.7, sepal_horizon_window): below it the factors hold
    // f c0 where f cos(theta_i) falls to 0 at the horizon, and the backends multiply the
    // light by cos(theta_i) / c0. 0: none.
    double horizon = 0;
};

// The diffuse part as a constant: per channel the `quantile` of f over a fixed grid of
// direction pairs above 1.1 degrees from the horizon (a low quantile, not the minimum, so
// one noisy measured cell cannot decide it). For models with a Lambert floor (rho_d/pi plus
// a lobe that vanishes somewhere) this is rho_d / pi. Deterministic; threads as parallel.h.
glm::dvec3 estimate_diffuse(const Brdf& f, double quantile = 0.005, int threads = 0);
// The diffuse part as a profile over the two cosines: at each of side x side nodes, the
// minimum of f over every azimuth (and, for anisotropic BRDFs, orientation) and over the
// cosines of the cells around the node, so the bilinear profile stays at or below f (no
// lobe leaks into it, not even at normal incidence, where every azimuth is the mirror
// one), each node rounded down to the 16 bits the asset stores (asset_file.h). Returned
// constant (side 0) when the profile varies by under 2%, or all zero.
DiffusePart estimate_diffuse_profile(const Brdf& f, int side = 16, int threads = 0);

// The weight of a fitted value in the radiance fit (FactorOptions::value_weight): what an
// error in g shows on a display under the declared light range. Under irradiance E a value
// v shows as v E, clipped at 1, so the brightest light that still shows it is
// min(E_max, 1 / v) and an error d in it shows as d min(E_max, 1 / v): the weight of the
// squared error is (min(E_max, 1 / v) / E_max)^2 of the value's largest channel. Dim
// values count as they do unweighted; a value above 1 / E_max counts relatively, so a
// grazing peak near the white level no longer outweighs the body and the highlights a dim
// or back light shows (measured: docs/fidelity.md, "The fit's weights").
double display_weight(const glm::dvec3& value, double irradiance_max);

// g(wi, wo) = max(0, min(f u, white) - diffuse u) per channel, u = max(cos_i, horizon) (what
// a light shows over its horizon window; cos_i without one), the function the bake factors;
// counts how many evaluations the cap and the floor at 0 changed (thread-safe).
class RadianceBrdf : public Brdf {
  public:
    RadianceBrdf(const Brdf& f, const RadianceTarget& t) : f_(f), t_(t) {}
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override;
    std::string spec() const override { return f_.spec(); }
    std::string model() const override { return f_.model(); }
    std::string info() const override { return f_.info(); }
    bool isotropic() const override { return f_.isotropic(); }
    InputCounts input_counts() const override { return f_.input_counts(); }
    int64_t evaluations() const { return calls_; }
    int64_t capped() const { return capped_; }
    int64_t floored() const { return floored_; }

  private:
    const Brdf& f_;
    RadianceTarget t_;
    mutable std::atomic<int64_t> calls_{0}, capped_{0}, floored_{0};
};

}  // namespace sepal
