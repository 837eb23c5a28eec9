// The windowed viewer (ports/windowed) driven like a user: sepal-view in an Xvfb server,
// real X input through XTEST (xdotool): an orbit drag, a light drag, backend and material
// keys, the PSNR key and three screenshots. Each screenshot comes with the command that
// renders the same view headless; the test renders it (ports/common/render_gl, the same
// llvmpipe) and holds the window's pixels to the golden tests' tolerance; and it holds
// them to the CPU backend's render of the same view (no GL code in common), so a runtime
// that draws wrong fails here (checked by skipping a pass in the GL ES 2 and 1.1
// executors). The third screenshot shows a copy of the asset with one term's pass masked:
// it must miss the tolerance against the intact asset, and meet it against its own.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "brdf/brdf.h"
#include "spec/spec.h"
#include "common/orbit.h"
#include "common/render_gl.h"
#include "port_fixtures.h"
#include "reference/render_exact.h"
#include "test_util.h"
#include "util/io.h"

namespace {

std::string read_text(const std::string& path) {
    std::ifstream f(path);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

sepal::Image read_png(const std::string& path) {
    sepal::Image img;
    std::string err;
    REQUIRE_MESSAGE(sepal::read_image(path, &img, &err), err);
    return sepal::to_rgb(img);
}

// Angles of v (relative to the target) in degrees: azimuth around z, elevation above xy.
void angles(const float v[3], double* azimuth, double* elevation) {
    const double r = std::sqrt(double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]);
    *azimuth = std::atan2(double(v[1]), double(v[0])) * 180.0 / M_PI;
    *elevation = std::asin(double(v[2]) / r) * 180.0 / M_PI;
}

}  // namespace

TEST_CASE("windowed viewer under Xvfb: scripted input, screenshots against the headless render") {
    for (const char* p : {"xvfb-run", "xdotool", "xauth"})
        REQUIRE_MESSAGE(port_test::have_program(p), std::string(p) << " is missing: run `make deps` (Debian xvfb, xauth, xdotool)");
    const std::string dir = sepal_test::temp_dir();
    const port_test::Assets assets = port_test::bake_assets(dir);
    const std::string shots = dir + "/shots";
    REQUIRE(sepal::make_dirs(shots, nullptr));
    // Pointer at (200,300) in the 3D view (the status line is the top 28 rows). Drag 1:
    // left button, 100 px right: the camera orbits 50 degrees. Drag 2: right button,
    // 40 px up: the light rises 20 degrees. Then: s (shot 1, gles2), B (previous
    // backend: gles1), p (PSNR), s (shot 2), n (next material: masked.sepal), s (shot 3).
    const std::string view = sepal_test::bin("sepal-view") + " " + assets.intact + " --backend gles2 --shot-dir " + shots;
    const std::string script =
        "xdotool search --sync --onlyvisible --name '^sepal-view' > /dev/null && "
        "xdotool mousemove 200 300 mousedown 1 mousemove 300 300 mouseup 1 "
        "mousemove 300 300 mousedown 3 mousemove 300 260 mouseup 3 "
        "key s key B key p key s key n key s key q";
    const std::string command = "timeout 60 xvfb-run -a -s '-screen 0 640x640x24' sh -c \"" + view +
                                " & pid=\\$!; " + script + "; wait \\$pid\"";
    std::string out;
    const int code = sepal_test::run(command, &out);
    CAPTURE(out);
    REQUIRE(code == 0);

    // The scripted drags moved the view by the documented rates (from the default scene).
    sepal_ports::SceneSetup initial;
    port_test::Command c1;
    std::string err;
    REQUIRE_MESSAGE(port_test::parse_command(read_text(shots + "/shot-001.txt"), &c1, &err), err);
    double az0, el0, az1, el1;
    angles(initial.scene.camera.eye, &az0, &el0);
    angles(c1.setup.scene.camera.eye, &az1, &el1);
    CHECK(az1 == doctest::Approx(az0 - 100 * sepal_ports::kOrbitDegreesPerPixel).epsilon(1e-4));
    CHECK(el1 == doctest::Approx(el0).epsilon(1e-4));
    angles(initial.scene.lights[0].position, &az0, &el0);
    angles(c1.setup.scene.lights[0].position, &az1, &el1);
    CHECK(az1 == doctest::Approx(az0).epsilon(1e-4));
    CHECK(el1 == doctest::Approx(el0 + 40 * sepal_ports::kOrbitDegreesPerPixel).epsilon(1e-4));

    const sepal::Tolerance tol = port_test::golden_tolerance();
    std::FILE* figures = std::fopen((sepal_test::output_dir() + "/ports-viewer.txt").c_str(), "w");  // docs/ports.md
    REQUIRE(figures);
    struct Shot {
        const char* name;
        const char* backend;
        const char* asset;  // what the window showed
    } const expected[] = {{"shot-001", "gles2", "intact"}, {"shot-002", "gles1", "intact"}, {"shot-003", "gles1", "masked"}};
    sepal::Image gles1_window;
    for (const Shot& s : expected) {
        CAPTURE(std::string(s.name));
        port_test::Command c;
        REQUIRE_MESSAGE(port_test::parse_command(read_text(shots + "/" + s.name + ".txt"), &c, &err), err);
        CHECK(c.backend == s.backend);
        CHECK(c.asset == (std::string(s.asset) == "intact" ? assets.intact : assets.masked));
        const sepal::Image window = read_png(shots + "/" + s.name + ".png");
        const sepal::Image intact = port_test::render_headless(assets.intact, c.setup, c.backend);
        const sepal::ImageDiff d = sepal::diff_images(intact, window, tol.max_diff);
        std::string why;
        CAPTURE(d.psnr);
        CAPTURE(d.share_over);
        const std::string& shown = std::string(s.asset) == "intact" ? assets.intact : assets.masked;
        const sepal::ImageDiff cpu = sepal::diff_images(port_test::render_cpu(shown, c.setup), window, 8);
        std::fprintf(figures, "%s %s %s: psnr %.2f dB, %.3f%% of pixels over 2 levels, max %.0f; to cpu %.2f dB, %.2f%% over 8\n",
                     s.name, s.backend, s.asset, d.psnr, 100 * d.share_over, d.max_diff, cpu.psnr, 100 * cpu.share_over);
        std::string cpu_why;
        CHECK_MESSAGE(sepal::tolerance_holds(cpu, port_test::cpu_tolerance(), &cpu_why), "against the CPU backend: " << cpu_why);
        if (std::string(s.asset) == "intact") {
            CHECK_MESSAGE(sepal::tolerance_holds(d, tol, &why), why);  // measured: identical (same llvmpipe)
            if (std::string(s.backend) == "gles1") gles1_window = window;
        } else {
            // The masked pass must be caught ...
            CHECK_FALSE(sepal::tolerance_holds(d, tol, &why));
            // ... and the window still shows exactly what the runtime drew for that asset.
            const sepal::Image masked = port_test::render_headless(assets.masked, c.setup, c.backend);
            const sepal::ImageDiff m = sepal::diff_images(masked, window, tol.max_diff);
            CHECK_MESSAGE(sepal::tolerance_holds(m, tol, &why), why);
        }
    }

    std::fclose(figures);
    // p printed the PSNR of shot 2's view against the exact render (through the sepal tool).
    const size_t at = out.find("psnr ");
    REQUIRE(at != std::string::npos);
    const double shown = std::atof(out.c_str() + at + 5);
    port_test::Command c2;
    REQUIRE(port_test::parse_command(read_text(shots + "/shot-002.txt"), &c2, &err));
    auto brdf = sepal::make_brdf("ward:rho_d=0.4,rho_s=0.5,ax=0.4,ay=0.15", &err);
    REQUIRE(brdf);
    sepal::Image exact;
    REQUIRE(sepal::render_exact(*brdf, c2.setup.scene, c2.setup.mesh, c2.setup.width, c2.setup.height, &exact, nullptr,
                                &err));
    for (float& v : exact.data) v = std::min(1.0f, std::max(0.0f, v));
    // The tool writes the exact image as an 8-bit PNG; the test compares the float one.
    CHECK(shown == doctest::Approx(sepal::diff_images(exact, gles1_window, 0).psnr).epsilon(0.01));

    // The window (with its status line) is the screenshot in docs/ports.md.
    const sepal::Image full = read_png(shots + "/shot-002-window.png");
    CHECK(full.width == c2.setup.width);
    CHECK(full.height == c2.setup.height + 28);
    sepal::write_png(sepal_test::output_dir() + "/ports-viewer.png", full, nullptr);
    if (sepal_test::update_goldens())
        REQUIRE(sepal::write_png(sepal_test::source_path("docs/img/viewer.png"), full, &err));
}

TEST_CASE("windowed viewer under Xvfb: a context weaker than the asset's device profile is named once") {
    for (const char* p : {"xvfb-run", "xdotool", "xauth"})
        REQUIRE_MESSAGE(port_test::have_program(p), std::string(p) << " is missing: run `make deps` (Debian xvfb, xauth, xdotool)");
    const std::string dir = sepal_test::temp_dir();
    const port_test::Assets assets = port_test::bake_assets(dir);
    // The asset has no PROF chunk: judged for `default`, two texture units. Masking
    // multitexture leaves the window's context one unit, weaker; without the mask it is not.
    const auto run_viewer = [&](const std::string& mask, std::string* out) {
        const std::string view = sepal_test::bin("sepal-view") + " " + assets.intact + " --gles 1" + mask;
        const std::string command = "timeout 60 xvfb-run -a -s '-screen 0 640x640x24' sh -c \"" + view +
                                    " & pid=\\$!; xdotool search --sync --onlyvisible --name '^sepal-view' > /dev/null && "
                                    "xdotool key q; wait \\$pid\"";
        return sepal_test::run(command, out);
    };
    const std::string warning = "sepal-view: warning: the context is weaker than the device profile 'default'";
    std::string masked, plain;
    REQUIRE(run_viewer(" --mask multitexture", &masked) == 0);
    CAPTURE(masked);
    const size_t at = masked.find(warning);
    CHECK(at != std::string::npos);
    CHECK(masked.find("1 texture unit (the profile's 2)") != std::string::npos);
    CHECK(masked.find(warning, at + 1) == std::string::npos);  // once per material, not per frame
    REQUIRE(run_viewer("", &plain) == 0);
    CAPTURE(plain);
    CHECK(plain.find("weaker than the device profile") == std::string::npos);
}
