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
