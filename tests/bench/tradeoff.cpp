// sepal-bench-tradeoff: the speed-accuracy trade, measured (make bench).
//
//   build/bin/sepal-bench-tradeoff [--out DIR] [--quick] [--size N] [--frames N]
//
// For each material (anisotropic ward, cook-torrance, poulin-fournier, velvet and the three
// Cornell measurements), gs-half parameterization, every half-angle resolution of the
// bake's ladder (16/16, 32/16, 64/16, 128/8: the lobe's factor G at the first size, the
// smooth H at the second), method (acls, the default non-negative one; wsvd, signed) and
// term count (1, 2, 3, 4, 6), 8 bits, is baked (sepal::bake with a one-configuration search
// and otherwise default options, so the numbers are the bake's own), then drawn on every
// backend (gles1 multipass, gles2-fused, cpu) in a fixed scene (the default sphere and point
// light, NxN, default 512): image PSNR against the exact render (4 x 4 samples per pixel),
// the bake's relative cosine-weighted RMS, encoded bytes, plan passes per light, and
// ms/frame (GL: median of --frames frames after 2 warm-up frames, each ended by glFinish;
// cpu: median of 3). The CPU frame is rounded to 8 bits like the GL ones before comparison.
// The sweep is sampled to keep `make bench` short (its 15-minute budget): 8 bits only (GL uploads 8;
// 16 bits bought the cpu backend at most 0.4 dB, and --bits 16 stays in the bake), the
// smooth factor at the ladder's size instead of the half-angle one's (same images, a
// fraction of the matrix: the full square sweep took 58 minutes), and each frame cost timed
// once: a row whose backend, passes, terms and half-angle side match a timed row's draws the
// same work (texel values do not change what a pass costs; the colour mode changes bytes, not
// passes, and bytes bought 0.00 ms/KiB in the fitted models) and takes its ms from it,
// rendering one frame for its image ("ms_from" in the JSON names the material timed).
// Repeated timings of equal work differed by a median 1.18x (max 2.1x) between materials on
// llvmpipe: a second timing added noise, not information. The run prints how many it timed.
//
// Writes DIR/tradeoff.json (rows, the fitted cost models of cost_model.h, the Pareto
// fronts and a check that the bake's --max-error pick lies on the measured front) and
// DIR/tradeoff.png (image error against ms/frame per material, the front marked; the last
// panel is the cost model's predicted against measured ms). Prints the fronts as markdown.
// --quick: two materials, 16 and 32, 1 and 2 terms (a smoke run).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <unistd.h>
#include <vector>

#include "bake/asset_file.h"
#include "bake/bake.h"
#include "bake/cost_model.h"
#include "util/image.h"
#include "util/io.h"
#include "util/json.h"
#include "util/plot.h"
#include "bench/bench_cli.h"
#include "bench/quiet.h"
#include "reference/render_exact.h"
#include "common/render_gl.h"
#include "common/scene_flags.h"
#include "spec/spec.h"

using namespace sepal;

namespace {

struct Material {
    std::string name, spec;
    double cap;
};

struct Row {
    std::string material, backend, method;
    int res = 0, terms = 0, bits = 0;
    bool ok = false;
    std::string note, ms_from;  // ms_from: the material whose row of equal work was timed
    int passes = 0;
    int64_t bytes = 0;
    double err_float = NAN, err_rel = NAN, psnr = NAN, ms = NAN, ms_predicted = NAN;
    bool on_front = false;          // per material, over every backend: ms vs image error
    bool on_backend_front = false;  // per material and backend: ms vs relative RMS (the bake's metric)
    double image_error() const { return std::pow(10.0, -psnr / 20.0); }  // RMS of [0,1] pixels
};

const char* kBackends[] = {"gles1", "gles2-fused", "cpu"};

[[noreturn]] void die(const std::string& m) {
    std::fprintf(stderr, "sepal-bench-tradeoff: %s\n", m.c_str());
    std::exit(1);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? NAN : v[v.size() / 2];
}

// Marks rows[i] (those with keep[i]) that no other kept row beats on both axes.
template <class X, class Y>
void mark_front(std::vector<Row>* rows, const std::vector<size_t>& idx, X x, Y y, bool Row::*flag) {
    for (size_t i : idx) {
        Row& r = (*rows)[i];
        r.*flag = true;
        for (size_t j : idx) {
            const Row& d = (*rows)[j];
            if (x(d) <= x(r) && y(d) <= y(r) && (x(d) < x(r) || y(d) < y(r))) {
                r.*flag = false;
                break;
            }
        }
    }
}

// A material's front (on_front rows), fastest first.
std::vector<const Row*> front_of(const std::vector<Row>& rows, const std::string& material) {
    std::vector<const Row*> front;
    for (const Row& r : rows)
        if (r.ok && r.material == material && r.on_front) front.push_back(&r);
    std::sort(front.begin(), front.end(), [](const Row* a, const Row* b) { return a->ms < b->ms; });
    return front;
}

// Markers of one backend's rows (of one material, or all when material is ""): x = ms.
template <class Y>
PlotSeries scatter(const std::vector<Row>& rows, int backend, const std::string& material, Y y) {
    PlotSeries sr;
    sr.label = kBackends[backend];
    sr.colour = plot_colour(backend);
    sr.lines = false;
    sr.marker = 1;
    for (const Row& r : rows)
        if (r.ok && r.backend == kBackends[backend] && (material.empty() || r.material == material))
            sr.x.push_back(r.ms), sr.y.push_back(y(r));
    return sr;
}

// Milliseconds and dB to the digits the measurement carries (the JSON stays readable).
double rounded(double v, int digits) {
    const double p = std::pow(10.0, digits);
    return std::isfinite(v) ? std::round(v * p) / p : v;
}

}  // namespace

int main(int argc, char** argv) {
    BenchCli cli("sepal-bench-tradeoff", "Image error against frame time: every bake candidate rendered on every backend.");
    bool quick = false;
    int size = 512, frames = 7;
    cli.app.add_flag("--quick", quick, "two materials, 16 and 32, 1 and 2 terms (a smoke run, ~1 minute)");
    cli.app.add_option("--size", size, "frame side, pixels")->check(CLI::Range(16, 2048))->capture_default_str();
    cli.app.add_option("--frames", frames, "timed frames per measurement (after 2 warm-up frames)")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    if (const int code = cli.parse(argc, argv); code >= 0) return code;
    const std::string& dir = cli.out;
    std::string err;
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    const std::string fx = SEPAL_SOURCE_DIR "/fixtures/cornell/";
    std::vector<Material> mats = {{"ward", "ward:rho_d=0.4,rho_s=0.5,ax=0.4,ay=0.15", -1},
                                  {"cook-torrance", "cook-torrance", -1},
                                  {"poulin-fournier", "poulin-fournier", -1},
                                  {"velvet", "velvet", -1},
                                  {"cayman", fx + "cayman.brdf", -1},
                                  {"garnet_red", fx + "garnet_red.brdf", -1},
                                  {"krylon_blue", fx + "krylon_blue.brdf", -1}};
    std::vector<int> resolutions = {16, 32, 64, 128}, terms = {1, 2, 3, 4, 6};
    std::vector<Method> methods = {Method::ACLS, Method::WSVD};
    const std::vector<int> bit_depths = {8};
    // The smooth factor's side for each half-angle side: the bake's ladder.
    auto smooth_side = [](int res) { return res >= 128 ? 8 : 16; };
    if (quick) {
        mats = {mats[0], mats[5]};
        resolutions = {16, 32};
        terms = {1, 2};
    }
    const bool tty = isatty(2) != 0;
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<Row> rows;
    std::string device;
    // Frame ms by the work a row draws (backend, passes, terms, res), and whose it is.
    std::map<std::string, std::pair<double, std::string>> timed;
    // Where the sweep's seconds go (JSON "phase_seconds"), so the next cut aims right.
    double t_exact = 0, t_bake = 0, t_gl = 0, t_cpu = 0;
    auto since = [](std::chrono::steady_clock::time_point a) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
    };
    // One context per GL ES version for the whole sweep: a context per render cost ~100 ms
    // of EGL set-up and shader compiles each (half the GL phase); frames are the same.
    std::unique_ptr<sepal_headless_context, void (*)(sepal_headless_context*)> contexts[2] = {
        {nullptr, sepal_headless_destroy}, {nullptr, sepal_headless_destroy}};
    for (int v = 1; v <= 2; ++v) {
        sepal_headless_desc hd = {};
        hd.width = hd.height = size;
        hd.gles_version = v;
        char msg[512];
        contexts[v - 1].reset(sepal_headless_create(&hd, msg, sizeof msg));
        if (!contexts[v - 1]) die(msg);
    }
    for (const Material& m : mats) {
        std::unique_ptr<Brdf> f = make_brdf(m.spec, &err);
        if (!f) die(err);
        sepal_ports::SceneSetup s;
        s.width = s.height = size;
        if (!sepal_ports::load_scene_mesh(&s, &err)) die(err);
        Image exact;
        const auto te = std::chrono::steady_clock::now();
        if (!render_exact(*f, s.scene, s.mesh, s.width, s.height, &exact, nullptr, &err, false, kReferenceSupersample))
            die(err);
        // As displayed: clamped and rounded to 8 bits (the fidelity bench's reference).
        for (float& v : exact.data) v = std::round(std::min(1.0f, std::max(0.0f, v)) * 255.0f) / 255.0f;
        t_exact += since(te);
        for (int res : resolutions)
            for (Method method : methods) {
                std::fprintf(stderr, "%stradeoff: %s %d %s (%.0f s)%s", tty ? "\r" : "", m.name.c_str(), res,
                             method_name(method), std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                             tty ? "        " : "\n");
                Row base;
                base.material = m.name;
                base.res = res;
                base.method = method_name(method);
                BakeResult r;
                std::string berr;
                bool baked = false;
                {
                    const auto tb = std::chrono::steady_clock::now();
                    BakeOptions o;
                    o.params = {Param::GsHalf};
                    o.resolutions = {res};
                    o.smooth_resolutions = {std::min(res, smooth_side(res))};
                    o.methods = {method};
                    o.terms = terms;
                    o.bits = bit_depths;
                    o.cap = m.cap;
                    o.keep_assets = true;
                    baked = bake(*f, o, &r, &berr);
                    t_bake += since(tb);
                }
                for (int k : terms)
                    for (int bits : bit_depths) {
                        const BakeCandidate* c = nullptr;
                        for (const BakeCandidate& x : r.candidates)
                            if (x.terms == k && x.bits == bits) c = &x;
                        for (const char* backend : kBackends) {
                            Row row = base;
                            row.terms = k;
                            row.bits = bits;
                            row.backend = backend;
                            if (!baked || !c || !c->ok) {
                                row.note = !baked ? berr : c ? c->note : "no candidate";
                                rows.push_back(row);
                                continue;
                            }
                            row.passes = c->passes;
                            row.bytes = c->bytes;
                            row.err_float = c->error_float;
                            row.err_rel = c->error_quantized;
                            std::vector<uint8_t> bytes;
                            if (!encode_asset(c->asset, &bytes, &err)) die(err);
                            const std::string work = row.backend + "/" + std::to_string(row.passes) + "/" +
                                                     std::to_string(k) + "/" + std::to_string(res);
                            const auto seen = timed.find(work);
                            const bool time_it = seen == timed.end();
                            Image img;
                            // A timed frame runs with the other bench lane stopped (quiet.h).
                            std::unique_ptr<BenchQuiet> quiet(time_it ? new BenchQuiet : nullptr);
                            const auto tr = std::chrono::steady_clock::now();
                            if (row.backend == "cpu") {
                                std::vector<double> times;
                                std::vector<float> rgb;
                                for (int i = 0; i < (time_it ? 3 : 1); ++i) {
                                    double ms = 0;
                                    if (!sepal_ports::render_asset_cpu(bytes.data(), bytes.size(), s, nullptr, &rgb, &ms, &err))
                                        die(m.name + " cpu: " + err);
                                    times.push_back(ms);
                                }
                                row.ms = median(times);
                                img = Image(s.width, s.height, 3);
                                img.data = rgb;
                                // What a display shows: clamped and rounded to 8 bits, like GL.
                                for (float& v : img.data) v = std::round(std::min(1.0f, std::max(0.0f, v)) * 255.0f) / 255.0f;
                            } else {
                                sepal_ports::GlRenderOptions opt;
                                if (!sepal_ports::parse_gl_backend(backend, &opt)) die(backend);
                                opt.frames = time_it ? frames : 1;
                                opt.context = contexts[opt.gles_version - 1].get();
                                sepal_ports::GlRenderInfo info;
                                std::vector<uint8_t> px;
                                if (!sepal_ports::render_asset_headless(bytes.data(), bytes.size(), s, opt, &px, &info, &err))
                                    die(m.name + " " + backend + ": " + err);
                                device = info.device;
                                row.ms = info.ms;
                                img = to_rgb(image_from_rgba8(px.data(), s.width, s.height));
                            }
                            quiet.reset();
                            (row.backend == "cpu" ? t_cpu : t_gl) += since(tr);
                            if (time_it) timed[work] = {row.ms, m.name};
                            else row.ms = seen->second.first, row.ms_from = seen->second.second;
                            row.psnr = diff_images(exact, img, 0).psnr;
                            row.ok = std::isfinite(row.psnr) && std::isfinite(row.ms);
                            if (!row.ok) row.note = "non-finite measurement";
                            rows.push_back(row);
                        }
                    }
            }
    }
    if (tty) std::fprintf(stderr, "\r%70s\r", "");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    // Cost models: one per backend, fitted to every material's rows.
    std::vector<CostModel> models;
    for (const char* backend : kBackends) {
        std::vector<CostSample> samples;
        for (const Row& r : rows)
            if (r.ok && r.backend == backend) samples.push_back({r.passes, r.terms, r.bytes, r.ms});
        CostModel cm;
        cm.backend = backend;
        cm.device = device;
        cm.width = cm.height = size;
        if (!fit_cost_model(samples, &cm, &err)) die(std::string(backend) + ": " + err);
        models.push_back(cm);
        for (Row& r : rows)
            if (r.ok && r.backend == backend) r.ms_predicted = cm.predict(r.passes, r.terms, r.bytes);
    }
    // Fronts, and the --max-error pick checked against the measured front.
    // Frame times of equal work differ by up to ~10% between renders on llvmpipe (the quick
    // run's 1-pass rows: 3.1..3.6 ms): a pick counts as on the front within noise unless a
    // row at least 10% faster is as accurate.
    const double kNoise = 0.10;
    int picks = 0, picks_on_front = 0, picks_within_noise = 0;
    std::string pick_misses;
    for (const Material& m : mats) {
        std::vector<size_t> all;
        for (size_t i = 0; i < rows.size(); ++i)
            if (rows[i].ok && rows[i].material == m.name) all.push_back(i);
        mark_front(&rows, all, [](const Row& r) { return r.ms; }, [](const Row& r) { return r.image_error(); },
                   &Row::on_front);
        for (const char* backend : kBackends) {
            std::vector<size_t> idx;
            for (size_t i : all)
                if (rows[i].backend == backend) idx.push_back(i);
            if (idx.empty()) continue;
            mark_front(&rows, idx, [](const Row& r) { return r.ms; }, [](const Row& r) { return r.err_rel; },
                       &Row::on_backend_front);
            // Budgets at the quartiles of the errors: the bake's rule (fastest predicted frame
            // meeting the budget, then lowest error) applied to the measured rows.
            std::vector<double> errs;
            for (size_t i : idx) errs.push_back(rows[i].err_rel);
            std::sort(errs.begin(), errs.end());
            for (double q : {0.25, 0.5, 0.75}) {
                const double budget = errs[size_t(q * double(errs.size() - 1))];
                size_t best = SIZE_MAX;
                for (size_t i : idx) {
                    if (rows[i].err_rel > budget) continue;
                    if (best == SIZE_MAX || std::make_pair(rows[i].ms_predicted, rows[i].err_rel) <
                                                std::make_pair(rows[best].ms_predicted, rows[best].err_rel))
                        best = i;
                }
                ++picks;
                bool beaten = false;
                for (size_t i : idx)
                    beaten = beaten || (rows[i].ms < rows[best].ms * (1 - kNoise) && rows[i].err_rel <= rows[best].err_rel);
                if (!beaten) ++picks_within_noise;
                if (rows[best].on_backend_front) ++picks_on_front;
                else {
                    char b[200];
                    std::snprintf(b, sizeof b, "%s %s budget %.4g: %d %s x%d %db", m.name.c_str(), backend, budget,
                                  rows[best].res, rows[best].method.c_str(), rows[best].terms, rows[best].bits);
                    pick_misses += (pick_misses.empty() ? "" : "; ") + std::string(b);
                }
            }
        }
    }

    Json j;
    j["device"] = device;
    j["size"] = {size, size};
    j["frames"] = frames;
    j["param"] = "gs-half";
    j["seconds"] = rounded(seconds, 1);
    j["timed_rows"] = int(timed.size());
    j["phase_seconds"] = {{"exact", rounded(t_exact, 1)}, {"bake", rounded(t_bake, 1)}, {"gl", rounded(t_gl, 1)},
                          {"cpu", rounded(t_cpu, 1)}};
    j["cost_models"] = Json::array();
    for (const CostModel& c : models)
        j["cost_models"].push_back({{"backend", c.backend},
                                    {"base_ms", c.base_ms},
                                    {"per_pass_ms", c.per_pass_ms},
                                    {"per_term_ms", c.per_term_ms},
                                    {"per_kib_ms", c.per_kib_ms},
                                    {"fit_error", c.fit_error},
                                    {"rows", c.rows}});
    j["max_error_picks"] = {{"checked", picks},
                            {"on_measured_front", picks_on_front},
                            {"within_noise", picks_within_noise},
                            {"noise", kNoise},
                            {"misses", pick_misses}};
    j["materials"] = Json::array();
    for (const Material& m : mats) j["materials"].push_back({{"name", m.name}, {"spec", m.spec}, {"cap", m.cap}});
    j["rows"] = Json::array();
    for (const Row& r : rows) {
        Json x = {{"material", r.material}, {"backend", r.backend}, {"method", r.method}, {"res", r.res},
                  {"terms", r.terms},       {"bits", r.bits},       {"ok", r.ok}};
        if (!r.ok) {
            x["note"] = r.note;
        } else {
            x["passes"] = r.passes;
            x["bytes"] = r.bytes;
            x["psnr"] = rounded(r.psnr, 3);
            x["cos_rms_relative"] = r.err_rel;
            x["cos_rms_relative_float"] = r.err_float;
            x["ms"] = rounded(r.ms, 3);
            if (!r.ms_from.empty()) x["ms_from"] = r.ms_from;
            x["ms_predicted"] = rounded(r.ms_predicted, 3);
            x["on_front"] = r.on_front;
            x["on_backend_front"] = r.on_backend_front;
        }
        j["rows"].push_back(std::move(x));
    }

    // The plot: a panel per material, image RMS error against ms/frame, the front joined;
    // the last panel shows the cost model's predictions against the measured frames.
    std::vector<PlotPanel> panels;
    for (const Material& m : mats) {
        PlotPanel p;
        p.title = m.name;
        p.x_label = "ms/frame (" + std::to_string(size) + "x" + std::to_string(size) + ", log)";
        p.y_label = "image RMS error";
        p.log_x = true;
        for (int b = 0; b < 3; ++b)
            p.series.push_back(scatter(rows, b, m.name, [](const Row& r) { return r.image_error(); }));
        PlotSeries fs;
        fs.label = "Pareto front";
        fs.colour = glm::dvec3(0);
        fs.marker = 3;
        for (const Row* r : front_of(rows, m.name)) fs.x.push_back(r->ms), fs.y.push_back(r->image_error());
        p.series.push_back(fs);
        panels.push_back(p);
    }
    PlotPanel cost;
    cost.title = "cost model";
    cost.x_label = "measured ms/frame (log)";
    cost.y_label = "predicted ms/frame";
    cost.log_x = true;
    for (int b = 0; b < 3; ++b) cost.series.push_back(scatter(rows, b, "", [](const Row& r) { return r.ms_predicted; }));
    panels.push_back(cost);
    if (!write_plot(dir + "/tradeoff.png", panels, 4, 420, 340, &err) ||
        !write_plot(dir + "/tradeoff.svg", panels, 4, 420, 340, &err))
        die(err);

    // For people: the models, the pick check, then each material's front.
    std::printf("trade-off sweep: %zu rows (%zu frame costs timed, the rest drew equal work), %s, %dx%d, %.0f s "
                "(exact %.0f, bake %.0f, GL %.0f, cpu %.0f)\n",
                rows.size(), timed.size(), device.c_str(), size, size, seconds, t_exact, t_bake, t_gl, t_cpu);
    std::printf("\ncost models (ms = base + pass * passes + term * terms + kib * KiB; median |rel. residual|):\n");
    for (const CostModel& c : models)
        std::printf("  %-12s base %.3f  pass %.3f  term %.3f  kib %.4f  fit %.1f%% (%d rows)\n", c.backend.c_str(),
                    c.base_ms, c.per_pass_ms, c.per_term_ms, c.per_kib_ms, 100 * c.fit_error, c.rows);
    std::printf("\n--max-error picks (model-ranked, budgets at error quartiles): on the measured front %d of %d, "
                "within %.0f%% timing noise %d of %d%s%s\n",
                picks_on_front, picks, 100 * kNoise, picks_within_noise, picks,
                pick_misses.empty() ? "" : "\n  strictly off: ", pick_misses.c_str());
    std::printf("\n| material | backend | res | method | terms | bits | passes | bytes | ms/frame | PSNR (dB) | cos RMS |\n");
    std::printf("|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const Material& m : mats)
        for (const Row* r : front_of(rows, m.name))
            std::printf("| %s | %s | %d | %s | %d | %d | %d | %lld | %.2f | %.2f | %.4f |\n", m.name.c_str(),
                        r->backend.c_str(), r->res, r->method.c_str(), r->terms, r->bits, r->passes,
                        (long long)r->bytes, r->ms, r->psnr, r->err_rel);
    // The best image each frame budget buys (docs/reference.md's table): among the rows
    // within 0.1 dB of the best under the budget, the fewest bytes.
    const double budgets[] = {10, 16, 25, 40, 1e30};
    std::printf("\n| material | <= 10 ms | <= 16 ms | <= 25 ms | <= 40 ms | any cost |\n| --- | --- | --- | --- | --- | --- |\n");
    for (const Material& m : mats) {
        std::printf("| %s |", m.name.c_str());
        for (double b : budgets) {
            const Row* best = nullptr;
            for (const Row& r : rows)
                if (r.ok && r.material == m.name && r.ms <= b && (!best || r.psnr > best->psnr)) best = &r;
            const Row* pick = best;
            for (const Row& r : rows)
                if (best && r.ok && r.material == m.name && r.ms <= b && r.psnr >= best->psnr - 0.1 && r.bytes < pick->bytes)
                    pick = &r;
            if (!pick) std::printf(" - |");
            else
                std::printf(" %.1f dB: %s, %d %s x%d, %.1f ms, %.0f KiB |", pick->psnr, pick->backend.c_str(), pick->res,
                            pick->method.c_str(), pick->terms, pick->ms, double(pick->bytes) / 1024.0);
        }
        std::printf("\n");
    }
    // The price of a decibel on gles1 with the default method: each knob's steps (a term more
    // at every resolution; the half-angle side doubled at every term count), the medians of
    // the steps that gained, their frame milliseconds and KiB per dB gained.
    std::printf("\nThe price of 1 dB on gles1 (acls): medians over the knob's steps that gained\n\n"
                "| material | knob | dB per step | ms per dB | KiB per dB |\n| --- | --- | ---: | ---: | ---: |\n");
    Json price = Json::array();
    for (const Material& m : mats) {
        auto at = [&](int res, int terms) -> const Row* {
            for (const Row& r : rows)
                if (r.ok && r.material == m.name && r.backend == "gles1" && r.method == "acls" && r.res == res &&
                    r.terms == terms)
                    return &r;
            return nullptr;
        };
        for (int knob = 0; knob < 2; ++knob) {
            std::vector<double> db, ms_per_db, kib_per_db;
            for (size_t i = 0; i < resolutions.size(); ++i)
                for (size_t t = 0; t < terms.size(); ++t) {
                    const Row* a = at(resolutions[i], terms[t]);
                    const Row* b = knob == 0 ? (t + 1 < terms.size() ? at(resolutions[i], terms[t + 1]) : nullptr)
                                             : (i + 1 < resolutions.size() ? at(resolutions[i + 1], terms[t]) : nullptr);
                    if (!a || !b || !(b->psnr > a->psnr + 0.05)) continue;
                    const double gain = b->psnr - a->psnr;
                    db.push_back(gain);
                    ms_per_db.push_back(std::max(0.0, b->ms - a->ms) / gain);
                    kib_per_db.push_back(double(b->bytes - a->bytes) / 1024.0 / gain);
                }
            const char* name = knob == 0 ? "a term more" : "half-angle side x2";
            if (db.empty()) {
                std::printf("| %s | %s | no step gained | | |\n", m.name.c_str(), name);
                continue;
            }
            std::printf("| %s | %s | %.2f | %.2f | %.1f |\n", m.name.c_str(), name, median(db), median(ms_per_db),
                        median(kib_per_db));
            price.push_back({{"material", m.name}, {"knob", name}, {"db_per_step", median(db)},
                             {"ms_per_db", median(ms_per_db)}, {"kib_per_db", median(kib_per_db)},
                             {"steps", int(db.size())}});
        }
    }
    j["price_of_a_db"] = price;
    if (!write_json_file(dir + "/tradeoff.json", j, &err)) die(err);
    std::printf("\nwrote %s/tradeoff.json and %s/tradeoff.png\n", dir.c_str(), dir.c_str());
    return 0;
}
