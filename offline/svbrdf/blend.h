// The one SVBRDF model of the offline tools: per texel, a non-negative blend of a few basis
// BRDFs, f(x, wi, wo) = sum_j w_j(x) f_j(wi, wo). The known objects of planned acquisition
// and what it reconstructs (Lensch et al. 2003: basis materials with per-texel weights), the
// ground truth of the inverse shade trees' test data (Lawrence et al. 2006) and the trees'
// own first level all use it, so they render, compare and bake the same way.
// Measurements of an SVBRDF (sampled direction pairs per texel) are svbrdf/samples.h.
//
// Usage:
//   sepal::BlendSvbrdf s; std::string err;
//   if (!sepal::make_blend_svbrdf(maps, {"lambert", "ward:ax=0.2,ay=0.2"}, &s, &err)) ...
//   glm::dvec3 f = s.eval(texel, wi, wo);                   // at a texel centre
//   render_exact_spatial(s, scene, mesh, w, h, &img, ...);  // bilinear weights between texels
//
// Texels: index = y * width + x, texel (x, y) at UV ((x + 0.5)/width, (y + 0.5)/height), row 0
// at v = 0; between texel centres the weights are bilinear and repeat at the borders, as a
// GL_REPEAT texture of the weight maps samples them. Directions: brdf.h's local frame.
// Limits: 1..16 bases (make_blend_svbrdf); maps of 1..4096 texels a side.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "brdf/brdf.h"
#include "reference/render_exact.h"

namespace sepal {

// Weight maps, one per basis, width x height texels.
struct BlendMaps {
    int width = 0, height = 0, count = 0;
    std::vector<float> w;  // [texel * count + j]
    float at(int texel, int j) const { return w[size_t(texel) * size_t(count) + size_t(j)]; }
    const float* texel(int t) const { return &w[size_t(t) * size_t(count)]; }
    // Map j at (u, v), bilinear between texel centres with repeat wrapping.
    double sample(int j, double u, double v) const;
    // Every map at (u, v) the same way, accumulated in float; out holds count values.
    void sample_all(double u, double v, float* out) const;
};

class BlendSvbrdf : public SpatialBrdf {
  public:
    BlendMaps maps;
    std::vector<std::shared_ptr<const Brdf>> basis;  // maps.count of them
    std::vector<std::string> specs;                 // make_brdf specs of the bases
    std::vector<std::string> names;                 // optional, e.g. "gold foil"

    int materials() const { return int(basis.size()); }
    glm::dvec3 eval(int texel, const glm::dvec3& wi, const glm::dvec3& wo) const {
        return eval_weights(maps.texel(texel), wi, wo);
    }
    // sum_j w[j] f_j(wi, wo), bases with weight 0 not evaluated.
    glm::dvec3 eval_weights(const float* w, const glm::dvec3& wi, const glm::dvec3& wo) const;
    // The spatial BRDF at uv (render_exact_spatial): weights by BlendMaps::sample.
    glm::dvec3 eval(const glm::dvec2& uv, const glm::dvec3& wi, const glm::dvec3& wo) const override;
};

// Builds the bases from their specs (make_brdf) over the given maps; false with the reason
// (a bad spec, a count that does not match the maps, sizes out of bounds).
bool make_blend_svbrdf(BlendMaps maps, const std::vector<std::string>& specs, BlendSvbrdf* out,
                       std::string* err);

}  // namespace sepal
