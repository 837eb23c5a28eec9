// Inverse shade trees at run time (sepal_tree.h): the GL halves, one per GL ES version.
#pragma once
#include "internal.h"
#include "sepal/sepal_tree.h"

namespace srt {

// Blend textures and the copy texture of a tree whose bases are already created (either
// version, tree_gl.cpp); on GL ES 2 also the programs and atlases. destroy frees what
// create made.
sepal_result tree_create_textures(const sepal_tree_asset* asset, sepal_tree* t, sepal_error* err);
void tree_destroy_textures(sepal_tree* t);
sepal_result tree_create_gles2(const sepal_tree_asset* asset, sepal_tree* t, sepal_error* err);
void tree_destroy_gles2(sepal_tree* t);

// Copies the framebuffer's running sum to the copy texture before the next basis, then
// adds it back after it (GL ES 1.1 and 2 differ only in how the quad is drawn).
void tree_copy(const sepal_tree* t, int width, int height);
void tree_add_gles1(const sepal_tree* t, int width, int height);
void tree_add_gles2(const sepal_tree* t, int width, int height);
// GL ES 2: the whole tree in one mesh pass per frame (SEPAL_MODE_FUSED_PIXEL).
sepal_result tree_draw_fused_gles2(const sepal_tree_draw_desc* d, sepal_draw_stats* stats, sepal_error* err);

}  // namespace srt
