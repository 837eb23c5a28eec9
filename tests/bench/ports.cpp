// Ports benchmark (make bench): the frame time of one 2-term asset at 512x512 on every
// port, side by side in one run: the headless EGL port (llvmpipe), the windowed viewer
// under Xvfb (llvmpipe; whole frames with the status line and the swap, and the draw
// alone), and the web page in headless Chromium (WebGL 1 on SwiftShader, driven in real
// time by tests/bench/chromium_page.js). Medians of `frames` frames after two warm-up
// frames. Native frames end with glFinish; web frames with a one-pixel glReadPixels
// (WebGL's finish does not wait for the GPU).
// Usage: sepal-bench-ports OUT_DIR BUILD_DIR [frames]  -> OUT_DIR/ports.json and a table.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench/bench_cli.h"
#include "bench/json_builder.h"
#include "bake/asset_file.h"
#include "bake/bake.h"
#include "brdf/brdf.h"
#include "spec/spec.h"
#include "common/render_gl.h"
#include "common/scene_flags.h"
#include "util/io.h"

namespace {

struct Row {
    std::string port, backend, device;
    double ms = -1;       // the port's frame (what a user waits for)
    double draw_ms = -1;  // sepal_draw and the wait for the GPU alone, where the port tells
    std::string note;
};

std::string run(const std::string& command) {
    std::string out;
    if (FILE* p = popen((command + " 2>&1").c_str(), "r")) {
        char buf[4096];
        size_t n;
        while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
        pclose(p);
    }
    return out;
}

double number_after(const std::string& text, const std::string& label) {
    const size_t at = text.find(label);
    return at == std::string::npos ? -1 : std::atof(text.c_str() + at + label.size());
}

}  // namespace

int main(int argc, char** argv) {
    int frames = 30;
    BenchCli cli("sepal-bench-ports", "The ports: windowed and web frames against the headless render.");
    cli.app.add_option("--frames", frames, "frames per measurement")->check(CLI::Range(1, 10000))->capture_default_str();
    if (const int code = cli.parse(argc, argv); code >= 0) return code;
    const std::string out = cli.out, build = cli.build;
    std::string err;
    if (!sepal::make_dirs(out, &err)) {
        std::fprintf(stderr, "sepal-bench-ports: %s\n", err.c_str());
        return 1;
    }
    // The asset of `make run`: a 2-term NMF Ward, gs-half 32x32, peaks capped at 2.
    const std::string spec = "ward:rho_d=0.4,rho_s=0.5,ax=0.4,ay=0.15";
    auto brdf = sepal::make_brdf(spec, &err);
    sepal::BakeOptions o;
    o.params = {sepal::Param::GsHalf};
    o.methods = {sepal::Method::NMF};
    o.terms = {2};
    o.cap = 2.0;
    sepal::BakeResult baked;
    char abs[4096];
    const std::string asset = std::string(realpath(out.c_str(), abs) ? abs : out.c_str()) + "/ports-bench.sepal";
    if (!brdf || !sepal::bake(*brdf, o, &baked, &err) || !sepal::write_asset(asset, baked.asset, &err)) {
        std::fprintf(stderr, "sepal-bench-ports: %s\n", err.c_str());
        return 1;
    }
    std::vector<uint8_t> bytes;
    sepal_ports::SceneSetup setup;  // 512x512, sphere, the default camera and light
    if (!sepal_ports::read_asset_file(asset, &bytes, &err) || !sepal_ports::load_scene_mesh(&setup, &err)) {
        std::fprintf(stderr, "sepal-bench-ports: %s\n", err.c_str());
        return 1;
    }
    std::vector<Row> rows;
    for (const char* backend : {"gles1", "gles2", "gles2-fused"}) {
        sepal_ports::GlRenderOptions opt;
        sepal_ports::parse_gl_backend(backend, &opt);
        opt.frames = frames;
        std::vector<uint8_t> rgba;
        sepal_ports::GlRenderInfo info;
        Row r{"headless EGL", backend, "", -1, -1, ""};
        if (sepal_ports::render_asset_headless(bytes.data(), bytes.size(), setup, opt, &rgba, &info, &err)) {
            r.ms = r.draw_ms = info.ms;
            r.device = info.device;
        } else {
            r.note = err;
        }
        rows.push_back(r);
    }
    {
        // What sepal-view's exact backend and its 'p' key wait for: the sepal process it runs
        // (4 x 4 samples per pixel at the viewer's 512x512), start-up included.
        const std::string cmd = build + "/bin/sepal render '" + spec + "' --backend exact --size 512x512 -o " + out +
                                "/ports-exact.png";
        std::vector<double> ms;
        std::string text;
        for (int i = 0; i < 3 && text.empty(); ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            const std::string said = run(cmd + " > /dev/null");
            ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
            text = said;  // the command prints nothing but on failure
        }
        std::sort(ms.begin(), ms.end());
        Row r{"sepal process", "exact", "CPU, 4x4 samples per pixel", text.empty() ? ms[ms.size() / 2] : -1, -1,
              text.substr(0, 200)};
        r.draw_ms = r.ms;
        rows.push_back(r);
    }
    const std::string view = build + "/bin/sepal-view";
    for (const char* backend : {"gles1", "gles2", "gles2-fused"}) {
        const std::string text = run("timeout 120 xvfb-run -a -s '-screen 0 640x640x24' " + view + " " + asset +
                                     " --backend " + backend + " --frames " + std::to_string(frames));
        Row r{"windowed, Xvfb", backend, "", number_after(text, "median "), number_after(text, "draw "), ""};
        const size_t open = text.find('('), close = text.rfind(')');
        if (open != std::string::npos && close > open) r.device = text.substr(open + 1, close - open - 1);
        if (r.ms < 0) r.note = text.substr(0, 200);
        rows.push_back(r);
    }
    const std::string index = std::string(SEPAL_SOURCE_DIR) + "/build/web/index.html";  // make web
    const std::string page = "file://" + index;
    // Without the page Chromium would wait out the script's 180 s per backend for nothing.
    std::FILE* index_file = std::fopen(index.c_str(), "rb");
    const bool web_built = index_file != nullptr;
    if (index_file) std::fclose(index_file);
    for (const char* backend : {"gles2", "gles2-fused"}) {
        if (!web_built) {
            rows.push_back(Row{"Chromium WebGL 1", backend, "", -1, -1, "no result: " + index + " missing (make web)"});
            continue;
        }
        const std::string text = run("node " + std::string(SEPAL_SOURCE_DIR) + "/tests/bench/chromium_page.js '" + page +
                                     "?bench=" + std::to_string(frames) + "&backend=" + backend + "&asset=file://" + asset +
                                     "' 180");
        Row r{"Chromium WebGL 1", backend, "", number_after(text, "median_ms "), -1, ""};
        r.draw_ms = r.ms;
        const size_t bar = text.find(" | ", text.find("median_ms ")), bar2 = text.find(" | ", bar + 3);
        if (bar != std::string::npos && bar2 != std::string::npos) r.device = text.substr(bar + 3, bar2 - bar - 3);
        if (r.ms < 0) r.note = "no result (is build/web built? make web)";
        rows.push_back(r);
    }

    std::printf("ports: 2-term NMF Ward (gs-half 32x32), 512x512 sphere, median of %d frames\n", frames);
    std::printf("%-18s %-12s %10s %10s  %s\n", "port", "backend", "frame ms", "draw ms", "device");
    JsonBuilder j;
    j.begin_object().key("asset").value(spec + " nmf x2 gs-half 32 cap 2").key("size").value("512x512");
    j.key("frames").value(frames).key("rows").begin_array();
    for (const Row& r : rows) {
        std::printf("%-18s %-12s %10.2f %10.2f  %s%s\n", r.port.c_str(), r.backend.c_str(), r.ms, r.draw_ms,
                    r.device.c_str(), r.note.empty() ? "" : (" FAILED: " + r.note).c_str());
        j.begin_object().key("port").value(r.port).key("backend").value(r.backend).key("device").value(r.device);
        j.key("frame_ms").value(r.ms).key("draw_ms").value(r.draw_ms).key("note").value(r.note).end_object();
    }
    j.end_array().end_object();
    const std::string json = out + "/ports.json";
    if (!sepal::write_file_atomic(json, j.str().data(), j.str().size(), &err)) {
        std::fprintf(stderr, "sepal-bench-ports: %s\n", err.c_str());
        return 1;
    }
    std::printf("%s\n", json.c_str());
    for (const Row& r : rows)
        if (r.ms < 0) return 1;
    return 0;
}
