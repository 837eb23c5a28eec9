// The clear every frame starts with, and the part of a frame's saved GL state both versions
// share (sepal_frame.h's contract), for the GL ES 1.1 and GL ES 2 paths: include it after
// <GLES/gl.h> or <GLES2/gl2.h> (both declare these entry points, with the same enums).
#pragma once
#include "sepal/sepal_frame.h"

namespace srt {

// Clears colour and depth whatever the caller left: a scissor test, a colour mask or a depth
// mask left off would keep part of the last frame (with the depth kept, the first pass's LESS
// test fails everywhere and the frame draws nothing; tests/runtime/gl_state_test.cpp). The
// scissor test stays off, as GL starts; the masks stay on, as the passes need them. The other
// state an application may leave that would change the passes (stencil test, polygon offset,
// the front face the culling keys on) goes back to GL's initial values too.
// prepare_state is that set-up without the clear (a frame that keeps what the engine drew).
inline void prepare_state() {
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glFrontFace(GL_CCW);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
}

inline void clear_frame(float r, float g, float b, float a) {
    prepare_state();
    glClearColor(r, g, b, a);
    glClearDepthf(1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

// What both versions save at a frame's begin and put back at its end.
struct CoreGlState {
    GLint viewport[4];
    GLboolean enables[7];
    GLint front_face, cull_mode, depth_func, active_unit, array_buffer, element_buffer;
    GLboolean color_mask[4], depth_mask;
    GLfloat clear_color[4], clear_depth;
};

inline const GLenum* core_enables() {
    static const GLenum caps[7] = {GL_SCISSOR_TEST, GL_STENCIL_TEST, GL_POLYGON_OFFSET_FILL, GL_CULL_FACE,
                                   GL_DEPTH_TEST,   GL_BLEND,        GL_DITHER};
    return caps;
}

inline void set_enable(GLenum cap, GLboolean on) { on ? glEnable(cap) : glDisable(cap); }

inline void save_core_state(CoreGlState* s) {
    glGetIntegerv(GL_VIEWPORT, s->viewport);
    for (int i = 0; i < 7; ++i) s->enables[i] = glIsEnabled(core_enables()[i]);
    glGetIntegerv(GL_FRONT_FACE, &s->front_face);
    glGetIntegerv(GL_CULL_FACE_MODE, &s->cull_mode);
    glGetIntegerv(GL_DEPTH_FUNC, &s->depth_func);
    glGetIntegerv(GL_ACTIVE_TEXTURE, &s->active_unit);
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &s->array_buffer);
    glGetIntegerv(GL_ELEMENT_ARRAY_BUFFER_BINDING, &s->element_buffer);
    glGetBooleanv(GL_COLOR_WRITEMASK, s->color_mask);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &s->depth_mask);
    glGetFloatv(GL_COLOR_CLEAR_VALUE, s->clear_color);
    glGetFloatv(GL_DEPTH_CLEAR_VALUE, &s->clear_depth);
}

// The frame-wide state every object's passes assume, after the save: client-memory arrays
// (no buffer bound), the frame's viewport, the clear if asked, no dithering (it would make
// passes disagree by a level), back faces culled.
inline void begin_core_frame(const sepal_frame_desc& d) {
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
    glViewport(d.viewport[0], d.viewport[1], d.viewport[2], d.viewport[3]);
    if (d.clear)
        clear_frame(d.clear_color[0], d.clear_color[1], d.clear_color[2], d.clear_color[3]);
    else
        prepare_state();
    glDisable(GL_DITHER);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
}

// Last at a frame's end (the buffer bindings and the active unit after the per-version
// state that needed other ones).
inline void restore_core_state(const CoreGlState& s) {
    glViewport(s.viewport[0], s.viewport[1], s.viewport[2], s.viewport[3]);
    for (int i = 0; i < 7; ++i) set_enable(core_enables()[i], s.enables[i]);
    glFrontFace((GLenum)s.front_face);
    glCullFace((GLenum)s.cull_mode);
    glDepthFunc((GLenum)s.depth_func);
    glColorMask(s.color_mask[0], s.color_mask[1], s.color_mask[2], s.color_mask[3]);
    glDepthMask(s.depth_mask);
    glClearColor(s.clear_color[0], s.clear_color[1], s.clear_color[2], s.clear_color[3]);
    glClearDepthf(s.clear_depth);
    glBindBuffer(GL_ARRAY_BUFFER, (GLuint)s.array_buffer);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, (GLuint)s.element_buffer);
    glActiveTexture((GLenum)s.active_unit);
}

}  // namespace srt
