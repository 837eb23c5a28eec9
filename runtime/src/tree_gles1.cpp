// Inverse shade trees on GL ES 1.1 (sepal_tree.h): the composition's full-screen addition.
#include <GLES/gl.h>
#include <GLES/glext.h>

#include "gles1_util.h"
#include "tree_internal.h"

namespace srt {

// The running sum added back: a quad over the viewport whose texel centres fall on pixel
// centres, one texture unit replacing the colour, blend (ONE, ONE).
void tree_add_gles1(const sepal_tree* t, int width, int height) {
    const float sx = (float)width / (float)t->copy_width, sy = (float)height / (float)t->copy_height;
    const float pos[8] = {-1, -1, 1, -1, 1, 1, -1, 1};
    const float uv[8] = {0, 0, sx, 0, sx, sy, 0, sy};
    with_identity_matrices([&] {
        // sepal_draw leaves the caller's viewport; the composition is over the tree's.
        glViewport(0, 0, width, height);
        glDisable(GL_DEPTH_TEST);
        glDisable(GL_CULL_FACE);
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
        glClientActiveTexture(GL_TEXTURE1);
        glDisableClientState(GL_TEXTURE_COORD_ARRAY);
        glActiveTexture(GL_TEXTURE1);
        glDisable(GL_TEXTURE_2D);
        glActiveTexture(GL_TEXTURE0);
        glClientActiveTexture(GL_TEXTURE0);
        glEnable(GL_TEXTURE_2D);
        glBindTexture(GL_TEXTURE_2D, t->copy_texture);
        glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
        glEnableClientState(GL_VERTEX_ARRAY);
        glVertexPointer(2, GL_FLOAT, 0, pos);
        glEnableClientState(GL_TEXTURE_COORD_ARRAY);
        glTexCoordPointer(2, GL_FLOAT, 0, uv);
        glDisableClientState(GL_COLOR_ARRAY);
        glDrawElements(GL_TRIANGLES, 6, GL_UNSIGNED_SHORT, quad_indices());
        // Back to GL's defaults for whoever draws next.
        glDisableClientState(GL_TEXTURE_COORD_ARRAY);
        glDisableClientState(GL_VERTEX_ARRAY);
        glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
        glBindTexture(GL_TEXTURE_2D, 0);
        glDisable(GL_TEXTURE_2D);
        glDisable(GL_BLEND);
    });
}

}  // namespace srt
