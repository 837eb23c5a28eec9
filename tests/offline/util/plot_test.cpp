// Plots and comparison sheets (offline/util/plot.h).
#include <doctest/doctest.h>

#include <string>

#include "util/image.h"
#include "util/plot.h"

namespace {
// Dark pixels in the title band (above the panels) between columns x0 and x1.
int dark_title_pixels(const sepal::Image& sheet, int x0, int x1) {
    int n = 0;
    for (int y = 0; y < 24; ++y)
        for (int x = x0; x < x1; ++x) n += sheet.at(x, y, 0) < 0.5f;
    return n;
}
}  // namespace

TEST_CASE("comparison sheet: a title wider than its panel stays above its own panel") {
    sepal::Image a(64, 64, 3), b(64, 64, 3);
    const std::string long_name = "build/some/long/directory/name/reference_render.png";
    const sepal::Image sheet = sepal::comparison_sheet(a, b, long_name, "", 16);
    const int w = 64, gap = 8;
    // Panel B's title is empty: any ink above it came from panel A's title.
    CHECK(dark_title_pixels(sheet, gap + w + gap, gap + 2 * (w + gap) - gap) == 0);
    CHECK(dark_title_pixels(sheet, gap, gap + w) > 0);  // the shortened title is still drawn
    // A title that fits keeps the large size: taller ink than the shortened one.
    const sepal::Image short_sheet = sepal::comparison_sheet(a, b, "A", "B", 16);
    int top = 24, bottom = 0;
    for (int y = 0; y < 24; ++y)
        for (int x = gap; x < gap + w; ++x)
            if (short_sheet.at(x, y, 0) < 0.5f) top = std::min(top, y), bottom = std::max(bottom, y);
    CHECK(bottom - top >= 10);
}

TEST_CASE("worst_window: the window holding the largest squared difference, first on ties") {
    sepal::Image a(96, 80, 3), b(96, 80, 3);
    int x = -1, y = -1;
    CHECK_FALSE(sepal::worst_window(a, b, 8, &x, &y));  // equal images: no window
    // A faint difference everywhere in one corner, a strong one at (70, 41): the strong one wins.
    for (int yy = 0; yy < 10; ++yy)
        for (int xx = 0; xx < 10; ++xx) b.at(xx, yy, 0) = 0.02f;
    b.at(70, 41, 1) = 0.5f;
    REQUIRE(sepal::worst_window(a, b, 8, &x, &y));
    // Every 8x8 window holding (70, 41) ties; the first in row-major order starts at 34, 63.
    CHECK(x == 63);
    CHECK(y == 34);
    CHECK_FALSE(sepal::worst_window(a, b, 81, &x, &y));  // larger than the image
    CHECK_FALSE(sepal::worst_window(a, b, 0, &x, &y));
}

TEST_CASE("comparison sheet: a magnified window of the largest difference under the panels") {
    const int w = 128, gap = 8;
    sepal::Image a(w, w, 3), b(w, w, 3);
    const sepal::Image same = sepal::comparison_sheet(a, b, "A", "B", 16);
    // One pixel differs by 16 levels: the second row shows it 8 times larger, in every panel.
    b.at(100, 20, 0) = 16.0f / 255.0f;
    const sepal::Image sheet = sepal::comparison_sheet(a, b, "A", "B", 16);
    REQUIRE(sheet.width == same.width);
    const int side = w / 8, zoom = 8;
    CHECK(sheet.height == same.height + 24 + side * zoom + gap);  // equal images: no second row
    int x0 = -1, y0 = -1;
    REQUIRE(sepal::worst_window(a, b, side, &x0, &y0));
    const int zy = same.height + 24;  // the magnified panels' top
    const int bx = gap + w + gap, hx = gap + 2 * (w + gap);  // B's and the heatmap's columns
    // B's pixel as a zoom x zoom block, its neighbours black; the heatmap's white at full scale.
    const int px = (100 - x0) * zoom, py = (20 - y0) * zoom;
    for (int dy = 0; dy < zoom; ++dy)
        for (int dx = 0; dx < zoom; ++dx) {
            CHECK(sheet.at(bx + px + dx, zy + py + dy, 0) == doctest::Approx(16.0 / 255.0));
            CHECK(sheet.at(hx + px + dx, zy + py + dy, 1) == doctest::Approx(1.0));
        }
    if (px >= 1) CHECK(sheet.at(bx + px - 1, zy + py, 0) == 0.0f);
    // The window is outlined in the first row (just outside it, in every panel).
    CHECK(sheet.at(gap + x0 - 1, 24 + y0, 2) == doctest::Approx(1.0));
    CHECK(sheet.at(gap + x0, 24 + y0, 2) == 0.0f);  // inside: A's own (black) pixel
    // Images under 64 pixels a side keep one row.
    sepal::Image c(32, 32, 3), d(32, 32, 3);
    d.at(3, 3, 0) = 1.0f;
    const sepal::Image small = sepal::comparison_sheet(c, d, "A", "B", 16);
    CHECK(small.height == sepal::comparison_sheet(c, c, "A", "B", 16).height);
}
