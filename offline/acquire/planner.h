// The view planner of Lensch et al. 2003: after each capture, the camera/light pair that most
// reduces the parameter uncertainty over the surface; and the baselines it is measured
// against.
//
// Usage:
//   sepal::PlanState st;  sepal::init_plan_state(obj, &st);          // prior estimates everywhere
//   for (int k = 0; k < 20; ++k) {
//       sepal::ViewPair v = sepal::plan_next_view(obj, rig, popt, k, &st, &stats);
//       captures.push_back(...capture_atlas(obj, truth, v, rig, seed + k, ...)...);
//       sepal::set_estimates(...);   // from the clusters' fits (reconstruct.h), optional
//       sepal::accumulate(obj, captures, rig, &st);
//   }
//   sepal::UncertaintySummary u = sepal::summarize(st, rig_rank_threshold);
//
// Model (the paper's section 7.3): per texel a grey isotropic one-lobe Lafortune model,
// L = 4 parameters b = (rho_d, Cxy, Cz, n), at the current estimate b^ (the texel's cluster
// fit). Every sample adds w^2 g g^T to the texel's Hessian H (Appendix A: H = J^T J), with
// g = df/db^ and w = the sample's weight (capture.h: 1 / std). We measure g in relative units
// (df/db_j times max(|b_j|, floor)), so that the exponent n (~10..100) does not swamp rho_d
// (~0.3) in the norm: H^-1 is then the covariance of the parameters' relative errors.
// Rank: eigenvalues of H above rank_threshold count as measured (0.01: the data pin that
// direction within a relative standard deviation of 10, an order of magnitude), the paper's
// "rank" made noise-aware: its exact rank of a sum of rank-1 terms is full after 4 samples
// even when 3 derivatives are ~0 away from highlights (its section 8), ours needs the
// highlight. How well a measured direction is known is ||CoV||: the Frobenius norm of the
// pseudo-inverse over the measured directions (the paper found 2-norm and Frobenius
// equivalent, Fig. 4; Frobenius has a closed-form rank-1 update).
// A candidate's effect on a texel is evaluated in the eigenbasis of its H (computed once per
// step): with z = V^T row, the new rank follows from the inertia of D + z z^T - threshold
// (interlacing: it rises by at most one, and does when 1 + sum z_i^2 / (d_i - threshold) < 0),
// and the new ||CoV||_F by Sherman-Morrison on the measured block (exact at full rank; at
// lower rank the coupling to unmeasured directions is ignored and a newly measured direction
// enters with eigenvalue max(threshold, d + z^2)). About 100 ns per texel and candidate.
// Objective (eq. 4 with section 5's rank-gain handling): per texel the uncertainty
//   U(H) = inf (1 + base + ... + base^(L-k-1)) + ||CoV||_F      (k = rank, inf = 1e3)
// so gaining rank is worth far more than any reduction within a rank. base = 1 (default):
// every rank gained is worth inf, the paper's F = Inf - s_k (its Fig. 3a); base = 10: its
// Fig. 3b, 10^(L-k) (Inf - s_k), which favours texels of low rank. On our objects base 1
// brings more texels to full rank (the bench measures both). The objective of a
// candidate view is the sum over texels of U(H) - U(H + w^2 g g^T) over the texels it would
// measure (visible, lit, within the rig's angles); zero when camera and light are closer than
// min_separation_deg (section 6.2).
// Search (section 5.1): sphere_points positions on a Fibonacci sphere, rotated at random
// before each view, for the camera and for the light; every pair is evaluated; then the
// best pair is refined by Nelder-Mead (the paper's simplex) in the tangent planes of its two
// positions for refine_evaluations evaluations. Deterministic for a seed; results do not
// depend on the thread count.
// Baselines: random_view (camera and light uniform on the sphere, at least the minimum
// separation apart) and expert_view (a fixed ring: the camera at 20 degrees elevation
// stepping evenly round, the light 40 degrees of azimuth beside it at 50 degrees elevation,
// alternating sides; each lap offset by half a step).
// Limits: the planner's model has 4 parameters; atlases up to 1024^2 texels.
#pragma once
#include <cstdint>
#include <vector>

#include "acquire/capture.h"
#include "acquire/object.h"
#include "fit/lafortune_fit.h"

namespace sepal {

constexpr int kPlanParams = 4;

struct PlannerOptions {
    int sphere_points = 16;       // discrete positions for the camera and for the light
    int refine_evaluations = 60;  // Nelder-Mead evaluations after the discrete search (0: none)
    double rank_threshold = 0.01; // eigenvalues of the relative Hessian counted as measured
    double rank_base = 1;         // 1: F = Inf - s_k (Fig. 3a); 10: 10^(L-k) (Inf - s_k) (Fig. 3b)
    double inf = 1e3;
    int threads = 0;
    uint64_t seed = 1;
};

// Per texel (compact: the atlas's valid texels in order).
struct PlanState {
    std::vector<int> texels;               // atlas texel of each entry
    std::vector<LafortuneModel> estimate;  // grey, one isotropic lobe
    std::vector<double> H;                 // 10 per texel: upper triangle, row-major
    // Derived by prepare_plan_state():
    std::vector<double> eigval;            // 4 per texel: eigenvalues of H, ascending
    std::vector<double> eigvec;            // 16 per texel: eigenvectors (columns, row-major)
    std::vector<int> rank;
    std::vector<double> cov_norm;          // ||CoV||_F over the measured directions
    std::vector<double> uncertainty;       // U(H)
    std::vector<double> smallest;          // largest singular value of CoV (1 / smallest measured eigenvalue of H), 0 at rank 0
    std::vector<int> index_of;             // atlas texel -> entry, -1 for invalid texels
    double threshold = 0.01, base = 1, inf = 1e3;
};

// The paper's one-pixel example parameters as the prior of every texel: rho_d 0.3, n 10,
// Cxy -0.8, Cz 0.8 (Lensch et al. Fig. 3).
LafortuneModel plan_prior();

void init_plan_state(const AcqObject& obj, const PlannerOptions& options, PlanState* st);
// Sets the estimate of every texel (grey, one isotropic lobe; by atlas texel index).
void set_estimates(const std::vector<LafortuneModel>& per_texel, PlanState* st);
// H of every texel from all captures at the current estimates, then prepare_plan_state.
void accumulate(const std::vector<Capture>& captures, const RigOptions& rig, PlanState* st, int threads = 0);
void prepare_plan_state(PlanState* st, int threads = 0);

// The predicted measurement row of a texel for a view (relative units, times the weight),
// false when the view does not measure it.
bool predicted_row(const PlanState& st, int entry, const glm::vec3& wi, const glm::vec3& wo, double E,
                   const RigOptions& rig, double row[kPlanParams]);

// The objective of a view whose camera and light see `cam` and `light` (object.h), over
// entries [begin, end).
double view_gain(const PlanState& st, const PointView& cam, const PointView& light, double intensity,
                 const RigOptions& rig, size_t begin, size_t end);

struct PlanStats {
    int evaluations = 0;        // objective evaluations (discrete + refinement)
    double discrete_best = 0;   // objective of the best discrete pair
    double objective = 0;       // of the chosen view
    double seconds = 0;
};

ViewPair plan_next_view(const AcqObject& obj, const RigOptions& rig, const PlannerOptions& options, int step,
                        const PlanState& st, PlanStats* stats = nullptr);

ViewPair random_view(const RigOptions& rig, uint64_t seed, int step);
ViewPair expert_view(int step, int views_per_lap = 9);

struct UncertaintySummary {
    int texels = 0;
    int by_rank[kPlanParams + 1] = {};
    double mean_largest_cov[kPlanParams + 1] = {};  // mean largest singular value of CoV per rank (Table 2)
    double full_rank_share = 0;
    double mean_log_cov_full = 0;  // mean log10 ||CoV||_F over full-rank texels
    // Mean log10 ||(H + threshold I)^-1||_F over all texels: the uncertainty with a prior of
    // relative std 10 on every direction, so unmeasured texels count too.
    double mean_log_cov_all = 0;
    double total_uncertainty = 0;  // sum of U
};
UncertaintySummary summarize(const PlanState& st);

// Eigenvalues (ascending) and optionally eigenvectors (columns of V, row-major 4x4) of a
// symmetric 4x4 given as its upper triangle (10 values), by cyclic Jacobi.
void sym4_eigen(const double upper[10], double lambda[4], double* V = nullptr);

}  // namespace sepal
