// One export layout for `sepal bake --export DIR` and `sepal factor --export DIR`: what a
// baked asset or a factorization holds, as files people and tools can open.
//
// Usage:
//   std::string err;
//   if (!sepal::export_asset(result.asset, "out/ward", &err)) ...       // bake: the shipped textures
//   if (!sepal::export_factored(result.factored, "out/ward", &err)) ... // factor: the float factors
//
// Files (k counts terms from 0, as the asset and `sepal inspect` do; role G or H):
//   DIR/term<k>_<G|H>_mip<l>.png  one PNG per texture per MIP level: the stored codes q in
//                                 [0, 1] (the value is scale * q + bias per channel, see the
//                                 manifest); 8-bit PNG for 8-bit textures, 16-bit PNG for
//                                 16-bit ones (--bits 16). A factorization has no MIP chain
//                                 and is not quantized: its float factors are written as
//                                 16-bit codes of level 0 with their own scale and bias.
//   DIR/term<k>_<G|H>.pfm         level 0 as the values it stands for (float PFM)
//   DIR/diffuse_profile.pfm       the diffuse part's profile over (cos_i, cos_o), when there is one
//   DIR/manifest.json             source, parameterization, map, colour, method, terms, colour
//                                 ratio; how the textures are drawn: the radiance and reciprocal
//                                 flags, the diffuse part, its profile, the white level, the
//                                 light range and the formula ("evaluation", as `sepal eval
//                                 ASSET` computes it); and per texture: term, role, size, levels,
//                                 channels, bits, scale, bias and its files ("layout" says how).
//                                 docs/format.md, "Export", is the reference.
// Images are flipped so that v grows upwards: texture row 0 (v = 0) is the image's bottom row,
// as the texture is drawn. Files are written atomically; equal inputs give equal bytes.
#pragma once
#include <string>

#include "bake/asset_file.h"
#include "factor/factored.h"

namespace sepal {

bool export_asset(const AssetData& asset, const std::string& dir, std::string* err);
bool export_factored(const Factored& factored, const std::string& dir, std::string* err);

}  // namespace sepal
