// The web port (ports/web, `make web`) in headless Chromium: the page loads two assets by
// URL from disk (file:// with --allow-file-access-from-files; no server), applies an orbit
// and a light drag through the same calls its mouse handlers make, draws each asset on
// gles2 and gles2-fused through WebGL 1 (SwiftShader), and writes the pixels into the DOM.
// Each frame is held to the golden tests' tolerance for another rasterizer against the
// headless EGL render of the same view (llvmpipe), and to the CPU backend's render (no GL
// code in common: a runtime that draws wrong fails, checked by skipping a pass in the
// GL ES 2 executor); the copy with one term's pass masked must miss the first against
// the intact asset. The .wasm size budget is checked here too.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <sys/stat.h>

#include "common/orbit.h"
#include "port_fixtures.h"
#include "test_util.h"

namespace {

std::vector<uint8_t> base64_decode(const std::string& in) {
    static const std::string kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::vector<uint8_t> out;
    uint32_t acc = 0;
    int bits = 0;
    for (char c : in) {
        const size_t v = kAlphabet.find(c);
        if (v == std::string::npos) continue;  // '=' padding
        acc = (acc << 6) | uint32_t(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out.push_back(uint8_t((acc >> bits) & 0xFF));
        }
    }
    return out;
}

std::string url_encode(const std::string& s) {
    std::string out;
    char buf[4];
    for (unsigned char c : s) {
        if (isalnum(c) || c == '-' || c == '_' || c == '.' || c == ',' || c == ':' || c == '/') {
            out += char(c);
        } else {
            std::snprintf(buf, sizeof buf, "%%%02X", c);
            out += buf;
        }
    }
    return out;
}

// The page's #result text after Chromium ran `url` (test mode: one line per frame).
std::string page_result(const std::string& url, const std::string& dir) {
    const std::string command =
        "timeout 90 chromium --headless=new --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader "
        "--allow-file-access-from-files --virtual-time-budget=20000 --dump-dom '" + url + "' 2> " + dir + "/chromium.log";
    std::string dom;
    const int code = sepal_test::run(command, &dom);
    REQUIRE_MESSAGE(code == 0, "chromium failed (" << code << "); see " << dir << "/chromium.log");
    const size_t begin = dom.find("<pre id=\"result\">"), end = dom.find("</pre>", begin);
    REQUIRE_MESSAGE(begin != std::string::npos, dom.substr(0, 2000));
    return dom.substr(begin + 17, end - begin - 17);
}

// One "ok ASSET BACKEND W H BASE64" line of the page's test mode, decoded.
struct PageFrame {
    std::string status, asset, backend;
    int w = 0, h = 0;
    std::vector<uint8_t> rgba;
};
PageFrame parse_frame(const std::string& line) {
    PageFrame f;
    std::string data;
    std::istringstream in(line);
    in >> f.status >> f.asset >> f.backend >> f.w >> f.h >> data;
    f.rgba = base64_decode(data);
    return f;
}

double azimuth(const float v[3]) { return std::atan2(double(v[1]), double(v[0])) * 180.0 / M_PI; }
double elevation(const float v[3]) {
    return std::asin(double(v[2]) / std::sqrt(double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2])) * 180.0 /
           M_PI;
}

}  // namespace

TEST_CASE("web port in headless Chromium: WebGL frames against the headless EGL render") {
    REQUIRE_MESSAGE(port_test::have_program("chromium"), "chromium is missing: run `make deps`");
    const std::string web = sepal_test::source_path("build/web");
    struct stat st;
    REQUIRE_MESSAGE(stat((web + "/sepal.js").c_str(), &st) == 0, "build/web is missing: run `make web`");
    REQUIRE(stat((web + "/sepal.wasm").c_str(), &st) == 0);
    CAPTURE(st.st_size);
    CHECK(st.st_size < 300 * 1024);  // the budget for the runtime's .wasm

    const std::string dir = sepal_test::temp_dir();
    const port_test::Assets assets = port_test::bake_assets(dir);
    const std::string flags = "--mesh torus --light point:-1.5,-2.2,2.6:45";
    const std::string url = "file://" + web + "/index.html?test=1&size=256x256&backends=gles2,gles2-fused" +
                            "&assets=file://" + assets.intact + ",file://" + assets.masked + "&orbit=100,0&light=0,-40" +
                            "&flags=" + url_encode(flags);
    std::istringstream lines(page_result(url, dir));

    // The view after the drags: orbit 100 px right (50 degrees), light 40 px up (20 degrees).
    std::string line, err;
    REQUIRE(std::getline(lines, line));
    REQUIRE(line.rfind("flags ", 0) == 0);
    port_test::Command view;
    REQUIRE_MESSAGE(port_test::parse_command("x " + line.substr(6), &view, &err), err);
    sepal_ports::SceneSetup given;
    std::vector<std::string> words = {"x"};
    for (std::istringstream f(flags); f >> line;) words.push_back(line);
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(&w[0]);
    for (int i = 1; i < int(argv.size()); i += 2) REQUIRE(sepal_ports::parse_scene_flag(int(argv.size()), argv.data(), i, &given, &err) == 2);
    CHECK(view.setup.width == 256);
    CHECK(view.setup.mesh_name == "torus");
    CHECK(azimuth(view.setup.scene.camera.eye) ==
          doctest::Approx(azimuth(given.scene.camera.eye) - 100 * sepal_ports::kOrbitDegreesPerPixel).epsilon(1e-4));
    CHECK(elevation(view.setup.scene.lights[0].position) ==
          doctest::Approx(elevation(given.scene.lights[0].position) + 40 * sepal_ports::kOrbitDegreesPerPixel).epsilon(1e-4));

    // SwiftShader and llvmpipe cover silhouette pixels differently (measured on this view:
    // PSNR 47 dB, 0.6-0.7% of pixels over 2 levels, all on edges).
    const sepal::Tolerance tol = port_test::cross_rasterizer_tolerance();
    int frames = 0;
    // The figures docs/ports.md quotes.
    std::FILE* figures = std::fopen((sepal_test::output_dir() + "/ports-web.txt").c_str(), "w");
    REQUIRE(figures);
    std::fprintf(figures, "wasm_bytes %lld\n", (long long)st.st_size);
    while (std::getline(lines, line) && line != "done") {
        CAPTURE(line.substr(0, 200));
        const PageFrame frame = parse_frame(line);
        REQUIRE(frame.status == "ok");
        REQUIRE(frame.w == 256);
        const int w = frame.w, h = frame.h;
        const std::vector<uint8_t>& rgba = frame.rgba;
        const std::string &asset = frame.asset, &backend = frame.backend;
        REQUIRE(rgba.size() == size_t(w) * h * 4);
        const sepal::Image page = sepal::to_rgb(sepal::image_from_rgba8(rgba.data(), w, h));
        const bool masked = asset.find("masked") != std::string::npos;
        CAPTURE(backend);
        CAPTURE(masked);
        const sepal::Image intact = port_test::render_headless(assets.intact, view.setup, backend);
        const sepal::ImageDiff d = sepal::diff_images(intact, page, tol.max_diff);
        CAPTURE(d.psnr);
        CAPTURE(d.share_over);
        CAPTURE(d.max_diff);
        std::string why;
        const sepal::ImageDiff d2 = sepal::diff_images(intact, page, 2);
        const sepal::ImageDiff cpu =
            sepal::diff_images(port_test::render_cpu(masked ? assets.masked : assets.intact, view.setup), page, 8);
        std::fprintf(figures,
                     "%s %s: psnr %.2f dB, %.2f%% of pixels over 2 levels, %.2f%% over 3, max %.0f; to cpu %.2f dB, %.2f%% over 8\n",
                     masked ? "masked" : "intact", backend.c_str(), d.psnr, 100 * d2.share_over, 100 * d.share_over,
                     d.max_diff, cpu.psnr, 100 * cpu.share_over);
        CHECK_MESSAGE(sepal::tolerance_holds(cpu, port_test::cpu_tolerance(), &why), "against the CPU backend: " << why);
        if (!masked) {
            CHECK_MESSAGE(sepal::tolerance_holds(d, tol, &why), why);
            if (backend == "gles2") sepal::write_png(sepal_test::output_dir() + "/ports-web-gles2.png", page, nullptr);
        } else {
            CHECK_FALSE(sepal::tolerance_holds(d, tol, &why));  // the masked pass is caught
            const sepal::ImageDiff m =
                sepal::diff_images(port_test::render_headless(assets.masked, view.setup, backend), page, tol.max_diff);
            CHECK_MESSAGE(sepal::tolerance_holds(m, tol, &why), why);
        }
        ++frames;
    }
    std::fclose(figures);
    CHECK(frames == 4);
    CHECK(line == "done");

    // The page as a user sees it (docs/ports.md): rewritten with the goldens.
    if (sepal_test::update_goldens()) {
        const std::string shot = sepal_test::source_path("docs/img/web.png");
        const std::string page = "file://" + web + "/index.html?flags=" + url_encode(flags);  // default.sepal
        REQUIRE(sepal_test::run("timeout 90 chromium --headless=new --no-sandbox --use-angle=swiftshader "
                                "--enable-unsafe-swiftshader --allow-file-access-from-files --virtual-time-budget=20000 "
                                "--hide-scrollbars --window-size=560,720 --screenshot=" + shot + " '" + page + "'") == 0);
    }
}

TEST_CASE("web port in headless Chromium: the default page draws the default sphere") {
    // The default scene's 128 x 64 sphere (49,152 indices) overflowed Emscripten's 2 MB
    // client-array ring (GL_MAX_TEMP_BUFFER_SIZE): the draw threw and the page stayed black.
    REQUIRE_MESSAGE(port_test::have_program("chromium"), "chromium is missing: run `make deps`");
    const std::string web = sepal_test::source_path("build/web");
    const std::string dir = sepal_test::temp_dir();
    const std::string url = "file://" + web + "/index.html?test=1&size=128x128&backends=gles2,gles2-fused";
    std::istringstream lines(page_result(url, dir));
    std::string line;
    REQUIRE(std::getline(lines, line));  // flags
    int frames = 0;
    while (std::getline(lines, line) && line != "done") {
        CAPTURE(line.substr(0, 200));
        const PageFrame f = parse_frame(line);
        REQUIRE(f.status == "ok");
        const int w = f.w, h = f.h;
        const std::vector<uint8_t>& rgba = f.rgba;
        REQUIRE(rgba.size() == size_t(w) * h * 4);
        int lit = 0;  // pixels of the lit sphere: about a quarter of the image
        for (size_t i = 0; i < rgba.size(); i += 4) lit += rgba[i] + rgba[i + 1] + rgba[i + 2] > 30 ? 1 : 0;
        CHECK(lit > w * h / 10);
        ++frames;
    }
    CHECK(frames == 2);
    CHECK(line == "done");
}

TEST_CASE("web port in headless Chromium: the kiosk scene bundle (make web) against sepal render --scene") {
    REQUIRE_MESSAGE(port_test::have_program("chromium"), "chromium is missing: run `make deps`");
    const std::string web = sepal_test::source_path("build/web");
    struct stat st;
    REQUIRE_MESSAGE(stat((web + "/kiosk/scene.txt").c_str(), &st) == 0, "build/web/kiosk is missing: run `make web`");
    const std::string dir = sepal_test::temp_dir();
    const std::string url = "file://" + web + "/index.html?test=1&size=640x480&scene=kiosk/scene.txt&time=4" +
                            "&backends=gles2,gles2-fused";
    std::istringstream lines(page_result(url, dir));
    const std::string kiosk = sepal_test::source_path("examples/kiosk.json");
    const sepal::Tolerance tol = port_test::cross_rasterizer_tolerance();
    std::string line;
    int frames = 0;
    while (std::getline(lines, line) && line != "done") {
        CAPTURE(line.substr(0, 200));
        const PageFrame f = parse_frame(line);
        REQUIRE(f.status == "ok");
        REQUIRE(f.w == 640);
        REQUIRE(f.rgba.size() == size_t(640) * 480 * 4);
        const std::string png = dir + "/" + f.backend + ".png";
        std::string out;
        REQUIRE_MESSAGE(sepal_test::run_cmd("render", {"--scene", kiosk, "--time", "4", "--backend", f.backend, "-o", png},
                                            &out) == 0,
                        out);
        sepal::Image native;
        std::string err;
        REQUIRE_MESSAGE(sepal::read_image(png, &native, &err), err);
        const sepal::Image page = sepal::to_rgb(sepal::image_from_rgba8(f.rgba.data(), 640, 480));
        const sepal::ImageDiff d = sepal::diff_images(sepal::to_rgb(native), page, tol.max_diff);
        CAPTURE(f.backend);
        CAPTURE(d.psnr);
        CAPTURE(d.share_over);
        CHECK(d.psnr >= tol.min_psnr);
        CHECK(d.share_over <= tol.max_share);
        MESSAGE("kiosk in the page, " << f.backend << " against sepal render --scene: " << d.psnr << " dB, "
                                      << 100 * d.share_over << "% over " << tol.max_diff << " levels");
        ++frames;
    }
    CHECK(frames == 2);
}
