// Linear models of the BRDF database (database.h): PCA in linear and log space, and the
// linear-combination-of-all-materials model of Matusik et al. 2003, section 7 (P c ~= b).
//
// Usage:
//   // Error vs dimension (in-sample, or leave-one-out: the PCA of the other K-1 materials):
//   std::vector<double> e = sepal::pca_projection_errors(db->gram(), K, k, true, 60, nullptr);
//   // Fit a new material from samples at database rows (a plan), write it out:
//   sepal::CombinationFit fit;
//   sepal::fit_combination(*db, rows, values, columns, sepal::FitOptions{}, &fit, &err);
//   std::vector<float> b = sepal::combination_values(*db, fit.coeffs);   // 3 per valid cell
//
// PCA works on the database's Gram matrices: materials are the samples, (cell, channel) rows the
// dimensions; the mean material is removed first. The residual of a material after d
// components is exact (no pass over the grid) and returned as a squared norm in the space's
// units (1/sr for linear; log(f + eps) for log); callers normalise (relative RMS: divide by
// the material's squared norm, G_kk; log RMS: divide by the row count).
//
// The combination model, in one of two spaces (FitOptions::space):
// - FitSpace::kLog (the default): log(f + eps) = sum_j c_j log(f_j + eps) + d_channel, eps =
//   kDatabaseLogEps, samples weighted by cos theta_i. In log space a sample's residual is a
//   relative error, so the body colour counts as much as the highlight (in linear space the
//   few specular samples decide the fit and the body comes back the wrong colour); the cosine
//   weights them as the picture does (f cos theta_i is what a light shows); the per-channel
//   offsets d are a colour scale, which the database's colours alone cannot give. Signed
//   coefficients are safe: exp keeps every value positive. Rendered leave-one-out
//   reconstructions (100 materials, 800 planned samples, docs/measure.md): median 42 dB and
//   mean CIEDE2000 1.3, against 21 dB and 15 for the paper's linear fit.
// - FitSpace::kLinear (Matusik et al. 2003, section 7): f = sum_j c_j f_j. Columns are
//   scaled to unit norm over the whole grid so that conditioning measures the geometry of
//   the sample set, not the materials' brightness; rows weighted 1/sigma (FitOptions::
//   weighted). Solver::kNonNegative keeps coefficients >= 0 (Lawson-Hanson active set), hence
//   every value >= 0; Solver::kLeastSquares is the paper's pseudo-inverse, whose output can go
//   negative (combination_values counts it, the MERL writer clamps).
// Both: least squares on the samples with Tikhonov regularisation chosen from the condition
// number (lambda = 0 while cond(X^T X) <= max_condition of the column-normalised system, else
// the lambda that brings it to max_condition).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "database/database.h"

namespace sepal {

// Eigenvalues (descending) of the centred K x K Gram: the PCA variances of the K materials.
std::vector<double> pca_variances(const double* gram, int K);

// Squared residual of material k after projection onto the mean + first d principal
// components, for d = 0..max_dims (capped at the components available). leave_out: the PCA
// is that of the other K-1 materials (how well the database generalises to a new one).
// `use` (optional, size K): only materials with use[j] != 0 take part.
std::vector<double> pca_projection_errors(const double* gram, int K, int k, bool leave_out,
                                          int max_dims, const std::vector<uint8_t>* use);

// How far a new material is expected to stray from the database's span, per row: the
// leave-one-out residual of every database material j in use, r_j = p_j - P_{-j} c_j (the best
// full-grid least-squares fit of j by the others, from the Gram matrix), relative to |p_j|;
// sigma^2(row) = mean over j of r_j(row)^2, floored at 1% of its grid mean. Rows where the
// materials are idiosyncratic (grazing angles, where the neural fits extrapolate) get a large
// sigma; weighting a fit by 1/sigma^2 (generalized least squares) keeps them from dragging the
// coefficients, and planning on rows scaled by 1/sigma picks samples that generalise.
struct ResidualModel {
    int K = 0;
    std::vector<double> R;  // K x K row-major: sigma^2(row) = |P_row R|^2 / n_used + floor
    double n_used = 0, floor = 0, grid_mean = 0;
};
ResidualModel residual_model(const BrdfDatabase& db, const std::vector<uint8_t>& use);
// sigma^2 of each of `rows` (pool or grid row indices), in one matrix product per block.
std::vector<double> row_sigma2(const BrdfDatabase& db, const ResidualModel& m, const std::vector<size_t>& rows);
// The floor of any reconstruction from the database: for each material (in `use`), the
// relative RMS over the whole grid of its best least-squares fit by the other materials
// (the residual model's r_j; 0 for materials not in use).
std::vector<double> loo_oracle_errors(const BrdfDatabase& db, const std::vector<uint8_t>& use);

enum class Solver { kNonNegative, kLeastSquares };
enum class FitSpace { kLog, kLinear };
const char* fit_space_name(FitSpace s);  // "log", "linear"

struct FitOptions {
    // Log space by default (above): the linear fit's renders are wrong (leave-one-out median
    // 21 dB, Delta E 15: gold paint comes back pinkish grey).
    FitSpace space = FitSpace::kLog;
    // Non-negative by default, for the image: signed least squares fits the peaks better
    // (leave-one-out median relative RMS 4.8% against 9.9%, 100 materials, 800 samples) but
    // cancels wildly off the peak, and its renders are wrong (PSNR 8.6 and 10.6 dB for
    // alum-bronze and specular-orange-phenolic against 24.6 and 21.4 dB non-negative;
    // sepal-bench-database). kLeastSquares is the paper's pseudo-inverse (--solver ls).
    // Linear space only (log-space coefficients are signed).
    Solver solver = Solver::kNonNegative;
    // Regularisation: none while the condition number of the column-normalised normal
    // matrix is at most this; above it, lambda brings it down to this value. 1e5 measured
    // best over 1e3 .. 1e6 (sepal-bench-database, leave-one-out at 800 samples).
    double max_condition = 1e5;
    // Linear space only. Generalized least squares: rows weighted by 1/sigma^2 of the
    // residual model (default). false: the paper's plain least squares.
    bool weighted = true;
};

struct CombinationFit {
    FitSpace space = FitSpace::kLinear;
    // K (one per database material; 0 for unused ones): 1/sr units in linear space, exponents
    // in log space.
    std::vector<double> coeffs;
    double offsets[3] = {0, 0, 0};  // log space: d per channel (R, G, B)
    double condition = 0;        // of the column-normalised X^T X, before regularisation
    double lambda = 0;           // Tikhonov weight used (on the normalised system)
    double sample_rms = 0;       // relative RMS residual on the samples (linear units, unweighted)
    int nonzero = 0;             // coefficients != 0
    int solver_iterations = 0;   // NNLS outer iterations (0 for least squares)
};

// Fits b ~= sum_j c_j P[row, j] over the materials with use[j] != 0 (use empty: all).
// rows: database rows (3 * valid cell + channel); values: the measured BRDF there (1/sr).
bool fit_combination(const BrdfDatabase& db, const std::vector<size_t>& rows,
                     const std::vector<double>& values, const std::vector<uint8_t>& use,
                     const FitOptions& opt, CombinationFit* fit, std::string* err);

// The fits' Tikhonov weight for a symmetric matrix of extreme eigenvalues lo and hi: 0 while
// hi / lo <= max_condition, else the lambda that brings (hi + lambda) / (lo + lambda) to it.
double ridge_for_condition(double lo, double hi, double max_condition);

// Condition number of the column-normalised X^T X of these rows (the plan's figure of merit):
// in linear space with `weighted`, rows scaled by 1/sigma; in log space the log model's
// design (log values and channel indicators, times cos theta_i): the system fit_combination solves.
double plan_condition(const BrdfDatabase& db, const std::vector<size_t>& rows,
                      const std::vector<uint8_t>& use, bool weighted = true, FitSpace space = FitSpace::kLinear);

// The log model's weight of a database row: cos theta_i of its cell's bin centre (>= 1e-3).
double log_row_weight(const BrdfDatabase& db, size_t row);
// One row of the log model's design, the system fit_combination solves in log space and the
// planner plans for: out[j] = log(values[cols[j]] + eps) w for the materials in cols, then the
// three channel indicators times w (cols.size() + 3 values). values: every material's value at
// the row (K floats, as BrdfDatabase::pool_row holds them). Returns w = log_row_weight.
double log_design_row(const BrdfDatabase& db, size_t row, const float* values, const std::vector<int>& cols,
                      double* out);

// The fitted model over every row (3 per valid cell), in float; *negative counts values below
// 0 (linear) or below the log model's floor (exp(s) < eps; both are returned as they are).
std::vector<float> fit_values(const BrdfDatabase& db, const CombinationFit& fit, size_t* negative = nullptr,
                              int threads = 0);
// P c over every row (3 per valid cell), in float; *negative counts values below 0.
std::vector<float> combination_values(const BrdfDatabase& db, const std::vector<double>& coeffs,
                                      size_t* negative = nullptr, int threads = 0);

// Relative RMS over the whole grid of P c against database material k, exactly, from the
// Gram matrix: sqrt((c - e_k)^T G (c - e_k) / G_kk). Linear-space coefficients only.
double combination_error_gram(const BrdfDatabase& db, const std::vector<double>& coeffs, int k);

// Relative RMS over all rows of `approx` against `truth` (both 3 per valid cell).
double relative_rms(const std::vector<float>& approx, const std::vector<float>& truth);

// Non-negative least squares in Gram form: min 1/2 c^T A c - g^T c, c >= 0 (Lawson and Hanson
// 1974, chapter 23, on the normal equations). A: n x n symmetric positive definite,
// row-major. Hand-written: Eigen 3.4 has no NNLS. Returns the outer iterations used.
int nnls_gram(const std::vector<double>& A, const std::vector<double>& g, int n,
              std::vector<double>* c);

}  // namespace sepal
