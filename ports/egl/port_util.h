// Helpers shared by the EGL ports (headless, windowed): EGL error names, extension
// lookup, error text, row flipping. Header-only, so each port's library stands alone
// when installed.
#pragma once
#include <EGL/egl.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

namespace sepal_ports {

inline const char* egl_error_name(EGLint e) {
    switch (e) {
        case EGL_SUCCESS: return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
        case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
        case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
        case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
        case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
        case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
        case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
        default: return "EGL error";
    }
}

// Whole-word match in a space-separated extension string.
inline bool egl_has_ext(const char* list, const char* name) {
    if (!list) return false;
    const size_t n = strlen(name);
    for (const char* p = list; (p = strstr(p, name)) != nullptr; p += n) {
        const bool start = (p == list) || p[-1] == ' ';
        const bool end = p[n] == '\0' || p[n] == ' ';
        if (start && end) return true;
    }
    return false;
}

// printf into a caller's error buffer (either may be NULL / 0).
inline void set_error(char* err, size_t n, const char* fmt, ...) __attribute__((format(printf, 3, 4)));
inline void set_error(char* err, size_t n, const char* fmt, ...) {
    if (!err || n == 0) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, n, fmt, ap);
    va_end(ap);
}

// A port's request: width and height in 1..max_side, GL ES version 1 or 2 (after the
// port's zero-means-default step). False with the reason in err.
inline bool check_request(const char* what, int width, int height, int max_side, int gles_version, char* err,
                          size_t n) {
    if (width < 1 || height < 1 || width > max_side || height > max_side) {
        set_error(err, n, "%s size %dx%d out of range 1..%d", what, width, height, max_side);
        return false;
    }
    if (gles_version != 1 && gles_version != 2) {
        set_error(err, n, "gles_version %d: only 1 (GL ES 1.1) and 2 (GL ES 2.0) exist", gles_version);
        return false;
    }
    return true;
}

// GL reads rows bottom first; images are stored top row first: swaps rows in place.
inline void flip_rows(uint8_t* rgba, int width, int height) {
    const size_t row = (size_t)width * 4;
    uint8_t tmp[4096];
    for (int y = 0; y < height / 2; ++y) {
        uint8_t* a = rgba + (size_t)y * row;
        uint8_t* b = rgba + (size_t)(height - 1 - y) * row;
        for (size_t off = 0; off < row; off += sizeof tmp) {
            const size_t k = row - off < sizeof tmp ? row - off : sizeof tmp;
            memcpy(tmp, a + off, k);
            memcpy(a + off, b + off, k);
            memcpy(b + off, tmp, k);
        }
    }
}

}  // namespace sepal_ports
