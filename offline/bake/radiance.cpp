#include "bake/radiance.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "factor/factor_error.h"
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

glm::dvec3 RadianceBrdf::eval(const glm::dvec3& wi, const glm::dvec3& wo) const {
    ++calls_;
    if (!(wi.z > 0) || !(wo.z > 0)) return glm::dvec3(0);
    const glm::dvec3 f = f_.eval(wi, wo);
    glm::dvec3 g;
    bool capped = false, floored = false;
    for (int c = 0; c < 3; ++c) {
        double r = f[c] * wi.z;
        if (t_.white > 0 && r > t_.white) r = t_.white, capped = true;
        r -= t_.diffuse[c] * wi.z;
        if (r < 0) r = 0, floored = true;
        g[c] = r;
    }
    if (capped) ++capped_;
    if (floored) ++floored_;
    return g;
}

}  // namespace sepal
