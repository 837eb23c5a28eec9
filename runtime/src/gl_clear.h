// The clear every frame starts with, shared by the GL ES 1.1 and GL ES 2 paths: include it
// after <GLES/gl.h> or <GLES2/gl2.h> (both declare these entry points, with the same enums).
#pragma once

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

}  // namespace srt
