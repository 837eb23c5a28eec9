#include "factor/scattered.h"

#include <algorithm>
#include <cmath>

namespace sepal {

namespace {

struct Prepared {
    BilinearTaps tap[2];  // G, H
    double w;
    glm::dvec3 f;
};

// A symmetric matrix on an n x n texel grid whose couplings reach the 8 neighbours (the
// bilinear taps of one lookup and the Laplacian's edges never reach further).
struct Stencil {
    int n = 0;
    std::vector<double> a, b;  // a: 9 per texel, row-major offsets (dj+1)*3 + (di+1)
    void reset(int side) {
        n = side;
        a.assign(size_t(n) * n * 9, 0.0);
        b.assign(size_t(n) * n, 0.0);
    }
    void add(int p, int q, double v) {
        const int di = q % n - p % n, dj = q / n - p / n;
        a[size_t(p) * 9 + size_t((dj + 1) * 3 + (di + 1))] += v;
    }
};

void add_laplacian(Stencil* s, double lambda) {
    const int n = s->n;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int t = j * n + i;
            for (int e = 0; e < 2; ++e) {
                const int ii = i + (e == 0), jj = j + (e == 1);
                if (ii >= n || jj >= n) continue;
                const int u = jj * n + ii;
                s->add(t, t, lambda);
                s->add(u, u, lambda);
                s->add(t, u, -lambda);
                s->add(u, t, -lambda);
            }
        }
}

// Projected Gauss-Seidel: each coordinate set to its exact non-negative minimizer given the
// others, so the quadratic never rises.
void gauss_seidel(const Stencil& s, std::vector<double>* x, int sweeps) {
    const int n = s.n;
    for (int it = 0; it < sweeps; ++it)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const int t = j * n + i;
                const double* a = &s.a[size_t(t) * 9];
                if (!(a[4] > 0)) continue;
                double sum = s.b[size_t(t)];
                for (int dj = -1; dj <= 1; ++dj)
                    for (int di = -1; di <= 1; ++di) {
                        if (!di && !dj) continue;
                        const int ii = i + di, jj = j + dj;
                        if (ii < 0 || jj < 0 || ii >= n || jj >= n) continue;
                        sum -= a[(dj + 1) * 3 + (di + 1)] * (*x)[size_t(jj * n + ii)];
                    }
                (*x)[size_t(t)] = std::max(0.0, sum / a[4]);
            }
}

double lookup(const BilinearTaps& t, const std::vector<double>& x) {
    return t.weight[0] * x[size_t(t.index[0])] + t.weight[1] * x[size_t(t.index[1])] +
           t.weight[2] * x[size_t(t.index[2])] + t.weight[3] * x[size_t(t.index[3])];
}

}  // namespace

bool refine_scattered(const std::vector<ScatteredSample>& samples, const ScatteredOptions& o, Factored* f,
                      ScatteredResult* result, std::string* err) {
    auto fail = [&](const char* m) {
        if (err) *err = m;
        return false;
    };
    if (f->channels != 3 || f->terms.empty() || f->terms.size() > 16 || f->param == Param::ElevAzim)
        return fail("scattered: per-channel factors (1..16 terms) of a parameterization with clamped factors");
    if (samples.size() > 1000000 || o.iterations < 1 || o.sweeps < 1 || !(o.smoothness >= 0))
        return fail("scattered: up to 1e6 samples, iterations and sweeps >= 1, smoothness >= 0");
    const int k = f->term_count();
    // Texels per side of G and of H (a half-angle factor may be finer than the other).
    const int side_n[2] = {f->terms[0].g.n, f->terms[0].h.n};
    for (const FactorTerm& t : f->terms)
        if (t.g.n != side_n[0] || t.h.n != side_n[1] || t.g.channels != 3 || t.h.channels != 3)
            return fail("scattered: every term's G (and H) factors of one size, 3 channels");
    std::vector<Prepared> pre;
    double wsum = 0;
    for (const ScatteredSample& s : samples) {
        TexCoords tc;
        if (!(s.weight > 0) || !param_forward(f->param, f->map, s.wi, s.wo, &tc)) continue;
        if (!std::isfinite(s.f.x) || !std::isfinite(s.f.y) || !std::isfinite(s.f.z)) return fail("scattered: a sample is not finite");
        pre.push_back(Prepared{{bilinear_taps(side_n[0], tc.x, false), bilinear_taps(side_n[1], tc.y, false)}, s.weight, s.f});
        wsum += s.weight;
    }
    if (pre.empty()) return fail("scattered: no sample above the horizon with a weight > 0");
    const size_t ns = pre.size();
    double before = 0, after = 0;
    int iterations = 0;
    Stencil st;
    for (int c = 0; c < 3; ++c) {
        // Factors of this channel as doubles, and their values at every sample.
        std::vector<std::vector<double>> x(size_t(2 * k));
        for (int t = 0; t < 2 * k; ++t) x[size_t(t)].assign(size_t(side_n[t % 2]) * side_n[t % 2], 0.0);
        std::vector<std::vector<double>> at(size_t(2 * k), std::vector<double>(ns));
        for (int t = 0; t < k; ++t)
            for (int side = 0; side < 2; ++side) {
                const FactorTexture& tex = side == 0 ? f->terms[size_t(t)].g : f->terms[size_t(t)].h;
                std::vector<double>& v = x[size_t(2 * t + side)];
                for (size_t i = 0; i < v.size(); ++i) v[i] = std::max(0.0, double(tex.data[i * 3 + size_t(c)]));
                for (size_t s = 0; s < ns; ++s) at[size_t(2 * t + side)][s] = lookup(pre[s].tap[side], v);
            }
        auto data_error = [&]() {
            double e = 0;
            for (size_t s = 0; s < ns; ++s) {
                double p = 0;
                for (int t = 0; t < k; ++t) p += at[size_t(2 * t)][s] * at[size_t(2 * t + 1)][s];
                const double d = pre[s].f[c] - p;
                e += pre[s].w * d * d;
            }
            return e;
        };
        before += data_error();
        double prev = -1;
        int it = 0;
        for (; it < o.iterations; ++it) {
            for (int t = 0; t < k; ++t)
                for (int side = 0; side < 2; ++side) {
                    if (t == 0 && side == o.constant_side) continue;
                    const int me = 2 * t + side, other = 2 * t + 1 - side;
                    const int n = side_n[side];
                    st.reset(n);
                    for (size_t s = 0; s < ns; ++s) {
                        double rest = 0;
                        for (int u = 0; u < k; ++u)
                            if (u != t) rest += at[size_t(2 * u)][s] * at[size_t(2 * u + 1)][s];
                        const double coef = at[size_t(other)][s], r = pre[s].f[c] - rest;
                        const BilinearTaps& tp = pre[s].tap[side];
                        const double wc = pre[s].w * coef;
                        for (int p = 0; p < 4; ++p) {
                            st.b[size_t(tp.index[p])] += wc * r * tp.weight[p];
                            for (int q = 0; q < 4; ++q)
                                st.add(tp.index[p], tp.index[q], wc * coef * tp.weight[p] * tp.weight[q]);
                        }
                    }
                    double diag = 0;
                    int with_data = 0;
                    for (int q = 0; q < n * n; ++q)
                        if (st.a[size_t(q) * 9 + 4] > 0) diag += st.a[size_t(q) * 9 + 4], ++with_data;
                    add_laplacian(&st, o.smoothness * (with_data ? diag / with_data : 0.0) + 1e-300);
                    gauss_seidel(st, &x[size_t(me)], o.sweeps);
                    for (size_t s = 0; s < ns; ++s) at[size_t(me)][s] = lookup(pre[s].tap[side], x[size_t(me)]);
                }
            const double e = data_error();
            if (prev >= 0 && prev - e <= o.tolerance * prev) {
                ++it;
                break;
            }
            prev = e;
        }
        iterations = std::max(iterations, it);
        after += data_error();
        for (int t = 0; t < k; ++t)
            for (int side = 0; side < 2; ++side) {
                FactorTexture& tex = side == 0 ? f->terms[size_t(t)].g : f->terms[size_t(t)].h;
                const std::vector<double>& v = x[size_t(2 * t + side)];
                for (size_t i = 0; i < v.size(); ++i) tex.data[i * 3 + size_t(c)] = float(v[i]);
            }
    }
    if (result) {
        result->rms_before = std::sqrt(before / (3 * wsum));
        result->rms_after = std::sqrt(after / (3 * wsum));
        result->iterations = iterations;
    }
    return true;
}

}  // namespace sepal
