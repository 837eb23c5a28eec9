#include "acquire/known.h"

#include <algorithm>
#include <cmath>

#include "util/parallel.h"

namespace sepal {

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
    BlendMaps maps;
    maps.width = maps.height = res;
    maps.count = int(specs.size());
    maps.w.assign(size_t(res) * res * specs.size(), 0.0f);
    BlendSvbrdf s;
    if (!make_blend_svbrdf(std::move(maps), specs, &s, err)) return false;
    const int K = int(specs.size()), n_seeds = K * o.seeds_per_material;
    std::vector<double> sx(static_cast<size_t>(n_seeds)), sy(static_cast<size_t>(n_seeds));
    SplitMix64 rng(o.seed);
    for (int i = 0; i < n_seeds; ++i) {
        sx[size_t(i)] = rng.uniform();
        sy[size_t(i)] = rng.uniform();
    }
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
            float* w = &s.maps.w[(size_t(y) * res + x) * size_t(K)];
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
