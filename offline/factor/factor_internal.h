// Internals of the factorization engine shared by factor*.cpp (not a public interface).
#pragma once
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "brdf/brdf.h"
#include "factor/factor.h"
#include "util/progress.h"

namespace sepal {
namespace detail {

// Rows are processed in chunks of this many; fixed so results never depend on threads.
constexpr int kRowChunk = 16;
constexpr int kColChunk = 64;

// Evaluates the sample matrix one row at a time (used by the held matrix and by ND).
class PairSampler {
  public:
    PairSampler(const Brdf& brdf, const FactorOptions& o);
    int rows() const { return int(row_texel_.size()); }
    int cols() const { return int(col_texel_.size()); }
    int pairs_per_entry() const { return pairs_; }
    const std::vector<int>& row_texels() const { return row_texel_; }
    const std::vector<int>& col_texels() const { return col_texel_; }
    // Sub-sample pairs of one sampling pass whose G point (the half vector) has a degenerate
    // frame and takes param.h's documented fallback: counted once, when the sampler is made.
    int64_t frame_fallback_pairs() const { return frame_fallback_pairs_; }
    // rgb: 3 * cols() floats (averages over valid pairs, 0 where none); count: valid pairs
    // per entry. False with a message when the BRDF returns a non-finite value.
    bool sample_row(int row, float* rgb, uint16_t* count, std::string* err) const;

  private:
    struct Point {
        glm::dvec3 p, t, s;  // the factor point; t, s: gs-half's frame (t', s')
        bool valid = false;
        bool fallback = false;  // a G point whose frame is degenerate (param.h)
    };
    void prepare(int which, std::vector<int>* texels, std::vector<Point>* points) const;

    const Brdf& brdf_;
    Param param_;
    HemiMap map_;
    int n_[2], s_, pairs_;  // n_: texels per side of G (0) and H (1)
    std::vector<int> row_texel_, col_texel_;
    std::vector<Point> row_points_, col_points_;  // s^2 per texel
    int64_t frame_fallback_pairs_ = 0;
};

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

enum class AlsRule { LeastSquares, Multiplicative, Constrained };
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
    int threads = 0;
    // Counts updates that fell back (never silent): a least-squares solution that is not
    // finite, or a multiplicative update whose denominator vanished while the entry was
    // nonzero; either sets the entry to 0. Totals do not depend on the thread count.
    std::atomic<int64_t>* fallbacks = nullptr;
};
// Alternating weighted least squares from the given start, in place. Returns the
// weighted sum of squared errors; *iterations receives the outer iterations done.
double als_solve(const Matrix& m, int channel, const AlsSettings& s, LowRank* f,
                 int* iterations);
// Weighted isotonic regression on a rooted forest (x[v] <= x[parent[v]]), exact.
void tree_isotonic(const std::vector<int>& parent, const std::vector<int>& order,
                   const std::vector<double>& y, const std::vector<double>& w,
                   std::vector<double>* x);
// Re-expresses g h^T as ordered orthogonal terms (an SVD of the product).
void orthogonalize(LowRank* f);

// Converts a sampled RGB row to the factored channels (3, or 1 = luminance) as doubles,
// out[ch * cols + c].
void row_channels(const float* rgb, int cols, int channels, double* out);

// Streaming normalized decomposition (factor_nd.cpp): per channel factors, the colour
// ratio (luminance mode), which rows/columns have any valid pair, and counters.
bool nd_factor(const PairSampler& s, const FactorOptions& o, int channels,
               std::vector<LowRank>* out, glm::dvec3* ratio, std::vector<uint8_t>* row_has,
               std::vector<uint8_t>* col_has, double* first_pass_seconds, int64_t* evals,
               std::string* err);

// Progress on stderr for long runs ("sepal factor: sampling 42%"); silent when disabled.
class Progress : public ::sepal::Progress {
  public:
    Progress(bool enabled, const std::string& what, size_t total)
        : ::sepal::Progress(enabled, "sepal factor: " + what, total) {}
};

// factor_brdf for Method::Homomorphic (homomorphic.cpp): picks the samples, fits every term
// count 1..K, fills the result like the other methods.
bool factor_brdf_homomorphic(const Brdf& brdf, const FactorOptions& o, FactorResult* out, std::string* err);

}  // namespace detail
}  // namespace sepal
