#include "util/plot.h"

#include "util/io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <stb/stb_easy_font.h>

namespace sepal {

namespace {
void put(Image* img, int x, int y, const glm::dvec3& c) {
    if (x < 0 || y < 0 || x >= img->width || y >= img->height) return;
    for (int k = 0; k < 3; ++k) img->at(x, y, k) = float(c[k]);
}

void fill_rect(Image* img, int x0, int y0, int x1, int y1, const glm::dvec3& c) {
    for (int y = std::max(0, y0); y <= std::min(img->height - 1, y1); ++y)
        for (int x = std::max(0, x0); x <= std::min(img->width - 1, x1); ++x) put(img, x, y, c);
}

void line(Image* img, int x0, int y0, int x1, int y1, const glm::dvec3& c, int thick) {
    // Bresenham, thickened by a square brush.
    const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
    const int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
    int err = dx + dy;
    for (int guard = 0; guard < 100000; ++guard) {
        fill_rect(img, x0 - thick / 2, y0 - thick / 2, x0 + (thick - 1) / 2, y0 + (thick - 1) / 2, c);
        if (x0 == x1 && y0 == y1) break;
        const int e2 = 2 * err;
        if (e2 >= dy) err += dy, x0 += sx;
        if (e2 <= dx) err += dx, y0 += sy;
    }
}

// Where draw_panel draws: pixels (the PNG figures) or SVG elements (the same layout, with
// real fonts a browser scales). Text y is the top of a 7-pixel line at scale 1; anchor 0
// starts at x, 1 centres on it, 2 ends at it.
class Canvas {
  public:
    virtual ~Canvas() = default;
    virtual void line(int x0, int y0, int x1, int y1, const glm::dvec3& c, int thick) = 0;
    virtual void rect(int x0, int y0, int x1, int y1, const glm::dvec3& c) = 0;  // filled, inclusive
    virtual void text(int x, int y, const std::string& s, const glm::dvec3& c, int scale, int anchor) = 0;
    int text_width(const std::string& s, int scale) const { return sepal::text_width(s, scale); }
};

class ImageCanvas : public Canvas {
  public:
    explicit ImageCanvas(Image* img) : img_(img) {}
    void line(int x0, int y0, int x1, int y1, const glm::dvec3& c, int thick) override {
        sepal::line(img_, x0, y0, x1, y1, c, thick);
    }
    void rect(int x0, int y0, int x1, int y1, const glm::dvec3& c) override { fill_rect(img_, x0, y0, x1, y1, c); }
    void text(int x, int y, const std::string& s, const glm::dvec3& c, int scale, int anchor) override {
        draw_text(img_, x - anchor * text_width(s, scale) / 2, y, s, c, scale);
    }

  private:
    Image* img_;
};

std::string svg_colour(const glm::dvec3& c) {
    char b[16];
    std::snprintf(b, sizeof b, "#%02x%02x%02x", int(std::lround(std::clamp(c.x, 0.0, 1.0) * 255)),
                  int(std::lround(std::clamp(c.y, 0.0, 1.0) * 255)), int(std::lround(std::clamp(c.z, 0.0, 1.0) * 255)));
    return b;
}

std::string svg_escape(const std::string& s) {
    std::string out;
    for (char ch : s) {
        if (ch == '&') out += "&amp;";
        else if (ch == '<') out += "&lt;";
        else if (ch == '>') out += "&gt;";
        else if (ch == '"') out += "&quot;";
        else if (static_cast<unsigned char>(ch) >= 32) out += ch;
    }
    return out;
}

class SvgCanvas : public Canvas {
  public:
    std::string body;
    void line(int x0, int y0, int x1, int y1, const glm::dvec3& c, int thick) override {
        char b[160];
        std::snprintf(b, sizeof b, "<line x1=\"%d\" y1=\"%d\" x2=\"%d\" y2=\"%d\" stroke=\"%s\" stroke-width=\"%d\"/>\n",
                      x0, y0, x1, y1, svg_colour(c).c_str(), thick);
        body += b;
    }
    void rect(int x0, int y0, int x1, int y1, const glm::dvec3& c) override {
        char b[160];
        std::snprintf(b, sizeof b, "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"%s\"/>\n", x0, y0,
                      x1 - x0 + 1, y1 - y0 + 1, svg_colour(c).c_str());
        body += b;
    }
    void text(int x, int y, const std::string& s, const glm::dvec3& c, int scale, int anchor) override {
        static const char* kAnchor[] = {"start", "middle", "end"};
        char b[200];
        std::snprintf(b, sizeof b, "<text x=\"%d\" y=\"%d\" font-size=\"%d\" fill=\"%s\" text-anchor=\"%s\">", x,
                      y + 8 * scale, 10 * scale + (scale > 1 ? 0 : 1), svg_colour(c).c_str(), kAnchor[std::clamp(anchor, 0, 2)]);
        body += b + svg_escape(s) + "</text>\n";
    }
};

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

// A step of 1, 2 or 5 times a power of ten giving at most about `target` intervals.
double nice_step(double span, int target) {
    if (!(span > 0)) return 1;
    const double raw = span / target, p = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * p >= raw) return m * p;
    return 10 * p;
}

void draw_panel(Canvas* img, int ox, int oy, int w, int h, const PlotPanel& p) {
    const glm::dvec3 black(0), grey(0.55), light(0.88);
    const int left = 62, right = 14, top = 30, bottom = 44;
    const int x0 = ox + left, x1 = ox + w - right, y0 = oy + top, y1 = oy + h - bottom;
    // Data ranges.
    double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
    for (const PlotSeries& s : p.series)
        for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
            const double x = s.x[i], y = s.y[i];
            if (!std::isfinite(x) || !std::isfinite(y) || (p.log_y && !(y > 0)) || (p.log_x && !(x > 0))) continue;
            xmin = std::min(xmin, x), xmax = std::max(xmax, x);
            ymin = std::min(ymin, y), ymax = std::max(ymax, y);
        }
    if (xmin > xmax) xmin = p.log_x ? 0.1 : 0, xmax = 1, ymin = p.log_y ? 0.1 : 0, ymax = 1;
    if (xmin == xmax) {
        if (p.log_x) xmin *= 0.5, xmax *= 2;
        else xmin -= 0.5, xmax += 0.5;
    }
    double lo, hi;
    if (p.log_y) {
        lo = std::floor(std::log10(ymin)), hi = std::ceil(std::log10(ymax));
        if (lo == hi) hi += 1;
    } else {
        const double st = nice_step(ymax - ymin, 6);
        lo = std::floor(ymin / st) * st, hi = std::ceil(ymax / st) * st;
        if (lo == hi) hi = lo + st;
    }
    // On a log x axis positions are in log10 units.
    auto xt = [&](double x) { return p.log_x ? std::log10(x) : x; };
    const double xpad = 0.04 * (xt(xmax) - xt(xmin));
    const double xa = xt(xmin) - xpad, xb = xt(xmax) + xpad;
    auto px = [&](double x) { return x0 + int(std::lround((xt(x) - xa) / (xb - xa) * (x1 - x0))); };
    auto py = [&](double y) {
        const double t = p.log_y ? (std::log10(y) - lo) / (hi - lo) : (y - lo) / (hi - lo);
        return y1 - int(std::lround(t * (y1 - y0)));
    };
    // Grid and y ticks.
    if (p.log_y) {
        const int decades = int(hi - lo);
        for (int d = int(lo); d <= int(hi); ++d)
            for (int m : {1, 2, 5}) {
                const double v = m * std::pow(10.0, d);
                if (std::log10(v) > hi + 1e-9) continue;
                const int y = py(v);
                const bool major = m == 1;
                img->line(x0, y, x1, y, major ? light : glm::dvec3(0.95), 1);
                img->line(x0 - (major ? 6 : 3), y, x0, y, black, 1);
                if (major || decades <= 2) {
                    const std::string s = number(v);
                    img->text(x0 - 9, y - 3, s, major ? black : grey, 1, 2);
                }
            }
    } else {
        const double st = nice_step(hi - lo, 6);
        for (double v = lo; v <= hi + 1e-9 * st; v += st) {
            const int y = py(v);
            img->line(x0, y, x1, y, light, 1);
            img->line(x0 - 6, y, x0, y, black, 1);
            const std::string s = number(v);
            img->text(x0 - 9, y - 3, s, black, 1, 2);
        }
    }
    // x ticks.
    if (p.log_x) {
        for (int d = int(std::floor(xa)); d <= int(std::ceil(xb)); ++d)
            for (int m : {1, 2, 5}) {
                const double v = m * std::pow(10.0, d), t = std::log10(v);
                if (t < xa || t > xb) continue;
                const int x = px(v);
                img->line(x, y0, x, y1, m == 1 ? light : glm::dvec3(0.95), 1);
                img->line(x, y1, x, y1 + (m == 1 ? 5 : 3), black, 1);
                const std::string s = number(v);
                img->text(x, y1 + 9, s, m == 1 ? black : grey, 1, 1);
            }
    } else {
        const double xs = std::max(nice_step(xmax - xmin, 8), 1e-12);
        for (double v = std::ceil(xmin / xs) * xs; v <= xmax + 1e-9 * xs; v += xs) {
            const int x = px(v);
            img->line(x, y1, x, y1 + 5, black, 1);
            const std::string s = number(v);
            img->text(x, y1 + 9, s, black, 1, 1);
        }
    }
    // Frame, labels, title.
    img->line(x0, y0, x1, y0, black, 1);
    img->line(x0, y1, x1, y1, black, 1);
    img->line(x0, y0, x0, y1, black, 1);
    img->line(x1, y0, x1, y1, black, 1);
    img->text((x0 + x1) / 2, y1 + 24, p.x_label, black, 1, 1);
    img->text(ox + 6, oy + 18, p.y_label, grey, 1, 0);
    img->text((x0 + x1) / 2, oy + 2, p.title, black, 2, 1);
    // Series.
    for (const PlotSeries& s : p.series) {
        int lx = 0, ly = 0;
        bool have = false;
        for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
            const double x = s.x[i], y = s.y[i];
            if (!std::isfinite(x) || !std::isfinite(y) || (p.log_y && !(y > 0)) || (p.log_x && !(x > 0))) {
                have = false;
                continue;
            }
            const int cx = px(x), cy = py(y), m = std::clamp(s.marker, 1, 6);
            if (have && s.lines) img->line(lx, ly, cx, cy, s.colour, 2);
            img->rect(cx - m, cy - m, cx + m, cy + m, s.colour);
            lx = cx, ly = cy, have = true;
        }
    }
    // Legend, top right inside the frame.
    int lw = 0;
    for (const PlotSeries& s : p.series) lw = std::max(lw, img->text_width(s.label, 1));
    if (!p.series.empty()) {
        const int bw = lw + 34, bh = int(p.series.size()) * 12 + 6;
        const int bx = x1 - bw - 6, by = y0 + 6;
        img->rect(bx, by, bx + bw, by + bh, glm::dvec3(1));
        img->line(bx, by, bx + bw, by, grey, 1);
        img->line(bx, by + bh, bx + bw, by + bh, grey, 1);
        img->line(bx, by, bx, by + bh, grey, 1);
        img->line(bx + bw, by, bx + bw, by + bh, grey, 1);
        for (size_t i = 0; i < p.series.size(); ++i) {
            const int yy = by + 6 + int(i) * 12;
            img->line(bx + 5, yy + 3, bx + 23, yy + 3, p.series[i].colour, 2);
            img->rect(bx + 12, yy + 1, bx + 16, yy + 5, p.series[i].colour);
            img->text(bx + 28, yy, p.series[i].label, black, 1, 0);
        }
    }
}
}  // namespace

// stb_easy_font (in the stb package we already use for PNGs) draws text as quads of
// 1-pixel segments; each quad is an axis-aligned rectangle, scaled here by whole pixels.
namespace {
// stb_easy_font indexes its glyph table with ch - 32: printable ASCII only.
std::string printable(const std::string& text) {
    std::string s;
    for (unsigned char ch : text) s += ch >= 32 && ch <= 126 ? char(ch) : '?';
    return s;
}
}  // namespace

int text_width(const std::string& text, int scale) {
    std::string s = printable(text);
    return stb_easy_font_width(&s[0]) * std::max(1, scale);
}

int draw_text(Image* img, int x, int y, const std::string& text, const glm::dvec3& colour,
              int scale) {
    scale = std::max(1, scale);
    std::string s = printable(text);
    if (s.empty()) return 0;
    struct Vertex {
        float x, y, z;
        unsigned char rgba[4];
    };
    // No glyph has more than 11 segments (4 vertices each); 16 leaves room.
    std::vector<Vertex> v(s.size() * 64);
    const int quads = stb_easy_font_print(0, 0, &s[0], nullptr, v.data(), int(v.size() * sizeof(Vertex)));
    for (int q = 0; q < quads; ++q) {
        const Vertex& a = v[size_t(q) * 4];
        const Vertex& b = v[size_t(q) * 4 + 2];  // the corner opposite a
        fill_rect(img, x + int(a.x) * scale, y + int(a.y) * scale, x + int(b.x) * scale - 1, y + int(b.y) * scale - 1,
                  colour);
    }
    return text_width(s, scale);
}

glm::dvec3 plot_colour(int index) {
    static const glm::dvec3 palette[] = {{0.84, 0.19, 0.15}, {0.16, 0.40, 0.75}, {0.20, 0.63, 0.17},
                                         {0.60, 0.31, 0.64}, {0.95, 0.55, 0.05}, {0.35, 0.35, 0.35},
                                         {0.10, 0.65, 0.70}, {0.65, 0.45, 0.20}};
    return palette[((index % 8) + 8) % 8];
}

Image render_plot(const std::vector<PlotPanel>& panels, int columns, int panel_w, int panel_h) {
    panel_w = std::clamp(panel_w, 160, 2000);
    panel_h = std::clamp(panel_h, 160, 2000);
    columns = std::max(1, std::min(columns, int(std::max<size_t>(1, panels.size()))));
    const int rows = std::max(1, int((panels.size() + size_t(columns) - 1) / size_t(columns)));
    Image img(columns * panel_w, rows * panel_h, 3);
    std::fill(img.data.begin(), img.data.end(), 1.0f);
    ImageCanvas canvas(&img);
    for (size_t i = 0; i < panels.size(); ++i)
        draw_panel(&canvas, int(i % size_t(columns)) * panel_w, int(i / size_t(columns)) * panel_h, panel_w, panel_h,
                   panels[i]);
    return img;
}

std::string render_plot_svg(const std::vector<PlotPanel>& panels, int columns, int panel_w, int panel_h) {
    panel_w = std::clamp(panel_w, 160, 2000);
    panel_h = std::clamp(panel_h, 160, 2000);
    columns = std::max(1, std::min(columns, int(std::max<size_t>(1, panels.size()))));
    const int rows = std::max(1, int((panels.size() + size_t(columns) - 1) / size_t(columns)));
    SvgCanvas canvas;
    for (size_t i = 0; i < panels.size(); ++i)
        draw_panel(&canvas, int(i % size_t(columns)) * panel_w, int(i / size_t(columns)) * panel_h, panel_w, panel_h,
                   panels[i]);
    char head[320];
    std::snprintf(head, sizeof head,
                  "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" "
                  "font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\">\n<rect width=\"100%%\" height=\"100%%\" "
                  "fill=\"#ffffff\"/>\n",
                  columns * panel_w, rows * panel_h, columns * panel_w, rows * panel_h);
    return head + canvas.body + "</svg>\n";
}

bool worst_window(const Image& a, const Image& b, int side, int* x0, int* y0) {
    const Image ra = to_rgb(a), rb = to_rgb(b);
    const int w = ra.width, h = ra.height;
    if (side < 1 || side > w || side > h || rb.width != w || rb.height != h) return false;
    // Summed-area table of the squared differences, one row and column of zeros in front.
    std::vector<double> sat(size_t(w + 1) * size_t(h + 1), 0.0);
    auto at = [&](int x, int y) -> double& { return sat[size_t(y) * size_t(w + 1) + size_t(x)]; };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double e = 0;
            for (int c = 0; c < 3; ++c) {
                const double d = double(ra.at(x, y, c)) - rb.at(x, y, c);
                e += d * d;
            }
            at(x + 1, y + 1) = e + at(x, y + 1) + at(x + 1, y) - at(x, y);
        }
    double best = 0;
    for (int y = 0; y + side <= h; ++y)
        for (int x = 0; x + side <= w; ++x) {
            const double e = at(x + side, y + side) - at(x, y + side) - at(x + side, y) + at(x, y);
            if (e > best) best = e, *x0 = x, *y0 = y;
        }
    return best > 0;
}

bool sheet_window(const Image& a, const Image& b, SheetWindow* out) {
    const int small = std::min(a.width, a.height);
    if (small < 64) return false;
    out->side = small / 8;
    out->zoom = small / out->side;
    return worst_window(a, b, out->side, &out->x, &out->y);
}

namespace {

// A one-pixel outline just outside a window of a panel drawn at (px, py) on the sheet.
void outline(Image* out, int px, int py, int x0, int y0, int side, const glm::dvec3& colour) {
    auto put = [&](int x, int y) {
        if (x < 0 || y < 0 || x >= out->width || y >= out->height) return;
        for (int c = 0; c < 3; ++c) out->at(x, y, c) = float(colour[c]);
    };
    for (int t = -1; t <= side; ++t) {
        put(px + x0 + t, py + y0 - 1);
        put(px + x0 + t, py + y0 + side);
        put(px + x0 - 1, py + y0 + t);
        put(px + x0 + side, py + y0 + t);
    }
}

}  // namespace

Image comparison_sheet(const Image& reference, const Image& test, const std::string& reference_title,
                       const std::string& test_title, double full_scale) {
    const Image a = to_rgb(reference), b = to_rgb(test);
    const Image heat = diff_heatmap(a, b, full_scale);
    const int w = a.width, h = a.height, gap = 8, title = 24, bar = 14, ticks = 22;
    // The magnified row: a window an eighth of the smaller side, scaled up to fill it.
    SheetWindow win;
    const bool magnify = sheet_window(a, b, &win);
    const int side = win.side, wx = win.x, wy = win.y, zoom = win.zoom;
    const int zoom_h = magnify ? title + side * zoom + gap : 0;
    Image out(3 * w + 4 * gap, title + h + gap + bar + ticks + zoom_h, 3);
    for (float& v : out.data) v = 1.0f;
    const glm::dvec3 black(0, 0, 0), mark(0.1, 0.75, 1.0);
    const Image* panels[3] = {&a, &b, &heat};
    char scale_text[64];
    std::snprintf(scale_text, sizeof scale_text, "|difference|, 8-bit levels");
    const std::string titles[3] = {reference_title, test_title, scale_text};
    for (int k = 0; k < 3; ++k) {
        const int x0 = gap + k * (w + gap);
        // A title wider than its panel would run into the next one: half size, then its tail
        // (a path's end names the file) behind "..".
        const int max_chars = std::max(3, w / 6);
        std::string t = titles[k];
        if (int(t.size()) > max_chars) t = ".." + t.substr(t.size() - size_t(max_chars - 2));
        const int scale = int(t.size()) * 12 <= w ? 2 : 1;
        draw_text(&out, x0 + std::max(0, (w - int(t.size()) * 6 * scale) / 2), scale == 2 ? 4 : 8, t, black, scale);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c) out.at(x0 + x, title + y, c) = panels[k]->at(x, y, c);
    }
    // The colour bar under the heatmap, with its scale in 8-bit levels.
    const int bx = gap + 2 * (w + gap), by = title + h + gap;
    for (int x = 0; x < w; ++x) {
        float rgb[3];
        heat_colour(double(x) / std::max(1, w - 1), rgb);
        for (int y = 0; y < bar; ++y)
            for (int c = 0; c < 3; ++c) out.at(bx + x, by + y, c) = rgb[c];
    }
    for (int t = 0; t <= 4; ++t) {
        char label[32];
        std::snprintf(label, sizeof label, "%g", full_scale * t / 4);
        const int x = bx + (w - 1) * t / 4;
        for (int y = by + bar; y < by + bar + 4; ++y)
            for (int c = 0; c < 3; ++c) out.at(std::min(x, out.width - 1), y, c) = 0.0f;
        const int tw = int(std::string(label).size()) * 6;
        draw_text(&out, std::clamp(x - tw / 2, 0, out.width - tw), by + bar + 6, label, black);
    }
    if (!magnify) return out;
    const int zy = by + bar + ticks;
    char zoom_text[160];
    std::snprintf(zoom_text, sizeof zoom_text, "the %dx%d window of the largest difference (x %d..%d, y %d..%d), %dx",
                  side, side, wx, wx + side - 1, wy, wy + side - 1, zoom);
    const int text_scale = int(std::string(zoom_text).size()) * 12 <= out.width - 2 * gap ? 2 : 1;
    draw_text(&out, gap, text_scale == 2 ? zy + 4 : zy + 8, zoom_text, black, text_scale);
    for (int k = 0; k < 3; ++k) {
        const int x0 = gap + k * (w + gap);
        outline(&out, x0, title, wx, wy, side, mark);
        for (int y = 0; y < side * zoom; ++y)
            for (int x = 0; x < side * zoom; ++x)
                for (int c = 0; c < 3; ++c)
                    out.at(x0 + x, zy + title + y, c) = panels[k]->at(wx + x / zoom, wy + y / zoom, c);
    }
    return out;
}

bool write_plot(const std::string& path, const std::vector<PlotPanel>& panels, int columns, int panel_w,
                int panel_h, std::string* err) {
    if (path.size() >= 4 && path.compare(path.size() - 4, 4, ".svg") == 0) {
        const std::string svg = render_plot_svg(panels, columns, panel_w, panel_h);
        return write_file_atomic(path, svg.data(), svg.size(), err);
    }
    return write_png(path, render_plot(panels, columns, panel_w, panel_h), err);
}

}  // namespace sepal
