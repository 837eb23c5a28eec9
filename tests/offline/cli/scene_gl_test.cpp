// The kiosk scene (examples/kiosk.json) as the runtime draws it: every backend against the
// exact render of the same description, the engine's pixels kept bit for bit where no object
// covers them, and objects that overlap on screen ordered by depth, not by draw order.
#include <doctest/doctest.h>

#include <GLES2/gl2.h>

#include <algorithm>
#include <cmath>

#include "cli/scene_file.h"
#include "frame_fixtures.h"
#include "reference/render_exact.h"
#include "test_util.h"

namespace {

// Half the kiosk's 640x480: its thin highlights (the brushed ring's) stay wider than a pixel,
// as at the size it ships at; a quarter aliases them.
constexpr int kW = 320, kH = 240;
constexpr double kTime = 4.0;  // the lights and the camera away from where they start

struct Kiosk {
    sepal::LoadedScene scene;
    sepal::SceneFrame frame;
    Kiosk() {
        sepal::SceneFile f;
        std::string err;
        REQUIRE_MESSAGE(sepal::read_scene_file(sepal_test::source_path("examples/kiosk.json"), &f, &err), err);
        REQUIRE_MESSAGE(sepal::load_scene(f, sepal::default_scene_cache(), &scene, &err), err);
        REQUIRE_MESSAGE(sepal::scene_frame(scene, kTime, kW, kH, &frame, &err), err);
    }
};

const Kiosk& kiosk() {
    static const Kiosk k;
    return k;
}

sepal::Image gl_image(const std::vector<uint8_t>& rgba) {
    return sepal::to_rgb(sepal::image_from_rgba8(rgba.data(), kW, kH));
}

std::vector<uint8_t> gl_render(const sepal::SceneGlOptions& o, const sepal::SceneFrame& fr) {
    std::vector<uint8_t> rgba;
    sepal::SceneGlInfo info;
    std::string err;
    REQUIRE_MESSAGE(sepal::render_scene_gl(kiosk().scene, fr, o, &rgba, &info, &err), err);
    return rgba;
}

// The engine's frame before sepal's objects: its clear colour and a rectangle nearer than
// every object (depth 0.05).
void engine_draws(const float clear[3], const float rect[3]) {
    frame_fx::engine_draws(clear, rect, 120, 90, 60, 40, 0.05f);
}

}  // namespace

TEST_CASE("kiosk scene: gles1, gles2 (multipass, fused) and cpu against exact, >= 38 dB each") {
    const Kiosk& k = kiosk();
    std::string err;
    sepal::Image exact;
    REQUIRE_MESSAGE(sepal::render_scene_exact(k.scene, k.frame, sepal::kReferenceSupersample, &exact, &err), err);
    for (float& v : exact.data) v = std::round(std::min(1.0f, std::max(0.0f, v)) * 255.0f) / 255.0f;
    sepal::write_png(sepal_test::output_dir() + "/kiosk_exact.png", exact, nullptr);
    auto check = [&](const sepal::Image& img, const char* name) {
        const sepal::ImageDiff d = sepal::diff_images(exact, img, 0);
        CAPTURE(std::string(name));
        CAPTURE(d.psnr);
        sepal::write_png(sepal_test::output_dir() + "/kiosk_" + name + ".png", img, nullptr);
        CHECK(d.psnr >= 38.0);
        MESSAGE("kiosk " << kW << "x" << kH << " t=" << kTime << ", " << std::string(name) << " against exact: " << d.psnr << " dB");
    };
    struct Backend {
        const char* name;
        int version;
        sepal_draw_mode mode;
    };
    for (const Backend& b : {Backend{"gles1", 1, SEPAL_MODE_MULTIPASS}, Backend{"gles2", 2, SEPAL_MODE_MULTIPASS},
                             Backend{"gles2-fused", 2, SEPAL_MODE_FUSED_VERTEX},
                             Backend{"gles2-fused-pixel", 2, SEPAL_MODE_FUSED_PIXEL}}) {
        sepal::SceneGlOptions o;
        o.gles_version = b.version;
        o.mode = b.mode;
        check(gl_image(gl_render(o, k.frame)), b.name);
    }
    sepal::Image cpu;
    REQUIRE_MESSAGE(sepal::render_scene_cpu(k.scene, k.frame, &cpu, nullptr, &err), err);
    for (float& v : cpu.data) v = std::min(1.0f, std::max(0.0f, v));
    check(cpu, "cpu");
}

TEST_CASE("kiosk scene: the engine's pixels are kept bit for bit; overlapping objects by depth, not order") {
    const Kiosk& k = kiosk();
    // Objects (not the floor) that overlap on screen: pixels two of them cover.
    size_t overlap = 0;
    {
        std::vector<int> covering(size_t(kW) * kH, 0);
        std::string err;
        for (size_t i = 1; i < k.frame.objects.size(); ++i) {
            sepal::Image img(kW, kH, 3);
            std::vector<float> depth(size_t(kW) * kH, 1.0f);
            const sepal_mesh mesh = k.scene.meshes[size_t(k.scene.object_mesh[i])].mesh();
            sepal_object o = k.frame.objects[i];
            o.mesh = &mesh;
            o.lights = k.frame.lights;
            sepal_scene scene;
            float clip[16];
            sepal_error e = {};
            REQUIRE(sepal_object_scene(&k.frame.desc, &o, &scene, clip, &e) == SEPAL_OK);
            REQUIRE(sepal::render_exact_object(*k.scene.brdfs[size_t(k.scene.file.objects[i].material)], scene, mesh,
                                               clip, kW, kH, &img, &depth, nullptr, &err));
            for (size_t p = 0; p < depth.size(); ++p) covering[p] += depth[p] < 1.0f;
        }
        for (int c : covering) overlap += c >= 2;
    }
    CAPTURE(overlap);
    CHECK(overlap > 100);
    sepal::SceneFrame empty = k.frame;
    empty.objects.clear();
    for (int version : {1, 2}) {
        CAPTURE(version);
        const float clear_a[3] = {0.2f, 0.3f, 0.4f}, rect_a[3] = {0.9f, 0.1f, 0.1f};
        const float clear_b[3] = {0.6f, 0.5f, 0.1f}, rect_b[3] = {0.1f, 0.8f, 0.2f};
        sepal::SceneGlOptions oa, ob;
        oa.gles_version = ob.gles_version = version;
        oa.before = [&] { engine_draws(clear_a, rect_a); };
        ob.before = [&] { engine_draws(clear_b, rect_b); };
        const std::vector<uint8_t> before_a = gl_render(oa, empty), before_b = gl_render(ob, empty);
        const std::vector<uint8_t> a = gl_render(oa, k.frame), b = gl_render(ob, k.frame);
        sepal::SceneGlOptions reversed = oa;
        for (int i = int(k.frame.objects.size()) - 1; i >= 0; --i) reversed.order.push_back(i);
        const std::vector<uint8_t> r = gl_render(reversed, k.frame);
        size_t kept = 0, covered = 0, neither = 0;
        for (size_t p = 0; p < size_t(kW) * kH; ++p) {
            auto same = [p](const std::vector<uint8_t>& x, const std::vector<uint8_t>& y) {
                return std::equal(x.begin() + 4 * p, x.begin() + 4 * p + 4, y.begin() + 4 * p);
            };
            const bool kp = same(a, before_a) && same(b, before_b);
            kept += kp;
            covered += !kp && same(a, b);
            neither += !kp && !same(a, b);
        }
        CAPTURE(kept);
        CAPTURE(covered);
        CHECK(neither == 0);
        CHECK(kept > 10000);     // the background above the floor and the engine's rectangle
        CHECK(covered > 30000);  // floor and objects
        CHECK(r == a);           // depth, not the order, decides
    }
}
