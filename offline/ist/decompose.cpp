#include "ist/decompose.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>

#include <Eigen/Dense>

#include "util/enum_names.h"
#include "factor/als.h"
#include "ist/ist_util.h"
#include "util/parallel.h"
#include "util/progress.h"

namespace sepal {

using detail::AlsRule;
using detail::AlsSettings;
using detail::LowRank;
using detail::Matrix;
using ist_detail::fail;

namespace {

constexpr int kBlockRows = 4096;

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// The cosine of each pair's incident direction: matrix entries are f cos(theta_i).
std::vector<double> pair_cosines(const std::vector<DirPair>& pairs) {
    std::vector<double> c(pairs.size());
    for (size_t p = 0; p < pairs.size(); ++p) c[p] = pairs[p].wi.z;
    return c;
}

// Rows `texels` of the SVBRDF's matrix (all when empty: first..first+count).
void build_matrix(const SvbrdfSamples& s, const std::vector<int>& texels, const std::vector<double>& cosines, Matrix* m) {
    const int np = s.pair_count();
    m->rows = int(texels.size());
    m->cols = 3 * np;
    m->channels = 1;
    m->w.assign(size_t(m->rows) * m->cols, 0.0f);
    m->wv.assign(1, std::vector<float>(size_t(m->rows) * m->cols, 0.0f));
    for (int r = 0; r < m->rows; ++r) {
        const int t = texels[size_t(r)];
        for (int p = 0; p < np; ++p) {
            const float c = s.confidence(t, p);
            if (c <= 0) continue;
            const glm::dvec3 v = s.value(t, p);
            for (int ch = 0; ch < 3; ++ch) {
                const size_t i = size_t(r) * m->cols + size_t(3 * p + ch);
                m->w[i] = c;
                m->wv[0][i] = float(c * v[ch] * cosines[size_t(p)]);
            }
        }
    }
}

// Energy groups: per view and channel, the pairs with an albedo weight.
std::vector<detail::EnergyGroup> energy_groups(const std::vector<DirPair>& pairs) {
    int views = 0;
    for (const DirPair& p : pairs) views = std::max(views, p.view + 1);
    std::vector<detail::EnergyGroup> g(size_t(views) * 3);
    for (size_t p = 0; p < pairs.size(); ++p) {
        if (pairs[p].view < 0 || pairs[p].albedo_weight <= 0) continue;
        for (int ch = 0; ch < 3; ++ch) {
            detail::EnergyGroup& e = g[size_t(pairs[p].view) * 3 + size_t(ch)];
            e.cols.push_back(int(3 * p) + ch);
            e.coef.push_back(pairs[p].albedo_weight);
        }
    }
    g.erase(std::remove_if(g.begin(), g.end(), [](const detail::EnergyGroup& e) { return e.cols.empty(); }), g.end());
    return g;
}

bool partial(const Matrix& m) {
    for (float w : m.w)
        if (w != 1.0f) return true;
    return false;
}

struct Stats {
    double variance = 0, row_weight = 0, mean = 0;
    bool partial = false;  // some entries missing or weighted below 1
};
Stats matrix_stats(const Matrix& m) {
    double sw = 0, sv = 0, sv2 = 0;
    for (size_t i = 0; i < m.w.size(); ++i) {
        if (m.w[i] <= 0) continue;
        const double v = m.wv[0][i] / m.w[i];
        sw += m.w[i];
        sv += m.w[i] * v;
        sv2 += m.w[i] * v * v;
    }
    Stats s;
    if (sw > 0) {
        s.mean = sv / sw;
        s.variance = std::max(sv2 / sw - s.mean * s.mean, 1e-30);
    }
    s.row_weight = m.rows > 0 ? sw / m.rows : 0;
    s.partial = partial(m);
    return s;
}

// Weighted k-means of the rows (distance over each row's observed entries), k-means++
// start from the seed; returns the centres as cols x k (row-major) in *centres and the
// cluster sizes.
void kmeans(const Matrix& m, int k, uint64_t seed, int threads, std::vector<double>* centres,
            std::vector<int>* sizes) {
    using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    using RowMatF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    const int rows = m.rows, cols = m.cols;
    std::vector<double> c(size_t(k) * cols, 0.0);  // centre-major here: [j * cols + col]
    auto value = [&](int r, int col) {
        const size_t i = size_t(r) * cols + col;
        return m.w[i] > 0 ? double(m.wv[0][i]) / m.w[i] : 0.0;
    };
    // Weighted squared distances by expansion, sum_c w (v - x)^2 = sum w v^2 - 2 (w v).x + w.x^2,
    // as two matrix products per chunk of rows (the scalar loop over every row, centre and
    // column was 40% of a SACLS decomposition at 96x96); entries with w = 0 add exact zeros.
    // Chunks are a function of `rows` only (determinism); clamped at 0 against rounding.
    std::vector<double> vsq(static_cast<size_t>(rows), 0.0);
    for (int r = 0; r < rows; ++r) {
        double q = 0;
        for (int col = 0; col < cols; ++col) {
            const size_t i = size_t(r) * cols + col;
            if (m.w[i] > 0) q += double(m.wv[0][i]) * m.wv[0][i] / m.w[i];
        }
        vsq[size_t(r)] = q;
    }
    constexpr int kChunk = 256;
    const size_t chunks = size_t((rows + kChunk - 1) / kChunk);
    struct Scratch {
        RowMat w, wv, d, e;
    };
    std::vector<Scratch> scratch(size_t(workers(chunks, threads)));
    RowMat dist(rows, k);  // [row, centre j0 + a] after distances(j0, j1)
    auto distances = [&](int j0, int j1) {
        const Eigen::Map<const RowMat> cm(c.data(), k, cols);
        const RowMat x = cm.middleRows(j0, j1 - j0), x2 = x.array().square().matrix();
        parallel_for_workers(chunks, threads, [&](size_t chunk, int worker) {
            const int r0 = int(chunk) * kChunk, n = std::min(rows, r0 + kChunk) - r0;
            Scratch& sc = scratch[size_t(worker)];
            sc.w = Eigen::Map<const RowMatF>(&m.w[size_t(r0) * cols], n, cols).cast<double>();
            sc.wv = Eigen::Map<const RowMatF>(&m.wv[0][size_t(r0) * cols], n, cols).cast<double>();
            sc.d.noalias() = sc.wv * x.transpose();
            sc.e.noalias() = sc.w * x2.transpose();
            for (int i = 0; i < n; ++i)
                for (int a = 0; a < j1 - j0; ++a)
                    dist(r0 + i, a) = std::max(0.0, vsq[size_t(r0 + i)] - 2 * sc.d(i, a) + sc.e(i, a));
        });
    };
    std::vector<double> best(size_t(rows), std::numeric_limits<double>::infinity());
    auto set_centre = [&](int j, int r) {
        for (int col = 0; col < cols; ++col) c[size_t(j) * cols + col] = value(r, col);
    };
    set_centre(0, std::min(rows - 1, int(counter_uniform(seed, 0) * rows)));
    for (int j = 1; j < k; ++j) {
        distances(j - 1, j);
        for (int r = 0; r < rows; ++r) best[size_t(r)] = std::min(best[size_t(r)], dist(r, 0));
        double total = 0;
        for (double b : best) total += b;
        double pick = counter_uniform(seed, uint64_t(j)) * total;
        int chosen = rows - 1;
        for (int r = 0; r < rows; ++r) {
            pick -= best[size_t(r)];
            if (pick <= 0) {
                chosen = r;
                break;
            }
        }
        set_centre(j, chosen);
    }
    std::vector<int> assign(size_t(rows), -1);
    for (int it = 0; it < 50; ++it) {
        std::vector<int> next(static_cast<size_t>(rows));
        distances(0, k);
        for (int r = 0; r < rows; ++r) {
            int arg = 0;
            double bd = std::numeric_limits<double>::infinity();
            for (int j = 0; j < k; ++j)
                if (dist(r, j) < bd) bd = dist(r, j), arg = j;
            next[size_t(r)] = arg;
        }
        if (next == assign) break;
        assign = next;
        std::vector<double> sw(size_t(k) * cols, 0.0), swv(size_t(k) * cols, 0.0);
        for (int r = 0; r < rows; ++r)
            for (int col = 0; col < cols; ++col) {
                const size_t i = size_t(r) * cols + col;
                sw[size_t(assign[size_t(r)]) * cols + col] += m.w[i];
                swv[size_t(assign[size_t(r)]) * cols + col] += m.wv[0][i];
            }
        for (size_t i = 0; i < c.size(); ++i)
            if (sw[i] > 0) c[i] = swv[i] / sw[i];
    }
    sizes->assign(size_t(k), 0);
    for (int a : assign) ++(*sizes)[size_t(a)];
    centres->assign(size_t(cols) * k, 0.0);
    for (int j = 0; j < k; ++j)
        for (int col = 0; col < cols; ++col) (*centres)[size_t(col) * k + j] = std::max(0.0, c[size_t(j) * cols + col]);
}

// One run of the chosen method on the held rows: fills f (g: rows x k, h: cols x k).
struct RunResult {
    double objective = 0;
    int iterations = 0;
};

AlsSettings base_settings(const DecomposeOptions& o, const std::vector<detail::EnergyGroup>* groups,
                          const Stats& st, std::atomic<int64_t>* fallbacks) {
    AlsSettings s;
    s.threads = o.threads;
    s.fallbacks = fallbacks;
    s.max_iters = o.iterations;
    s.tolerance = o.tolerance;
    s.horizon_weight = 0;
    s.anchor = nullptr;
    s.anchor_weight = 0;
    const double unit = st.variance * st.row_weight / 50.0;
    // Missing samples: 1% of the normal equations' mean diagonal bounds the least-squares
    // solves' weak directions (als.h; PCA at 96x96 with 50% missing predicted the missing
    // samples 116x off without it, 1.04x with it; NMF's least-squares start likewise).
    if (st.partial) s.ridge = 1e-2;
    switch (o.method) {
        case IstMethod::SACLS:
        case IstMethod::ACLS:
            s.rule = AlsRule::Sparse;
            s.inner = 2;
            if (o.method == IstMethod::SACLS) {
                s.sparsity_l = o.sparsity * unit;
                s.sparsity_m = o.normalization * unit;
            }
            s.energy = o.energy && !groups->empty() ? groups : nullptr;
            break;
        case IstMethod::NMF:
            s.rule = AlsRule::Multiplicative;
            s.inner = 8;
            s.max_iters = 5 * o.iterations;
            break;
        case IstMethod::PCA: s.rule = AlsRule::LeastSquares; break;
        case IstMethod::KMeans:
            s.rule = AlsRule::Sparse;  // l = m = 0: exact non-negative re-projection
            break;
    }
    return s;
}

// The settings that project rows onto fixed bases after the fit: the method's own exact
// row solve (nmf and kmeans: non-negative least squares).
AlsSettings projection_settings(AlsSettings s) {
    if (s.rule == AlsRule::Multiplicative) s.rule = AlsRule::Sparse, s.sparsity_l = s.sparsity_m = 0;
    return s;
}

bool fit_rows(const Matrix& m, int k, const DecomposeOptions& o, const AlsSettings& s,
              LowRank* best, RunResult* result, std::string* err) {
    const int rows = m.rows, cols = m.cols;
    result->objective = std::numeric_limits<double>::infinity();
    if (o.method == IstMethod::PCA) {
        LowRank f;
        detail::truncated_svd(m, 0, k, o.seed, o.threads, &f, nullptr);
        int it = 0;
        if (partial(m)) detail::als_solve(m, 0, s, &f, &it);
        result->objective = detail::als_project(m, 0, s, &f);
        result->iterations = it;
        *best = f;
        return true;
    }
    if (o.method == IstMethod::NMF) {
        // NNDSVD start (the SVD's terms made non-negative, zeros filled small).
        LowRank svd, f;
        detail::truncated_svd(m, 0, k, o.seed, o.threads, &svd, nullptr);
        if (partial(m)) {
            // Missing samples: the zero-filled SVD is biased toward 0; refine it over the
            // observed entries first (PCA's weighted fit).
            AlsSettings ls = s;
            ls.rule = AlsRule::LeastSquares;
            int it = 0;
            detail::als_solve(m, 0, ls, &svd, &it);
            result->iterations += it;
        }
        f.k = k;
        f.g.assign(size_t(rows) * k, 0.0);
        f.h.assign(size_t(cols) * k, 0.0);
        for (int j = 0; j < k; ++j) detail::nndsvd_column(svd, j, &f, j, true);
        int it = 0;
        result->objective = detail::als_solve(m, 0, s, &f, &it);
        result->iterations = it;
        *best = f;
        return true;
    }
    const int pool = o.method == IstMethod::KMeans ? k : std::max(k, std::min(o.kmeans_clusters, rows));
    if (pool > rows) return fail(err, "decompose: " + std::to_string(k) + " terms need at least as many texels");
    std::vector<double> centres;
    std::vector<int> sizes;
    kmeans(m, pool, o.seed, o.threads, &centres, &sizes);
    const int runs = o.method == IstMethod::KMeans ? 1 : std::max(1, o.restarts);
    for (int run = 0; run < runs; ++run) {
        // Run 0 starts from the k largest clusters, the others from random subsets.
        std::vector<int> idx(static_cast<size_t>(pool));
        std::iota(idx.begin(), idx.end(), 0);
        if (run == 0) {
            std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) { return sizes[size_t(a)] > sizes[size_t(b)]; });
        } else {
            for (int i = pool - 1; i > 0; --i) {
                const int j = int(counter_uniform(o.seed ^ (0xabcdULL + uint64_t(run)), uint64_t(i)) * (i + 1));
                std::swap(idx[size_t(i)], idx[size_t(std::min(j, i))]);
            }
        }
        LowRank f;
        f.k = k;
        f.g.assign(size_t(rows) * k, 1.0 / k);
        f.h.assign(size_t(cols) * k, 0.0);
        for (int col = 0; col < cols; ++col)
            for (int j = 0; j < k; ++j) f.h[size_t(col) * k + j] = centres[size_t(col) * pool + size_t(idx[size_t(j)])];
        RunResult r;
        if (o.method == IstMethod::KMeans) {
            r.objective = detail::als_project(m, 0, s, &f);
        } else {
            detail::als_project(m, 0, s, &f);
            r.objective = detail::als_solve(m, 0, s, &f, &r.iterations);
        }
        result->iterations += r.iterations;
        if (o.progress) {
            char line[160];
            std::snprintf(line, sizeof line, "sepal ist: %s K=%d run %d/%d: objective %.6g after %d iterations",
                          ist_method_name(o.method), k, run + 1, runs, r.objective, r.iterations);
            progress_note(line);
        }
        if (r.objective < result->objective) {
            result->objective = r.objective;
            *best = f;
        }
    }
    return true;
}

// Terms by decreasing total weight (pca keeps the SVD's order).
void order_terms(Decomposition* d) {
    const int k = d->terms, texels = d->width * d->height, np = int(d->pairs.size());
    std::vector<double> total(size_t(k), 0.0);
    for (int t = 0; t < texels; ++t)
        for (int j = 0; j < k; ++j) total[size_t(j)] += std::fabs(d->weights[size_t(t) * k + size_t(j)]);
    std::vector<int> order(static_cast<size_t>(k));
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return total[size_t(a)] > total[size_t(b)]; });
    std::vector<float> w(d->weights.size()), b(d->basis.size());
    for (int j = 0; j < k; ++j) {
        const int from = order[size_t(j)];
        for (int t = 0; t < texels; ++t) w[size_t(t) * k + size_t(j)] = d->weights[size_t(t) * k + size_t(from)];
        std::copy_n(&d->basis[size_t(from) * np * 3], size_t(np) * 3, &b[size_t(j) * np * 3]);
    }
    d->weights.swap(w);
    d->basis.swap(b);
}

bool decompose_fixed(const SvbrdfSamples& s, const DecomposeOptions& o, int k, Decomposition* out, std::string* err) {
    const double t0 = now_seconds();
    const int texels = s.texels(), np = s.pair_count();
    const std::vector<double> cosines = pair_cosines(s.pairs);
    // The fitted rows: all, or a fixed random subset (sorted, so block order is stable).
    std::vector<int> rows(static_cast<size_t>(texels));
    std::iota(rows.begin(), rows.end(), 0);
    if (texels > o.max_rows) {
        for (int i = 0; i < o.max_rows; ++i) {
            const int j = i + int(counter_uniform(o.seed ^ 0x5eedULL, uint64_t(i)) * (texels - i));
            std::swap(rows[size_t(i)], rows[size_t(std::min(j, texels - 1))]);
        }
        rows.resize(size_t(o.max_rows));
        std::sort(rows.begin(), rows.end());
    }
    const double mb = double(rows.size()) * 3 * np * 8 / (1 << 20);
    if (mb > o.max_memory_mb) {
        char buf[256];
        std::snprintf(buf, sizeof buf, "decompose: the %zu x %d matrix needs %.0f MB, over %.0f MB; lower max_rows",
                      rows.size(), 3 * np, mb, o.max_memory_mb);
        return fail(err, buf);
    }
    Matrix m;
    build_matrix(s, rows, cosines, &m);
    const Stats st = matrix_stats(m);
    const std::vector<detail::EnergyGroup> groups = energy_groups(s.pairs);
    std::atomic<int64_t> fallbacks{0};
    const AlsSettings settings = base_settings(o, &groups, st, &fallbacks);
    LowRank f;
    RunResult run;
    if (!fit_rows(m, k, o, settings, &f, &run, err)) return false;

    Decomposition d;
    d.method = o.method;
    d.terms = k;
    d.width = s.width;
    d.height = s.height;
    d.pairs = s.pairs;
    d.objective = run.objective;
    d.iterations = run.iterations;
    d.fitted_rows = int(rows.size());
    d.weights.assign(size_t(texels) * k, 0.0f);
    d.basis.assign(size_t(k) * np * 3, 0.0f);
    for (int j = 0; j < k; ++j)
        for (int col = 0; col < 3 * np; ++col)
            d.basis[(size_t(j) * np + size_t(col / 3)) * 3 + size_t(col % 3)] =
                float(f.h[size_t(col) * k + j] / cosines[size_t(col / 3)]);
    // Every texel's weights (the fitted rows again when subsampled: one exact projection).
    const AlsSettings proj = projection_settings(settings);
    double sse = 0, sw = 0;
    for (int first = 0; first < texels; first += kBlockRows) {
        const int count = std::min(kBlockRows, texels - first);
        std::vector<int> block(static_cast<size_t>(count));
        std::iota(block.begin(), block.end(), first);
        const bool fitted = int(rows.size()) == texels;
        Matrix mb_;
        build_matrix(s, block, cosines, &mb_);
        LowRank g;
        g.k = k;
        g.h = f.h;
        if (fitted) {
            g.g.assign(f.g.begin() + long(size_t(first) * k), f.g.begin() + long(size_t(first + count) * k));
        } else {
            g.g.assign(size_t(count) * k, 1.0 / k);
            detail::als_project(mb_, 0, proj, &g);
        }
        for (int r = 0; r < count; ++r)
            for (int j = 0; j < k; ++j) d.weights[size_t(first + r) * k + size_t(j)] = float(g.g[size_t(r) * k + size_t(j)]);
        // Error over the observed entries.
        for (int r = 0; r < count; ++r)
            for (int col = 0; col < mb_.cols; ++col) {
                const size_t i = size_t(r) * mb_.cols + col;
                if (mb_.w[i] <= 0) continue;
                double pred = 0;
                for (int j = 0; j < k; ++j) pred += g.g[size_t(r) * k + size_t(j)] * g.h[size_t(col) * k + size_t(j)];
                const double e = mb_.wv[0][i] / mb_.w[i] - pred;
                sse += mb_.w[i] * e * e;
                sw += mb_.w[i];
            }
    }
    d.rms = sw > 0 ? std::sqrt(sse / sw) : 0;
    if (o.method != IstMethod::PCA) order_terms(&d);
    d.fallbacks = fallbacks.load();
    if (d.fallbacks) d.notes.push_back(std::to_string(d.fallbacks) + " solver updates fell back (als.h)");
    if (int(rows.size()) < texels)
        d.notes.push_back("bases fitted to " + std::to_string(rows.size()) + " of " + std::to_string(texels) +
                          " texels, every texel projected onto them");
    d.seconds = now_seconds() - t0;
    *out = std::move(d);
    return true;
}

}  // namespace

constexpr EnumName<IstMethod> kIstMethods[] = {{IstMethod::SACLS, "sacls"}, {IstMethod::ACLS, "acls"}, {IstMethod::PCA, "pca"}, {IstMethod::NMF, "nmf"}, {IstMethod::KMeans, "kmeans"}};

const char* ist_method_name(IstMethod m) { return enum_name(kIstMethods, m); }

bool parse_ist_method(const std::string& name, IstMethod* m) { return parse_enum(kIstMethods, name, m); }

BlendMaps Decomposition::blend() const {
    BlendMaps b;
    b.width = width;
    b.height = height;
    b.count = terms;
    b.w = weights;
    return b;
}

bool decompose_svbrdf(const SvbrdfSamples& s, const DecomposeOptions& o, Decomposition* out, std::string* err) {
    if (!validate_svbrdf(s, err)) return false;
    if (o.terms < 0 || o.terms > 8 || o.max_terms < 1 || o.max_terms > 8)
        return fail(err, "decompose: terms 1..8 (0: chosen by error), max_terms 1..8");
    if (o.max_rows < 16 || o.max_rows > 1000000 || o.restarts < 1 || o.restarts > 64 || o.iterations < 1 ||
        o.iterations > 100000 || o.kmeans_clusters < 1 || o.kmeans_clusters > 256)
        return fail(err, "decompose: max_rows 16..1e6, restarts 1..64, iterations 1..1e5, kmeans_clusters 1..256");
    if (!(o.sparsity >= 0) || !(o.normalization >= 0) || !std::isfinite(o.sparsity) ||
        !std::isfinite(o.normalization) || !(o.tolerance >= 0) || !(o.choose_slack >= 0))
        return fail(err, "decompose: sparsity, normalization, tolerance and slack must be finite and >= 0");
    if (o.terms > 0) return decompose_fixed(s, o, o.terms, out, err);
    std::vector<Decomposition> all;
    for (int k = 1; k <= o.max_terms; ++k) {
        Decomposition d;
        if (!decompose_fixed(s, o, k, &d, err)) return false;
        if (o.progress) {
            char line[80];
            std::snprintf(line, sizeof line, "sepal ist: K=%d RMS %.5g", k, d.rms);
            progress_note(line);
        }
        all.push_back(std::move(d));
    }
    std::vector<double> by;
    for (const Decomposition& d : all) by.push_back(d.rms);
    // The knee: the first K after which one more term lowers the RMS by less than the slack.
    size_t pick = all.size() - 1;
    for (size_t i = 0; i + 1 < all.size(); ++i)
        if (all[i + 1].rms > (1 - o.choose_slack) * all[i].rms) {
            pick = i;
            break;
        }
    *out = std::move(all[pick]);
    out->rms_by_terms = by;
    out->notes.push_back("terms chosen by error: K=" + std::to_string(out->terms) + " (K+1 lowers the RMS by less than " +
                         std::to_string(int(std::lround(100 * o.choose_slack))) + "%)");
    return true;
}

ReconError reconstruction_error(const Decomposition& d, const SvbrdfSamples& input, const SvbrdfSamples& reference) {
    ReconError r;
    double so = 0, sm = 0;
    const int np = int(d.pairs.size()), k = d.terms;
    for (int t = 0; t < reference.texels(); ++t)
        for (int p = 0; p < np; ++p) {
            glm::dvec3 pred(0);
            for (int j = 0; j < k; ++j) pred += double(d.weights[size_t(t) * k + size_t(j)]) * d.basis_value(j, p);
            const glm::dvec3 e = (pred - reference.value(t, p)) * d.pairs[size_t(p)].wi.z;
            const double q = e.x * e.x + e.y * e.y + e.z * e.z;
            if (input.confidence(t, p) > 0) {
                so += q;
                r.n_observed += 3;
            } else {
                sm += q;
                r.n_missing += 3;
            }
        }
    r.observed = r.n_observed ? std::sqrt(so / double(r.n_observed)) : 0;
    r.missing = r.n_missing ? std::sqrt(sm / double(r.n_missing)) : 0;
    return r;
}

TermMatch match_terms(const Decomposition& d, const BlendMaps& truth) {
    const int k = d.terms, n = truth.count, texels = d.width * d.height;
    // Correlation (uncentred cosine) of every term with every true map.
    std::vector<double> corr(size_t(k) * n, 0.0), dot(size_t(k) * n, 0.0), tt(size_t(n), 0.0), ww(size_t(k), 0.0);
    for (int t = 0; t < texels; ++t) {
        for (int i = 0; i < n; ++i) tt[size_t(i)] += double(truth.at(t, i)) * truth.at(t, i);
        for (int j = 0; j < k; ++j) {
            const double w = d.weights[size_t(t) * k + size_t(j)];
            ww[size_t(j)] += w * w;
            for (int i = 0; i < n; ++i) dot[size_t(j) * n + size_t(i)] += w * truth.at(t, i);
        }
    }
    for (int j = 0; j < k; ++j)
        for (int i = 0; i < n; ++i) {
            const double den = std::sqrt(ww[size_t(j)] * tt[size_t(i)]);
            corr[size_t(j) * n + size_t(i)] = den > 0 ? dot[size_t(j) * n + size_t(i)] / den : 0;
        }
    // Exhaustive assignment over permutations of the larger side (k, n <= 8).
    TermMatch m;
    m.truth_of_term.assign(size_t(k), -1);
    const int big = std::max(k, n);
    std::vector<int> perm(static_cast<size_t>(big));
    std::iota(perm.begin(), perm.end(), 0);
    double best = -std::numeric_limits<double>::infinity();
    do {
        double s = 0;
        for (int j = 0; j < k; ++j)
            if (perm[size_t(j)] < n) s += corr[size_t(j) * n + size_t(perm[size_t(j)])];
        if (s > best + 1e-12) {
            best = s;
            for (int j = 0; j < k; ++j) m.truth_of_term[size_t(j)] = perm[size_t(j)] < n ? perm[size_t(j)] : -1;
        }
    } while (std::next_permutation(perm.begin(), perm.end()));
    m.map_rms.assign(size_t(k), 0.0);
    m.scale.assign(size_t(k), 1.0);
    int matched = 0;
    for (int j = 0; j < k; ++j) {
        const int i = m.truth_of_term[size_t(j)];
        if (i < 0) continue;
        const double s = ww[size_t(j)] > 0 ? dot[size_t(j) * n + size_t(i)] / ww[size_t(j)] : 0;
        double e = 0;
        for (int t = 0; t < texels; ++t) {
            const double x = s * d.weights[size_t(t) * k + size_t(j)] - truth.at(t, i);
            e += x * x;
        }
        m.scale[size_t(j)] = s;
        m.map_rms[size_t(j)] = std::sqrt(e / texels);
        m.mean_map_rms += m.map_rms[size_t(j)];
        m.max_map_rms = std::max(m.max_map_rms, m.map_rms[size_t(j)]);
        ++matched;
    }
    if (matched) m.mean_map_rms /= matched;
    return m;
}

double multi_material_share(const BlendMaps& maps, double threshold) {
    const int k = maps.count, texels = maps.width * maps.height;
    int64_t multi = 0;
    for (int t = 0; t < texels; ++t) {
        double sum = 0;
        for (int j = 0; j < k; ++j) sum += std::fabs(maps.at(t, j));
        int used = 0;
        for (int j = 0; j < k; ++j) used += std::fabs(maps.at(t, j)) > threshold * sum;
        multi += used > 1;
    }
    return texels ? double(multi) / texels : 0;
}

double multi_material_share(const Decomposition& d, double threshold) { return multi_material_share(d.blend(), threshold); }

double max_basis_albedo(const Decomposition& d) {
    double worst = 0;
    int views = 0;
    for (const DirPair& p : d.pairs) views = std::max(views, p.view + 1);
    for (int j = 0; j < d.terms; ++j)
        for (int v = 0; v < views; ++v)
            for (int c = 0; c < 3; ++c) {
                double a = 0;
                for (size_t p = 0; p < d.pairs.size(); ++p)
                    if (d.pairs[p].view == v)
                        a += d.pairs[p].albedo_weight * d.basis_value(j, int(p))[c] * d.pairs[p].wi.z;
                worst = std::max(worst, a);
            }
    return worst;
}

}  // namespace sepal
