// The blit on GL ES 2: a textured quad through a two-line shader.
#include <GLES2/gl2.h>

#include "windowed/overlay.h"

namespace sepal_ports {
namespace {

const char kVert[] =
    "attribute vec2 a_pos;\nattribute vec2 a_uv;\nvarying vec2 v_uv;\n"
    "void main() { v_uv = a_uv; gl_Position = vec4(a_pos, 0.0, 1.0); }\n";
const char kFrag[] =
    "precision mediump float;\nuniform sampler2D u_tex;\nvarying vec2 v_uv;\n"
    "void main() { gl_FragColor = texture2D(u_tex, v_uv); }\n";

GLuint shader(GLenum type, const char* src) {
    const GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        glDeleteShader(s);
        return 0;
    }
    return s;
}

}  // namespace

bool blit_gles2(Blitter* b, int x, int y, int width, int height, float u, float v, std::string* err) {
    if (!b->program) {
        const GLuint vs = shader(GL_VERTEX_SHADER, kVert), fs = shader(GL_FRAGMENT_SHADER, kFrag);
        b->program = glCreateProgram();
        if (vs) glAttachShader(b->program, vs);
        if (fs) glAttachShader(b->program, fs);
        glBindAttribLocation(b->program, 0, "a_pos");
        glBindAttribLocation(b->program, 1, "a_uv");
        glLinkProgram(b->program);
        glDeleteShader(vs);
        glDeleteShader(fs);
        GLint linked = 0;
        glGetProgramiv(b->program, GL_LINK_STATUS, &linked);
        if (!vs || !fs || !linked) {
            *err = "blit: the GL ES 2 blit shader failed to compile or link";
            glDeleteProgram(b->program);
            b->program = 0;
            return false;
        }
    }
    const BlitQuad quad(u, v);
    glViewport(x, y, width, height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glUseProgram(b->program);
    glUniform1i(glGetUniformLocation(b->program, "u_tex"), 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, b->texture);
    for (GLuint i = 2; i < 4; ++i) glDisableVertexAttribArray(i);
    glEnableVertexAttribArray(0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, quad.position);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 0, quad.uv);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glDisableVertexAttribArray(0);
    glDisableVertexAttribArray(1);
    glUseProgram(0);
    return true;
}

}  // namespace sepal_ports
