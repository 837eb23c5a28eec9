// sepal_window.h - an on-screen GL ES context: an X11 window (Xlib) with EGL, the windowed
// twin of ports/headless. The runtime never learns which port made its context.
//
// Usage:
//   sepal_window_desc d = {};                 // zero means default: 512x512, GL ES 2
//   d.width = 512; d.height = 536; d.title = "sepal-view";
//   char err[256];
//   sepal_window* w = sepal_window_create(&d, err, sizeof err);
//   if (!w) { fprintf(stderr, "%s\n", err); return 1; }   // e.g. no DISPLAY
//   for (;;) {
//       sepal_window_event ev;
//       while (sepal_window_poll(w, &ev, 0)) { ... ev.type, ev.key, ev.x ... }
//       sepal_window_use_gles(w, 1, err, sizeof err);   // GL ES 1.1 (or 2) current
//       ... draw with the runtime ...
//       sepal_window_swap(w);
//   }
//   sepal_window_destroy(w);
//
// One window, one EGL surface and up to two contexts, one per GL ES version (the config
// is renderable by both), made on first use: switching the backend between GL ES 1.1 and
// 2 keeps the window. Each context has its own textures and programs: GL objects made
// under one version are not visible under the other.
// Limits: X11 only (XWayland works); the window has a fixed size (no resizing); key events
// carry ASCII for printable keys and SEPAL_KEY_* for a few others. Events are delivered in
// the order the X server sent them; pointer motion is not compressed.
// Platform: EGL_KHR_platform_x11 when the EGL client offers it, else eglGetDisplay on the
// Xlib display. Works under Xvfb with Mesa llvmpipe (how the tests run it).
#pragma once
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sepal_window_desc {
    int width;          // client area in pixels; 0 means 512
    int height;         // 0 means 512
    int gles_version;   // the context made current at creation: 1 or 2; 0 means 2
    int depth_bits;     // minimum depth bits; 0 means 16
    const char* title;  // NULL means "sepal"
} sepal_window_desc;

typedef enum sepal_window_event_type {
    SEPAL_WINDOW_EVENT_NONE = 0,
    SEPAL_WINDOW_EVENT_KEY = 1,          // key pressed: key, shift
    SEPAL_WINDOW_EVENT_BUTTON_DOWN = 2,  // button, x, y, shift
    SEPAL_WINDOW_EVENT_BUTTON_UP = 3,
    SEPAL_WINDOW_EVENT_MOTION = 4,       // x, y, buttons (bit 0 left, 1 middle, 2 right)
    SEPAL_WINDOW_EVENT_SCROLL = 5,       // scroll: +1 away from the user, -1 towards
    SEPAL_WINDOW_EVENT_EXPOSE = 6,       // the window needs a redraw
    SEPAL_WINDOW_EVENT_CLOSE = 7,        // the window manager asked to close
} sepal_window_event_type;

enum { SEPAL_KEY_ESCAPE = 27, SEPAL_KEY_LEFT = 0x100, SEPAL_KEY_RIGHT, SEPAL_KEY_UP, SEPAL_KEY_DOWN };

typedef struct sepal_window_event {
    sepal_window_event_type type;
    int key;      // KEY: ASCII ('a', 'B', '1', ...) or SEPAL_KEY_*
    int button;   // BUTTON_*: 1 left, 2 middle, 3 right
    int buttons;  // MOTION: buttons held
    int x, y;     // pointer in client pixels, from the top-left corner
    int shift;    // shift held
    int scroll;
} sepal_window_event;

typedef struct sepal_window sepal_window;

// Opens the display ($DISPLAY), creates and maps the window, creates a context of
// desc->gles_version and makes it current. NULL with the reason in err on failure.
sepal_window* sepal_window_create(const sepal_window_desc* desc, char* err, size_t err_len);
// Makes a GL ES 1.1 (version 1) or 2.0 (version 2) context current on the window, creating
// it on first use. Returns 1, or 0 with the reason in err.
int sepal_window_use_gles(sepal_window* w, int version, char* err, size_t err_len);
int sepal_window_gles(const sepal_window* w);  // the version now current
// Fills *ev with the next event and returns 1; returns 0 when none is queued
// (wait = 0) or blocks until one arrives (wait = 1).
int sepal_window_poll(sepal_window* w, sepal_window_event* ev, int wait);
int sepal_window_swap(sepal_window* w);
// Reads a rectangle of the back buffer (call before swapping) as RGBA8, top row first;
// x, y from the client area's top-left. Returns 1 on success.
int sepal_window_read_rgba(sepal_window* w, int x, int y, int width, int height, uint8_t* out);
void sepal_window_set_title(sepal_window* w, const char* title);
int sepal_window_width(const sepal_window* w);
int sepal_window_height(const sepal_window* w);
// EGL vendor, GL renderer and version of the current context.
const char* sepal_window_describe(const sepal_window* w);
void sepal_window_destroy(sepal_window* w);
// eglGetProcAddress, typed as the runtime's sepal_proc_loader wants it.
typedef void (*sepal_window_proc)(void);
sepal_window_proc sepal_window_get_proc_address(const char* name);

#ifdef __cplusplus
}
#endif
