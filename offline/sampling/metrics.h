// Error and variance measures of the sampling subsystem (the bench's tables, the tests).
//
// Usage:
//   double mae = sepal::normalized_mae(*brdf, [&](const glm::dvec3& wi, const glm::dvec3& wo) {
//       return approx_f_cos(wi, wo); }, 1 << 18, 7);
//
// normalized_mae: the paper's Table 1 measure, sum |f~ cos - f cos| / sum f cos over `pairs`
// (wi, wo) pairs drawn uniformly over both hemispheres (a fixed seed; independent of any
// fit's resolution), on luminance. The paper says only "a dense set of samples of the 4D
// domain"; PairDensity::Angles draws (theta_i, phi_i, theta_o, phi_o) uniformly instead (a
// regular angle grid's weighting: more pairs near the normal, fewer at grazing angles).
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

#include "brdf/brdf.h"
#include "sepal/sepal_sampler.h"
#include "util/image.h"

namespace sepal {

using ApproxFn = std::function<double(const glm::dvec3& wi, const glm::dvec3& wo)>;

enum class PairDensity { SolidAngle, Angles };
double normalized_mae(const Brdf& truth, const ApproxFn& approx, int pairs, uint64_t seed,
                      PairDensity density = PairDensity::SolidAngle);

// A FACTORED sampler's reconstruction of f(wi, wo) cos(theta_i) in luminance (what it
// samples): total(wo) times its factored density at wi, without the defensive share.
double factored_lum(const sepal_sampler_view& v, const glm::dvec3& wi);

// Views the samplers are judged at without rendering: 8 elevations from 5 to 87 degrees
// (x 4 azimuths 0..90 for anisotropic BRDFs).
std::vector<glm::dvec3> judge_views(bool isotropic);

// The relative variance of the one-sample estimator f cos / pdf (luminance) under a constant
// environment, averaged over the views: mean of Var / E^2, by `samples` stratified draws per
// view (fixed seed). What a sampler is for; 0 for a perfect one.
double relative_variance(const Brdf& f, const sepal_sampler& s, const std::vector<glm::dvec3>& views,
                         int samples, uint64_t seed);

// Image statistics over the pixels where mask != 0 (all pixels with an empty mask), on the
// mean of the RGB channels: mean squared difference between two images, and the per-pixel
// variance across repeated renders (unbiased, over >= 2 images) averaged over the pixels.
double image_mse(const Image& a, const Image& b, const std::vector<uint8_t>& mask);
double image_variance(const std::vector<Image>& trials, const std::vector<uint8_t>& mask);

}  // namespace sepal
