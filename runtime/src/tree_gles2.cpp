// Inverse shade trees on GL ES 2 (sepal_tree.h): blend textures, the composition's copy
// and addition, and the fused shader drawing the whole tree in one mesh pass.
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "gles2_util.h"
#include "gl_clear.h"
#include "material_state.h"
#include "tree_internal.h"

namespace {

const char kFullscreenVert[] =
#include "shaders/fullscreen.vert.inc"
    ;
const char kFullscreenFrag[] =
#include "shaders/fullscreen.frag.inc"
    ;
const char kFusedPixelFrag[] =
#include "shaders/fused_pixel.frag.inc"
    ;
const char kTreeVert[] =
#include "shaders/tree_fused.vert.inc"
    ;
const char kTreeFrag[] =
#include "shaders/tree_fused.frag.inc"
    ;
const char* const kFullscreenAttribs[] = {"a_position", "a_uv", nullptr};
const char* const kTreeAttribs[] = {"a_position", "a_normal", "a_tangent", "a_uv", nullptr};

int next_pow2(int v) {
    int p = 1;
    while (p < v) p *= 2;
    return p;
}

GLint loc(GLuint program, const char* name) { return glGetUniformLocation(program, name); }

// Why the tree cannot take the fused shader, or "" when it can.
const char* fused_check(const sepal_tree_asset* a, const sepal_caps& caps, int* tiles, int* n) {
    *tiles = 0;
    *n = 0;
    const sepal_fmt_material& m0 = a->bases[0].material;
    if ((int)a->header.basis_count + 2 > caps.texture_units) return "more bases than texture units for their maps";
    for (uint32_t j = 0; j < a->header.basis_count; ++j) {
        const sepal_asset& b = a->bases[j];
        if (b.material.param != m0.param || b.material.map != m0.map) return "bases differ in parameterization";
        if (b.material.channels != 3) return "a basis is not per-channel RGB";
        for (uint32_t p = 0; p < b.plan.pass_count; ++p)
            if (b.passes[p].blend != SEPAL_BLEND_ADD) return "a basis subtracts (signed factors)";
        for (uint32_t i = 0; i < b.texture_count; ++i) {
            const sepal_fmt_texture& d = b.textures[i].desc;
            if (d.bits != 8 || d.channels != 3 || d.width != d.height) return "textures are not square 8-bit RGB";
            if (*n == 0) *n = (int)d.width;
            if ((int)d.width != *n) return "textures differ in size";
        }
        *tiles += (int)b.material.terms;
    }
    if (*tiles > SEPAL_TREE_MAX_TILES) return "more terms than SEPAL_TREE_MAX_TILES";
    return "";
}

sepal_result create_fused(const sepal_tree_asset* a, sepal_tree* t, sepal_error* err) {
    int tiles = 0, n = 0;
    const char* why = fused_check(a, t->caps, &tiles, &n);
    if (*why) {
        snprintf(t->fused_reason, sizeof t->fused_reason, "%s", why);
        return srt::ok(err);
    }
    t->tiles = tiles;
    t->tile_n = n;
    t->atlas_cols = 1;
    while (t->atlas_cols * t->atlas_cols < tiles) ++t->atlas_cols;
    t->atlas_rows = (tiles + t->atlas_cols - 1) / t->atlas_cols;
    const int aw = next_pow2(t->atlas_cols * n), ah = next_pow2(t->atlas_rows * n);
    if (aw > t->caps.max_texture_size || ah > t->caps.max_texture_size) {
        snprintf(t->fused_reason, sizeof t->fused_reason, "atlas %dx%d exceeds the GPU's %d", aw, ah,
                 t->caps.max_texture_size);
        return srt::ok(err);
    }
    GLuint atlas[2];
    glGenTextures(2, atlas);
    t->atlas_g = atlas[0];
    t->atlas_h = atlas[1];
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (int r = 0; r < 2; ++r) {
        glBindTexture(GL_TEXTURE_2D, atlas[r]);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, aw, ah, 0, GL_RGB, GL_UNSIGNED_BYTE, nullptr);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    int tile = 0;
    for (uint32_t j = 0; j < a->header.basis_count; ++j) {
        const sepal_asset& b = a->bases[j];
        for (uint32_t k = 0; k < b.material.terms; ++k, ++tile) {
            for (uint32_t i = 0; i < b.texture_count; ++i) {
                const sepal_fmt_texture& d = b.textures[i].desc;
                if (d.term != k) continue;
                const int r = d.role == SEPAL_ROLE_G ? 0 : 1;
                glBindTexture(GL_TEXTURE_2D, atlas[r]);
                glTexSubImage2D(GL_TEXTURE_2D, 0, (tile % t->atlas_cols) * n, (tile / t->atlas_cols) * n, n, n, GL_RGB,
                                GL_UNSIGNED_BYTE, b.textures[i].level_data[0]);
                // The material's colour ratio rides on G's decode.
                for (int c = 0; c < 3; ++c) {
                    const float ratio = r == 0 ? b.material.ratio[c] : 1.0f;
                    t->tile_scale[tile][r][c] = d.scale[c] * ratio;
                    t->tile_bias[tile][r][c] = d.bias[c] * ratio;
                }
            }
            t->tile_basis[tile] = (int)j;
        }
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    // fused_pixel.frag supplies hemi(), coords() and pixel_frame(); its own main is renamed.
    static char source[24576];  // creation is single-threaded per context (GL's own rule)
    const int len = snprintf(source, sizeof source,
                             "#define MAX_TERMS 1\n#define MAX_TILES %d\n#define MAX_BASES %u\n#define main fused_pixel_main\n"
                             "%s\n%s",
                             tiles, a->header.basis_count, kFusedPixelFrag, kTreeFrag);
    if (len < 0 || len >= (int)sizeof source)
        return srt::fail(err, SEPAL_ERR_CAPACITY, "tree: fused shader source too long");
    t->program_fused = srt::gles2_program("tree_fused", kTreeVert, source, kTreeAttribs, err);
    if (!t->program_fused) return err ? err->code : SEPAL_ERR_GL;
    return srt::gl_check("tree atlases", err);
}

void quad_attribs(const float* pos, const float* uv) {
    glEnableVertexAttribArray(0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, pos);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 0, uv);
}

}  // namespace

namespace srt {

sepal_result tree_create_gles2(const sepal_tree_asset* asset, sepal_tree* t, sepal_error* err) {
    sepal_result r = tree_create_textures(asset, t, err);
    if (r != SEPAL_OK) return r;
    t->program_fullscreen = gles2_program("tree_fullscreen", kFullscreenVert, kFullscreenFrag, kFullscreenAttribs, err);
    if (!t->program_fullscreen) return err ? err->code : SEPAL_ERR_GL;
    r = create_fused(asset, t, err);
    if (r != SEPAL_OK) return r;
    return gl_check("tree textures", err);
}

void tree_destroy_gles2(sepal_tree* t) {
    tree_destroy_textures(t);
    const uint32_t textures[2] = {t->atlas_g, t->atlas_h};
    for (uint32_t x : textures)
        if (x) glDeleteTextures(1, &x);
    t->atlas_g = t->atlas_h = 0;
    if (t->program_fullscreen) glDeleteProgram(t->program_fullscreen);
    if (t->program_fused) glDeleteProgram(t->program_fused);
    t->program_fullscreen = t->program_fused = 0;
}

void tree_add_gles2(const sepal_tree* t, int width, int height) {
    const float sx = (float)width / (float)t->copy_width, sy = (float)height / (float)t->copy_height;
    const float pos[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const float uv[8] = {0, 0, sx, 0, sx, sy, 0, sy};
    static const GLushort idx[6] = {0, 1, 2, 0, 2, 3};
    // sepal_draw leaves the caller's viewport; the composition is over the tree's.
    glViewport(0, 0, width, height);
    const GLuint p = t->program_fullscreen;
    glUseProgram(p);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, t->copy_texture);
    glUniform1i(loc(p, "u_texture"), 0);
    glUniform1i(loc(p, "u_textured"), 1);
    glUniform4f(loc(p, "u_color"), 1, 1, 1, 1);
    quad_attribs(pos, uv);
    glDrawElements(GL_TRIANGLES, 6, GL_UNSIGNED_SHORT, idx);
    glDisableVertexAttribArray(0);
    glDisableVertexAttribArray(1);
    glBindTexture(GL_TEXTURE_2D, 0);
    glDisable(GL_BLEND);
    glUseProgram(0);
}

sepal_result tree_draw_fused_gles2(const sepal_tree_draw_desc* d, sepal_draw_stats* stats, sepal_error* err) {
    const sepal_tree* t = d->tree;
    const sepal_scene& scene = *d->scene;
    float view[16], proj[16], mvp[16];
    sepal_result r = sepal_scene_matrices(&scene, d->width, d->height, view, proj, err);
    if (r != SEPAL_OK) return r;
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) {
            float s = 0.0f;
            for (int k = 0; k < 4; ++k) s += proj[k * 4 + row] * view[c * 4 + k];
            mvp[c * 4 + row] = s;
        }
    glViewport(0, 0, d->width, d->height);
    clear_frame(scene.background[0], scene.background[1], scene.background[2], 1.0f);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);  // depth writes: on since clear_frame
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glDisable(GL_BLEND);
    const GLuint p = t->program_fused;
    glUseProgram(p);
    glUniformMatrix4fv(loc(p, "u_mvp"), 1, GL_FALSE, mvp);
    float pos[4 * SEPAL_MAX_LIGHTS] = {}, intensity[3 * SEPAL_MAX_LIGHTS] = {};
    for (int l = 0; l < scene.light_count; ++l) {
        const float* lp = scene.lights[l].position;
        const bool point = scene.lights[l].type == SEPAL_LIGHT_POINT;
        float len = point ? 1.0f : sqrtf(lp[0] * lp[0] + lp[1] * lp[1] + lp[2] * lp[2]);
        if (!(len > 0.0f)) len = 1.0f;
        for (int k = 0; k < 3; ++k) pos[4 * l + k] = lp[k] / len, intensity[3 * l + k] = scene.lights[l].intensity[k];
        pos[4 * l + 3] = point ? 1.0f : 0.0f;
    }
    glUniform4fv(loc(p, "u_light_pos"), SEPAL_MAX_LIGHTS, pos);
    glUniform3fv(loc(p, "u_light_intensity"), SEPAL_MAX_LIGHTS, intensity);
    glUniform1i(loc(p, "u_light_count"), scene.light_count);
    glUniform3fv(loc(p, "u_eye"), 1, scene.camera.eye);
    glUniform1i(loc(p, "u_param"), (int)srt::material(&t->bases[0])->info.param);
    glUniform1i(loc(p, "u_map"), (int)srt::material(&t->bases[0])->info.map);
    const int aw = next_pow2(t->atlas_cols * t->tile_n), ah = next_pow2(t->atlas_rows * t->tile_n);
    glUniform2f(loc(p, "u_tile_size"), (float)t->tile_n / (float)aw, (float)t->tile_n / (float)ah);
    glUniform1f(loc(p, "u_half_texel"), 0.5f / (float)t->tile_n);
    glUniform1i(loc(p, "u_tiles"), t->tiles);
    char name[32];
    for (int k = 0; k < t->tiles; ++k) {
        const float tile[3] = {(float)(k % t->atlas_cols * t->tile_n) / (float)aw,
                               (float)(k / t->atlas_cols * t->tile_n) / (float)ah, (float)t->tile_basis[k]};
        snprintf(name, sizeof name, "u_tile[%d]", k);
        glUniform3fv(loc(p, name), 1, tile);
        const char* prefix[4] = {"u_tg_scale", "u_tg_bias", "u_th_scale", "u_th_bias"};
        for (int q = 0; q < 4; ++q) {
            snprintf(name, sizeof name, "%s[%d]", prefix[q], k);
            glUniform3fv(loc(p, name), 1, q % 2 == 0 ? t->tile_scale[k][q / 2] : t->tile_bias[k][q / 2]);
        }
    }
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, t->atlas_g);
    glUniform1i(loc(p, "u_atlas_g"), 0);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, t->atlas_h);
    glUniform1i(loc(p, "u_atlas_h"), 1);
    for (uint32_t j = 0; j < t->basis_count; ++j) {
        glActiveTexture(GL_TEXTURE2 + j);
        glBindTexture(GL_TEXTURE_2D, t->blend_textures[j]);
        snprintf(name, sizeof name, "u_blend[%u]", j);
        glUniform1i(loc(p, name), (GLint)(2 + j));
    }
    const sepal_vertex* v = d->mesh->vertices;
    for (GLuint i = 0; i < 4; ++i) glEnableVertexAttribArray(i);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(sepal_vertex), v->position);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(sepal_vertex), v->normal);
    glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, sizeof(sepal_vertex), v->tangent);
    glVertexAttribPointer(3, 2, GL_FLOAT, GL_FALSE, sizeof(sepal_vertex), v->uv);
    glDrawElements(GL_TRIANGLES, d->mesh->index_count, GL_UNSIGNED_SHORT, d->mesh->indices);
    stats->draw_calls = 1;
    stats->exposure = 1.0f;
    stats->exposure_stages = 1;
    for (GLuint i = 0; i < 4; ++i) glDisableVertexAttribArray(i);
    for (uint32_t j = 0; j < t->basis_count + 2; ++j) {
        glActiveTexture(GL_TEXTURE0 + j);
        glBindTexture(GL_TEXTURE_2D, 0);
    }
    glActiveTexture(GL_TEXTURE0);
    glUseProgram(0);
    glDisable(GL_CULL_FACE);
    glDisable(GL_DEPTH_TEST);
    return gl_check("the fused tree pass", err);
}

}  // namespace srt
