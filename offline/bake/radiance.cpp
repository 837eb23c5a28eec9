#include "bake/radiance.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/common.hpp>

#include "bake/asset_file.h"
#include "brdf/brdf_util.h"
#include "factor/factor_error.h"
#include "sepal/sepal_asset.h"
#include "util/parallel.h"

namespace sepal {

glm::dvec3 estimate_diffuse(const Brdf& f, double quantile, int threads) {
    // The dense grid of the error metric (equal-area cells over both hemispheres): 16^4
    // pairs, the same in every run.
    constexpr int kGrid = 16;
    constexpr int64_t kPairs = int64_t(kGrid) * kGrid * kGrid * kGrid;
    constexpr size_t kChunks = 64;
    std::vector<glm::dvec3> values(size_t(kPairs), glm::dvec3(-1));
    parallel_for(kChunks, threads, [&](size_t chunk) {
        for (int64_t k = int64_t(chunk); k < kPairs; k += int64_t(kChunks)) {
            glm::dvec3 wi, wo;
            ErrorEvaluator::dense_pair(kGrid, k, &wi, &wo);
            // 1.1 degrees from the horizon: the models' own grazing clamps stay out of it.
            if (wi.z < 0.02 || wo.z < 0.02) continue;
            values[size_t(k)] = f.eval(wi, wo);
        }
    });
    glm::dvec3 out(0);
    for (int c = 0; c < 3; ++c) {
        std::vector<double> v;
        v.reserve(values.size());
        for (const glm::dvec3& x : values)
            if (x[c] >= 0 && std::isfinite(x[c])) v.push_back(x[c]);
        if (v.empty()) continue;
        const size_t at = std::min(v.size() - 1, size_t(quantile * double(v.size())));
        std::nth_element(v.begin(), v.begin() + long(at), v.end());
        out[c] = std::max(0.0, v[at]);
    }
    return out;
}

double DiffusePart::eval(int c, double cos_i, double cos_o) const {
    if (side < 2) return scale[c];
    // The runtime's own lookup, so the bake subtracts exactly what the runtime adds.
    return scale[c] * double(sepal_diffuse_profile(profile.data(), uint32_t(side), SEPAL_FMT_DIFFUSE_RGB_F32, float(cos_i), float(cos_o), c));
}

DiffusePart estimate_diffuse_profile(const Brdf& f, int side, int threads) {
    DiffusePart d;
    side = std::max(2, std::min(side, int(SEPAL_FMT_MAX_DIFFUSE_SIDE)));
    const int nodes = side * side;
    std::vector<glm::dvec3> floor(size_t(nodes), glm::dvec3(0));
    const bool iso = f.isotropic();
    parallel_for(size_t(nodes), threads, [&](size_t node) {
        const int i = int(node) % side, j = int(node) / side;
        glm::dvec3 low(1e300);
        // The cells around the node: its cosine and the midpoints towards its neighbours.
        for (int a = -1; a <= 1; ++a)
            for (int b = -1; b <= 1; ++b) {
                const double ci = std::clamp((i + 0.5 * a) / (side - 1), 1e-3, 1.0);
                const double co = std::clamp((j + 0.5 * b) / (side - 1), 1e-3, 1.0);
                const double si = std::sqrt(1 - ci * ci), so = std::sqrt(1 - co * co);
                for (int p = 0; p < (iso ? 1 : 8); ++p) {
                    const double phi_i = kPi * p / 8;
                    for (int q = 0; q < 24; ++q) {
                        const double phi_o = phi_i + 2 * kPi * q / 24;
                        const glm::dvec3 wi(si * std::cos(phi_i), si * std::sin(phi_i), ci);
                        const glm::dvec3 wo(so * std::cos(phi_o), so * std::sin(phi_o), co);
                        low = glm::min(low, f.eval(wi, wo));
                    }
                }
            }
        floor[node] = glm::max(low, glm::dvec3(0));
    });
    for (const glm::dvec3& v : floor) d.scale = glm::max(d.scale, v);
    if (!d.any()) return d;
    glm::dvec3 lowest(1e300);
    for (const glm::dvec3& v : floor) lowest = glm::min(lowest, v);
    bool flat = true;
    for (int c = 0; c < 3; ++c) flat = flat && lowest[c] >= 0.98 * d.scale[c];
    if (flat) {
        d.scale = lowest;  // a constant at or below f everywhere
        return d;
    }
    d.side = side;
    d.profile.resize(size_t(nodes) * 3);
    for (int k = 0; k < nodes; ++k)
        for (int c = 0; c < 3; ++c)
            // Rounded down to the 16 bits the asset stores: still at or below f.
            d.profile[size_t(k) * 3 + c] =
                d.scale[c] > 0 ? diffuse_u16_value(uint16_t(std::floor(glm::clamp(floor[size_t(k)][c] / d.scale[c], 0.0, 1.0) * 65535.0)))
                               : 0.0f;
    return d;
}

double display_weight(const glm::dvec3& value, double irradiance_max) {
    const double v = std::max(value.x, std::max(value.y, value.z)) * irradiance_max;
    return v <= 1.0 ? 1.0 : 1.0 / (v * v);
}

glm::dvec3 RadianceBrdf::eval(const glm::dvec3& wi, const glm::dvec3& wo) const {
    ++calls_;
    if (!(wi.z > 0) || !(wo.z > 0)) return glm::dvec3(0);
    const glm::dvec3 f = f_.eval(wi, wo);
    glm::dvec3 g;
    bool capped = false, floored = false;
    // Divided by the horizon window: cos_i / w(cos_i) = max(cos_i, c0).
    const double u = std::max(wi.z, t_.horizon);
    for (int c = 0; c < 3; ++c) {
        double r = f[c] * u;
        if (t_.white > 0 && r > t_.white) r = t_.white, capped = true;
        r -= t_.diffuse.eval(c, wi.z, wo.z) * u;
        if (r < 0) r = 0, floored = true;
        g[c] = r;
    }
    if (capped) ++capped_;
    if (floored) ++floored_;
    return g;
}

}  // namespace sepal
