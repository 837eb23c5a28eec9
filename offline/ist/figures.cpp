#include "ist/figures.h"

#include <algorithm>
#include <cmath>

#include "factor/factored.h"
#include "util/plot.h"

namespace sepal {

namespace {
constexpr int kLabelH = 14, kGap = 4;
const glm::dvec3 kInk(0.05, 0.05, 0.05);

void fill(Image* img, const glm::dvec3& c) {
    for (size_t p = 0; p < size_t(img->width) * img->height; ++p)
        for (int k = 0; k < 3; ++k) img->data[p * 3 + size_t(k)] = float(c[k]);
}
}  // namespace

Image blend_sheet(const std::vector<BlendRow>& rows, int cell_px) {
    int slots = 0, label_w = 0;
    for (const BlendRow& r : rows) {
        slots = std::max(slots, r.maps.count);
        for (int s : r.order) slots = std::max(slots, s + 1);
        label_w = std::max(label_w, 6 * int(r.label.size()) + 8);
    }
    const int row_h = cell_px + kGap;
    Image sheet(label_w + slots * (cell_px + kGap), std::max(1, int(rows.size()) * row_h), 3);
    fill(&sheet, glm::dvec3(1));
    for (size_t ri = 0; ri < rows.size(); ++ri) {
        const BlendRow& r = rows[ri];
        const int y0 = int(ri) * row_h;
        draw_text(&sheet, 2, y0 + cell_px / 2 - 3, r.label, kInk);
        const BlendMaps& m = r.maps;
        if (m.width < 1 || m.height < 1) continue;
        const int scale = std::max(1, cell_px / std::max(m.width, m.height));
        for (int j = 0; j < m.count; ++j) {
            const int slot = j < int(r.order.size()) && r.order[size_t(j)] >= 0 ? r.order[size_t(j)] : j;
            double peak = 0;
            bool signed_map = false;
            for (int t = 0; t < m.width * m.height; ++t) {
                peak = std::max(peak, double(std::fabs(m.at(t, j))));
                signed_map = signed_map || m.at(t, j) < 0;
            }
            Image tile(m.width, m.height, 3);
            for (int t = 0; t < m.width * m.height; ++t) {
                const double v = peak > 0 ? m.at(t, j) / peak : 0.0;
                float* px = &tile.data[size_t(t) * 3];
                if (signed_map) {
                    px[0] = float(std::max(0.0, v));
                    px[1] = float(std::max(0.0, -v));
                    px[2] = 0;
                } else {
                    px[0] = px[1] = px[2] = float(std::max(0.0, v));
                }
            }
            paste_image(&sheet, tile, label_w + slot * (cell_px + kGap), y0, scale);
        }
    }
    return sheet;
}

Image curve_sheet(const ShadeTree& t) {
    static const char* const kTitles[4] = {"G theta", "G phi", "H theta", "H phi"};
    std::vector<PlotPanel> panels;
    for (int j = 0; j < t.basis_count(); ++j)
        for (int i = 0; i < 4; ++i) {
            PlotPanel p;
            p.title = "basis " + std::to_string(j) + ": " + kTitles[i];
            p.x_label = "degrees";
            p.y_label = "value (luminance)";
            p.log_y = false;
            const std::vector<TreeTerm>& terms = t.bases[size_t(j)].terms;
            for (size_t k = 0; k < terms.size(); ++k) {
                const Curve& c = terms[k].curve(i);
                PlotSeries s;
                s.label = "term " + std::to_string(k);
                s.colour = plot_colour(int(k));
                s.marker = 1;
                for (size_t q = 0; q < c.x.size(); ++q) {
                    s.x.push_back(c.x[q] * 180 / 3.14159265358979323846);
                    s.y.push_back(luminance(c.y[q]));
                }
                p.series.push_back(std::move(s));
            }
            panels.push_back(std::move(p));
        }
    return render_plot(panels, 4, 300, 220);
}

void ist_default_scene(sepal_scene* s) {
    sepal_scene_default(s);
    const float eye[3] = {0.0f, -1.9f, 2.3f}, light[3] = {0.0f, 1.1f, 2.0f}, side[3] = {-2.5f, -1.0f, 2.0f};
    std::copy(eye, eye + 3, s->camera.eye);
    s->camera.fovy_degrees = 40.0f;
    s->light_count = 2;
    std::copy(light, light + 3, s->lights[0].position);
    for (int c = 0; c < 3; ++c) s->lights[0].intensity[c] = 12.0f;
    s->lights[1].type = SEPAL_LIGHT_POINT;
    std::copy(side, side + 3, s->lights[1].position);
    for (int c = 0; c < 3; ++c) s->lights[1].intensity[c] = 14.0f;
}

Image labelled_grid(const std::vector<std::pair<std::string, Image>>& tiles, int columns) {
    columns = std::max(1, std::min(columns, int(tiles.size())));
    int tw = 1, th = 1;
    for (const auto& t : tiles) tw = std::max(tw, t.second.width), th = std::max(th, t.second.height);
    const int rows = (int(tiles.size()) + columns - 1) / columns;
    Image sheet(columns * (tw + kGap), std::max(1, rows * (th + kLabelH + kGap)), 3);
    fill(&sheet, glm::dvec3(1));
    for (size_t i = 0; i < tiles.size(); ++i) {
        const int x0 = int(i) % columns * (tw + kGap), y0 = int(i) / columns * (th + kLabelH + kGap);
        draw_text(&sheet, x0 + 2, y0 + 3, tiles[i].first, kInk);
        Image tile = to_rgb(tiles[i].second);
        for (float& v : tile.data) v = std::min(1.0f, std::max(0.0f, v));
        paste_image(&sheet, tile, x0, y0 + kLabelH);
    }
    return sheet;
}

}  // namespace sepal
