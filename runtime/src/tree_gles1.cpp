// Inverse shade trees on GL ES 1.1 (sepal_tree.h): blend textures and the composition's
// copy and full-screen addition.
#include <GLES/gl.h>
#include <GLES/glext.h>

#include "tree_internal.h"

namespace {

int next_pow2(int v) {
    int p = 1;
    while (p < v) p *= 2;
    return p;
}

}  // namespace

namespace srt {

sepal_result tree_create_gles1(const sepal_tree_asset* asset, sepal_tree* t, sepal_error* err) {
    const uint32_t w = asset->header.blend_width, h = asset->header.blend_height;
    if ((int)w > t->caps.max_texture_size || (int)h > t->caps.max_texture_size)
        return fail(err, SEPAL_ERR_UNSUPPORTED, "tree: blend maps %ux%u exceed the GPU's %d", w, h, t->caps.max_texture_size);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (uint32_t j = 0; j < asset->header.basis_count; ++j) {
        GLuint name = 0;
        glGenTextures(1, &name);
        t->blend_textures[j] = name;
        glBindTexture(GL_TEXTURE_2D, name);
        glTexParameteri(GL_TEXTURE_2D, GL_GENERATE_MIPMAP, GL_TRUE);  // core in GL ES 1.1
        glTexImage2D(GL_TEXTURE_2D, 0, GL_LUMINANCE, (GLsizei)w, (GLsizei)h, 0, GL_LUMINANCE, GL_UNSIGNED_BYTE,
                     asset->blend[j]);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    }
    if (asset->header.basis_count > 1) {
        t->copy_width = next_pow2(t->max_width);
        t->copy_height = next_pow2(t->max_height);
        GLuint name = 0;
        glGenTextures(1, &name);
        t->copy_texture = name;
        glBindTexture(GL_TEXTURE_2D, name);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, t->copy_width, t->copy_height, 0, GL_RGB, GL_UNSIGNED_BYTE, nullptr);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    return gl_check("tree textures", err);
}

void tree_destroy_gles1(sepal_tree* t) {
    for (uint32_t j = 0; j < SEPAL_TREE_MAX_BASES; ++j)
        if (t->blend_textures[j]) glDeleteTextures(1, &t->blend_textures[j]), t->blend_textures[j] = 0;
    if (t->copy_texture) glDeleteTextures(1, &t->copy_texture), t->copy_texture = 0;
}

void tree_copy_gles1(const sepal_tree* t, int width, int height) {
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, t->copy_texture);
    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 0, 0, width, height);
    glBindTexture(GL_TEXTURE_2D, 0);
}

// The running sum added back: a quad over the viewport whose texel centres fall on pixel
// centres, one texture unit replacing the colour, blend (ONE, ONE).
void tree_add_gles1(const sepal_tree* t, int width, int height) {
    const float sx = (float)width / (float)t->copy_width, sy = (float)height / (float)t->copy_height;
    const float pos[8] = {-1, -1, 1, -1, 1, 1, -1, 1};
    const float uv[8] = {0, 0, sx, 0, sx, sy, 0, sy};
    static const GLushort idx[6] = {0, 1, 2, 0, 2, 3};
    glMatrixMode(GL_PROJECTION);
    glPushMatrix();
    glLoadIdentity();
    glMatrixMode(GL_MODELVIEW);
    glPushMatrix();
    glLoadIdentity();
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
    glDrawElements(GL_TRIANGLES, 6, GL_UNSIGNED_SHORT, idx);
    // Back to GL's defaults for whoever draws next.
    glDisableClientState(GL_TEXTURE_COORD_ARRAY);
    glDisableClientState(GL_VERTEX_ARRAY);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    glBindTexture(GL_TEXTURE_2D, 0);
    glDisable(GL_TEXTURE_2D);
    glDisable(GL_BLEND);
    glMatrixMode(GL_PROJECTION);
    glPopMatrix();
    glMatrixMode(GL_MODELVIEW);
    glPopMatrix();
}

}  // namespace srt
