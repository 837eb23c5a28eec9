// Non-negative matrix factorization under the generalized Kullback-Leibler divergence
// (Lee and Seung 2000; the update rules of Lawrence et al. 2004, appendix eq. 14-16).
//
// Usage:
//   Eigen::MatrixXd Y = ...;                     // non-negative, rows x cols
//   sepal::NmfKl r;
//   sepal::nmf_kl(Y, 3, sepal::NmfKlOptions{}, &r);
//   // Y ~= r.W * r.H, W's columns sum to 1 (each a distribution over the rows)
//
// Why KL and not the Euclidean NMF of factor/: the factors become sampling distributions,
// and KL(Y || WH) is the measure of how well sampling WH matches Y (relative errors where
// Y is small count as much as where it is large), as the paper chose.
// Determinism: a fixed-seed start (splitmix64) and fused updates over chunks of a fixed size
// (threads decide only who computes a chunk); equal inputs give equal factors whatever the
// thread count. Limits: k <= min(rows, cols) is not required (extra columns
// stay near 0); entries must be finite and >= 0 (checked by the caller).
#pragma once
#include <cstdint>

#include <Eigen/Dense>

namespace sepal {

struct NmfKlOptions {
    int max_iterations = 1000;
    double tolerance = 1e-6;  // stop when the divergence falls by less than this share (per 10 iterations)
    uint64_t seed = 1;
    int threads = 0;  // 0 = default_threads(); matrices under 65,536 entries use one
};

struct NmfKl {
    Eigen::MatrixXd W, H;     // rows x k, k x cols
    double divergence = 0;    // D(Y || WH)
    double relative = 0;      // divergence / sum(Y) (0 when Y is 0)
    int iterations = 0;
};

void nmf_kl(const Eigen::MatrixXd& Y, int k, const NmfKlOptions& o, NmfKl* out);

// D(Y || X) = sum Y log(Y / X) - Y + X, with 0 log 0 = 0.
double kl_divergence(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& X);

}  // namespace sepal
