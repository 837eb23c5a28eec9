#include "svbrdf/blend.h"

#include <cmath>

#include "spec/spec.h"

namespace sepal {

namespace {

int wrap(long long i, int n) { return int((i % n + n) % n); }

// The four texels around (u, v), repeating at the borders, and their bilinear weights.
struct Corners {
    int texel[4];
    double weight[4];
    Corners(const BlendMaps& m, double u, double v) {
        const double fx = u * m.width - 0.5, fy = v * m.height - 0.5;
        const double x0 = std::floor(fx), y0 = std::floor(fy);
        const double ax = fx - x0, ay = fy - y0;
        const int xs[2] = {wrap((long long)x0, m.width), wrap((long long)x0 + 1, m.width)};
        const int ys[2] = {wrap((long long)y0, m.height), wrap((long long)y0 + 1, m.height)};
        const double ws[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
        for (int c = 0; c < 4; ++c) texel[c] = ys[c / 2] * m.width + xs[c % 2], weight[c] = ws[c];
    }
    double weight_of(const BlendMaps& m, int j) const {
        double w = 0;
        for (int c = 0; c < 4; ++c) w += weight[c] * m.at(texel[c], j);
        return w;
    }
};

}  // namespace

double BlendMaps::sample(int j, double u, double v) const { return Corners(*this, u, v).weight_of(*this, j); }

void BlendMaps::sample_all(double u, double v, float* out) const {
    const Corners k(*this, u, v);
    for (int j = 0; j < count; ++j) out[j] = 0;
    for (int c = 0; c < 4; ++c) {
        const float* w = texel(k.texel[c]);
        for (int j = 0; j < count; ++j) out[j] += float(k.weight[c]) * w[j];
    }
}

glm::dvec3 BlendSvbrdf::eval_weights(const float* w, const glm::dvec3& wi, const glm::dvec3& wo) const {
    glm::dvec3 f(0.0);
    for (size_t j = 0; j < basis.size(); ++j)
        if (w[j] != 0.0f) f += double(w[j]) * basis[j]->eval(wi, wo);
    return f;
}

glm::dvec3 BlendSvbrdf::eval(const glm::dvec2& uv, const glm::dvec3& wi, const glm::dvec3& wo) const {
    const Corners k(maps, uv.x, uv.y);  // once for every basis
    glm::dvec3 f(0);
    for (int j = 0; j < maps.count; ++j) {
        const double w = k.weight_of(maps, j);
        if (w != 0) f += w * basis[size_t(j)]->eval(wi, wo);
    }
    return f;
}

bool make_blend_svbrdf(BlendMaps maps, const std::vector<std::string>& specs, BlendSvbrdf* out,
                       std::string* err) {
    if (specs.empty() || specs.size() > 16 || int(specs.size()) != maps.count || maps.width < 1 ||
        maps.width > 4096 || maps.height < 1 || maps.height > 4096 ||
        maps.w.size() != size_t(maps.width) * size_t(maps.height) * size_t(maps.count)) {
        if (err)
            *err = "svbrdf: " + std::to_string(specs.size()) + " bases for " + std::to_string(maps.count) +
                   " weight maps of " + std::to_string(maps.width) + "x" + std::to_string(maps.height) +
                   " (1..16 bases, one map each, 1..4096 texels a side)";
        return false;
    }
    BlendSvbrdf s;
    for (const std::string& spec : specs) {
        std::string e;
        std::unique_ptr<Brdf> b = make_brdf(spec, &e);
        if (!b) {
            if (err) *err = "svbrdf: " + e;
            return false;
        }
        s.basis.emplace_back(std::move(b));
    }
    s.maps = std::move(maps);
    s.specs = specs;
    *out = std::move(s);
    return true;
}

}  // namespace sepal
