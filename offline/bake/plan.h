// The pass plan: how a GL ES 1.1 framebuffer (values in [0,1], add and subtract by
// blending) rebuilds f = sum_k G_k H_k from quantized textures.
//
// Usage:
//   sepal::AssetData a;  ... textures with scale/bias filled in ...
//   std::string err;
//   if (!sepal::build_plan(&a, &err)) ...      // fills a.passes and a.plan
//
// Each texture stores q in [0,1] and means scale * q + bias (per channel; a luminance
// material's one channel is multiplied by material.ratio per channel, folded into the
// pass colours). For a term
// with G = aG qG + bG and H = aH qH + bH,
//   G H = aG aH qG qH + aG bH qG + bG aH qH + bG bH          (Kautz-McCool section 5.1)
// so a term is one PRODUCT pass, plus a TEXTURE pass per nonzero bias of the other
// factor and a CONSTANT pass when both biases are nonzero; non-negative factors (bias
// 0, e.g. NMF) need the PRODUCT pass alone. A coefficient's sign picks the blend (add or
// subtract); where channels disagree in sign the pass is split in two. All adds come
// before all subtracts, so partial sums only grow and then only shrink: none clamps at 0
// unless f itself is negative there. Coefficients are scaled by 2^-D so that every pass
// colour and the sum of all added passes (a bound on any partial sum, since q <= 1) stay
// within [0,1] at unit irradiance; plan.doublings = D undoes it.
// A radiance material's diffuse part (material.diffuse, format 2) becomes one DIFFUSE pass
// (untextured, added; the runtime multiplies its colour by E cos(theta_i)).
// A reciprocal material (SEPAL_MATERIAL_RECIPROCAL, homomorphic factors, format 2.1) gets one
// RECIPROCAL pass per term, colour ratio * sG^2 * sH (both biases must be 0).
#pragma once
#include <string>

#include "bake/asset_file.h"

namespace sepal {

// Every coefficient zero (an all-zero BRDF, or factors that quantized to 0) is refused
// unless allow_all_zero: then the plan is one CONSTANT pass of colour (0, 0, 0), added, no
// doublings, peak_partial_sum 1e-30 (the reader wants (0, 1]; only subtracting plans use
// it). It draws nothing: the material renders black (the reader needs at least one pass).
// bake() allows it and reports it ("all_zero" in its counts, and a note).
bool build_plan(AssetData* asset, std::string* err, bool allow_all_zero = false);
// True when every pass of the plan has colour 0 (the plan above, or one like it).
bool plan_all_zero(const AssetData& asset);

// Largest partial sum of the plan (after every added pass, at unit irradiance) over every
// pair of texel centres: the plan's peak_partial_sum. 0 if textures or passes are missing.
double partial_sum_peak(const AssetData& asset);

// f at one point from decoded factor values, as the plan computes it (for tests):
// sum over passes of sign * colour * operands, times 2^doublings (a DIFFUSE pass counts
// its colour: the cosine the runtime multiplies it by is not included). A RECIPROCAL pass
// reads tex0 a second time at the swapped pair: q_swapped[tex0] (q when NULL).
double plan_value(const AssetData& asset, const double* q, int channel, const double* q_swapped = nullptr);

}  // namespace sepal
