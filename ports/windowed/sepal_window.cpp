// Windowed EGL port on X11: see sepal_window.h.
#include "windowed/sepal_window.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES2/gl2.h>
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/keysym.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "egl/port_util.h"

using sepal_ports::egl_error_name;
using sepal_ports::set_error;

struct sepal_window {
    Display* x;
    Window window;
    Colormap colormap;
    Atom wm_delete;
    EGLDisplay display;
    EGLConfig config;
    EGLSurface surface;
    EGLContext contexts[3];  // by GL ES version (1, 2)
    int current;
    int width, height;
    char description[512];
};

namespace {

EGLDisplay open_egl(Display* x) {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto get_platform_display = (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    if (get_platform_display && (sepal_ports::egl_has_ext(client, "EGL_KHR_platform_x11") ||
                                 sepal_ports::egl_has_ext(client, "EGL_EXT_platform_x11")))
        return get_platform_display(EGL_PLATFORM_X11_KHR, x, nullptr);
    return eglGetDisplay((EGLNativeDisplayType)x);
}

void destroy_partial(sepal_window* w) {
    if (w->display != EGL_NO_DISPLAY) {
        eglMakeCurrent(w->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        for (EGLContext c : w->contexts)
            if (c != EGL_NO_CONTEXT) eglDestroyContext(w->display, c);
        if (w->surface != EGL_NO_SURFACE) eglDestroySurface(w->display, w->surface);
        // No eglTerminate: Mesa shares the display with any headless context of the process.
        eglReleaseThread();
    }
    if (w->x) {
        if (w->window) XDestroyWindow(w->x, w->window);
        if (w->colormap) XFreeColormap(w->x, w->colormap);
        XCloseDisplay(w->x);
    }
    free(w);
}

int key_code(XKeyEvent* e) {
    char text[8] = {0};
    KeySym sym = 0;
    const int n = XLookupString(e, text, sizeof text, &sym, nullptr);
    switch (sym) {
        case XK_Escape: return SEPAL_KEY_ESCAPE;
        case XK_Left: return SEPAL_KEY_LEFT;
        case XK_Right: return SEPAL_KEY_RIGHT;
        case XK_Up: return SEPAL_KEY_UP;
        case XK_Down: return SEPAL_KEY_DOWN;
        default: break;
    }
    return n == 1 && (unsigned char)text[0] >= 32 && (unsigned char)text[0] < 127 ? text[0] : 0;
}

}  // namespace

extern "C" sepal_window* sepal_window_create(const sepal_window_desc* desc, char* err, size_t err_len) {
    sepal_window_desc d = desc ? *desc : sepal_window_desc{};
    if (d.width == 0) d.width = 512;
    if (d.height == 0) d.height = 512;
    if (d.gles_version == 0) d.gles_version = 2;
    if (d.depth_bits == 0) d.depth_bits = 16;
    if (!sepal_ports::check_request("window", d.width, d.height, 8192, d.gles_version, err, err_len)) return nullptr;
    sepal_window* w = (sepal_window*)calloc(1, sizeof(sepal_window));
    if (!w) {
        set_error(err, err_len, "out of memory");
        return nullptr;
    }
    w->display = EGL_NO_DISPLAY;
    w->surface = EGL_NO_SURFACE;
    for (EGLContext& c : w->contexts) c = EGL_NO_CONTEXT;
    w->width = d.width;
    w->height = d.height;
    w->x = XOpenDisplay(nullptr);
    if (!w->x) {
        const char* name = getenv("DISPLAY");
        set_error(err, err_len, "cannot open the X display '%s' (no X server? try xvfb-run, or --headless)",
                  name ? name : "(DISPLAY unset)");
        destroy_partial(w);
        return nullptr;
    }
    w->display = open_egl(w->x);
    EGLint major = 0, minor = 0;
    if (w->display == EGL_NO_DISPLAY || !eglInitialize(w->display, &major, &minor)) {
        set_error(err, err_len, "EGL cannot use the X display: %s (install libegl-mesa0)",
                  egl_error_name(eglGetError()));
        w->display = EGL_NO_DISPLAY;
        destroy_partial(w);
        return nullptr;
    }
    eglBindAPI(EGL_OPENGL_ES_API);
    // One config both GL ES versions render with, so either context can use the surface.
    const EGLint attribs[] = {EGL_SURFACE_TYPE, EGL_WINDOW_BIT,
                              EGL_RENDERABLE_TYPE, EGL_OPENGL_ES_BIT | EGL_OPENGL_ES2_BIT,
                              EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8,
                              EGL_DEPTH_SIZE, d.depth_bits, EGL_NONE};
    EGLint count = 0;
    if (!eglChooseConfig(w->display, attribs, &w->config, 1, &count) || count < 1) {
        set_error(err, err_len, "no RGB8 window config with %d depth bits renderable by GL ES 1.1 and 2 (EGL %s)",
                  d.depth_bits, eglQueryString(w->display, EGL_VENDOR));
        destroy_partial(w);
        return nullptr;
    }
    EGLint visual_id = 0;
    eglGetConfigAttrib(w->display, w->config, EGL_NATIVE_VISUAL_ID, &visual_id);
    XVisualInfo want = {};
    want.visualid = (VisualID)visual_id;
    int visuals = 0;
    XVisualInfo* vi = XGetVisualInfo(w->x, VisualIDMask, &want, &visuals);
    if (!vi) {
        set_error(err, err_len, "the X server has no visual 0x%x for the EGL config", (unsigned)visual_id);
        destroy_partial(w);
        return nullptr;
    }
    const Window root = RootWindow(w->x, vi->screen);
    XSetWindowAttributes swa = {};
    w->colormap = swa.colormap = XCreateColormap(w->x, root, vi->visual, AllocNone);
    swa.event_mask = KeyPressMask | ButtonPressMask | ButtonReleaseMask | PointerMotionMask | ExposureMask |
                     StructureNotifyMask;
    w->window = XCreateWindow(w->x, root, 0, 0, (unsigned)d.width, (unsigned)d.height, 0, vi->depth, InputOutput,
                              vi->visual, CWColormap | CWEventMask, &swa);
    XFree(vi);
    XSizeHints hints = {};  // fixed size: the runtime's material is made for one viewport
    hints.flags = PMinSize | PMaxSize;
    hints.min_width = hints.max_width = d.width;
    hints.min_height = hints.max_height = d.height;
    XSetWMNormalHints(w->x, w->window, &hints);
    XStoreName(w->x, w->window, d.title ? d.title : "sepal");
    w->wm_delete = XInternAtom(w->x, "WM_DELETE_WINDOW", False);
    XSetWMProtocols(w->x, w->window, &w->wm_delete, 1);
    XMapWindow(w->x, w->window);
    for (XEvent e;;) {  // draw only once mapped (and so that scripted input finds it)
        XWindowEvent(w->x, w->window, StructureNotifyMask, &e);
        if (e.type == MapNotify) break;
    }
    w->surface = eglCreateWindowSurface(w->display, w->config, (EGLNativeWindowType)w->window, nullptr);
    if (w->surface == EGL_NO_SURFACE) {
        set_error(err, err_len, "eglCreateWindowSurface failed: %s", egl_error_name(eglGetError()));
        destroy_partial(w);
        return nullptr;
    }
    if (!sepal_window_use_gles(w, d.gles_version, err, err_len)) {
        destroy_partial(w);
        return nullptr;
    }
    // Frames are drawn on demand; a swap interval would only add latency to measurements.
    eglSwapInterval(w->display, 0);
    return w;
}

extern "C" int sepal_window_use_gles(sepal_window* w, int version, char* err, size_t err_len) {
    if (!w || (version != 1 && version != 2)) {
        set_error(err, err_len, "sepal_window_use_gles: no window, or version %d is not 1 or 2", version);
        return 0;
    }
    if (w->contexts[version] == EGL_NO_CONTEXT) {
        const EGLint attribs[] = {EGL_CONTEXT_CLIENT_VERSION, version, EGL_NONE};
        w->contexts[version] = eglCreateContext(w->display, w->config, EGL_NO_CONTEXT, attribs);
        if (w->contexts[version] == EGL_NO_CONTEXT) {
            set_error(err, err_len, "cannot create a GL ES %d context: %s", version, egl_error_name(eglGetError()));
            return 0;
        }
    }
    if (!eglMakeCurrent(w->display, w->surface, w->surface, w->contexts[version])) {
        set_error(err, err_len, "eglMakeCurrent (GL ES %d) failed: %s", version, egl_error_name(eglGetError()));
        return 0;
    }
    w->current = version;
    const char* renderer = (const char*)glGetString(GL_RENDERER);
    const char* gl_version = (const char*)glGetString(GL_VERSION);
    snprintf(w->description, sizeof w->description, "EGL x11 (%s) | %s | %s", eglQueryString(w->display, EGL_VENDOR),
             renderer ? renderer : "?", gl_version ? gl_version : "?");
    return 1;
}

extern "C" int sepal_window_gles(const sepal_window* w) { return w ? w->current : 0; }

extern "C" int sepal_window_poll(sepal_window* w, sepal_window_event* ev, int wait) {
    if (!w || !ev) return 0;
    while (wait || XPending(w->x) > 0) {
        XEvent e;
        XNextEvent(w->x, &e);
        *ev = sepal_window_event{};
        switch (e.type) {
            case KeyPress:
                ev->type = SEPAL_WINDOW_EVENT_KEY;
                ev->key = key_code(&e.xkey);
                ev->shift = (e.xkey.state & ShiftMask) != 0;
                if (ev->key) return 1;
                break;
            case ButtonPress:
            case ButtonRelease:
                // X reports the wheel as buttons 4 (away) and 5 (towards).
                if (e.xbutton.button == 4 || e.xbutton.button == 5) {
                    if (e.type == ButtonRelease) break;
                    ev->type = SEPAL_WINDOW_EVENT_SCROLL;
                    ev->scroll = e.xbutton.button == 4 ? 1 : -1;
                } else {
                    ev->type = e.type == ButtonPress ? SEPAL_WINDOW_EVENT_BUTTON_DOWN : SEPAL_WINDOW_EVENT_BUTTON_UP;
                    ev->button = (int)e.xbutton.button;
                }
                ev->x = e.xbutton.x;
                ev->y = e.xbutton.y;
                ev->shift = (e.xbutton.state & ShiftMask) != 0;
                return 1;
            case MotionNotify:
                ev->type = SEPAL_WINDOW_EVENT_MOTION;
                ev->x = e.xmotion.x;
                ev->y = e.xmotion.y;
                ev->buttons = ((e.xmotion.state & Button1Mask) ? 1 : 0) | ((e.xmotion.state & Button2Mask) ? 2 : 0) |
                              ((e.xmotion.state & Button3Mask) ? 4 : 0);
                ev->shift = (e.xmotion.state & ShiftMask) != 0;
                return 1;
            case Expose:
                if (e.xexpose.count != 0) break;
                ev->type = SEPAL_WINDOW_EVENT_EXPOSE;
                return 1;
            case ClientMessage:
                if ((Atom)e.xclient.data.l[0] != w->wm_delete) break;
                ev->type = SEPAL_WINDOW_EVENT_CLOSE;
                return 1;
            default:
                break;
        }
    }
    return 0;
}

extern "C" int sepal_window_swap(sepal_window* w) { return w && eglSwapBuffers(w->display, w->surface) ? 1 : 0; }

extern "C" int sepal_window_read_rgba(sepal_window* w, int x, int y, int width, int height, uint8_t* out) {
    if (!w || !out || x < 0 || y < 0 || width < 1 || height < 1 || x + width > w->width || y + height > w->height)
        return 0;
    glFinish();
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(x, w->height - y - height, width, height, GL_RGBA, GL_UNSIGNED_BYTE, out);
    if (glGetError() != GL_NO_ERROR) return 0;
    sepal_ports::flip_rows(out, width, height);
    return 1;
}

extern "C" void sepal_window_set_title(sepal_window* w, const char* title) {
    if (!w || !title) return;
    XStoreName(w->x, w->window, title);
    XFlush(w->x);
}

extern "C" int sepal_window_width(const sepal_window* w) { return w ? w->width : 0; }
extern "C" int sepal_window_height(const sepal_window* w) { return w ? w->height : 0; }
extern "C" const char* sepal_window_describe(const sepal_window* w) { return w ? w->description : ""; }

extern "C" void sepal_window_destroy(sepal_window* w) {
    if (w) destroy_partial(w);
}

extern "C" sepal_window_proc sepal_window_get_proc_address(const char* name) {
    return (sepal_window_proc)eglGetProcAddress(name);
}
