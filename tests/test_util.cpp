#include "test_util.h"

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "headless/sepal_headless.h"
#include "util/io.h"

#include <EGL/egl.h>
#include <GLES2/gl2.h>

namespace sepal_test {

std::string source_path(const std::string& relative) {
    return std::string(SEPAL_SOURCE_DIR) + "/" + relative;
}

std::string output_dir() {
    const char* env = std::getenv("SEPAL_TEST_OUTPUT");
    std::string dir = env && *env ? env : source_path("build/test-output");
    sepal::make_dirs(dir, nullptr);
    return dir;
}

std::string temp_dir() {
    std::string tmpl = output_dir() + "/tmp.XXXXXX";
    std::vector<char> buf(tmpl.begin(), tmpl.end());
    buf.push_back('\0');
    const char* made = mkdtemp(buf.data());
    return made ? std::string(made) : output_dir();
}

std::string bin(const std::string& name) { return std::string(SEPAL_BIN_DIR) + "/" + name; }

std::string build_dir() {
    const std::string exe = sepal::executable_dir();
    return exe.substr(0, exe.rfind('/'));
}

bool update_goldens() {
    const char* env = std::getenv("SEPAL_UPDATE_GOLDENS");
    return env && std::strcmp(env, "1") == 0;
}

std::string check_golden_in(const std::string& golden_dir, const std::string& name,
                            const sepal::Image& actual, const sepal::Tolerance& tol, bool owner,
                            bool update) {
    const std::string golden = golden_dir + "/" + name + ".png";
    std::string err;
    if (update) {
        if (!owner) return "";
        if (!sepal::make_dirs(golden_dir, &err) || !sepal::write_png(golden, actual, &err))
            return "could not update golden: " + err;
        std::printf("updated golden %s\n", golden.c_str());
        return "";
    }
    sepal::Image expected;
    const std::string out = output_dir() + "/" + name;
    if (!sepal::read_image(golden, &expected, &err)) {
        sepal::write_png(out + ".actual.png", actual, nullptr);
        return "golden missing or unreadable (" + err + "); actual image: " + out +
               ".actual.png; run `make update-goldens` to create it";
    }
    const sepal::ImageDiff d =
        sepal::diff_images(expected, actual, sepal::tolerance_threshold(tol));
    std::string why;
    if (sepal::tolerance_holds(d, tol, &why)) return "";
    sepal::write_png(out + ".actual.png", actual, nullptr);
    sepal::write_png(out + ".expected.png", expected, nullptr);
    if (d.comparable)
        sepal::write_png(out + ".heatmap.png",
                         sepal::diff_heatmap(expected, actual, d.max_diff > 0 ? d.max_diff : 1),
                         nullptr);
    char psnr[64];
    std::snprintf(psnr, sizeof psnr, "%.2f", d.psnr);
    return "golden '" + name + "' differs: " + why + " (PSNR " + psnr + " dB). See " + out +
           ".actual.png, " + out + ".expected.png" +
           (d.comparable ? ", " + out + ".heatmap.png" : std::string());
}

std::string check_golden(const std::string& name, const sepal::Image& actual,
                         const sepal::Tolerance& tol, bool owner) {
    return check_golden_in(source_path("fixtures/golden"), name, actual, tol, owner,
                           update_goldens());
}

const std::string& gl_renderer() {
    static const std::string renderer = [] {
        // The probe's context replaces the caller's as current: put the caller's back, or a
        // test whose first golden check comes between two draws loses its context (the caps
        // test, run alone, did).
        const EGLDisplay dpy = eglGetCurrentDisplay();
        const EGLContext ctx = eglGetCurrentContext();
        const EGLSurface draw = eglGetCurrentSurface(EGL_DRAW), read = eglGetCurrentSurface(EGL_READ);
        struct Restore {
            EGLDisplay dpy;
            EGLContext ctx;
            EGLSurface draw, read;
            ~Restore() {
                if (ctx != EGL_NO_CONTEXT) eglMakeCurrent(dpy, draw, read, ctx);
            }
        } restore{dpy, ctx, draw, read};
        sepal_headless_desc d = {};
        d.width = d.height = 4;
        char err[512];
        sepal_headless_context* c = sepal_headless_create(&d, err, sizeof err);
        if (!c) return std::string();
        const char* r = (const char*)glGetString(GL_RENDERER);
        std::string out = r ? r : "";
        sepal_headless_destroy(c);
        return out;
    }();
    return renderer;
}

// Fails closed: a probe that cannot make a context counts as the reference (strict bounds).
bool reference_renderer() {
    return gl_renderer().empty() || gl_renderer().find("llvmpipe") != std::string::npos;
}

std::string check_gl_golden(const std::string& name, const sepal::Image& actual,
                            const sepal::Tolerance& tol, bool owner) {
    if (!reference_renderer() && update_goldens()) {  // never overwrite llvmpipe's goldens
        std::printf("note: golden '%s' not updated: goldens are llvmpipe's, this is '%s'\n", name.c_str(),
                    gl_renderer().c_str());
        return "";
    }
    const std::string msg = check_golden(name, actual, tol, owner);
    if (msg.empty() || reference_renderer()) return msg;
    std::printf("note: golden '%s' is llvmpipe's, not enforced on '%s': %s\n", name.c_str(),
                gl_renderer().c_str(), msg.c_str());
    return "";
}

int run_cmd(const char* command, const std::vector<std::string>& args, std::string* out) {
    std::FILE* o = std::tmpfile();
    std::FILE* e = std::tmpfile();
    sepal::CommandIO io;
    io.out = o;
    io.err = e;
    const int code = sepal::run_command(command, args, io);
    std::string text;
    for (std::FILE* f : {o, e}) {
        std::rewind(f);
        char buf[512];
        size_t n;
        while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) text.append(buf, n);
        std::fclose(f);
    }
    if (out) *out = text;
    return code;
}

int run(const std::string& command, std::string* out) {
    FILE* p = popen((command + " 2>&1").c_str(), "r");
    if (!p) return -1;
    std::string text;
    char buf[4096];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) text.append(buf, n);
    const int status = pclose(p);
    if (out) *out = text;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace sepal_test
