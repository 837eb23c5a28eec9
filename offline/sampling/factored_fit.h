// The sampling factorization of Lawrence, Rusinkiewicz and Ramamoorthi 2004: a BRDF times the
// cosine, as a density over a reparameterized incident direction wp for each view wo,
//   q(wp | wo) = f(wi, wo) cos(theta_i) |dwi/dwp|  ~=  sum_l F_l(wo) u_l(theta_p) v_l(phi_p),
// fitted by two levels of KL non-negative matrix factorization, stored as a FACTORED sampler
// (runtime/include/sepal/sepal_sampler.h).
//
// Usage:
//   sepal::FactoredOptions o;  o.J = 4; o.K = 1;          // the paper's Cook-Torrance row
//   sepal::SamplerData d; sepal::FactoredReport rep; std::string err;
//   if (!sepal::fit_factored(*brdf, o, &d, &rep, &err)) ...
//   sepal::write_sampler("ct.smp", d, &err);
//
// Method (docs/sampling.md has the derivation and the measurements behind each default):
//   1. Data matrix Y: rows are wp bins (n_theta_p x n_phi_p; theta bins uniform in theta, or
//      in sqrt(theta) with sqrt_theta; phi bins uniform), columns are views at the centres
//      of an n_theta_o x n_phi_o grid. An entry is the bin's MASS of q: the mean of q over
//      S x S points of the bin, uniform in (cos theta, phi), times its solid angle. Masses
//      keep separability (dOmega = dz dphi) and make KL the sampling-efficiency measure.
//   2. Y ~= G F (J terms), then each column of G, as an n_theta_p x n_phi_p matrix, ~= u v^T
//      (K terms); u and v normalized to unit mass become CDFs, their norms go into F
//      (eq. 6-8), L = J K terms.
//   3. Colour: f_c / f_lum ~= a_c(wo) b_c(theta_p) c_c(phi_p), fitted to the channel masses
//      (for eval); luminance is what is sampled.
//   0. With separate_diffuse, the Lambert floor D = estimate_diffuse(f) is taken out first:
//      the terms fit (f - D) cos and the sampler mixes in cosine samples for D.
// Two choices differ from the paper (both measured in the bench, both switchable):
//   - jacobian: q includes |dwi/dwh| = 4 (wi.h), so a perfect fit samples f cos exactly;
//     the paper factors f cos and samples it as a density in h (off by 1/(4 wi.h)).
//   - phi frame: for isotropic BRDFs phi_p is measured from phi_o, so F depends on theta_o
//     only (n_phi_o = 1); anisotropic BRDFs keep the paper's absolute phi.
// Limits: view grid 1..128 per side, direction bins 1..1024 per side, J, K >= 1 with
// J K <= 64, supersample 1..8. A BRDF returning NaN or inf fails with the pair named.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "sampling/sampler_file.h"

namespace sepal {

enum class SampleParam { Auto, Half, Incident };
// The coordinates wp is binned in (sepal_smp_axis): polar about the normal (the paper's), or
// angles about the tangent t or the bitangent s, where anisotropic lobes separate; the view
// axes (half vector only) measure the angle about t or s from half the view's own, the
// mirror axes (incident direction only) centre wi.t or wi.s on the mirror cone of wo
// (sepal_smp_axis has the definitions).
enum class SampleAxis { Auto, Normal, Tangent, Bitangent, TangentView, BitangentView, TangentMirror, BitangentMirror };
// "auto", "n", "t", "s", "t-view", "s-view", "t-mirror", "s-mirror"
const char* sample_axis_name(SampleAxis a);
bool parse_sample_axis(const std::string& s, SampleAxis* a);
enum class PhiFrame { Auto, Absolute, View };
const char* sample_param_name(SampleParam p);  // "auto", "half", "incident"
bool parse_sample_param(const std::string& s, SampleParam* p);
const char* phi_frame_name(PhiFrame f);        // "auto", "absolute", "view"
bool parse_phi_frame(const std::string& s, PhiFrame* f);

struct FactoredOptions {
    // auto: fits both and keeps the one whose estimator f cos / pdf has the lower relative
    // variance at the judge views (metrics.h): half wins on glossy materials, incident on
    // diffuse-like ones, as the paper chose by hand.
    SampleParam param = SampleParam::Auto;
    PhiFrame phi = PhiFrame::Auto;
    // auto: the normal for isotropic BRDFs; anisotropic ones also try h about t and s and wi
    // about the mirror axes of t and s, ranked by coarse fits (the lowest relative variance
    // is fitted). Ward picks h about s, Poulin-Fournier wi about t's mirror axis.
    SampleAxis axis = SampleAxis::Auto;
    // View grid (n_phi_o becomes 1 in the view frame); 0: 16 x 16, and 20 x 24 about the
    // mirror axes, where the term weights change faster with phi_o (Poulin-Fournier's
    // normalized MAE 0.147 at 16 x 16 and at 24 x 20, 0.132 at 20 x 24; 59 KB).
    int n_theta_o = 0, n_phi_o = 0;
    // wp bins (c1 x c2). Defaults measured (bench ablation): 64 bins uniform in sqrt(theta)
    // resolve sharp highlights near the pole (nickel: 8x less variance than 32 uniform bins)
    // and cost nothing on diffuse-like BRDFs; the paper used 32 to 128 uniform bins.
    // 0: 64 about the normal, 192 about t or s (Ward ay = 0.02 is 0.02 wide in c1).
    // n_phi_p 0: 16 for isotropic BRDFs, 64 for anisotropic ones about the normal (Ward
    // ay = 0.02: 16 bins gave 6x the variance), 96 about t or s.
    int n_theta_p = 0, n_phi_p = 0;
    // Outer and inner terms; 0: 4 x 2 for isotropic BRDFs, 2 x 4 for anisotropic ones about
    // the normal (the paper's Figure 6: an anisotropic lobe needs >= 2 inner terms), 16 x 1
    // about t or s (the lobe separates there; its shape across views needs the outer terms).
    int J = 0, K = 0;
    bool sqrt_theta = true;            // c1 bins uniform in sqrt(theta) (dense near alpha = 0 about t, s)
    bool jacobian = true;
    int supersample = 3;               // S: S x S points per wp bin
    // NMF iteration cap (each level); 0: 2000 about the normal, 500 about t or s, where the
    // level-1 matrix is 16x larger (18,432 x 256, 16 terms) and iterations past 500 lower the
    // estimator's relative variance by under 2% (Ward: 0.01568 at 700, 0.01542 at 2000, 0.01654
    // at 300) for 4x the fit time.
    int iterations = 0;
    double tolerance = 1e-6;
    double defensive = 0.02;           // share of cosine samples (unbiasedness)
    // The Lambert floor D (estimate_diffuse: a low quantile of f) kept out of the terms and
    // sampled by cosine samples in proportion to its albedo (format 1.1): under a sun,
    // a paint's diffuse part is sampled as well as cosine sampling does (docs/sampling.md).
    bool separate_diffuse = true;
    bool colour = true;                // fit and store the colour ratio (for eval)
    uint64_t seed = 1;
    int threads = 0;
    bool progress = false;
};

bool validate_factored_options(const FactoredOptions& o, std::string* err);

struct FactoredReport {
    std::string param, phi_frame;       // as used ("half" or "incident", "view" or "absolute")
    std::string axis;                   // as used: "n", "t" or "s"
    int n_theta_o = 0, n_phi_o = 0, n_theta_p = 0, n_phi_p = 0, J = 0, K = 0;
    int64_t evaluations = 0;
    double sample_seconds = 0, factor_seconds = 0;
    double kl_level1 = 0, kl_level2 = 0;  // relative KL divergence of each level's fit
    double kl_total = 0;  // KL(data || the stored sampler's reconstruction) / data mass
    double relative_variance = -1;  // param auto: the winner's (metrics.h); -1 when not measured
    int iterations1 = 0, iterations2 = 0;
    double dense_bytes = 0;             // the data matrix Y in float32
    size_t sampler_bytes = 0;           // the encoded sampler file
    std::vector<std::string> notes;
};

bool fit_factored(const Brdf& brdf, const FactoredOptions& o, SamplerData* out, FactoredReport* rep,
                  std::string* err);

// cos(theta) bin edges, from 1 down to exactly 0: n bins uniform in theta, or in sqrt(theta).
std::vector<float> theta_bin_z_edges(int n, bool sqrt_theta);
// Edges of c1 = sin(alpha) about a tangent axis, from 1 down to exactly -1: n bins uniform
// in alpha, or (dense) in sign(alpha) sqrt(|alpha|), fine near alpha = 0.
std::vector<float> axis_bin_edges(int n, bool dense);

// Luminance of linear RGB (Rec. 709 weights): what the samplers follow.
double luminance(const glm::dvec3& rgb);

}  // namespace sepal
