// Runtime internals shared by its translation units (not part of the API).
#pragma once
#include "sepal_rt.h"

namespace srt {

// Fills err (may be NULL) and returns code: `return fail(err, SRT_ERR_GL, "...", ...);`
srt_result fail(srt_error* err, srt_result code, const char* fmt, ...)
    __attribute__((format(printf, 3, 4)));

inline srt_result ok(srt_error* err) {
    if (err) {
        err->code = SRT_OK;
        err->message[0] = '\0';
    }
    return SRT_OK;
}

// Whole-word search in a space-separated GL extension string.
bool has_extension(const char* list, const char* name);

// Returns SRT_OK, or drains GL's error flags and fills err naming `what`. Works on
// either GL ES version (glGetError is common to both).
srt_result gl_check(const char* what, srt_error* err);

}  // namespace srt
