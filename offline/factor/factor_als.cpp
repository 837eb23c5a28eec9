// Weighted alternating least squares on the held matrix (als.h): NMF's multiplicative
// updates, ACLS's constrained block updates, SACLS's sparse row solves and the weighted
// refinement of the SVD share it.
//
// With one side fixed, the weighted problem separates per row (or column) r:
//   min_g sum_c w_rc (m_rc - g . h_c)^2  =  g^T C_r g - 2 g^T b_r + ssq_r,
//   C_r = sum_c w_rc h_c h_c^T,  b_r = sum_c w_rc m_rc h_c,
// so one pass over the matrix builds every C_r and b_r, and each rule works from them:
//   least squares   g = C_r^-1 b_r
//   multiplicative  g <- g . b_r / (C_r g)          (Lee-Seung with weights; repeated
//                   `inner` times per pass, as in Gillis-Glineur's accelerated MU)
//   constrained     exact per-term block updates (HALS): g_a = target given the others,
//                   clamped to >= 0, or a tree isotonic regression over the whole column
//                   for monotone factors; column 0 of one side may be held at 1; with
//                   energy groups, the weighted projection onto each group's bound.
//   sparse          per row, g = the non-negative minimizer of the normal equations plus
//                   SACLS's penalties (Lawson-Hanson on k x k), best over the free term.
// The error g^T C g - 2 g^T b + ssq comes out of the same sums without another pass.
#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "factor/factor_internal.h"
#include "util/parallel.h"
#include "util/thin_product.h"

namespace sepal {
namespace detail {

namespace {
struct Normals {
    std::vector<double> c, b, ssq;  // n*k*k, n*k, n
};

// side 0: normals of every row given h; side 1: of every column given g.
using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using RowMatF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

double anchor_value(const LowRank& a, int r, int c) {
    double s = 0;
    for (int j = 0; j < a.k; ++j) s += a.g[size_t(r) * a.k + j] * a.h[size_t(c) * a.k + j];
    return s;
}

// sum w x^2 per row and per column, entries without data counting toward the anchor.
void sums_of_squares(const Matrix& m, int ch, const LowRank* anchor, double anchor_weight,
                     std::vector<double>* rows_ssq, std::vector<double>* cols_ssq) {
    rows_ssq->assign(size_t(m.rows), 0.0);
    cols_ssq->assign(size_t(m.cols), 0.0);
    const float* w = m.w.data();
    const float* wv = m.wv[size_t(ch)].data();
    for (int r = 0; r < m.rows; ++r)
        for (int c = 0; c < m.cols; ++c) {
            const size_t i = size_t(r) * m.cols + c;
            double q = 0;
            if (w[i] > 0) {
                q = double(wv[i]) * wv[i] / w[i];
            } else if (anchor) {
                const double a = anchor_value(*anchor, r, c);
                q = anchor_weight * a * a;
            }  // else: target 0, nothing to add
            (*rows_ssq)[size_t(r)] += q;
            (*cols_ssq)[size_t(c)] += q;
        }
}

// The weights and weighted values of one channel as doubles, entries without data filled
// in (toward 0 with the horizon weight, or toward the anchor): built once per solve, so the
// passes are matrix products only.
// Complete data with one confidence everywhere (the IST's generated and fully observed
// SVBRDFs) gives every line the same Gram matrix: `uniform` is that weight (w is then left
// empty and the W P product, 70% of the multiply-adds at 4 terms, is a column sum of P).
struct Weighted {
    RowMat w, wm;
    double uniform = -1;
};

void build_weighted(const Matrix& m, int ch, const LowRank* anchor, double anchor_weight, bool shortcut,
                    Weighted* out) {
    out->wm = Eigen::Map<const RowMatF>(m.wv[size_t(ch)].data(), m.rows, m.cols).cast<double>();
    const float w0 = m.w.empty() ? 0.0f : m.w[0];
    if (shortcut && w0 > 0 && std::all_of(m.w.begin(), m.w.end(), [w0](float x) { return x == w0; })) {
        out->uniform = double(w0);
        out->w.resize(0, 0);
        return;
    }
    out->uniform = -1;
    out->w = Eigen::Map<const RowMatF>(m.w.data(), m.rows, m.cols).cast<double>();
    if (!(anchor_weight > 0)) return;
    for (int r = 0; r < m.rows; ++r)
        for (int c = 0; c < m.cols; ++c) {
            if (out->w(r, c) > 0) continue;
            out->w(r, c) = anchor_weight;
            out->wm(r, c) = anchor ? anchor_weight * anchor_value(*anchor, r, c) : 0.0;
        }
}

// Scratch per worker thread, kept across the passes of one solve.
struct Scratch {
    std::vector<double> cp, bp;  // sized once for a full chunk, viewed by Maps
};

// All normal equations of one side in two matrix products per chunk of 256 rows (or
// columns; 32 on short sides), so the work runs at GEMM speed: with P[c][ab] = h_c[a] h_c[b] (a >= b),
//   C_r[a][b] = sum_c w_rc P[c][ab]   ->  C = W P,      b_r = (W.M) H.
void build_normals(const Weighted& wt, int side, const std::vector<double>& other, int k,
                   const std::vector<double>& ssq, Normals* out, std::vector<Scratch>* scratch, int threads) {
    const int rows = int(wt.wm.rows()), cols = int(wt.wm.cols());
    const int n = side == 0 ? rows : cols, n_other = side == 0 ? cols : rows;
    const int kk = k * (k + 1) / 2;
    out->c.assign(size_t(n) * k * k, 0.0);
    out->b.assign(size_t(n) * k, 0.0);
    out->ssq = ssq;
    const Eigen::Map<const RowMat> o(other.data(), n_other, k);
    RowMat p(n_other, kk);
    for (int c = 0; c < n_other; ++c)
        for (int a = 0, q = 0; a < k; ++a)
            for (int bb = 0; bb <= a; ++bb, ++q) p(c, q) = o(c, a) * o(c, bb);
    std::vector<double> common;  // uniform weights: every line's packed Gram matrix
    if (wt.uniform > 0) {
        common.assign(size_t(kk), 0.0);
        for (int c = 0; c < n_other; ++c)
            for (int q = 0; q < kk; ++q) common[size_t(q)] += p(c, q);
        for (double& x : common) x *= wt.uniform;
    }
    // Chunks of 256 lines on long sides: each chunk's Eigen product packs all of p (n_other x kk)
    // again, which at 32 lines took as long as the multiply-adds (IST's 96 x 96 texels), and
    // thin_product_t streams 256-wide row segments far better than 32-wide ones (2.8 vs 5.7
    // ms at 2304 x 1344, k = 4; 128 lines 10% better than 32 at 812 x 812); short sides keep
    // 32 so they still split across threads. A function of n only (determinism); the thin
    // products do not depend on it at all, and Eigen's gave the same results at either size
    // (ist.json identical).
    const int step = n >= 1024 ? 256 : n >= 512 ? 128 : 32;
    const size_t chunks = size_t((n + step - 1) / step);
    scratch->resize(size_t(workers(chunks, threads)));
    parallel_for_workers(chunks, threads, [&](size_t chunk, int worker) {
        const int i0 = int(chunk) * step, ni = std::min(n, i0 + step) - i0;
        Scratch& sc = (*scratch)[size_t(worker)];
        if (sc.cp.size() < size_t(step) * kk) sc.cp.resize(size_t(step) * kk), sc.bp.resize(size_t(step) * k);
        Eigen::Map<RowMat> cp(sc.cp.data(), ni, kk), bp(sc.bp.data(), ni, k);
        const bool uniform = wt.uniform > 0;
        // thin_product(_t) where the outputs are few (2..8 of them), Eigen otherwise.
        const size_t ld = size_t(cols);
        if (side == 0) {
            if (!uniform && !thin_product(&wt.w(i0, 0), ld, ni, cols, p.data(), kk, cp.data()))
                cp.noalias() = wt.w.middleRows(i0, ni) * p;
            if (!thin_product(&wt.wm(i0, 0), ld, ni, cols, o.data(), k, bp.data()))
                bp.noalias() = wt.wm.middleRows(i0, ni) * o;
        } else {
            if (!uniform && !thin_product_t(wt.w.data(), ld, rows, i0, ni, p.data(), kk, cp.data()))
                cp.noalias() = wt.w.middleCols(i0, ni).transpose() * p;
            if (!thin_product_t(wt.wm.data(), ld, rows, i0, ni, o.data(), k, bp.data()))
                bp.noalias() = wt.wm.middleCols(i0, ni).transpose() * o;
        }
        for (int line = 0; line < ni; ++line) {
            double* cr = &out->c[size_t(i0 + line) * k * k];
            for (int a = 0, q = 0; a < k; ++a)
                for (int bb = 0; bb <= a; ++bb, ++q)
                    cr[a * k + bb] = cr[bb * k + a] = uniform ? common[size_t(q)] : cp(line, q);
            for (int a = 0; a < k; ++a) out->b[size_t(i0 + line) * k + a] = bp(line, a);
        }
    });
}

// Weighted squared error of side x given the normals built from the other side.
double side_error(const Normals& nm, const std::vector<double>& x, int n, int k) {
    double e = 0;
    for (int r = 0; r < n; ++r) {
        const double* c = &nm.c[size_t(r) * k * k];
        const double* b = &nm.b[size_t(r) * k];
        const double* g = &x[size_t(r) * k];
        double q = nm.ssq[size_t(r)];
        for (int a = 0; a < k; ++a) {
            double cg = 0;
            for (int bb = 0; bb < k; ++bb) cg += c[a * k + bb] * g[bb];
            q += g[a] * (cg - 2 * b[a]);
        }
        e += q;
    }
    return std::max(e, 0.0);
}

void solve_least_squares(const Normals& nm, std::vector<double>* x, int n, int k, double ridge_share,
                         int threads, std::atomic<int64_t>* fallbacks) {
    double mean_diag = 0;
    for (int r = 0; r < n; ++r)
        for (int a = 0; a < k; ++a) mean_diag += nm.c[size_t(r) * k * k + size_t(a) * k + a];
    const double ridge = ridge_share * mean_diag / (double(n) * k) + 1e-300;
    const size_t chunks = size_t((n + kColChunk - 1) / kColChunk);
    parallel_for(chunks, threads, [&](size_t chunk) {
        const int r0 = int(chunk) * kColChunk, r1 = std::min(n, r0 + kColChunk);
        int64_t fell_back = 0;
        for (int r = r0; r < r1; ++r) {
            Eigen::MatrixXd c = Eigen::Map<const Eigen::MatrixXd>(&nm.c[size_t(r) * k * k], k, k);
            const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(&nm.b[size_t(r) * k], k);
            double* g = &(*x)[size_t(r) * k];
            c.diagonal().array() += ridge;
            const Eigen::VectorXd sol = c.ldlt().solve(b);
            for (int a = 0; a < k; ++a) {
                if (std::isfinite(sol(a))) {
                    g[a] = sol(a);
                } else {
                    g[a] = 0.0;
                    ++fell_back;
                }
            }
        }
        if (fell_back && fallbacks) *fallbacks += fell_back;
    });
}

void solve_multiplicative(const Normals& nm, std::vector<double>* x, int n, int k, int inner,
                          int threads, std::atomic<int64_t>* fallbacks) {
    const size_t chunks = size_t((n + kColChunk - 1) / kColChunk);
    parallel_for(chunks, threads, [&](size_t chunk) {
        const int r0 = int(chunk) * kColChunk, r1 = std::min(n, r0 + kColChunk);
        int64_t fell_back = 0;
        std::vector<double> cg(size_t(k), 0.0);
        for (int r = r0; r < r1; ++r) {
            const double* c = &nm.c[size_t(r) * k * k];
            const double* b = &nm.b[size_t(r) * k];
            double* g = &(*x)[size_t(r) * k];
            for (int it = 0; it < inner; ++it) {
                for (int a = 0; a < k; ++a) {
                    double s = 0;
                    for (int bb = 0; bb < k; ++bb) s += c[a * k + bb] * g[bb];
                    cg[size_t(a)] = s;
                }
                for (int a = 0; a < k; ++a) {
                    const double den = cg[size_t(a)];
                    if (den > 1e-300) {
                        g[a] = g[a] * std::max(b[a], 0.0) / den;
                    } else {
                        // No data left to scale by (0/0): the entry goes to 0, counted
                        // unless it was 0 already (then nothing changed).
                        if (g[a] != 0.0) ++fell_back;
                        g[a] = 0.0;
                    }
                }
            }
        }
        if (fell_back && fallbacks) *fallbacks += fell_back;
    });
}

// The exact weighted projection of one term's column onto {x >= 0, sum coef x <= bound}
// per group: x_c = max(0, t_c - lambda coef_c / w_c) with the multiplier lambda >= 0 found
// by bisection (the sum falls monotonically in lambda).
void project_energy(const std::vector<EnergyGroup>& groups, const std::vector<double>& target,
                    const std::vector<double>& weight, double wfloor, std::vector<double>* x,
                    int k, int a) {
    for (const EnergyGroup& g : groups) {
        const size_t n = g.cols.size();
        auto value = [&](size_t i, double lambda) {
            const size_t c = size_t(g.cols[i]);
            const double w = std::max(weight[c], wfloor);
            return std::max(0.0, target[c] - lambda * g.coef[i] / w);
        };
        auto total = [&](double lambda) {
            double t = 0;
            for (size_t i = 0; i < n; ++i) t += g.coef[i] * value(i, lambda);
            return t;
        };
        double lambda = 0;
        if (total(0) > g.bound) {
            double hi = 1;
            for (int it = 0; it < 200 && total(hi) > g.bound; ++it) hi *= 4;
            double lo = 0;
            for (int it = 0; it < 100; ++it) {
                const double mid = 0.5 * (lo + hi);
                (total(mid) > g.bound ? lo : hi) = mid;
            }
            lambda = hi;  // the feasible side
        }
        for (size_t i = 0; i < n; ++i) (*x)[size_t(g.cols[i]) * k + a] = value(i, lambda);
    }
}

void solve_constrained(const Normals& nm, std::vector<double>* x, int n, int k, int side,
                       const AlsSettings& s) {
    const bool monotone = s.monotone_side == side && s.parent && s.order;
    std::vector<double> target(static_cast<size_t>(n)), weight(static_cast<size_t>(n)), iso;
    for (int sweep = 0; sweep < s.inner; ++sweep) {
        for (int a = 0; a < k; ++a) {
            if (s.constant_side == side && a == 0) continue;  // held at 1
            const bool mono_col = monotone && !(s.constant_side == side && a == 0);
            double wmax = 0;
            for (int r = 0; r < n; ++r) {
                const double* c = &nm.c[size_t(r) * k * k];
                const double* g = &(*x)[size_t(r) * k];
                double t = nm.b[size_t(r) * k + a];
                for (int bb = 0; bb < k; ++bb)
                    if (bb != a) t -= c[a * k + bb] * g[bb];
                const double caa = c[a * k + a];
                weight[size_t(r)] = caa;
                target[size_t(r)] = caa > 0 ? t / caa : g[a];
                wmax = std::max(wmax, caa);
            }
            if (mono_col) {
                // Rows without data still take part, with a negligible weight, so they
                // follow their neighbours instead of breaking the order.
                for (int r = 0; r < n; ++r)
                    weight[size_t(r)] = std::max(weight[size_t(r)], 1e-12 * wmax + 1e-300);
                tree_isotonic(*s.parent, *s.order, target, weight, &iso);
                for (int r = 0; r < n; ++r) (*x)[size_t(r) * k + a] = std::max(iso[size_t(r)], 0.0);
            } else {
                for (int r = 0; r < n; ++r)
                    if (weight[size_t(r)] > 0)
                        (*x)[size_t(r) * k + a] = std::max(target[size_t(r)], 0.0);
                if (side == 1 && s.energy)
                    project_energy(*s.energy, target, weight, 1e-12 * wmax + 1e-300, x, k, a);
            }
        }
    }
}

// SACLS's row solve (Lawrence et al. 2006, eq. 4-5). Returns the penalties' total.
double solve_sparse(const Normals& nm, std::vector<double>* x, int n, int k, const AlsSettings& s) {
    const double l = s.sparsity_l, mm = s.sparsity_m;
    double mean_diag = 0;
    for (int r = 0; r < n; ++r)
        for (int a = 0; a < k; ++a) mean_diag += nm.c[size_t(r) * k * k + size_t(a) * k + a];
    const double ridge = 1e-12 * mean_diag / (double(n) * k) + 1e-300;
    std::vector<double> pen(size_t(n), 0.0);
    const size_t chunks = size_t((n + kColChunk - 1) / kColChunk);
    parallel_for(chunks, s.threads, [&](size_t chunk) {
        const int r0 = int(chunk) * kColChunk, r1 = std::min(n, r0 + kColChunk);
        const size_t kn = static_cast<size_t>(k);
        std::vector<double> a(kn * kn), b(kn), xj(kn), best(kn);
        for (int r = r0; r < r1; ++r) {
            const double* c = &nm.c[size_t(r) * k * k];
            const double* br = &nm.b[size_t(r) * k];
            double best_obj = std::numeric_limits<double>::infinity(), best_pen = 0;
            const int choices = l > 0 ? k : 1;
            for (int j = 0; j < choices; ++j) {
                for (int p = 0; p < k; ++p) {
                    for (int q = 0; q < k; ++q) a[size_t(p) * k + q] = c[p * k + q] + mm;
                    a[size_t(p) * k + p] += ridge + (p != j ? l : 0.0);
                    b[size_t(p)] = br[p] + mm;
                }
                if (!nnls_gram(a.data(), b.data(), k, xj.data()) && s.fallbacks) ++*s.fallbacks;
                double obj = 0, sum = 0, sq = 0;
                for (int p = 0; p < k; ++p) {
                    double ax = 0;
                    for (int q = 0; q < k; ++q) ax += a[size_t(p) * k + q] * xj[size_t(q)];
                    obj += xj[size_t(p)] * (ax - 2 * b[size_t(p)]);
                    sum += xj[size_t(p)];
                    if (p != j) sq += xj[size_t(p)] * xj[size_t(p)];
                }
                if (obj < best_obj) {
                    best_obj = obj;
                    best = xj;
                    best_pen = (l > 0 ? l * sq : 0.0) + mm * (1 - sum) * (1 - sum);
                }
            }
            std::copy(best.begin(), best.end(), x->begin() + long(size_t(r) * k));
            pen[size_t(r)] = best_pen;
        }
    });
    double total = 0;
    for (double p : pen) total += p;
    return total;
}

// Returns the side's penalty (the Sparse rule's, on side 0; otherwise 0).
double solve_side(const Normals& nm, std::vector<double>* x, int n, int k, int side,
                  const AlsSettings& s) {
    switch (s.rule) {
        case AlsRule::LeastSquares: solve_least_squares(nm, x, n, k, s.ridge, s.threads, s.fallbacks); break;
        case AlsRule::Multiplicative:
            solve_multiplicative(nm, x, n, k, s.inner, s.threads, s.fallbacks);
            break;
        case AlsRule::Constrained: solve_constrained(nm, x, n, k, side, s); break;
        case AlsRule::Sparse:
            if (side == 0) return solve_sparse(nm, x, n, k, s);
            solve_constrained(nm, x, n, k, side, s);
            break;
    }
    return 0;
}

// Equal largest magnitudes for g_a and h_a: products unchanged, no drift in scale.
void balance(LowRank* f, int rows, int cols, int skip) {
    const int k = f->k;
    for (int a = 0; a < k; ++a) {
        if (a == skip) continue;
        double mg = 0, mh = 0;
        for (int r = 0; r < rows; ++r) mg = std::max(mg, std::fabs(f->g[size_t(r) * k + a]));
        for (int c = 0; c < cols; ++c) mh = std::max(mh, std::fabs(f->h[size_t(c) * k + a]));
        if (!(mg > 0) || !(mh > 0)) continue;
        const double s = std::sqrt(mh / mg);
        for (int r = 0; r < rows; ++r) f->g[size_t(r) * k + a] *= s;
        for (int c = 0; c < cols; ++c) f->h[size_t(c) * k + a] /= s;
    }
}
}  // namespace

double als_solve(const Matrix& m, int channel, const AlsSettings& s, LowRank* f,
                 int* iterations) {
    const int k = f->k, rows = m.rows, cols = m.cols;
    Normals nm;
    double prev = std::numeric_limits<double>::infinity(), err = 0;
    int it = 0;
    // A column held at 1 may not be rescaled: its term is left out of the balancing.
    const int skip = s.constant_side >= 0 ? 0 : -1;
    // Entries without data: toward 0 with horizon_weight, or toward the anchor.
    const LowRank* anchor = s.horizon_weight > 0 ? nullptr : s.anchor;
    const double inv_w = s.horizon_weight > 0 ? s.horizon_weight : anchor ? s.anchor_weight : 0.0;
    std::vector<Scratch> scratch;
    std::vector<double> ssq_rows, ssq_cols;
    sums_of_squares(m, channel, anchor, inv_w, &ssq_rows, &ssq_cols);
    const bool rescale = s.rule != AlsRule::Sparse && !s.energy;
    Weighted wt;
    build_weighted(m, channel, anchor, inv_w, s.uniform_shortcut, &wt);
    while (it < s.max_iters) {
        ++it;
        build_normals(wt, 0, f->h, k, ssq_rows, &nm, &scratch, s.threads);
        const double penalty = solve_side(nm, &f->g, rows, k, 0, s);
        build_normals(wt, 1, f->g, k, ssq_cols, &nm, &scratch, s.threads);
        solve_side(nm, &f->h, cols, k, 1, s);
        err = side_error(nm, f->h, cols, k) + penalty;
        if (rescale) balance(f, rows, cols, skip);
        double total = 0;
        for (double q : nm.ssq) total += q;
        if (err <= 1e-24 * total) break;
        if (std::isfinite(prev) && prev - err <= s.tolerance * prev) break;
        prev = err;
    }
    if (iterations) *iterations = it;
    return err;
}

double als_project(const Matrix& m, int channel, const AlsSettings& s, LowRank* f) {
    const LowRank* anchor = s.horizon_weight > 0 ? nullptr : s.anchor;
    const double inv_w = s.horizon_weight > 0 ? s.horizon_weight : anchor ? s.anchor_weight : 0.0;
    std::vector<double> ssq_rows, ssq_cols;
    sums_of_squares(m, channel, anchor, inv_w, &ssq_rows, &ssq_cols);
    Normals nm;
    std::vector<Scratch> scratch;
    Weighted wt;
    build_weighted(m, channel, anchor, inv_w, s.uniform_shortcut, &wt);
    build_normals(wt, 0, f->h, f->k, ssq_rows, &nm, &scratch, s.threads);
    const double penalty = solve_side(nm, &f->g, m.rows, f->k, 0, s);
    return side_error(nm, f->g, m.rows, f->k) + penalty;
}

void nndsvd_column(const LowRank& svd, int j, LowRank* out, int a, bool fill_zeros) {
    const size_t rows = svd.g.size() / size_t(svd.k), cols = svd.h.size() / size_t(svd.k);
    double pg = 0, ng = 0, ph = 0, nh = 0;
    for (size_t r = 0; r < rows; ++r) {
        const double x = svd.g[r * svd.k + j];
        (x > 0 ? pg : ng) += x * x;
    }
    for (size_t c = 0; c < cols; ++c) {
        const double x = svd.h[c * svd.k + j];
        (x > 0 ? ph : nh) += x * x;
    }
    const double sign = pg * ph >= ng * nh ? 1.0 : -1.0;
    auto fill = [&](const std::vector<double>& src, size_t n, int k_src, std::vector<double>* dst) {
        double sum = 0;
        int nz = 0;
        for (size_t r = 0; r < n; ++r) {
            const double x = std::max(0.0, sign * src[r * k_src + j]);
            (*dst)[r * out->k + a] = x;
            if (x > 0) sum += x, ++nz;
        }
        // Multiplicative updates never move a zero: start those entries small instead.
        if (fill_zeros) {
            const double small = nz ? 0.01 * sum / nz : 1e-3;
            for (size_t r = 0; r < n; ++r)
                if (!((*dst)[r * out->k + a] > 0)) (*dst)[r * out->k + a] = small;
        }
    };
    fill(svd.g, rows, svd.k, &out->g);
    fill(svd.h, cols, svd.k, &out->h);
}

bool nnls_gram(const double* a, const double* b, int n, double* x) {
    // Lawson and Hanson (1974), chapter 23, on the normal equations: a passive set P grows
    // by the most promising coordinate; the unconstrained solve on P is accepted when it
    // is positive, else the step toward it stops at the first coordinate that hits 0.
    constexpr int kMax = 16;
    if (n < 1 || n > kMax) return false;
    bool passive[kMax] = {};
    double z[kMax], l[kMax * kMax];
    std::fill(x, x + n, 0.0);
    double scale = 0;
    for (int i = 0; i < n; ++i) scale = std::max({scale, std::fabs(b[i]), std::fabs(a[i * n + i])});
    const double tol = 1e-13 * scale;
    // Cholesky of a restricted to P, solving for z on P (0 elsewhere); false on breakdown.
    auto solve_passive = [&]() {
        int idx[kMax], m = 0;
        for (int i = 0; i < n; ++i)
            if (passive[i]) idx[m++] = i;
        for (int p = 0; p < m; ++p)
            for (int q = 0; q <= p; ++q) {
                double v = a[idx[p] * n + idx[q]];
                for (int r = 0; r < q; ++r) v -= l[p * kMax + r] * l[q * kMax + r];
                if (p == q) {
                    if (!(v > 1e-300)) return false;
                    l[p * kMax + p] = std::sqrt(v);
                } else {
                    l[p * kMax + q] = v / l[q * kMax + q];
                }
            }
        double y[kMax];
        for (int p = 0; p < m; ++p) {
            double v = b[idx[p]];
            for (int r = 0; r < p; ++r) v -= l[p * kMax + r] * y[r];
            y[p] = v / l[p * kMax + p];
        }
        std::fill(z, z + n, 0.0);
        for (int p = m - 1; p >= 0; --p) {
            double v = y[p];
            for (int r = p + 1; r < m; ++r) v -= l[r * kMax + p] * z[idx[r]];
            z[idx[p]] = v / l[p * kMax + p];
        }
        return true;
    };
    for (int outer = 0; outer < 3 * n; ++outer) {
        int t = -1;
        double best = tol;
        for (int i = 0; i < n; ++i) {
            if (passive[i]) continue;
            double w = b[i];
            for (int j = 0; j < n; ++j) w -= a[i * n + j] * x[j];
            if (w > best) best = w, t = i;
        }
        if (t < 0) return true;
        passive[t] = true;
        for (int inner = 0; inner < 3 * n; ++inner) {
            if (!solve_passive()) {
                std::fill(x, x + n, 0.0);
                return false;
            }
            bool positive = true;
            for (int i = 0; i < n; ++i)
                if (passive[i] && z[i] <= 0) positive = false;
            if (positive) {
                std::copy(z, z + n, x);
                break;
            }
            double alpha = 1;
            int stop = -1;  // the coordinate the step stops at: it leaves P exactly at 0
            for (int i = 0; i < n; ++i)
                if (passive[i] && z[i] <= 0) {
                    const double q = x[i] / (x[i] - z[i]);
                    if (stop < 0 || q < alpha) alpha = q, stop = i;
                }
            for (int i = 0; i < n; ++i) {
                if (!passive[i]) continue;
                x[i] += alpha * (z[i] - x[i]);
                if (i == stop || x[i] <= 0) passive[i] = false, x[i] = 0;
            }
        }
    }
    return true;
}

void tree_isotonic(const std::vector<int>& parent, const std::vector<int>& order,
                   const std::vector<double>& y, const std::vector<double>& w,
                   std::vector<double>* x) {
    // Bottom-up pooling (Pardalos and Xue 1999): a node starts as its own block; while the
    // child block with the largest mean exceeds the node's block mean, the two pool.
    // Children are processed before parents, so a child's block is final when its parent
    // arrives, and its top node is that child.
    const size_t n = y.size();
    std::vector<std::vector<int>> kids(n);
    for (size_t v = 0; v < n; ++v)
        if (parent[v] >= 0) kids[size_t(parent[v])].push_back(int(v));
    struct Block {
        double sw = 0, swy = 0;
        std::vector<int> members, kids;
        bool alive = true;
    };
    std::vector<Block> blocks;
    blocks.reserve(n);
    std::vector<int> block_of(n, -1);
    for (int v : order) {
        const int b = int(blocks.size());
        blocks.emplace_back();
        blocks[size_t(b)].sw = w[size_t(v)];
        blocks[size_t(b)].swy = w[size_t(v)] * y[size_t(v)];
        blocks[size_t(b)].members.push_back(v);
        for (int c : kids[size_t(v)]) blocks[size_t(b)].kids.push_back(block_of[size_t(c)]);
        for (;;) {
            Block& cur = blocks[size_t(b)];
            int best = -1;
            double best_mean = -std::numeric_limits<double>::infinity();
            size_t best_pos = 0;
            for (size_t i = 0; i < cur.kids.size(); ++i) {
                const Block& kb = blocks[size_t(cur.kids[i])];
                const double mean = kb.swy / kb.sw;
                if (mean > best_mean) best = cur.kids[i], best_mean = mean, best_pos = i;
            }
            if (best < 0 || !(best_mean > cur.swy / cur.sw)) break;
            Block& kb = blocks[size_t(best)];
            cur.sw += kb.sw;
            cur.swy += kb.swy;
            cur.members.insert(cur.members.end(), kb.members.begin(), kb.members.end());
            cur.kids.erase(cur.kids.begin() + long(best_pos));
            cur.kids.insert(cur.kids.end(), kb.kids.begin(), kb.kids.end());
            kb.alive = false;
            kb.members.clear();
            kb.kids.clear();
        }
        block_of[size_t(v)] = b;
    }
    x->assign(n, 0.0);
    for (const Block& b : blocks)
        if (b.alive)
            for (int v : b.members) (*x)[size_t(v)] = b.swy / b.sw;
}

}  // namespace detail
}  // namespace sepal
