// The first k terms of a parsed asset, for viewers that show how the approximation
// converges (sepal-view's digit keys, the web page's term control).
//
// Usage:
//   static sepal_asset all, some;  ... sepal_asset_parse(bytes, size, &all, &err) ...
//   TermPrefix p = term_prefix(all, 2, &some);   // then sepal_material_create(..., &some, ...)
//
// The fused and CPU backends sum material.terms terms: that count is lowered. The pass
// plan is filtered: PRODUCT and TEXTURE passes belong to the term of their textures;
// CONSTANT passes (a signed term's bias x bias) carry no texture, so each is matched by
// value to the term whose |ratio bG bH| 2^-doublings it equals (relative 1e-3 per
// nonzero channel). A pass no term can be named for (no match, several, or an op this
// code does not know) is kept and counted in `unattributed`: the view is then
// approximate and says so. Exposure bounds stay the full plan's: a subset of the added
// passes never sums higher.
#pragma once
#include "sepal/sepal_asset.h"

namespace sepal_ports {

struct TermPrefix {
    int terms = 0;         // terms kept (k clamped to 1..material.terms; 0 asks for all)
    int passes = 0;        // passes kept
    int unattributed = 0;  // passes kept although no term could be named for them
    size_t texture_bytes = 0;  // GPU bytes of the kept terms' textures (8 bits per channel)
};

// out may not alias in. The textures' pixel pointers still point into in's bytes.
TermPrefix term_prefix(const sepal_asset& in, int terms, sepal_asset* out);

}  // namespace sepal_ports
