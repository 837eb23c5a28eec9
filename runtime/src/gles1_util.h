// Helpers the GL ES 1.1 paths share (draw_gles1.cpp, tree_gles1.cpp). Header-only so builds
// without GL ES 1.1 (SEPAL_NO_GLES1) need no extra object.
#pragma once
#include <GLES/gl.h>

namespace srt {

// Corners of a viewport quad (two triangles over 0-1-2-3, counter-clockwise from -1,-1).
inline const GLushort* quad_indices() {
    static const GLushort idx[6] = {0, 1, 2, 0, 2, 3};
    return idx;
}

// Runs draw() with identity projection and modelview, so positions are NDC, then puts the
// caller's matrices back: full-screen passes sit between mesh passes that keep theirs.
template <class Draw>
void with_identity_matrices(Draw draw) {
    glMatrixMode(GL_PROJECTION);
    glPushMatrix();
    glLoadIdentity();
    glMatrixMode(GL_MODELVIEW);
    glPushMatrix();
    glLoadIdentity();
    draw();
    glMatrixMode(GL_PROJECTION);
    glPopMatrix();
    glMatrixMode(GL_MODELVIEW);
    glPopMatrix();
}

}  // namespace srt
