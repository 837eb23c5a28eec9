#include "fit/lafortune_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>
#include <Eigen/Dense>

#include "brdf/brdf_models.h"
#include "brdf/brdf_spec.h"
#include "brdf/brdf_util.h"

namespace sepal {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Lobe values and their derivatives are capped here: a trial step of the solver to a huge
// exponent must give a huge residual, not inf or NaN.
constexpr double kValueCap = 1e150;

int lobe_params(bool isotropic) { return isotropic ? 3 : 4; }

double capped(double v) { return std::isfinite(v) ? std::min(v, kValueCap) : kValueCap; }

// The per-sample products the lobes need (x_i x_o, y_i y_o, z_i z_o).
struct Products {
    double xx, yy, zz;
};

Products products(const glm::dvec3& wi, const glm::dvec3& wo) {
    return {wi.x * wo.x, wi.y * wo.y, wi.z * wo.z};
}

double lobe_value(const LafortuneLobe& l, const Products& p) {
    const double d = l.cx * p.xx + l.cy * p.yy + l.cz * p.zz;
    return d > 0 ? capped(std::pow(d, l.n)) : 0.0;
}

// Adds d(lobe)/d(its parameters) to grad[0..]: (Cxy, Cz, n) or (Cx, Cy, Cz, n).
void lobe_gradient(const LafortuneLobe& l, const Products& p, bool isotropic, double scale, double* grad) {
    const double d = l.cx * p.xx + l.cy * p.yy + l.cz * p.zz;
    const int np = lobe_params(isotropic);
    if (!(d > 1e-300)) {
        for (int i = 0; i < np; ++i) grad[i] = 0;
        return;
    }
    const double v = capped(std::pow(d, l.n));
    const double dv = capped(l.n * v / d) * scale;  // n d^(n-1)
    int i = 0;
    if (isotropic) {
        grad[i++] = dv * (p.xx + p.yy);
    } else {
        grad[i++] = dv * p.xx;
        grad[i++] = dv * p.yy;
    }
    grad[i++] = dv * p.zz;
    grad[i] = capped(v * std::log(d)) * scale;
    if (!std::isfinite(grad[i])) grad[i] = -kValueCap;
}

struct Problem {
    std::vector<Products> prod;
    std::vector<double> weight;
    std::vector<double> value;  // channels per sample
    int channels = 3, lobes = 1;
    bool isotropic = true;
    bool forward = false;  // LafortuneFitOptions::forward: x kept inside its bounds
    int params() const { return channels + lobes * lobe_params(isotropic); }
    int samples() const { return int(weight.size()); }
};

// LafortuneFitOptions::forward's bounds on parameter j: rho_d >= 0, Cx, Cy <= 0, Cz >= 0,
// n >= 1 (-inf / +inf where a side is free).
void bounds(const Problem& pb, int j, double* lo, double* hi) {
    *lo = -kInf;
    *hi = kInf;
    const int C = pb.channels, np = lobe_params(pb.isotropic);
    if (j < C) {
        *lo = 0;
        return;
    }
    const int i = (j - C) % np;
    if (i < np - 2) *hi = 0;
    else if (i == np - 2) *lo = 0;
    else *lo = 1;
}

// Clamps x into the bounds (no-op without them).
void project(const Problem& pb, Eigen::VectorXd* x) {
    if (!pb.forward) return;
    for (int j = 0; j < pb.params(); ++j) {
        double lo, hi;
        bounds(pb, j, &lo, &hi);
        (*x)[j] = std::min(hi, std::max(lo, (*x)[j]));
    }
}

// The weighted residuals of a parameter vector.
void residuals(const Problem& pb, const Eigen::VectorXd& x, Eigen::VectorXd* r) {
    const LafortuneModel m = lafortune_from_params(x, pb.channels, pb.lobes, pb.isotropic);
    const int C = pb.channels;
    for (int s = 0; s < pb.samples(); ++s) {
        double lobe = 0;
        for (const LafortuneLobe& l : m.lobes) lobe += lobe_value(l, pb.prod[size_t(s)]);
        for (int c = 0; c < C; ++c) {
            const double f = m.rho_d[c] / kPi + lobe;
            (*r)[s * C + c] = capped(pb.weight[size_t(s)] * (f - pb.value[size_t(s) * C + c]));
        }
    }
}

void jacobian(const Problem& pb, const Eigen::VectorXd& x, Eigen::MatrixXd* J) {
    const LafortuneModel m = lafortune_from_params(x, pb.channels, pb.lobes, pb.isotropic);
    const int C = pb.channels, np = lobe_params(pb.isotropic);
    J->setZero(pb.samples() * C, pb.params());
    double g[4];
    for (int s = 0; s < pb.samples(); ++s) {
        const double w = pb.weight[size_t(s)];
        for (int c = 0; c < C; ++c) (*J)(s * C + c, c) = w / kPi;
        for (int k = 0; k < pb.lobes; ++k) {
            lobe_gradient(m.lobes[size_t(k)], pb.prod[size_t(s)], pb.isotropic, w, g);
            for (int c = 0; c < C; ++c)
                for (int i = 0; i < np; ++i) (*J)(s * C + c, C + k * np + i) = g[i];
        }
    }
}

// Levenberg-Marquardt on the normal equations: Marquardt's scaling (the damping is mu times
// the diagonal of J^T J, so parameters of any unit, exponents in the hundreds beside albedos
// below 1, are damped alike) and Nielsen's update of mu (Madsen, Nielsen and Tingleff 2004,
// "Methods for non-linear least squares problems", algorithm 3.16). Written here rather than
// taken from Eigen's MINPACK port (unsupported/NonLinearOptimization): at
// these sizes (3 residuals per sample, 4-19 parameters, thousands of per-texel fits in an
// acquisition session) its QR with column pivoting, blueNorm column norms and per-iteration
// allocations took about 30% of sepal-bench-acquire (perf) against 17% for the model itself,
// while the p x p normal equations cost next to nothing. It stops as MINPACK does by default:
// a relative cost reduction or a relative (scaled) step below sqrt(eps), or the evaluation
// budget. Returns an LmStop.
int minimize_lm(const Problem& pb, Eigen::VectorXd* x, int max_evaluations, int* evaluations) {
    const int m = pb.samples() * pb.channels, p = pb.params();
    const double tol = std::sqrt(std::numeric_limits<double>::epsilon());
    Eigen::VectorXd r(m), r_try(m), x_try(p), g(p), delta(p), scale(p);
    Eigen::MatrixXd J(m, p), A(p, p), Ad(p, p);
    residuals(pb, *x, &r);
    ++*evaluations;
    int used = 1;
    double cost = r.squaredNorm();
    if (!std::isfinite(cost)) return kLmStuck;
    double mu = 1e-3, nu = 2;
    while (true) {
        jacobian(pb, *x, &J);
        A.noalias() = J.transpose() * J;
        g.noalias() = J.transpose() * r;
        if (!A.allFinite() || !g.allFinite()) return kLmStuck;
        if (g.lpNorm<Eigen::Infinity>() == 0.0) return kLmGradient;
        // A parameter no sample reaches (a zero column) keeps a tiny damping, so the
        // system stays solvable and its step 0.
        const double dmax = A.diagonal().maxCoeff();
        for (int j = 0; j < p; ++j) scale[j] = std::max(A(j, j), 1e-12 * dmax);
        while (true) {
            if (used >= max_evaluations) return kLmBudget;
            Ad = A;
            Ad.diagonal() += mu * scale;
            delta = Ad.ldlt().solve(-g);
            if (!delta.allFinite()) return kLmStuck;
            x_try = *x + delta;
            project(pb, &x_try);
            // A projected step is the step taken: the model's predicted reduction is its own.
            if (pb.forward) delta = x_try - *x;
            const double step = delta.cwiseProduct(scale.cwiseSqrt()).norm();
            const double size = x->cwiseProduct(scale.cwiseSqrt()).norm();
            if (step <= tol * size) return kLmStep;
            residuals(pb, x_try, &r_try);
            ++*evaluations;
            ++used;
            const double cost_try = r_try.squaredNorm();
            const double predicted = -(2.0 * delta.dot(g) + delta.dot(A * delta));
            const double gain = std::isfinite(cost_try) && predicted > 0 ? (cost - cost_try) / predicted : -1.0;
            if (gain > 0) {
                const double drop = cost - cost_try;
                *x = x_try;
                r.swap(r_try);
                const double before = cost;
                cost = cost_try;
                mu *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * gain - 1.0, 3));
                nu = 2;
                if (drop <= tol * before && predicted <= tol * before) return kLmCost;
                break;
            }
            mu *= nu;
            nu *= 2;
            if (!(mu < 1e200)) return kLmStuck;
        }
    }
}

double rss_of(const Problem& pb, const Eigen::VectorXd& x) {
    Eigen::VectorXd r(pb.samples() * pb.channels);
    residuals(pb, x, &r);
    return r.squaredNorm();
}

// Greedy grid start: for each new lobe, shapes Cxy/Cz = ratio and exponents n on a grid with
// the diffuse values and the lobe's scale W = Cz^n by linear least squares (the earlier
// lobes fixed). Returns the candidates for the first lobe ranked by their residual (the
// later lobes chosen greedily on the best one).
std::vector<Eigen::VectorXd> grid_starts(const Problem& pb, int keep) {
    static const double kRatios[] = {-1.2, -1.0, -0.8, 0.0, 1.0};
    static const double kExponents[] = {1, 3, 10, 30, 100, 300};
    const int C = pb.channels, S = pb.samples(), np = lobe_params(pb.isotropic);
    struct Cand {
        double sse;
        LafortuneModel m;
    };
    std::vector<Cand> firsts;
    LafortuneModel base;
    base.rho_d = glm::dvec3(0);
    std::vector<double> fixed(static_cast<size_t>(S), 0.0);  // earlier lobes' sum per sample
    std::vector<double> g(static_cast<size_t>(S), 0.0);
    for (int k = 0; k < pb.lobes; ++k) {
        std::vector<Cand> cands;
        for (double ratio : kRatios)
            for (double n : kExponents) {
                bool any = false;
                if (pb.forward && ratio > 0) continue;  // a retro lobe
                for (int s = 0; s < S; ++s) {
                    const Products& p = pb.prod[size_t(s)];
                    const double d = ratio * (p.xx + p.yy) + p.zz;
                    g[size_t(s)] = d > 0 ? std::pow(d, n) : 0.0;
                    any = any || g[size_t(s)] > 0;
                }
                if (!any) continue;
                // Unknowns: rho_c / pi (C of them) and W; weighted normal equations.
                Eigen::MatrixXd A = Eigen::MatrixXd::Zero(C + 1, C + 1);
                Eigen::VectorXd b = Eigen::VectorXd::Zero(C + 1);
                for (int s = 0; s < S; ++s) {
                    const double w2 = pb.weight[size_t(s)] * pb.weight[size_t(s)];
                    const double gs = g[size_t(s)];
                    for (int c = 0; c < C; ++c) {
                        const double y = pb.value[size_t(s) * C + c] - fixed[size_t(s)];
                        A(c, c) += w2;
                        A(c, C) += w2 * gs;
                        A(C, C) += w2 * gs * gs;
                        b[c] += w2 * y;
                        b[C] += w2 * gs * y;
                    }
                }
                for (int c = 0; c < C; ++c) A(C, c) = A(c, C);
                const Eigen::VectorXd sol = A.ldlt().solve(b);
                if (!sol.allFinite() || !(sol[C] > 0)) continue;
                Cand cand;
                cand.m = base;
                for (int c = 0; c < C; ++c) cand.m.rho_d[c] = std::max(0.0, sol[c]) * kPi;
                if (C == 1) cand.m.rho_d = glm::dvec3(cand.m.rho_d.x);
                const double cz = std::pow(sol[C], 1.0 / n);
                cand.m.lobes.push_back({ratio * cz, ratio * cz, cz, n});
                cand.sse = 0;
                for (int s = 0; s < S; ++s)
                    for (int c = 0; c < C; ++c) {
                        const double e = pb.weight[size_t(s)] *
                                         (cand.m.rho_d[c] / kPi + fixed[size_t(s)] + sol[C] * g[size_t(s)] -
                                          pb.value[size_t(s) * C + c]);
                        cand.sse += e * e;
                    }
                cands.push_back(cand);
            }
        if (cands.empty()) {  // no sample reaches any lobe shape: a default, flat lobe
            Cand c;
            c.m = base;
            c.m.lobes.push_back({-0.5, -0.5, 0.5, 10});
            c.sse = kInf;
            cands.push_back(c);
        }
        std::stable_sort(cands.begin(), cands.end(), [](const Cand& a, const Cand& b) { return a.sse < b.sse; });
        if (k == 0) firsts = cands;
        base = cands[0].m;
        for (int s = 0; s < S; ++s) fixed[size_t(s)] += lobe_value(base.lobes.back(), pb.prod[size_t(s)]);
    }
    (void)np;
    std::vector<Eigen::VectorXd> out;
    // The best greedy model first, then other first-lobe shapes with the later lobes of the
    // greedy model (multi-start against the local minima of sharp lobes).
    out.push_back(lafortune_params(base, C, pb.isotropic));
    for (size_t i = 1; i < firsts.size() && int(out.size()) < keep; ++i) {
        LafortuneModel m = base;
        m.rho_d = firsts[i].m.rho_d;
        m.lobes[0] = firsts[i].m.lobes[0];
        out.push_back(lafortune_params(m, C, pb.isotropic));
    }
    return out;
}

}  // namespace

double LafortuneModel::lobe_sum(const glm::dvec3& wi, const glm::dvec3& wo) const {
    const Products p = products(wi, wo);
    double s = 0;
    for (const LafortuneLobe& l : lobes) s += lobe_value(l, p);
    return s;
}

glm::dvec3 LafortuneModel::eval(const glm::dvec3& wi, const glm::dvec3& wo) const {
    if (wi.z <= 0 || wo.z <= 0) return glm::dvec3(0.0);
    const Products p = products(wi, wo);
    glm::dvec3 f = rho_d / kPi;
    for (const LafortuneLobe& l : lobes) f += l.colour * lobe_value(l, p);
    return f;
}

bool tint_lafortune_lobes(const std::vector<BrdfSample>& samples, LafortuneModel* model) {
    LafortuneModel white = *model;
    for (LafortuneLobe& l : white.lobes) l.colour = glm::dvec3(1.0);
    // The diffuse term is held: where the lobe is wide it is nearly collinear with it, and a
    // joint fit trades the body colour into the lobe.
    double a = 0;
    glm::dvec3 b(0.0);
    for (const BrdfSample& s : samples) {
        if (!(s.weight > 0) || s.wi.z <= 0 || s.wo.z <= 0) continue;
        const double w2 = s.weight * s.weight, L = white.lobe_sum(s.wi, s.wo);
        a += w2 * L * L;
        b += w2 * L * (s.value - model->rho_d / kPi);
    }
    if (!(a > 0) || !std::isfinite(a)) return false;
    const glm::dvec3 t = glm::max(b / a, glm::dvec3(0.0));
    for (LafortuneLobe& l : model->lobes) l.colour = t;
    return true;
}

std::string LafortuneModel::spec(bool* clamped) const {
    bool c = false;
    auto clamp = [&](double v, double lo, double hi) {
        const double r = std::min(hi, std::max(lo, v));
        if (r != v) c = true;
        return r;
    };
    const glm::dvec3 rho(clamp(rho_d.x, 0, 1), clamp(rho_d.y, 0, 1), clamp(rho_d.z, 0, 1));
    std::string s = "lafortune:rho_d=" + format_colour(rho);
    for (const LafortuneLobe& l : lobes) {
        const double cx = clamp(l.cx, -100, 100), cy = clamp(l.cy, -100, 100), cz = clamp(l.cz, -100, 100);
        double n = clamp(l.n, 0, 1e6);
        // The spec refuses max|C|^n > 1e200 (overflow): lower n to the bound.
        const double cmax = std::max({std::fabs(cx), std::fabs(cy), std::fabs(cz)});
        if (cmax > 1 && n * std::log10(cmax) > 200) {
            n = 200 / std::log10(cmax);
            c = true;
        }
        s += ",lobe=" + format_number(cx) + "/" + format_number(cy) + "/" + format_number(cz) + "/" +
             format_number(n);
        if (l.colour != glm::dvec3(1.0)) {
            const glm::dvec3 w(clamp(l.colour.x, 0, 1000), clamp(l.colour.y, 0, 1000), clamp(l.colour.z, 0, 1000));
            s += "/" + format_number(w.x) + "/" + format_number(w.y) + "/" + format_number(w.z);
        }
    }
    if (clamped) *clamped = c;
    return s;
}

bool lafortune_plausible(const LafortuneModel& m, double* albedo) {
    bool clamped = false;
    std::unique_ptr<Brdf> b = make_analytic_brdf(m.spec(&clamped), nullptr);
    double most = b ? 0.0 : std::numeric_limits<double>::infinity();
    // 32 samples: the quadrature's panels are graded towards the mirror direction
    // (brdf_util.h), and a bound of 1.1 needs percent accuracy, not more; the angles reach the
    // grazing incidence where misfitted lobes put their energy.
    bool anisotropic = false;  // then the incidence azimuth matters: along x and along y
    for (const LafortuneLobe& l : m.lobes) anisotropic = anisotropic || l.cx != l.cy;
    if (b)
        for (double phi : {0.0, kPi / 2}) {
            for (double deg : {0.0, 20.0, 40.0, 60.0, 75.0, 85.0, 89.0}) {
                const glm::dvec3 a = directional_albedo(*b, deg2rad(deg), 32, phi);
                most = std::max({most, a.x, a.y, a.z});
            }
            if (!anisotropic) break;
        }
    if (albedo) *albedo = most;
    // 1.1, not 1: fits to noisy samples of a conserving material, and Lafortune lobes that
    // peak a little above 1, exceed it by a few percent; the misfits this is for exceed it by
    // orders of magnitude (1e6 for a grazing lobe of the acquisition bench's gold paint).
    return b && !clamped && most <= kPlausibleAlbedo;
}

Eigen::VectorXd lafortune_params(const LafortuneModel& m, int channels, bool isotropic) {
    const int np = lobe_params(isotropic);
    Eigen::VectorXd p(channels + int(m.lobes.size()) * np);
    for (int c = 0; c < channels; ++c) p[c] = m.rho_d[c];
    for (size_t k = 0; k < m.lobes.size(); ++k) {
        const LafortuneLobe& l = m.lobes[k];
        int i = channels + int(k) * np;
        if (isotropic) {
            p[i++] = l.cx;
        } else {
            p[i++] = l.cx;
            p[i++] = l.cy;
        }
        p[i++] = l.cz;
        p[i] = l.n;
    }
    return p;
}

LafortuneModel lafortune_from_params(const Eigen::VectorXd& p, int channels, int lobes, bool isotropic) {
    LafortuneModel m;
    const int np = lobe_params(isotropic);
    m.rho_d = channels == 1 ? glm::dvec3(p[0]) : glm::dvec3(p[0], p[1], p[2]);
    m.lobes.resize(size_t(lobes));
    for (int k = 0; k < lobes; ++k) {
        LafortuneLobe& l = m.lobes[size_t(k)];
        int i = channels + k * np;
        l.cx = p[i++];
        l.cy = isotropic ? l.cx : p[i++];
        l.cz = p[i++];
        l.n = p[i];
    }
    return m;
}

std::vector<std::string> lafortune_param_names(int channels, int lobes, bool isotropic) {
    std::vector<std::string> names;
    if (channels == 1) {
        names.push_back("rho_d");
    } else {
        for (const char* c : {"rho_d.r", "rho_d.g", "rho_d.b"}) names.push_back(c);
    }
    for (int k = 0; k < lobes; ++k) {
        const std::string l = "lobe" + std::to_string(k + 1) + ".";
        if (isotropic) {
            names.push_back(l + "Cxy");
        } else {
            names.push_back(l + "Cx");
            names.push_back(l + "Cy");
        }
        names.push_back(l + "Cz");
        names.push_back(l + "n");
    }
    return names;
}

void lafortune_gradient_grey_iso(const LafortuneModel& m, const glm::dvec3& wi, const glm::dvec3& wo,
                                 double* grad) {
    grad[0] = 1.0 / kPi;
    const Products p = products(wi, wo);
    for (size_t k = 0; k < m.lobes.size(); ++k) lobe_gradient(m.lobes[k], p, true, 1.0, grad + 1 + 3 * k);
}

double LafortuneFit::ci95(int j) const {
    const double v = cov(j, j);
    return std::isfinite(v) ? 1.959963984540054 * std::sqrt(std::max(0.0, v)) : kInf;
}

bool fit_lafortune(const std::vector<BrdfSample>& samples, const LafortuneFitOptions& o, LafortuneFit* out,
                   std::string* err) {
    auto fail = [&](const std::string& why) {
        if (err) *err = "fit lafortune: " + why;
        return false;
    };
    if (o.lobes < 1 || o.lobes > 4) return fail("lobes must be 1..4");
    if (o.channels != 1 && o.channels != 3) return fail("channels must be 1 or 3");
    if (!(o.sigma < 0 || (o.sigma > 0 && std::isfinite(o.sigma)))) return fail("sigma must be finite and > 0");
    if (o.start && int(o.start->lobes.size()) != o.lobes) return fail("start model has the wrong lobe count");
    Problem pb;
    pb.channels = o.channels;
    pb.lobes = o.lobes;
    pb.isotropic = o.isotropic;
    pb.forward = o.forward;
    for (size_t i = 0; i < samples.size(); ++i) {
        const BrdfSample& s = samples[i];
        const bool finite = std::isfinite(s.wi.x + s.wi.y + s.wi.z + s.wo.x + s.wo.y + s.wo.z) &&
                            std::isfinite(s.value.x + s.value.y + s.value.z) && std::isfinite(s.weight);
        if (!finite) return fail("sample " + std::to_string(i) + " is not finite");
        if (s.weight < 0) return fail("sample " + std::to_string(i) + " has a negative weight");
        if (s.weight == 0) continue;
        const double li = glm::dot(s.wi, s.wi), lo = glm::dot(s.wo, s.wo);
        if (!(li > 1e-12 && lo > 1e-12)) return fail("sample " + std::to_string(i) + " has a zero direction");
        const glm::dvec3 wi = s.wi / std::sqrt(li), wo = s.wo / std::sqrt(lo);
        if (wi.z <= 0 || wo.z <= 0)
            return fail("sample " + std::to_string(i) + " has a direction at or below the horizon (z <= 0)");
        pb.prod.push_back(products(wi, wo));
        pb.weight.push_back(s.weight);
        if (o.channels == 1) {
            pb.value.push_back(luminance(s.value));
        } else {
            for (int c = 0; c < 3; ++c) pb.value.push_back(s.value[c]);
        }
    }
    const int p = pb.params(), m = pb.samples() * pb.channels;
    if (m <= p)
        return fail(std::to_string(pb.samples()) + " samples with positive weight give " + std::to_string(m) +
                    " residuals; " + std::to_string(p) + " parameters need more");

    // Starts: the caller's model, or the grid's best few.
    std::vector<Eigen::VectorXd> starts;
    if (o.start) {
        starts.push_back(lafortune_params(*o.start, o.channels, o.isotropic));
    } else {
        starts = grid_starts(pb, 3);
        if (!o.isotropic)  // the grid's lobes are isotropic; anisotropic layouts start equal
            for (Eigen::VectorXd& s : starts)
                s = lafortune_params(lafortune_from_params(s, o.channels, o.lobes, true), o.channels, false);
    }
    int evaluations = 0;
    Eigen::VectorXd best;
    double best_rss = kInf;
    int best_status = 0;
    for (const Eigen::VectorXd& x0 : starts) {
        Eigen::VectorXd x = x0;
        project(pb, &x);
        const int status = minimize_lm(pb, &x, o.max_evaluations, &evaluations);
        const double r = x.allFinite() ? rss_of(pb, x) : kInf;
        if (r < best_rss) {
            best_rss = r;
            best = x;
            best_status = status;
        }
    }
    if (!(best_rss < kInf)) return fail("the solver found no finite solution");

    LafortuneFit r;
    r.params = best;
    r.model = lafortune_from_params(best, o.channels, o.lobes, o.isotropic);
    r.names = lafortune_param_names(o.channels, o.lobes, o.isotropic);
    r.samples = pb.samples();
    r.residuals = m;
    r.rss = best_rss;
    r.evaluations = evaluations;
    r.lm_status = best_status;
    {
        double sq = 0;
        Eigen::VectorXd res(m);
        residuals(pb, best, &res);
        for (int s = 0; s < pb.samples(); ++s)
            for (int c = 0; c < pb.channels; ++c) {
                const double e = res[s * pb.channels + c] / pb.weight[size_t(s)];
                sq += e * e;
            }
        r.rms = std::sqrt(sq / m);
    }
    r.sigma = o.sigma > 0 ? o.sigma : std::sqrt(best_rss / double(m - p));

    // Covariance from the scaled Jacobian's SVD (see the header).
    Eigen::MatrixXd J;
    jacobian(pb, best, &J);
    // Columns scaled to unit norm (rank is then about directions, not units); an all-zero
    // column (a lobe no sample reaches) stays zero: unmeasured.
    Eigen::VectorXd scale(p);
    for (int j = 0; j < p; ++j) {
        const double n = J.col(j).norm();
        scale[j] = n > 1e-300 ? 1.0 / n : 0.0;
    }
    const Eigen::MatrixXd Js = J * scale.asDiagonal();
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(Js, Eigen::ComputeThinV);
    const Eigen::VectorXd& sv = svd.singularValues();
    int rank = 0;
    for (int i = 0; i < sv.size(); ++i)
        if (sv[i] > kRankTolerance * sv[0] && sv[i] > 0) ++rank;
    r.rank = rank;
    const Eigen::MatrixXd& V = svd.matrixV();
    Eigen::MatrixXd cs = Eigen::MatrixXd::Zero(p, p);
    for (int i = 0; i < rank; ++i) cs += V.col(i) * V.col(i).transpose() / (sv[i] * sv[i]);
    r.cov = r.sigma * r.sigma * (scale.asDiagonal() * cs * scale.asDiagonal());
    for (int i = rank; i < p; ++i)
        for (int j = 0; j < p; ++j)
            if (std::fabs(V(j, i)) > 1e-3) r.cov(j, j) = kInf;
    for (int j = 0; j < p; ++j)
        if (scale[j] == 0) r.cov(j, j) = kInf;
    r.model.spec(&r.clamped);
    *out = std::move(r);
    return true;
}

}  // namespace sepal
