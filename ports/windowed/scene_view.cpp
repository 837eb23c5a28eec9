#include "windowed/scene_view.h"

#include <GLES2/gl2.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "common/orbit.h"
#include "common/png_write.h"
#include "common/render_gl.h"
#include "common/scene_bundle.h"
#include "headless/sepal_headless.h"
#include "windowed/sepal_window.h"
#include "windowed/viewer.h"

namespace sepal_ports {
namespace {

const char* const kSceneBackends[] = {"gles1", "gles2", "gles2-fused", "gles2-fused-pixel"};

struct SceneViewArgs {
    std::string scene, out, shot, backend = "gles1", tool;
    bool headless = false;
    double time = -1;
    int frames = 0;
    int framebuffer = 0;  // headless: 8888 or 565 (0: not given, 8888)
};

int parse_args(int argc, char** argv, SceneViewArgs* a) {
    for (int i = 1; i < argc; ++i) {
        const std::string f = argv[i];
        const bool v = i + 1 < argc;
        if (f == "--scene" && v) a->scene = argv[++i];
        else if (f == "--headless") a->headless = true;
        else if (f == "-o" && v) a->out = argv[++i];
        else if (f == "--shot" && v) a->shot = argv[++i];
        else if (f == "--backend" && v) a->backend = argv[++i];
        else if (f == "--sepal" && v) a->tool = argv[++i];
        else if (f == "--framebuffer" && v) {
            std::string err;
            if (!parse_framebuffer(argv[++i], &a->framebuffer, &err)) return fprintf(stderr, "sepal-view: %s\n", err.c_str()), 2;
        }
        else if (f == "--time" && v) {
            char* end = nullptr;
            a->time = strtod(argv[++i], &end);
            if (!end || *end || !(a->time >= 0 && a->time <= 1e6))
                return fprintf(stderr, "sepal-view: --time '%s': seconds, 0..1e6\n", argv[i]), 2;
        } else if (f == "--frames" && v) {
            a->frames = atoi(argv[++i]);
            if (a->frames < 1 || a->frames > 100000) return fprintf(stderr, "sepal-view: --frames: 1..100000\n"), 2;
        } else {
            return fprintf(stderr, "sepal-view: --scene: unknown or incomplete argument '%s' (scene mode takes "
                                   "--headless, -o, --backend, --time, --frames, --shot, --sepal, --framebuffer)\n",
                           f.c_str()), 2;
        }
    }
    GlRenderOptions o;
    if (!parse_gl_backend(a->backend, &o))
        return fprintf(stderr, "sepal-view: --backend '%s': gles1, gles2, gles2-fused or gles2-fused-pixel\n",
                       a->backend.c_str()), 2;
    if (a->headless != !a->out.empty())
        return fprintf(stderr, "sepal-view: --scene: --headless needs -o out.png, and -o needs --headless\n"), 2;
    if (a->framebuffer && !a->headless)
        return fprintf(stderr, "sepal-view: --scene: --framebuffer applies with --headless (a window has the display's format)\n"), 2;
    if (!a->shot.empty() && !a->frames) return fprintf(stderr, "sepal-view: --shot needs --frames N\n"), 2;
    return -1;
}

// A .json goes through the sepal tool into a bundle in a fresh folder; a folder or a
// scene.txt is read as it is.
bool open_bundle(const SceneViewArgs& a, SceneBundle* b, std::string* err) {
    std::string path = a.scene;
    struct stat st;
    if (stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) path += "/scene.txt";
    const size_t dot = path.rfind('.');
    if (dot != std::string::npos && path.substr(dot) == ".json") {
        char tmpl[] = "/tmp/sepal-view-scene-XXXXXX";
        if (!mkdtemp(tmpl)) return *err = "cannot make a folder for the scene bundle", false;
        const std::string dir = tmpl, log = dir + "/export.log";
        fprintf(stderr, "sepal-view: preparing %s with the sepal tool (bakes materials not in its cache)\n", path.c_str());
        const int code = run_process({sepal_tool(a.tool), "render", "--scene", path, "--export", dir}, log);
        if (code != 0) {
            std::vector<uint8_t> text;
            read_bounded_file(log, 1 << 16, &text, err);
            std::string msg(text.begin(), text.end());
            while (!msg.empty() && msg.back() == '\n') msg.pop_back();
            *err = code == 127 || code < 0 ? "--scene FILE.json needs the sepal tool (--sepal PATH or $SEPAL_CLI)"
                                           : msg.substr(msg.rfind('\n') == std::string::npos ? 0 : msg.rfind('\n') + 1);
            return false;
        }
        path = dir + "/scene.txt";
    }
    return load_scene_bundle(path, b, err);
}

struct SceneGl {
    const SceneBundle& b;
    sepal_caps caps{};
    std::vector<std::unique_ptr<sepal_material>> materials;
    std::vector<float> scratch;

    explicit SceneGl(const SceneBundle& bundle) : b(bundle) {}
    ~SceneGl() { destroy(); }
    void destroy() {
        for (auto& m : materials) sepal_material_destroy(m.get());
        materials.clear();
    }
    bool create(int version, sepal_proc_loader loader, std::string* err) {
        destroy();
        sepal_error e = {};
        if (sepal_query_caps(version, 0, loader, &caps, &e) != SEPAL_OK) return *err = e.message, false;
        for (const auto& a : b.assets) {
            materials.push_back(std::make_unique<sepal_material>());
            if (sepal_material_create(&caps, a.get(), b.width, b.height, materials.back().get(), &e) != SEPAL_OK) {
                materials.pop_back();
                return *err = e.message, false;
            }
        }
        scratch.resize(sepal_draw_scratch_floats(int(b.max_vertices()), int(b.lights.size())));
        return true;
    }
    // The engine's clear to the background, then one frame of every object.
    bool draw(double t, double yaw, double pitch, sepal_draw_mode mode, SceneBundle& mut, std::string* err) {
        sepal_frame_desc fd;
        sepal_light lights[SEPAL_MAX_LIGHTS];
        int nl = 0;
        std::vector<sepal_object> objs;
        if (!bundle_frame(b, t, yaw, pitch, b.width, b.height, &fd, lights, &nl, &objs, err)) return false;
        glViewport(0, 0, b.width, b.height);
        glClearColor(fd.clear_color[0], fd.clear_color[1], fd.clear_color[2], 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        fd.caps = &caps;
        fd.scratch = scratch.data();
        fd.scratch_floats = scratch.size();
        sepal_frame f;
        sepal_error e = {};
        if (sepal_frame_begin(&f, &fd, &e) != SEPAL_OK) return *err = e.message, false;
        bool ok = true;
        for (size_t i = 0; ok && i < objs.size(); ++i) {
            const sepal_mesh mesh = mut.meshes[size_t(b.objects[i].mesh)].mesh();
            objs[i].mesh = &mesh;
            objs[i].material = materials[size_t(b.objects[i].material)].get();
            objs[i].mode = mode;
            ok = sepal_frame_draw(&f, &objs[i], nullptr, &e) == SEPAL_OK;
        }
        sepal_error end = {};
        const bool ended = sepal_frame_end(&f, &end) == SEPAL_OK;
        if (!ok || !ended) return *err = ok ? end.message : e.message, false;
        return true;
    }
};

int headless_scene(const SceneViewArgs& a, SceneBundle& b, const GlRenderOptions& o) {
    sepal_headless_desc hd = {};
    hd.width = b.width;
    hd.height = b.height;
    hd.gles_version = o.gles_version;
    hd.framebuffer = a.framebuffer;
    char msg[512];
    sepal_headless_context* ctx = sepal_headless_create(&hd, msg, sizeof msg);
    if (!ctx) return fprintf(stderr, "sepal-view: %s\n", msg), 1;
    std::string err;
    std::vector<uint8_t> rgba(size_t(b.width) * b.height * 4);
    bool ok;
    {
        SceneGl gl(b);
        ok = gl.create(o.gles_version, sepal_headless_get_proc_address, &err) &&
             gl.draw(a.time < 0 ? 0 : a.time, 0, 0, o.mode, b, &err);
        if (ok && !sepal_headless_read_rgba(ctx, rgba.data())) ok = false, err = "reading the frame back failed";
    }
    sepal_headless_destroy(ctx);
    if (!ok) return fprintf(stderr, "sepal-view: %s\n", err.c_str()), 1;
    if (!write_png_atomic(a.out, b.width, b.height, rgba.data()))
        return fprintf(stderr, "sepal-view: could not write %s\n", a.out.c_str()), 1;
    printf("%s\n", a.out.c_str());
    return 0;
}

int window_scene(const SceneViewArgs& a, SceneBundle& b) {
    int backend = 0;
    for (int k = 0; k < 4; ++k)
        if (a.backend == kSceneBackends[k]) backend = k;
    GlRenderOptions o;
    parse_gl_backend(kSceneBackends[backend], &o);
    sepal_window_desc d = {};
    d.width = b.width;
    d.height = b.height;
    d.gles_version = o.gles_version;
    d.title = "sepal-view scene";
    char msg[512];
    sepal_window* w = sepal_window_create(&d, msg, sizeof msg);
    if (!w) return fprintf(stderr, "sepal-view: %s\n", msg), 1;
    std::string err;
    auto gl = std::make_unique<SceneGl>(b);
    bool ok = gl->create(o.gles_version, sepal_window_get_proc_address, &err);
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    double yaw = 0, pitch = 0, paused_at = -1, offset = 0;
    int drag_x = -1, drag_y = -1, drawn = 0;
    std::vector<double> times;
    std::vector<uint8_t> shot;
    bool quit = false;
    while (ok && !quit) {
        sepal_window_event ev;
        while (sepal_window_poll(w, &ev, 0)) {
            if (ev.type == SEPAL_WINDOW_EVENT_CLOSE || (ev.type == SEPAL_WINDOW_EVENT_KEY && (ev.key == 'q' || ev.key == SEPAL_KEY_ESCAPE)))
                quit = true;
            else if (ev.type == SEPAL_WINDOW_EVENT_BUTTON_DOWN && ev.button == 1) drag_x = ev.x, drag_y = ev.y;
            else if (ev.type == SEPAL_WINDOW_EVENT_BUTTON_UP && ev.button == 1) drag_x = -1;
            else if (ev.type == SEPAL_WINDOW_EVENT_MOTION && drag_x >= 0 && (ev.buttons & 1)) {
                yaw -= (ev.x - drag_x) * kOrbitDegreesPerPixel;
                pitch += (ev.y - drag_y) * kOrbitDegreesPerPixel;
                drag_x = ev.x, drag_y = ev.y;
            } else if (ev.type == SEPAL_WINDOW_EVENT_KEY && ev.key == ' ') {
                const double now = std::chrono::duration<double>(Clock::now() - start).count();
                if (paused_at < 0) paused_at = now;
                else offset += now - paused_at, paused_at = -1;
            } else if (ev.type == SEPAL_WINDOW_EVENT_KEY && (ev.key == 'b' || ev.key == 'B')) {
                backend = (backend + (ev.key == 'b' ? 1 : 3)) % 4;
                parse_gl_backend(kSceneBackends[backend], &o);
                gl.reset();
                char m[256];
                ok = sepal_window_use_gles(w, o.gles_version, m, sizeof m) != 0;
                gl = std::make_unique<SceneGl>(b);
                if (!ok) err = m;
                ok = ok && gl->create(o.gles_version, sepal_window_get_proc_address, &err);
            }
        }
        if (!ok || quit) break;
        const double now = std::chrono::duration<double>(Clock::now() - start).count();
        const double t = a.time >= 0 ? a.time : (paused_at >= 0 ? paused_at : now) - offset;
        const auto t0 = Clock::now();
        ok = gl->draw(t, yaw, pitch, o.mode, b, &err);
        glFinish();
        times.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        char title[160];
        snprintf(title, sizeof title, "sepal-view scene: %s, t = %.1f s, %.1f ms", kSceneBackends[backend], t, times.back());
        sepal_window_set_title(w, title);
        ++drawn;
        if (ok && a.frames && drawn == a.frames && !a.shot.empty()) {
            shot.resize(size_t(b.width) * b.height * 4);
            if (!sepal_window_read_rgba(w, 0, 0, b.width, b.height, shot.data())) ok = false, err = "reading the window failed";
        }
        sepal_window_swap(w);
        if (a.frames && drawn >= a.frames) break;
    }
    gl.reset();
    sepal_window_destroy(w);
    if (!ok) return fprintf(stderr, "sepal-view: %s\n", err.c_str()), 1;
    if (a.frames) {
        std::sort(times.begin(), times.end());
        printf("%d frames, %s, %dx%d: median %.2f ms\n", drawn, kSceneBackends[backend], b.width, b.height,
               times[times.size() / 2]);
        if (!a.shot.empty() && !write_png_atomic(a.shot, b.width, b.height, shot.data()))
            return fprintf(stderr, "sepal-view: could not write %s\n", a.shot.c_str()), 1;
    }
    return 0;
}

}  // namespace

int run_scene_view(int argc, char** argv) {
    SceneViewArgs a;
    if (const int code = parse_args(argc, argv, &a); code >= 0) return code;
    SceneBundle b;
    std::string err;
    if (!open_bundle(a, &b, &err)) return fprintf(stderr, "sepal-view: %s\n", err.c_str()), 2;
    GlRenderOptions o;
    parse_gl_backend(a.backend, &o);
    return a.headless ? headless_scene(a, b, o) : window_scene(a, b);
}

}  // namespace sepal_ports
