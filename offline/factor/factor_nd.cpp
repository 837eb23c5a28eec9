// Normalized decomposition (Kautz and McCool 1999, section 4.2), streamed over rows.
//
// One term: G(x) = (sum_y w |f|^p / sum_y w)^(1/p), the p-norm of row x (a weighted mean,
// so rows of different valid lengths compare), and H(y) = the weighted average over rows
// of f(x, y) / G(x), the average normalized profile. Further terms factor the residual of
// the terms so far the same way; a residual row has no natural sign, so each row's G takes
// the sign of its weighted correlation with the residual row of largest norm (a reference
// profile) - without it the averaged profiles of rows of opposite sign would cancel.
// Rows are sampled again for every pass instead of being kept: term 1 needs one pass,
// each further term two (find the reference row, then accumulate); memory is the output
// plus per-chunk sums of H. Rows with |G| below 1e-6 of the largest are left out of the
// average of a residual term (their profiles would be noise divided by almost nothing).
#include <algorithm>
#include <chrono>
#include <cmath>

#include "factor/factor_internal.h"
#include "util/parallel.h"

namespace sepal {
namespace detail {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// One nd_factor call: the sampler, the factors being built and the row chunks the passes
// run over in parallel (each chunk's sums kept apart and added in chunk order, so the
// result does not depend on the thread count).
struct NdRun {
    NdRun(const PairSampler& sampler, const FactorOptions& options, int channels, std::vector<LowRank>* factors)
        : s(sampler), o(options), rows(s.rows()), cols(s.cols()), big_k(o.terms), ch_n(channels), p(o.nd_p),
          inv_pairs(1.0 / s.pairs_per_entry()), out(factors), chunks(size_t(std::min(rows, 32))), errors(chunks),
          counted(chunks, 0),
          h_planes(static_cast<size_t>(ch_n), std::vector<std::vector<double>>(static_cast<size_t>(big_k))) {}

    const PairSampler& s;
    const FactorOptions& o;
    const int rows, cols, big_k, ch_n;
    const double p, inv_pairs;
    std::vector<LowRank>* out;
    const size_t chunks;
    std::vector<std::string> errors;
    std::vector<int64_t> counted;
    // H of the finished terms, one contiguous plane per channel and term, [ch][j][c]: the
    // residual streams through it for every row of every pass.
    std::vector<std::vector<std::vector<double>>> h_planes;

    // Pass B's per-chunk sums: H's numerator and denominator per channel and column, the
    // first term's column weights and colour-ratio sums.
    struct Sums {
        std::vector<std::vector<double>> num, den, wcol, fy;
    };

    void chunk_rows(size_t c, int* r0, int* r1) const {
        *r0 = int(size_t(rows) * c / chunks);
        *r1 = int(size_t(rows) * (c + 1) / chunks);
    }

    // Residual of row r after the first k terms, as ch_n planes of cols doubles.
    bool residual(int r, int k, float* rgb, uint16_t* cnt, double* res, std::string* e, int64_t* n_evals) const {
        if (!s.sample_row(r, rgb, cnt, e)) return false;
        for (int c = 0; c < cols; ++c) *n_evals += cnt[c];
        row_channels(rgb, cols, ch_n, res);
        for (int ch = 0; ch < ch_n; ++ch) {
            const LowRank& l = (*out)[size_t(ch)];
            for (int j = 0; j < k; ++j) {
                const double g = l.g[size_t(r) * big_k + j];
                if (g == 0) continue;
                double* x = res + size_t(ch) * cols;
                const double* h = h_planes[size_t(ch)][size_t(j)].data();
                for (int c = 0; c < cols; ++c) x[c] -= g * h[c];
            }
        }
        return true;
    }

    double row_norm(const double* x, const uint16_t* cnt) const {
        double sw = 0, sp = 0;
        for (int c = 0; c < cols; ++c) {
            if (!cnt[c]) continue;
            const double w = cnt[c] * inv_pairs, a = std::fabs(x[c]);
            sw += w;
            sp += w * (p == 2 ? a * a : std::pow(a, p));
        }
        if (!(sw > 0) || !(sp > 0)) return 0.0;
        const double mean = sp / sw;
        return p == 2 ? std::sqrt(mean) : std::pow(mean, 1.0 / p);
    }

    bool failed(std::string* err) const {
        for (const std::string& e : errors)
            if (!e.empty()) {
                if (err) *err = e;
                return true;
            }
        return false;
    }

    // Pass A (terms after the first): per channel, the residual row of largest norm (first
    // on ties), its norm and its weighted profile, the reference for the rows' signs.
    bool reference_rows(int k, std::vector<double>* max_norm, std::vector<std::vector<double>>* ref, int64_t* evals,
                        std::string* err) {
        std::vector<std::vector<double>> best_norm(chunks, std::vector<double>(size_t(ch_n), -1));
        std::vector<std::vector<int>> best_row(chunks, std::vector<int>(size_t(ch_n), -1));
        Progress progress(o.progress, "nd term " + std::to_string(k + 1) + " (1/2)", chunks);
        parallel_for(chunks, o.threads, [&](size_t chunk) {
            int r0, r1;
            chunk_rows(chunk, &r0, &r1);
            std::vector<float> rgb(size_t(cols) * 3);
            std::vector<uint16_t> cnt(static_cast<size_t>(cols));
            std::vector<double> res(size_t(cols) * ch_n);
            for (int r = r0; r < r1; ++r) {
                if (!residual(r, k, rgb.data(), cnt.data(), res.data(), &errors[chunk], &counted[chunk])) return;
                for (int ch = 0; ch < ch_n; ++ch) {
                    const double nrm = row_norm(&res[size_t(ch) * cols], cnt.data());
                    if (nrm > best_norm[chunk][size_t(ch)])
                        best_norm[chunk][size_t(ch)] = nrm, best_row[chunk][size_t(ch)] = r;
                }
            }
            progress.advance();
        });
        if (failed(err)) return false;
        std::vector<float> rgb(size_t(cols) * 3);
        std::vector<uint16_t> cnt(static_cast<size_t>(cols));
        std::vector<double> res(size_t(cols) * ch_n);
        for (int ch = 0; ch < ch_n; ++ch) {
            int row = -1;
            for (size_t c = 0; c < chunks; ++c)
                if (best_norm[c][size_t(ch)] > (*max_norm)[size_t(ch)])
                    (*max_norm)[size_t(ch)] = best_norm[c][size_t(ch)], row = best_row[c][size_t(ch)];
            (*ref)[size_t(ch)].assign(size_t(cols), 0.0);
            if (row < 0) continue;
            std::string e;
            if (!residual(row, k, rgb.data(), cnt.data(), res.data(), &e, evals)) {
                if (err) *err = e;
                return false;
            }
            for (int c = 0; c < cols; ++c)
                (*ref)[size_t(ch)][size_t(c)] = cnt[c] ? res[size_t(ch) * cols + c] * cnt[c] * inv_pairs : 0.0;
        }
        return true;
    }

    // Pass B: G of term k per row (signed by the reference after the first term), and the
    // sums for its H; the first term also marks the rows and columns holding data.
    bool accumulate(int k, const std::vector<double>& max_norm, const std::vector<std::vector<double>>& ref,
                    std::vector<uint8_t>* row_has, Sums* sums, std::string* err) {
        sums->num.assign(chunks, {});
        sums->den.assign(chunks, {});
        sums->wcol.assign(chunks, {});
        sums->fy.assign(chunks, std::vector<double>(4, 0.0));
        Progress progress(o.progress, k == 0 ? std::string("nd term 1") : "nd term " + std::to_string(k + 1) + " (2/2)",
                          chunks);
        parallel_for(chunks, o.threads, [&](size_t chunk) {
            int r0, r1;
            chunk_rows(chunk, &r0, &r1);
            std::vector<double>& num = sums->num[chunk];
            std::vector<double>& den = sums->den[chunk];
            std::vector<double>& wcol = sums->wcol[chunk];
            std::vector<double>& fy = sums->fy[chunk];
            num.assign(size_t(cols) * ch_n, 0.0);
            den.assign(size_t(cols) * ch_n, 0.0);
            if (k == 0) wcol.assign(size_t(cols), 0.0);
            std::vector<float> rgb(size_t(cols) * 3);
            std::vector<uint16_t> cnt(static_cast<size_t>(cols));
            std::vector<double> res(size_t(cols) * ch_n);
            for (int r = r0; r < r1; ++r) {
                if (!residual(r, k, rgb.data(), cnt.data(), res.data(), &errors[chunk], &counted[chunk])) return;
                if (k == 0) {
                    for (int c = 0; c < cols; ++c) {
                        if (!cnt[c]) continue;
                        const double w = cnt[c] * inv_pairs;
                        (*row_has)[size_t(r)] = 1;
                        wcol[size_t(c)] += w;
                        if (ch_n == 1) {  // luminance mode: the colour ratio's sums
                            const double y = res[size_t(c)];
                            for (int q = 0; q < 3; ++q) fy[size_t(q)] += w * rgb[3 * c + q] * y;
                            fy[3] += w * y * y;
                        }
                    }
                }
                for (int ch = 0; ch < ch_n; ++ch) {
                    const double* x = &res[size_t(ch) * cols];
                    double g = row_norm(x, cnt.data());
                    if (k > 0) {
                        double dot = 0;
                        for (int c = 0; c < cols; ++c)
                            if (cnt[c]) dot += x[c] * ref[size_t(ch)][size_t(c)];
                        if (dot < 0) g = -g;
                    }
                    (*out)[size_t(ch)].g[size_t(r) * big_k + k] = g;
                    const double thresh = k == 0 ? 0.0 : 1e-6 * max_norm[size_t(ch)];
                    if (!(std::fabs(g) > thresh)) continue;
                    double* nu = &num[size_t(ch) * cols];
                    double* de = &den[size_t(ch) * cols];
                    const double inv_g = 1.0 / g;
                    for (int c = 0; c < cols; ++c) {
                        if (!cnt[c]) continue;
                        const double w = cnt[c] * inv_pairs;
                        nu[c] += w * x[c] * inv_g;
                        de[c] += w;
                    }
                }
            }
            progress.advance();
        });
        return !failed(err);
    }

    // H of term k from pass B's sums, added in chunk order.
    void finish_term(int k, const Sums& sums) {
        for (int ch = 0; ch < ch_n; ++ch) {
            std::vector<double>& plane = h_planes[size_t(ch)][size_t(k)];
            plane.assign(size_t(cols), 0.0);
            for (int c = 0; c < cols; ++c) {
                double nu = 0, de = 0;
                for (size_t q = 0; q < chunks; ++q) {
                    nu += sums.num[q][size_t(ch) * cols + c];
                    de += sums.den[q][size_t(ch) * cols + c];
                }
                plane[size_t(c)] = de > 0 ? nu / de : 0.0;
                (*out)[size_t(ch)].h[size_t(c) * big_k + k] = plane[size_t(c)];
            }
        }
    }
};

}  // namespace

bool nd_factor(const PairSampler& s, const FactorOptions& o, int channels,
               std::vector<LowRank>* out, glm::dvec3* ratio, std::vector<uint8_t>* row_has,
               std::vector<uint8_t>* col_has, double* first_pass_seconds, int64_t* evals,
               std::string* err) {
    const auto t0 = std::chrono::steady_clock::now();
    out->assign(size_t(channels), LowRank{});
    for (LowRank& l : *out) {
        l.k = o.terms;
        l.g.assign(size_t(s.rows()) * o.terms, 0.0);
        l.h.assign(size_t(s.cols()) * o.terms, 0.0);
    }
    row_has->assign(size_t(s.rows()), 0);
    col_has->assign(size_t(s.cols()), 0);
    *evals = 0;
    NdRun run(s, o, channels, out);
    std::vector<double> fy_total(3, 0.0);
    double yy_total = 0;
    for (int k = 0; k < run.big_k; ++k) {
        std::vector<double> max_norm(size_t(run.ch_n), 0.0);
        std::vector<std::vector<double>> ref(static_cast<size_t>(run.ch_n));
        if (k > 0 && !run.reference_rows(k, &max_norm, &ref, evals, err)) return false;
        NdRun::Sums sums;
        if (!run.accumulate(k, max_norm, ref, row_has, &sums, err)) return false;
        run.finish_term(k, sums);
        if (k == 0) {
            for (int c = 0; c < run.cols; ++c) {
                double w = 0;
                for (size_t q = 0; q < run.chunks; ++q) w += sums.wcol[q][size_t(c)];
                (*col_has)[size_t(c)] = w > 0 ? 1 : 0;
            }
            for (size_t q = 0; q < run.chunks; ++q) {
                for (int i = 0; i < 3; ++i) fy_total[size_t(i)] += sums.fy[q][size_t(i)];
                yy_total += sums.fy[q][3];
            }
            *first_pass_seconds = seconds_since(t0);
        }
    }
    *ratio = run.ch_n == 1 && yy_total > 0 ? glm::dvec3(fy_total[0], fy_total[1], fy_total[2]) / yy_total
                                           : glm::dvec3(1);
    for (int64_t c : run.counted) *evals += c;
    return true;
}

}  // namespace detail
}  // namespace sepal
