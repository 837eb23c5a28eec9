// Headless EGL port: see sepal_headless.h.
#include "headless/sepal_headless.h"

#include "egl/port_util.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES2/gl2.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct sepal_headless_context {
    EGLDisplay display;
    EGLSurface surface;
    EGLContext context;
    int width, height;
    int gles_version;  // as requested: 1 or 2
    char description[512];
};

using sepal_ports::set_error;

// Opens and initializes a display; returns the platform's name in *platform.
static EGLDisplay open_display(const char** platform, char* err, size_t n) {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const char* forced = getenv("SEPAL_EGL_PLATFORM");
    auto get_platform_display =
        (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    const char* order[3] = {"surfaceless", "device", "default"};
    int count = 3;
    if (forced && *forced) {
        order[0] = forced;
        count = 1;
    }
    char tried[256] = "";
    for (int i = 0; i < count; ++i) {
        const char* name = order[i];
        EGLDisplay d = EGL_NO_DISPLAY;
        if (strcmp(name, "surfaceless") == 0) {
            if (get_platform_display && sepal_ports::egl_has_ext(client, "EGL_MESA_platform_surfaceless"))
                d = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY,
                                         nullptr);
        } else if (strcmp(name, "device") == 0) {
            auto query_devices =
                (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
            if (get_platform_display && query_devices &&
                sepal_ports::egl_has_ext(client, "EGL_EXT_platform_device")) {
                EGLDeviceEXT devices[8];
                EGLint num = 0;
                if (query_devices(8, devices, &num) && num > 0)
                    d = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[0], nullptr);
            }
        } else if (strcmp(name, "default") == 0) {
            d = eglGetDisplay(EGL_DEFAULT_DISPLAY);
        } else {
            set_error(err, n, "SEPAL_EGL_PLATFORM='%s' is not one of surfaceless, device, default",
                    name);
            return EGL_NO_DISPLAY;
        }
        if (d != EGL_NO_DISPLAY) {
            EGLint major = 0, minor = 0;
            if (eglInitialize(d, &major, &minor)) {
                *platform = name;
                return d;
            }
        }
        size_t len = strlen(tried);
        snprintf(tried + len, sizeof tried - len, "%s%s", len ? ", " : "", name);
    }
    set_error(err, n,
            "no usable EGL display (tried: %s). Install Mesa's EGL (libegl-mesa0, "
            "libgl1-mesa-dri) or set SEPAL_EGL_PLATFORM; client extensions: %s",
            tried, client ? client : "(none: EGL 1.5 client extensions unsupported)");
    return EGL_NO_DISPLAY;
}

extern "C" sepal_headless_context* sepal_headless_create(const sepal_headless_desc* desc, char* err, size_t err_len) {
    sepal_headless_desc d = desc ? *desc : sepal_headless_desc{};
    if (d.width == 0) d.width = 256;
    if (d.height == 0) d.height = 256;
    if (d.gles_version == 0) d.gles_version = 1;
    if (d.depth_bits == 0) d.depth_bits = 16;
    if (!sepal_ports::check_request("image", d.width, d.height, 16384, d.gles_version, err, err_len)) return nullptr;

    const char* platform = "";
    EGLDisplay display = open_display(&platform, err, err_len);
    if (display == EGL_NO_DISPLAY) return nullptr;

    if (!eglBindAPI(EGL_OPENGL_ES_API)) {
        set_error(err, err_len, "eglBindAPI(EGL_OPENGL_ES_API) failed: %s",
                sepal_ports::egl_error_name(eglGetError()));
        return nullptr;
    }
    if (d.framebuffer != 0 && d.framebuffer != 8888 && d.framebuffer != 565) {
        set_error(err, err_len, "framebuffer %d is not 8888 or 565", d.framebuffer);
        return nullptr;
    }
    const bool rgb565 = d.framebuffer == 565;
    const EGLint renderable = d.gles_version == 1 ? EGL_OPENGL_ES_BIT : EGL_OPENGL_ES2_BIT;
    const EGLint want[4] = {rgb565 ? 5 : 8, rgb565 ? 6 : 8, rgb565 ? 5 : 8, rgb565 ? 0 : 8};
    const EGLint config_attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
                                     EGL_RENDERABLE_TYPE, renderable,
                                     EGL_RED_SIZE, want[0], EGL_GREEN_SIZE, want[1], EGL_BLUE_SIZE, want[2],
                                     EGL_ALPHA_SIZE, want[3], EGL_DEPTH_SIZE, d.depth_bits,
                                     EGL_NONE};
    // EGL sorts deeper colour buffers first: 565 must pick its exact match from the list.
    EGLConfig configs[128];
    EGLint num_configs = 0;
    EGLConfig config = nullptr;
    if (eglChooseConfig(display, config_attribs, configs, rgb565 ? 128 : 1, &num_configs))
        for (EGLint i = 0; i < num_configs && !config; ++i) {
            const EGLint attribs[4] = {EGL_RED_SIZE, EGL_GREEN_SIZE, EGL_BLUE_SIZE, EGL_ALPHA_SIZE};
            bool exact = true;
            for (int k = 0; k < 4 && rgb565; ++k) {
                EGLint v = -1;
                exact = exact && eglGetConfigAttrib(display, configs[i], attribs[k], &v) && v == want[k];
            }
            if (exact) config = configs[i];
        }
    if (!config) {
        set_error(err, err_len,
                "EGL platform '%s' has no %s pbuffer config with %d depth bits for GL ES %d "
                "(vendor %s)",
                platform, rgb565 ? "RGB565" : "RGBA8", d.depth_bits, d.gles_version,
                eglQueryString(display, EGL_VENDOR));
        return nullptr;
    }
    const EGLint surface_attribs[] = {EGL_WIDTH, d.width, EGL_HEIGHT, d.height, EGL_NONE};
    EGLSurface surface = eglCreatePbufferSurface(display, config, surface_attribs);
    if (surface == EGL_NO_SURFACE) {
        set_error(err, err_len, "eglCreatePbufferSurface %dx%d failed: %s", d.width, d.height,
                sepal_ports::egl_error_name(eglGetError()));
        return nullptr;
    }
    const EGLint context_attribs[] = {EGL_CONTEXT_CLIENT_VERSION, d.gles_version, EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attribs);
    if (context == EGL_NO_CONTEXT) {
        set_error(err, err_len, "EGL platform '%s' cannot create a GL ES %d context: %s",
                platform, d.gles_version, sepal_ports::egl_error_name(eglGetError()));
        eglDestroySurface(display, surface);
        return nullptr;
    }
    if (!eglMakeCurrent(display, surface, surface, context)) {
        set_error(err, err_len, "eglMakeCurrent failed: %s", sepal_ports::egl_error_name(eglGetError()));
        eglDestroyContext(display, context);
        eglDestroySurface(display, surface);
        return nullptr;
    }
    sepal_headless_context* c = (sepal_headless_context*)calloc(1, sizeof(sepal_headless_context));
    if (!c) {
        set_error(err, err_len, "out of memory");
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display, context);
        eglDestroySurface(display, surface);
        return nullptr;
    }
    c->display = display;
    c->surface = surface;
    c->context = context;
    c->width = d.width;
    c->height = d.height;
    c->gles_version = d.gles_version;
    const char* renderer = (const char*)glGetString(GL_RENDERER);
    const char* version = (const char*)glGetString(GL_VERSION);
    snprintf(c->description, sizeof c->description, "EGL %s (%s) | %s | %s", platform,
             eglQueryString(display, EGL_VENDOR), renderer ? renderer : "?",
             version ? version : "?");
    return c;
}

extern "C" int sepal_headless_make_current(sepal_headless_context* c) {
    return c && eglMakeCurrent(c->display, c->surface, c->surface, c->context) ? 1 : 0;
}

extern "C" int sepal_headless_read_rgba(sepal_headless_context* c, uint8_t* out) {
    if (!c || !out) return 0;
    glFinish();
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, c->width, c->height, GL_RGBA, GL_UNSIGNED_BYTE, out);
    if (glGetError() != GL_NO_ERROR) return 0;
    sepal_ports::flip_rows(out, c->width, c->height);
    return 1;
}

extern "C" int sepal_headless_width(const sepal_headless_context* c) { return c ? c->width : 0; }
extern "C" int sepal_headless_height(const sepal_headless_context* c) { return c ? c->height : 0; }
extern "C" int sepal_headless_gles_version(const sepal_headless_context* c) { return c ? c->gles_version : 0; }
extern "C" const char* sepal_headless_describe(const sepal_headless_context* c) { return c ? c->description : ""; }

extern "C" void sepal_headless_destroy(sepal_headless_context* c) {
    if (!c) return;
    eglMakeCurrent(c->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(c->display, c->context);
    eglDestroySurface(c->display, c->surface);
    // eglTerminate is not called: Mesa shares the display between contexts of the
    // process and terminating it under another live context would invalidate it.
    eglReleaseThread();
    free(c);
}

extern "C" sepal_headless_proc sepal_headless_get_proc_address(const char* name) {
    return (sepal_headless_proc)eglGetProcAddress(name);
}
