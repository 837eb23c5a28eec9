#include "database/linear_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "measured/tabulated.h"
#include "util/parallel.h"

namespace sepal {

namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

std::vector<int> used_columns(int K, const std::vector<uint8_t>* use, int skip = -1) {
    std::vector<int> cols;
    for (int j = 0; j < K; ++j)
        if ((!use || use->empty() || (*use)[size_t(j)]) && j != skip) cols.push_back(j);
    return cols;
}

// The column-normalised sample matrix X (rows x used columns) and the column scales.
MatrixXd sample_matrix(const BrdfDatabase& db, const std::vector<size_t>& rows,
                       const std::vector<int>& cols, std::vector<double>* scale,
                       const std::vector<double>* row_weight = nullptr) {
    const int K = db.size();
    MatrixXd X(Index(rows.size()), Index(cols.size()));
    scale->assign(cols.size(), 0.0);
    for (size_t j = 0; j < cols.size(); ++j) {
        const double g = db.gram()[size_t(cols[j]) * size_t(K) + size_t(cols[j])];
        (*scale)[j] = g > 0.0 ? std::sqrt(g) : 0.0;
        const double inv = g > 0.0 ? 1.0 / (*scale)[j] : 0.0;
        const float* col = db.column(cols[j]);
        for (size_t i = 0; i < rows.size(); ++i)
            X(Index(i), Index(j)) = col[rows[i]] * inv * (row_weight ? (*row_weight)[i] : 1.0);
    }
    return X;
}

// Extreme eigenvalues of a symmetric matrix.
void extreme_eigenvalues(const MatrixXd& A, double* lo, double* hi) {
    Eigen::SelfAdjointEigenSolver<MatrixXd> es(A, Eigen::EigenvaluesOnly);
    *lo = es.eigenvalues()(0);
    *hi = es.eigenvalues()(es.eigenvalues().size() - 1);
}

double condition_of(double lo, double hi) {
    if (!(hi > 0.0)) return std::numeric_limits<double>::infinity();
    if (!(lo > hi * 1e-300)) return std::numeric_limits<double>::infinity();
    return hi / lo;
}

// 1/sigma per row (the square root of the GLS weight).
std::vector<double> row_weights(const BrdfDatabase& db, const std::vector<size_t>& rows,
                                const std::vector<uint8_t>& use) {
    const ResidualModel m = residual_model(db, use);
    std::vector<double> w = row_sigma2(db, m, rows);
    for (double& x : w) x = 1.0 / std::sqrt(x);
    return w;
}

// Tikhonov lambda that brings the condition number of A down to max_condition (0 when it is
// already there); sets fit->condition.
double ridge_lambda(const MatrixXd& A, double max_condition, CombinationFit* fit) {
    double lo, hi;
    extreme_eigenvalues(A, &lo, &hi);
    fit->condition = condition_of(lo, hi);
    return ridge_for_condition(lo, hi, max_condition);
}

// The log-space model's value from its exponent sum s (before the channel offset's exp).
inline double log_model_value(double s) { return std::exp(std::min(s, 700.0)) - kDatabaseLogEps; }

// The log model's design over sample rows (log_design_row per row) and the rows' weights.
MatrixXd log_design(const BrdfDatabase& db, const std::vector<size_t>& rows, const std::vector<int>& cols,
                    std::vector<double>* weights = nullptr) {
    const size_t N = rows.size();
    const int K = db.size(), M = int(cols.size()) + 3;
    MatrixXd X(Index(N), M);
    std::vector<float> values(static_cast<size_t>(K));
    std::vector<double> out(static_cast<size_t>(M));
    if (weights) weights->resize(N);
    for (size_t i = 0; i < N; ++i) {
        for (int k = 0; k < K; ++k) values[size_t(k)] = db.value(k, rows[i]);
        const double w = log_design_row(db, rows[i], values.data(), cols, out.data());
        for (int j = 0; j < M; ++j) X(Index(i), j) = out[size_t(j)];
        if (weights) (*weights)[i] = w;
    }
    return X;
}

// FitSpace::kLog (linear_model.h): the design above, each column normalised over the samples,
// then ridge least squares.
void fit_combination_log(const BrdfDatabase& db, const std::vector<size_t>& rows,
                         const std::vector<double>& values, const std::vector<int>& cols,
                         const FitOptions& opt, CombinationFit* fit) {
    const size_t N = rows.size();
    const int Mdb = int(cols.size()), M = Mdb + 3;
    std::vector<double> w;
    MatrixXd X = log_design(db, rows, cols, &w);
    VectorXd b(static_cast<Index>(N));
    for (size_t i = 0; i < N; ++i) b(Index(i)) = std::log(std::max(values[i], 0.0) + kDatabaseLogEps) * w[i];
    const VectorXd norm = X.colwise().norm().transpose();
    for (int j = 0; j < M; ++j)
        if (norm(j) > 0.0) X.col(j) /= norm(j);
    MatrixXd A = X.transpose() * X;
    fit->lambda = ridge_lambda(A, opt.max_condition, fit);
    A.diagonal().array() += fit->lambda;
    VectorXd c = A.ldlt().solve(X.transpose() * b);
    // The fitted exponent sums at the samples, from the design itself (its rows are w s_i).
    const VectorXd ws = X * c;
    for (int j = 0; j < M; ++j) c(j) = norm(j) > 0.0 ? c(j) / norm(j) : 0.0;
    fit->coeffs.assign(size_t(db.size()), 0.0);
    for (int j = 0; j < Mdb; ++j) {
        fit->coeffs[size_t(cols[size_t(j)])] = c(j);
        fit->nonzero += c(j) != 0.0;
    }
    for (int ch = 0; ch < 3; ++ch) fit->offsets[ch] = c(Mdb + ch);
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < N; ++i) {
        const double d = log_model_value(ws(Index(i)) / w[i]) - values[i];
        num += d * d;
        den += values[i] * values[i];
    }
    fit->sample_rms = den > 0.0 ? std::sqrt(num / den) : std::sqrt(num);
}

}  // namespace

double ridge_for_condition(double lo, double hi, double max_condition) {
    const double kappa = std::max(max_condition, 2.0);
    return condition_of(lo, hi) > kappa ? std::max(0.0, (hi - kappa * lo) / (kappa - 1.0)) : 0.0;
}

const char* fit_space_name(FitSpace s) { return s == FitSpace::kLog ? "log" : "linear"; }

double log_row_weight(const BrdfDatabase& db, size_t row) {
    glm::dvec3 wi, wo;
    from_half_diff(db.cell_center(db.grid_cell(row / 3)), &wi, &wo);
    return std::max(wi.z, 1e-3);
}

double log_design_row(const BrdfDatabase& db, size_t row, const float* values, const std::vector<int>& cols,
                      double* out) {
    const double w = log_row_weight(db, row);
    const size_t n = cols.size();
    for (size_t j = 0; j < n; ++j) out[j] = std::log(double(values[cols[j]]) + kDatabaseLogEps) * w;
    for (size_t ch = 0; ch < 3; ++ch) out[n + ch] = row % 3 == ch ? w : 0.0;
    return w;
}

ResidualModel residual_model(const BrdfDatabase& db, const std::vector<uint8_t>& use) {
    const int K = db.size();
    const std::vector<int> cols = used_columns(K, &use);
    const Eigen::Map<const MatrixXd> G(db.gram(), K, K);
    ResidualModel m;
    m.K = K;
    m.R.assign(size_t(K) * size_t(K), 0.0);
    m.n_used = double(cols.size());
    MatrixXd Rm = MatrixXd::Zero(K, K);  // column j: the combination giving r_j / |p_j|
    for (int j : cols) {
        const double gj = G(j, j);
        if (!(gj > 0.0)) continue;
        std::vector<int> others;
        for (int o : cols)
            if (o != j && G(o, o) > 0.0) others.push_back(o);
        const int n = int(others.size());
        VectorXd coef = VectorXd::Zero(n);
        if (n > 0) {
            MatrixXd A(n, n);
            VectorXd g(n), s(n);
            for (int a = 0; a < n; ++a) s(a) = std::sqrt(G(others[size_t(a)], others[size_t(a)]));
            for (int a = 0; a < n; ++a) {
                g(a) = G(others[size_t(a)], j) / s(a);
                for (int b = 0; b < n; ++b)
                    A(a, b) = G(others[size_t(a)], others[size_t(b)]) / (s(a) * s(b));
            }
            A.diagonal().array() += 1e-10;  // the database is nearly rank-deficient
            coef = A.ldlt().solve(g).cwiseQuotient(s);
        }
        const double inv = 1.0 / std::sqrt(gj);
        Rm(j, j) = inv;
        for (int a = 0; a < n; ++a) Rm(others[size_t(a)], j) = -coef(a) * inv;
    }
    // Grid mean of sigma^2, exactly: trace(R^T G R) / rows / n_used.
    const double total = (Rm.transpose() * G * Rm).trace();
    m.grid_mean = m.n_used > 0 ? std::max(total, 0.0) / double(db.rows()) / m.n_used : 0.0;
    m.floor = 0.01 * m.grid_mean + 1e-300;
    for (int a = 0; a < K; ++a)
        for (int b = 0; b < K; ++b) m.R[size_t(a) * size_t(K) + size_t(b)] = Rm(a, b);
    return m;
}

std::vector<double> loo_oracle_errors(const BrdfDatabase& db, const std::vector<uint8_t>& use) {
    const int K = db.size();
    const ResidualModel m = residual_model(db, use);
    const Eigen::Map<const MatrixXd> G(db.gram(), K, K);
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> R(m.R.data(), K, K);
    std::vector<double> e(size_t(K), 0.0);
    for (int j = 0; j < K; ++j) {
        const VectorXd r = R.col(j);
        e[size_t(j)] = std::sqrt(std::max(0.0, r.dot(G * r)));
    }
    return e;
}

std::vector<double> row_sigma2(const BrdfDatabase& db, const ResidualModel& m, const std::vector<size_t>& rows) {
    const int K = m.K;
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> R(m.R.data(), K, K);
    std::vector<double> out(rows.size());
    // A block of rows times R as one product (the planning pool is ~10^5 rows; row by row
    // this was a quarter of the database bench). Blocks keep the gathered values small.
    constexpr size_t kBlock = 2048;
    MatrixXd V;
    for (size_t r0 = 0; r0 < rows.size(); r0 += kBlock) {
        const size_t n = std::min(kBlock, rows.size() - r0);
        V.resize(Index(n), K);
        for (int a = 0; a < K; ++a) {
            const float* col = db.column(a);
            for (size_t i = 0; i < n; ++i) V(Index(i), a) = double(col[rows[r0 + i]]);
        }
        const VectorXd s = (V * R).rowwise().squaredNorm();
        for (size_t i = 0; i < n; ++i)
            out[r0 + i] = (m.n_used > 0 ? s(Index(i)) / m.n_used : 0.0) + m.floor;
    }
    return out;
}

std::vector<double> pca_variances(const double* gram, int K) {
    MatrixXd G = Eigen::Map<const MatrixXd>(gram, K, K);
    const MatrixXd H = MatrixXd::Identity(K, K) - MatrixXd::Constant(K, K, 1.0 / K);
    Eigen::SelfAdjointEigenSolver<MatrixXd> es(H * G * H, Eigen::EigenvaluesOnly);
    std::vector<double> v(static_cast<size_t>(K));
    for (int i = 0; i < K; ++i) v[size_t(i)] = std::max(0.0, es.eigenvalues()(K - 1 - i));
    return v;
}

std::vector<double> pca_projection_errors(const double* gram, int K, int k, bool leave_out,
                                          int max_dims, const std::vector<uint8_t>* use) {
    const std::vector<int> S = used_columns(K, use, leave_out ? k : -1);
    const int n = int(S.size());
    std::vector<double> out;
    if (n == 0) return out;
    auto G = [&](int a, int b) { return gram[size_t(a) * size_t(K) + size_t(b)]; };
    MatrixXd GS(n, n);
    VectorXd gk(n);
    for (int a = 0; a < n; ++a) {
        gk(a) = G(S[size_t(a)], k);
        for (int b = 0; b < n; ++b) GS(a, b) = G(S[size_t(a)], S[size_t(b)]);
    }
    const MatrixXd H = MatrixXd::Identity(n, n) - MatrixXd::Constant(n, n, 1.0 / n);
    Eigen::SelfAdjointEigenSolver<MatrixXd> es(H * GS * H);
    // t = p_k - mean; |t|^2 and its coordinates on the principal directions, from G alone.
    const VectorXd ones = VectorXd::Ones(n);
    const double t2 = G(k, k) - 2.0 / n * gk.sum() + ones.dot(GS * ones) / (double(n) * n);
    const VectorXd q = H * (gk - GS * ones / n);
    const double top = std::max(es.eigenvalues()(n - 1), 0.0);
    double res = std::max(t2, 0.0);
    out.push_back(res);
    for (int d = 1; d <= max_dims && d <= n - 1; ++d) {
        const int i = n - d;  // eigenvalues ascending
        const double mu = es.eigenvalues()(i);
        if (!(mu > top * 1e-14)) break;  // no further components (numerically zero)
        const double p = es.eigenvectors().col(i).dot(q) / std::sqrt(mu);
        res = std::max(res - p * p, 0.0);
        out.push_back(res);
    }
    return out;
}

int nnls_gram(const std::vector<double>& Avec, const std::vector<double>& gvec, int n,
              std::vector<double>* cout) {
    const Eigen::Map<const MatrixXd> A(Avec.data(), n, n);  // symmetric: order irrelevant
    const Eigen::Map<const VectorXd> g(gvec.data(), n);
    VectorXd c = VectorXd::Zero(n);
    std::vector<uint8_t> passive(size_t(n), 0);
    // A variable that left the passive set in the same outer step that brought it in (possible
    // only through rounding on a nearly singular A) is not offered again until the passive
    // set changes otherwise: no cycling.
    std::vector<uint8_t> blocked(size_t(n), 0);
    const double tol = 1e-12 * std::max(1.0, g.cwiseAbs().maxCoeff());
    int iter = 0;
    const int max_iter = 3 * n + 10;
    VectorXd w = g - A * c;
    while (iter < max_iter) {
        int jmax = -1;
        double wmax = tol;
        for (int j = 0; j < n; ++j)
            if (!passive[size_t(j)] && !blocked[size_t(j)] && w(j) > wmax) {
                wmax = w(j);
                jmax = j;
            }
        if (jmax < 0) break;
        passive[size_t(jmax)] = 1;
        ++iter;
        for (int inner = 0; inner < 3 * n; ++inner) {
            std::vector<int> P;
            for (int j = 0; j < n; ++j)
                if (passive[size_t(j)]) P.push_back(j);
            const int m = int(P.size());
            MatrixXd App(m, m);
            VectorXd gp(m);
            for (int a = 0; a < m; ++a) {
                gp(a) = g(P[size_t(a)]);
                for (int b = 0; b < m; ++b) App(a, b) = A(P[size_t(a)], P[size_t(b)]);
            }
            const VectorXd sp = App.ldlt().solve(gp);
            bool all_pos = true;
            for (int a = 0; a < m; ++a) all_pos = all_pos && sp(a) > 0.0;
            if (all_pos) {
                c.setZero();
                for (int a = 0; a < m; ++a) c(P[size_t(a)]) = sp(a);
                break;
            }
            // Step from c towards s until the first passive coefficient reaches 0.
            double alpha = 1.0;
            for (int a = 0; a < m; ++a) {
                const int j = P[size_t(a)];
                if (sp(a) <= 0.0) {
                    const double den = c(j) - sp(a);
                    if (den > 0.0) alpha = std::min(alpha, c(j) / den);
                }
            }
            VectorXd s = VectorXd::Zero(n);
            for (int a = 0; a < m; ++a) s(P[size_t(a)]) = sp(a);
            c += alpha * (s - c);
            for (int j = 0; j < n; ++j)
                if (passive[size_t(j)] && c(j) <= tol * 1e-3) {
                    passive[size_t(j)] = 0;
                    c(j) = 0.0;
                }
        }
        if (passive[size_t(jmax)]) {
            std::fill(blocked.begin(), blocked.end(), 0);
        } else {
            blocked[size_t(jmax)] = 1;
        }
        w = g - A * c;
    }
    cout->assign(size_t(n), 0.0);
    for (int j = 0; j < n; ++j) (*cout)[size_t(j)] = std::max(c(j), 0.0);
    return iter;
}

bool fit_combination(const BrdfDatabase& db, const std::vector<size_t>& rows,
                     const std::vector<double>& values, const std::vector<uint8_t>& use,
                     const FitOptions& opt, CombinationFit* fit, std::string* err) {
    const int K = db.size();
    if (rows.size() != values.size() || rows.empty()) {
        if (err) *err = "fit: " + std::to_string(rows.size()) + " rows and " +
                        std::to_string(values.size()) + " values (need as many, at least 1)";
        return false;
    }
    for (size_t i = 0; i < rows.size(); ++i) {
        if (rows[i] >= db.rows()) {
            if (err) *err = "fit: sample " + std::to_string(i) + " names row " +
                            std::to_string(rows[i]) + ", outside the database's " +
                            std::to_string(db.rows());
            return false;
        }
        if (!std::isfinite(values[i])) {
            if (err) *err = "fit: sample " + std::to_string(i) + " is not a finite number";
            return false;
        }
    }
    if (!use.empty() && int(use.size()) != K) {
        if (err) *err = "fit: the material mask has the wrong size";
        return false;
    }
    const std::vector<int> cols = used_columns(K, &use);
    if (cols.empty()) {
        if (err) *err = "fit: no database material left to combine";
        return false;
    }
    *fit = CombinationFit();
    fit->space = opt.space;
    if (opt.space == FitSpace::kLog) {
        fit_combination_log(db, rows, values, cols, opt, fit);
        return true;
    }
    std::vector<double> scale, w;
    if (opt.weighted) w = row_weights(db, rows, use);
    const MatrixXd X = sample_matrix(db, rows, cols, &scale, opt.weighted ? &w : nullptr);
    VectorXd b = Eigen::Map<const VectorXd>(values.data(), Index(values.size()));
    if (opt.weighted)
        for (size_t i = 0; i < rows.size(); ++i) b(Index(i)) *= w[i];
    const int M = int(cols.size());
    MatrixXd A = X.transpose() * X;
    const VectorXd g = X.transpose() * b;
    fit->lambda = ridge_lambda(A, opt.max_condition, fit);
    A.diagonal().array() += fit->lambda;
    VectorXd cn(M);
    if (opt.solver == Solver::kNonNegative) {
        std::vector<double> Av(A.data(), A.data() + A.size()), gv(g.data(), g.data() + M), c;
        fit->solver_iterations = nnls_gram(Av, gv, M, &c);
        cn = Eigen::Map<const VectorXd>(c.data(), M);
    } else {
        cn = A.ldlt().solve(g);
    }
    fit->coeffs.assign(size_t(K), 0.0);
    for (int j = 0; j < M; ++j) {
        const double c = scale[size_t(j)] > 0.0 ? cn(j) / scale[size_t(j)] : 0.0;
        fit->coeffs[size_t(cols[size_t(j)])] = c;
        fit->nonzero += c != 0.0;
    }
    const double bn = b.norm();
    fit->sample_rms = bn > 0.0 ? (X * cn - b).norm() / bn : (X * cn).norm();
    return true;
}

double plan_condition(const BrdfDatabase& db, const std::vector<size_t>& rows,
                      const std::vector<uint8_t>& use, bool weighted, FitSpace space) {
    const std::vector<int> cols = used_columns(db.size(), &use);
    if (space == FitSpace::kLog) {
        MatrixXd X = log_design(db, rows, cols);
        for (Index j = 0; j < X.cols(); ++j)
            if (X.col(j).norm() > 0.0) X.col(j) /= X.col(j).norm();
        double lo, hi;
        extreme_eigenvalues(X.transpose() * X, &lo, &hi);
        return condition_of(lo, hi);
    }
    std::vector<double> scale, w;
    if (weighted) w = row_weights(db, rows, use);
    const MatrixXd X = sample_matrix(db, rows, cols, &scale, weighted ? &w : nullptr);
    double lo, hi;
    extreme_eigenvalues(X.transpose() * X, &lo, &hi);
    return condition_of(lo, hi);
}

namespace {

// sum_j c_j x_j over every row, x_j = P_j (linear) or log(P_j + eps) with the log model's
// value (exp(sum + d_channel) - eps) taken (offsets given); counts the values below 0.
template <bool kLog>
std::vector<float> combine_rows(const BrdfDatabase& db, const std::vector<double>& coeffs, const double* offsets,
                                size_t* negative, int threads) {
    const size_t R = db.rows();
    std::vector<int> nz;
    for (int j = 0; j < db.size() && j < int(coeffs.size()); ++j)
        if (coeffs[size_t(j)] != 0.0) nz.push_back(j);
    std::vector<float> out(R, 0.0f);
    constexpr size_t kChunk = 1 << 14;
    const size_t chunks = (R + kChunk - 1) / kChunk;
    std::vector<size_t> neg(chunks, 0);
    parallel_for(chunks, threads, [&](size_t ch) {
        const size_t r0 = ch * kChunk, r1 = std::min(R, r0 + kChunk);
        std::vector<double> acc(r1 - r0, 0.0);
        for (int j : nz) {
            const float* col = db.column(j);
            const double c = coeffs[size_t(j)];
            for (size_t r = r0; r < r1; ++r)
                acc[r - r0] += c * (kLog ? std::log(double(col[r]) + kDatabaseLogEps) : double(col[r]));
        }
        for (size_t r = r0; r < r1; ++r) {
            const double v = kLog ? log_model_value(acc[r - r0] + offsets[r % 3]) : acc[r - r0];
            out[r] = float(v);
            neg[ch] += v < 0.0;
        }
    });
    if (negative) {
        *negative = 0;
        for (size_t n : neg) *negative += n;
    }
    return out;
}

}  // namespace

std::vector<float> combination_values(const BrdfDatabase& db, const std::vector<double>& coeffs,
                                      size_t* negative, int threads) {
    return combine_rows<false>(db, coeffs, nullptr, negative, threads);
}

std::vector<float> fit_values(const BrdfDatabase& db, const CombinationFit& fit, size_t* negative, int threads) {
    if (fit.space == FitSpace::kLinear) return combination_values(db, fit.coeffs, negative, threads);
    return combine_rows<true>(db, fit.coeffs, fit.offsets, negative, threads);
}

double combination_error_gram(const BrdfDatabase& db, const std::vector<double>& coeffs, int k) {
    const int K = db.size();
    const Eigen::Map<const MatrixXd> G(db.gram(), K, K);
    VectorXd d = Eigen::Map<const VectorXd>(coeffs.data(), K);
    d(k) -= 1.0;
    const double e2 = d.dot(G * d);
    const double gkk = G(k, k);
    return gkk > 0.0 ? std::sqrt(std::max(e2, 0.0) / gkk) : 0.0;
}

double relative_rms(const std::vector<float>& approx, const std::vector<float>& truth) {
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < truth.size() && i < approx.size(); ++i) {
        const double d = double(approx[i]) - double(truth[i]);
        num += d * d;
        den += double(truth[i]) * truth[i];
    }
    return den > 0.0 ? std::sqrt(num / den) : std::sqrt(num);
}

}  // namespace sepal
