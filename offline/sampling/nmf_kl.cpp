#include "sampling/nmf_kl.h"

#include <cmath>

#include "util/parallel.h"

namespace sepal {

namespace {
// Floor of a reconstruction entry in the ratio Y / X (relative to Y's mean): keeps 0/0 at 0
// and a vanishing X from blowing the update up; far below any value that matters.
constexpr double kFloor = 1e-14;
}  // namespace

double kl_divergence(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& X) {
    double d = 0;
    for (Eigen::Index j = 0; j < Y.cols(); ++j)
        for (Eigen::Index i = 0; i < Y.rows(); ++i) {
            const double y = Y(i, j), x = X(i, j);
            d += x - y;
            if (y > 0) d += y * std::log(y / std::max(x, 1e-300));
        }
    return d;
}

void nmf_kl(const Eigen::MatrixXd& Y, int k, const NmfKlOptions& o, NmfKl* out) {
    const Eigen::Index n = Y.rows(), m = Y.cols();
    const double total = Y.sum();
    const double mean = total > 0 ? total / double(n * m) : 1.0;
    const double floor = kFloor * mean;
    // Start: positive random factors whose product has Y's mean, plus a rank-1 ramp from Y's
    // row and column sums in the first term (converges in far fewer iterations).
    SplitMix64 rng(o.seed);
    Eigen::MatrixXd W(n, k), H(k, m);
    const Eigen::VectorXd rows = Y.rowwise().sum(), cols = Y.colwise().sum().transpose();
    for (Eigen::Index i = 0; i < n; ++i)
        for (int a = 0; a < k; ++a)
            W(i, a) = (a == 0 && total > 0 ? rows(i) / total : 0.0) + (0.5 + rng.uniform()) / double(n);
    for (int a = 0; a < k; ++a)
        for (Eigen::Index j = 0; j < m; ++j)
            H(a, j) = (a == 0 && total > 0 ? cols(j) : 0.0) / k + (0.5 + rng.uniform()) * mean * double(n) / k;
    Eigen::MatrixXd X(n, m), R(n, m);
    auto ratio = [&] {
        X.noalias() = W * H;
        R = Y.array() / X.array().max(floor);
    };
    double previous = -1;
    int it = 0;
    for (; it < o.max_iterations; ++it) {
        ratio();
        // H <- H .* (W^T R) ./ (W^T 1)      (eq. 14)
        const Eigen::VectorXd wsum = W.colwise().sum().transpose();
        Eigen::MatrixXd num = W.transpose() * R;
        for (int a = 0; a < k; ++a)
            H.row(a) = H.row(a).array() * num.row(a).array() / std::max(wsum(a), 1e-300);
        ratio();
        // W <- W .* (R H^T) ./ (1 H^T)      (eq. 15)
        const Eigen::VectorXd hsum = H.rowwise().sum();
        Eigen::MatrixXd numw = R * H.transpose();
        for (int a = 0; a < k; ++a)
            W.col(a) = W.col(a).array() * numw.col(a).array() / std::max(hsum(a), 1e-300);
        // Columns of W sum to 1, the scale goes to H (eq. 16).
        for (int a = 0; a < k; ++a) {
            const double s = W.col(a).sum();
            if (s > 0) {
                W.col(a) /= s;
                H.row(a) *= s;
            }
        }
        if ((it + 1) % 10 == 0) {
            X.noalias() = W * H;
            const double d = kl_divergence(Y, X);
            if (previous >= 0 && previous - d <= o.tolerance * std::max(previous, 1e-300)) {
                ++it;
                break;
            }
            previous = d;
        }
    }
    X.noalias() = W * H;
    out->divergence = kl_divergence(Y, X);
    out->relative = total > 0 ? out->divergence / total : 0.0;
    out->iterations = it;
    out->W = std::move(W);
    out->H = std::move(H);
}

}  // namespace sepal
