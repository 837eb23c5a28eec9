// The GL state contract on GL ES 2 (sepal_frame.h): every piece of state a frame touches is
// queried before and after a frame of two objects drawn on top of an application's state,
// in every mode, and must come back unchanged. Each change of that state is first shown to
// show up in the snapshot, so a frame that left one behind would fail.
#include <GLES2/gl2.h>

#include <cstdint>
#include <functional>

#include "frame_fixtures.h"
#include "gl_snapshot.h"
#include "material_fixtures.h"

using namespace frame_fx;
using gl_snapshot::Snapshot;

namespace {

Snapshot snapshot(const sepal_caps& caps) {
    Snapshot s;
    gl_snapshot::add_core(s);
    GLint v = 0;
    GLfloat f4[4];
    const std::pair<const char*, GLenum> ints[] = {
        {"blend src rgb", GL_BLEND_SRC_RGB},     {"blend dst rgb", GL_BLEND_DST_RGB},
        {"blend src alpha", GL_BLEND_SRC_ALPHA}, {"blend dst alpha", GL_BLEND_DST_ALPHA},
        {"blend eq rgb", GL_BLEND_EQUATION_RGB}, {"blend eq alpha", GL_BLEND_EQUATION_ALPHA},
        {"program", GL_CURRENT_PROGRAM},         {"framebuffer", GL_FRAMEBUFFER_BINDING},
        {"renderbuffer", GL_RENDERBUFFER_BINDING}};
    for (const auto& e : ints) glGetIntegerv(e.second, &v), s.add(e.first, v);
    glGetFloatv(GL_BLEND_COLOR, f4), s.add("blend color", f4, 4);
    GLint active = 0;
    glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    const int units = caps.texture_units < 32 ? caps.texture_units : 32;
    for (int u = 0; u < units; ++u) {
        glActiveTexture(GL_TEXTURE0 + u);
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &v), s.add("unit " + std::to_string(u) + " binding", v);
    }
    glActiveTexture(GLenum(active));
    for (GLuint a = 0; a < 8; ++a) {
        const std::string n = "attrib " + std::to_string(a) + " ";
        const std::pair<const char*, GLenum> params[] = {
            {"enabled", GL_VERTEX_ATTRIB_ARRAY_ENABLED}, {"size", GL_VERTEX_ATTRIB_ARRAY_SIZE},
            {"type", GL_VERTEX_ATTRIB_ARRAY_TYPE},       {"normalized", GL_VERTEX_ATTRIB_ARRAY_NORMALIZED},
            {"stride", GL_VERTEX_ATTRIB_ARRAY_STRIDE},   {"buffer", GL_VERTEX_ATTRIB_ARRAY_BUFFER_BINDING}};
        for (const auto& p : params) glGetVertexAttribiv(a, p.second, &v), s.add(n + p.first, v);
        void* ptr = nullptr;
        glGetVertexAttribPointerv(a, GL_VERTEX_ATTRIB_ARRAY_POINTER, &ptr);
        s.add(n + "pointer", double(reinterpret_cast<uintptr_t>(ptr)));
        glGetVertexAttribfv(a, GL_CURRENT_VERTEX_ATTRIB, f4), s.add(n + "current", f4, 4);
    }
    s.add("gl error", glGetError());
    return s;
}

GLuint engine_program() {
    const char* vs = "attribute vec4 p; void main() { gl_Position = p; }";
    const char* fs = "precision mediump float; void main() { gl_FragColor = vec4(1.0); }";
    const GLuint v = glCreateShader(GL_VERTEX_SHADER), f = glCreateShader(GL_FRAGMENT_SHADER);
    glShaderSource(v, 1, &vs, nullptr), glCompileShader(v);
    glShaderSource(f, 1, &fs, nullptr), glCompileShader(f);
    const GLuint p = glCreateProgram();
    glAttachShader(p, v), glAttachShader(p, f), glLinkProgram(p);
    glDeleteShader(v), glDeleteShader(f);
    return p;
}

}  // namespace

TEST_CASE("frame state, GL ES 2: a frame leaves every piece of GL state it touches as it found it") {
    const std::vector<uint8_t> signed_bytes = material_fx::encode(material_fx::signed_asset());
    struct Case {
        uint32_t mask;
        sepal_draw_mode mode;
    };
    for (const Case c : {Case{0, SEPAL_MODE_MULTIPASS}, Case{SEPAL_MASK_BLEND_SUBTRACT, SEPAL_MODE_MULTIPASS},
                         Case{0, SEPAL_MODE_FUSED_VERTEX}, Case{0, SEPAL_MODE_FUSED_PIXEL}}) {
        CAPTURE(c.mask);
        CAPTURE(int(c.mode));
        Gl gl(2);
        const sepal_material* m = gl.material(signed_bytes, c.mask);
        const Scene sc;
        static const float kClient[64] = {};
        GLuint buffers[3], textures[3];
        glGenBuffers(3, buffers);
        for (GLuint b : buffers) {
            glBindBuffer(GL_ARRAY_BUFFER, b);
            glBufferData(GL_ARRAY_BUFFER, 256, kClient, GL_STATIC_DRAW);
        }
        glBindBuffer(GL_ARRAY_BUFFER, 0);
        glGenTextures(3, textures);
        const GLuint program = engine_program();
        std::vector<Change> changes = {
            {"viewport", [] { glViewport(3, 4, 50, 40); }},
            {"scissor", [] { glEnable(GL_SCISSOR_TEST), glScissor(1, 2, 30, 20); }},
            {"stencil", [] { glEnable(GL_STENCIL_TEST); }},
            {"polygon offset", [] { glEnable(GL_POLYGON_OFFSET_FILL); }},
            {"front face", [] { glFrontFace(GL_CW); }},
            {"cull face", [] { glCullFace(GL_FRONT); }},
            {"depth", [] { glEnable(GL_DEPTH_TEST), glDepthFunc(GL_LEQUAL); }},
            {"blend", [] { glEnable(GL_BLEND), glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ZERO); }},
            {"blend equation", [] { glBlendEquationSeparate(GL_FUNC_SUBTRACT, GL_FUNC_REVERSE_SUBTRACT); }},
            {"dither", [] { glDisable(GL_DITHER); }},
            {"masks", [] { glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE), glDepthMask(GL_FALSE); }},
            {"clear values", [] { glClearColor(0.1f, 0.2f, 0.3f, 0.4f), glClearDepthf(0.75f); }},
            {"program", [&] { glUseProgram(program); }},
            {"textures",
             [&] {
                 glActiveTexture(GL_TEXTURE0), glBindTexture(GL_TEXTURE_2D, textures[0]);
                 glActiveTexture(GL_TEXTURE1), glBindTexture(GL_TEXTURE_2D, textures[1]);
                 glActiveTexture(GL_TEXTURE5), glBindTexture(GL_TEXTURE_2D, textures[2]);
                 glActiveTexture(GL_TEXTURE3);
             }},
            {"attributes",
             [&] {
                 glBindBuffer(GL_ARRAY_BUFFER, buffers[0]);
                 glEnableVertexAttribArray(0), glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 24, (void*)8);
                 glBindBuffer(GL_ARRAY_BUFFER, 0);
                 glEnableVertexAttribArray(1), glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 8, kClient);
                 glVertexAttrib4f(2, 0.5f, 0.25f, 0.125f, 2.0f);
                 glBindBuffer(GL_ARRAY_BUFFER, buffers[1]);
                 glEnableVertexAttribArray(5), glVertexAttribPointer(5, 4, GL_UNSIGNED_BYTE, GL_TRUE, 8, (void*)4);
                 glBindBuffer(GL_ARRAY_BUFFER, buffers[2]);
                 glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffers[1]);
             }},
        };
        check_state_kept(gl, sc, m, c.mode, changes, [&] { return snapshot(gl.caps); });
        glUseProgram(0);
        glDeleteProgram(program);
        glBindBuffer(GL_ARRAY_BUFFER, 0);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
        glDeleteBuffers(3, buffers);
        glDeleteTextures(3, textures);
    }
}
