// Sampling, orchestration and output of the factorization engine (see factor.h).
#include "factor/factor.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>

#include <glm/geometric.hpp>

#include "util/enum_names.h"
#include "factor/factor_internal.h"
#include "util/io.h"
#include "sepal/sepal_format.h"
#include "util/parallel.h"

namespace sepal {

using detail::LowRank;
using detail::Matrix;
using detail::PairSampler;

namespace {
double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

int channels_of(const FactorOptions& o) { return o.colour == ColourMode::PerChannel ? 3 : 1; }

int count_valid(const FactorOptions& o, int which) {
    const std::vector<uint8_t> v = valid_texels(o.param, o.map, which, factor_res(o, which));
    return int(std::count(v.begin(), v.end(), uint8_t(1)));
}
}  // namespace

constexpr EnumName<Method> kMethods[] = {{Method::SVD, "svd"}, {Method::ND, "nd"}, {Method::NMF, "nmf"}, {Method::ACLS, "acls"}, {Method::WSVD, "wsvd"},
                                         {Method::Homomorphic, "homomorphic"}};

const char* method_name(Method m) { return enum_name(kMethods, m); }

bool parse_method(const std::string& name, Method* m) { return parse_enum(kMethods, name, m); }

bool validate_factor_options(const FactorOptions& o, std::string* err) {
    auto fail = [&](const std::string& why) {
        if (err) *err = why;
        return false;
    };
    // 1 is allowed: a 1 x 1 factor is a constant (Lambert is exact at 1 term, 1 x 1).
    if (o.res < 1 || o.res > 256) return fail("--res must be 1..256 (texels per side)");
    if (o.res_h < 0 || o.res_h > 256) return fail("the H factor's resolution must be 1..256 (0: --res)");
    if (o.terms < 1 || o.terms > 16) return fail("--terms must be 1..16");
    if (o.supersample < 1 || o.supersample > 4) return fail("--supersample must be 1..4");
    if (!(o.nd_p >= 1 && o.nd_p <= 16)) return fail("--p must be 1..16");
    if (o.iterations < 0 || o.iterations > 100000) return fail("--iters must be 0..100000");
    if (!(o.tolerance >= 0 && o.tolerance < 1)) return fail("--tolerance must be in [0, 1)");
    if (!(o.max_memory_mb > 0) || !std::isfinite(o.max_memory_mb))
        return fail("--max-memory must be a positive number of MB");
    if (o.threads < 0 || o.threads > 64) return fail("--threads must be 0..64");
    if (!(o.horizon_weight >= 0 && o.horizon_weight <= 1))
        return fail("--horizon-weight must be in [0, 1]");
    if ((o.acls_constant || o.acls_monotonic) && o.method != Method::ACLS)
        return fail("--acls-constant and --acls-monotonic need --method acls");
    if ((o.acls_constant || o.acls_monotonic) && half_angle_factor(o.param) < 0)
        return fail(std::string("--acls-constant and --acls-monotonic need a half-angle "
                                "parameterization (gs-half, vh, rusinkiewicz), not ") +
                    param_name(o.param));
    if (o.acls_constant && o.terms < 2)
        return fail("--acls-constant holds term 1 constant: it needs --terms 2 or more");
    if (o.method == Method::Homomorphic) {
        if (o.param != Param::ViewHalf || o.map != HemiMap::Parabolic)
            return fail("--method homomorphic fits p(wi) q(h) p(wo): it needs --param vh --map parabolic");
        if (o.res_h != 0 && o.res_h != o.res)
            return fail("--method homomorphic: p and q have one resolution (--res)");
        if (o.res > SEPAL_FMT_MAX_RECIPROCAL_SIDE || o.terms > SEPAL_FMT_MAX_RECIPROCAL_TERMS)
            return fail("--method homomorphic: at most --res " + std::to_string(SEPAL_FMT_MAX_RECIPROCAL_SIDE) +
                        " and --terms " + std::to_string(SEPAL_FMT_MAX_RECIPROCAL_TERMS) +
                        " (the runtime keeps a copy of p: format 2.1's bounds)");
        if (o.dense_per_texel < 1 || o.dense_per_texel > 256) return fail("--dense-per-texel must be 1..256");
        HomomorphicOptions h = o.homomorphic;
        h.res = o.res, h.terms = o.terms, h.colour = o.colour;
        return validate_homomorphic_options(h, err);
    }
    return true;
}

void matrix_shape(const FactorOptions& o, int* rows, int* cols) {
    *rows = count_valid(o, 0);
    *cols = count_valid(o, 1);
}

double estimate_memory_mb(const FactorOptions& o) {
    int rows, cols;
    matrix_shape(o, &rows, &cols);
    const double c = channels_of(o), k = o.terms, mb = 1.0 / (1024.0 * 1024.0);
    const double tex = 2.0 * o.res * o.res * c * k * 4 * (k + 1);  // factors and by_terms
    if (o.method == Method::ND) {
        const int chunks = std::min(rows, 32);
        // per-chunk sums of H, factors in double, row buffers per thread, textures
        return (double(chunks) * cols * c * 2 * 8 + (rows + cols) * c * k * 8 +
                cols * (3 * 4 + 2 + 8 * c) * 4.0 + tex) * mb;
    }
    // the matrix (float weight x value per channel plus the float weights; the weighted fits
    // also hold one channel's weights and values as doubles), the SVD's double chunk
    // buffers and blocks, the ALS normal equations
    const bool weighted = o.method == Method::NMF || o.method == Method::ACLS || (o.method == Method::SVD && o.svd_weighted);
    const double matrix = double(rows) * cols * (4 * c + 4 + (weighted ? 16 : 0));
    const double l = k + 8;
    const double svd = 2.0 * 64 * std::max(rows, cols) * 8 * 2 + 6.0 * (rows + cols) * l * 8;
    const double als = double(std::max(rows, cols)) * (k * k + k + 1) * 8 * 2;
    return (matrix + svd + als + tex) * mb;
}

// ---- progress ---------------------------------------------------------------------------
// ---- sampling ---------------------------------------------------------------------------
PairSampler::PairSampler(const Brdf& brdf, const FactorOptions& o)
    : brdf_(brdf), confidence_(o.confidence), value_weight_(o.value_weight), param_(o.param), map_(o.map), n_{factor_res(o, 0), factor_res(o, 1)}, s_(o.supersample),
      pairs_(o.supersample * o.supersample * o.supersample * o.supersample) {
    prepare(0, &row_texel_, &row_points_);
    prepare(1, &col_texel_, &col_points_);
    // The pairs each degenerate G point takes part in (rare: only at --res 1).
    for (const Point& px : row_points_) {
        if (!px.valid || !px.fallback) continue;
        for (const Point& py : col_points_) {
            glm::dvec3 wi, wo;
            if (py.valid && combine_points(param_, px.p, py.p, &wi, &wo)) ++frame_fallback_pairs_;
        }
    }
}

void PairSampler::prepare(int which, std::vector<int>* texels, std::vector<Point>* points) const {
    const int n = n_[which];
    const std::vector<uint8_t> valid = valid_texels(param_, map_, which, n);
    for (int t = 0; t < n * n; ++t)
        if (valid[size_t(t)]) texels->push_back(t);
    points->resize(texels->size() * size_t(s_) * s_);
    for (size_t k = 0; k < texels->size(); ++k) {
        const int i = (*texels)[k] % n, j = (*texels)[k] / n;
        for (int b = 0; b < s_; ++b)
            for (int a = 0; a < s_; ++a) {
                Point& p = (*points)[k * s_ * s_ + size_t(b) * s_ + a];
                const glm::dvec2 uv((i + (a + 0.5) / s_) / n, (j + (b + 0.5) / s_) / n);
                p.valid = factor_point(param_, map_, which, uv, &p.p);
                if (!p.valid || which != 0) continue;
                // eq. 6's frame depends on h only: computed once per sub-sample
                if (param_ == Param::GsHalf) p.fallback = !gs_half_frame(p.p, &p.t, &p.s);
                else p.fallback = frame_fallback(param_, p.p);
            }
    }
}

bool PairSampler::sample_row(int row, float* rgb, uint16_t* count, std::string* err,
                             float* confidence) const {
    const int s2 = s_ * s_;
    const Point* px = &row_points_[size_t(row) * s2];
    for (int c = 0; c < cols(); ++c) {
        const Point* py = &col_points_[size_t(c) * s2];
        glm::dvec3 acc(0);
        double conf = 0;
        int n = 0;
        for (int a = 0; a < s2; ++a) {
            if (!px[a].valid) continue;
            for (int b = 0; b < s2; ++b) {
                if (!py[b].valid) continue;
                glm::dvec3 wi, wo;
                if (param_ == Param::GsHalf) {
                    const glm::dvec3& h = px[a].p;
                    wi = glm::normalize(py[b].p.x * px[a].t + py[b].p.y * px[a].s + py[b].p.z * h);
                    wo = glm::normalize(2 * glm::dot(wi, h) * h - wi);
                    if (!(wi.z > 0) || !(wo.z > 0)) continue;
                } else if (!combine_points(param_, px[a].p, py[b].p, &wi, &wo)) {
                    continue;
                }
                const glm::dvec3 f = brdf_.eval(wi, wo);
                if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z)) {
                    if (err) {
                        char buf[256];
                        std::snprintf(buf, sizeof buf,
                                      "the BRDF returned a non-finite value at wi = (%.6f, "
                                      "%.6f, %.6f), wo = (%.6f, %.6f, %.6f)",
                                      wi.x, wi.y, wi.z, wo.x, wo.y, wo.z);
                        *err = buf;
                    }
                    return false;
                }
                acc += f;
                if (confidence && confidence_) conf += std::min(1.0, std::max(0.0, confidence_(wi, wo)));
                ++n;
            }
        }
        if (n) acc /= double(n);
        if (confidence) {
            double w = !confidence_ ? 1.0 : n ? conf / n : 0.0;
            if (value_weight_ && n) w *= std::min(1.0, std::max(1e-3, value_weight_(acc)));
            confidence[c] = float(w);
        }
        rgb[3 * c] = float(acc.x), rgb[3 * c + 1] = float(acc.y), rgb[3 * c + 2] = float(acc.z);
        count[c] = uint16_t(n);
    }
    return true;
}

void detail::row_channels(const float* rgb, int cols, int channels, double* out) {
    if (channels == 3) {
        for (int c = 0; c < cols; ++c)
            for (int ch = 0; ch < 3; ++ch) out[size_t(ch) * cols + c] = rgb[3 * c + ch];
    } else {
        for (int c = 0; c < cols; ++c)
            out[c] = luminance(glm::dvec3(rgb[3 * c], rgb[3 * c + 1], rgb[3 * c + 2]));
    }
}

namespace {
// Ratio sums of the luminance mode: sum w f_c Y and sum w Y^2.
struct RatioSums {
    double fy[3] = {0, 0, 0}, yy = 0;
    void add(const float* rgb, const uint16_t* count, int cols, double inv_pairs) {
        for (int c = 0; c < cols; ++c) {
            if (!count[c]) continue;
            const double w = count[c] * inv_pairs;
            const glm::dvec3 f(rgb[3 * c], rgb[3 * c + 1], rgb[3 * c + 2]);
            const double y = luminance(f);
            for (int ch = 0; ch < 3; ++ch) fy[ch] += w * f[ch] * y;
            yy += w * y * y;
        }
    }
    void merge(const RatioSums& o) {
        for (int ch = 0; ch < 3; ++ch) fy[ch] += o.fy[ch];
        yy += o.yy;
    }
    glm::dvec3 ratio() const {
        if (!(yy > 0)) return glm::dvec3(1);
        return glm::dvec3(fy[0], fy[1], fy[2]) / yy;
    }
};

bool sample_matrix(const PairSampler& s, const FactorOptions& o, Matrix* m, glm::dvec3* ratio,
                   int64_t* evals, std::string* err) {
    const int rows = s.rows(), cols = s.cols(), ch = channels_of(o);
    m->rows = rows;
    m->cols = cols;
    m->channels = ch;
    const double inv_pairs = 1.0 / s.pairs_per_entry();
    m->w.assign(size_t(rows) * cols, 0.0f);
    m->wv.assign(size_t(ch), std::vector<float>(size_t(rows) * cols));
    const size_t chunks = size_t((rows + detail::kRowChunk - 1) / detail::kRowChunk);
    std::vector<RatioSums> sums(chunks);
    std::vector<std::string> errors(chunks);
    std::vector<int64_t> counted(chunks, 0);
    std::atomic<bool> failed{false};
    detail::Progress progress(o.progress, "sampling", chunks);
    parallel_for(chunks, o.threads, [&](size_t chunk) {
        if (failed) return;
        std::vector<float> rgb(size_t(cols) * 3);
        std::vector<uint16_t> cnt(static_cast<size_t>(cols));
        std::vector<float> conf(static_cast<size_t>(cols), 1.0f);
        std::vector<double> conv(size_t(cols) * ch);
        const int r0 = int(chunk) * detail::kRowChunk;
        const int r1 = std::min(rows, r0 + detail::kRowChunk);
        for (int r = r0; r < r1; ++r) {
            if (!s.sample_row(r, rgb.data(), cnt.data(), &errors[chunk], o.confidence || o.value_weight ? conf.data() : nullptr)) {
                failed = true;
                return;
            }
            for (int c = 0; c < cols; ++c) counted[chunk] += cnt[c];
            if (ch == 1) sums[chunk].add(rgb.data(), cnt.data(), cols, inv_pairs);
            detail::row_channels(rgb.data(), cols, ch, conv.data());
            for (int c = 0; c < cols; ++c) {
                const double w = cnt[c] * inv_pairs * conf[size_t(c)];
                m->w[size_t(r) * cols + c] = float(w);
                for (int k = 0; k < ch; ++k)
                    m->wv[size_t(k)][size_t(r) * cols + c] = float(w * conv[size_t(k) * cols + c]);
            }
        }
        progress.advance();
    });
    for (size_t c = 0; c < chunks; ++c)
        if (!errors[c].empty()) {
            if (err) *err = errors[c];
            return false;
        }
    RatioSums total;
    for (const RatioSums& r : sums) total.merge(r);
    *ratio = ch == 1 ? total.ratio() : glm::dvec3(1);
    *evals = std::accumulate(counted.begin(), counted.end(), int64_t(0));
    return true;
}

// ---- output -----------------------------------------------------------------------------
// Fill order for texels without data: rings of texels next to known ones, each the mean of
// its known 8-neighbours from earlier rings.
struct Dilation {
    std::vector<int> target, start, sources;
};

Dilation plan_dilation(int n, std::vector<uint8_t> known) {
    Dilation d;
    d.start.push_back(0);
    bool any = std::find(known.begin(), known.end(), uint8_t(1)) != known.end();
    for (;;) {
        std::vector<int> ring;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                if (known[size_t(j) * n + i]) continue;
                const size_t before = d.sources.size();
                for (int dj = -1; dj <= 1; ++dj)
                    for (int di = -1; di <= 1; ++di) {
                        const int x = i + di, y = j + dj;
                        if ((di || dj) && x >= 0 && y >= 0 && x < n && y < n &&
                            known[size_t(y) * n + x])
                            d.sources.push_back(y * n + x);
                    }
                if (d.sources.size() == before) continue;
                d.target.push_back(j * n + i);
                d.start.push_back(int(d.sources.size()));
                ring.push_back(j * n + i);
            }
        if (ring.empty()) break;
        for (int t : ring) known[size_t(t)] = 1;
    }
    if (!any) {  // no data at all: everything stays 0
        d.target.clear();
        d.sources.clear();
        d.start.assign(1, 0);
    }
    return d;
}

void apply_dilation(const Dilation& d, FactorTexture* t) {
    for (size_t e = 0; e < d.target.size(); ++e)
        for (int c = 0; c < t->channels; ++c) {
            double sum = 0;
            for (int s = d.start[e]; s < d.start[e + 1]; ++s)
                sum += t->data[size_t(d.sources[size_t(s)]) * t->channels + c];
            t->data[size_t(d.target[e]) * t->channels + c] =
                float(sum / (d.start[e + 1] - d.start[e]));
        }
}

struct Layout {
    const std::vector<int>* row_texel;
    const std::vector<int>* col_texel;
    Dilation dil_g, dil_h;
    std::vector<uint8_t> row_has, col_has;
};

Layout make_layout(const PairSampler& s, int n, int n_h, std::vector<uint8_t> row_has,
                   std::vector<uint8_t> col_has) {
    Layout l;
    l.row_texel = &s.row_texels();
    l.col_texel = &s.col_texels();
    std::vector<uint8_t> kg(size_t(n) * n, 0), kh(size_t(n_h) * n_h, 0);
    for (size_t r = 0; r < row_has.size(); ++r)
        if (row_has[r]) kg[size_t((*l.row_texel)[r])] = 1;
    for (size_t c = 0; c < col_has.size(); ++c)
        if (col_has[c]) kh[size_t((*l.col_texel)[c])] = 1;
    l.dil_g = plan_dilation(n, kg);
    l.dil_h = plan_dilation(n_h, kh);
    l.row_has = std::move(row_has);
    l.col_has = std::move(col_has);
    return l;
}

Factored build_factored(const FactorOptions& o, const std::string& source, glm::dvec3 ratio,
                        const std::vector<LowRank>& lr, const Layout& l) {
    Factored f;
    f.param = o.param;
    f.map = o.map;
    f.colour = o.colour;
    f.n = o.res;
    f.channels = channels_of(o);
    f.ratio = ratio;
    f.method = method_name(o.method == Method::SVD && o.svd_weighted ? Method::WSVD : o.method);
    f.source = source;
    const int k = lr[0].k, rows = int(l.row_texel->size()), cols = int(l.col_texel->size());
    for (int a = 0; a < k; ++a) {
        FactorTerm term{FactorTexture(factor_res(o, 0), f.channels), FactorTexture(factor_res(o, 1), f.channels)};
        for (int ch = 0; ch < f.channels; ++ch) {
            const LowRank& x = lr[size_t(ch)];
            // Scale G and H to equal largest magnitudes: the product is unchanged and
            // both textures use their range alike when quantized.
            double mg = 0, mh = 0;
            for (int r = 0; r < rows; ++r)
                if (l.row_has[size_t(r)]) mg = std::max(mg, std::fabs(x.g[size_t(r) * k + a]));
            for (int c = 0; c < cols; ++c)
                if (l.col_has[size_t(c)]) mh = std::max(mh, std::fabs(x.h[size_t(c) * k + a]));
            const double s = mg > 0 && mh > 0 ? std::sqrt(mh / mg) : 1.0;
            for (int r = 0; r < rows; ++r)
                if (l.row_has[size_t(r)])
                    term.g.data[size_t((*l.row_texel)[size_t(r)]) * f.channels + ch] =
                        float(x.g[size_t(r) * k + a] * s);
            for (int c = 0; c < cols; ++c)
                if (l.col_has[size_t(c)])
                    term.h.data[size_t((*l.col_texel)[size_t(c)]) * f.channels + ch] =
                        float(x.h[size_t(c) * k + a] / s);
        }
        apply_dilation(l.dil_g, &term.g);
        apply_dilation(l.dil_h, &term.h);
        f.terms.push_back(std::move(term));
    }
    return f;
}

// Per-prefix weighted squared errors of one sampled row against the factors' texel values.
struct TexelValues {
    int k = 0, ch = 0;
    std::vector<double> g, h;  // [(r * k + a) * ch + c]
};

TexelValues texel_values(const Factored& f, const Layout& l) {
    TexelValues t;
    t.k = f.term_count();
    t.ch = f.channels;
    const size_t rows = l.row_texel->size(), cols = l.col_texel->size();
    t.g.resize(rows * size_t(t.k) * t.ch);
    t.h.resize(cols * size_t(t.k) * t.ch);
    for (int a = 0; a < t.k; ++a)
        for (int c = 0; c < t.ch; ++c) {
            for (size_t r = 0; r < rows; ++r)
                t.g[(r * t.k + a) * t.ch + c] =
                    f.terms[size_t(a)].g.data[size_t((*l.row_texel)[r]) * t.ch + c];
            for (size_t r = 0; r < cols; ++r)
                t.h[(r * t.k + a) * t.ch + c] =
                    f.terms[size_t(a)].h.data[size_t((*l.col_texel)[r]) * t.ch + c];
        }
    return t;
}

// Adds sum w (m - prefix_k)^2 for k = 1..K into sse[0..K), and sum w into *wsum.
void row_sse(const TexelValues& t, int r, const double* vals /* ch * cols */, const float* w,
             int cols, double* sse, double* wsum) {
    for (int c = 0; c < cols; ++c) {
        if (!(w[c] > 0)) continue;
        *wsum += w[c];
        for (int ch = 0; ch < t.ch; ++ch) {
            double acc = 0;
            const double m = vals[size_t(ch) * cols + c];
            for (int a = 0; a < t.k; ++a) {
                acc += t.g[(size_t(r) * t.k + a) * t.ch + ch] * t.h[(size_t(c) * t.k + a) * t.ch + ch];
                const double e = m - acc;
                sse[a] += w[c] * e * e;
            }
        }
    }
}

std::vector<double> finish_rms(const std::vector<std::vector<double>>& sse,
                               const std::vector<double>& wsum, int k, int ch) {
    std::vector<double> total(size_t(k), 0.0);
    double w = 0;
    for (size_t c = 0; c < sse.size(); ++c) {
        for (int a = 0; a < k; ++a) total[size_t(a)] += sse[c][size_t(a)];
        w += wsum[c];
    }
    for (double& x : total) x = w > 0 ? std::sqrt(x / (w * ch)) : 0.0;
    return total;
}

std::vector<double> matrix_rms_held(const Matrix& m, const Factored& f, const Layout& l,
                                    int threads) {
    const TexelValues t = texel_values(f, l);
    const size_t chunks = size_t((m.rows + detail::kRowChunk - 1) / detail::kRowChunk);
    std::vector<std::vector<double>> sse(chunks, std::vector<double>(size_t(t.k), 0.0));
    std::vector<double> wsum(chunks, 0.0);
    parallel_for(chunks, threads, [&](size_t chunk) {
        const int r0 = int(chunk) * detail::kRowChunk;
        const int r1 = std::min(m.rows, r0 + detail::kRowChunk);
        std::vector<double> vals(size_t(m.cols) * m.channels);
        for (int r = r0; r < r1; ++r) {
            const float* w = &m.w[size_t(r) * m.cols];
            for (int ch = 0; ch < m.channels; ++ch)
                for (int c = 0; c < m.cols; ++c)
                    vals[size_t(ch) * m.cols + c] =
                        w[c] > 0 ? m.wv[size_t(ch)][size_t(r) * m.cols + c] / double(w[c]) : 0.0;
            row_sse(t, r, vals.data(), w, m.cols, sse[chunk].data(), &wsum[chunk]);
        }
    });
    return finish_rms(sse, wsum, t.k, t.ch);
}

bool matrix_rms_streamed(const PairSampler& s, const FactorOptions& o, const Factored& f,
                         const Layout& l, std::vector<double>* out, std::string* err) {
    const TexelValues t = texel_values(f, l);
    const int rows = s.rows(), cols = s.cols();
    const size_t chunks = size_t((rows + detail::kRowChunk - 1) / detail::kRowChunk);
    std::vector<std::vector<double>> sse(chunks, std::vector<double>(size_t(t.k), 0.0));
    std::vector<double> wsum(chunks, 0.0);
    std::vector<std::string> errors(chunks);
    const double inv_pairs = 1.0 / s.pairs_per_entry();
    detail::Progress progress(o.progress, "error at the sample points", chunks);
    parallel_for(chunks, o.threads, [&](size_t chunk) {
        const int r0 = int(chunk) * detail::kRowChunk, r1 = std::min(rows, r0 + detail::kRowChunk);
        std::vector<float> rgb(size_t(cols) * 3);
        std::vector<uint16_t> cnt(static_cast<size_t>(cols));
        std::vector<double> vals(size_t(cols) * t.ch);
        std::vector<float> w(static_cast<size_t>(cols));
        for (int r = r0; r < r1; ++r) {
            if (!s.sample_row(r, rgb.data(), cnt.data(), &errors[chunk])) return;
            detail::row_channels(rgb.data(), cols, t.ch, vals.data());
            for (int c = 0; c < cols; ++c) w[size_t(c)] = float(cnt[size_t(c)] * inv_pairs);
            row_sse(t, r, vals.data(), w.data(), cols, sse[chunk].data(), &wsum[chunk]);
        }
        progress.advance();
    });
    for (const std::string& e : errors)
        if (!e.empty()) {
            if (err) *err = e;
            return false;
        }
    *out = finish_rms(sse, wsum, t.k, t.ch);
    return true;
}

// ---- NMF / ACLS -------------------------------------------------------------------------
// The monotone constraint's forest over the texels of the half-angle factor: each texel's
// parent is the texel one texel-width closer to the pole (the texture centre), so values
// may only fall with theta_h along every ray. Roots: texels within one texel of the centre.
void monotone_forest(const std::vector<int>& texels, int n, std::vector<int>* parent,
                     std::vector<int>* order) {
    std::vector<int> index(size_t(n) * n, -1);
    for (size_t k = 0; k < texels.size(); ++k) index[size_t(texels[k])] = int(k);
    parent->assign(texels.size(), -1);
    std::vector<double> radius(texels.size());
    const double centre = 0.5 * n;
    for (size_t k = 0; k < texels.size(); ++k) {
        const double x = texels[k] % n + 0.5 - centre, y = texels[k] / n + 0.5 - centre;
        const double r = std::sqrt(x * x + y * y);
        radius[k] = r;
        if (r <= 1) continue;
        const double qx = centre + x * (r - 1) / r, qy = centre + y * (r - 1) / r;
        const int i = std::min(n - 1, int(qx)), j = std::min(n - 1, int(qy));
        (*parent)[k] = index[size_t(j) * n + i];
    }
    order->resize(texels.size());
    std::iota(order->begin(), order->end(), 0);
    std::stable_sort(order->begin(), order->end(),
                     [&](int a, int b) { return radius[size_t(a)] > radius[size_t(b)]; });
}

void copy_column(const LowRank& from, int j, LowRank* to, int a) {
    const size_t rows = from.g.size() / size_t(from.k), cols = from.h.size() / size_t(from.k);
    for (size_t r = 0; r < rows; ++r) to->g[r * to->k + a] = from.g[r * from.k + j];
    for (size_t c = 0; c < cols; ++c) to->h[c * to->k + a] = from.h[c * from.k + j];
}

// Terms by decreasing energy |g_a| |h_a|; a held constant term stays first.
void order_terms(LowRank* f, bool keep_first, size_t rows, size_t cols) {
    const int k = f->k;
    std::vector<double> energy(size_t(k), 0.0);
    for (int a = 0; a < k; ++a) {
        double g = 0, h = 0;
        for (size_t r = 0; r < rows; ++r) g += f->g[r * k + a] * f->g[r * k + a];
        for (size_t c = 0; c < cols; ++c) h += f->h[c * k + a] * f->h[c * k + a];
        energy[size_t(a)] = std::sqrt(g * h);
    }
    std::vector<int> idx(static_cast<size_t>(k));
    std::iota(idx.begin(), idx.end(), 0);
    std::stable_sort(idx.begin() + (keep_first ? 1 : 0), idx.end(),
                     [&](int a, int b) { return energy[size_t(a)] > energy[size_t(b)]; });
    LowRank o = *f;
    for (int a = 0; a < k; ++a) {
        for (size_t r = 0; r < rows; ++r) o.g[r * k + a] = f->g[r * k + idx[size_t(a)]];
        for (size_t c = 0; c < cols; ++c) o.h[c * k + a] = f->h[c * k + idx[size_t(a)]];
    }
    *f = std::move(o);
}

LowRank with_columns(const LowRank& f, int k, size_t rows, size_t cols) {
    LowRank o;
    o.k = k;
    o.g.assign(rows * k, 0.0);
    o.h.assign(cols * k, 0.0);
    for (int a = 0; a < std::min(k, f.k); ++a) {
        for (size_t r = 0; r < rows; ++r) o.g[r * k + a] = f.g[r * f.k + a];
        for (size_t c = 0; c < cols; ++c) o.h[c * k + a] = f.h[c * f.k + a];
    }
    return o;
}
}  // namespace

// ---- the engine ---------------------------------------------------------------------------
namespace {

// The matrix an option set asks for, against the rank it can have, --max-memory and the
// machine's memory: refused before any work, with the flags that would fit.
bool check_factor_budget(const FactorOptions& o, FactorResult* r, std::string* err) {
    matrix_shape(o, &r->rows, &r->cols);
    if (o.terms > std::min(r->rows, r->cols)) {
        if (err)
            *err = "--terms " + std::to_string(o.terms) + " exceeds the rank the " + std::to_string(r->rows) + " x " +
                   std::to_string(r->cols) + " sample matrix can have at --res " + std::to_string(o.res) +
                   " (at most " + std::to_string(std::min(r->rows, r->cols)) + ")";
        return false;
    }
    r->memory_mb = estimate_memory_mb(o);
    if (r->memory_mb > o.max_memory_mb) {
        char buf[512];
        if (o.method == Method::ND)
            std::snprintf(buf, sizeof buf,
                          "--method nd at --res %d needs about %.0f MB, over the --max-memory "
                          "limit of %.0f MB; use a lower --res or raise --max-memory",
                          o.res, r->memory_mb, o.max_memory_mb);
        else
            std::snprintf(buf, sizeof buf,
                          "--method %s holds the %d x %d x %d sample matrix: about %.0f MB at "
                          "--res %d, over the --max-memory limit of %.0f MB; use --method nd "
                          "(it streams: memory = output), --colour luminance, a lower --res, "
                          "or raise --max-memory",
                          method_name(o.method), r->rows, r->cols, channels_of(o), r->memory_mb, o.res,
                          o.max_memory_mb);
        if (err) *err = buf;
        return false;
    }
    // Whatever --max-memory allows, not more than the machine has: past it the allocation
    // fails (or the kernel kills the process) after minutes of work.
    const double physical_mb = physical_memory_mb();
    if (physical_mb > 0 && r->memory_mb > physical_mb) {
        char buf[256];
        std::snprintf(buf, sizeof buf,
                      "--method %s at --res %d needs about %.0f MB; this machine has %.0f MB of memory "
                      "(use --method nd, --colour luminance or a lower --res)",
                      method_name(o.method), o.res, r->memory_mb, physical_mb);
        if (err) *err = buf;
        return false;
    }
    return true;
}

// nmf, acls and the SVD weighted over valid entries: term counts one after another, each
// warm-started from the previous solution plus the next SVD term. (A K-term weighted fit is
// not nested: its first term need not be the best single term, so each k gets its own
// solution, kept in stages[k - 1].)
void als_ladder(const Matrix& m, const PairSampler& sampler, const FactorOptions& o, bool weighted_svd,
                std::atomic<int64_t>* solver_fallbacks, std::vector<LowRank>* lr,
                std::vector<std::vector<LowRank>>* stages, FactorResult* r) {
    const int ch = channels_of(o), k = o.terms;
    const bool acls = o.method == Method::ACLS, nmf = o.method == Method::NMF;
    const int hside = half_angle_factor(o.param);
    std::vector<int> parent, order;
    if (acls && o.acls_monotonic)
        monotone_forest(hside == 0 ? sampler.row_texels() : sampler.col_texels(), factor_res(o, hside), &parent,
                        &order);
    detail::AlsSettings s;
    s.rule = acls ? detail::AlsRule::Constrained : nmf ? detail::AlsRule::Multiplicative : detail::AlsRule::LeastSquares;
    // Defaults per term count, chosen on ward/velvet at 64x64 (README): beyond them
    // the matrix error still falls slowly but the cosine-weighted RMS no longer moves.
    s.max_iters = o.iterations ? o.iterations : (acls ? 50 : nmf ? 100 : 50);
    s.tolerance = o.tolerance > 0 ? o.tolerance : (acls ? 1e-5 : nmf ? 1e-4 : 1e-6);
    // Extra per-row updates are cheap next to a pass over the matrix: 16 multiplicative
    // updates per pass cut the passes about 4x at equal error (measured, ward 32x32).
    s.inner = acls ? 8 : 16;
    s.threads = o.threads;
    s.constant_side = acls && o.acls_constant ? hside : -1;
    s.monotone_side = acls && o.acls_monotonic ? hside : -1;
    s.parent = &parent;
    s.order = &order;
    s.horizon_weight = o.horizon_weight;
    s.fallbacks = solver_fallbacks;
    stages->assign(size_t(k), std::vector<LowRank>(size_t(ch)));
    if (weighted_svd)
        r->notes.push_back("weighted: entries partly or wholly below the horizon "
                           "count by their share of valid pairs");
    for (int c = 0; c < ch; ++c) {
        LowRank init;
        detail::truncated_svd(m, c, k, o.seed, o.threads, &init, nullptr);
        LowRank cur;
        for (int kk = 1; kk <= k; ++kk) {
            LowRank next = with_columns(cur, kk, size_t(m.rows), size_t(m.cols));
            const int a = kk - 1;
            if (s.constant_side >= 0 && a == 0) {
                // The held term: 1 on the half-angle side, the SVD's leading
                // profile (made positive) on the other.
                detail::nndsvd_column(init, 0, &next, 0, false);
                std::vector<double>& held = hside == 0 ? next.g : next.h;
                for (size_t i = 0; i < held.size(); i += size_t(kk)) held[i] = 1.0;
            } else if (weighted_svd) {
                copy_column(init, a, &next, a);
            } else {
                const int j = s.constant_side >= 0 ? a - 1 : a;
                detail::nndsvd_column(init, j, &next, a, nmf);
                if (kk > 1) {
                    // The new term starts small: the start is then as good as the
                    // previous term count's solution, and both update rules only
                    // lower the error from there (a full-size SVD-shaped term can
                    // start far worse than the solution it extends).
                    for (size_t i = 0; i < size_t(m.rows); ++i) next.g[i * kk + a] *= 0.03;
                    for (size_t i = 0; i < size_t(m.cols); ++i) next.h[i * kk + a] *= 0.03;
                }
            }
            int it = 0;
            s.anchor = kk > 1 ? &cur : nullptr;
            detail::als_solve(m, c, s, &next, &it);
            r->iterations += it;
            if (weighted_svd)
                detail::orthogonalize(&next);
            else
                order_terms(&next, s.constant_side >= 0, size_t(m.rows), size_t(m.cols));
            (*stages)[size_t(kk - 1)][size_t(c)] = next;
            cur = next;
        }
        (*lr)[size_t(c)] = cur;
    }
}

// Every method but nd: the sample matrix held in memory, the rows and columns that hold
// data marked, negative entries clamped for the non-negative fits, then the plain SVD or
// the ladder above.
bool factor_held(const PairSampler& sampler, const FactorOptions& o, double t0, Matrix* m, glm::dvec3* ratio,
                 std::vector<uint8_t>* row_has, std::vector<uint8_t>* col_has, std::vector<LowRank>* lr,
                 std::vector<std::vector<LowRank>>* stages, FactorResult* r, std::string* err) {
    if (!sample_matrix(sampler, o, m, ratio, &r->evaluations, err)) return false;
    const double t1 = now_seconds();
    r->sample_seconds = t1 - t0;
    row_has->assign(size_t(m->rows), 0);
    col_has->assign(size_t(m->cols), 0);
    bool partial = false;
    for (int i = 0; i < m->rows; ++i)
        for (int c = 0; c < m->cols; ++c) {
            const float w = m->w[size_t(i) * m->cols + c];
            if (w > 0) (*row_has)[size_t(i)] = (*col_has)[size_t(c)] = 1;
            if (w != 1.0f) partial = true;
        }
    if (o.method == Method::NMF || o.method == Method::ACLS)
        for (std::vector<float>& plane : m->wv)
            for (float& x : plane)
                if (x < 0) x = 0, ++r->clamped_negative;
    if (r->clamped_negative)
        r->notes.push_back(std::to_string(r->clamped_negative) +
                           " negative matrix entries clamped to 0 for a non-negative fit");
    const int ch = channels_of(o);
    lr->resize(size_t(ch));
    const bool svd = o.method == Method::SVD || o.method == Method::WSVD;
    const bool weighted_svd = svd && (o.method == Method::WSVD || o.svd_weighted) && partial;
    std::atomic<int64_t> solver_fallbacks{0};
    if (svd && !weighted_svd) {
        for (int c = 0; c < ch; ++c) detail::truncated_svd(*m, c, o.terms, o.seed, o.threads, &(*lr)[size_t(c)], nullptr);
    } else {
        als_ladder(*m, sampler, o, weighted_svd, &solver_fallbacks, lr, stages, r);
    }
    r->factor_seconds = now_seconds() - t1;
    r->solver_fallbacks = solver_fallbacks.load();
    if (r->solver_fallbacks)
        r->notes.push_back(std::to_string(r->solver_fallbacks) +
                           " solver updates fell back to 0 (a non-finite solution or no data)");
    return true;
}

}  // namespace

bool factor_brdf(const Brdf& brdf, const FactorOptions& o, FactorResult* out, std::string* err) {
    if (!validate_factor_options(o, err)) return false;
    if (o.method == Method::Homomorphic) return detail::factor_brdf_homomorphic(brdf, o, out, err);
    FactorResult r;
    if (!check_factor_budget(o, &r, err)) return false;
    const int ch = channels_of(o), k = o.terms;
    PairSampler sampler(brdf, o);
    r.frame_fallbacks = sampler.frame_fallback_pairs();
    if (r.frame_fallbacks)
        r.notes.push_back(std::to_string(r.frame_fallbacks) +
                          " sample pairs use the degenerate-frame fallback of param.h");
    const double t0 = now_seconds();
    std::vector<LowRank> lr;
    glm::dvec3 ratio(1);
    std::vector<uint8_t> row_has, col_has;
    std::vector<std::vector<LowRank>> stages;  // nmf/acls: [k-1][channel]
    Matrix m;
    if (o.method == Method::ND) {
        if (!detail::nd_factor(sampler, o, ch, &lr, &ratio, &row_has, &col_has, &r.sample_seconds, &r.evaluations,
                               err))
            return false;
        r.factor_seconds = now_seconds() - t0 - r.sample_seconds;
    } else if (!factor_held(sampler, o, t0, &m, &ratio, &row_has, &col_has, &lr, &stages, &r, err)) {
        return false;
    }

    // Every term count's prefix, and its error over the matrix when asked for.
    const Layout layout = make_layout(sampler, factor_res(o, 0), factor_res(o, 1), row_has, col_has);
    r.factored = build_factored(o, brdf.spec(), ratio, lr, layout);
    if (stages.empty()) {
        for (int kk = 1; kk <= k; ++kk) r.by_terms.push_back(r.factored.prefix(kk));
        if (!o.matrix_error) {
            // left empty
        } else if (o.method == Method::ND) {
            if (!matrix_rms_streamed(sampler, o, r.factored, layout, &r.matrix_rms, err)) return false;
        } else {
            r.matrix_rms = matrix_rms_held(m, r.factored, layout, o.threads);
        }
    } else {
        for (int kk = 1; kk <= k; ++kk) {
            r.by_terms.push_back(build_factored(o, brdf.spec(), ratio, stages[size_t(kk - 1)], layout));
            if (o.matrix_error)
                r.matrix_rms.push_back(matrix_rms_held(m, r.by_terms.back(), layout, o.threads).back());
        }
    }
    *out = std::move(r);
    return true;
}

double time_sampling_pass(const Brdf& brdf, const FactorOptions& o, std::string* err) {
    FactorOptions opt = o;
    if (!validate_factor_options(opt, err)) return -1;
    PairSampler s(brdf, opt);
    const int rows = s.rows(), cols = s.cols();
    const size_t chunks = size_t((rows + detail::kRowChunk - 1) / detail::kRowChunk);
    std::vector<std::string> errors(chunks);
    const double t0 = now_seconds();
    parallel_for(chunks, opt.threads, [&](size_t chunk) {
        std::vector<float> rgb(size_t(cols) * 3);
        std::vector<uint16_t> cnt(static_cast<size_t>(cols));
        const int r0 = int(chunk) * detail::kRowChunk, r1 = std::min(rows, r0 + detail::kRowChunk);
        for (int r = r0; r < r1; ++r)
            if (!s.sample_row(r, rgb.data(), cnt.data(), &errors[chunk])) return;
    });
    const double t = now_seconds() - t0;
    for (const std::string& e : errors)
        if (!e.empty()) {
            if (err) *err = e;
            return -1;
        }
    return t;
}

}  // namespace sepal
