// Separable factors fitted to scattered samples: f(wi, wo) ~= sum_k G_k(x) H_k(y) with the
// factors' bilinear lookups evaluated at each sample's own texture coordinates (no table
// in between). The refinement step of a factorization whose data are measurements at a
// few hundred direction pairs (an inverse shade tree's basis, Lawrence et al. 2006).
//
// Usage:
//   std::vector<sepal::ScatteredSample> s = ...;   // wi, wo, f (RGB), weight
//   sepal::Factored f = ...;                        // a start: any per-channel, non-negative fit
//   sepal::ScatteredOptions o; o.constant_side = 0;  // term 0's G held (a diffuse-like lobe)
//   sepal::ScatteredResult r; std::string err;
//   if (!sepal::refine_scattered(s, o, &f, &r, &err)) ...
//
// Objective, per channel: sum_s w_s (f_s - sum_k G_k(x_s) H_k(y_s))^2 plus
// smoothness x (mean data curvature) x sum over 4-neighbour texel edges of each factor of
// the squared difference (a graph Laplacian: texels no sample reaches take the harmonic
// interpolation of their neighbours). Alternating constrained least squares by blocks:
// each factor of each term in turn, holding the rest, is the exact non-negative minimizer
// of its (sparse, banded) quadratic, found by projected Gauss-Seidel sweeps; no step raises
// the objective. Factors keep their resolution, parameterization and map.
// Limits: per-channel factors (3 channels), parameterizations with clamped factors (not
// elev-azim), 1..16 terms, up to 1e6 samples.
#pragma once
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "factor/factored.h"

namespace sepal {

struct ScatteredSample {
    glm::dvec3 wi, wo, f;
    double weight = 1;  // >= 0
};

struct ScatteredOptions {
    int iterations = 40;       // outer passes over all factors
    int sweeps = 20;           // Gauss-Seidel sweeps per factor update
    double smoothness = 1e-3;  // relative weight of the Laplacian
    int constant_side = -1;    // 0 or 1: that factor of term 0 is held (a constant lobe)
    double tolerance = 1e-6;   // stop when the objective falls by less than this share
};

struct ScatteredResult {
    double rms_before = 0, rms_after = 0;  // weighted RMS over samples and channels
    int iterations = 0;
};

bool refine_scattered(const std::vector<ScatteredSample>& samples, const ScatteredOptions& o, Factored* f,
                      ScatteredResult* result, std::string* err);

}  // namespace sepal
