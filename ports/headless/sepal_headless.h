// sepal_headless.h - offscreen GL ES contexts through EGL, no display needed.
//
// Usage:
//   sepal_headless_desc d = {0};                // zero means default: 256x256, GL ES 1.1
//   d.width = 512; d.height = 512; d.gles_version = 2;
//   char err[256];
//   sepal_headless_context* c = sepal_headless_create(&d, err, sizeof err);
//   if (!c) { fprintf(stderr, "%s\n", err); return 2; }
//   // draw with GL ES
//   sepal_headless_read_rgba(c, pixels);       // width*height*4 bytes, top row first
//   sepal_headless_destroy(c);
//
// Limits: one context per process at a time is what the tests use; nothing stops
// more, but each is made current on create and callers must re-bind with
// sepal_headless_make_current. The context draws into an EGL pbuffer, so no
// framebuffer-object extension is needed for the default target. Its colour buffer:
// framebuffer 0 or 8888 asks EGL for at least 8/8/8/8 bits (RGBA8 on Mesa); 565 takes the
// first config with exactly 5/6/5 bits and no alpha (RGB565, as older phones and kiosk boards
// render; Mesa's surfaceless platform offers it for GL ES 1 and 2), GL_DITHER left on as GL
// ES starts. Depth: at least depth_bits. read_rgba widens 565 to 8 bits as GL does.
// Not every EGL has a 565 pbuffer config: create then fails and says so.
// Platform order: EGL_MESA_platform_surfaceless, then EGL_EXT_platform_device, then
// the default display. SEPAL_EGL_PLATFORM=surfaceless|device|default forces one.
// This is the only place in sepal that talks to EGL for offscreen work.
//
// Thread safety: a context is current on one thread at a time (EGL's rule): create,
// make_current, read_rgba and destroy for one context from the thread it is current on;
// distinct contexts may live on distinct threads. sepal_headless_get_proc_address, _width,
// _height and _gles_version only read.
#pragma once
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sepal_headless_desc {
    int width;         // pixels; 0 means 256
    int height;        // pixels; 0 means 256
    int gles_version;  // 1 (GL ES 1.1 common profile) or 2 (GL ES 2.0); 0 means 1
    int depth_bits;    // minimum depth bits; 0 means 16
    int framebuffer;   // colour buffer: 0 or 8888 (RGBA8), 565 (RGB565)
} sepal_headless_desc;

typedef struct sepal_headless_context sepal_headless_context;

// Creates and makes current a context. Returns NULL and writes the reason to err.
sepal_headless_context* sepal_headless_create(const sepal_headless_desc* desc, char* err, size_t err_len);
int sepal_headless_make_current(sepal_headless_context* c);
// Reads the colour buffer as RGBA8, top row first (GL's rows are flipped here).
// out must hold width*height*4 bytes. Returns 1 on success.
int sepal_headless_read_rgba(sepal_headless_context* c, uint8_t* out);
int sepal_headless_width(const sepal_headless_context* c);
int sepal_headless_height(const sepal_headless_context* c);
// The GL ES version the context was made for: 1 or 2.
int sepal_headless_gles_version(const sepal_headless_context* c);
// Human-readable description: platform, EGL vendor, GL renderer and version.
const char* sepal_headless_describe(const sepal_headless_context* c);
void sepal_headless_destroy(sepal_headless_context* c);
// eglGetProcAddress, typed as the runtime's sepal_proc_loader wants it.
typedef void (*sepal_headless_proc)(void);
sepal_headless_proc sepal_headless_get_proc_address(const char* name);

#ifdef __cplusplus
}
#endif
