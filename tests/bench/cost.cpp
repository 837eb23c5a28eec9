// sepal-bench-cost: the cost curves users plan with, each with its fitted
// log-log exponent.
//
//   build/bin/sepal-bench-cost [--out DIR] [--frames N] [--quick]
//
// Frame time on GL ES 1.1 (llvmpipe, headless) of a baked Blinn (grey: luminance factors)
// against terms, lights, image side, screen coverage (camera distance) and texture side,
// one knob at a time around a base (2 terms, 1 light, 512 x 512, the default camera, 32 x 32
// factors); bake time and asset bytes against the half-angle factor's side (the ladder's
// shape: the smooth factor at 16, 8 at 128) and against terms. Each point is the median of
// --frames frames (after 2 warm-up frames, each ended by glFinish) or of 3 bakes; the
// exponent b of y = a x^b is the least-squares slope of ln y on ln x over the curve's points.
// Then the fill-rate arithmetic for embedded GPUs: how many full-screen-equivalent passes fit
// VGA at 60 fps, and which of the default bakes' plans fit at 1, 2 and 4 lights.
// Writes DIR/cost.json, DIR/cost.md (the tables) and DIR/cost.png and .svg (log-log panels).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bake/asset_file.h"
#include "bake/bake.h"
#include "bench/bench_cli.h"
#include "bench/json_builder.h"
#include "brdf/brdf.h"
#include "spec/spec.h"
#include "common/render_gl.h"
#include "common/scene_flags.h"
#include "util/io.h"
#include "util/plot.h"

namespace {

using Clock = std::chrono::steady_clock;

struct Point {
    double x = 0, y = 0;
};

struct Curve {
    std::string name, x_label, y_label;
    std::vector<Point> points;
    double exponent = NAN;
    Curve(std::string n, std::string x, std::string y) : name(std::move(n)), x_label(std::move(x)), y_label(std::move(y)) {}
};

[[noreturn]] void die(const std::string& m) {
    std::fprintf(stderr, "sepal-bench-cost: %s\n", m.c_str());
    std::exit(1);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? NAN : v[v.size() / 2];
}

// Least-squares slope of ln y on ln x.
double loglog_slope(const std::vector<Point>& p) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (const Point& q : p) {
        if (!(q.x > 0) || !(q.y > 0)) continue;
        const double x = std::log(q.x), y = std::log(q.y);
        sx += x, sy += y, sxx += x * x, sxy += x * y, ++n;
    }
    const double d = n * sxx - sx * sx;
    return n >= 2 && d > 0 ? (n * sxy - sx * sy) / d : NAN;
}

struct Baked {
    std::vector<uint8_t> bytes;
    double seconds = 0;
};

// Blinn baked at one configuration: gs-half, G at `res`, H at `smooth`, `terms` terms.
Baked bake_blinn(int res, int smooth, int terms, int runs) {
    std::string err;
    std::unique_ptr<sepal::Brdf> f = sepal::make_brdf("blinn", &err);
    if (!f) die(err);
    sepal::BakeOptions o;
    o.params = {sepal::Param::GsHalf};
    o.resolutions = {res};
    o.smooth_resolutions = {smooth};
    o.terms = {terms};
    Baked b;
    std::vector<double> times;
    for (int r = 0; r < runs; ++r) {
        sepal::BakeResult result;
        const auto t0 = Clock::now();
        if (!sepal::bake(*f, o, &result, &err)) die("bake: " + err);
        times.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
        if (!sepal::encode_asset(result.asset, &b.bytes, &err)) die(err);
    }
    b.seconds = median(times);
    return b;
}

sepal_ports::SceneSetup scene(int side, int lights, double distance_scale) {
    sepal_ports::SceneSetup s;
    s.width = s.height = side;
    const float eye[3] = {0.0f, -3.2f, 1.4f};
    for (int c = 0; c < 3; ++c) s.scene.camera.eye[c] = float(eye[c] * distance_scale);
    s.scene.camera.z_near = 0.05f;
    s.scene.camera.z_far = float(4.0 * distance_scale + 2.0);
    s.camera_given = true;
    s.scene.light_count = lights;
    for (int l = 0; l < lights; ++l) {
        s.scene.lights[l] = s.scene.lights[0];
        s.scene.lights[l].type = SEPAL_LIGHT_POINT;
        s.scene.lights[l].position[0] = 2.0f * std::cos(float(l));
        s.scene.lights[l].position[1] = -2.5f;
        s.scene.lights[l].position[2] = 2.0f + float(l);
    }
    std::string err;
    if (!sepal_ports::load_scene_mesh(&s, &err)) die(err);
    return s;
}

// The unit sphere's share of a square image, seen from distance d with the default 38 degree
// vertical field of view: projected radius tan(asin(1/d)) / tan(19 degrees) in NDC.
double sphere_coverage(double d) {
    const double r = std::tan(std::asin(1.0 / d)) / std::tan(19.0 * M_PI / 180.0);
    return std::min(1.0, M_PI * r * r / 4.0);
}

double frame_ms(const std::vector<uint8_t>& bytes, const sepal_ports::SceneSetup& s, int frames) {
    sepal_ports::GlRenderOptions opt;
    opt.frames = frames;
    std::vector<uint8_t> rgba;
    sepal_ports::GlRenderInfo info;
    std::string err;
    if (!sepal_ports::render_asset_headless(bytes.data(), bytes.size(), s, opt, &rgba, &info, &err)) die(err);
    return info.ms;
}

}  // namespace

int main(int argc, char** argv) {
    BenchCli cli("sepal-bench-cost",
                 "Cost curves: frame time against terms, lights, image side, coverage and texture side; bake time and "
                 "bytes against resolution and terms; fitted log-log exponents and the fill-rate arithmetic");
    int frames = 9;
    bool quick = false;
    cli.app.add_option("--frames", frames, "timed frames per point (after 2 warm-up frames)")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    cli.app.add_flag("--quick", quick, "two points per curve, 1 bake per point (a smoke run)");
    if (const int code = cli.parse(argc, argv); code >= 0) return code;
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    const int runs = quick ? 1 : 3;
    auto pick = [&](std::vector<int> v) { return quick ? std::vector<int>{v.front(), v.back()} : v; };
    std::vector<Curve> curves;
    const auto t0 = Clock::now();

    // The base asset and scene, then one knob at a time.
    const Baked base = bake_blinn(32, 32, 2, 1);
    {
        // Warm-up: llvmpipe's first frames of a process compile its state sets.
        frame_ms(base.bytes, scene(512, 1, 1.0), 20);
    }
    Curve terms{"frame vs terms", "terms", "ms/frame"};
    for (int k : pick({1, 2, 4, 8}))
        terms.points.push_back({double(k), frame_ms(bake_blinn(32, 32, k, 1).bytes, scene(512, 1, 1.0), frames)});
    curves.push_back(terms);
    Curve lights{"frame vs lights", "lights", "ms/frame"};
    for (int l : pick({1, 2, 4, 8})) lights.points.push_back({double(l), frame_ms(base.bytes, scene(512, l, 1.0), frames)});
    curves.push_back(lights);
    Curve pixels{"frame vs image pixels", "pixels (side^2)", "ms/frame"};
    for (int side : pick({128, 256, 512, 1024}))
        pixels.points.push_back({double(side) * side, frame_ms(base.bytes, scene(side, 1, 1.0), frames)});
    curves.push_back(pixels);
    Curve coverage{"frame vs coverage", "sphere's share of the image", "ms/frame"};
    for (double d : quick ? std::vector<double>{2.8, 1.0} : std::vector<double>{2.8, 2.0, 1.4, 1.0})
        coverage.points.push_back({sphere_coverage(d * std::sqrt(3.2 * 3.2 + 1.4 * 1.4)),
                                   frame_ms(base.bytes, scene(512, 1, d), frames)});
    curves.push_back(coverage);
    Curve texture{"frame vs texture side", "half-angle factor side (smooth 16)", "ms/frame"};
    for (int r : pick({16, 32, 64, 128}))
        texture.points.push_back({double(r), frame_ms(bake_blinn(r, 16, 2, 1).bytes, scene(512, 1, 1.0), frames)});
    curves.push_back(texture);

    // Bake time and bytes: the ladder's shape, then terms.
    Curve bake_res{"bake vs resolution", "half-angle factor side (smooth 16; 8 at 128)", "seconds"};
    Curve bytes_res{"bytes vs resolution", "half-angle factor side (smooth 16; 8 at 128)", "bytes"};
    for (int r : pick({16, 32, 64, 128})) {
        const Baked b = bake_blinn(r, r >= 128 ? 8 : 16, 2, runs);
        bake_res.points.push_back({double(r), b.seconds});
        bytes_res.points.push_back({double(r), double(b.bytes.size())});
    }
    Curve bake_terms{"bake vs terms", "terms (32/16)", "seconds"};
    Curve bytes_terms{"bytes vs terms", "terms (32/16)", "bytes"};
    for (int k : pick({1, 2, 4, 8})) {
        const Baked b = bake_blinn(32, 16, k, runs);
        bake_terms.points.push_back({double(k), b.seconds});
        bytes_terms.points.push_back({double(k), double(b.bytes.size())});
    }
    curves.push_back(bake_res);
    curves.push_back(bake_terms);
    curves.push_back(bytes_res);
    curves.push_back(bytes_terms);
    for (Curve& c : curves) c.exponent = loglog_slope(c.points);

    // The fill-rate arithmetic: passes per frame at VGA, 60 fps, for GPUs of the class.
    struct Gpu {
        const char* name;
        double mpix_low, mpix_high;  // quoted fill rate, Mpixels/s (one texture per pixel)
    };
    const Gpu gpus[] = {{"Adreno 200", 133, 133}, {"Mali-400 MP1", 210, 500}, {"VideoCore IV", 1000, 1000}};
    const double vga = 640.0 * 480.0, fps = 60.0, covered = 0.4;
    std::string md = "| curve | points (x: y) | exponent |\n|---|---|---:|\n";
    JsonBuilder j;
    j.begin_object().key("seconds").value(std::chrono::duration<double>(Clock::now() - t0).count());
    j.key("base").value("blinn, gs-half, 2 terms, 32/32, 1 light, 512x512, default camera");
    j.key("frames").value(frames).key("curves").begin_array();
    std::printf("%-24s %-9s  points\n", "curve", "exponent");
    for (const Curve& c : curves) {
        std::string pts;
        j.begin_object().key("name").value(c.name).key("x").value(c.x_label).key("y").value(c.y_label);
        j.key("exponent").value(c.exponent).key("points").begin_array();
        for (const Point& p : c.points) {
            char b[64];
            std::snprintf(b, sizeof b, "%s%.4g: %.4g", pts.empty() ? "" : ", ", p.x, p.y);
            pts += b;
            j.begin_array().value(p.x).value(p.y).end_array();
        }
        j.end_array().end_object();
        std::printf("%-24s %-9.2f  %s\n", c.name.c_str(), c.exponent, pts.c_str());
        char row[512];
        std::snprintf(row, sizeof row, "| %s (%s) | %s | %.2f |\n", c.name.c_str(), c.y_label.c_str(), pts.c_str(),
                      c.exponent);
        md += row;
    }
    j.end_array();
    md += "\nPasses per frame that fit 640x480 at 60 fps (full-screen equivalents; a sphere covering "
          "40% of the image pays 40%; a two-texture product pass costs up to twice on GPUs with one "
          "texture unit per pipe):\n\n| GPU | fill Mpix/s | full-screen passes | at 40% coverage | two-texture passes at 40% |\n"
          "|---|---|---:|---:|---:|\n";
    j.key("fill_rate").begin_array();
    // "lo" or "lo-hi" with the given decimals.
    auto range = [](double lo, double hi, int decimals) {
        char b[64];
        if (hi > lo) std::snprintf(b, sizeof b, "%.*f-%.*f", decimals, lo, decimals, hi);
        else std::snprintf(b, sizeof b, "%.*f", decimals, lo);
        return std::string(b);
    };
    for (const Gpu& g : gpus) {
        const double lo = g.mpix_low * 1e6 / (vga * fps), hi = g.mpix_high * 1e6 / (vga * fps);
        md += "| " + std::string(g.name) + " | " + range(g.mpix_low, g.mpix_high, 0) + " | " + range(lo, hi, 1) + " | " +
              range(std::floor(lo / covered), std::floor(hi / covered), 0) + " | " +
              range(std::floor(lo / covered / 2), std::floor(hi / covered / 2), 0) + " |\n";
        j.begin_object().key("gpu").value(g.name).key("mpix_per_s").begin_array().value(g.mpix_low).value(g.mpix_high);
        j.end_array().key("fullscreen_passes").begin_array().value(lo).value(hi).end_array().end_object();
    }
    // Which plans fit: the default bakes' plans have 2-9 passes per light (docs/fidelity.md).
    md += "\nLights a plan can draw at 640x480, 60 fps, 40% coverage, two-texture passes (low end of each "
          "fill rate):\n\n| passes per light |";
    for (const Gpu& g : gpus) md += " " + std::string(g.name) + " |";
    md += "\n|---:|---:|---:|---:|\n";
    for (int passes : {1, 2, 4, 5, 9}) {
        md += "| " + std::to_string(passes) + " |";
        for (const Gpu& g : gpus) {
            const double budget = std::floor(g.mpix_low * 1e6 / (vga * fps) / covered / 2);
            md += " " + std::to_string(int(budget) / passes) + " |";
        }
        md += "\n";
    }
    j.end_array().end_object();
    std::printf("\n%s", md.substr(md.find("Passes per frame")).c_str());

    std::vector<sepal::PlotPanel> panels;
    for (const Curve& c : curves) {
        sepal::PlotPanel p;
        char title[128];
        std::snprintf(title, sizeof title, "%s: exponent %.2f", c.name.c_str(), c.exponent);
        p.title = title;
        p.x_label = c.x_label + " (log)";
        p.y_label = c.y_label;
        p.log_x = true;
        sepal::PlotSeries sr;
        sr.label = "measured";
        sr.colour = sepal::plot_colour(0);
        for (const Point& q : c.points) sr.x.push_back(q.x), sr.y.push_back(q.y);
        p.series.push_back(sr);
        panels.push_back(p);
    }
    std::string err;
    const std::string json = j.str();
    if (!sepal::write_file_atomic(cli.out + "/cost.json", json.data(), json.size(), &err) ||
        !sepal::write_file_atomic(cli.out + "/cost.md", md.data(), md.size(), &err) ||
        !sepal::write_plot(cli.out + "/cost.png", panels, 3, 420, 320, &err) ||
        !sepal::write_plot(cli.out + "/cost.svg", panels, 3, 420, 320, &err))
        die(err);
    std::printf("wrote %s/cost.json, cost.md, cost.png and cost.svg\n", cli.out.c_str());
    return 0;
}
