// The GL state contract on GL ES 1.1 (sepal_frame.h): every piece of state a frame touches
// is queried before and after a frame of two objects drawn on top of an application's
// state, and must come back unchanged. Each change of that state is first shown to show up
// in the snapshot, so a frame that left one behind would fail.
#include <GLES/gl.h>
#include <GLES/glext.h>

#include <cstdint>
#include <functional>

#include "frame_fixtures.h"
#include "gl_snapshot.h"
#include "material_fixtures.h"

using namespace frame_fx;
using gl_snapshot::Snapshot;

namespace {

void add_array(Snapshot& s, const std::string& name, GLenum array, GLenum size, GLenum type, GLenum stride,
               GLenum buffer, GLenum pointer) {
    GLint v = 0;
    s.add(name + " enabled", glIsEnabled(array));
    glGetIntegerv(size, &v), s.add(name + " size", v);
    glGetIntegerv(type, &v), s.add(name + " type", v);
    glGetIntegerv(stride, &v), s.add(name + " stride", v);
    glGetIntegerv(buffer, &v), s.add(name + " buffer", v);
    void* p = nullptr;
    glGetPointerv(pointer, &p);
    s.add(name + " pointer", double(reinterpret_cast<uintptr_t>(p)));
}

Snapshot snapshot(const sepal_caps& caps) {
    Snapshot s;
    gl_snapshot::add_core(s);
    GLfloat f16[16];
    const std::pair<const char*, GLenum> enables[] = {
        {"lighting", GL_LIGHTING},       {"alpha test", GL_ALPHA_TEST},        {"fog", GL_FOG},
        {"logic op", GL_COLOR_LOGIC_OP}, {"color material", GL_COLOR_MATERIAL}, {"normalize", GL_NORMALIZE},
        {"normal array", GL_NORMAL_ARRAY}};
    for (const auto& e : enables) s.add(e.first, glIsEnabled(e.second));
    const std::pair<const char*, GLenum> ints[] = {{"blend src", GL_BLEND_SRC},   {"blend dst", GL_BLEND_DST},
                                                   {"shade model", GL_SHADE_MODEL}, {"matrix mode", GL_MATRIX_MODE},
                                                   {"client active", GL_CLIENT_ACTIVE_TEXTURE}};
    GLint v = 0;
    for (const auto& e : ints) glGetIntegerv(e.second, &v), s.add(e.first, v);
    if (caps.blend_equation) glGetIntegerv(0x8009, &v), s.add("blend equation", v);  // GL_BLEND_EQUATION_OES
    glGetFloatv(GL_CURRENT_COLOR, f16), s.add("current color", f16, 4);
    glGetFloatv(GL_PROJECTION_MATRIX, f16), s.add("projection", f16, 16);
    glGetFloatv(GL_MODELVIEW_MATRIX, f16), s.add("modelview", f16, 16);
    GLint active = 0, client = 0;
    glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    glGetIntegerv(GL_CLIENT_ACTIVE_TEXTURE, &client);
    const GLenum env[] = {GL_TEXTURE_ENV_MODE, GL_COMBINE_RGB,   GL_COMBINE_ALPHA, GL_SRC0_RGB,    GL_SRC1_RGB,
                          GL_SRC2_RGB,         GL_SRC0_ALPHA,    GL_SRC1_ALPHA,    GL_OPERAND0_RGB, GL_OPERAND1_RGB,
                          GL_OPERAND0_ALPHA,   GL_OPERAND1_ALPHA, GL_RGB_SCALE,    GL_ALPHA_SCALE};
    const int units = caps.texture_units < 3 ? caps.texture_units : 3;
    for (int u = 0; u < units; ++u) {
        const std::string n = "unit " + std::to_string(u) + " ";
        glActiveTexture(GL_TEXTURE0 + u);
        glClientActiveTexture(GL_TEXTURE0 + u);
        s.add(n + "texture 2d", glIsEnabled(GL_TEXTURE_2D));
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &v), s.add(n + "binding", v);
        for (GLenum p : env) glGetTexEnviv(GL_TEXTURE_ENV, p, &v), s.add(n + "env " + std::to_string(p), v);
        glGetFloatv(GL_TEXTURE_MATRIX, f16), s.add(n + "texture matrix", f16, 16);
        add_array(s, n + "coords", GL_TEXTURE_COORD_ARRAY, GL_TEXTURE_COORD_ARRAY_SIZE, GL_TEXTURE_COORD_ARRAY_TYPE,
                  GL_TEXTURE_COORD_ARRAY_STRIDE, GL_TEXTURE_COORD_ARRAY_BUFFER_BINDING, GL_TEXTURE_COORD_ARRAY_POINTER);
    }
    glActiveTexture(GLenum(active));
    glClientActiveTexture(GLenum(client));
    add_array(s, "vertex", GL_VERTEX_ARRAY, GL_VERTEX_ARRAY_SIZE, GL_VERTEX_ARRAY_TYPE, GL_VERTEX_ARRAY_STRIDE,
              GL_VERTEX_ARRAY_BUFFER_BINDING, GL_VERTEX_ARRAY_POINTER);
    add_array(s, "color", GL_COLOR_ARRAY, GL_COLOR_ARRAY_SIZE, GL_COLOR_ARRAY_TYPE, GL_COLOR_ARRAY_STRIDE,
              GL_COLOR_ARRAY_BUFFER_BINDING, GL_COLOR_ARRAY_POINTER);
    s.add("gl error", glGetError());
    return s;
}

}  // namespace

TEST_CASE("frame state, GL ES 1.1: a frame leaves every piece of GL state it touches as it found it") {
    const std::vector<uint8_t> signed_bytes = material_fx::encode(material_fx::signed_asset());
    for (uint32_t mask : {0u, uint32_t(SEPAL_MASK_BLEND_SUBTRACT), uint32_t(SEPAL_MASK_MULTITEXTURE)}) {
        CAPTURE(mask);
        Gl gl(1);
        const sepal_material* m = gl.material(signed_bytes, mask);
        const Scene sc;
        static const float kClient[64] = {};
        GLuint buffers[3], texture = 0;
        glGenBuffers(3, buffers);
        for (GLuint b : buffers) {
            glBindBuffer(GL_ARRAY_BUFFER, b);
            glBufferData(GL_ARRAY_BUFFER, 256, kClient, GL_STATIC_DRAW);
        }
        glGenTextures(1, &texture);
        const float proj[16] = {2, 0, 0, 0, 0, 3, 0, 0, 0, 0, -1, -1, 0.5f, 0, -0.2f, 0};
        const float mv[16] = {1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 1, 2, 3, 1};
        const float tm[16] = {0.5f, 0, 0, 0, 0, 0.5f, 0, 0, 0, 0, 1, 0, 0.25f, 0.25f, 0, 1};
        // What an application might leave, one change at a time.
        std::vector<Change> changes = {
            {"viewport", [] { glViewport(3, 4, 50, 40); }},
            {"scissor", [] { glEnable(GL_SCISSOR_TEST), glScissor(1, 2, 30, 20); }},
            {"stencil", [] { glEnable(GL_STENCIL_TEST); }},
            {"polygon offset", [] { glEnable(GL_POLYGON_OFFSET_FILL); }},
            {"front face", [] { glFrontFace(GL_CW); }},
            {"cull face", [] { glCullFace(GL_FRONT); }},
            {"depth", [] { glEnable(GL_DEPTH_TEST), glDepthFunc(GL_LEQUAL); }},
            {"blend", [] { glEnable(GL_BLEND), glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA); }},
            {"dither", [] { glDisable(GL_DITHER); }},
            {"lighting", [] { glEnable(GL_LIGHTING), glEnable(GL_COLOR_MATERIAL), glEnable(GL_NORMALIZE); }},
            {"alpha test and fog", [] { glEnable(GL_ALPHA_TEST), glEnable(GL_FOG), glEnable(GL_COLOR_LOGIC_OP); }},
            {"shade model", [] { glShadeModel(GL_FLAT); }},
            {"masks", [] { glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE), glDepthMask(GL_FALSE); }},
            {"clear values", [] { glClearColor(0.1f, 0.2f, 0.3f, 0.4f), glClearDepthf(0.75f); }},
            {"current colour", [] { glColor4f(0.25f, 0.5f, 0.75f, 0.5f); }},
            {"matrices",
             [&] {
                 glMatrixMode(GL_PROJECTION), glLoadMatrixf(proj);
                 glMatrixMode(GL_MODELVIEW), glLoadMatrixf(mv);
                 glActiveTexture(GL_TEXTURE1), glMatrixMode(GL_TEXTURE), glLoadMatrixf(tm);
                 glActiveTexture(GL_TEXTURE0), glLoadMatrixf(tm);
             }},
            {"texture units",
             [&] {
                 glActiveTexture(GL_TEXTURE1), glEnable(GL_TEXTURE_2D), glBindTexture(GL_TEXTURE_2D, texture);
                 glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
                 glActiveTexture(GL_TEXTURE0), glBindTexture(GL_TEXTURE_2D, texture);
                 glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_COMBINE);
                 glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_RGB, GL_ADD);
                 glTexEnvi(GL_TEXTURE_ENV, GL_SRC1_RGB, GL_CONSTANT);
                 glTexEnvi(GL_TEXTURE_ENV, GL_RGB_SCALE, 2);
                 glActiveTexture(GL_TEXTURE1);
             }},
            {"arrays",
             [&] {
                 glEnableClientState(GL_VERTEX_ARRAY), glVertexPointer(2, GL_FLOAT, 16, kClient);
                 glBindBuffer(GL_ARRAY_BUFFER, buffers[0]);
                 glEnableClientState(GL_COLOR_ARRAY), glColorPointer(4, GL_UNSIGNED_BYTE, 8, (void*)4);
                 glClientActiveTexture(GL_TEXTURE1), glBindBuffer(GL_ARRAY_BUFFER, buffers[1]);
                 glEnableClientState(GL_TEXTURE_COORD_ARRAY), glTexCoordPointer(3, GL_FLOAT, 12, (void*)16);
                 glEnableClientState(GL_NORMAL_ARRAY);
                 glBindBuffer(GL_ARRAY_BUFFER, buffers[2]);
                 glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffers[1]);
             }},
        };
        if (gl.caps.blend_equation)  // GL_OES_blend_subtract: GL_FUNC_SUBTRACT
            changes.push_back({"blend equation", [&] { gl.caps.blend_equation(0x800A); }});
        check_state_kept(gl, sc, m, SEPAL_MODE_MULTIPASS, changes, [&] { return snapshot(gl.caps); });
        glBindBuffer(GL_ARRAY_BUFFER, 0);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
        glDeleteBuffers(3, buffers);
        glDeleteTextures(1, &texture);
    }
}
