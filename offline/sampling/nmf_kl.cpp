#include "sampling/nmf_kl.h"

#include <algorithm>
#include <cmath>
#include <vector>

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

namespace {

// The updates below are written as loops over (column or row) chunks instead of Eigen
// products: each half-step needs X = WH only through R = Y / X, and with k of 2-8 terms an
// Eigen GEMM spent as long packing W and H as multiplying (and R, X and the products were
// three full-size temporaries per half-step). Fused, a chunk computes its part of X, R and
// the numerator in one sweep over Y, and chunks run on threads. The chunk sizes are fixed,
// so the results do not depend on the thread count.
constexpr Eigen::Index kColChunk = 8, kRowChunk = 128;
// Below this many entries of Y a solve stays on one thread (starting threads twice per
// iteration would cost more than the work).
constexpr Eigen::Index kParallelEntries = 1 << 16;

struct Fused {
    const Eigen::MatrixXd& Y;
    Eigen::MatrixXd& W;
    Eigen::MatrixXd& H;
    int k;
    double floor;
    int threads;
    std::vector<std::vector<double>> scratch;  // per worker

    Eigen::Index n() const { return Y.rows(); }
    Eigen::Index m() const { return Y.cols(); }

    // x[i] = (W H)(i, j) for the rows [i0, i1).
    void column_of_x(Eigen::Index j, Eigen::Index i0, Eigen::Index i1, double* x) const {
        for (Eigen::Index i = i0; i < i1; ++i) x[i - i0] = 0.0;
        for (int a = 0; a < k; ++a) {
            const double h = H(a, j);
            const double* w = &W(i0, a);
            for (Eigen::Index i = 0; i < i1 - i0; ++i) x[i] += w[i] * h;
        }
    }

    // H <- H .* (W^T R) ./ (W^T 1): column j's numerator needs only column j of H.
    void update_h(const Eigen::VectorXd& wsum) {
        const Eigen::Index chunks = (m() + kColChunk - 1) / kColChunk;
        parallel_for_workers(size_t(chunks), threads, [&](size_t chunk, int worker) {
            double* x = worker_buffer(worker);
            const Eigen::Index j1 = std::min(m(), Eigen::Index(chunk + 1) * kColChunk);
            for (Eigen::Index j = Eigen::Index(chunk) * kColChunk; j < j1; ++j) {
                column_of_x(j, 0, n(), x);
                const double* y = &Y(0, j);
                for (Eigen::Index i = 0; i < n(); ++i) x[i] = y[i] / std::max(x[i], floor);
                for (int a = 0; a < k; ++a) {
                    const double* w = &W(0, a);
                    double s = 0.0;
                    for (Eigen::Index i = 0; i < n(); ++i) s += w[i] * x[i];
                    H(a, j) *= s / std::max(wsum(a), 1e-300);
                }
            }
        });
    }

    // W <- W .* (R H^T) ./ (1 H^T): row i's numerator needs only row i of W.
    void update_w(const Eigen::VectorXd& hsum) {
        const Eigen::Index chunks = (n() + kRowChunk - 1) / kRowChunk;
        parallel_for_workers(size_t(chunks), threads, [&](size_t chunk, int worker) {
            const Eigen::Index i0 = Eigen::Index(chunk) * kRowChunk, i1 = std::min(n(), i0 + kRowChunk), b = i1 - i0;
            double* x = worker_buffer(worker);
            double* acc = x + kRowChunk;  // acc[a * kRowChunk + i]
            for (Eigen::Index q = 0; q < kRowChunk * k; ++q) acc[q] = 0.0;
            for (Eigen::Index j = 0; j < m(); ++j) {
                column_of_x(j, i0, i1, x);
                const double* y = &Y(i0, j);
                for (Eigen::Index i = 0; i < b; ++i) x[i] = y[i] / std::max(x[i], floor);
                for (int a = 0; a < k; ++a) {
                    const double h = H(a, j);
                    double* ac = acc + a * kRowChunk;
                    for (Eigen::Index i = 0; i < b; ++i) ac[i] += x[i] * h;
                }
            }
            for (int a = 0; a < k; ++a)
                for (Eigen::Index i = 0; i < b; ++i) W(i0 + i, a) *= acc[a * kRowChunk + i] / std::max(hsum(a), 1e-300);
        });
    }

    // D(Y || WH), summed per column chunk and then over chunks in order.
    double divergence() {
        const Eigen::Index chunks = (m() + kColChunk - 1) / kColChunk;
        std::vector<double> part(size_t(chunks), 0.0);
        parallel_for_workers(size_t(chunks), threads, [&](size_t chunk, int worker) {
            double* x = worker_buffer(worker);
            const Eigen::Index j1 = std::min(m(), Eigen::Index(chunk + 1) * kColChunk);
            double d = 0.0;
            for (Eigen::Index j = Eigen::Index(chunk) * kColChunk; j < j1; ++j) {
                column_of_x(j, 0, n(), x);
                for (Eigen::Index i = 0; i < n(); ++i) {
                    const double y = Y(i, j);
                    d += x[i] - y;
                    if (y > 0) d += y * std::log(y / std::max(x[i], 1e-300));
                }
            }
            part[chunk] = d;
        });
        double d = 0.0;
        for (double v : part) d += v;
        return d;
    }

    // Sized once before the iterations (a worker must not allocate: parallel.h).
    double* worker_buffer(int worker) { return scratch[size_t(worker)].data(); }
};

}  // namespace

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
    if (n == 0 || m == 0) {  // nothing to fit (the chunks below would index an empty Y)
        *out = NmfKl{};
        out->W = std::move(W);
        out->H = std::move(H);
        return;
    }
    const int threads = n * m >= kParallelEntries ? o.threads : 1;
    Fused f{Y, W, H, k, floor, threads, {}};
    f.scratch.assign(size_t(std::max(workers(size_t((m + kColChunk - 1) / kColChunk), threads),
                                     workers(size_t((n + kRowChunk - 1) / kRowChunk), threads))),
                     std::vector<double>(std::max(size_t(n), size_t(kRowChunk) * size_t(k + 1)), 0.0));
    double previous = -1;
    int it = 0;
    for (; it < o.max_iterations; ++it) {
        // H <- H .* (W^T R) ./ (W^T 1)      (eq. 14)
        f.update_h(W.colwise().sum().transpose());
        // W <- W .* (R H^T) ./ (1 H^T)      (eq. 15), R from the new H
        f.update_w(H.rowwise().sum());
        // Columns of W sum to 1, the scale goes to H (eq. 16).
        for (int a = 0; a < k; ++a) {
            const double s = W.col(a).sum();
            if (s > 0) {
                W.col(a) /= s;
                H.row(a) *= s;
            }
        }
        if ((it + 1) % 10 == 0) {
            const double d = f.divergence();
            if (previous >= 0 && previous - d <= o.tolerance * std::max(previous, 1e-300)) {
                ++it;
                break;
            }
            previous = d;
        }
    }
    out->divergence = f.divergence();
    out->relative = total > 0 ? out->divergence / total : 0.0;
    out->iterations = it;
    out->W = std::move(W);
    out->H = std::move(H);
}

}  // namespace sepal
