// Inverse shade trees: the GL calls both GL ES versions share (sepal_tree.h): blend
// textures, the copy texture of the composition, and the copy itself.
#include <GLES2/gl2.h>

#include "tree_internal.h"

#ifndef GL_GENERATE_MIPMAP
#define GL_GENERATE_MIPMAP 0x8191  // GL ES 1.1's texture parameter (core there, absent in GL ES 2)
#endif

namespace {

int next_pow2(int v) {
    int p = 1;
    while (p < v) p *= 2;
    return p;
}

GLuint new_texture() {
    GLuint name = 0;
    glGenTextures(1, &name);
    glBindTexture(GL_TEXTURE_2D, name);
    return name;
}

void filter_and_wrap(GLint min_filter, GLint mag_filter, GLint wrap) {
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, min_filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, mag_filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
}

}  // namespace

namespace srt {

sepal_result tree_create_textures(const sepal_tree_asset* asset, sepal_tree* t, sepal_error* err) {
    const uint32_t w = asset->header.blend_width, h = asset->header.blend_height;
    if ((int)w > t->caps.max_texture_size || (int)h > t->caps.max_texture_size)
        return fail(err, SEPAL_ERR_UNSUPPORTED, "tree: blend maps %ux%u exceed the GPU's %d", w, h, t->caps.max_texture_size);
    const bool es1 = t->caps.gles_version == 1;
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (uint32_t j = 0; j < asset->header.basis_count; ++j) {
        t->blend_textures[j] = new_texture();
        // The MIP chain: GL ES 1.1 builds it on upload, GL ES 2 on request.
        if (es1) glTexParameteri(GL_TEXTURE_2D, GL_GENERATE_MIPMAP, GL_TRUE);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_LUMINANCE, (GLsizei)w, (GLsizei)h, 0, GL_LUMINANCE, GL_UNSIGNED_BYTE,
                     asset->blend[j]);
        if (!es1) glGenerateMipmap(GL_TEXTURE_2D);
        filter_and_wrap(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR, GL_REPEAT);
    }
    if (asset->header.basis_count > 1) {
        t->copy_width = next_pow2(t->max_width);
        t->copy_height = next_pow2(t->max_height);
        t->copy_texture = new_texture();
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, t->copy_width, t->copy_height, 0, GL_RGB, GL_UNSIGNED_BYTE, nullptr);
        // Nearest: the full-screen addition samples the copy exactly at texel centres.
        filter_and_wrap(GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    return gl_check("tree textures", err);
}

void tree_destroy_textures(sepal_tree* t) {
    for (uint32_t j = 0; j < SEPAL_TREE_MAX_BASES; ++j)
        if (t->blend_textures[j]) glDeleteTextures(1, &t->blend_textures[j]), t->blend_textures[j] = 0;
    if (t->copy_texture) glDeleteTextures(1, &t->copy_texture), t->copy_texture = 0;
}

void tree_copy(const sepal_tree* t, int width, int height) {
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, t->copy_texture);
    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 0, 0, width, height);
    glBindTexture(GL_TEXTURE_2D, 0);
}

}  // namespace srt
