// The GL ES 2 executor: the plan with tiny shaders, or fused shaders (see sepal_material.h).
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "draw_internal.h"
#include "gles2_util.h"
#include "gl_clear.h"

namespace {

const char kPassVert[] =
#include "shaders/pass.vert.inc"
    ;
const char kPassFrag[] =
#include "shaders/pass.frag.inc"
    ;
const char kFullscreenVert[] =
#include "shaders/fullscreen.vert.inc"
    ;
const char kFullscreenFrag[] =
#include "shaders/fullscreen.frag.inc"
    ;
const char kMeshTextureFrag[] =
#include "shaders/mesh_texture.frag.inc"
    ;
const char kFusedVertexVert[] =
#include "shaders/fused_vertex.vert.inc"
    ;
const char kFusedVertexFrag[] =
#include "shaders/fused_vertex.frag.inc"
    ;
const char kFusedPixelVert[] =
#include "shaders/fused_pixel.vert.inc"
    ;
const char kFusedPixelFrag[] =
#include "shaders/fused_pixel.frag.inc"
    ;
const char kAccumulatedFrag[] =
#include "shaders/accumulated.frag.inc"
    ;

const char* const kPassAttribs[] = {"a_position", "a_color", "a_uv0", "a_uv1", "a_uvm", nullptr};
const char* const kFullscreenAttribs[] = {"a_position", "a_uv", nullptr};
const char* const kFusedVertexAttribs[] = {"a_position", "a_uv_g",   "a_uv_h", "a_irradiance",
                                           "a_diffuse",  "a_uv_g2", nullptr};
const char* const kFusedPixelAttribs[] = {"a_position", "a_normal", "a_tangent", nullptr};

struct Frame {
    const srt::Material* m;
    const sepal_draw_desc* d;
    const srt::MeshView* mesh;  // d->mesh is not read: the object's vertices are these
    float* scratch;
    float mvp[16];
    float exposure;
    sepal_draw_stats* stats;
    int bad_vertices;  // > 0: triangles touching one are skipped
    bool repaired;     // some tangents were replaced: per-pixel attributes come from scratch
    bool map_per_pass;  // multipass: the diffuse map multiplies each pass (unit 2)
    // The next mesh draw lays depth (LESS, depth writes, no blending) instead of a pre-pass;
    // draw_mesh clears it. Mutable: the passes take the frame as const.
    mutable bool lays_depth;
};

// Enables attribute arrays 0..count-1 and disables the rest of the 6 the programs use.
void attribs(int count) {
    for (GLuint i = 0; i < 6; ++i) (int)i < count ? glEnableVertexAttribArray(i) : glDisableVertexAttribArray(i);
}

GLint loc(GLuint program, const char* name) { return glGetUniformLocation(program, name); }

void bind_texture(GLenum unit, GLuint texture) {
    glActiveTexture(unit);
    glBindTexture(GL_TEXTURE_2D, texture);
}

// One mesh pass: the whole index list, or the runs of it without bad vertices.
void draw_mesh(const Frame& f) {
    // Laying depth: the nearest fragment's colour replaces an occluded one's, which is what
    // adding it to the cleared framebuffer gives; then EQUAL, as after a pre-pass.
    if (f.lays_depth) glDisable(GL_BLEND);
    srt::for_each_drawable_run(*f.mesh, f.bad_vertices, [&f](int first, int count) {
        glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_SHORT, f.mesh->indices + first);
    });
    ++f.stats->draw_calls;
    if (f.lays_depth) {
        f.lays_depth = false;
        glEnable(GL_BLEND);
        glDepthMask(GL_FALSE);
        glDepthFunc(GL_EQUAL);
    }
}

// The object's positions (object space: u_mvp moves them) and UVs, read in place.
const float* positions(const Frame& f) { return f.mesh->position(0); }
GLsizei pos_stride(const Frame& f) { return (GLsizei)f.mesh->stride[srt::MeshView::kPosition]; }
const float* uvs(const Frame& f) { return f.mesh->element(srt::MeshView::kUv, 0); }
GLsizei uv_stride(const Frame& f) { return (GLsizei)f.mesh->stride[srt::MeshView::kUv]; }

// The object's mesh in a constant colour (the pass program, no texture): the black
// pre-pass, and the framebuffer-wide operations restricted to the object's visible
// pixels (doublings, inversions: depth EQUAL), counted with the full-screen passes they
// replace.
void solid_mesh(const Frame& f, const float color[4], bool counts_as_pass) {
    const GLuint p = f.m->program_pass;
    glUseProgram(p);
    glUniformMatrix4fv(loc(p, "u_mvp"), 1, GL_FALSE, f.mvp);
    glUniform1i(loc(p, "u_op"), 0);
    glUniform1f(loc(p, "u_scale"), 1.0f);
    glUniform1f(loc(p, "u_use_map"), 0.0f);
    attribs(1);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, pos_stride(f), positions(f));
    glVertexAttrib4fv(1, color);
    if (counts_as_pass) {
        draw_mesh(f);
        return;
    }
    srt::for_each_drawable_run(*f.mesh, f.bad_vertices, [&f](int first, int count) {
        glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_SHORT, f.mesh->indices + first);
    });
    ++f.stats->fullscreen_passes;
}

void invert(const Frame& f) {
    static const float kWhite[4] = {1, 1, 1, 1};
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE_MINUS_DST_COLOR, GL_ZERO);
    solid_mesh(f, kWhite, false);
}


void multipass(const Frame& f) {
    const srt::Material* m = f.m;
    const int n = f.mesh->vertex_count, lights = f.d->scene->light_count;
    const GLuint p = m->program_pass;
    glUseProgram(p);
    glUniformMatrix4fv(loc(p, "u_mvp"), 1, GL_FALSE, f.mvp);
    glUniform1i(loc(p, "u_tex0"), 0);
    glUniform1i(loc(p, "u_tex1"), 1);
    glUniform1i(loc(p, "u_map"), 2);
    glUniform1f(loc(p, "u_use_map"), f.map_per_pass ? 1.0f : 0.0f);
    if (f.map_per_pass) bind_texture(GL_TEXTURE2, f.d->diffuse_texture);
    const GLint op_loc = loc(p, "u_op"), scale_loc = loc(p, "u_scale");
    float* colors = srt::pass_colors(f.scratch, n, lights);
    bool inverted = false;
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    for (uint32_t i = 0; i < m->plan.pass_count; ++i) {
        const sepal_fmt_pass& pass = m->passes[i];
        if (pass.blend == SEPAL_BLEND_SUBTRACT && m->subtract_by_inversion && !inverted) {
            invert(f);
            inverted = true;
            glUseProgram(p);
            glUniform1f(loc(p, "u_use_map"), f.map_per_pass ? 1.0f : 0.0f);
            glBlendFunc(GL_ONE, GL_ONE);
        }
        glBlendEquation(pass.blend == SEPAL_BLEND_SUBTRACT && !inverted ? GL_FUNC_REVERSE_SUBTRACT : GL_FUNC_ADD);
        glUniform1i(op_loc, srt::pass_texture_count(pass));
        glUniform1f(scale_loc, (float)pass.rgb_scale);
        if (srt::pass_texture_count(pass) >= 1) bind_texture(GL_TEXTURE0, m->gl_textures[pass.tex0]);
        if (srt::pass_texture_count(pass) == 2) bind_texture(GL_TEXTURE1, m->gl_textures[pass.tex1]);
        for (int l = 0; l < lights; ++l) {
            srt::fill_pass_colors(m->info, pass, srt::pass_inputs(m, f.scratch, n, lights, l), f.exposure, n, colors);
            auto uv = [&](uint16_t tex) {
                return m->texture_role[tex] == SEPAL_ROLE_G ? srt::light_g_uv(f.scratch, n, l) : srt::light_h_uv(f.scratch, n, l);
            };
            attribs(f.map_per_pass ? 5 : 4);
            glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, pos_stride(f), positions(f));
            if (f.map_per_pass)
                glVertexAttribPointer(4, 2, GL_FLOAT, GL_FALSE, uv_stride(f), uvs(f));
            glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 0, colors);
            // Unused coordinates still need a valid array: point them at the G ones.
            glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, 0,
                                  srt::pass_texture_count(pass) >= 1 ? uv(pass.tex0) : srt::light_g_uv(f.scratch, n, l));
            glVertexAttribPointer(3, 2, GL_FLOAT, GL_FALSE, 0,
                                  srt::pass_texture_count(pass) == 2 ? uv(pass.tex1) : srt::light_g_uv(f.scratch, n, l));
            draw_mesh(f);
        }
    }
    glBlendEquation(GL_FUNC_ADD);
    if (inverted) invert(f);
}

// Uniforms shared by both fused programs for terms [first, first + count).
void fused_terms(const Frame& f, GLuint p, int first, int count) {
    const srt::Material* m = f.m;
    char name[32];
    for (int k = 0; k < count; ++k) {
        const int gi = (int)m->term_textures[first + k][SEPAL_ROLE_G], hi = (int)m->term_textures[first + k][SEPAL_ROLE_H];
        bind_texture(GL_TEXTURE0 + 2 * k, m->gl_textures[gi]);
        bind_texture(GL_TEXTURE0 + 2 * k + 1, m->gl_textures[hi]);
        snprintf(name, sizeof name, "u_g[%d]", k);
        glUniform1i(loc(p, name), 2 * k);
        snprintf(name, sizeof name, "u_h[%d]", k);
        glUniform1i(loc(p, name), 2 * k + 1);
        const int idx[2] = {gi, hi};
        const char* prefix[2] = {"u_g", "u_h"};
        for (int r = 0; r < 2; ++r) {
            float scale[3], bias[3];
            for (int c = 0; c < 3; ++c) {
                const int cc = m->info.channels == 1 ? 0 : c;
                scale[c] = m->texture_scale[idx[r]][cc];
                bias[c] = m->texture_bias[idx[r]][cc];
            }
            snprintf(name, sizeof name, "%s_scale[%d]", prefix[r], k);
            glUniform3fv(loc(p, name), 1, scale);
            snprintf(name, sizeof name, "%s_bias[%d]", prefix[r], k);
            glUniform3fv(loc(p, name), 1, bias);
        }
    }
    glUniform1i(loc(p, "u_terms"), count);
    glUniform1i(loc(p, "u_reciprocal"), (m->info.flags & SEPAL_MATERIAL_RECIPROCAL) ? 1 : 0);
    glUniform3fv(loc(p, "u_ratio"), 1, m->info.ratio);
    // Version 1: the factors are f, times cos(theta_i); radiance materials hold the cosine
    // in the factors and add the diffuse part times it (once: with the first group).
    if (p == m->program_fused_pixel) {
        const float zero[3] = {0, 0, 0};
        glUniform1f(loc(p, "u_factor_cosine"), (m->info.flags & SEPAL_MATERIAL_RADIANCE) ? 0.0f : 1.0f);
        glUniform1f(loc(p, "u_horizon"), m->info.horizon);
        glUniform3fv(loc(p, "u_diffuse"), 1, first == 0 ? m->info.diffuse : zero);
        // The diffuse profile at (cos theta_i, cos theta_o), in the unit after the factors'.
        const int unit = 2 * m->fused_group;
        bind_texture(GL_TEXTURE0 + unit, m->diffuse_texture);
        glUniform1i(loc(p, "u_profile"), unit);
        glUniform1f(loc(p, "u_profile_on"), m->diffuse_texture ? 1.0f : 0.0f);
        glUniform1f(loc(p, "u_profile_side"), (float)(m->diffuse_side ? m->diffuse_side : 2));
    }
    // The fused shaders compute f itself: scaled by the frame's fused exposure.
    glUniform1f(loc(p, "u_out_scale"), f.exposure);
    glUniformMatrix4fv(loc(p, "u_mvp"), 1, GL_FALSE, f.mvp);
}

void fused(const Frame& f, bool per_pixel) {
    const srt::Material* m = f.m;
    const int n = f.mesh->vertex_count;
    const sepal_scene& scene = *f.d->scene;
    const GLuint p = per_pixel ? m->program_fused_pixel : m->program_fused_vertex;
    glUseProgram(p);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE);
    if (per_pixel) {
        float pos[4 * SEPAL_MAX_LIGHTS] = {}, intensity[3 * SEPAL_MAX_LIGHTS] = {};
        for (int l = 0; l < scene.light_count; ++l) {
            const sepal_light& light = scene.lights[l];
            float len = 1.0f;
            if (light.type == SEPAL_LIGHT_DIRECTIONAL)
                len = sqrtf(light.position[0] * light.position[0] + light.position[1] * light.position[1] +
                            light.position[2] * light.position[2]);
            for (int k = 0; k < 3; ++k) pos[4 * l + k] = light.position[k] / len, intensity[3 * l + k] = light.intensity[k];
            pos[4 * l + 3] = light.type == SEPAL_LIGHT_POINT ? 1.0f : 0.0f;
        }
        glUniform4fv(loc(p, "u_light_pos"), SEPAL_MAX_LIGHTS, pos);
        glUniform3fv(loc(p, "u_light_intensity"), SEPAL_MAX_LIGHTS, intensity);
        glUniform1i(loc(p, "u_light_count"), scene.light_count);
        glUniform3fv(loc(p, "u_eye"), 1, scene.camera.eye);
        // Positions into the shading space (world under a model that is not a similarity).
        float shade[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        if (f.mesh->transform)
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 3; ++r) shade[c * 4 + r] = f.mesh->m[c * 3 + r];
        glUniformMatrix4fv(loc(p, "u_shade_from_object"), 1, GL_FALSE, shade);
        glUniform1i(loc(p, "u_param"), (int)m->info.param);
        glUniform1i(loc(p, "u_map"), (int)m->info.map);
    }
    for (int first = 0; first < (int)m->info.terms; first += m->fused_group) {
        const int count = (int)m->info.terms - first < m->fused_group ? (int)m->info.terms - first : m->fused_group;
        fused_terms(f, p, first, count);
        if (per_pixel) {
            attribs(3);
            glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, pos_stride(f), positions(f));
            // The normals and tangents the CPU backend interpolates too: repaired, or moved
            // to the shading space, in the scratch.
            if (f.repaired || f.mesh->transform) {
                const float* a = srt::vertex_frames(f.scratch, n, scene.light_count);
                const GLsizei stride = srt::kFrameFloats * sizeof(float);
                glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, a);
                glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, stride, a + 3);
            } else {
                glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, (GLsizei)f.mesh->stride[srt::MeshView::kNormal],
                                      f.mesh->element(srt::MeshView::kNormal, 0));
                glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, (GLsizei)f.mesh->stride[srt::MeshView::kTangent],
                                      f.mesh->element(srt::MeshView::kTangent, 0));
            }
            draw_mesh(f);
            continue;
        }
        for (int l = 0; l < scene.light_count; ++l) {
            // The factors' irradiance (E cos for factors of f, E for radiance factors) and the
            // diffuse part's radiance (the DIFFUSE pass's colour: diffuse E cos profile), in the
            // colour scratch; the diffuse part once, with the first group.
            const srt::PassInputs in = srt::pass_inputs(m, f.scratch, n, scene.light_count, l);
            sepal_fmt_pass textured = {};
            textured.op = SEPAL_OP_PRODUCT;
            textured.color[0] = textured.color[1] = textured.color[2] = 1.0f;
            sepal_fmt_pass diffuse = {};
            diffuse.op = SEPAL_OP_DIFFUSE;
            for (int k = 0; k < 3; ++k) diffuse.color[k] = first == 0 ? m->info.diffuse[k] : 0.0f;
            float* irr = srt::pass_colors(f.scratch, n, scene.light_count);
            float* dif = srt::second_colors(f.scratch, n, scene.light_count);
            srt::fill_pass_colors(m->info, textured, in, 1.0f, n, irr);
            srt::fill_pass_colors(m->info, diffuse, in, 1.0f, n, dif);
            const bool reciprocal = (m->info.flags & SEPAL_MATERIAL_RECIPROCAL) != 0;
            attribs(reciprocal ? 6 : 5);
            glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, pos_stride(f), positions(f));
            if (reciprocal) glVertexAttribPointer(5, 2, GL_FLOAT, GL_FALSE, 0, srt::light_swapped_uv(f.scratch, n, l));
            glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 0, srt::light_g_uv(f.scratch, n, l));
            glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, 0, srt::light_h_uv(f.scratch, n, l));
            glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, 0, irr);
            glVertexAttribPointer(4, 4, GL_FLOAT, GL_FALSE, 0, dif);
            draw_mesh(f);
        }
    }
}

// Compiles one program; the fused ones get "#define MAX_TERMS n" in front.
GLuint build(const char* name, const char* vs, const char* fs, const char* const* attributes, int max_terms,
             sepal_error* err) {
    if (max_terms <= 0) return srt::gles2_program(name, vs, fs, attributes, err);
    static char source[16384];  // creation is single-threaded per context (GL's own rule)
    const int n = snprintf(source, sizeof source, "#define MAX_TERMS %d\n%s", max_terms, fs);
    if (n < 0 || n >= (int)sizeof source) {
        srt::fail(err, SEPAL_ERR_CAPACITY, "shader '%s' source too long", name);
        return 0;
    }
    return srt::gles2_program(name, vs, source, attributes, err);
}

}  // namespace

namespace srt {

sepal_result create_gles2_programs(srt::Material* m, sepal_error* err) {
    if (m->float_target) {
        // GL ES 3 names, not in the GL ES 2 header this file includes.
        const GLenum kRGBA16F = 0x881A, kHalfFloat = 0x140B;
        glGenTextures(1, &m->float_color);
        glBindTexture(GL_TEXTURE_2D, m->float_color);
        glTexImage2D(GL_TEXTURE_2D, 0, (GLint)kRGBA16F, m->max_width, m->max_height, 0, GL_RGBA, kHalfFloat, nullptr);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glGenRenderbuffers(1, &m->float_depth);
        glBindRenderbuffer(GL_RENDERBUFFER, m->float_depth);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT16, m->max_width, m->max_height);
        glGenFramebuffers(1, &m->float_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, m->float_fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, m->float_color, 0);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, m->float_depth);
        const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (status != GL_FRAMEBUFFER_COMPLETE)
            return fail(err, SEPAL_ERR_UNSUPPORTED, "material: half-float target incomplete (status 0x%04x)",
                        (unsigned)status);
        sepal_result r = gl_check("half-float target", err);
        if (r != SEPAL_OK) return r;
    }
    if (m->diffuse_side) {
        // The diffuse profile for the fused per-pixel shader: RGB8 (a smooth function in
        // [0,1]), sample (i, j) at texel (i, j), linear, clamped.
        uint8_t rgb[SEPAL_FMT_MAX_DIFFUSE_SIDE * SEPAL_FMT_MAX_DIFFUSE_SIDE * 3];
        const uint32_t count = m->diffuse_side * m->diffuse_side * 3;
        for (uint32_t k = 0; k < count; ++k) rgb[k] = (uint8_t)(m->diffuse_profile[k] * 255.0f + 0.5f);
        glGenTextures(1, &m->diffuse_texture);
        glBindTexture(GL_TEXTURE_2D, m->diffuse_texture);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, (GLsizei)m->diffuse_side, (GLsizei)m->diffuse_side, 0, GL_RGB,
                     GL_UNSIGNED_BYTE, rgb);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        sepal_result r = gl_check("diffuse profile texture", err);
        if (r != SEPAL_OK) return r;
    }
    m->program_pass = build("pass", kPassVert, kPassFrag, kPassAttribs, 0, err);
    if (!m->program_pass) return err ? err->code : SEPAL_ERR_GL;
    m->program_fullscreen = build("fullscreen", kFullscreenVert, kFullscreenFrag, kFullscreenAttribs, 0, err);
    if (!m->program_fullscreen) return err ? err->code : SEPAL_ERR_GL;
    m->program_mesh_texture = build("mesh_texture", kPassVert, kMeshTextureFrag, kPassAttribs, 0, err);
    if (!m->program_mesh_texture) return err ? err->code : SEPAL_ERR_GL;
    m->program_fused_vertex =
        build("fused_vertex", kFusedVertexVert, kFusedVertexFrag, kFusedVertexAttribs, m->fused_group, err);
    if (!m->program_fused_vertex) return err ? err->code : SEPAL_ERR_GL;
    m->program_fused_pixel =
        build("fused_pixel", kFusedPixelVert, kFusedPixelFrag, kFusedPixelAttribs, m->fused_group, err);
    if (!m->program_fused_pixel) return err ? err->code : SEPAL_ERR_GL;
    return ok(err);
}

const FboFunctions& gles2_fbo_functions() {
    static const FboFunctions f = {glGenFramebuffers,      glDeleteFramebuffers,  glBindFramebuffer,
                                   glFramebufferTexture2D, glGenRenderbuffers,    glDeleteRenderbuffers,
                                   glBindRenderbuffer,     glRenderbufferStorage, glFramebufferRenderbuffer,
                                   glCheckFramebufferStatus};
    return f;
}

bool create_gles2_sum_program(srt::Material* m) {
    m->program_accumulated = build("accumulated", kPassVert, kAccumulatedFrag, kPassAttribs, 0, nullptr);
    return m->program_accumulated != 0;
}

void destroy_gles2_programs(srt::Material* m) {
    if (m->diffuse_texture) glDeleteTextures(1, &m->diffuse_texture);
    m->diffuse_texture = 0;
    if (m->float_fbo) glDeleteFramebuffers(1, &m->float_fbo);
    if (m->float_depth) glDeleteRenderbuffers(1, &m->float_depth);
    if (m->float_color) glDeleteTextures(1, &m->float_color);
    m->float_fbo = m->float_depth = m->float_color = 0;
    const uint32_t programs[6] = {m->program_pass,         m->program_fullscreen,  m->program_mesh_texture,
                                  m->program_fused_vertex, m->program_fused_pixel, m->program_accumulated};
    for (uint32_t p : programs)
        if (p) glDeleteProgram(p);
    m->program_pass = m->program_fullscreen = m->program_mesh_texture = m->program_accumulated = 0;
    m->program_fused_vertex = m->program_fused_pixel = 0;
}

sepal_result draw_object(const sepal_draw_desc* d, const FramePrep& prep, sepal_draw_stats* stats, sepal_error* err,
                         float mvp[16]);

sepal_result draw_gles2(const sepal_draw_desc* d, const FramePrep& prep, sepal_draw_stats* stats, sepal_error* err) {
    const srt::Material* m = srt::material(d->material);
    float mvp[16];
    if (!m->acc_fbo) return draw_object(d, prep, stats, err, mvp);
    // Framebuffers with fewer bits: the object's passes go to the 8-bit target, at the same
    // size and with the same matrices; then one write to the framebuffer bound now (the
    // GL ES 1.1 executor does the same: draw_gles1.cpp).
    const SumTarget target = enter_sum_target(m);
    const sepal_result r = draw_object(d, prep, stats, err, mvp);
    leave_sum_target(m, target);
    if (r != SEPAL_OK) return r;
    const int* viewport = target.viewport;
    // The object's mesh at depth LESS, as the first pass lays it, so that what the engine drew
    // in front still hides it; replaces what the pixel held, as the first pass did.
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glDisable(GL_BLEND);
    const GLuint p = m->program_accumulated;
    glUseProgram(p);
    glUniformMatrix4fv(loc(p, "u_mvp"), 1, GL_FALSE, mvp);
    glUniform1i(loc(p, "u_sum"), 0);
    glUniform2f(loc(p, "u_origin"), (float)viewport[0], (float)viewport[1]);
    glUniform2f(loc(p, "u_inv_size"), 1.0f / (float)m->acc_width, 1.0f / (float)m->acc_height);
    const int bits[3] = {m->caps.red_bits, m->caps.green_bits, m->caps.blue_bits};
    float levels[3];
    for (int c = 0; c < 3; ++c) levels[c] = bits[c] > 0 && bits[c] < 8 ? (float)((1 << bits[c]) - 1) : 255.0f;
    glUniform3fv(loc(p, "u_levels"), 1, levels);
    bind_texture(GL_TEXTURE0, m->acc_color);
    const MeshView& mesh = prep.mesh;
    attribs(1);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, (GLsizei)mesh.stride[MeshView::kPosition], mesh.position(0));
    for_each_drawable_run(mesh, prep.vertices.bad_vertices, [&mesh](int first, int count) {
        glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_SHORT, mesh.indices + first);
    });
    ++stats->draw_calls;  // a mesh pass, as on GL ES 1.1
    return gl_check("the accumulated sum's write", err);
}

sepal_result draw_object(const sepal_draw_desc* d, const FramePrep& prep, sepal_draw_stats* stats, sepal_error* err,
                         float mvp[16]) {
    const srt::Material* m = srt::material(d->material);
    if (d->mode == SEPAL_MODE_FUSED_VERTEX || d->mode == SEPAL_MODE_MULTIPASS) {
        if (!param_per_vertex((sepal_param)m->info.param))
            return fail(err, SEPAL_ERR_UNSUPPORTED,
                        "draw: parameterization %u needs per-pixel coordinates (SEPAL_MODE_FUSED_PIXEL)",
                        m->info.param);
    } else if (d->mode != SEPAL_MODE_FUSED_PIXEL) {
        return fail(err, SEPAL_ERR_INVALID_ARGUMENT, "draw: unknown mode %d", (int)d->mode);
    }
    Frame f = {m, d, &prep.mesh, d->scratch, {}, prep.exposure, stats, prep.vertices.bad_vertices,
               prep.vertices.fallback_tangents > 0, prep.diffuse_per_pass, false};
    mat4_mul(prep.proj, prep.view, f.mvp);
    memcpy(mvp, f.mvp, sizeof f.mvp);
    // The frame's begin set what every object shares (gles2_frame_begin); the depth set-up
    // of this object here.
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glDisable(GL_BLEND);
    // Later draws test EQUAL, so each pixel's front surface is shaded once and only the
    // object's visible pixels are touched. The first mesh draw lays that depth when it
    // adds (every fused draw, and a plan whose first pass adds): drawn without blending, it
    // replaces what the pixel held. Otherwise a pre-pass in black lays it, so the object's
    // pixels start from 0 whatever the framebuffer held. Folding saves a mesh pass.
    f.lays_depth = d->mode == SEPAL_MODE_MULTIPASS
                       ? m->plan.pass_count > 0 && m->passes[0].blend != SEPAL_BLEND_SUBTRACT &&
                             d->scene->light_count > 0
                       : m->info.terms > 0 && d->scene->light_count > 0;
    if (!f.lays_depth) {
        static const float kBlack[4] = {0, 0, 0, 0};
        solid_mesh(f, kBlack, true);
        glDepthMask(GL_FALSE);
        glDepthFunc(GL_EQUAL);
    }
    sepal_result r = gl_check(f.lays_depth ? "object set-up" : "depth pre-pass", err);
    if (r != SEPAL_OK) return r;
    if (d->mode == SEPAL_MODE_MULTIPASS)
        multipass(f);
    else
        fused(f, d->mode == SEPAL_MODE_FUSED_PIXEL);
    if ((r = gl_check("the material's passes", err)) != SEPAL_OK) return r;
    // The diffuse map before the doublings, as on GL ES 1.1 (draw_gles1.cpp says why);
    // in multipass it was a factor of every pass (f.map_per_pass).
    if (d->diffuse_texture && !f.map_per_pass) {
        const GLuint p = m->program_mesh_texture;
        glDepthFunc(GL_EQUAL);
        glEnable(GL_BLEND);
        glBlendFunc(GL_DST_COLOR, GL_ZERO);
        glUseProgram(p);
        glUniformMatrix4fv(loc(p, "u_mvp"), 1, GL_FALSE, f.mvp);
        glUniform1i(loc(p, "u_tex0"), 0);
        bind_texture(GL_TEXTURE0, d->diffuse_texture);
        attribs(3);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, pos_stride(f), positions(f));
        glVertexAttrib4f(1, 1, 1, 1, 1);
        glDisableVertexAttribArray(1);
        glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, uv_stride(f), uvs(f));
        glEnableVertexAttribArray(2);
        draw_mesh(f);
    }
    // The doublings over the object's own pixels.
    static const float kWhite[4] = {1, 1, 1, 1};
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_DST_COLOR, GL_ONE);
    for (int i = 0; i < stats->doublings; ++i) solid_mesh(f, kWhite, false);
    return gl_check("the object's final passes", err);
}

}  // namespace srt

namespace {

constexpr int kAttribs = 6;  // the programs' attributes 0..5
constexpr int kMaxUnits = 32;

struct AttribState {
    GLint enabled, size, type, normalized, stride, buffer;
    void* pointer;
    GLfloat current[4];
};

struct Gles2Saved {
    srt::CoreGlState core;
    GLint blend_src_rgb, blend_dst_rgb, blend_src_alpha, blend_dst_alpha, blend_eq_rgb, blend_eq_alpha;
    GLint program, framebuffer, units;
    GLint bindings[kMaxUnits];
    AttribState attrib[kAttribs];
};
static_assert(sizeof(Gles2Saved) <= srt::kSavedStateBytes, "sepal_frame.saved is too small");

// A quad over the viewport at NDC depth z in a constant colour, or textured (the float
// target shown): sepal_draw's own frame only.
void viewport_quad(const srt::Material* m, float z, const float color[4], GLuint texture, float sx, float sy) {
    const float pos[12] = {-1, -1, z, 1, -1, z, 1, 1, z, -1, 1, z};
    const float uv[8] = {0, 0, sx, 0, sx, sy, 0, sy};
    static const GLushort idx[6] = {0, 1, 2, 0, 2, 3};
    const GLuint p = m->program_fullscreen;
    glUseProgram(p);
    glUniform4fv(loc(p, "u_color"), 1, color);
    glUniform1i(loc(p, "u_textured"), texture ? 1 : 0);
    glUniform1i(loc(p, "u_texture"), 0);
    if (texture) bind_texture(GL_TEXTURE0, texture);
    attribs(texture ? 2 : 1);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, pos);
    if (texture) glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 0, uv);
    glDrawElements(GL_TRIANGLES, 6, GL_UNSIGNED_SHORT, idx);
}

}  // namespace

namespace srt {

void gles2_frame_begin(const sepal_frame_desc& d, void* out, uint32_t material_fbo) {
    Gles2Saved& s = *static_cast<Gles2Saved*>(out);
    memset(&s, 0, sizeof s);
    save_core_state(&s.core);
    glGetIntegerv(GL_BLEND_SRC_RGB, &s.blend_src_rgb);
    glGetIntegerv(GL_BLEND_DST_RGB, &s.blend_dst_rgb);
    glGetIntegerv(GL_BLEND_SRC_ALPHA, &s.blend_src_alpha);
    glGetIntegerv(GL_BLEND_DST_ALPHA, &s.blend_dst_alpha);
    glGetIntegerv(GL_BLEND_EQUATION_RGB, &s.blend_eq_rgb);
    glGetIntegerv(GL_BLEND_EQUATION_ALPHA, &s.blend_eq_alpha);
    glGetIntegerv(GL_CURRENT_PROGRAM, &s.program);
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &s.framebuffer);
    s.units = d.caps->texture_units < kMaxUnits ? d.caps->texture_units : kMaxUnits;
    for (int u = 0; u < s.units; ++u) {
        glActiveTexture(GL_TEXTURE0 + u);
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &s.bindings[u]);
    }
    for (GLuint a = 0; a < kAttribs; ++a) {
        AttribState& t = s.attrib[a];
        glGetVertexAttribiv(a, GL_VERTEX_ATTRIB_ARRAY_ENABLED, &t.enabled);
        glGetVertexAttribiv(a, GL_VERTEX_ATTRIB_ARRAY_SIZE, &t.size);
        glGetVertexAttribiv(a, GL_VERTEX_ATTRIB_ARRAY_TYPE, &t.type);
        glGetVertexAttribiv(a, GL_VERTEX_ATTRIB_ARRAY_NORMALIZED, &t.normalized);
        glGetVertexAttribiv(a, GL_VERTEX_ATTRIB_ARRAY_STRIDE, &t.stride);
        glGetVertexAttribiv(a, GL_VERTEX_ATTRIB_ARRAY_BUFFER_BINDING, &t.buffer);
        glGetVertexAttribPointerv(a, GL_VERTEX_ATTRIB_ARRAY_POINTER, &t.pointer);
        glGetVertexAttribfv(a, GL_CURRENT_VERTEX_ATTRIB, t.current);
    }
    if (material_fbo) glBindFramebuffer(GL_FRAMEBUFFER, material_fbo);
    begin_core_frame(d);
}

void gles2_frame_end(const sepal_caps&, const void* in) {
    const Gles2Saved& s = *static_cast<const Gles2Saved*>(in);
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)s.framebuffer);
    glBlendFuncSeparate((GLenum)s.blend_src_rgb, (GLenum)s.blend_dst_rgb, (GLenum)s.blend_src_alpha,
                        (GLenum)s.blend_dst_alpha);
    glBlendEquationSeparate((GLenum)s.blend_eq_rgb, (GLenum)s.blend_eq_alpha);
    for (int u = 0; u < s.units; ++u) bind_texture(GL_TEXTURE0 + u, (GLuint)s.bindings[u]);
    for (GLuint a = 0; a < kAttribs; ++a) {
        const AttribState& t = s.attrib[a];
        glBindBuffer(GL_ARRAY_BUFFER, (GLuint)t.buffer);
        glVertexAttribPointer(a, t.size, (GLenum)t.type, (GLboolean)t.normalized, t.stride, t.pointer);
        t.enabled ? glEnableVertexAttribArray(a) : glDisableVertexAttribArray(a);
        glVertexAttrib4fv(a, t.current);
    }
    glUseProgram((GLuint)s.program);
    restore_core_state(s.core);
}

void gles2_background(const srt::Material* m, const float bg[3], sepal_draw_stats* stats) {
    // A quad at the far plane passes LEQUAL only where no surface is.
    if (!(bg[0] > 0.0f || bg[1] > 0.0f || bg[2] > 0.0f)) return;
    const float color[4] = {bg[0], bg[1], bg[2], 1.0f};
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    viewport_quad(m, 1.0f, color, 0, 0.0f, 0.0f);
    ++stats->fullscreen_passes;
}

void gles2_show_float(const srt::Material* m, const void* saved, int width, int height, sepal_draw_stats* stats) {
    // The float frame in the framebuffer bound at begin (8-bit there: clamped at 1).
    static const float kWhite[4] = {1, 1, 1, 1};
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint) static_cast<const Gles2Saved*>(saved)->framebuffer);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    viewport_quad(m, 0.0f, kWhite, m->float_color, (float)width / (float)m->max_width,
                  (float)height / (float)m->max_height);
    ++stats->fullscreen_passes;
}

}  // namespace srt

extern "C" sepal_result sepal_read_float(const sepal_material* material, int width, int height, float* rgba, int* nonfinite_clamped,
                                     sepal_error* err) {
    const srt::Material* m = srt::material(material);
    if (nonfinite_clamped) *nonfinite_clamped = 0;
    if (!m || !rgba) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "read_float: NULL argument");
    if (!m->float_fbo) return srt::fail(err, SEPAL_ERR_UNSUPPORTED, "read_float: the material has no float target");
    if (width < 1 || height < 1 || width > m->max_width || height > m->max_height)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "read_float: %dx%d outside the target", width, height);
    GLint previous = 0;
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &previous);
    glBindFramebuffer(GL_FRAMEBUFFER, m->float_fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, rgba);
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)previous);
    // A radiance over 65504 (a light of 1e12, say) is inf in a half-float target.
    const size_t values = (size_t)width * (size_t)height * 4;
    int clamped = 0;
    for (size_t i = 0; i < values; ++i)
        if (!(fabsf(rgba[i]) <= 65504.0f)) {
            rgba[i] = isnan(rgba[i]) ? 0.0f : rgba[i] > 0.0f ? 65504.0f : -65504.0f;
            ++clamped;
        }
    if (nonfinite_clamped) *nonfinite_clamped = clamped;
    return srt::gl_check("read_float", err);
}
