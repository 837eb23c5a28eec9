// Spatially varying BRDFs on a texture atlas: per texel, a weighted sum of a few basis BRDFs,
// f(x, wi, wo) = sum_k w_k(x) f_k(wi, wo). The known objects of the virtual setup are such
// blends, and so is what the acquisition reconstructs (Lensch et al.'s basis materials
// with per-texel weights), so both render, compare and bake the same way.
//
// Usage:
//   sepal::BlendSvbrdf truth; std::string err;
//   if (!sepal::make_svbrdf(128, sepal::SvbrdfGenOptions(), &truth, &err)) ...
//   glm::dvec3 f = truth.eval(texel, wi, wo);      // local frame of the texel
//
// The generator (kept small on purpose; the inverse-shade-tree generator, ist/generate.h,
// is the richer one): a few seed points per material scattered over the atlas, periodic in both
// UV directions (no seam on the sphere or torus), and soft-min weights
// w_k(x) ~ sum over material k's seeds of exp(-(d^2 - d_min^2) / softness^2), normalized,
// weights below 1e-3 dropped: regions of pure material with blended borders.
// Limits: 1..8 materials; weights are >= 0; basis BRDFs are any make_brdf spec.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "brdf/brdf.h"

namespace sepal {

struct BlendSvbrdf {
    int res = 0;
    std::vector<std::shared_ptr<const Brdf>> basis;
    std::vector<float> weights;  // res * res * basis.size(), texel-major
    int materials() const { return int(basis.size()); }
    const float* texel_weights(int texel) const { return &weights[size_t(texel) * basis.size()]; }
    glm::dvec3 eval(int texel, const glm::dvec3& wi, const glm::dvec3& wo) const {
        return eval_weights(texel_weights(texel), wi, wo);
    }
    glm::dvec3 eval_weights(const float* w, const glm::dvec3& wi, const glm::dvec3& wo) const;
    // The weights at (u, v) bilinearly between texel centres, repeating at the borders (as
    // a GL_REPEAT texture of the weight maps samples them); out holds materials() values.
    void weights_at(double u, double v, float* out) const;
};

struct SvbrdfGenOptions {
    std::vector<std::string> materials;  // empty: default_svbrdf_materials()
    int seeds_per_material = 3;
    double softness = 0.05;  // in UV units
    uint64_t seed = 1;
};

// Four materials a Lafortune lobe fits only approximately, two analytic and two measured
// (MERL, as neural fits: measured/nbrdf.h), glossy but not mirror-like: red plastic (Blinn
// n 25), nbrdf:gold-metallic-paint, blue rough clay (Oren-Nayar), nbrdf:white-paint.
std::vector<std::string> default_svbrdf_materials();

bool make_svbrdf(int res, const SvbrdfGenOptions& options, BlendSvbrdf* out, std::string* err);

}  // namespace sepal
