#include "ist/tree.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <glm/common.hpp>

#include "factor/als.h"
#include "factor/factor.h"
#include "factor/scattered.h"
#include "ist/ist_util.h"
#include "measured/cornell.h"
#include "spec/spec.h"
#include "util/image.h"
#include "util/io.h"
#include "util/json.h"
#include "util/json.h"

namespace sepal {

using ist_detail::fail;

namespace {

constexpr double kPi = 3.14159265358979323846;
const char* const kCurveNames[4] = {"g_theta", "g_phi", "h_theta", "h_phi"};

// The unit vector of a map coordinate, clamped onto the disk's rim outside it.
glm::dvec3 map_point(HemiMap m, const glm::dvec2& uv) {
    glm::dvec3 a;
    if (map_inverse(m, uv, &a)) return a;
    glm::dvec2 d = 2.0 * uv - 1.0;
    const double r = std::sqrt(d.x * d.x + d.y * d.y);
    d /= std::max(r, 1e-12);
    return glm::dvec3(d.x, d.y, 0.0);
}

double theta_of(const glm::dvec3& a) { return std::acos(std::min(1.0, std::max(-1.0, a.z))); }
double phi_of(const glm::dvec3& a) {
    const double p = std::atan2(a.y, a.x);
    return p < 0 ? p + 2 * kPi : p;
}

// Knots of a theta curve on [0, pi/2] (sqrt-spaced for half-angle factors) or a phi curve.
std::vector<double> knots(bool phi, bool sqrt_spaced, int n) {
    std::vector<double> x(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
        if (phi) {
            x[size_t(i)] = 2 * kPi * i / n;
        } else {
            const double t = double(i) / (n - 1);
            x[size_t(i)] = 0.5 * kPi * (sqrt_spaced ? t * t : t);
        }
    }
    return x;
}

class TableBrdf : public Brdf {
  public:
    explicit TableBrdf(Tabulated t) : t_(std::move(t)) {}
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override { return t_.eval(wi, wo); }
    // The confidence of the cell holding (wi, wo): its clamped splat weight, 0 where
    // push-pull filled it.
    double confidence(const glm::dvec3& wi, const glm::dvec3& wo) const {
        return t_.confidence(t_.cell_index(to_half_diff(wi, wo)));
    }
    std::string spec() const override { return "ist-basis-table"; }
    std::string model() const override { return "table"; }
    std::string info() const override { return "a basis BRDF tabulated from SVBRDF samples\n"; }
    bool isotropic() const override { return true; }

  private:
    Tabulated t_;
};

// The factor options of the second level.
FactorOptions level2_options(const TreeOptions& o) {
    FactorOptions f;
    f.param = o.param;
    f.map = o.map;
    f.res = o.res;
    f.terms = o.terms;
    f.method = Method::ACLS;
    f.colour = ColourMode::PerChannel;
    const bool has_half = half_angle_factor(o.param) >= 0;
    f.acls_constant = has_half && o.constant_term && o.terms > 1;
    f.acls_monotonic = has_half && o.monotonic;
    f.threads = o.threads;
    return f;
}

bool check_options(const TreeOptions& o, std::string* err) {
    if (angle_textures(o.param))
        return fail(err, std::string("tree: the ") + param_name(o.param) + " parameterization has no hemisphere maps to make curves of");
    if (o.res < 4 || o.res > 128 || o.terms < 1 || o.terms > 4 || o.curve_samples < 2 || o.curve_samples > 1024)
        return fail(err, "tree: res 4..128, terms 1..4, curve samples 2..1024");
    return true;
}

bool factor_level2(const Brdf& b, const TreeOptions& o, Factored* out, std::string* err,
                   const TableBrdf* table = nullptr) {
    FactorResult r;
    FactorOptions f = level2_options(o);
    if (table) {
        const double floor = o.confidence_floor;
        f.confidence = [table, floor](const glm::dvec3& wi, const glm::dvec3& wo) {
            return floor + (1 - floor) * table->confidence(wi, wo);
        };
    }
    if (!factor_brdf(b, f, &r, err)) return false;
    *out = r.factored;
    return true;
}

}  // namespace

glm::dvec3 Curve::at(double a) const {
    const size_t n = x.size();
    if (n == 0) return glm::dvec3(0);
    if (n == 1) return y[0];
    if (periodic) {
        a = std::fmod(a, 2 * kPi);
        if (a < 0) a += 2 * kPi;
        if (a < x.front() || a >= x.back()) {
            // Between the last knot and the first one a period later.
            const double x0 = x.back(), x1 = x.front() + 2 * kPi;
            const double aa = a < x.front() ? a + 2 * kPi : a;
            const double t = (aa - x0) / (x1 - x0);
            return (1 - t) * y.back() + t * y.front();
        }
    } else {
        if (a <= x.front()) return y.front();
        if (a >= x.back()) return y.back();
    }
    const size_t i = size_t(std::upper_bound(x.begin(), x.end(), a) - x.begin());
    const double t = (a - x[i - 1]) / (x[i] - x[i - 1]);
    return (1 - t) * y[i - 1] + t * y[i];
}

glm::dvec3 ShadeTree::eval_basis(int j, const glm::dvec3& wi, const glm::dvec3& wo) const {
    TexCoords tc;
    if (!param_forward(param, map, wi, wo, &tc)) return glm::dvec3(0);
    const glm::dvec3 px = map_point(map, tc.x), py = map_point(map, tc.y);
    const double tx = theta_of(px), fx = phi_of(px), ty = theta_of(py), fy = phi_of(py);
    glm::dvec3 f(0);
    for (const TreeTerm& t : bases[size_t(j)].terms)
        f += t.g_theta.at(tx) * t.g_phi.at(fx) * t.h_theta.at(ty) * t.h_phi.at(fy);
    return f;
}

Factored ShadeTree::textures(int j) const {
    Factored f;
    f.param = param;
    f.map = map;
    f.colour = ColourMode::PerChannel;
    f.n = res;
    f.channels = 3;
    f.method = "ist";
    f.source = bases[size_t(j)].source;
    for (const TreeTerm& t : bases[size_t(j)].terms) {
        FactorTerm ft{FactorTexture(res, 3), FactorTexture(res, 3)};
        for (int jj = 0; jj < res; ++jj)
            for (int i = 0; i < res; ++i) {
                const glm::dvec2 uv((i + 0.5) / res, (jj + 0.5) / res);
                const glm::dvec3 p = map_point(map, uv);
                const glm::dvec3 g = t.g_theta.at(theta_of(p)) * t.g_phi.at(phi_of(p));
                const glm::dvec3 h = t.h_theta.at(theta_of(p)) * t.h_phi.at(phi_of(p));
                for (int c = 0; c < 3; ++c) {
                    ft.g.at(i, jj, c) = float(g[c]);
                    ft.h.at(i, jj, c) = float(h[c]);
                }
            }
        f.terms.push_back(std::move(ft));
    }
    return f;
}

bool curves_from_factors(const Factored& f, int samples, int threads, TreeBasis* out, std::string* err) {
    if (angle_textures(f.param)) return fail(err, std::string("curves: ") + param_name(f.param) + " factors have no hemisphere map");
    const int half = half_angle_factor(f.param);
    const int n_phi = samples;
    TreeBasis b = *out;
    b.terms.clear();
    for (const FactorTerm& ft : f.terms) {
        TreeTerm tt;
        for (int which = 0; which < 2; ++which) {
            const FactorTexture& tex = which == 0 ? ft.g : ft.h;
            const std::vector<double> th = knots(false, which == half, samples), ph = knots(true, false, n_phi);
            // The polar grid, weighted by the solid angle each theta knot stands for.
            detail::Matrix m;
            m.rows = samples;
            m.cols = n_phi;
            m.channels = 3;
            m.w.assign(size_t(samples) * n_phi, 0.0f);
            m.wv.assign(3, std::vector<float>(size_t(samples) * n_phi, 0.0f));
            std::vector<double> vals(size_t(samples) * n_phi * 3);
            for (int i = 0; i < samples; ++i) {
                for (int k = 0; k < n_phi; ++k) {
                    const double t = th[size_t(i)], p = ph[size_t(k)];
                    const glm::dvec3 dir(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
                    double v[3];
                    bilinear_lookup(tex, map_forward(f.map, dir), false, v);
                    for (int c = 0; c < 3; ++c) {
                        const double x = std::max(0.0, f.channels == 1 ? v[0] * f.ratio[c] : v[c]);
                        vals[(size_t(i) * n_phi + size_t(k)) * 3 + size_t(c)] = x;
                    }
                }
                // Each theta row counts by the projected solid angle it stands for (sin cos
                // dtheta), except the outermost ring of texels, whose values are partly filled
                // from inside the disk (factored.h): it would steer the phi curve every row
                // shares. A row's own theta value does not depend on its weight.
                const double lo = i > 0 ? 0.5 * (th[size_t(i - 1)] + th[size_t(i)]) : 0.0;
                const double hi = i + 1 < samples ? 0.5 * (th[size_t(i)] + th[size_t(i + 1)]) : 0.5 * kPi;
                const double proj = 0.5 * (std::cos(lo) * std::cos(lo) - std::cos(hi) * std::cos(hi));
                const glm::dvec2 uv = map_forward(f.map, glm::dvec3(std::sin(th[size_t(i)]), 0, std::cos(th[size_t(i)])));
                const bool rim = 2 * uv.x - 1 > 1 - 3.0 / f.n;
                const double w = rim ? 1e-9 : std::max(proj, 1e-6);
                for (int k = 0; k < n_phi; ++k) {
                    const size_t e = size_t(i) * n_phi + size_t(k);
                    m.w[e] = float(w);
                    for (int c = 0; c < 3; ++c) m.wv[size_t(c)][e] = float(w * vals[e * 3 + size_t(c)]);
                }
            }
            Curve ct, cp;
            ct.x = th;
            cp.x = ph;
            cp.periodic = true;
            ct.y.assign(th.size(), glm::dvec3(0));
            cp.y.assign(ph.size(), glm::dvec3(1));
            for (int c = 0; c < 3; ++c) {
                detail::LowRank svd, r;
                detail::truncated_svd(m, c, 1, 1, threads, &svd, nullptr);
                r.k = 1;
                r.g.assign(size_t(samples), 0.0);
                r.h.assign(size_t(n_phi), 0.0);
                detail::nndsvd_column(svd, 0, &r, 0, false);
                detail::AlsSettings s;
                s.rule = detail::AlsRule::Constrained;
                s.max_iters = 30;
                s.tolerance = 1e-9;
                s.threads = threads;
                int it = 0;
                detail::als_solve(m, c, s, &r, &it);
                double mean = 0;
                for (double v : r.h) mean += v;
                mean /= n_phi;
                if (!(mean > 0)) continue;  // an all-zero channel: theta 0, phi 1
                for (int i = 0; i < samples; ++i) ct.y[size_t(i)][c] = r.g[size_t(i)] * mean;
                for (int k = 0; k < n_phi; ++k) cp.y[size_t(k)][c] = r.h[size_t(k)] / mean;
            }
            (which == 0 ? tt.g_theta : tt.h_theta) = ct;
            (which == 0 ? tt.g_phi : tt.h_phi) = cp;
        }
        // The G theta curve peaks at 1 per channel; H theta takes the magnitude.
        for (int c = 0; c < 3; ++c) {
            double peak = 0;
            for (const glm::dvec3& v : tt.g_theta.y) peak = std::max(peak, v[c]);
            if (!(peak > 0)) continue;
            for (glm::dvec3& v : tt.g_theta.y) v[c] /= peak;
            for (glm::dvec3& v : tt.h_theta.y) v[c] *= peak;
        }
        b.terms.push_back(std::move(tt));
    }
    *out = std::move(b);
    return true;
}

namespace {

// Linear interpolation taps of a curve at an angle (as Curve::at).
struct CurveTap {
    int i0, i1;
    double w0, w1;
};
CurveTap curve_tap(const Curve& c, double a) {
    const int n = int(c.x.size());
    if (c.periodic) {
        a = std::fmod(a, 2 * kPi);
        if (a < 0) a += 2 * kPi;
        if (a < c.x.front() || a >= c.x.back()) {
            const double x0 = c.x.back(), x1 = c.x.front() + 2 * kPi;
            const double t = ((a < c.x.front() ? a + 2 * kPi : a) - x0) / (x1 - x0);
            return CurveTap{n - 1, 0, 1 - t, t};
        }
    } else {
        if (a <= c.x.front()) return CurveTap{0, 0, 1, 0};
        if (a >= c.x.back()) return CurveTap{n - 1, n - 1, 1, 0};
    }
    const int i = int(std::upper_bound(c.x.begin(), c.x.end(), a) - c.x.begin());
    const double t = (a - c.x[size_t(i - 1)]) / (c.x[size_t(i)] - c.x[size_t(i - 1)]);
    return CurveTap{i - 1, i, 1 - t, t};
}

// Puts each term's scale in its H theta curve (phi curves mean 1, G theta peak 1) without
// changing any product.
void normalize_curves(TreeTerm* t) {
    for (int c = 0; c < 3; ++c) {
        for (Curve* p : {&t->g_phi, &t->h_phi}) {
            double mean = 0;
            for (const glm::dvec3& v : p->y) mean += v[c];
            mean /= double(p->y.size());
            if (!(mean > 0)) continue;
            for (glm::dvec3& v : p->y) v[c] /= mean;
            Curve& theta = p == &t->g_phi ? t->g_theta : t->h_theta;
            for (glm::dvec3& v : theta.y) v[c] *= mean;
        }
        double peak = 0;
        for (const glm::dvec3& v : t->g_theta.y) peak = std::max(peak, v[c]);
        if (!(peak > 0)) continue;
        for (glm::dvec3& v : t->g_theta.y) v[c] /= peak;
        for (glm::dvec3& v : t->h_theta.y) v[c] *= peak;
    }
}

// The curves refitted to the samples themselves: alternating constrained least squares
// over the leaves (each curve, the others held, is the exact non-negative minimizer of its
// banded quadratic plus a first-difference smoothness, by projected Gauss-Seidel).
void refine_curves(const std::vector<ScatteredSample>& samples, Param param, HemiMap map, bool hold_first_g,
                   int iterations, double smoothness, TreeBasis* b) {
    struct Pre {
        double angle[4];
        glm::dvec3 f;
        double w;
    };
    std::vector<Pre> pre;
    for (const ScatteredSample& s : samples) {
        TexCoords tc;
        if (!(s.weight > 0) || !param_forward(param, map, s.wi, s.wo, &tc)) continue;
        const glm::dvec3 px = map_point(map, tc.x), py = map_point(map, tc.y);
        pre.push_back(Pre{{theta_of(px), phi_of(px), theta_of(py), phi_of(py)}, s.f, s.weight});
    }
    const int k = int(b->terms.size());
    const size_t ns = pre.size();
    if (!ns) return;
    std::vector<std::vector<CurveTap>> taps(size_t(4 * k), std::vector<CurveTap>(ns));
    for (int t = 0; t < k; ++t)
        for (int i = 0; i < 4; ++i)
            for (size_t s = 0; s < ns; ++s)
                taps[size_t(4 * t + i)][s] = curve_tap(b->terms[size_t(t)].curve(i), pre[s].angle[i]);
    auto value = [&](int t, int i, size_t s, int c) {
        const CurveTap& tp = taps[size_t(4 * t + i)][s];
        const Curve& cv = b->terms[size_t(t)].curve(i);
        return tp.w0 * cv.y[size_t(tp.i0)][c] + tp.w1 * cv.y[size_t(tp.i1)][c];
    };
    for (int it = 0; it < iterations; ++it) {
        for (int c = 0; c < 3; ++c)
            for (int t = 0; t < k; ++t)
                for (int i = 0; i < 4; ++i) {
                    if (hold_first_g && t == 0 && i < 2) continue;
                    Curve& cv = b->terms[size_t(t)].curve(i);
                    const int n = int(cv.x.size());
                    // Tridiagonal (cyclic for phi) normal equations: diagonal, upper.
                    std::vector<double> d(size_t(n), 0.0), u(size_t(n), 0.0), rhs(size_t(n), 0.0);
                    for (size_t s = 0; s < ns; ++s) {
                        double rest = 0, coef = 1;
                        for (int tt = 0; tt < k; ++tt) {
                            if (tt == t) continue;
                            double p = 1;
                            for (int q = 0; q < 4; ++q) p *= value(tt, q, s, c);
                            rest += p;
                        }
                        for (int q = 0; q < 4; ++q)
                            if (q != i) coef *= value(t, q, s, c);
                        const CurveTap& tp = taps[size_t(4 * t + i)][s];
                        const double wc = pre[s].w * coef, r = pre[s].f[c] - rest;
                        rhs[size_t(tp.i0)] += wc * r * tp.w0;
                        rhs[size_t(tp.i1)] += wc * r * tp.w1;
                        d[size_t(tp.i0)] += wc * coef * tp.w0 * tp.w0;
                        d[size_t(tp.i1)] += wc * coef * tp.w1 * tp.w1;
                        if (tp.i0 != tp.i1) u[size_t(tp.i0)] += wc * coef * tp.w0 * tp.w1;  // i1 = i0 + 1 (or 0 after n - 1)
                        else d[size_t(tp.i0)] += 2 * wc * coef * tp.w0 * tp.w1;
                    }
                    double mean = 0;
                    int with = 0;
                    for (double x : d)
                        if (x > 0) mean += x, ++with;
                    const double lambda = smoothness * (with ? mean / with : 0.0) + 1e-300;
                    const int edges = cv.periodic ? n : n - 1;
                    for (int e = 0; e < edges; ++e) {
                        d[size_t(e)] += lambda;
                        d[size_t((e + 1) % n)] += lambda;
                        u[size_t(e)] -= lambda;
                    }
                    for (int sweep = 0; sweep < 30; ++sweep)
                        for (int q = 0; q < n; ++q) {
                            if (!(d[size_t(q)] > 0)) continue;
                            double sum = rhs[size_t(q)];
                            const int next = q + 1 < n ? q + 1 : (cv.periodic ? 0 : -1);
                            const int prev = q > 0 ? q - 1 : (cv.periodic ? n - 1 : -1);
                            if (next >= 0 && next != q) sum -= u[size_t(q)] * cv.y[size_t(next)][c];
                            if (prev >= 0 && prev != q) sum -= u[size_t(prev)] * cv.y[size_t(prev)][c];
                            cv.y[size_t(q)][c] = std::max(0.0, sum / d[size_t(q)]);
                        }
                }
        for (TreeTerm& t : b->terms) normalize_curves(&t);
    }
}

}  // namespace

bool validate_tree(const ShadeTree& t, std::string* err) {
    if (angle_textures(t.param) || t.res < 4 || t.res > 128)
        return fail(err, "tree: parameterization iv, gs-half, vh or rusinkiewicz (hemisphere maps), res 4..128");
    if (t.bases.empty() || t.bases.size() > 8) return fail(err, "tree: 1..8 bases");
    if (t.blend.count != t.basis_count() || t.blend.width < 1 || t.blend.height < 1 ||
        t.blend.width > SvbrdfSamples::kMaxSide || t.blend.height > SvbrdfSamples::kMaxSide ||
        t.blend.w.size() != size_t(t.blend.width) * t.blend.height * t.blend.count)
        return fail(err, "tree: one blend map per basis, 1.." + std::to_string(SvbrdfSamples::kMaxSide) + " texels a side");
    // Weights mix basis BRDFs: a negative one would subtract a material (set_blend refuses
    // them too).
    for (size_t i = 0; i < t.blend.w.size(); ++i)
        if (!(t.blend.w[i] >= 0.0f) || !std::isfinite(t.blend.w[i])) {
            const size_t texel = i / size_t(t.blend.count);
            return fail(err, "tree: blend map " + std::to_string(i % size_t(t.blend.count)) + " at texel (" +
                                 std::to_string(texel % size_t(t.blend.width)) + ", " +
                                 std::to_string(texel / size_t(t.blend.width)) + ") has weight " +
                                 std::to_string(t.blend.w[i]) + ": weights are finite and >= 0");
        }
    for (size_t j = 0; j < t.bases.size(); ++j) {
        const TreeBasis& b = t.bases[j];
        if (b.terms.empty() || b.terms.size() > 4) return fail(err, "tree: basis " + std::to_string(j) + ": 1..4 terms");
        for (size_t k = 0; k < b.terms.size(); ++k)
            for (int i = 0; i < 4; ++i) {
                const Curve& c = b.terms[k].curve(i);
                const std::string where = "tree: curve " + std::to_string(j) + "." + std::to_string(4 * k + size_t(i)) + ": ";
                if (c.x.size() < 2 || c.x.size() > 1024 || c.y.size() != c.x.size())
                    return fail(err, where + "2..1024 knots");
                const double hi = c.periodic ? 2 * kPi : 0.5 * kPi + 1e-9;
                for (size_t q = 0; q < c.x.size(); ++q) {
                    if (!(c.x[q] >= -1e-12 && c.x[q] < hi + (c.periodic ? 0 : 1e-9)) || (q > 0 && !(c.x[q] > c.x[q - 1])))
                        return fail(err, where + "knots must increase within the curve's range");
                    for (int ch = 0; ch < 3; ++ch)
                        if (!(c.y[q][ch] >= 0) || !std::isfinite(c.y[q][ch])) return fail(err, where + "values must be finite and >= 0");
                }
                if (c.periodic != (i % 2 == 1)) return fail(err, where + "phi curves are periodic, theta curves not");
            }
    }
    return true;
}

bool build_tree(const Decomposition& d, const TreeOptions& o, ShadeTree* out, std::string* err) {
    if (!check_options(o, err)) return false;
    if (d.method == IstMethod::PCA) return fail(err, "tree: PCA's signed bases are not BRDFs; decompose with sacls, acls, nmf or kmeans");
    ShadeTree t;
    t.param = o.param;
    t.map = o.map;
    t.res = o.res;
    t.blend = d.blend();
    const int np = int(d.pairs.size());
    for (int j = 0; j < d.terms; ++j) {
        std::vector<CornellSample> samples;
        for (int p = 0; p < np; ++p) {
            const DirPair& dp = d.pairs[size_t(p)];
            CornellSample s;
            s.theta_i = theta_of(dp.wi);
            s.phi_i = std::atan2(dp.wi.y, dp.wi.x);
            s.theta_s = theta_of(dp.wo);
            s.phi_s = std::atan2(dp.wo.y, dp.wo.x);
            s.rgb = glm::max(d.basis_value(j, p), glm::dvec3(0));
            samples.push_back(s);
        }
        CornellTabulation how;
        std::copy(o.table_res, o.table_res + 3, how.res);
        how.base_lobes = 0;  // a basis material's values, not a paint: no Lafortune base under them
        Tabulated table;
        tabulate_cornell(samples, &table, how);
        const TableBrdf tb(table);
        Factored f;
        if (!factor_level2(tb, o, &f, err, &tb)) return fail(err, "tree: basis " + std::to_string(j) + ": " + *err);
        if (o.refine_iterations > 0) {
            // The table's factors, refitted to the samples themselves (scattered.h): the
            // factors' separable structure interpolates between the pairs where the table's
            // push-pull can only blur.
            std::vector<ScatteredSample> ss;
            for (int p = 0; p < np; ++p) {
                const DirPair& dp = d.pairs[size_t(p)];
                ss.push_back(ScatteredSample{dp.wi, dp.wo, glm::max(d.basis_value(j, p), glm::dvec3(0)), dp.wi.z * dp.wi.z});
            }
            ScatteredOptions so;
            so.iterations = o.refine_iterations;
            so.smoothness = o.smoothness;
            so.constant_side = level2_options(o).acls_constant ? half_angle_factor(o.param) : -1;
            if (!refine_scattered(ss, so, &f, nullptr, err)) return fail(err, "tree: basis " + std::to_string(j) + ": " + *err);
        }
        TreeBasis b;
        b.name = "basis " + std::to_string(j);
        if (!curves_from_factors(f, o.curve_samples, o.threads, &b, err)) return false;
        if (o.refine_iterations > 0) {
            std::vector<ScatteredSample> ss;
            for (int p = 0; p < np; ++p) {
                const DirPair& dp = d.pairs[size_t(p)];
                ss.push_back(ScatteredSample{dp.wi, dp.wo, glm::max(d.basis_value(j, p), glm::dvec3(0)), dp.wi.z * dp.wi.z});
            }
            refine_curves(ss, o.param, o.map, level2_options(o).acls_constant, o.refine_iterations, o.smoothness, &b);
        }
        t.bases.push_back(std::move(b));
        // Errors of each level at the pairs, against the top level's basis values.
        LevelErrors le;
        double s_tab = 0, s_fac = 0, s_cur = 0;
        for (int p = 0; p < np; ++p) {
            const DirPair& dp = d.pairs[size_t(p)];
            const glm::dvec3 v = d.basis_value(j, p);
            auto sq = [&](const glm::dvec3& x) {
                const glm::dvec3 e = (x - v) * dp.wi.z;
                return e.x * e.x + e.y * e.y + e.z * e.z;
            };
            s_tab += sq(tb.eval(dp.wi, dp.wo));
            s_fac += sq(evaluate(f, dp.wi, dp.wo));
            s_cur += sq(t.eval_basis(j, dp.wi, dp.wo));
        }
        le.tabular = std::sqrt(s_tab / (3.0 * np));
        le.factors = std::sqrt(s_fac / (3.0 * np));
        le.curves = std::sqrt(s_cur / (3.0 * np));
        t.level_errors.push_back(le);
    }
    char buf[256];
    std::snprintf(buf, sizeof buf, "%s, %d terms, top-level RMS %.4g; bases: %s %d x %d, %d terms, acls",
                  ist_method_name(d.method), d.terms, d.rms, param_name(o.param), o.res, o.res, o.terms);
    t.provenance = buf;
    *out = std::move(t);
    return true;
}

bool ShadeTree::set_curve(int basis, int curve, const Curve& c, std::string* err) {
    if (basis < 0 || basis >= basis_count() || curve < 0 || curve >= 4 * int(bases[size_t(basis)].terms.size()))
        return fail(err, "edit: no curve " + std::to_string(basis) + "." + std::to_string(curve));
    ShadeTree t = *this;
    t.bases[size_t(basis)].terms[size_t(curve / 4)].curve(curve % 4) = c;
    if (!validate_tree(t, err)) return false;
    *this = std::move(t);
    return true;
}

bool ShadeTree::set_blend(int j, const Image& img, std::string* err) {
    if (j < 0 || j >= basis_count()) return fail(err, "edit: no blend map " + std::to_string(j));
    if (img.empty()) return fail(err, "edit: empty image");
    BlendMaps one;
    one.width = img.width;
    one.height = img.height;
    one.count = 1;
    one.w.resize(size_t(img.width) * img.height);
    for (size_t i = 0; i < one.w.size(); ++i) {
        const float v = img.data[i * size_t(img.channels)];
        if (!(v >= 0) || !std::isfinite(v)) return fail(err, "edit: blend weights must be finite and >= 0");
        one.w[i] = v;
    }
    for (int y = 0; y < blend.height; ++y)
        for (int x = 0; x < blend.width; ++x)
            blend.w[(size_t(y) * blend.width + x) * blend.count + size_t(j)] =
                float(one.sample(0, (x + 0.5) / blend.width, (y + 0.5) / blend.height));
    return true;
}

bool ShadeTree::swap_basis(int j, const std::string& spec, const TreeOptions& o, std::string* err) {
    if (j < 0 || j >= basis_count()) return fail(err, "edit: no basis " + std::to_string(j));
    TreeOptions to = o;
    to.param = param;
    to.map = map;
    to.res = res;
    if (!check_options(to, err)) return false;
    std::unique_ptr<Brdf> b = make_brdf(spec, err);
    if (!b) return false;
    Factored f;
    if (!factor_level2(*b, to, &f, err)) return false;
    TreeBasis nb;
    nb.name = b->model();
    nb.source = b->spec();
    if (!curves_from_factors(f, to.curve_samples, to.threads, &nb, err)) return false;
    bases[size_t(j)] = std::move(nb);
    if (size_t(j) < level_errors.size()) level_errors[size_t(j)] = LevelErrors();
    return true;
}

namespace {
class TreeBasisBrdf : public Brdf {
  public:
    TreeBasisBrdf(const ShadeTree& t, int j) : t_(t), j_(j) {}
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override { return t_.eval_basis(j_, wi, wo); }
    std::string spec() const override { return t_.bases[size_t(j_)].source; }
    std::string model() const override { return "ist-basis"; }
    std::string info() const override { return "basis " + std::to_string(j_) + " of an inverse shade tree\n"; }
    bool isotropic() const override { return false; }

  private:
    const ShadeTree& t_;
    int j_;
};
}  // namespace

std::unique_ptr<Brdf> tree_basis_brdf(const ShadeTree& t, int j) { return std::make_unique<TreeBasisBrdf>(t, j); }

glm::dvec3 TreeSvbrdf::eval(const glm::dvec2& uv, const glm::dvec3& wi, const glm::dvec3& wo) const {
    glm::dvec3 f(0);
    for (int j = 0; j < t_.basis_count(); ++j) {
        const double w = t_.blend.sample(j, uv.x, uv.y);
        if (w != 0) f += w * t_.eval_basis(j, wi, wo);
    }
    return f;
}

// ---- files ------------------------------------------------------------------------------

bool write_curve_csv(const std::string& path, const Curve& c, const std::string& what, std::string* err) {
    std::string s = "# sepal-ist curve: " + what + "\n# degrees,r,g,b\n";
    char buf[160];
    for (size_t i = 0; i < c.x.size(); ++i) {
        std::snprintf(buf, sizeof buf, "%.9g,%.9g,%.9g,%.9g\n", c.x[i] * 180 / kPi, c.y[i].x, c.y[i].y, c.y[i].z);
        s += buf;
    }
    return write_file_atomic(path, s.data(), s.size(), err);
}

bool read_curve_csv(const std::string& path, bool periodic, Curve* out, std::string* err) {
    std::vector<uint8_t> bytes;
    if (!read_file(path, &bytes, err, 1u << 20)) return false;
    const std::string text(bytes.begin(), bytes.end());
    Curve c;
    c.periodic = periodic;
    size_t pos = 0;
    int line = 0;
    while (pos < text.size()) {
        size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        std::string l = text.substr(pos, end - pos);
        pos = end + 1;
        ++line;
        const size_t hash = l.find('#');
        if (hash != std::string::npos) l = l.substr(0, hash);
        if (l.find_first_not_of(" \t\r") == std::string::npos) continue;
        double v[4];
        char tail = 0;
        std::replace(l.begin(), l.end(), ',', ' ');
        if (std::sscanf(l.c_str(), "%lf %lf %lf %lf %c", &v[0], &v[1], &v[2], &v[3], &tail) != 4)
            return fail(err, path + ":" + std::to_string(line) + ": expected \"degrees,r,g,b\"");
        for (double x : v)
            if (!std::isfinite(x)) return fail(err, path + ":" + std::to_string(line) + ": a value is not finite");
        const double hi = periodic ? 360 : 90;
        if (v[0] < 0 || (periodic ? v[0] >= hi : v[0] > hi) || (!c.x.empty() && !(v[0] * kPi / 180 > c.x.back())))
            return fail(err, path + ":" + std::to_string(line) + ": angles must increase within [0, " +
                                 (periodic ? "360)" : "90]"));
        if (v[1] < 0 || v[2] < 0 || v[3] < 0) return fail(err, path + ":" + std::to_string(line) + ": values must be >= 0");
        c.x.push_back(v[0] * kPi / 180);
        c.y.push_back(glm::dvec3(v[1], v[2], v[3]));
        if (c.x.size() > 1024) return fail(err, path + ": more than 1024 knots");
    }
    if (c.x.size() < 2) return fail(err, path + ": a curve needs at least 2 knots");
    *out = std::move(c);
    return true;
}

namespace {
std::string curve_file(int j, int k, int i) {
    return "curves/b" + std::to_string(j) + "_t" + std::to_string(k) + "_" + kCurveNames[i] + ".csv";
}
}  // namespace

bool write_tree(const std::string& dir, const ShadeTree& t, std::string* err) {
    if (!validate_tree(t, err)) return false;
    if (!make_dirs(dir + "/blend", err) || !make_dirs(dir + "/curves", err)) return false;
    Json j = Json::object();
    j["format"] = "sepal-ist-tree";
    j["version"] = 1;
    j["param"] = param_name(t.param);
    j["map"] = map_name(t.map);
    j["res"] = t.res;
    j["provenance"] = t.provenance;
    Json& blend = j["blend"] = Json::object();
    blend["width"] = t.blend.width;
    blend["height"] = t.blend.height;
    Json& maps = blend["maps"] = Json::array();
    for (int b = 0; b < t.blend.count; ++b) {
        Image img(t.blend.width, t.blend.height, 1);
        for (int i = 0; i < t.blend.width * t.blend.height; ++i) img.data[size_t(i)] = t.blend.at(i, b);
        const std::string name = "blend/" + std::to_string(b) + ".pfm";
        if (!write_pfm(dir + "/" + name, img, err)) return false;
        maps.push_back(name);
    }
    Json& bases = j["bases"] = Json::array();
    for (int b = 0; b < t.basis_count(); ++b) {
        const TreeBasis& tb = t.bases[size_t(b)];
        Json bj = Json::object();
        bj["name"] = tb.name;
        bj["source"] = tb.source;
        if (size_t(b) < t.level_errors.size()) {
            const LevelErrors& le = t.level_errors[size_t(b)];
            Json rms = Json::object();
            rms["tabular"] = le.tabular;
            rms["factors"] = le.factors;
            rms["curves"] = le.curves;
            bj["rms"] = std::move(rms);
        }
        Json& terms = bj["terms"] = Json::array();
        for (size_t k = 0; k < tb.terms.size(); ++k) {
            Json curves = Json::array();
            for (int i = 0; i < 4; ++i) {
                const std::string name = curve_file(b, int(k), i);
                const std::string what = std::string(kCurveNames[i]) + " of basis " + std::to_string(b) + ", term " +
                                         std::to_string(k) + " (curve " + std::to_string(b) + "." +
                                         std::to_string(4 * k + size_t(i)) + ")";
                if (!write_curve_csv(dir + "/" + name, tb.terms[k].curve(i), what, err)) return false;
                curves.push_back(name);
            }
            Json term = Json::object();
            term["curves"] = std::move(curves);
            terms.push_back(std::move(term));
        }
        bases.push_back(std::move(bj));
    }
    return write_json_file(dir + "/tree.json", j, err);
}

bool read_tree(const std::string& dir, ShadeTree* out, std::string* err) {
    const std::string path = dir + "/tree.json";
    Json root;
    if (!read_json_file(path, &root, err, 1u << 20)) return false;
    const JsonField top{root, path};
    std::string s, why;
    int version = 0;
    if (!json_string(top, "format", &s, &why, true) || s != "sepal-ist-tree" ||
        !json_int(top, "version", 1, 1, &version, &why, true))
        return fail(err, path + ": not a sepal-ist-tree file of version 1");
    ShadeTree t;
    std::string pname, mname;
    if (!json_string(top, "param", &pname, err, true) || !json_string(top, "map", &mname, err, true) ||
        !json_int(top, "res", 4, 128, &t.res, err, true) || !json_string(top, "provenance", &t.provenance, err))
        return false;
    if (!parse_param(pname, &t.param)) return fail(err, path + ".param: unknown parameterization \"" + pname + "\"");
    if (!parse_map(mname, &t.map)) return fail(err, path + ".map: unknown map \"" + mname + "\"");
    const Json* bases = nullptr;
    const Json* maps = nullptr;
    if (!json_array(top, "bases", 1, 8, &bases, err, true)) return false;
    static const Json kAbsent;  // "expected an object, got null" when "blend" is missing
    const JsonField blend{root.contains("blend") ? root.at("blend") : kAbsent, path + ".blend"};
    if (!json_int(blend, "width", 1, SvbrdfSamples::kMaxSide, &t.blend.width, err, true) ||
        !json_int(blend, "height", 1, SvbrdfSamples::kMaxSide, &t.blend.height, err, true) ||
        !json_array(blend, "maps", bases->size(), bases->size(), &maps, err, true))
        return false;
    t.blend.count = int(maps->size());
    t.blend.w.assign(size_t(t.blend.width) * t.blend.height * t.blend.count, 0.0f);
    for (int b = 0; b < t.blend.count; ++b) {
        const Json& m = (*maps)[size_t(b)];
        if (!m.is_string()) return fail(err, path + ".blend.maps[" + std::to_string(b) + "]: expected a path, got " + json_kind(m));
        const std::string img_path = dir + "/" + m.get<std::string>();
        Image img;
        if (!read_image(img_path, &img, err)) return false;
        if (img.width != t.blend.width || img.height != t.blend.height)
            return fail(err, img_path + ": not " + std::to_string(t.blend.width) + "x" + std::to_string(t.blend.height));
        for (int i = 0; i < t.blend.width * t.blend.height; ++i)
            t.blend.w[size_t(i) * t.blend.count + size_t(b)] = img.data[size_t(i) * size_t(img.channels)];
    }
    for (size_t b = 0; b < bases->size(); ++b) {
        const JsonField e{(*bases)[b], path + ": bases[" + std::to_string(b) + "]"};
        TreeBasis tb;
        const Json* terms = nullptr;
        if (!json_string(e, "name", &tb.name, err, true) || !json_string(e, "source", &tb.source, err, true) ||
            !json_array(e, "terms", 1, 4, &terms, err, true))
            return false;
        for (size_t k = 0; k < terms->size(); ++k) {
            const JsonField te{(*terms)[k], e.where + ".terms[" + std::to_string(k) + "]"};
            const Json* curves = nullptr;
            if (!json_array(te, "curves", 4, 4, &curves, err, true)) return false;
            TreeTerm tt;
            for (int i = 0; i < 4; ++i) {
                const Json& c = (*curves)[size_t(i)];
                if (!c.is_string()) return fail(err, te.where + ".curves[" + std::to_string(i) + "]: expected a path, got " + json_kind(c));
                if (!read_curve_csv(dir + "/" + c.get<std::string>(), i % 2 == 1, &tt.curve(i), err)) return false;
            }
            tb.terms.push_back(std::move(tt));
        }
        t.bases.push_back(std::move(tb));
    }
    if (!validate_tree(t, err)) return fail(err, path + ": " + *err);
    *out = std::move(t);
    return true;
}

}  // namespace sepal
