// A two-object frame shared by the frame tests: two spheres with their own model matrices
// that overlap on screen, two lights, the engine's camera as matrices.
#pragma once
#include <doctest/doctest.h>

#include <GLES2/gl2.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gl_snapshot.h"
#include "headless/sepal_headless.h"
#include "sepal/sepal_frame.h"

namespace frame_fx {

constexpr int kWidth = 96, kHeight = 72;

// Rotation about z by `degrees`, uniform scale, then translation (column-major).
inline void model_matrix(float degrees, float scale, float x, float y, float z, float m[16]) {
    const float a = degrees * 3.14159265f / 180.0f, c = std::cos(a) * scale, s = std::sin(a) * scale;
    const float v[16] = {c, s, 0, 0, -s, c, 0, 0, 0, 0, scale, 0, x, y, z, 1};
    std::memcpy(m, v, sizeof v);
}

// The engine's frame before sepal's objects: its clear colour, and a rectangle (window
// coordinates, rows from the bottom) at `depth`, drawn by scissored clears.
inline void engine_draws(const float clear[3], const float rect[3], int x, int y, int w, int h, float depth) {
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glClearColor(clear[0], clear[1], clear[2], 1.0f);
    glClearDepthf(1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_SCISSOR_TEST);
    glScissor(x, y, w, h);
    glClearColor(rect[0], rect[1], rect[2], 1.0f);
    glClearDepthf(depth);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDisable(GL_SCISSOR_TEST);
    glClearDepthf(1.0f);
}

struct Scene {
    std::vector<sepal_vertex> vertices;
    std::vector<uint16_t> indices;
    sepal_mesh mesh{};
    sepal_light lights[2]{};
    sepal_frame_desc frame{};
    float model[2][16];
    std::vector<float> scratch;

    Scene() {
        vertices.resize(SEPAL_SPHERE_MAX_VERTICES);
        indices.resize(SEPAL_SPHERE_MAX_INDICES);
        mesh = {vertices.data(), indices.data(), (int)vertices.size(), (int)indices.size()};
        sepal_error e = {};
        REQUIRE(sepal_mesh_sphere(32, 16, &mesh, &e) == SEPAL_OK);
        sepal_scene s;
        sepal_scene_default(&s);
        REQUIRE(sepal_scene_matrices(&s, kWidth, kHeight, frame.view, frame.projection, &e) == SEPAL_OK);
        frame.viewport[2] = kWidth;
        frame.viewport[3] = kHeight;
        lights[0].type = SEPAL_LIGHT_POINT;
        const float p[3] = {2.0f, -2.5f, 3.0f}, d[3] = {-0.5f, -1.0f, 0.6f};
        std::memcpy(lights[0].position, p, sizeof p);
        lights[1].type = SEPAL_LIGHT_DIRECTIONAL;
        std::memcpy(lights[1].position, d, sizeof d);
        for (int c = 0; c < 3; ++c) lights[0].intensity[c] = 40.0f + 4.0f * c, lights[1].intensity[c] = 1.5f;
        // Object 0 left and behind, object 1 right and nearer the camera (on -y), turned and
        // smaller: they overlap on screen, 1 in front.
        model_matrix(0.0f, 0.7f, -0.35f, 0.3f, 0.0f, model[0]);
        model_matrix(40.0f, 0.5f, 0.3f, -0.5f, -0.1f, model[1]);
        scratch.resize(sepal_draw_scratch_floats(mesh.vertex_count, 2));
        frame.scratch = scratch.data();
        frame.scratch_floats = scratch.size();
    }

    sepal_object object(int k, const sepal_material* m, const sepal_asset* a, sepal_draw_mode mode) const {
        sepal_object o = {};
        o.material = m;
        o.asset = a;
        o.mesh = &mesh;
        std::memcpy(o.model, model[k], sizeof o.model);
        o.lights = lights;
        o.light_count = 2;
        o.mode = mode;
        return o;
    }
};

// A headless context and materials on it (destroyed in order).
struct Gl {
    sepal_headless_context* ctx = nullptr;
    sepal_caps caps{};
    std::vector<std::unique_ptr<sepal_asset>> assets;
    std::vector<std::unique_ptr<sepal_material>> materials;

    // framebuffer: 0 (RGBA8) or 565 (RGB565, sepal_headless_desc.framebuffer).
    explicit Gl(int version, int framebuffer = 0) {
        sepal_headless_desc hd = {};
        hd.width = kWidth;
        hd.height = kHeight;
        hd.gles_version = version;
        hd.framebuffer = framebuffer;
        char msg[512];
        ctx = sepal_headless_create(&hd, msg, sizeof msg);
        REQUIRE_MESSAGE(ctx, msg);
        sepal_error e = {};
        REQUIRE(sepal_query_caps(version, 0, sepal_headless_get_proc_address, &caps, &e) == SEPAL_OK);
    }
    ~Gl() {
        for (auto& m : materials) sepal_material_destroy(m.get());
        sepal_headless_destroy(ctx);
    }
    // bytes must outlive the material (the asset points into them).
    sepal_material* material(const std::vector<uint8_t>& bytes, uint32_t mask) {
        sepal_error e = {};
        sepal_caps c;
        REQUIRE(sepal_query_caps(caps.gles_version, mask, sepal_headless_get_proc_address, &c, &e) == SEPAL_OK);
        assets.push_back(std::make_unique<sepal_asset>());
        REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), assets.back().get(), &e) == SEPAL_OK);
        materials.push_back(std::make_unique<sepal_material>());
        REQUIRE_MESSAGE(sepal_material_create(&c, assets.back().get(), kWidth, kHeight, materials.back().get(), &e) ==
                            SEPAL_OK,
                        e.message);
        return materials.back().get();
    }
    std::vector<uint8_t> read() const {
        std::vector<uint8_t> px(size_t(kWidth) * kHeight * 4);
        REQUIRE(sepal_headless_read_rgba(ctx, px.data()));
        return px;
    }
};

// One frame of the scene's two objects on gl's context: object(k) for k = 0, 1 (1, 0 when
// reversed), cleared first when clear.
using ObjectOf = std::function<sepal_object(int k)>;
inline void draw_frame(Gl& gl, const Scene& sc, bool clear, const ObjectOf& object, bool reversed = false) {
    sepal_frame_desc fd = sc.frame;
    fd.caps = &gl.caps;
    fd.clear = clear ? 1 : 0;
    sepal_frame f;
    sepal_error e = {};
    REQUIRE_MESSAGE(sepal_frame_begin(&f, &fd, &e) == SEPAL_OK, e.message);
    for (int i = 0; i < 2; ++i) {
        const sepal_object o = object(reversed ? 1 - i : i);
        sepal_draw_stats stats = {};
        REQUIRE_MESSAGE(sepal_frame_draw(&f, &o, &stats, &e) == SEPAL_OK, e.message);
    }
    REQUIRE_MESSAGE(sepal_frame_end(&f, &e) == SEPAL_OK, e.message);
}

// The state contract: each change (what an application might leave) must show in the
// snapshot; then a two-object frame and a sepal_draw on that state must leave the snapshot
// as it was.
using Change = std::pair<const char*, std::function<void()>>;
inline void check_state_kept(Gl& gl, const Scene& sc, const sepal_material* m, sepal_draw_mode mode,
                             const std::vector<Change>& changes,
                             const std::function<gl_snapshot::Snapshot()>& snapshot) {
    gl_snapshot::Snapshot last = snapshot();
    for (const Change& c : changes) {
        CAPTURE(std::string(c.first));
        c.second();
        const gl_snapshot::Snapshot now = snapshot();
        CHECK(!gl_snapshot::differences(last, now).empty());  // the snapshot sees this change
        last = now;
    }
    draw_frame(gl, sc, true, [&](int k) { return sc.object(k, m, nullptr, mode); });
    sepal_error e = {};
    const std::string diff = gl_snapshot::differences(last, snapshot());
    CHECK_MESSAGE(diff.empty(), "left behind: " << diff);
    // sepal_draw, the one-object frame, keeps the contract too.
    std::vector<float> scratch(sepal_draw_scratch_floats(sc.mesh.vertex_count, 1));
    sepal_scene scene;
    sepal_scene_default(&scene);
    sepal_draw_desc d = {};
    d.material = m;
    d.mesh = &sc.mesh;
    d.scene = &scene;
    d.width = kWidth;
    d.height = kHeight;
    d.scratch = scratch.data();
    d.scratch_floats = scratch.size();
    d.mode = mode;
    REQUIRE_MESSAGE(sepal_draw(&d, nullptr, &e) == SEPAL_OK, e.message);
    const std::string diff_draw = gl_snapshot::differences(last, snapshot());
    CHECK_MESSAGE(diff_draw.empty(), "sepal_draw left behind: " << diff_draw);
}

}  // namespace frame_fx
