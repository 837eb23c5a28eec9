// Homomorphic factorization (see homomorphic.h).
#include "factor/homomorphic.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "factor/factor.h"
#include "factor/factor_internal.h"
#include "factor/param.h"
#include "util/parallel.h"

namespace sepal {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The ridge that fixes log p + c, log q - 2c: small against every data and smoothness row.
constexpr double kRidge = 1e-4;

using SparseMat = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// The texels and GL_LINEAR weights of one lookup (clamped at the edges, as factored.h's
// bilinear_lookup and GL do).
struct Lookup {
    int texel[4];
    double weight[4];
};

Lookup lookup(const glm::dvec2& uv, int n) {
    const double sx = uv.x * n - 0.5, sy = uv.y * n - 0.5;
    const double fx = std::floor(sx), fy = std::floor(sy);
    const double ax = sx - fx, ay = sy - fy;
    auto clamp = [n](int k) { return k < 0 ? 0 : k >= n ? n - 1 : k; };
    const int i0 = clamp(int(fx)), i1 = clamp(int(fx) + 1), j0 = clamp(int(fy)), j1 = clamp(int(fy) + 1);
    return Lookup{{j0 * n + i0, j0 * n + i1, j1 * n + i0, j1 * n + i1},
                  {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay}};
}

glm::dvec3 rotate_z(const glm::dvec3& v, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return glm::dvec3(c * v.x - s * v.y, s * v.x + c * v.y, v.z);
}

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// One data row: the three lookups (p at wi, q at h, p at wo) of a direction pair.
struct Row {
    Lookup pi, q, po;
    glm::dvec3 value;  // f, per channel
    double weight;     // before normalization
};

// The design matrix: data rows (sqrt of their weight times the lookup weights), then the
// smoothness rows, then the ridge. Unknowns: log p texels [0, n^2), log q texels [n^2, 2 n^2).
SparseMat design_matrix(const std::vector<Row>& rows, const std::vector<double>& row_scale, int n,
                        double lambda, int order) {
    const int nn = n * n;
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(rows.size() * 12 + size_t(2 * nn) * 6);
    int r = 0;
    for (size_t k = 0; k < rows.size(); ++k, ++r) {
        const Row& row = rows[k];
        const double s = row_scale[k];
        for (int c = 0; c < 4; ++c) {
            t.emplace_back(r, row.pi.texel[c], s * row.pi.weight[c]);
            t.emplace_back(r, nn + row.q.texel[c], s * row.q.weight[c]);
            t.emplace_back(r, row.po.texel[c], s * row.po.weight[c]);
        }
    }
    // Smoothness: lambda (count x - sum of neighbours) per texel of each factor; at the
    // edges only the neighbours that exist (a Neumann border: flat extension).
    for (int f = 0; f < 2 && order == 1; ++f)  // membrane: one row per neighbour pair
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                for (int d = 0; d < 2; ++d) {
                    const int i2 = i + (d == 0), j2 = j + (d == 1);
                    if (i2 >= n || j2 >= n) continue;
                    t.emplace_back(r, f * nn + j * n + i, lambda);
                    t.emplace_back(r, f * nn + j2 * n + i2, -lambda);
                    ++r;
                }
    for (int f = 0; f < 2 && order == 2; ++f)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i, ++r) {
                const int nb[4][2] = {{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}};
                int count = 0;
                for (const auto& q : nb)
                    if (q[0] >= 0 && q[0] < n && q[1] >= 0 && q[1] < n) {
                        t.emplace_back(r, f * nn + q[1] * n + q[0], -lambda);
                        ++count;
                    }
                t.emplace_back(r, f * nn + j * n + i, lambda * count);
            }
    for (int u = 0; u < 2 * nn; ++u, ++r) t.emplace_back(r, u, kRidge);
    SparseMat a(r, 2 * nn);
    a.setFromTriplets(t.begin(), t.end());
    a.makeCompressed();
    return a;
}

struct Solve {
    std::vector<double> log_p, log_q;
    int iterations = 0;
};

int polish(const SparseMat& a, const std::vector<Row>& rows, const std::vector<double>& row_scale,
           const std::vector<double>& target, int n, const HomomorphicOptions& o, Eigen::VectorXd* x);

// One least-squares solve for right-hand side `target` (f per data row, already floored),
// then the polish on the rendered model.
Solve solve(const SparseMat& a, const std::vector<Row>& rows, const std::vector<double>& row_scale,
            const std::vector<double>& target, int n, const HomomorphicOptions& o) {
    Eigen::VectorXd b = Eigen::VectorXd::Zero(a.rows());
    for (size_t k = 0; k < target.size(); ++k) b[Eigen::Index(k)] = row_scale[k] * std::log(target[k]);
    Eigen::LeastSquaresConjugateGradient<SparseMat> cg;
    cg.setMaxIterations(o.max_iterations);
    cg.setTolerance(o.tolerance);
    cg.compute(a);
    Eigen::VectorXd x = cg.solve(b);
    Solve s;
    s.iterations = int(cg.iterations());
    if (o.polish_iterations > 0) s.iterations += polish(a, rows, row_scale, target, n, o, &x);
    const int nn = n * n;
    s.log_p.assign(x.data(), x.data() + nn);
    s.log_q.assign(x.data() + nn, x.data() + 2 * nn);
    return s;
}

double row_model(const Row& r, const std::vector<double>& p, const std::vector<double>& q) {
    double a = 0, b = 0, c = 0;
    for (int k = 0; k < 4; ++k) {
        a += r.pi.weight[k] * p[size_t(r.pi.texel[k])];
        b += r.q.weight[k] * q[size_t(r.q.texel[k])];
        c += r.po.weight[k] * p[size_t(r.po.texel[k])];
    }
    return a * b * c;
}

// Gauss-Newton on what the renderer computes, bilinear(P)(wi) bilinear(Q)(h) bilinear(P)(wo),
// from the log-space solution (which fits exp(bilinear(log P)) ..., the paper's linear
// model). The two differ where neighbouring texels differ a lot in log (a mirror peak's
// texel next to its neighbours: the linear interpolation of a 40x jump overshoots by far).
// Same weights and regularization rows; a step is halved until the objective falls.
// Returns the conjugate-gradient iterations spent; x (log p then log q) is updated.
int polish(const SparseMat& a, const std::vector<Row>& rows, const std::vector<double>& row_scale,
           const std::vector<double>& target, int n, const HomomorphicOptions& o, Eigen::VectorXd* x) {
    const int nn = n * n;
    const Eigen::Index data = Eigen::Index(rows.size());
    std::vector<double> log_target(rows.size());
    for (size_t k = 0; k < rows.size(); ++k) log_target[k] = std::log(target[k]);
    // The regularization rows of `a` (after the data rows) do not change.
    std::vector<Eigen::Triplet<double>> reg;
    for (Eigen::Index r = data; r < a.rows(); ++r)
        for (SparseMat::InnerIterator it(a, r); it; ++it) reg.emplace_back(int(r), int(it.col()), it.value());
    auto objective = [&](const Eigen::VectorXd& v, Eigen::VectorXd* res) {
        res->resize(a.rows());
        double sum = 0;
        for (size_t k = 0; k < rows.size(); ++k) {
            const Row& w = rows[k];
            double pa = 0, qb = 0, pc = 0;
            for (int j = 0; j < 4; ++j) {
                pa += w.pi.weight[j] * std::exp(v[w.pi.texel[j]]);
                qb += w.q.weight[j] * std::exp(v[nn + w.q.texel[j]]);
                pc += w.po.weight[j] * std::exp(v[w.po.texel[j]]);
            }
            (*res)[Eigen::Index(k)] = row_scale[k] * (std::log(pa * qb * pc) - log_target[k]);
        }
        const Eigen::VectorXd r_reg = a.bottomRows(a.rows() - data) * v;
        res->tail(a.rows() - data) = r_reg;
        sum = res->squaredNorm();
        return sum;
    };
    Eigen::VectorXd res;
    double current = objective(*x, &res);
    int spent = 0;
    for (int it = 0; it < o.polish_iterations; ++it) {
        std::vector<Eigen::Triplet<double>> t = reg;
        t.reserve(reg.size() + rows.size() * 12);
        for (size_t k = 0; k < rows.size(); ++k) {
            const Row& w = rows[k];
            double pa = 0, qb = 0, pc = 0;
            for (int j = 0; j < 4; ++j) {
                pa += w.pi.weight[j] * std::exp((*x)[w.pi.texel[j]]);
                qb += w.q.weight[j] * std::exp((*x)[nn + w.q.texel[j]]);
                pc += w.po.weight[j] * std::exp((*x)[w.po.texel[j]]);
            }
            const double s = row_scale[k];
            for (int j = 0; j < 4; ++j) {  // d log(sum w e^x) / dx_t = w e^x_t / sum
                t.emplace_back(int(k), w.pi.texel[j], s * w.pi.weight[j] * std::exp((*x)[w.pi.texel[j]]) / pa);
                t.emplace_back(int(k), nn + w.q.texel[j], s * w.q.weight[j] * std::exp((*x)[nn + w.q.texel[j]]) / qb);
                t.emplace_back(int(k), w.po.texel[j], s * w.po.weight[j] * std::exp((*x)[w.po.texel[j]]) / pc);
            }
        }
        SparseMat j(a.rows(), a.cols());
        j.setFromTriplets(t.begin(), t.end());
        j.makeCompressed();
        Eigen::LeastSquaresConjugateGradient<SparseMat> cg;
        cg.setMaxIterations(o.max_iterations);
        cg.setTolerance(o.tolerance);
        cg.compute(j);
        const Eigen::VectorXd step = cg.solve(-res);
        spent += int(cg.iterations());
        bool improved = false;
        for (double scale = 1.0; scale > 1.0 / 64; scale *= 0.5) {
            const Eigen::VectorXd trial = *x + scale * step;
            Eigen::VectorXd trial_res;
            const double value = objective(trial, &trial_res);
            if (value < current) {
                *x = trial;
                res = trial_res;
                improved = current - value > 1e-6 * current;
                current = value;
                break;
            }
        }
        if (!improved) break;
    }
    return spent;
}

}  // namespace

bool validate_homomorphic_options(const HomomorphicOptions& o, std::string* err) {
    auto fail = [&](const std::string& why) {
        if (err) *err = "homomorphic: " + why;
        return false;
    };
    if (o.res < 2 || o.res > 256 || (o.res & (o.res - 1)))
        return fail("--res " + std::to_string(o.res) + ": a power of two in 2..256");
    if (o.terms < 1 || o.terms > 4) return fail("--terms " + std::to_string(o.terms) + ": 1..4");
    if (!(o.smoothness > 0 && o.smoothness <= 100)) return fail("--smoothness must be in (0, 100]");
    if (!(o.weight_exponent >= 0 && o.weight_exponent <= 4)) return fail("--hm-weight must be in [0, 4]");
    if (!(o.floor > 0 && o.floor < 1)) return fail("the floor must be in (0, 1)");
    if (!std::isfinite(o.cap) || !std::isfinite(o.white)) return fail("the cap and white level must be finite (<= 0: none)");
    if (!(o.weight_quantile > 0 && o.weight_quantile <= 1)) return fail("the weight quantile must be in (0, 1]");
    if (o.rotations < 1 || o.rotations > 256) return fail("rotations must be 1..256");
    if (o.smoothness_order != 1 && o.smoothness_order != 2) return fail("smoothness order 1 or 2");
    if (o.max_iterations < 1 || o.max_iterations > 100000 || !(o.tolerance > 0))
        return fail("iterations 1..100000 and a positive tolerance");
    if (o.backfit_sweeps < 1 || o.backfit_sweeps > 50) return fail("backfit sweeps 1..50");
    if (o.polish_iterations < 0 || o.polish_iterations > 50) return fail("polish iterations 0..50");
    return true;
}

namespace {

// Every sample finite, non-negative, with unit directions, and not too many of them.
bool check_samples(const std::vector<BrdfSample>& samples, std::string* why) {
    if (samples.empty()) return *why = "no samples to fit (an empty measurement?)", false;
    if (samples.size() > kMaxHomomorphicSamples)
        return *why = std::to_string(samples.size()) + " samples; at most " + std::to_string(kMaxHomomorphicSamples),
               false;
    for (size_t i = 0; i < samples.size(); ++i) {
        const BrdfSample& s = samples[i];
        if (!finite3(s.wi) || !finite3(s.wo) || !finite3(s.value))
            return *why = "sample " + std::to_string(i) + " has a non-finite direction or value", false;
        if (s.value.x < 0 || s.value.y < 0 || s.value.z < 0)
            return *why = "sample " + std::to_string(i) + " has a negative value", false;
        if (std::fabs(glm::length(s.wi) - 1) > 1e-6 || std::fabs(glm::length(s.wo) - 1) > 1e-6)
            return *why = "sample " + std::to_string(i) + " has a direction that is not a unit vector", false;
    }
    return true;
}

// The fit's rows: each sample above the horizon (isotropic fits: also rotated about the
// normal), its three parabolic-map lookups, its value capped at the cap and white level,
// and its weight f cos theta_i.
std::vector<Row> make_rows(const std::vector<BrdfSample>& samples, const HomomorphicOptions& o, HomomorphicStats* st) {
    const int n = o.res;
    const int rotations = o.isotropic ? o.rotations : 1;
    std::vector<Row> rows;
    rows.reserve(samples.size() * size_t(rotations));
    for (const BrdfSample& s : samples) {
        if (s.wi.z <= 0 || s.wo.z <= 0) {
            ++st->below_horizon;
            continue;
        }
        for (int r = 0; r < rotations; ++r) {
            const double angle = 2 * kPi * r / rotations;
            const glm::dvec3 wi = r ? rotate_z(s.wi, angle) : s.wi, wo = r ? rotate_z(s.wo, angle) : s.wo;
            const glm::dvec3 h = glm::normalize(wi + wo);
            Row row;
            row.pi = lookup(map_forward(HemiMap::Parabolic, wi), n);
            row.q = lookup(map_forward(HemiMap::Parabolic, h), n);
            row.po = lookup(map_forward(HemiMap::Parabolic, wo), n);
            row.value = s.value;
            double cap = o.cap > 0 ? o.cap : 1e300;
            if (o.white > 0) cap = std::min(cap, o.white);
            if (s.value.x > cap || s.value.y > cap || s.value.z > cap) {
                row.value = glm::min(s.value, glm::dvec3(cap));
                if (r == 0) ++st->capped;
            }
            row.weight = luminance(row.value) * wi.z;
            rows.push_back(row);
        }
    }
    return rows;
}

// Row weights (f cos)^gamma, floored at a small share of the mean so zero values still
// count a little, clipped at a quantile so a handful of mirror-peak samples cannot
// outweigh everything else, normalized to mean 1 so lambda means the same for any
// sample count. Returned as their square roots (what scales a least-squares row).
std::vector<double> row_scales(const std::vector<Row>& rows, const HomomorphicOptions& o) {
    std::vector<double> row_scale(rows.size());
    double wmean = 0;
    std::vector<double> sorted;
    sorted.reserve(rows.size());
    for (const Row& r : rows) wmean += r.weight, sorted.push_back(r.weight);
    wmean = wmean > 0 ? wmean / double(rows.size()) : 1.0;
    const size_t qi = std::min(sorted.size() - 1, size_t(o.weight_quantile * double(sorted.size())));
    std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(qi), sorted.end());
    const double clip = std::max(sorted[qi], o.floor * wmean);
    double total = 0;
    for (size_t k = 0; k < rows.size(); ++k) {
        row_scale[k] = std::pow(std::min(clip, std::max(rows[k].weight, o.floor * wmean)), o.weight_exponent);
        total += row_scale[k];
    }
    for (double& v : row_scale) v = std::sqrt(v * double(rows.size()) / total);
    return row_scale;
}

// What one channel's fit needs besides its values: the rows, their scales, the design
// matrix and which texels of p and q some sample reaches.
struct ChannelProblem {
    const std::vector<Row>& rows;
    const std::vector<double>& row_scale;
    const SparseMat& a;
    const std::vector<uint8_t>& hit_p;
    const std::vector<uint8_t>& hit_q;
    const HomomorphicOptions& o;
};

// One channel's factors: K terms p_t(wi) q_t(h) p_t(wo) by backfitting (K = 1: one solve),
// each the solve of its target's logs, floored at o.floor x the channel's mean.
struct ChannelFit {
    std::vector<std::vector<double>> p, q;  // [term] -> texels
    int iterations = 0;
    int64_t floored = 0;
    double log_sq = 0;  // single term: the weighted mean squared log residual
};

ChannelFit fit_channel(const ChannelProblem& pr, const std::vector<double>& value, double cmean) {
    const std::vector<Row>& rows = pr.rows;
    const HomomorphicOptions& o = pr.o;
    const int n = o.res, nn = n * n, terms = o.terms;
    ChannelFit out;
    out.p.assign(size_t(terms), {});
    out.q.assign(size_t(terms), {});
    if (!(cmean > 0)) {  // a channel that is 0 everywhere: zero factors, exactly
        for (int t = 0; t < terms; ++t) out.p[size_t(t)].assign(size_t(nn), 0.0), out.q[size_t(t)].assign(size_t(nn), 0.0);
        return out;
    }
    const double fl = o.floor * cmean;
    std::vector<std::vector<double>> model(size_t(terms), std::vector<double>(rows.size(), 0.0));
    std::vector<double> target(rows.size());
    const int sweeps = terms == 1 ? 1 : o.backfit_sweeps;
    for (int sweep = 0; sweep < sweeps; ++sweep)
        for (int t = 0; t < terms; ++t) {
            int64_t low = 0;
            for (size_t k = 0; k < rows.size(); ++k) {
                double others = 0;
                for (int u = 0; u < terms; ++u)
                    if (u != t) others += model[size_t(u)][k];
                const double v = value[k] - others;
                if (v < fl) ++low;
                target[k] = std::max(v, fl);
            }
            if (sweep == 0 && t == 0) out.floored = low;
            Solve s = solve(pr.a, rows, pr.row_scale, target, n, o);
            // Texels no sample reaches stay within the range of those some sample
            // does: the smoothness term extends the logs along their slope, and exp
            // of a long extrapolation is a peak no measurement showed.
            for (int f = 0; f < 2; ++f) {
                std::vector<double>& x = f ? s.log_q : s.log_p;
                const std::vector<uint8_t>& hit = f ? pr.hit_q : pr.hit_p;
                double lo = 1e300, hi = -1e300;
                for (int i = 0; i < nn; ++i)
                    if (hit[size_t(i)]) lo = std::min(lo, x[size_t(i)]), hi = std::max(hi, x[size_t(i)]);
                for (int i = 0; i < nn && lo <= hi; ++i)
                    if (!hit[size_t(i)]) x[size_t(i)] = std::min(hi, std::max(lo, x[size_t(i)]));
            }
            out.iterations += s.iterations;
            std::vector<double>& pt = out.p[size_t(t)];
            std::vector<double>& qt = out.q[size_t(t)];
            pt.resize(size_t(nn));
            qt.resize(size_t(nn));
            for (int i = 0; i < nn; ++i) pt[size_t(i)] = std::exp(s.log_p[size_t(i)]), qt[size_t(i)] = std::exp(s.log_q[size_t(i)]);
            for (size_t k = 0; k < rows.size(); ++k) model[size_t(t)][k] = row_model(rows[k], pt, qt);
            // Single term: the log residual of the fit itself (what the solve minimized).
            if (terms == 1) {
                double sum = 0, wsum = 0;
                for (size_t k = 0; k < rows.size(); ++k) {
                    double m = 0;
                    for (int j = 0; j < 4; ++j)
                        m += rows[k].pi.weight[j] * s.log_p[size_t(rows[k].pi.texel[j])] +
                             rows[k].q.weight[j] * s.log_q[size_t(rows[k].q.texel[j])] +
                             rows[k].po.weight[j] * s.log_p[size_t(rows[k].po.texel[j])];
                    const double d = m - std::log(target[k]), w = pr.row_scale[k] * pr.row_scale[k];
                    sum += w * d * d, wsum += w;
                }
                out.log_sq = sum / wsum;
            }
        }
    return out;
}

}  // namespace

bool factor_homomorphic(const std::vector<BrdfSample>& samples, const HomomorphicOptions& o, Factored* out,
                        HomomorphicStats* stats, std::string* err) {
    const auto start = std::chrono::steady_clock::now();
    if (!validate_homomorphic_options(o, err)) return false;
    auto fail = [&](const std::string& why) {
        if (err) *err = "homomorphic: " + why;
        return false;
    };
    std::string why;
    if (!check_samples(samples, &why)) return fail(why);
    HomomorphicStats st;
    st.samples = int64_t(samples.size());
    const int n = o.res, nn = n * n;
    const std::vector<Row> rows = make_rows(samples, o, &st);
    if (rows.empty()) return fail("every sample has a direction at or below the horizon");
    st.rows = int64_t(rows.size());

    // Channels: per channel, or the luminance with per-channel least-squares ratios.
    const int ch = o.colour == ColourMode::PerChannel ? 3 : 1;
    glm::dvec3 ratio(1), mean(0);
    double lum_mean = 0;
    for (const Row& r : rows) mean += r.value, lum_mean += luminance(r.value);
    mean /= double(rows.size());
    lum_mean /= double(rows.size());
    if (ch == 1) {
        glm::dvec3 num(0);
        double den = 0;
        for (const Row& r : rows) {
            const double l = luminance(r.value);
            num += r.value * l;
            den += l * l;
        }
        ratio = den > 0 ? num / den : glm::dvec3(1);
    }
    const std::vector<double> row_scale = row_scales(rows, o);
    // Smoothness rows weigh like the data: lambda * sqrt(data rows / texels).
    const double lambda = o.smoothness * std::sqrt(double(rows.size()) / double(2 * nn));
    const SparseMat a = design_matrix(rows, row_scale, n, lambda, o.smoothness_order);
    std::vector<uint8_t> hit_p(size_t(nn), 0), hit_q(size_t(nn), 0);
    for (const Row& r : rows)
        for (int k = 0; k < 4; ++k) {
            if (r.pi.weight[k] > 0) hit_p[size_t(r.pi.texel[k])] = 1;
            if (r.po.weight[k] > 0) hit_p[size_t(r.po.texel[k])] = 1;
            if (r.q.weight[k] > 0) hit_q[size_t(r.q.texel[k])] = 1;
        }
    st.unreached_p = int(std::count(hit_p.begin(), hit_p.end(), uint8_t(0)));
    st.unreached_q = int(std::count(hit_q.begin(), hit_q.end(), uint8_t(0)));

    const ChannelProblem problem{rows, row_scale, a, hit_p, hit_q, o};
    std::vector<ChannelFit> fits(static_cast<size_t>(ch));
    parallel_for(size_t(ch), o.threads, [&](size_t c) {
        std::vector<double> value(rows.size());
        for (size_t k = 0; k < rows.size(); ++k) value[k] = ch == 1 ? luminance(rows[k].value) : rows[k].value[int(c)];
        fits[c] = fit_channel(problem, value, ch == 1 ? lum_mean : mean[int(c)]);
    });
    Factored f;
    f.form = Form::Reciprocal;
    f.param = Param::ViewHalf;
    f.map = HemiMap::Parabolic;
    f.colour = o.colour;
    f.n = n;
    f.channels = ch;
    f.ratio = ratio;
    f.method = "homomorphic";
    for (int t = 0; t < o.terms; ++t) {
        FactorTerm term{FactorTexture(n, ch), FactorTexture(n, ch)};
        for (int c = 0; c < ch; ++c)
            for (int i = 0; i < nn; ++i) {
                term.g.data[size_t(i) * size_t(ch) + size_t(c)] = float(fits[size_t(c)].p[size_t(t)][size_t(i)]);
                term.h.data[size_t(i) * size_t(ch) + size_t(c)] = float(fits[size_t(c)].q[size_t(t)][size_t(i)]);
            }
        f.terms.push_back(std::move(term));
    }
    std::string verr;
    if (!validate_factored(f, &verr))  // exp overflow: a fit gone wild, never silently
        return fail("the fit produced unusable factors (" + verr + "); raise --smoothness");
    for (int c = 0; c < ch; ++c) {
        st.iterations += fits[size_t(c)].iterations;
        st.floored += fits[size_t(c)].floored;
        st.log_rms += fits[size_t(c)].log_sq / ch;
    }
    st.log_rms = std::sqrt(st.log_rms);
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    *out = std::move(f);
    if (stats) *stats = st;
    return true;
}

bool homomorphic_dense_samples(const Brdf& brdf, int res, int per_texel, std::vector<BrdfSample>* out,
                               std::string* err) {
    const std::vector<uint8_t> valid = valid_texels(Param::ViewHalf, HemiMap::Parabolic, 1, res);
    const int64_t texels = std::count(valid.begin(), valid.end(), uint8_t(1));
    const int64_t want = std::max<int64_t>(1, int64_t(per_texel) * texels * 2);
    out->clear();
    out->reserve(size_t(want));
    // A point uniform over the map's disk, as a unit vector (the parabolic map's inverse).
    auto disk_point = [](uint64_t seed, uint64_t i, glm::dvec3* a) {
        for (uint64_t k = 0;; ++k) {
            const double u = counter_uniform(seed, 2 * (i + (k << 40))), v = counter_uniform(seed, 2 * (i + (k << 40)) + 1);
            if (map_inverse(HemiMap::Parabolic, glm::dvec2(u, v), a)) return;
        }
    };
    const uint64_t kSeed = 0x686f6d6f6d6f7270ULL;  // fixed: equal samples in every run
    for (int64_t i = 0, draw = 0; int64_t(out->size()) < want; ++draw) {
        if (draw > 64 * want) break;  // never: half the pairs are above the horizon
        glm::dvec3 h, wo;
        disk_point(kSeed, uint64_t(draw), &h);
        disk_point(kSeed ^ 1, uint64_t(draw), &wo);
        const glm::dvec3 wi = 2.0 * glm::dot(wo, h) * h - wo;
        if (wi.z <= 1e-6 || wo.z <= 1e-6) continue;
        const glm::dvec3 v = brdf.eval(wi, wo);
        if (!finite3(v)) {
            if (err) *err = "homomorphic: the BRDF returned a non-finite value";
            return false;
        }
        out->push_back({glm::normalize(wi), wo, glm::max(v, glm::dvec3(0.0)), 1.0});
        ++i;
    }
    return true;
}

}  // namespace sepal

namespace sepal {
namespace detail {

bool factor_brdf_homomorphic(const Brdf& brdf, const FactorOptions& o, FactorResult* out, std::string* err) {
    const auto start = std::chrono::steady_clock::now();
    FactorResult r;
    std::vector<BrdfSample> samples;
    const bool raw = o.samples != FactorOptions::Samples::Dense && brdf.scattered_samples(&samples);
    if (o.samples == FactorOptions::Samples::Raw && !raw) {
        if (err)
            *err = "--samples raw: " + brdf.spec() +
                   " has no scattered samples (an analytic model or a dense table); use --samples dense";
        return false;
    }
    HomomorphicOptions h = o.homomorphic;
    h.res = o.res, h.colour = o.colour, h.threads = o.threads;
    if (!raw) {
        if (!homomorphic_dense_samples(brdf, o.res, o.dense_per_texel, &samples, err)) return false;
        r.evaluations = int64_t(samples.size());
        h.rotations = 1;  // dense samples cover every azimuth already
    }
    h.isotropic = h.isotropic && brdf.isotropic();
    r.sample_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.rows = int(samples.size());
    r.cols = 1;
    r.memory_mb = double(samples.size()) * (raw && h.isotropic ? h.rotations : 1) * 12 * 16 / (1024.0 * 1024.0);
    for (int k = 1; k <= o.terms; ++k) {
        h.terms = k;
        Factored f;
        HomomorphicStats st;
        if (!factor_homomorphic(samples, h, &f, &st, err)) return false;
        f.source = brdf.spec();
        r.iterations += st.iterations;
        r.matrix_rms.push_back(st.log_rms);
        if (k == 1) {
            char buf[320];
            std::snprintf(buf, sizeof buf,
                          "homomorphic: %s samples (%lld; %lld rows after %d rotation%s), %lld below the horizon "
                          "dropped, %lld values raised to the floor; %d p and %d q texels reached by no sample "
                          "(filled by the smoothness term)",
                          raw ? "raw scattered" : "dense", (long long)st.samples, (long long)st.rows,
                          h.isotropic ? h.rotations : 1, (h.isotropic ? h.rotations : 1) == 1 ? "" : "s",
                          (long long)st.below_horizon, (long long)st.floored, st.unreached_p, st.unreached_q);
            r.notes.push_back(buf);
        }
        r.by_terms.push_back(std::move(f));
    }
    r.factored = r.by_terms.back();
    r.factor_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - r.sample_seconds;
    *out = std::move(r);
    return true;
}

}  // namespace detail
}  // namespace sepal
