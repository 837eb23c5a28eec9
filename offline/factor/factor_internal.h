// Internals of the factorization engine shared by factor*.cpp (not a public interface).
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "brdf/brdf.h"
#include "factor/als.h"
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
    // confidence (optional, cols() floats): the mean of FactorOptions::confidence over each
    // entry's valid pairs (1 without one), times FactorOptions::value_weight of its mean.
    bool sample_row(int row, float* rgb, uint16_t* count, std::string* err,
                    float* confidence = nullptr) const;

  private:
    struct Point {
        glm::dvec3 p, t, s;  // the factor point; t, s: gs-half's frame (t', s')
        bool valid = false;
        bool fallback = false;  // a G point whose frame is degenerate (param.h)
    };
    void prepare(int which, std::vector<int>* texels, std::vector<Point>* points) const;

    const Brdf& brdf_;
    std::function<double(const glm::dvec3&, const glm::dvec3&)> confidence_;
    std::function<double(const glm::dvec3&)> value_weight_;
    Param param_;
    HemiMap map_;
    int n_[2], s_, pairs_;  // n_: texels per side of G (0) and H (1)
    std::vector<int> row_texel_, col_texel_;
    std::vector<Point> row_points_, col_points_;  // s^2 per texel
    int64_t frame_fallback_pairs_ = 0;
};

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
