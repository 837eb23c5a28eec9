// The web port: the runtime's GL ES 2 paths on a WebGL 1 canvas, through Emscripten's
// html5.h and its GL ES 2 emulation of WebGL (no Emscripten "ports", no network). The
// page (index.html, app.js) calls these C functions; `make web` builds them into
// build/web/sepal.{js,wasm}.
//
// Usage from JavaScript (app.js does this):
//   Module._sepal_web_init(canvas_selector, 512, 512)      // WebGL 1 context, GL ES 2 caps
//   Module._sepal_web_load(ptr, size)                      // asset bytes copied in
//   Module._sepal_web_scene("--mesh torus --light ...")    // scene flags, as sepal-view's
//   Module._sepal_web_orbit(dx, dy); Module._sepal_web_draw()
//
// What WebGL 1 lacks, and what this port does about it (docs/ports.md has the list):
//   - no fixed function (glTexEnv combiners, GL_RGB_SCALE, glLight, glColorPointer...):
//     the GL ES 1.1 backend is not built (SEPAL_NO_GLES1); the GL ES 2 plan path draws the
//     same passes with a shader that applies the combiner's scale, and the fused paths
//     sum the terms in one pass;
//   - no client-side vertex or index arrays (the runtime hands GL pointers into caller
//     memory, as GL ES allows): Emscripten's FULL_ES2 emulation copies them into buffers
//     per draw (measured in the benchmark);
//   - no half-float render target without extensions: caps report none (the runtime asks
//     GL ES 3 for it), so frames go through the 8-bit canvas like GL ES 2 on a phone;
//   - NPOT textures only without MIP maps: the runtime's factor textures are powers of two.
// Limits: one canvas, one asset at a time; --size in scene flags is ignored (the canvas
// size given to sepal_web_init is the viewport); OBJ meshes cannot be read (no file system).
#include <GLES2/gl2.h>
#include <emscripten/emscripten.h>
#include <emscripten/html5.h>

#include <stdio.h>
#include <string.h>

#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "common/orbit.h"
#include "common/scene_bundle.h"
#include "common/scene_args.h"
#include "common/scene_draw.h"
#include "common/scene_flags.h"
#include "common/term_prefix.h"
#include "sepal/sepal.h"

namespace {

struct App {
    EMSCRIPTEN_WEBGL_CONTEXT_HANDLE context = 0;
    int width = 0, height = 0;
    sepal_caps caps = {};
    std::vector<uint8_t> bytes;  // the asset's bytes, which parsed assets point into
    sepal_asset full = {}, shown = {};
    bool loaded = false;
    sepal_material material = {};
    bool have_material = false;
    sepal_ports::SceneSetup setup;
    sepal_ports::OrbitView view;
    sepal_ports::TermPrefix prefix;
    int terms = 0;
    sepal_draw_mode mode = SEPAL_MODE_MULTIPASS;
    std::vector<float> scratch;
    sepal_draw_stats stats = {};
    std::string error, text;
};

App& app() {
    static App a;
    return a;
}

// Scene mode: a scene bundle (ports/common/scene_bundle.h) the page fetched, drawn as one
// frame of many objects.
struct WebScene {
    std::map<std::string, std::vector<uint8_t>> files;  // what the page handed over, by name
    sepal_ports::SceneBundle bundle;
    std::vector<std::unique_ptr<sepal_material>> materials;
    std::vector<float> scratch;
    double yaw = 0, pitch = 0;
    void clear() {
        for (auto& m : materials) sepal_material_destroy(m.get());
        materials.clear();
    }
};

WebScene& web_scene() {
    static WebScene s;
    return s;
}

int fail(const std::string& message) {
    app().error = message;
    return 0;
}

// (Re)makes the GL material from the shown asset (after a load or a term change).
bool make_material() {
    App& a = app();
    if (a.have_material) sepal_material_destroy(&a.material);
    a.have_material = false;
    sepal_error e = {};
    if (sepal_material_create(&a.caps, &a.shown, a.width, a.height, &a.material, &e) != SEPAL_OK)
        return fail(e.message);
    a.have_material = true;
    return true;
}

}  // namespace

extern "C" {

// Creates the WebGL 1 context on the canvas (a CSS selector such as "#sepal") of
// width x height pixels and reads its capabilities. 1, or 0 with sepal_web_error().
EMSCRIPTEN_KEEPALIVE int sepal_web_init(const char* canvas, int width, int height) {
    App& a = app();
    EmscriptenWebGLContextAttributes attrs;
    emscripten_webgl_init_context_attributes(&attrs);
    attrs.alpha = false;                 // an opaque canvas, like the EGL targets
    attrs.depth = true;
    attrs.stencil = false;
    attrs.antialias = false;             // pixel-comparable with the headless render
    attrs.premultipliedAlpha = false;
    attrs.preserveDrawingBuffer = true;  // the page and the tests read the last frame back
    attrs.majorVersion = 1;
    attrs.minorVersion = 0;
    emscripten_set_canvas_element_size(canvas, width, height);
    a.context = emscripten_webgl_create_context(canvas, &attrs);
    if (a.context <= 0) return fail("this browser gives no WebGL 1 context");
    emscripten_webgl_make_context_current(a.context);
    a.width = width;
    a.height = height;
    a.setup.width = width;
    a.setup.height = height;
    std::string err;
    if (!sepal_ports::load_scene_mesh(&a.setup, &err)) return fail(err);
    a.view.reset(a.setup.scene);
    sepal_error e = {};
    // glBlendEquation is core in WebGL 1: no loader needed.
    if (sepal_query_caps(2, 0, nullptr, &a.caps, &e) != SEPAL_OK) return fail(e.message);
    return 1;
}

// Scene flags as sepal-view and `sepal render` take them (space-separated), applied to
// the default scene; the view controls start again from the result.
EMSCRIPTEN_KEEPALIVE int sepal_web_scene(const char* flags) {
    App& a = app();
    sepal_ports::SceneSetup s;
    std::istringstream in(flags ? flags : "");
    std::vector<std::string> words;
    for (std::string w; in >> w;) words.push_back(w);
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(&w[0]);
    std::string err;
    for (int i = 0; i < (int)argv.size(); ++i) {
        const int used = sepal_ports::parse_scene_flag((int)argv.size(), argv.data(), i, &s, &err);
        if (used < 0) return fail(err);
        if (used == 0) return fail("not a scene flag: '" + words[(size_t)i] + "'");
        i += used - 1;
    }
    s.width = a.width;
    s.height = a.height;
    if (!sepal_ports::load_scene_mesh(&s, &err)) return fail(err);
    a.setup.scene = s.scene;
    a.setup.mesh_name = s.mesh_name;
    a.setup.lights_given = s.lights_given;
    if (!sepal_ports::load_scene_mesh(&a.setup, &err)) return fail(err);
    a.view.reset(a.setup.scene);
    return 1;
}

// Copies and parses an asset, and uploads it. 1, or 0 with sepal_web_error() (the
// previous asset stays).
EMSCRIPTEN_KEEPALIVE int sepal_web_load(const uint8_t* bytes, int size) {
    App& a = app();
    if (!bytes || size <= 0 || (size_t)size > SEPAL_FMT_MAX_FILE_BYTES) return fail("asset: empty or too large");
    std::vector<uint8_t> copy(bytes, bytes + size);
    static sepal_asset parsed;
    sepal_error e = {};
    if (sepal_asset_parse(copy.data(), copy.size(), &parsed, &e) != SEPAL_OK) return fail(e.message);
    a.bytes.swap(copy);
    a.full = parsed;  // points into a.bytes (the vector's buffer moved with the swap)
    a.prefix = sepal_ports::term_prefix(a.full, a.terms, &a.shown);
    a.loaded = true;
    return make_material() ? 1 : 0;
}

// 0: the plan with tiny shaders (gles2), 1: fused, per-vertex coordinates (gles2-fused),
// 2: fused per pixel (gles2-fused-pixel).
EMSCRIPTEN_KEEPALIVE int sepal_web_set_backend(int mode) {
    if (mode < 0 || mode > 2) return fail("backend: 0 gles2, 1 gles2-fused, 2 gles2-fused-pixel");
    app().mode = (sepal_draw_mode)mode;
    return 1;
}

// Shows the first k terms (0: all).
EMSCRIPTEN_KEEPALIVE int sepal_web_set_terms(int terms) {
    App& a = app();
    a.terms = terms;
    if (!a.loaded) return 1;
    a.prefix = sepal_ports::term_prefix(a.full, a.terms, &a.shown);
    return make_material() ? 1 : 0;
}

EMSCRIPTEN_KEEPALIVE void sepal_web_orbit(float dx, float dy) {
    app().view.orbit(dx, dy);
    app().view.apply(&app().setup.scene);
}

EMSCRIPTEN_KEEPALIVE void sepal_web_move_light(float dx, float dy) {
    app().view.move_light(dx, dy);
    app().view.apply(&app().setup.scene);
}

EMSCRIPTEN_KEEPALIVE void sepal_web_zoom(int steps) {
    app().view.zoom(steps);
    app().view.apply(&app().setup.scene);
}

EMSCRIPTEN_KEEPALIVE void sepal_web_reset_view(void) {
    app().view.restore();
    app().view.apply(&app().setup.scene);
}

// Draws a frame; returns its time in ms (sepal_draw and a one-pixel read that waits for
// the GPU), or -1 with sepal_web_error().
EMSCRIPTEN_KEEPALIVE double sepal_web_draw(void) {
    App& a = app();
    if (!a.have_material) {
        fail(a.loaded ? a.error : "no asset loaded");
        return -1;
    }
    const sepal_draw_desc d = sepal_ports::scene_draw_desc(&a.material, a.setup, a.mode, &a.scratch);
    const double start = emscripten_get_now();
    sepal_error e = {};
    const sepal_result r = sepal_draw(&d, &a.stats, &e);
    uint8_t pixel[4];
    glReadPixels(0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, pixel);  // WebGL's finish does not wait
    const double ms = emscripten_get_now() - start;
    if (r != SEPAL_OK) {
        fail(e.message);
        return -1;
    }
    return ms;
}

// Scene mode. The page hands over each file scene.txt names (sepal_web_scene_file), then
// its text (sepal_web_scene_open: the materials are made for the canvas), then draws frames
// at times t (sepal_web_scene_draw: the backend from sepal_web_set_backend).
EMSCRIPTEN_KEEPALIVE int sepal_web_scene_file(const char* name, const uint8_t* bytes, int size) {
    if (!name || !bytes || size < 0) return fail("sepal_web_scene_file: no name or bytes");
    web_scene().files[name].assign(bytes, bytes + size);
    return 1;
}

EMSCRIPTEN_KEEPALIVE int sepal_web_scene_open(const char* text) {
    App& a = app();
    WebScene& s = web_scene();
    s.clear();
    std::string err;
    const bool ok = sepal_ports::parse_scene_bundle(
        text ? text : "", "scene.txt",
        [&s](const std::string& name, size_t max, std::vector<uint8_t>* out, std::string* e) {
            auto it = s.files.find(name);
            if (it == s.files.end() || it->second.size() > max) return *e = name + ": not fetched (or too large)", false;
            *out = it->second;
            return true;
        },
        &s.bundle, &err);
    if (!ok) return fail(err);
    for (const auto& asset : s.bundle.assets) {
        s.materials.push_back(std::make_unique<sepal_material>());
        sepal_error e = {};
        if (sepal_material_create(&a.caps, asset.get(), a.width, a.height, s.materials.back().get(), &e) != SEPAL_OK) {
            s.materials.pop_back();
            s.clear();
            return fail(e.message);
        }
    }
    s.scratch.resize(sepal_draw_scratch_floats(int(s.bundle.max_vertices()), int(s.bundle.lights.size())));
    return 1;
}

EMSCRIPTEN_KEEPALIVE void sepal_web_scene_orbit(float dx, float dy) {
    web_scene().yaw -= dx * sepal_ports::kOrbitDegreesPerPixel;
    web_scene().pitch += dy * sepal_ports::kOrbitDegreesPerPixel;
}

// The background, then one frame of every object at time t; its time in ms, or -1.
EMSCRIPTEN_KEEPALIVE double sepal_web_scene_draw(double t) {
    App& a = app();
    WebScene& s = web_scene();
    if (s.materials.empty()) return fail("no scene open"), -1;
    sepal_frame_desc fd;
    sepal_light lights[SEPAL_MAX_LIGHTS];
    int nl = 0;
    std::vector<sepal_object> objs;
    std::string err;
    if (!sepal_ports::bundle_frame(s.bundle, t, s.yaw, s.pitch, a.width, a.height, &fd, lights, &nl, &objs, &err))
        return fail(err), -1;
    const double start = emscripten_get_now();
    glViewport(0, 0, a.width, a.height);
    glClearColor(fd.clear_color[0], fd.clear_color[1], fd.clear_color[2], 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    fd.caps = &a.caps;
    fd.scratch = s.scratch.data();
    fd.scratch_floats = s.scratch.size();
    sepal_frame f;
    sepal_error e = {};
    if (sepal_frame_begin(&f, &fd, &e) != SEPAL_OK) return fail(e.message), -1;
    bool ok = true;
    a.stats = sepal_draw_stats{};
    for (size_t i = 0; ok && i < objs.size(); ++i) {
        const sepal_mesh mesh = s.bundle.meshes[size_t(s.bundle.objects[i].mesh)].mesh();
        objs[i].mesh = &mesh;
        objs[i].material = s.materials[size_t(s.bundle.objects[i].material)].get();
        objs[i].mode = a.mode;
        sepal_draw_stats st = {};
        ok = sepal_frame_draw(&f, &objs[i], &st, &e) == SEPAL_OK;
        a.stats.draw_calls += st.draw_calls;
    }
    sepal_error end = {};
    const bool ended = sepal_frame_end(&f, &end) == SEPAL_OK;
    uint8_t pixel[4];
    glReadPixels(0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, pixel);  // WebGL's finish does not wait
    if (!ok || !ended) return fail(ok ? end.message : e.message), -1;
    return emscripten_get_now() - start;
}

// The last frame as RGBA8, top row first (width * height * 4 bytes).
EMSCRIPTEN_KEEPALIVE int sepal_web_read(uint8_t* rgba) {
    App& a = app();
    if (!rgba) return 0;
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, a.width, a.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    const size_t row = (size_t)a.width * 4;
    std::vector<uint8_t> tmp(row);
    for (int y = 0; y < a.height / 2; ++y) {
        uint8_t* top = rgba + (size_t)y * row;
        uint8_t* bottom = rgba + (size_t)(a.height - 1 - y) * row;
        memcpy(tmp.data(), top, row);
        memcpy(top, bottom, row);
        memcpy(bottom, tmp.data(), row);
    }
    return glGetError() == GL_NO_ERROR ? 1 : 0;
}

EMSCRIPTEN_KEEPALIVE const char* sepal_web_error(void) { return app().error.c_str(); }

// One line for the page: device, terms, passes, texture bytes.
EMSCRIPTEN_KEEPALIVE const char* sepal_web_status(void) {
    App& a = app();
    char line[512];
    snprintf(line, sizeof line, "%s | terms %d/%u%s | %d draws + %d full-screen | %.1f KB textures", a.caps.renderer,
             a.prefix.terms, a.full.material.terms, a.prefix.unattributed ? " (approx.)" : "", a.stats.draw_calls,
             a.stats.fullscreen_passes, a.prefix.texture_bytes / 1024.0);
    a.text = line;
    return a.text.c_str();
}

// The current view as scene flags: `sepal-view --headless ASSET <these> -o x.png` draws it natively.
EMSCRIPTEN_KEEPALIVE const char* sepal_web_flags(void) {
    app().text = sepal_ports::shell_join(sepal_ports::scene_args(app().setup));
    return app().text.c_str();
}

}  // extern "C"
