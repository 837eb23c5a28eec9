// The sampling strategies a user would otherwise pick, as sampler data for the one runtime
// API (runtime/include/sepal/sepal_sampler.h), so every strategy is compared through the
// same calls (the paper's Table 2 columns):
//   cosine      cosine-weighted hemisphere ("Unif.")
//   analytic    the model's own lobe where it has one: phong (Phong lobe about the mirror
//               direction), blinn (cos^n theta_h), lafortune (its lobes), ward and ward-duer
//               (Ward's anisotropic Gaussian in h), cook-torrance (Beckmann D cos theta_h),
//               ashikhmin-shirley (its lobe); each with a diffuse cosine lobe
//   lafortune   a best-fit multi-lobe Lafortune model ("Laf.": 2 lobes, 3 for Cook-Torrance
//               in the paper) sampled lobe by lobe
//   as          a best-fit Ashikhmin-Shirley model ("A&S"), sampled by its lobe
//   tabulated   Matusik 2003 ("Mat."): per view bin, CDFs of the dense BRDF slice
// Lobe mixture weights are fitted to f cos (luminance) by the same KL criterion as the
// factored sampler (a fixed-point EM over views; see refine_lobe_weights), so every lobe
// strategy gets its best mixture, not a guess.
//
// Usage:
//   sepal::SamplerData d; std::string err;
//   if (!sepal::make_analytic_sampler(*brdf, &d, &err)) ...   // err names the models that have a lobe
//   sepal::LobeFitReport rep;
//   sepal::fit_lafortune_sampler(*brdf, 2, &d, &rep, &err);    // rep.spec: the fitted model
//
// Fits (Lafortune, A-S): Levenberg-Marquardt (Eigen's unsupported module, numerical
// Jacobian) on log-parameters, minimizing the squared error of sqrt(f cos(theta_i))
// (luminance; a Hellinger distance, which weighs a lobe's shape and not only its peak: a
// plain L2 fit of f cos sampled Cook-Torrance 1000x worse) over a fixed set of pairs: views at 8 elevations (x 4 azimuths for anisotropic BRDFs),
// incident directions half uniform, half around the mirror direction (weighted back to
// uniform), from several fixed starts; the fitted model is built through make_brdf from
// its spec (no copied formulas). Deterministic.
#pragma once
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "sampling/factored_fit.h"
#include "sampling/sampler_file.h"

namespace sepal {

SamplerData make_cosine_sampler();

// False (with the models that have one) when the model has no analytic lobe.
bool make_analytic_sampler(const Brdf& brdf, SamplerData* out, std::string* err);

struct LobeFitReport {
    std::string spec;      // the fitted model, a make_brdf spec
    double rms = 0;        // RMS of the residual sqrt(f~ cos) - sqrt(f cos) over the pairs
    double rms_relative = 0;  // the same over the RMS of sqrt(f cos)
    int evaluations = 0;   // LM function evaluations over all starts
};
bool fit_lafortune_sampler(const Brdf& brdf, int lobes, SamplerData* out, LobeFitReport* rep,
                           std::string* err);
bool fit_as_sampler(const Brdf& brdf, SamplerData* out, LobeFitReport* rep, std::string* err);

struct TabulatedOptions {
    int n_theta_o = 32, n_phi_o = 16;   // views (n_phi_o is 1 in the view frame)
    int n_theta_i = 64, n_phi_i = 128;  // incident bins per view
    PhiFrame phi = PhiFrame::Auto;
    int supersample = 2;
    double defensive = 0.02;
    int threads = 0;
    bool progress = false;
};
bool make_tabulated_sampler(const Brdf& brdf, const TabulatedOptions& o, SamplerData* out,
                            std::string* err);

// Refits the weights of a LOBES sampler to f cos (luminance) by a fixed-point EM over a set
// of views (KL-optimal mixture weights; per-view lobe factors as the runtime applies them),
// then keeps the cosine lobe's share at >= floor at every view so the mixture covers the
// hemisphere.
void refine_lobe_weights(const Brdf& brdf, SamplerData* d, double floor = 0.02);

}  // namespace sepal
