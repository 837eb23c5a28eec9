// sepal-view's interactive mode: see viewer.h.
#include "windowed/viewer.h"

#include <GLES2/gl2.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "common/orbit.h"
#include "common/png_write.h"
#include "common/render_gl.h"
#include "common/scene_args.h"
#include "common/scene_draw.h"
#include "common/term_prefix.h"
#include "sepal/sepal_material.h"
#include "windowed/overlay.h"
#include "windowed/sepal_window.h"

namespace sepal_ports {
namespace {

constexpr int kStrip = 28;              // status line height (two text lines)
const char* const kBackends[] = {"gles1", "gles2", "gles2-fused", "gles2-fused-pixel", "cpu", "exact"};
constexpr int kBackendCount = 6;
const char* const kMeshes[] = {"sphere", "torus", "wave"};

const char kHelp[] =
    "sepal-view controls:\n"
    "  left drag            orbit the camera (0.5 degrees per pixel)\n"
    "  right / shift drag   move the first light around the target\n"
    "  wheel, + / -         closer / further;  arrow keys: orbit by 5 degrees\n"
    "  b / B                next / previous backend (gles1 gles2 gles2-fused gles2-fused-pixel cpu exact)\n"
    "  1..9, 0              first k terms of the asset, 0: all\n"
    "  m / M                next / previous mesh;  n / N: next / previous material in the folder\n"
    "  p                    PSNR of this view against the exact render\n"
    "  s                    screenshot (PNG of the view and of the window, and the headless command)\n"
    "  r                    reset the view;  h: this help;  q, Esc: quit\n";

bool ends_with(const std::string& s, const char* tail) {
    const size_t n = strlen(tail);
    return s.size() >= n && s.compare(s.size() - n, n, tail) == 0;
}

// Every *.sepal of a folder, sorted.
std::vector<std::string> folder_assets(const std::string& dir) {
    std::vector<std::string> out;
    if (DIR* d = opendir(dir.c_str())) {
        while (const dirent* e = readdir(d)) {
            const std::string name = e->d_name;
            if (ends_with(name, ".sepal") && name[0] != '.') out.push_back(dir + "/" + name);
        }
        closedir(d);
    }
    std::sort(out.begin(), out.end());
    return out;
}

// The "spec" string of the asset's META manifest (JSON written by `sepal bake`).
std::string meta_spec(const sepal_asset& a) {
    if (!a.meta) return "";
    const std::string meta(a.meta, a.meta_bytes);
    size_t p = meta.find("\"spec\"");
    if (p == std::string::npos) return "";
    p = meta.find_first_not_of(" \t\r\n", p + 6);
    if (p == std::string::npos || meta[p] != ':') return "";
    p = meta.find_first_not_of(" \t\r\n", p + 1);
    if (p == std::string::npos || meta[p] != '"') return "";
    std::string out;
    for (++p; p < meta.size() && meta[p] != '"'; ++p) {
        if (meta[p] == '\\' && p + 1 < meta.size()) ++p;  // \" and \\ (specs use no other escapes)
        out += meta[p];
    }
    return out;
}

}  // namespace

std::string self_dir() {
    char buf[PATH_MAX];
    const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n <= 0) return "";
    std::string path(buf, (size_t)n);
    const size_t slash = path.rfind('/');
    return slash == std::string::npos ? "" : path.substr(0, slash);
}

// Runs argv (argv[0] looked up on PATH when it has no slash) with its output in log;
// returns the exit status, or -1 when it could not run.
int run_process(const std::vector<std::string>& args, const std::string& log) {
    std::vector<char*> argv;
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
            close(fd);
        }
        execvp(argv[0], argv.data());
        fprintf(stderr, "cannot run %s: %s\n", argv[0], strerror(errno));
        _exit(127);
    }
    int status = 0;
    if (waitpid(pid, &status, 0) != pid) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string sepal_tool(const std::string& given) {
    if (!given.empty()) return given;
    const char* env = getenv("SEPAL_CLI");
    if (env && *env) return env;
    const std::string beside = self_dir() + "/sepal";
    return access(beside.c_str(), X_OK) == 0 ? beside : "sepal";
}

namespace {

std::string last_line(const std::string& path) {
    std::vector<uint8_t> bytes;
    std::string err;
    if (!read_bounded_file(path, 1 << 20, &bytes, &err)) return "";
    std::string text(bytes.begin(), bytes.end());
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    const size_t nl = text.rfind('\n');
    return nl == std::string::npos ? text : text.substr(nl + 1);
}

double psnr_rgb(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    double sum = 0;
    size_t n = 0;
    for (size_t i = 0; i + 3 < a.size() && i + 3 < b.size(); i += 4)
        for (int c = 0; c < 3; ++c, ++n) {
            const double d = double(a[i + c]) - double(b[i + c]);
            sum += d * d;
        }
    const double mse = n ? sum / double(n) : 0.0;
    return mse > 0 ? 10.0 * log10(255.0 * 255.0 / mse) : INFINITY;
}

double ms_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

class Viewer {
  public:
    Viewer(const ViewerOptions& o, SceneSetup* s) : opt_(o), setup_(*s) {}
    ~Viewer();
    int run();

  private:
    bool open_input(std::string* err);
    bool load_asset(size_t index, std::string* err);
    void apply_prefix();
    bool gl_backend() const { return backend_ < 4; }
    int backend_gles() const { return backend_ == 0 ? 1 : 2; }
    void release_material();
    bool ensure_material(std::string* err);
    bool draw(bool capture_view, bool capture_window);
    void present();
    bool exact_image(std::string* err);
    std::string temp(const char* name);
    std::string tool();
    void set_view() { view_.apply(&setup_.scene); }
    bool handle(const sepal_window_event& e);  // false: quit
    void screenshot();
    void measure_psnr();
    int benchmark();
    std::vector<std::string> status_lines() const;
    std::string view_key() const;

    ViewerOptions opt_;
    SceneSetup& setup_;
    sepal_window* window_ = nullptr;
    int width_ = 0, height_ = 0;
    std::vector<std::string> meshes_;
    size_t mesh_index_ = 0;
    // Materials: every *.sepal of the folder; one loaded at a time.
    std::vector<std::string> assets_;
    size_t asset_index_ = 0;
    std::string baked_spec_;  // the input was a spec, baked through the tool
    std::vector<uint8_t> bytes_;
    std::unique_ptr<sepal_asset> full_ = std::make_unique<sepal_asset>();
    std::unique_ptr<sepal_asset> shown_ = std::make_unique<sepal_asset>();
    TermPrefix prefix_;
    int terms_ = 0;
    int backend_ = 0;
    // The GL material, made under the context of mat_gles_ (0: none).
    std::unique_ptr<sepal_material> material_ = std::make_unique<sepal_material>();
    int mat_gles_ = 0;
    bool mat_stale_ = true;
    Blitter blit_[3];
    std::vector<float> scratch_;
    CpuFrame cpu_;
    std::vector<uint8_t> frame_, window_rgba_, strip_;
    OrbitView view_;
    int drag_button_ = 0, last_x_ = 0, last_y_ = 0;
    // Figures shown.
    double draw_ms_ = 0, frame_ms_ = 0;
    sepal_draw_stats stats_ = {};
    std::string error_;
    double psnr_ = 0;
    std::string psnr_key_;
    std::vector<uint8_t> exact_;
    std::string exact_key_;
    int shots_ = 0;
    std::string temp_dir_;
    std::vector<std::string> temp_files_;
};

Viewer::~Viewer() {
    if (window_) {
        release_material();
        for (int v = 1; v <= 2; ++v)
            if (blit_[v].gles && sepal_window_use_gles(window_, v, nullptr, 0)) blit_release(&blit_[v]);
        sepal_window_destroy(window_);
    }
    for (const std::string& f : temp_files_) remove(f.c_str());
    if (!temp_dir_.empty()) rmdir(temp_dir_.c_str());
}

std::string Viewer::temp(const char* name) {
    if (temp_dir_.empty()) {
        const char* base = getenv("TMPDIR");
        std::string tmpl = std::string(base && *base ? base : "/tmp") + "/sepal-view.XXXXXX";
        std::vector<char> buf(tmpl.begin(), tmpl.end());
        buf.push_back('\0');
        if (mkdtemp(buf.data())) temp_dir_ = buf.data();
    }
    // Without a private folder (mkdtemp failed): files named by the process in /tmp.
    const std::string path = temp_dir_.empty() ? "/tmp/sepal-view-" + std::to_string((int)getpid()) + "-" + name
                                               : temp_dir_ + "/" + name;
    if (std::find(temp_files_.begin(), temp_files_.end(), path) == temp_files_.end()) temp_files_.push_back(path);
    return path;
}

std::string Viewer::tool() { return sepal_tool(opt_.sepal_tool); }

bool Viewer::open_input(std::string* err) {
    struct stat st;
    const std::string& in = opt_.input;
    if (in.empty()) {
        *err = "give an asset (.sepal), a folder of assets or a BRDF spec to view (or --headless ... -o out.png)";
        return false;
    }
    if (stat(in.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
        assets_ = folder_assets(in);
        if (assets_.empty()) {
            *err = in + ": no .sepal assets in this folder";
            return false;
        }
        return true;
    }
    if (ends_with(in, ".sepal")) {
        const size_t slash = in.rfind('/');
        assets_ = folder_assets(slash == std::string::npos ? "." : in.substr(0, slash));
        const std::string self = slash == std::string::npos ? "./" + in : in;
        auto it = std::find(assets_.begin(), assets_.end(), self);
        if (it == assets_.end()) {  // unreadable folder, odd name: the file alone
            assets_ = {in};
            it = assets_.begin();
        }
        asset_index_ = size_t(it - assets_.begin());
        return true;
    }
    // A BRDF spec: baked into the temporary folder.
    const std::string out = temp("spec.sepal"), log = temp("bake.log");
    fprintf(stderr, "sepal-view: baking '%s' with %s ...\n", in.c_str(), tool().c_str());
    // gs-half only: a third of the default search, and drawn by every backend.
    const int code = run_process({tool(), "bake", in, "--param", "gs-half", "-o", out}, log);
    if (code != 0) {
        *err = "'" + in + "' is not an asset or folder, and `" + tool() + " bake` failed on it" +
               (code < 0 || code == 127 ? " (the sepal tool was not found: --sepal PATH)" : ": " + last_line(log));
        return false;
    }
    assets_ = {out};
    baked_spec_ = in;
    return true;
}

bool Viewer::load_asset(size_t index, std::string* err) {
    std::vector<uint8_t> bytes;
    sepal_error e = {};
    if (!read_asset_file(assets_[index], &bytes, err)) return false;
    auto parsed = std::make_unique<sepal_asset>();
    if (sepal_asset_parse(bytes.data(), bytes.size(), parsed.get(), &e) != SEPAL_OK) {
        *err = assets_[index] + ": " + e.message;
        return false;
    }
    release_material();
    bytes_.swap(bytes);  // the parsed asset points into these bytes
    full_ = std::move(parsed);
    asset_index_ = index;
    apply_prefix();
    return true;
}

void Viewer::apply_prefix() {
    prefix_ = term_prefix(*full_, terms_, shown_.get());
    mat_stale_ = true;
}

void Viewer::release_material() {
    if (mat_gles_ && sepal_window_use_gles(window_, mat_gles_, nullptr, 0)) sepal_material_destroy(material_.get());
    mat_gles_ = 0;
}

bool Viewer::ensure_material(std::string* err) {
    const int gles = backend_gles();
    if (!mat_stale_ && mat_gles_ == gles) return sepal_window_use_gles(window_, gles, nullptr, 0) != 0;
    release_material();
    char msg[256];
    if (!sepal_window_use_gles(window_, gles, msg, sizeof msg)) {
        *err = msg;
        return false;
    }
    sepal_caps caps;
    sepal_error e = {};
    if (sepal_query_caps(gles, opt_.mask, sepal_window_get_proc_address, &caps, &e) != SEPAL_OK ||
        sepal_material_create(&caps, shown_.get(), width_, height_, material_.get(), &e) != SEPAL_OK) {
        *err = e.message;
        mat_stale_ = true;
        return false;
    }
    // A context weaker than the device profile the asset was judged for: said once per material.
    if (sepal_profile_check(&caps, shown_.get(), nullptr, &e) != SEPAL_OK) fprintf(stderr, "sepal-view: warning: %s\n", e.message);
    mat_gles_ = gles;
    mat_stale_ = false;
    return true;
}

std::string Viewer::view_key() const {
    std::string key = shell_join(scene_args(setup_));
    return key + "|" + (baked_spec_.empty() ? assets_[asset_index_] : baked_spec_) + "|" + opt_.spec;
}

bool Viewer::exact_image(std::string* err) {
    const std::string key = view_key();
    if (exact_key_ == key && !exact_.empty()) return true;
    const std::string spec = !opt_.spec.empty() ? opt_.spec : !baked_spec_.empty() ? baked_spec_ : meta_spec(*full_);
    if (spec.empty()) {
        *err = "exact: the asset names no spec (META); pass --spec SPEC";
        return false;
    }
    const std::string out = temp("exact.png"), log = temp("exact.log");
    std::vector<std::string> args = {tool(), "render", spec, "--backend", "exact"};
    for (const std::string& a : scene_args(setup_)) args.push_back(a);
    args.push_back("-o");
    args.push_back(out);
    const int code = run_process(args, log);
    Rgba8Image img;
    if (code != 0 || !read_png_rgba8(out, &img, err) || img.width != width_ || img.height != height_) {
        *err = code == 127 || code < 0 ? "exact: needs the sepal tool (--sepal PATH or $SEPAL_CLI)"
                                       : "exact: " + (code != 0 ? last_line(log) : *err);
        return false;
    }
    exact_.swap(img.pixels);
    exact_key_ = key;
    return true;
}

// Draws the view and the status line into the back buffer; optionally reads the 3D view
// (frame_) and the whole window (window_rgba_) back before anyone swaps.
bool Viewer::draw(bool capture_view, bool capture_window) {
    error_.clear();
    stats_ = sepal_draw_stats{};
    auto start = std::chrono::steady_clock::now();
    std::string err;
    int blit_gles = 2;
    if (gl_backend()) {
        static const sepal_draw_mode kModes[] = {SEPAL_MODE_MULTIPASS, SEPAL_MODE_MULTIPASS, SEPAL_MODE_FUSED_VERTEX,
                                                 SEPAL_MODE_FUSED_PIXEL};
        blit_gles = backend_gles();
        const bool made = ensure_material(&err);
        start = std::chrono::steady_clock::now();  // material creation (uploads, shaders) is not the frame
        if (made) {
            const sepal_draw_desc d = scene_draw_desc(material_.get(), setup_, kModes[backend_], &scratch_);
            sepal_error e = {};
            if (sepal_draw(&d, &stats_, &e) != SEPAL_OK) err = e.message;
            glFinish();  // the frame is done when the GPU is
        }
    } else {
        sepal_window_use_gles(window_, 2, nullptr, 0);
        const size_t pixels = size_t(width_) * height_;
        frame_.assign(pixels * 4, 0);
        if (backend_ == 4) {
            const sepal_cpu_desc d = scene_cpu_desc(shown_.get(), setup_, &cpu_, &stats_);
            sepal_error e = {};
            if (sepal_draw_cpu(&d, &e) == SEPAL_OK)
                rgb_to_rgba8(cpu_.rgb.data(), pixels, frame_.data());
            else
                err = e.message;
        } else if (exact_image(&err)) {
            frame_ = exact_;
        }
        glClearColor(0, 0, 0, 1);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        std::string blit_err;
        if (!blit_rgba(&blit_[2], 2, frame_.data(), width_, height_, 0, kStrip, width_, height_ + kStrip, &blit_err))
            err = blit_err;
        glFinish();
    }
    draw_ms_ = ms_since(start);
    if (!err.empty()) {
        error_ = err;
        if (gl_backend()) {  // nothing trustworthy was drawn: a dark view says so
            glViewport(0, 0, width_, height_);
            glClearColor(0.15f, 0.05f, 0.05f, 1);
            glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        }
    }
    if (capture_view && gl_backend()) {
        frame_.resize(size_t(width_) * height_ * 4);
        if (!sepal_window_read_rgba(window_, 0, kStrip, width_, height_, frame_.data())) error_ = "read back failed";
    }
    text_strip(status_lines(), width_, kStrip, &strip_);
    std::string blit_err;
    if (!blit_rgba(&blit_[blit_gles], blit_gles, strip_.data(), width_, kStrip, 0, 0, width_, height_ + kStrip,
                   &blit_err) && error_.empty())
        error_ = blit_err;
    if (capture_window) {
        window_rgba_.resize(size_t(width_) * (height_ + kStrip) * 4);
        sepal_window_read_rgba(window_, 0, 0, width_, height_ + kStrip, window_rgba_.data());
    }
    return error_.empty();
}

void Viewer::present() {
    const auto start = std::chrono::steady_clock::now();
    draw(false, false);
    sepal_window_swap(window_);
    frame_ms_ = ms_since(start);
}

std::vector<std::string> Viewer::status_lines() const {
    char a[256], b[320];
    const std::string& path = baked_spec_.empty() ? assets_[asset_index_] : baked_spec_;
    const size_t slash = path.rfind('/');
    snprintf(a, sizeof a, "[%zu/%zu] %s | %s | terms %d/%u%s | %s | %.1f KB textures | h: help", asset_index_ + 1,
             assets_.size(), (slash == std::string::npos ? path : path.substr(slash + 1)).c_str(), kBackends[backend_],
             prefix_.terms, full_->material.terms, prefix_.unattributed ? " (approx.)" : "", setup_.mesh_name.c_str(),
             prefix_.texture_bytes / 1024.0);
    if (!error_.empty()) {
        snprintf(b, sizeof b, "error: %s", error_.c_str());
    } else {
        std::string psnr = "p: PSNR";
        char buf[64];
        if (psnr_key_ == view_key() + "|" + kBackends[backend_] + "|" + std::to_string(prefix_.terms)) {
            snprintf(buf, sizeof buf, "PSNR %.2f dB vs exact", psnr_);
            psnr = buf;
        }
        snprintf(b, sizeof b, "draw %.2f ms, frame %.2f ms | %d draws + %d full-screen | %s", draw_ms_, frame_ms_,
                 stats_.draw_calls, stats_.fullscreen_passes, psnr.c_str());
    }
    return {a, b};
}

void Viewer::measure_psnr() {
    std::string err;
    if (!draw(true, false)) return present();
    const std::vector<uint8_t> view = frame_;
    if (!exact_image(&err)) {
        error_ = err;
        text_strip(status_lines(), width_, kStrip, &strip_);
        fprintf(stderr, "sepal-view: %s\n", err.c_str());
        return present();
    }
    psnr_ = psnr_rgb(exact_, view);
    psnr_key_ = view_key() + "|" + kBackends[backend_] + "|" + std::to_string(prefix_.terms);
    printf("psnr %.2f dB (%s, %d terms, against exact)\n", psnr_, kBackends[backend_], prefix_.terms);
    fflush(stdout);
    present();
}

void Viewer::screenshot() {
    draw(true, true);
    char name[64];
    // The next number whose files are all absent: a second session in the same folder
    // continues after the first one's shots instead of overwriting them.
    std::string base;
    for (;;) {
        snprintf(name, sizeof name, "shot-%03d", ++shots_);
        base = opt_.shot_dir + "/" + name;
        bool taken = false;
        for (const char* ext : {".png", "-window.png", ".txt", ".sepal", ".headless.png"})
            taken = taken || access((base + ext).c_str(), F_OK) == 0;
        if (!taken) break;
    }
    std::vector<std::string> cmd;
    if (backend_ == 5) {
        const std::string spec = !opt_.spec.empty() ? opt_.spec : !baked_spec_.empty() ? baked_spec_ : meta_spec(*full_);
        cmd = {"sepal", "render", spec, "--backend", "exact"};
    } else {
        // A spec's asset lives in a temporary folder: the shot keeps a copy.
        std::string asset = assets_[asset_index_];
        if (!baked_spec_.empty()) {
            asset = opt_.shot_dir + "/" + name + ".sepal";
            FILE* f = fopen(asset.c_str(), "wb");
            if (!f || fwrite(bytes_.data(), 1, bytes_.size(), f) != bytes_.size())
                fprintf(stderr, "sepal-view: could not write %s\n", asset.c_str());
            if (f) fclose(f);
        }
        cmd = {"sepal-view", "--headless", asset, "--backend", kBackends[backend_]};
    }
    for (const std::string& a : scene_args(setup_)) cmd.push_back(a);
    if (opt_.mask && gl_backend()) cmd.insert(cmd.begin() + 5, {"--mask", mask_names(opt_.mask)});
    cmd.push_back("-o");
    cmd.push_back(base + ".headless.png");
    const std::string line = shell_join(cmd);
    bool ok = write_png_atomic(base + ".png", width_, height_, frame_.data()) &&
              write_png_atomic(base + "-window.png", width_, height_ + kStrip, window_rgba_.data());
    if (FILE* f = ok ? fopen((base + ".txt").c_str(), "w") : nullptr) {
        fprintf(f, "%s\n", line.c_str());
        if (prefix_.terms != (int)full_->material.terms)
            fprintf(f, "# shown with the first %d of %u terms (digit keys); the command draws all\n", prefix_.terms,
                    full_->material.terms);
        ok = fclose(f) == 0;
    } else {
        ok = false;
    }
    if (ok)
        printf("screenshot %s.png: %s\n", base.c_str(), line.c_str());
    else
        fprintf(stderr, "sepal-view: could not write %s.png / .txt\n", base.c_str());
    fflush(stdout);
    present();
}

bool Viewer::handle(const sepal_window_event& e) {
    std::string err;
    switch (e.type) {
        case SEPAL_WINDOW_EVENT_CLOSE: return false;
        case SEPAL_WINDOW_EVENT_BUTTON_DOWN:
            if (e.button == 1 || e.button == 3) drag_button_ = e.button == 1 && !e.shift ? 1 : 3;
            last_x_ = e.x, last_y_ = e.y;
            return true;
        case SEPAL_WINDOW_EVENT_BUTTON_UP:
            drag_button_ = 0;
            return true;
        case SEPAL_WINDOW_EVENT_MOTION: {
            const int dx = e.x - last_x_, dy = e.y - last_y_;
            last_x_ = e.x, last_y_ = e.y;
            if (drag_button_ == 1) view_.orbit((float)dx, (float)dy);
            if (drag_button_ == 3) view_.move_light((float)dx, (float)dy);
            if (drag_button_ && (dx || dy)) set_view();
            return true;
        }
        case SEPAL_WINDOW_EVENT_SCROLL:
            view_.zoom(e.scroll);
            set_view();
            return true;
        case SEPAL_WINDOW_EVENT_KEY: break;
        default: return true;
    }
    const int k = e.key;
    if (k == 'q' || k == SEPAL_KEY_ESCAPE) return false;
    if (k == 'b' || k == 'B') {
        backend_ = (backend_ + (k == 'b' ? 1 : kBackendCount - 1)) % kBackendCount;
    } else if (k >= '0' && k <= '9') {
        terms_ = k - '0';
        apply_prefix();
    } else if (k == 'm' || k == 'M') {
        mesh_index_ = (mesh_index_ + (k == 'm' ? 1 : meshes_.size() - 1)) % meshes_.size();
        setup_.mesh_name = meshes_[mesh_index_];
        if (!load_scene_mesh(&setup_, &err)) error_ = err;
    } else if (k == 'n' || k == 'N') {
        const size_t next = (asset_index_ + (k == 'n' ? 1 : assets_.size() - 1)) % assets_.size();
        if (!load_asset(next, &err)) fprintf(stderr, "sepal-view: %s\n", err.c_str());
    } else if (k == '+' || k == '=' || k == '-') {
        view_.zoom(k == '-' ? -1 : 1);
        set_view();
    } else if (k == SEPAL_KEY_LEFT || k == SEPAL_KEY_RIGHT || k == SEPAL_KEY_UP || k == SEPAL_KEY_DOWN) {
        const float step = 5.0f / kOrbitDegreesPerPixel;  // 5 degrees
        view_.orbit(k == SEPAL_KEY_LEFT ? -step : k == SEPAL_KEY_RIGHT ? step : 0,
                    k == SEPAL_KEY_UP ? step : k == SEPAL_KEY_DOWN ? -step : 0);
        set_view();
    } else if (k == 'r') {
        view_.restore();
        set_view();
    } else if (k == 'h' || k == '?') {
        fputs(kHelp, stdout);
        fflush(stdout);
    } else if (k == 'p') {
        measure_psnr();  // synchronous: scripted input sees the PSNR of this very view
    } else if (k == 's') {
        screenshot();
    }
    return true;
}

int Viewer::benchmark() {
    std::vector<double> frames, draws;
    for (int i = 0; i < opt_.frames + 2; ++i) {  // two warm-up frames
        present();
        if (!error_.empty()) {
            fprintf(stderr, "sepal-view: %s\n", error_.c_str());
            return 1;
        }
        if (i >= 2) frames.push_back(frame_ms_), draws.push_back(draw_ms_);
    }
    printf("frames %d %s %dx%d terms %d: median %.3f ms/frame, draw %.3f ms (%s)\n", opt_.frames, kBackends[backend_],
           width_, height_, prefix_.terms, median(frames), median(draws), sepal_window_describe(window_));
    return 0;
}

int Viewer::run() {
    std::string err;
    if (!open_input(&err) || !load_scene_mesh(&setup_, &err)) {
        fprintf(stderr, "sepal-view: %s\n", err.c_str());
        return 2;
    }
    for (const char* m : kMeshes) meshes_.push_back(m);
    auto it = std::find(meshes_.begin(), meshes_.end(), setup_.mesh_name);
    if (it == meshes_.end()) it = meshes_.insert(meshes_.end(), setup_.mesh_name);
    mesh_index_ = size_t(it - meshes_.begin());
    for (int b = 0; b < kBackendCount; ++b)
        if (opt_.backend == kBackends[b]) backend_ = b;
    terms_ = opt_.terms;
    if (!load_asset(asset_index_, &err)) {
        fprintf(stderr, "sepal-view: %s\n", err.c_str());
        return 2;
    }
    width_ = setup_.width;
    height_ = setup_.height;
    view_.reset(setup_.scene);
    sepal_window_desc wd = {};
    wd.width = width_;
    wd.height = height_ + kStrip;
    wd.gles_version = backend_gles();
    wd.title = "sepal-view";
    char msg[512];
    window_ = sepal_window_create(&wd, msg, sizeof msg);
    if (!window_) {
        fprintf(stderr, "sepal-view: %s\n", msg);
        return 1;
    }
    // The scene is drawn as given until the first drag (no round trip through angles).
    if (opt_.frames > 0) return benchmark();
    printf("sepal-view: %s; h for help\n", sepal_window_describe(window_));
    fflush(stdout);
    present();
    for (bool running = true; running;) {
        sepal_window_event e;
        bool redraw = false;
        sepal_window_poll(window_, &e, 1);  // wait for the first, then take what is queued
        do {
            running = handle(e);
            redraw = true;
        } while (running && sepal_window_poll(window_, &e, 0));
        if (running && redraw) present();
    }
    return 0;
}

}  // namespace

int parse_viewer_flag(int argc, char** argv, int i, ViewerOptions* o, std::string* err) {
    const std::string flag = argv[i];
    static const char* const kFlags[] = {"--shot-dir", "--sepal", "--spec", "--terms", "--frames"};
    bool known = false;
    for (const char* f : kFlags) known = known || flag == f;
    if (!known) return 0;
    if (i + 1 >= argc) {
        *err = flag + " needs a value";
        return -1;
    }
    const std::string value = argv[i + 1];
    if (flag == "--shot-dir") o->shot_dir = value;
    if (flag == "--sepal") o->sepal_tool = value;
    if (flag == "--spec") o->spec = value;
    if (flag == "--terms" || flag == "--frames") {
        char* end = nullptr;
        const long v = strtol(value.c_str(), &end, 10);
        if (end == value.c_str() || *end || v < 0 || v > (flag == "--terms" ? SEPAL_FMT_MAX_TERMS : 100000)) {
            *err = flag + " '" + value + "': expected a count (terms 0..16, frames 0..100000)";
            return -1;
        }
        (flag == "--terms" ? o->terms : o->frames) = int(v);
    }
    return 2;
}

const char* viewer_flags_help() {
    return "  --shot-dir DIR        where s writes screenshots (default .)\n"
           "  --sepal PATH          the sepal tool for exact renders, PSNR and specs (default: beside sepal-view)\n"
           "  --spec SPEC           the BRDF the exact backend renders (default: the asset's META spec)\n"
           "  --terms K             start with the first K terms\n"
           "  --frames N            draw N frames, print the median frame time and exit\n";
}

int run_viewer(const ViewerOptions& options, SceneSetup* setup) {
    Viewer v(options, setup);
    return v.run();
}

}  // namespace sepal_ports
