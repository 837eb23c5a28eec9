// The weighted alternating least-squares engine on a held matrix: the solver behind
// `factor` (svd/nmf/acls, factor.h) and the inverse shade trees (ist/decompose.h).
// Library-internal: not a user API (no option checking; callers validate).
//
// Usage:
//   sepal::detail::Matrix m;              // rows x cols, weights w and weighted data wv
//   sepal::detail::LowRank f;             // the start: g (rows x k), h (cols x k)
//   sepal::detail::AlsSettings s; s.rule = sepal::detail::AlsRule::Constrained;
//   int it = 0; double sse = sepal::detail::als_solve(m, 0, s, &f, &it);
//   sepal::detail::als_project(m, 0, s, &f);   // one exact update of g with h held
//
// The problem is  min sum_rc w_rc (m_rc - g_r . h_c)^2  (plus the rule's penalties), with
// w_rc >= 0 the confidence of an entry (0 = missing: the entry is left out). Each
// half-step holds one side and solves the other exactly (or, for the block rules, one
// exact pass of block updates), so no rule ever raises its objective: every rule converges
// to a local minimum (Lawrence et al. 2006, section 4.2).
// Rules (side 0 = g, side 1 = h):
//   LeastSquares    unconstrained per-row solves (a tiny ridge); from an SVD start with all
//                   weights 1 this is the truncated SVD (PCA's global minimum)
//   Multiplicative  Lee-Seung NMF with weights, `inner` updates per pass
//   Constrained     ACLS: exact per-term block updates under g, h >= 0; optionally one
//                   column held at 1, monotone columns (tree isotonic regression) and
//                   energy groups on h
//   Sparse          SACLS (eq. 4): side 0 solves, per row and exactly (non-negative least
//                   squares, Lawson-Hanson), for each choice j of the one unpenalized term
//                     sum_c w (m - g.h)^2 + l sum_{a != j} g_a^2 + m_l1 (1 - sum_a g_a)^2
//                   and keeps the best j; side 1 is Constrained's (with energy groups).
// Energy groups (section 4.3.1): for every term a and group G, sum_{c in G} coef_c h_ca <=
// bound; the block update of h_a is then the exact weighted projection onto that set (a
// one-dimensional search for the multiplier per group).
// Determinism: results do not depend on the thread count (see util/parallel.h).
#pragma once
#include <atomic>
#include <cstdint>
#include <vector>

namespace sepal {
namespace detail {

// The held matrix: the weight of every entry (its share of valid sub-sample pairs, 0..1)
// and, per factored channel, weight x value - the zero-filled matrix the SVD factors and
// the weighted data the ALS rules need, without a division or a branch per entry.
struct Matrix {
    int rows = 0, cols = 0, channels = 0;
    std::vector<float> w;                // [r * cols + c]
    std::vector<std::vector<float>> wv;  // [channel][r * cols + c]
};

// Factors of one channel: g is rows x k, h is cols x k, both row-major.
struct LowRank {
    int k = 0;
    std::vector<double> g, h;
};

// svd: top-k singular triplets of the zero-filled matrix W.M (values times weights) by
// randomized subspace iteration; g = u sqrt(sigma), h = v sqrt(sigma).
void truncated_svd(const Matrix& m, int channel, int k, uint64_t seed, int threads,
                   LowRank* out, std::vector<double>* sigma);

// One linear inequality per term on side 1: sum_i coef[i] h[cols[i]][a] <= bound.
struct EnergyGroup {
    std::vector<int> cols;
    std::vector<double> coef;  // >= 0
    double bound = 1;
};

enum class AlsRule { LeastSquares, Multiplicative, Constrained, Sparse };
struct AlsSettings {
    AlsRule rule = AlsRule::LeastSquares;
    int max_iters = 50;
    double tolerance = 1e-6;
    int inner = 1;            // per-row updates per half-step (multiplicative, constrained)
    int constant_side = -1;   // 0: g column 0 held at 1; 1: h column 0 held at 1
    int monotone_side = -1;   // side whose columns are non-increasing along `parent`
    const std::vector<int>* parent = nullptr;  // monotone side: parent index or -1 (root)
    const std::vector<int>* order = nullptr;   // children before parents
    // Entries wholly below the horizon have no data; with an anchor they count with
    // anchor_weight toward the anchor's reconstruction (the previous term count's), which
    // keeps a new term from taking arbitrary values there (bilinear lookups near the edge
    // of the valid region blend such entries in). Null: they are left out.
    const LowRank* anchor = nullptr;
    double anchor_weight = 1e-4;
    // > 0: such entries count with this weight toward 0 instead (the anchor is unused).
    double horizon_weight = 0;
    // LeastSquares rule: a ridge on every row solve, as a share of the mean diagonal of the
    // normal equations. With entries wholly below the horizon left out, a term can be
    // non-zero on such entries only, at no cost at the sample points - but bilinear lookups
    // near the edge of the valid region blend those entries in; the ridge (the factor-norm
    // penalty that favours low-rank completions) zeroes any such term in one exact solve
    // however small it is, and 1e-9 leaves the fit of valid entries unchanged to float
    // precision. With entries missing at random a weak direction can take huge values that
    // the rows observing an entry cancel and the rows missing it do not (IST PCA, 96x96, 50%
    // missing: -79/sr predicted where the truth is 1.4): decompose.cpp uses 1e-2 there.
    double ridge = 1e-9;
    // Sparse rule: the absolute weights of the sparsity (l) and unit-L1 (m) penalties.
    double sparsity_l = 0, sparsity_m = 0;
    // Constrained and Sparse rules: inequalities on the columns of h (null: none).
    const std::vector<EnergyGroup>* energy = nullptr;
    int threads = 0;
    // Complete data with one confidence everywhere shares one Gram matrix across the lines
    // of a side (computed once, not as a product with the weights); false takes the general
    // weighted products anyway (tests compare the two).
    bool uniform_shortcut = true;
    // Counts updates that fell back (never silent): a least-squares solution that is not
    // finite, or a multiplicative update whose denominator vanished while the entry was
    // nonzero; either sets the entry to 0. Totals do not depend on the thread count.
    std::atomic<int64_t>* fallbacks = nullptr;
};
// Alternating weighted least squares from the given start, in place. Returns the
// objective (weighted sum of squared errors, plus the Sparse rule's penalties);
// *iterations receives the outer iterations done. Terms are rescaled to equal largest
// magnitudes after each iteration, except under the Sparse rule or energy groups, where
// the scale of each side means something (unit-L1 weights, bounded albedo).
double als_solve(const Matrix& m, int channel, const AlsSettings& s, LowRank* f,
                 int* iterations);
// One update of side 0 (g) with h held, by the rule's side-0 solve (for Constrained: `inner`
// sweeps of block updates from the given g). Returns the objective after it. The
// projection of data onto a fixed basis (k-means re-projection, subsampled factorizations).
double als_project(const Matrix& m, int channel, const AlsSettings& s, LowRank* f);
// Weighted isotonic regression on a rooted forest (x[v] <= x[parent[v]]), exact.
void tree_isotonic(const std::vector<int>& parent, const std::vector<int>& order,
                   const std::vector<double>& y, const std::vector<double>& w,
                   std::vector<double>* x);
// Re-expresses g h^T as ordered orthogonal terms (an SVD of the product).
void orthogonalize(LowRank* f);

// NNDSVD (Boutsidis and Gallopoulos 2008): column a of *out (g and h, sized) from the
// larger of the positive and the negative part of SVD term j, a non-negative start;
// fill_zeros starts zero entries small instead (multiplicative updates never move a 0).
void nndsvd_column(const LowRank& svd, int j, LowRank* out, int a, bool fill_zeros);

// min x^T a x - 2 b^T x over x >= 0 for a small symmetric positive semi-definite a (n x n,
// row-major), exactly (Lawson-Hanson active set on the normal equations). Returns false
// (x = 0) when a solve breaks down.
bool nnls_gram(const double* a, const double* b, int n, double* x);

}  // namespace detail
}  // namespace sepal
