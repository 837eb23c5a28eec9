// A tiny line-plot rasterizer for error curves (README figures, `sepal factor --plot`), and
// the same plots as SVG.
//
// Usage:
//   sepal::PlotPanel p;
//   p.title = "ward"; p.x_label = "terms"; p.y_label = "cos-weighted RMS";
//   p.series.push_back({"gs-half", {1, 2, 3}, {0.3, 0.2, 0.15}, {0.85, 0.2, 0.1}});
//   sepal::Image img = sepal::render_plot({p}, 1);
//   sepal::write_png("plot.png", img, &err);
//
// Hand-written because no plotting library is among the project's allowed dependencies
// (Debian packages: GLM, stb, doctest, Eigen): axes with numbered ticks (a linear x axis
// with integer-friendly steps, a log-scale y axis with decades and 2x/5x sub-ticks), one
// polyline (or markers only) with square markers per series, optionally a log x axis, a legend, and a title, drawn with
// stb_easy_font (ASCII 32..126; other bytes draw as '?'). Panels are laid out in a grid.
// Limits: no anti-aliasing; non-positive or non-finite y values are skipped on log axes
// (and non-finite ones on linear axes); panel sizes 160..2000 pixels.
#pragma once
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "util/image.h"

namespace sepal {

struct PlotSeries {
    std::string label;
    std::vector<double> x, y;
    glm::dvec3 colour{0, 0, 0};  // linear 0..1
    bool lines = true;  // false: markers only (a scatter)
    int marker = 2;     // marker half-size in pixels, 1..6
};

struct PlotPanel {
    std::string title, x_label, y_label;
    std::vector<PlotSeries> series;
    bool log_y = true;
    bool log_x = false;  // decades on x too (frame times spanning 1..100 ms)
};

// Panels left to right, top to bottom, `columns` per row; each panel_w x panel_h pixels.
// Returns an RGB image with a white background.
Image render_plot(const std::vector<PlotPanel>& panels, int columns, int panel_w = 480,
                  int panel_h = 360);

// The same panels as SVG (the same layout; text in a sans-serif font a browser scales, so
// figures stay readable when zoomed): a complete document, UTF-8.
std::string render_plot_svg(const std::vector<PlotPanel>& panels, int columns, int panel_w = 480,
                            int panel_h = 360);

// Writes the panels to `path`: SVG when it ends in ".svg", else PNG (atomically, either way).
bool write_plot(const std::string& path, const std::vector<PlotPanel>& panels, int columns, int panel_w,
                int panel_h, std::string* err);

// A palette of distinguishable series colours.
glm::dvec3 plot_colour(int index);

// Three panels side by side for people: a reference image, a test image and the heatmap of
// their difference (diff_heatmap, full_scale 8-bit levels to white), each titled, with a
// labelled colour bar under the heatmap. Both images the same size (RGB or grey).
// When they differ and are at least 64 pixels a side, a second row shows the three panels'
// window of the largest difference (worst_window, a side of an eighth of the smaller image
// side) magnified to the panel's size with nearest-neighbour pixels, outlined in the first
// row: a highlight a few pixels wide is where bakes go wrong, and at full size it is a dot.
Image comparison_sheet(const Image& reference, const Image& test, const std::string& reference_title,
                       const std::string& test_title, double full_scale);

// The sheet's magnified window (comparison_sheet): false when the images are equal or under
// 64 pixels a side; else its side (an eighth of the smaller image side), its top-left corner
// (worst_window) and the magnification that fills the panel.
struct SheetWindow {
    int side = 0, x = 0, y = 0, zoom = 0;
};
bool sheet_window(const Image& a, const Image& b, SheetWindow* out);

// The side x side window of two same-size images with the largest sum of squared channel
// differences (the first in row-major order on ties); false when they are equal or smaller
// than the window.
bool worst_window(const Image& a, const Image& b, int side, int* x0, int* y0);

// Draws text with stb_easy_font (printable ASCII; anything else draws as '?') at (x, y) =
// top-left corner, scale >= 1 (pixel size): capitals are 7 pixels tall at scale 1, descenders
// reach 2 more. Returns the width drawn, text_width's.
int text_width(const std::string& text, int scale = 1);
int draw_text(Image* img, int x, int y, const std::string& text, const glm::dvec3& colour,
              int scale = 1);

}  // namespace sepal
