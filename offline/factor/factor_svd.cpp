// Truncated SVD by randomized subspace iteration, and re-orthogonalization of factors.
//
// Only the top K singular triplets are needed, so instead of a full decomposition of the
// (up to 13000 x 13000) matrix we iterate on a block of K + 8 vectors: Y = X Omega,
// then Q <- orth(X (X^T Q)) until the leading singular values settle (Halko, Martinsson,
// Tropp 2011, algorithm 4.4 with a Rayleigh-Ritz step). Products run in double over fixed
// row or column chunks of the float matrix, so results do not depend on the thread count.
#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "factor/factor_internal.h"
#include "util/parallel.h"

namespace sepal {
namespace detail {

namespace {
using Mat = Eigen::MatrixXd;
using RowMatF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Y = X * in, X = W.M (rows x cols), in: cols x l.
void mul(const Matrix& m, int ch, const Mat& in, Mat* y, int threads) {
    const int rows = m.rows, cols = m.cols;
    const int rc = 64;
    const size_t chunks = size_t((rows + rc - 1) / rc);
    y->resize(rows, in.cols());
    parallel_for(chunks, threads, [&](size_t chunk) {
        const int r0 = int(chunk) * rc, r1 = std::min(rows, r0 + rc);
        const Mat x = Eigen::Map<const RowMatF>(&m.wv[size_t(ch)][size_t(r0) * cols], r1 - r0, cols)
                          .cast<double>();
        y->middleRows(r0, r1 - r0).noalias() = x * in;
    });
}

// Z = X^T * q, q: rows x l.
void mul_t(const Matrix& m, int ch, const Mat& q, Mat* z, int threads) {
    const int rows = m.rows, cols = m.cols;
    const int cc = 64;
    const size_t chunks = size_t((cols + cc - 1) / cc);
    z->resize(cols, q.cols());
    parallel_for(chunks, threads, [&](size_t chunk) {
        const int c0 = int(chunk) * cc, c1 = std::min(cols, c0 + cc);
        const Mat x = Eigen::Map<const RowMatF>(m.wv[size_t(ch)].data(), rows, cols)
                          .middleCols(c0, c1 - c0)
                          .cast<double>();
        z->middleRows(c0, c1 - c0).noalias() = x.transpose() * q;
    });
}

Mat orth(const Mat& y) {
    Eigen::HouseholderQR<Mat> qr(y);
    return qr.householderQ() * Mat::Identity(y.rows(), y.cols());
}

// Deterministic sign: each left vector sums to >= 0 (ties: its largest entry positive).
void fix_signs(Mat* u, Mat* v) {
    for (int j = 0; j < u->cols(); ++j) {
        double s = u->col(j).sum();
        if (std::fabs(s) < 1e-12 * u->col(j).cwiseAbs().sum()) {
            Eigen::Index at;
            u->col(j).cwiseAbs().maxCoeff(&at);
            s = (*u)(at, j);
        }
        if (s < 0) {
            u->col(j) = -u->col(j);
            v->col(j) = -v->col(j);
        }
    }
}

double gaussian(uint64_t seed, uint64_t i) {
    const double u1 = counter_uniform(seed, 2 * i), u2 = counter_uniform(seed, 2 * i + 1);
    return std::sqrt(-2.0 * std::log(1.0 - u1)) * std::cos(6.283185307179586 * u2);
}
}  // namespace

void truncated_svd(const Matrix& m, int channel, int k, uint64_t seed, int threads,
                   LowRank* out, std::vector<double>* sigma) {
    const int rows = m.rows, cols = m.cols;
    const int l = std::min({k + 8, rows, cols});
    Mat omega(cols, l);
    for (int c = 0; c < cols; ++c)
        for (int j = 0; j < l; ++j) omega(c, j) = gaussian(seed, uint64_t(c) * l + j);
    Mat y, z;
    mul(m, channel, omega, &y, threads);
    Mat q = orth(y);
    Eigen::VectorXd prev = Eigen::VectorXd::Constant(l, -1.0);
    const int max_iters = 40;
    for (int it = 0;; ++it) {
        mul_t(m, channel, q, &z, threads);  // z = X^T q = B^T
        const Eigen::VectorXd s = Eigen::JacobiSVD<Mat>(z).singularValues();
        // The leading K values settle long before the rest of the block; 1e-10 of the top
        // value is below what float storage of the matrix resolves anyway.
        double change = 0;
        for (int j = 0; j < std::min(k, l); ++j) change = std::max(change, std::fabs(s(j) - prev(j)));
        prev = s;
        if ((it >= 2 && change <= 1e-10 * std::max(s(0), 1e-300)) || it >= max_iters) break;
        mul(m, channel, z, &y, threads);
        q = orth(y);
    }
    // X ~= q B, B = z^T = (V_z S U_z^T): left vectors q V_z, right vectors U_z.
    Eigen::JacobiSVD<Mat> svd(z, Eigen::ComputeThinU | Eigen::ComputeThinV);
    Mat u = q * svd.matrixV();
    Mat v = svd.matrixU();
    fix_signs(&u, &v);
    const int kk = std::min(k, l);
    out->k = k;
    out->g.assign(size_t(rows) * k, 0.0);
    out->h.assign(size_t(cols) * k, 0.0);
    if (sigma) sigma->assign(size_t(k), 0.0);
    for (int j = 0; j < kk; ++j) {
        const double sv = svd.singularValues()(j);
        const double r = std::sqrt(sv);
        if (sigma) (*sigma)[size_t(j)] = sv;
        for (int i = 0; i < rows; ++i) out->g[size_t(i) * k + j] = u(i, j) * r;
        for (int i = 0; i < cols; ++i) out->h[size_t(i) * k + j] = v(i, j) * r;
    }
}

void orthogonalize(LowRank* f) {
    const int k = f->k;
    const int rows = int(f->g.size() / size_t(k)), cols = int(f->h.size() / size_t(k));
    Mat g = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        f->g.data(), rows, k);
    Mat h = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        f->h.data(), cols, k);
    Eigen::HouseholderQR<Mat> qg(g), qh(h);
    const Mat qgm = qg.householderQ() * Mat::Identity(rows, k);
    const Mat qhm = qh.householderQ() * Mat::Identity(cols, k);
    const Mat rg = qgm.transpose() * g, rh = qhm.transpose() * h;
    Eigen::JacobiSVD<Mat> svd(rg * rh.transpose(), Eigen::ComputeFullU | Eigen::ComputeFullV);
    Mat u = qgm * svd.matrixU(), v = qhm * svd.matrixV();
    fix_signs(&u, &v);
    for (int j = 0; j < k; ++j) {
        const double r = std::sqrt(svd.singularValues()(j));
        for (int i = 0; i < rows; ++i) f->g[size_t(i) * k + j] = u(i, j) * r;
        for (int i = 0; i < cols; ++i) f->h[size_t(i) * k + j] = v(i, j) * r;
    }
}

}  // namespace detail
}  // namespace sepal
