// sepal-view's scene mode (ports/windowed/scene_view.h) and the scene bundle it reads
// (ports/common/scene_bundle.h): the kiosk headless and in a window under Xvfb draw what
// `sepal render --scene` draws, bit for bit; the window takes drags and backend keys; bad
// bundles are refused with the line.
#include <doctest/doctest.h>

#include <fstream>

#include "common/scene_bundle.h"
#include "port_fixtures.h"
#include "test_util.h"
#include "util/image.h"

namespace {

sepal::Image read_png(const std::string& path) {
    sepal::Image img;
    std::string err;
    REQUIRE_MESSAGE(sepal::read_image(path, &img, &err), err);
    return img;
}

}  // namespace

TEST_CASE("sepal-view --scene: headless and in a window under Xvfb, the frame sepal render draws") {
    for (const char* p : {"xvfb-run", "xdotool", "xauth"})
        REQUIRE_MESSAGE(port_test::have_program(p), std::string(p) << " is missing: run `make deps`");
    const std::string dir = sepal_test::temp_dir(), bundle = dir + "/bundle";
    const std::string kiosk = sepal_test::source_path("examples/kiosk.json");
    std::string out;
    REQUIRE_MESSAGE(sepal_test::run_cmd("render", {"--scene", kiosk, "--export", bundle}, &out) == 0, out);
    REQUIRE_MESSAGE(sepal_test::run_cmd("render", {"--scene", kiosk, "--time", "4", "-o", dir + "/render.png"}, &out) == 0,
                    out);
    const std::string view = sepal_test::bin("sepal-view");
    // From the .json (through the sepal tool) and from the bundle.
    REQUIRE_MESSAGE(sepal_test::run(view + " --scene " + kiosk + " --headless --time 4 -o " + dir + "/json.png 2>&1", &out) == 0, out);
    REQUIRE_MESSAGE(sepal_test::run(view + " --scene " + bundle + " --headless --time 4 -o " + dir + "/bundle.png 2>&1", &out) == 0, out);
    const sepal::Image render = read_png(dir + "/render.png");
    CHECK(read_png(dir + "/json.png").data == render.data);
    CHECK(read_png(dir + "/bundle.png").data == render.data);
    // On an RGB565 pbuffer (each object's passes summed in 8 bits), the same frame as render's.
    REQUIRE_MESSAGE(sepal_test::run_cmd("render", {"--scene", kiosk, "--time", "4", "--framebuffer", "565", "-o",
                                                   dir + "/render565.png"}, &out) == 0, out);
    REQUIRE_MESSAGE(sepal_test::run(view + " --scene " + bundle + " --headless --framebuffer 565 --time 4 -o " + dir +
                                        "/bundle565.png 2>&1", &out) == 0, out);
    const sepal::Image render565 = read_png(dir + "/render565.png");
    CHECK(read_png(dir + "/bundle565.png").data == render565.data);
    CHECK(render565.data != render.data);
    CHECK(sepal_test::run(view + " --scene " + bundle + " --framebuffer 565 2>&1", &out) == 2);
    CHECK(out.find("--framebuffer applies with --headless") != std::string::npos);
    // A window: two frames at t = 4, the last one's pixels.
    const std::string xvfb = "timeout 180 xvfb-run -a -s '-screen 0 800x600x24' ";
    REQUIRE_MESSAGE(sepal_test::run(xvfb + view + " --scene " + bundle + " --time 4 --frames 2 --shot " + dir +
                                        "/window.png 2>&1", &out) == 0, out);
    CHECK(out.find("2 frames, gles1, 640x480: median") != std::string::npos);
    CHECK(read_png(dir + "/window.png").data == render.data);
    // Scripted input: an orbit drag, the next backend twice (GL ES 2, then fused), pause, quit.
    const std::string script =
        "xdotool search --sync --onlyvisible --name '^sepal-view scene' > /dev/null && "
        "xdotool mousemove 200 300 mousedown 1 mousemove 260 280 mouseup 1 key b key b key space && "
        "timeout 60 xdotool search --sync --name 'sepal-view scene: gles2-fused' > /dev/null && echo switched; "
        "xdotool key q";
    const int code = sepal_test::run(xvfb + "sh -c \"" + view + " --scene " + bundle + " & pid=\\$!; " + script +
                                         "; wait \\$pid\" 2>&1", &out);
    CAPTURE(out);
    CHECK(code == 0);
    CHECK(out.find("switched") != std::string::npos);
}

TEST_CASE("scene bundles: bad records are refused with the file and line") {
    const std::string dir = sepal_test::temp_dir();
    struct Case {
        const char* text;
        const char* says;
    } const cases[] = {
        {"scene 1\n", "line 1: not a scene bundle"},
        {"sepal-scene 2\n", "line 1: version '2'"},
        {"sepal-scene 1\nsize 4 4\n", "line 2: size W H"},
        {"sepal-scene 1\nlight spot 0 0 0\n", "line 2: light point|directional"},
        {"sepal-scene 1\nmaterial ../x.sepal\n", "line 2: material FILE.sepal"},
        {"sepal-scene 1\nmesh cube\n", "line 2: "},
        {"sepal-scene 1\nmesh sphere\nobject 0 0 0 0 0 0 0 0 1 0\n", "line 3: object: material or mesh index out of range"},
        {"sepal-scene 1\nteapot\n", "line 2: unknown record 'teapot'"},
        {"sepal-scene 1\nmesh sphere\n", "no objects or no lights"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.text);
        const std::string path = dir + "/scene.txt";
        std::ofstream(path) << c.text;
        sepal_ports::SceneBundle b;
        std::string err;
        CHECK_FALSE(sepal_ports::load_scene_bundle(path, &b, &err));
        CAPTURE(err);
        CHECK(err.find(c.says) != std::string::npos);
    }
    // A mesh file that is not one.
    std::ofstream(dir + "/bad.mesh") << "SEPALMSH\x03";
    std::ofstream(dir + "/scene.txt") << "sepal-scene 1\nmesh bad.mesh\n";
    sepal_ports::SceneBundle b;
    std::string err;
    CHECK_FALSE(sepal_ports::load_scene_bundle(dir + "/scene.txt", &b, &err));
    CHECK(err.find("line 2: bad.mesh: not a bundle mesh") != std::string::npos);
}
