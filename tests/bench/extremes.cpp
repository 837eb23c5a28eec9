// The runtime's extreme cases as a contact sheet for a person to look at (make bench):
// one row per case, one tile per backend (every GL path and fallback mask, the CPU
// backend, and the exact render where the case has an analytic BRDF), labelled with the
// built-in font of offline/util/plot.h. Writes OUT/extremes.png and OUT/extremes.json (per
// tile: case, backend, finite, PSNR and largest difference against the CPU backend and
// against exact, every sepal_draw_stats counter, the GL path taken; or refused and why).
//
//   build/bin/sepal-bench-extremes [--out DIR]     (default build/bench)
//
// The cases are tests/extremes_test.cpp's (tests/extremes_runtime_cases.h), plus
// the encoder's side where this branch's encoder can be asked: an all-zero BRDF and 1x1
// factors baked by the offline library (refused today, shown as refused tiles with the
// reason), and a MERL table with NaN and inf samples baked and drawn.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "bake/bake.h"
#include "extremes_runtime_cases.h"
#include "util/image.h"
#include "util/io.h"
#include "util/json.h"
#include "measured/merl.h"
#include "util/plot.h"
#include "bench/bench_cli.h"
#include "common/render_gl.h"
#include "reference/render_exact.h"
#include "spec/spec.h"

using namespace extremes;

namespace {

constexpr int kTile = 96;      // tiles are kTile x kTile
constexpr int kLabelW = 232;   // row labels on the left
constexpr int kHeaderH = 22;   // column labels on top
constexpr int kCaptionH = 22;  // two text lines under each tile
constexpr int kPad = 4;

struct Row {
    std::string name, group, note;
    std::string refused;           // non-empty: the encoder refused; why
    std::vector<uint8_t> bytes;    // the asset
    sepal_ports::SceneSetup scene;
    std::unique_ptr<sepal::Brdf> exact;  // the analytic BRDF, if any
    std::string exact_spec;
};

struct Column {
    std::string label;  // short, fits a tile
    bool exact = false;
    Backend backend;
};

std::string short_label(const Backend& b) {
    if (b.cpu) return "cpu";
    std::string s;
    if (b.mode == SEPAL_MODE_FUSED_VERTEX) return "gles2 fused";
    if (b.mode == SEPAL_MODE_FUSED_PIXEL) return "gles2 fused-px";
    if (b.float_target) return "gles2 half-float";
    s = b.gles == 1 ? "gles1" : "gles2";
    if (b.mask & SEPAL_MASK_BLEND_SUBTRACT) s += " -sub";
    if (b.mask & SEPAL_MASK_MULTITEXTURE) s += " -mtex";
    if (b.mask & SEPAL_MASK_FBO) s += " -fbo-npot";
    return s;
}

bool bytes_of(const sepal::AssetData& a, Row* r) {
    std::string err;
    if (!encode(a, &r->bytes, &err)) {
        r->refused = "encode: " + err;
        return false;
    }
    return true;
}

// The rows, in order. Baked rows go through the offline library; a refusal is kept.
std::vector<Row> make_rows() {
    std::vector<Row> rows;
    auto quad = [&](const std::string& name, const QuadConfig& q, sepal_param p, const std::string& note) {
        Row r;
        r.name = name;
        r.group = "frames";
        r.note = note;
        r.scene = quad_scene(q, kTile, kTile);
        bytes_of(lobe_asset(p, 32), &r);
        rows.push_back(std::move(r));
    };
    quad("grazing 89.9/89.9 gs-half", {QuadLight::kDirectional, 89.9, 89.9, 20}, SEPAL_PARAM_GS_HALF,
         "light and view at 89.9 degrees, irradiance 20 at the centre");
    quad("grazing 89.9/89.9 rusinkiewicz", {QuadLight::kDirectional, 89.9, 89.9, 20}, SEPAL_PARAM_RUSINKIEWICZ,
         "the same, rusinkiewicz asset (per-pixel backends only)");
    quad("retro 89.9: h 0.1 deg from t", {QuadLight::kAtEye, 89.9, 89.9, 20}, SEPAL_PARAM_GS_HALF,
         "point light at the eye, wi = wo at 89.9 along t: gs-half near its singularity");
    quad("retro 89.99: h 0.01 deg from t", {QuadLight::kAtEye, 89.99, 89.99, 20}, SEPAL_PARAM_GS_HALF,
         "within 1e-3 rad of h = t: the gs-half fallback frame, counted");
    quad("normal incidence: h = n", {QuadLight::kAtEye, 0, 0, 1.2}, SEPAL_PARAM_RUSINKIEWICZ,
         "rusinkiewicz pole at every vertex");
    quad("mirror 86: h = n", {QuadLight::kMirror, 86, 86, 1.2}, SEPAL_PARAM_RUSINKIEWICZ,
         "mirror pairs, 83..89 degrees, h = n exactly at every vertex");
    quad("light below horizon 90.1", {QuadLight::kDirectional, 90.1, 60, 1}, SEPAL_PARAM_GS_HALF,
         "every vertex-light pair below: black, counted");
    quad("view below horizon 120", {QuadLight::kDirectional, 45, 120, 1}, SEPAL_PARAM_GS_HALF,
         "back-facing shading frames: black, counted");
    {
        Row r;
        r.name = "broken mesh";
        r.group = "meshes";
        r.note = "13 degenerate tangents, 4 NaN/zero/inf vertices (24 triangles skipped), 7 zero-area triangles";
        BrokenMesh m = broken_sphere(2);
        r.scene = std::move(m.broken);
        rebind(&r.scene);
        r.scene.width = r.scene.height = kTile;
        bytes_of(signed_asset(SEPAL_PARAM_GS_HALF), &r);
        for (sepal_light& l : r.scene.scene.lights)
            for (float& c : l.intensity) c *= 4.0f;  // the signed asset is dim
        rows.push_back(std::move(r));
    }
    auto sphere_row = [&](const std::string& name, const std::string& note) {
        Row r;
        r.name = name;
        r.group = "assets";
        r.note = note;
        r.scene = sphere_scene(2, kTile, kTile);
        return r;
    };
    auto baked = [&](const std::string& name, const std::string& spec, sepal_param p, int res, const std::string& note) {
        Row r = sphere_row(name, note);
        sepal::AssetData a;
        std::string err;
        if (bake_asset(spec, p, res, &a, &err))
            bytes_of(a, &r);
        else
            r.refused = "encoder: " + err;
        r.exact = sepal::make_brdf(spec, &err);
        r.exact_spec = spec;
        rows.push_back(std::move(r));
    };
    auto built = [&](const std::string& name, const sepal::AssetData& a, const std::string& note, double constant = -1) {
        Row r = sphere_row(name, note);
        bytes_of(a, &r);
        if (constant >= 0) {
            r.exact = std::make_unique<ConstantBrdf>(constant);
            r.exact_spec = "constant " + std::to_string(constant);
        }
        rows.push_back(std::move(r));
    };
    baked("phong n=1e4 (baked)", "phong:n=10000", SEPAL_PARAM_GS_HALF, 32, "gs-half 32x32, 1 NMF term");
    baked("ward alpha=1e-3 (baked)", "ward:ax=0.001,ay=0.001", SEPAL_PARAM_GS_HALF, 32, "gs-half 32x32, 1 NMF term");
    built("huge peaks 1e4", huge_peak_asset(), "0.3/sr plus a 1e4 spike at h = n, 16-bit textures");
    built("tiny values 1e-8", tiny_asset(), "f ~ 6e-9/sr");
    built("all zero (hand-built)", zero_asset(), "every texel 0", 0.0);
    baked("all zero (baked)", "lambert:rho=0", SEPAL_PARAM_IV, 32, "the encoder's all-zero BRDF");
    built("1x1 textures (hand-built)", constant_asset(SEPAL_PARAM_IV, 1, 0.125), "f = 0.125, 1x1 G and H", 0.125);
    baked("1x1 textures (baked)", "lambert", SEPAL_PARAM_IV, 1, "lambert through the encoder at res 1");
    built("256x256 textures", lobe_asset(SEPAL_PARAM_GS_HALF, 256), "the lobe asset at 256x256");
    {
        // A MERL table of blinn:n=20 with 1000 NaN red, 1000 +inf green and 10 -inf blue
        // samples: the encoder treats them as missing; the exact render is the clean blinn.
        Row r = sphere_row("MERL with NaN and inf (baked)", "blinn:n=20 as MERL, 2010 NaN/inf samples");
        std::unique_ptr<sepal::Brdf> clean;
        std::string err;
        clean = sepal::make_brdf("blinn:n=20", &err);
        std::vector<uint8_t> merl;
        if (clean && sepal::encode_merl(*clean, &merl, &err)) {
            const size_t n = 90 * 90 * 180;
            auto poke = [&](size_t plane, size_t i, double v) { std::memcpy(&merl[12 + 8 * (plane * n + i)], &v, 8); };
            for (size_t k = 0; k < 1000; ++k) {
                poke(0, (k * 1457) % n, NAN);
                poke(1, (k * 1457) % n, INFINITY);
            }
            for (size_t k = 0; k < 10; ++k) poke(2, k * 99991, -INFINITY);
            std::unique_ptr<sepal::Brdf> measured = sepal::make_merl_brdf(merl, "nan-inf.binary", &err);
            sepal::BakeOptions o;
            sepal::AssetData a;
            if (measured) {
                // bake_asset takes a spec; this one is a table in memory.
                o.params = {sepal::Param::GsHalf};
                o.resolutions = {32};
                o.methods = {sepal::Method::NMF};
                o.terms = {1};
                sepal::BakeResult res;
                if (sepal::bake(*measured, o, &res, &err)) {
                    bytes_of(res.asset, &r);
                } else {
                    r.refused = "encoder: " + err;
                }
            } else {
                r.refused = "encoder: " + err;
            }
        } else {
            r.refused = "gen-merl: " + err;
        }
        r.exact = std::move(clean);
        r.exact_spec = "blinn:n=20 (the table's clean source)";
        rows.push_back(std::move(r));
    }
    {
        Row r = sphere_row("light 1e12: exposure clamp", "GL ES 1.1 needs 2^37; clamped at 2^-30, counted");
        for (float& c : r.scene.scene.lights[0].intensity) c = 1e12f;
        r.scene.scene.light_count = 1;
        bytes_of(lobe_asset(SEPAL_PARAM_GS_HALF, 32), &r);
        rows.push_back(std::move(r));
    }
    {
        Row r = sphere_row("light 3e38 at 0.05: overflow", "intensity / d^2 overflows float: clamped, counted");
        const float near[3] = {0.0f, -1.05f, 0.0f};
        std::copy(near, near + 3, r.scene.scene.lights[0].position);
        for (float& c : r.scene.scene.lights[0].intensity) c = 3e38f;
        r.scene.scene.light_count = 1;
        bytes_of(lobe_asset(SEPAL_PARAM_GS_HALF, 32), &r);
        rows.push_back(std::move(r));
    }
    for (Row& r : rows) rebind(&r.scene);
    return rows;
}

void blit(sepal::Image* sheet, const sepal::Image& tile, int x0, int y0) {
    for (int y = 0; y < tile.height && y0 + y < sheet->height; ++y)
        for (int x = 0; x < tile.width && x0 + x < sheet->width; ++x)
            for (int c = 0; c < 3; ++c) sheet->at(x0 + x, y0 + y, c) = tile.at(x, y, c);
}

void fill(sepal::Image* sheet, int x0, int y0, int w, int h, const glm::dvec3& colour) {
    for (int y = std::max(0, y0); y < std::min(sheet->height, y0 + h); ++y)
        for (int x = std::max(0, x0); x < std::min(sheet->width, x0 + w); ++x)
            for (int c = 0; c < 3; ++c) sheet->at(x, y, c) = float(colour[c]);
}

sepal::Json stats_json(const sepal_draw_stats& s) {
    sepal::Json j = {{"draw_calls", s.draw_calls},
                     {"fullscreen_passes", s.fullscreen_passes},
                     {"copies", s.copies},
                     {"doublings", s.doublings},
                     {"exposure", double(s.exposure)},
                     {"exposure_stages", s.exposure_stages}};
    for (const sepal_ports::DrawCounter& c : sepal_ports::draw_counters(s)) j[c.name] = c.value;
    return j;
}

// The counters worth a glance, as short tokens that fit under a tile.
std::string counters(const sepal_draw_stats& s) {
    std::string out;
    auto add = [&](const char* tag, int v) {
        if (v == 0) return;
        const std::string t = std::string(tag) + std::to_string(v);
        if (out.size() + t.size() + 1 > 16) return;
        out += (out.empty() ? "" : " ") + t;
    };
    add("sk", s.skipped_triangles);
    add("t", s.fallback_tangents);
    add("bv", s.bad_vertices);
    add("z", s.zero_area_triangles);
    add("ec", s.exposure_clamped);
    add("nf", s.nonfinite_clamped);
    add("bh", s.below_horizon);
    add("pf", s.param_fallbacks);
    if (s.exposure_stages > 1) add("st", s.exposure_stages);
    return out;
}

std::string fmt_db(double psnr) {
    char buf[32];
    if (std::isinf(psnr)) return "identical";
    std::snprintf(buf, sizeof buf, "%.1f dB", psnr);
    return buf;
}

}  // namespace

int main(int argc, char** argv) {
    const auto start = std::chrono::steady_clock::now();
    BenchCli cli("sepal-bench-extremes", "The runtime's extreme cases on every backend: a contact sheet and JSON.");
    if (const int code = cli.parse(argc, argv); code >= 0) return code;
    const std::string& out_dir = cli.out;
    std::string err;
    const std::vector<Row> rows = make_rows();
    std::vector<Column> cols;
    for (const Backend& b : all_backends()) cols.push_back({short_label(b), false, b});
    cols.push_back({"exact", true, Backend{}});
    const int W = kLabelW + int(cols.size()) * (kTile + kPad) + kPad;
    const int rowh = kTile + kCaptionH + kPad;
    const int legend_h = 5 * 10 + 8;
    const int H = kHeaderH + int(rows.size()) * rowh + legend_h;
    sepal::Image sheet(W, H, 3);
    std::fill(sheet.data.begin(), sheet.data.end(), 1.0f);
    const glm::dvec3 ink(0.1, 0.1, 0.1), red(0.8, 0.1, 0.1), grey(0.45, 0.45, 0.45), blue(0.1, 0.25, 0.7);
    for (size_t c = 0; c < cols.size(); ++c)
        sepal::draw_text(&sheet, kLabelW + int(c) * (kTile + kPad) + kPad, 7, cols[c].label, ink);
    sepal::Json j;
    j["what"] = "the runtime's extreme cases on every backend (tests/extremes_test.cpp)";
    j["tile"] = kTile;
    j["reference"] = ("psnr_cpu / max_diff_cpu: against the CPU backend (the precise reference of the same "
                             "factored material); psnr_exact / max_diff_exact: against the exact render of the "
                             "analytic BRDF, where the row has one; 8-bit display levels of the clamped images");
    j["columns"] = sepal::Json::array();
    for (const Column& c : cols) j["columns"].push_back(c.label);
    j["tiles"] = sepal::Json::array();
    int tiles = 0, refused_tiles = 0, nonfinite_tiles = 0;
    for (size_t r = 0; r < rows.size(); ++r) {
        const Row& row = rows[r];
        const int y0 = kHeaderH + int(r) * rowh;
        sepal::draw_text(&sheet, kPad, y0 + 4, row.name, ink);
        sepal::draw_text(&sheet, kPad, y0 + 16, row.group, grey);
        std::printf("%-34s", row.name.c_str());
        std::fflush(stdout);
        sepal::Image cpu_image;
        sepal_draw_stats cpu_stats{};
        bool have_cpu = false;
        sepal::Image exact_image;
        bool have_exact = false;
        if (row.exact) {
            sepal::ExactStats es;
            have_exact = sepal::render_exact(*row.exact, row.scene.scene, row.scene.mesh, row.scene.width,
                                             row.scene.height, &exact_image, &es, &err);
        }
        if (row.refused.empty()) {
            const Frame cpu = render(cols[cols.size() - 2].backend, row.bytes, row.scene);
            have_cpu = cpu.ok;
            cpu_image = cpu.image;
            cpu_stats = cpu.stats;
        }
        for (size_t c = 0; c < cols.size(); ++c) {
            const Column& col = cols[c];
            const int x0 = kLabelW + int(c) * (kTile + kPad) + kPad;
            sepal::Json t = {{"case", row.name},
                             {"group", row.group},
                             {"note", row.note},
                             {"backend", col.exact ? std::string("exact") : col.backend.name},
                             {"row", int(r)},
                             {"column", int(c)}};
            ++tiles;
            Frame f;
            if (col.exact) {
                f.ok = have_exact;
                f.err = row.exact ? err : "no analytic BRDF for this case";
                f.image = exact_image;
                f.finite = have_exact && all_finite(exact_image);
                if (have_exact) t["exact_spec"] = row.exact_spec;
            } else if (!row.refused.empty()) {
                f.ok = false;
                f.err = row.refused;
            } else if (col.backend.cpu) {
                f.ok = have_cpu;
                f.image = cpu_image;
                f.stats = cpu_stats;
                f.finite = have_cpu && all_finite(cpu_image);
                if (!have_cpu) f.err = "cpu backend failed";
            } else {
                f = render(col.backend, row.bytes, row.scene);
            }
            if (!f.ok) {
                const bool refused = !row.refused.empty() || f.err.find("per-pixel") != std::string::npos;
                fill(&sheet, x0, y0, kTile, kTile, glm::dvec3(0.88, 0.88, 0.88));
                const bool no_brdf = col.exact && !row.exact;
                if (no_brdf) {
                    sepal::draw_text(&sheet, x0 + 4, y0 + kTile / 2 - 4, "no BRDF", grey);
                } else {
                    sepal::draw_text(&sheet, x0 + 4, y0 + kTile / 2 - 4, refused ? "refused" : "FAILED", red);
                    ++refused_tiles;
                }
                // refused: the encoder or the runtime declined, with its reason in not_drawn.
                t["drawn"] = false;
                t["refused"] = !no_brdf && refused;
                t["not_drawn"] = f.err;
                j["tiles"].push_back(std::move(t));
                std::printf(" %c", col.exact ? '-' : 'x');
                std::fflush(stdout);
                continue;
            }
            blit(&sheet, display(f.image), x0, y0);
            t["drawn"] = true;
            t["finite"] = f.finite;
            if (!f.finite) ++nonfinite_tiles;
            std::string caption;
            if (have_cpu && !col.backend.cpu && !col.exact) {
                const sepal::ImageDiff d = sepal::diff_images(display(cpu_image), display(f.image), 0);
                t["psnr_cpu"] = d.psnr;
                t["max_diff_cpu"] = d.max_diff;
                caption = fmt_db(d.psnr);
            }
            if (have_exact && !col.exact) {
                const sepal::ImageDiff d = sepal::diff_images(display(exact_image), display(f.image), 0);
                t["psnr_exact"] = d.psnr;
                t["max_diff_exact"] = d.max_diff;
                if (col.backend.cpu) caption = "ex " + fmt_db(d.psnr);
            }
            if (col.backend.cpu && !have_exact) caption = "reference";
            if (col.exact) caption = "exact";
            if (!f.finite) caption = "NOT FINITE";
            if (!col.exact) {
                t["stats"] = stats_json(f.stats);
                t["path"] = f.path;
            }
            j["tiles"].push_back(std::move(t));
            sepal::draw_text(&sheet, x0, y0 + kTile + 3, caption, f.finite ? ink : red);
            if (!col.exact) sepal::draw_text(&sheet, x0, y0 + kTile + 12, counters(f.stats), blue);
            std::printf(" .");
            std::fflush(stdout);
        }
        std::printf("\n");
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    j["summary"] = {{"tiles", tiles}, {"refused_or_failed", refused_tiles}, {"not_finite", nonfinite_tiles},
                    {"seconds", seconds}};
    // Legend.
    const char* legend[] = {
        "dB: PSNR of the displayed tile against the cpu tile; cpu column: 'ex' against the exact render.",
        "Counters: sk skipped triangles, t fallback tangents, bv bad vertices, z zero-area triangles,",
        "ec exposure clamped, nf non-finite clamped, bh below horizon, pf parameterization fallbacks,",
        "st exposure stages (GL: per vertex / vertex-light; cpu: per pixel / pixel-light). Every number: extremes.json.",
        "refused: the encoder (baked rows) or the runtime (per-pixel-only assets on per-vertex paths) said why."};
    for (int i = 0; i < 5; ++i)
        sepal::draw_text(&sheet, kPad, H - legend_h + 4 + 10 * i, legend[i], ink);
    const std::string png = out_dir + "/extremes.png", json = out_dir + "/extremes.json";
    if (!sepal::write_png(png, sheet, &err) ||
        !sepal::write_json_file(json, j, &err)) {
        std::fprintf(stderr, "sepal-bench-extremes: %s\n", err.c_str());
        return 1;
    }
    std::printf("%d tiles (%d refused or failed, %d not finite) in %.1f s\nwrote %s\nwrote %s\n", tiles, refused_tiles,
                nonfinite_tiles, seconds, png.c_str(), json.c_str());
    return nonfinite_tiles == 0 ? 0 : 1;
}
