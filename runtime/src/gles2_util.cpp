// GL ES 2 shader compile/link with the driver's log in the error message.
#include "gles2_util.h"

namespace srt {
namespace {
GLuint compile(const char* name, GLenum type, const char* src, sepal_error* err) {
    GLuint s = glCreateShader(type);
    if (!s) {
        fail(err, SEPAL_ERR_GL, "shader '%s': glCreateShader failed", name);
        return 0;
    }
    glShaderSource(s, 1, &src, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[200];
        GLsizei len = 0;
        glGetShaderInfoLog(s, sizeof log, &len, log);
        fail(err, SEPAL_ERR_GL, "shader '%s' (%s) failed to compile: %s", name,
             type == GL_VERTEX_SHADER ? "vertex" : "fragment", len ? log : "(no log)");
        glDeleteShader(s);
        return 0;
    }
    return s;
}
}  // namespace

GLuint gles2_program(const char* name, const char* vertex_src, const char* fragment_src,
                     const char* const* attributes, sepal_error* err) {
    GLuint vs = compile(name, GL_VERTEX_SHADER, vertex_src, err);
    if (!vs) return 0;
    GLuint fs = compile(name, GL_FRAGMENT_SHADER, fragment_src, err);
    if (!fs) {
        glDeleteShader(vs);
        return 0;
    }
    GLuint p = glCreateProgram();
    glAttachShader(p, vs);
    glAttachShader(p, fs);
    for (GLuint i = 0; attributes && attributes[i]; ++i) glBindAttribLocation(p, i, attributes[i]);
    glLinkProgram(p);
    glDeleteShader(vs);  // flagged; freed with the program
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[200];
        GLsizei len = 0;
        glGetProgramInfoLog(p, sizeof log, &len, log);
        fail(err, SEPAL_ERR_GL, "shader program '%s' failed to link: %s", name,
             len ? log : "(no log)");
        glDeleteProgram(p);
        return 0;
    }
    return p;
}

}  // namespace srt
