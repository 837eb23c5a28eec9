// Homomorphic factorization (McCool, Ang and Ahmad 2001): f(wi, wo) ~= p(wi) q(h) p(wo),
// fitted in log space, from scattered samples or from any BRDF.
//
// Usage:
//   std::vector<sepal::BrdfSample> s;  brdf->scattered_samples(&s);   // raw measurements
//   // or: sepal::homomorphic_dense_samples(*brdf, o, &s, &err);      // any BRDF
//   sepal::HomomorphicOptions o;  o.res = 64;
//   sepal::Factored f;  sepal::HomomorphicStats st;  std::string err;
//   if (!sepal::factor_homomorphic(s, o, &f, &st, &err)) ...
//   glm::dvec3 v = sepal::evaluate(f, wi, wo);    // factored.h, reciprocal form
//
// The result is a Factored of form Reciprocal with param vh and the parabolic map: G = p
// (looked up at wo and again at wi), H = q (at the half vector h). Positive factors.
// The fit: log f = log p(wi) + log q(h) + log p(wo) is linear in the texels of log p and
// log q: each sample is one row holding the bilinear weights of its three lookups (the
// weights GL_LINEAR uses, applied to the logs, as the paper does), weighted by
// (luminance(f) cos theta_i)^weight_exponent (0: the paper's plain relative error; 1, the
// default, was measured best on the Cornell files: docs/homomorphic.md). Rows of a
// smoothness term, lambda times the 5-point Laplacian of each factor over its whole grid,
// give the texels no sample reaches (outside the hemisphere's disk, directions the
// measurement never took) the smooth extension of their neighbours; a tiny ridge fixes the
// one free constant (log p + c, log q - 2c). The sparse least-squares system is solved by
// Eigen's conjugate gradient on the normal equations, once per colour channel (PerChannel)
// or once for the luminance with a per-channel ratio (Luminance), like factor.h's modes.
// Values of f below floor * the channel's mean are raised to it (log 0 is not a number)
// and counted. Isotropic input (o.isotropic) is rotated about the normal `rotations` times:
// Cornell measures phi_i = 0 only, and without rotation p(wi) would be pinned along one
// line of its texture.
// A sum of K products (o.terms > 1, our extension, not the paper's) is fitted by
// backfitting: term k fits the floored positive part of f - sum_{j != k} f_j, a few
// sweeps; docs/homomorphic.md has what it buys.
// Determinism: one thread per channel at most, each solve sequential: equal inputs give
// equal factors whatever the thread count.
// Limits: res a power of two in 2..256; 1..kMaxHomomorphicSamples samples (before
// rotation); terms 1..4. Refused with a message: no samples, a non-finite or negative
// value, a non-unit or non-finite direction, every sample at or below the horizon.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "factor/factored.h"

namespace sepal {

constexpr size_t kMaxHomomorphicSamples = size_t(1) << 22;

struct HomomorphicOptions {
    int res = 64;                     // texels per side of p and q
    ColourMode colour = ColourMode::PerChannel;
    int terms = 1;                    // 1 = the paper; > 1 = a sum of products (backfitting)
    double smoothness = 0.05;         // lambda (relative: see homomorphic.cpp)
    // 2: rows of the 5-point Laplacian (the paper's); 1: first differences (a membrane:
    // unreached texels continue flat instead of along the slope at the data's edge).
    int smoothness_order = 2;
    double weight_exponent = 1.0;     // rows weighted by (luminance f cos theta_i)^this
    double weight_quantile = 0.99;    // ... with f cos clipped at this quantile of the rows
    double floor = 1e-3;              // of the channel's mean
    // Values above cap (per steradian) are clamped before fitting (<= 0: none), counted:
    // a measured mirror peak hundreds of times the rest (cayman: 627/sr against a median
    // of 0.003) would otherwise set the factors' range, and an 8-bit product cannot hold it.
    double cap = -1;
    // The bake's cap (<= 0: none): its radiance fit's white level, the f cos theta_i every
    // judged view shows as white, applied to f itself (f >= f cos theta_i). Capping f cos
    // theta_i instead (f at white / cos theta_i) left p 1 / cos theta large at grazing: 11
    // framebuffer doublings and 21.0 dB on gles1 for ward at 32x32, against 1 and 23.9 dB.
    double white = -1;
    bool isotropic = true;            // rotate samples about the normal
    int rotations = 16;               // when isotropic (1: none)
    int max_iterations = 3000;        // conjugate gradient, per solve
    double tolerance = 1e-9;          // conjugate gradient, relative residual
    int backfit_sweeps = 4;           // terms > 1
    // Gauss-Newton steps on the rendered model (bilinear of p, not exp of bilinear of log p)
    // after the paper's linear log-space solve; 0: the paper's solution as it is.
    int polish_iterations = 0;
    int threads = 0;
};

struct HomomorphicStats {
    int64_t samples = 0;       // given
    int64_t rows = 0;          // data rows after rotation (samples above the horizon x rotations)
    int64_t floored = 0;       // values raised to the floor (per channel)
    int64_t capped = 0;        // samples with a value clamped at the cap
    int64_t below_horizon = 0;  // samples dropped: a direction at or below the horizon
    int unreached_p = 0, unreached_q = 0;  // texels no sample weights (the smoothness fills them)
    int iterations = 0;        // conjugate-gradient iterations, all solves
    double log_rms = 0;        // weighted RMS of the log-space residual at the data rows
    double seconds = 0;
};

bool validate_homomorphic_options(const HomomorphicOptions& o, std::string* err);

bool factor_homomorphic(const std::vector<BrdfSample>& samples, const HomomorphicOptions& o, Factored* out,
                        HomomorphicStats* stats, std::string* err);

// Samples of any BRDF for the fit: `per_texel` pairs per valid texel of p and of q, with h
// and wo uniform over the parabolic map's disk (every texel of both factors gets about the
// same number of rows; wi = the reflection of wo about h, pairs below the horizon redrawn),
// from a fixed seed. False with a message on a non-finite BRDF value.
bool homomorphic_dense_samples(const Brdf& brdf, int res, int per_texel, std::vector<BrdfSample>* out,
                               std::string* err);

}  // namespace sepal
