#include "offline/sampling/chi2.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "util/parallel.h"

namespace sepal_test {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Regularized lower incomplete gamma P(a, x): series for x < a + 1, else continued fraction.
double gamma_p(double a, double x) {
    if (x <= 0) return 0.0;
    const double lg = std::lgamma(a);
    if (x < a + 1) {
        double sum = 1.0 / a, term = sum;
        for (int n = 1; n < 10000; ++n) {
            term *= x / (a + n);
            sum += term;
            if (std::fabs(term) < std::fabs(sum) * 1e-15) break;
        }
        return sum * std::exp(-x + a * std::log(x) - lg);
    }
    // Lentz's method for the continued fraction of Q(a, x).
    double b = x + 1 - a, c = 1e300, d = 1 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        const double an = -i * (i - a);
        b += 2;
        d = an * d + b;
        if (std::fabs(d) < 1e-300) d = 1e-300;
        c = b + an / c;
        if (std::fabs(c) < 1e-300) c = 1e-300;
        d = 1 / d;
        const double del = d * c;
        h *= del;
        if (std::fabs(del - 1) < 1e-15) break;
    }
    return 1.0 - std::exp(-x + a * std::log(x) - lg) * h;
}

double simpson(const std::function<double(double)>& f, double a, double b, double fa, double fm, double fb,
               double whole, double eps, int depth) {
    const double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
    const double flm = f(lm), frm = f(rm);
    const double left = (m - a) / 6 * (fa + 4 * flm + fm), right = (b - m) / 6 * (fm + 4 * frm + fb);
    const double both = left + right;
    if (depth <= 0 || std::fabs(both - whole) <= 15 * eps) return both + (both - whole) / 15;
    return simpson(f, a, m, fa, flm, fm, left, eps / 2, depth - 1) +
           simpson(f, m, b, fm, frm, fb, right, eps / 2, depth - 1);
}

// Adaptive Simpson on `panels` equal panels: the fixed first split keeps the error estimate
// from being fooled by a step of a piecewise-constant pdf that the first points all miss.
double integrate(const std::function<double(double)>& f, double a, double b, double eps, int depth, int panels) {
    double sum = 0;
    for (int k = 0; k < panels; ++k) {
        const double lo = a + (b - a) * k / panels, hi = a + (b - a) * (k + 1) / panels;
        const double fa = f(lo), fb = f(hi), fm = f(0.5 * (lo + hi));
        sum += simpson(f, lo, hi, fa, fm, fb, (hi - lo) / 6 * (fa + 4 * fm + fb), eps / panels, depth);
    }
    return sum;
}

}  // namespace

double chi2_cdf(double x, int dof) {
    if (dof < 1 || x <= 0) return 0.0;
    return gamma_p(0.5 * dof, 0.5 * x);
}

Chi2Result chi2_test(const std::function<bool(int, glm::dvec3*)>& sample,
                     const std::function<double(const glm::dvec3&)>& pdf, int samples, int tests,
                     double significance, int theta_res, int phi_res) {
    Chi2Result r;
    // theta_res x phi_res cells over the upper hemisphere, and one cell for every draw at or
    // below the horizon (the estimator's zeros): its expected count is what the pdf leaves
    // to the lower hemisphere. Half-vector samplers have an integrable singularity there
    // (wi -> -wo as wo.h -> 0), which no quadrature resolves; the upper hemisphere has none.
    const int cells = theta_res * phi_res + 1, below = cells - 1;
    // Observed: chunks of samples in parallel, summed in chunk order.
    const int chunk = 1 << 16, chunks = (samples + chunk - 1) / chunk;
    std::vector<std::vector<double>> part(static_cast<size_t>(chunks), std::vector<double>(static_cast<size_t>(cells), 0.0));
    sepal::parallel_for(size_t(chunks), 0, [&](size_t c) {
        const int end = std::min(samples, int(c + 1) * chunk);
        for (int i = int(c) * chunk; i < end; ++i) {
            glm::dvec3 w;
            if (!sample(i, &w)) continue;
            if (!(w.z > 0)) {
                part[c][size_t(below)] += 1;
                continue;
            }
            const double theta = std::acos(std::max(-1.0, std::min(1.0, w.z)));
            double phi = std::atan2(w.y, w.x);
            if (phi < 0) phi += 2 * kPi;
            const int ti = std::min(theta_res - 1, std::max(0, int(theta / (0.5 * kPi) * theta_res)));
            const int pi = std::min(phi_res - 1, std::max(0, int(phi / (2 * kPi) * phi_res)));
            part[c][size_t(ti * phi_res + pi)] += 1;
        }
    });
    std::vector<double> observed(static_cast<size_t>(cells), 0.0), expected(static_cast<size_t>(cells), 0.0);
    for (const auto& p : part)
        for (int k = 0; k < cells; ++k) observed[size_t(k)] += p[size_t(k)];
    // Expected: the pdf integrated over each cell, in parallel per cell.
    sepal::parallel_for(size_t(below), 0, [&](size_t k) {
        const int ti = int(k) / phi_res, pi = int(k) % phi_res;
        const double t0 = ti * 0.5 * kPi / theta_res, t1 = (ti + 1) * 0.5 * kPi / theta_res;
        const double p0 = pi * 2 * kPi / phi_res, p1 = (pi + 1) * 2 * kPi / phi_res;
        // The accuracy a cell needs: its count's error well below the count's standard
        // deviation, sqrt(N m) for mass m, so eps = 0.01 sqrt(m / N) in mass (from a coarse
        // first pass); deep refinement is spent only where a large cell needs it.
        auto cell = [&](double eps, int depth) {
            auto inner = [&](double theta) {
                const double st = std::sin(theta), ct = std::cos(theta);
                return integrate(
                    [&](double phi) { return pdf(glm::dvec3(st * std::cos(phi), st * std::sin(phi), ct)) * st; },
                    p0, p1, eps / (t1 - t0), depth, 8);
            };
            return integrate(inner, t0, t1, eps, depth, 8);
        };
        const double coarse = cell(1.0, 0);
        expected[k] = cell(0.01 * std::sqrt(std::max(coarse, 1e-12) / samples), 10) * samples;
    });
    double upper = 0;
    for (int k = 0; k < below; ++k) upper += expected[size_t(k)];
    expected[size_t(below)] = std::max(0.0, samples - upper);
    r.pdf_upper = upper / samples;
    r.pdf_integral = r.pdf_upper + observed[size_t(below)] / samples;
    // Pool cells expecting < 5 (in order of expected count), as pbrt does.
    std::vector<int> order(static_cast<size_t>(cells));
    for (int k = 0; k < cells; ++k) order[size_t(k)] = k;
    std::sort(order.begin(), order.end(), [&](int a, int b) { return expected[size_t(a)] < expected[size_t(b)]; });
    double pooled_o = 0, pooled_e = 0, chsq = 0;
    int dof = 0;
    for (int k : order) {
        const double o = observed[size_t(k)], e = expected[size_t(k)];
        if (e == 0) {
            if (o > samples * 1e-5) {
                char m[160];
                std::snprintf(m, sizeof m, "%.0f samples in a cell the pdf says is empty", o);
                r.message = m;
                return r;
            }
        } else if (e < 5 || (pooled_e > 0 && pooled_e < 5)) {
            pooled_o += o;
            pooled_e += e;
        } else {
            chsq += (o - e) * (o - e) / e;
            ++dof;
        }
    }
    if (pooled_e > 0 || pooled_o > 0) {
        chsq += (pooled_o - pooled_e) * (pooled_o - pooled_e) / std::max(pooled_e, 1e-300);
        ++dof;
    }
    dof -= 1;
    r.statistic = chsq;
    r.dof = dof;
    r.alpha = 1 - std::pow(1 - significance, 1.0 / tests);
    if (dof <= 0) {
        // Everything in one cell (a very sharp lobe): nothing to test at this resolution.
        r.pass = true;
        r.p_value = 1;
        r.message = "one cell holds all the mass";
        return r;
    }
    r.p_value = 1 - chi2_cdf(chsq, dof);
    r.pass = r.p_value >= r.alpha && std::isfinite(r.p_value);
    char m[200];
    std::snprintf(m, sizeof m, "chi2 %.1f, dof %d, p-value %.3g, alpha %.3g, pdf over the upper hemisphere %.4f + "
                  "drawn below %.4f", chsq, dof, r.p_value, r.alpha, r.pdf_upper, r.pdf_integral - r.pdf_upper);
    r.message = m;
    return r;
}

}  // namespace sepal_test
