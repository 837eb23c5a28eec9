// Fitting a Lafortune model to scattered BRDF samples, with the parameters' covariance
// (Lensch et al. 2003, section 4; NOTES.md section 5).
//
// Usage:
//   std::vector<sepal::BrdfSample> s = ...;           // (wi, wo, value, weight) each
//   sepal::LafortuneFitOptions o;                       // 1 isotropic lobe, RGB diffuse
//   sepal::LafortuneFit r; std::string err;
//   if (!sepal::fit_lafortune(s, o, &r, &err)) { ... err says what is wrong ... }
//   r.model.spec();        // "lafortune:rho_d=0.31/0.2/0.1,lobe=-0.8/-0.8/0.8/20": make_brdf rebuilds it
//   r.ci95(j);             // half-width of parameter j's 95% interval (1.96 sqrt(cov_jj))
//
// The model is the `lafortune` spec of brdf_models.h with white lobes:
//   f_c(wi, wo) = rho_d_c / pi + sum_k max(0, Cx_k x_i x_o + Cy_k y_i y_o + Cz_k z_i z_o)^n_k
// Parameters, in this order: rho_d (1 value with channels = 1, 3 with channels = 3), then per
// lobe Cxy, Cz, n (isotropic, Cx = Cy = Cxy) or Cx, Cy, Cz, n. A lobe's strength is carried
// by |C| (w = 1): a separate weight would be degenerate with it (w c^n = (w^(1/n) c)^n).
// Coloured lobes are not fitted: specular highlights of dielectrics take the light's colour,
// and a colour per lobe would need that weight back. tint_lafortune_lobes adds one colour for
// the lobes after the fit, with the lobes' shape held (a linear problem per channel).
//
// The fit: weighted least squares, Q = sum_s sum_c (weight_s (f_c(s) - value_s,c))^2, by
// Levenberg-Marquardt (normal equations, Marquardt's scaling, analytic Jacobian) from the best of a
// small grid of starts (lobe shape Cxy/Cz and exponent n on a grid, rho_d and the lobe's
// scale by linear least squares at each; lobes added greedily).
// Covariance: cov = s^2 (J^T J)^+ at the minimum (J the weighted Jacobian), s^2 = Q / (m - p)
// estimated from the residual (m residuals, p parameters), or sigma^2 when the caller knows
// the noise (options.sigma > 0; weights are then 1/std of each sample). The inverse is the
// SVD pseudo-inverse over the directions the data determine: `rank` counts the singular
// values of J (columns scaled to unit norm, so the count does not depend on units; a column
// that is exactly zero stays unmeasured) above kRankTolerance times the largest. A rank below p means some
// parameter combination is not measured (no sample in a highlight, say): its variance is
// reported as infinite, never as a small number.
// The intervals are the linearized ones: tests/offline/fit/lafortune_fit_test.cpp checks
// that they hold their 95% in 200 random trials (per parameter and jointly).
//
// Limits: 1..4 lobes; at least p + 1 samples with positive weight; samples must be finite
// with directions above the horizon (z > 0) and weights >= 0; values may be negative
// (noise). The fitted model may leave the spec's ranges (n < 0 in a rank-deficient fit):
// model.spec() clamps into them and `clamped` says so.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <glm/vec3.hpp>

#include "brdf/brdf.h"          // BrdfSample
#include "factor/factored.h"  // luminance(): the grey channel of channels = 1 fits

namespace sepal {

struct LafortuneLobe {
    double cx = -1, cy = -1, cz = 1, n = 20;
    // Per-channel weight (the spec's lobe=Cx/Cy/Cz/n/r/g/b). fit_lafortune fits white lobes
    // (1, 1, 1: not parameters, and the covariance is of those); tint_lafortune_lobes colours
    // them afterwards, for a material whose highlight is coloured (metals, metallic paints).
    glm::dvec3 colour{1.0};
};

struct LafortuneModel {
    glm::dvec3 rho_d{0.2};
    std::vector<LafortuneLobe> lobes;
    // The lobes' sum at (wi, wo), without the diffuse term; both directions above the horizon.
    double lobe_sum(const glm::dvec3& wi, const glm::dvec3& wo) const;
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const;
    // A `lafortune` spec (brdf_models.h), values clamped into its ranges; *clamped (if given)
    // is set when a value had to be.
    std::string spec(bool* clamped = nullptr) const;
};

struct LafortuneFitOptions {
    int lobes = 1;         // 1..4
    bool isotropic = true;  // Cx = Cy per lobe
    int channels = 3;      // 3: rho_d per channel; 1: one grey value (samples' luminance)
    // > 0: the noise is known, weight = 1 / (sigma_s / sigma) per sample: the covariance
    // uses sigma^2 instead of the residual's estimate.
    double sigma = -1;
    // Start here instead of the grid (per-texel fits start from their cluster's model).
    const LafortuneModel* start = nullptr;
    int max_evaluations = 400;  // function evaluations of the LM solver
    // Keep the fit a diffuse colour and forward lobes: rho_d >= 0, Cx, Cy <= 0, Cz >= 0,
    // n >= 1 (projected steps: each trial step is clamped into the bounds, and the grid's
    // starts keep to them). Clamped, not solved without the bound parameters: near a bound the
    // solver can stop short of the constrained minimum (taking them out of the system reached
    // other minima, and the acquisition bench's expert sphere rendered 3.4 dB worse). The
    // covariance stays the unconstrained one: a parameter that ends on its bound gets an
    // interval reaching past it. A lobe with Cz < 0 lives only at grazing angles, and one
    // with Cx, Cy > 0 is a retro-reflection; fitted to sparse captures, such lobes can explain
    // a few samples while creating energy where none was measured. Off: the model's full
    // range (Lafortune's retro and grazing lobes, a negative diffuse term a lobe makes up).
    bool forward = false;
};

// Why the Levenberg-Marquardt solver stopped (LafortuneFit::lm_status): converged on the
// cost's relative reduction or on the step's relative size (both below sqrt(eps)), a zero
// gradient, the evaluation budget spent, or no finite step left to take.
enum LmStop { kLmCost = 1, kLmStep = 2, kLmGradient = 4, kLmBudget = 5, kLmStuck = 6 };

// Singular values of the scaled Jacobian below this times the largest count as unmeasured.
constexpr double kRankTolerance = 1e-6;

struct LafortuneFit {
    LafortuneModel model;
    std::vector<std::string> names;  // per parameter: "rho_d", "rho_d.r", "lobe1.Cxy", ...
    Eigen::VectorXd params;          // in the order above
    Eigen::MatrixXd cov;             // p x p; +inf on the diagonal of unmeasured directions
    int rank = 0;                    // of the scaled Jacobian (p: every parameter measured)
    int samples = 0;                 // with positive weight
    int residuals = 0;               // samples x channels
    double rss = 0;                  // weighted residual sum of squares Q
    double sigma = 0;                // noise scale used for cov (estimated or given)
    double rms = 0;                  // unweighted RMS of f - value over residuals
    int evaluations = 0;             // model evaluations of the LM solver
    int lm_status = 0;               // why the solver stopped, for the best start: an LmStop
    bool clamped = false;            // model.spec() had to clamp (see Limits)
    double ci95(int j) const;        // 1.959964 sqrt(cov(j, j)); inf when unmeasured
};

bool fit_lafortune(const std::vector<BrdfSample>& samples, const LafortuneFitOptions& options,
                   LafortuneFit* out, std::string* err);

// Colours the lobes of a fitted model: per channel c, weighted least squares of
// value_c - rho_d,c / pi ~= t_c L(wi, wo) over the samples (L: the model's white lobe sum, its
// shape, exponent and the diffuse term held; t_c >= 0), then every lobe's colour = t. For
// metals and metallic paints, whose highlights take the material's colour. false (model
// unchanged) when the samples do not determine it (no sample where the lobe is non-zero).
bool tint_lafortune_lobes(const std::vector<BrdfSample>& samples, LafortuneModel* model);

// Whether a fitted model can stand for a material: its spec renders it as fitted (spec()
// clamps nothing: a negative diffuse colour that a lobe made up for does not) and its
// directional albedo stays <= kPlausibleAlbedo at incidence 0..89 degrees, any channel (no
// created energy: a lobe fitted where no sample was, such as one living only at grazing
// angles, fails it). *albedo (optional): the largest albedo found (+inf when the spec does
// not build). Cost: about 1.5 million model evaluations.
constexpr double kPlausibleAlbedo = 1.1;
bool lafortune_plausible(const LafortuneModel& m, double* albedo = nullptr);

// Parameter vector <-> model, with the layout of fit_lafortune (channels, lobes, isotropic).
Eigen::VectorXd lafortune_params(const LafortuneModel& m, int channels, bool isotropic);
LafortuneModel lafortune_from_params(const Eigen::VectorXd& p, int channels, int lobes, bool isotropic);
std::vector<std::string> lafortune_param_names(int channels, int lobes, bool isotropic);

// d f / d params at one direction pair for a grey (channels = 1) isotropic model, the
// planner's 4 derivatives of Lensch et al. Appendix A (rho_d, Cxy, Cz, n per lobe); with
// f = rho_d / pi the first is 1 / pi. grad must hold 1 + 3 lobes values.
void lafortune_gradient_grey_iso(const LafortuneModel& m, const glm::dvec3& wi, const glm::dvec3& wo,
                                 double* grad);

}  // namespace sepal
