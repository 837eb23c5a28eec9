#include "gl_counter.h"

#include <GLES/gl.h>
#include <dlfcn.h>

#include <algorithm>
#include <cstring>
#include <vector>

namespace {
struct GlCounter {
    const char* name;
    long calls;
};
GlCounter g_counters[64];
int g_counter_count = 0;
bool g_counting = false;
int register_counter(const char* name) {
    g_counters[g_counter_count] = {name, 0};
    return g_counter_count++;
}
}  // namespace

#define SEPAL_TEST_COUNT_GL(ret, name, params, args)                                     \
    extern "C" ret name params {                                                       \
        static ret(*real) params = reinterpret_cast<ret(*) params>(dlsym(RTLD_NEXT, #name)); \
        static const int index = register_counter(#name);                                     \
        if (g_counting) ++g_counters[index].calls;                                   \
        return real args;                                                               \
    }
SEPAL_TEST_COUNT_GL(void, glEnable, (GLenum cap), (cap))
SEPAL_TEST_COUNT_GL(void, glDisable, (GLenum cap), (cap))
SEPAL_TEST_COUNT_GL(void, glTexEnvi, (GLenum target, GLenum pname, GLint param), (target, pname, param))
SEPAL_TEST_COUNT_GL(void, glBindTexture, (GLenum target, GLuint texture), (target, texture))
SEPAL_TEST_COUNT_GL(void, glMatrixMode, (GLenum mode), (mode))
SEPAL_TEST_COUNT_GL(void, glEnableClientState, (GLenum array), (array))
SEPAL_TEST_COUNT_GL(void, glDisableClientState, (GLenum array), (array))
SEPAL_TEST_COUNT_GL(void, glBlendFunc, (GLenum s, GLenum d), (s, d))
SEPAL_TEST_COUNT_GL(void, glDepthFunc, (GLenum func), (func))
SEPAL_TEST_COUNT_GL(void, glDepthMask, (GLboolean flag), (flag))
SEPAL_TEST_COUNT_GL(void, glColorMask, (GLboolean r, GLboolean g, GLboolean b, GLboolean a), (r, g, b, a))
SEPAL_TEST_COUNT_GL(void, glActiveTexture, (GLenum texture), (texture))
SEPAL_TEST_COUNT_GL(void, glClientActiveTexture, (GLenum texture), (texture))
SEPAL_TEST_COUNT_GL(void, glVertexPointer, (GLint size, GLenum type, GLsizei stride, const void* p), (size, type, stride, p))
SEPAL_TEST_COUNT_GL(void, glTexCoordPointer, (GLint size, GLenum type, GLsizei stride, const void* p), (size, type, stride, p))
SEPAL_TEST_COUNT_GL(void, glColorPointer, (GLint size, GLenum type, GLsizei stride, const void* p), (size, type, stride, p))
SEPAL_TEST_COUNT_GL(void, glColor4f, (GLfloat r, GLfloat g, GLfloat b, GLfloat a), (r, g, b, a))
SEPAL_TEST_COUNT_GL(void, glPushMatrix, (void), ())
SEPAL_TEST_COUNT_GL(void, glPopMatrix, (void), ())
SEPAL_TEST_COUNT_GL(void, glLoadIdentity, (void), ())
SEPAL_TEST_COUNT_GL(void, glLoadMatrixf, (const GLfloat* m), (m))
SEPAL_TEST_COUNT_GL(void, glDrawElements, (GLenum mode, GLsizei count, GLenum type, const void* indices), (mode, count, type, indices))
SEPAL_TEST_COUNT_GL(void, glClear, (GLbitfield mask), (mask))
SEPAL_TEST_COUNT_GL(void, glClearColor, (GLfloat r, GLfloat g, GLfloat b, GLfloat a), (r, g, b, a))
SEPAL_TEST_COUNT_GL(void, glViewport, (GLint x, GLint y, GLsizei w, GLsizei h), (x, y, w, h))
SEPAL_TEST_COUNT_GL(void, glShadeModel, (GLenum mode), (mode))
SEPAL_TEST_COUNT_GL(void, glCullFace, (GLenum mode), (mode))
SEPAL_TEST_COUNT_GL(void, glCopyTexSubImage2D, (GLenum t, GLint l, GLint xo, GLint yo, GLint x, GLint y, GLsizei w, GLsizei h), (t, l, xo, yo, x, y, w, h))
SEPAL_TEST_COUNT_GL(GLenum, glGetError, (void), ())
#undef SEPAL_TEST_COUNT_GL

namespace sepal_test {

void gl_counting(bool on) { g_counting = on; }
void gl_counts_reset() {
    for (int i = 0; i < g_counter_count; ++i) g_counters[i].calls = 0;
}
long gl_calls(const char* name) {
    for (int i = 0; i < g_counter_count; ++i)
        if (std::strcmp(g_counters[i].name, name) == 0) return g_counters[i].calls;
    return 0;
}
long gl_calls_total() {
    long n = 0;
    for (int i = 0; i < g_counter_count; ++i) n += g_counters[i].calls;
    return n;
}
std::string gl_calls_by_name() {
    std::vector<GlCounter> by(g_counters, g_counters + g_counter_count);
    std::stable_sort(by.begin(), by.end(), [](const GlCounter& a, const GlCounter& b) { return a.calls > b.calls; });
    std::string out;
    for (const GlCounter& c : by)
        if (c.calls > 0) out += (out.empty() ? "" : " ") + std::string(c.name) + " " + std::to_string(c.calls);
    return out;
}

}  // namespace sepal_test
