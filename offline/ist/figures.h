// Pictures of inverse shade trees (PNG-ready images): blend maps side by side (the
// paper's Fig. 5 / 6 layout), the curves of every basis as plots, and labelled grids of
// renders (contact sheets).
//
// Usage:
//   std::vector<sepal::BlendRow> rows = {{"truth", truth.blend, {}}, {"SACLS", d.blend(), order}};
//   sepal::write_png("blend.png", sepal::blend_sheet(rows, 96), &err);
//   sepal::write_png("curves.png", sepal::curve_sheet(tree), &err);
//   sepal::write_png("renders.png", sepal::labelled_grid({{"exact", a}, {"gles1", b}}, 4), &err);
//
// Blend maps: each map scaled by its own largest |weight| (terms of NMF or PCA have no
// fixed scale), grey for non-negative maps, and for maps with negative values (PCA) red
// for positive and green for negative, brightness the magnitude (as the paper's Fig. 5).
// Curves: per basis four panels (G theta, G phi, H theta, H phi; degrees), one series per
// term, the luminance of the RGB curve. Labels use the plot module's font (stb_easy_font).
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "ist/generate.h"
#include "ist/tree.h"
#include "sepal/sepal_scene.h"
#include "util/image.h"

namespace sepal {

struct BlendRow {
    std::string label;
    BlendMaps maps;
    std::vector<int> order;  // display slot of each map (e.g. its matched true map); empty: as is
};
// One row per entry, one column per slot, cell_px pixels a cell (maps scaled nearest).
Image blend_sheet(const std::vector<BlendRow>& rows, int cell_px);

Image curve_sheet(const ShadeTree& t);

// The scene the tree renders use by default (sepal ist render, tests, bench): a camera
// above and in front of a surface near z = 0 (the "wave" mesh), a point light behind it
// at the mirror position, so highlights of the shiny bases fall on the surface, and a
// dim second light from the side for the diffuse ones.
void ist_default_scene(sepal_scene* s);

// Tiles (RGB, values clipped to [0, 1]) in a grid of `columns`, each with its label above.
Image labelled_grid(const std::vector<std::pair<std::string, Image>>& tiles, int columns);

}  // namespace sepal
