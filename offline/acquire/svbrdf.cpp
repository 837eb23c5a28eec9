#include "acquire/svbrdf.h"
#include "spec/spec.h"

#include <algorithm>
#include <cmath>

#include "util/parallel.h"

namespace sepal {

glm::dvec3 BlendSvbrdf::eval_weights(const float* w, const glm::dvec3& wi, const glm::dvec3& wo) const {
    glm::dvec3 f(0.0);
    for (size_t k = 0; k < basis.size(); ++k)
        if (w[k] != 0.0f) f += double(w[k]) * basis[k]->eval(wi, wo);
    return f;
}

void BlendSvbrdf::weights_at(double u, double v, float* out) const {
    const size_t K = basis.size();
    const double fx = u * res - 0.5, fy = v * res - 0.5;
    const double x0 = std::floor(fx), y0 = std::floor(fy);
    const double ax = fx - x0, ay = fy - y0;
    auto wrap = [&](double i) { return int(((long long)i % res + res) % res); };
    const int xs[2] = {wrap(x0), wrap(x0 + 1)}, ys[2] = {wrap(y0), wrap(y0 + 1)};
    const double ws[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
    for (size_t k = 0; k < K; ++k) out[k] = 0;
    for (int c = 0; c < 4; ++c) {
        const float* w = texel_weights(ys[c / 2] * res + xs[c % 2]);
        for (size_t k = 0; k < K; ++k) out[k] += float(ws[c]) * w[k];
    }
}

std::vector<std::string> default_svbrdf_materials() {
    return {
        "blinn:rho_d=0.45/0.06/0.04,rho_s=0.3,n=25",
        "nbrdf:gold-metallic-paint",
        "oren-nayar:rho=0.12/0.2/0.55,sigma=0.4",
        "nbrdf:white-paint",
    };
}

bool make_svbrdf(int res, const SvbrdfGenOptions& o, BlendSvbrdf* out, std::string* err) {
    const std::vector<std::string> specs = o.materials.empty() ? default_svbrdf_materials() : o.materials;
    if (specs.empty() || specs.size() > 8) {
        if (err) *err = "svbrdf: 1..8 materials, got " + std::to_string(specs.size());
        return false;
    }
    if (res < 1 || res > 4096 || o.seeds_per_material < 1 || o.seeds_per_material > 64 || !(o.softness > 0)) {
        if (err) *err = "svbrdf: res 1..4096, seeds per material 1..64, softness > 0";
        return false;
    }
    BlendSvbrdf s;
    s.res = res;
    for (const std::string& spec : specs) {
        std::string e;
        std::unique_ptr<Brdf> b = make_brdf(spec, &e);
        if (!b) {
            if (err) *err = "svbrdf: " + e;
            return false;
        }
        s.basis.emplace_back(std::move(b));
    }
    const int K = int(specs.size()), n_seeds = K * o.seeds_per_material;
    std::vector<double> sx(static_cast<size_t>(n_seeds)), sy(static_cast<size_t>(n_seeds));
    SplitMix64 rng(o.seed);
    for (int i = 0; i < n_seeds; ++i) {
        sx[size_t(i)] = rng.uniform();
        sy[size_t(i)] = rng.uniform();
    }
    s.weights.assign(size_t(res) * res * size_t(K), 0.0f);
    const double t2 = o.softness * o.softness;
    std::vector<double> d2(static_cast<size_t>(n_seeds));
    for (int y = 0; y < res; ++y)
        for (int x = 0; x < res; ++x) {
            const double u = (x + 0.5) / res, v = (y + 0.5) / res;
            double dmin = 1e9;
            for (int i = 0; i < n_seeds; ++i) {
                double dx = std::fabs(u - sx[size_t(i)]), dy = std::fabs(v - sy[size_t(i)]);
                dx = std::min(dx, 1 - dx);
                dy = std::min(dy, 1 - dy);
                d2[size_t(i)] = dx * dx + dy * dy;
                dmin = std::min(dmin, d2[size_t(i)]);
            }
            float* w = &s.weights[(size_t(y) * res + x) * size_t(K)];
            double sum = 0;
            for (int i = 0; i < n_seeds; ++i) {
                const double e = std::exp(-(d2[size_t(i)] - dmin) / t2);
                w[i % K] += float(e);
                sum += e;
            }
            // Weights below 1e-3 are dropped (and the rest renormalized): a texel then
            // evaluates only the one or two materials it shows.
            double kept = 0;
            for (int k = 0; k < K; ++k) {
                w[k] = w[k] / sum < 1e-3 ? 0.0f : w[k];
                kept += w[k];
            }
            for (int k = 0; k < K; ++k) w[k] = float(w[k] / kept);
        }
    *out = std::move(s);
    return true;
}

}  // namespace sepal
