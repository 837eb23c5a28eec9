// Writing a tree for the runtime: a .sepaltree file (runtime/include/sepal/sepal_tree.h):
// each basis's factor textures (rasterized from its curves, ist/tree.h) quantized and
// planned as a .sepal material (bake/bake.h's make_asset), and its blend map as 8 bits.
//
// Usage:
//   std::vector<uint8_t> bytes; sepal::TreeAssetInfo info; std::string err;
//   if (!sepal::encode_tree_asset(tree, sepal::TreeAssetOptions(), &bytes, &info, &err)) ...
//   sepal::write_file_atomic("card.sepaltree", bytes.data(), bytes.size(), &err);
//
// Blend maps are resampled (bilinear, repeat, as the runtime samples them) onto the next
// power-of-two size at or above the tree's (at most SEPAL_TREE_MAX_BLEND_SIDE a side) and
// each divided by its largest weight, which multiplies that basis's H factors instead, so
// a map uses all 256 levels. Materials: 8-bit textures (level 0; TreeAssetOptions), add-only plans for
// the non-negative factors of a tree. The file is parsed back with the runtime's reader
// before it is returned: a writer bug cannot make a file the runtime refuses.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "ist/tree.h"

namespace sepal {

struct TreeAssetOptions {
    int bits = 8;       // 8 or 16 (the fused GL ES 2 shader takes 8)
    // MIP chains for the bases' factor textures (direction space): off, as the bake's
    // (bake.h: GL's level selection blurs them where the view grazes). The blend maps are
    // surface textures and always get their MIP levels at load.
    bool mips = false;
};

struct TreeAssetInfo {
    int blend_width = 0, blend_height = 0;
    std::vector<float> blend_scale;  // per basis
    std::vector<int> passes;         // per basis: its plan's passes
    size_t bytes = 0;
};

bool encode_tree_asset(const ShadeTree& t, const TreeAssetOptions& o, std::vector<uint8_t>* out, TreeAssetInfo* info,
                       std::string* err);

}  // namespace sepal
