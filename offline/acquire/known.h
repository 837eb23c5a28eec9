// The known SVBRDFs of the virtual acquisition setup: blends of basis BRDFs on the object's
// texture atlas (svbrdf/blend.h, the model the acquisition also reconstructs).
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
// Limits: 1..8 materials; weights are >= 0 and sum to 1; basis BRDFs are any make_brdf spec.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "svbrdf/blend.h"

namespace sepal {

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
