// The GL ES 1.1 fixed-function executor of a material's pass plan (see sepal_material.h).
#include <GLES/gl.h>
#include <GLES/glext.h>
#include <math.h>
#include <string.h>

#include "internal.h"
#include "sepal/sepal_material.h"
#include "draw_internal.h"
#include "gles1_util.h"
#include "gl_clear.h"
#include "vertex_setup.h"

namespace {

using srt::quad_indices;

constexpr GLenum kFuncAdd = 0x8006;             // GL_FUNC_ADD(_OES)
constexpr GLenum kFuncSubtract = 0x800A;        // GL_FUNC_SUBTRACT(_OES): src - dst
constexpr GLenum kFuncReverseSubtract = 0x800B;  // GL_FUNC_REVERSE_SUBTRACT(_OES): dst - src

struct Frame {
    const srt::Material* m;
    const srt::MeshView* mesh;
    const sepal_scene* scene;
    float* scratch;
    int width, height;
    int x0, y0;  // the viewport's corner (where the single-unit path copies from)
    const float* mvp;  // clip from object: the single-unit path's screen coordinates
    float exposure;
    sepal_draw_stats* stats;
    bool acc_valid;  // single-unit path: the copy texture holds the running sum
    int bad_vertices;  // > 0: triangles touching one are skipped
    GLuint diffuse_texture;  // non-zero: multiplies each pass in its first stage (unit 0)
    bool lays_depth;  // this pass writes depth (LESS) and replaces colour: no pre-pass drawn
    // The texture environment last set on units 0..2 this frame (set_env_modulate skips what
    // is already so: the passes of a plan share their combiner set-up). Unknown at the start
    // of a frame: whatever ran between frames may have changed it.
    struct Env {
        bool valid;
        GLenum arg0, arg1;
        GLint scale;
    } env[3];
};

// The object's positions (object space: GL moves them with the modelview) and UVs, read in
// place from its mesh or the engine's arrays.
const float* pos(const Frame& f) { return f.mesh->position(0); }
GLsizei pos_stride(const Frame& f) { return (GLsizei)f.mesh->stride[srt::MeshView::kPosition]; }
const float* uv(const Frame& f) { return f.mesh->element(srt::MeshView::kUv, 0); }
GLsizei uv_stride(const Frame& f) { return (GLsizei)f.mesh->stride[srt::MeshView::kUv]; }

void set_equation(const srt::Material* m, GLenum eq) {
    // Without the extension only GL_FUNC_ADD exists, which is GL's fixed behaviour.
    if (m->caps.blend_equation) m->caps.blend_equation(eq);
}

void bind_unit(GLenum unit, GLuint texture, const float* uv, GLsizei stride = 0) {
    glActiveTexture(unit);
    glClientActiveTexture(unit);
    if (texture) {
        glEnable(GL_TEXTURE_2D);
        glBindTexture(GL_TEXTURE_2D, texture);
        glEnableClientState(GL_TEXTURE_COORD_ARRAY);
        glTexCoordPointer(2, GL_FLOAT, stride, uv);
    } else {
        glDisable(GL_TEXTURE_2D);
        glDisableClientState(GL_TEXTURE_COORD_ARRAY);
    }
}

// texture env of `unit` (the active one): out = arg0 (x arg1) times scale, RGB; alpha passes
// through.
void set_env_modulate(Frame& f, GLenum unit, GLenum arg0, GLenum arg1, GLint scale) {
    Frame::Env& e = f.env[unit - GL_TEXTURE0];
    if (e.valid && e.arg0 == arg0 && e.arg1 == arg1) {
        if (e.scale != scale) glTexEnvi(GL_TEXTURE_ENV, GL_RGB_SCALE, scale);
        e.scale = scale;
        return;
    }
    e = {true, arg0, arg1, scale};
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_COMBINE);
    glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_RGB, arg1 ? GL_MODULATE : GL_REPLACE);
    glTexEnvi(GL_TEXTURE_ENV, GL_SRC0_RGB, (GLint)arg0);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND0_RGB, GL_SRC_COLOR);
    if (arg1) {
        glTexEnvi(GL_TEXTURE_ENV, GL_SRC1_RGB, (GLint)arg1);
        glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND1_RGB, GL_SRC_COLOR);
    }
    glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_ALPHA, GL_REPLACE);
    glTexEnvi(GL_TEXTURE_ENV, GL_SRC0_ALPHA, GL_PRIMARY_COLOR);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND0_ALPHA, GL_SRC_ALPHA);
    glTexEnvi(GL_TEXTURE_ENV, GL_RGB_SCALE, scale);
}

const float* factor_uv(const Frame& f, uint16_t tex, int light) {
    const int n = f.mesh->vertex_count;
    return f.m->texture_role[tex] == SEPAL_ROLE_G ? srt::light_g_uv(f.scratch, n, light)
                                                 : srt::light_h_uv(f.scratch, n, light);
}

void mesh_arrays(const Frame& f, bool colors) {
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(3, GL_FLOAT, pos_stride(f), pos(f));
    if (colors) {
        glEnableClientState(GL_COLOR_ARRAY);
        glColorPointer(4, GL_FLOAT, 0, srt::pass_colors(f.scratch, f.mesh->vertex_count, f.scene->light_count));
    } else {
        glDisableClientState(GL_COLOR_ARRAY);
        glColor4f(1, 1, 1, 1);
    }
}

// One mesh pass: the whole index list, or the runs of it without bad vertices.
void draw_mesh(const Frame& f) {
    srt::for_each_drawable_run(*f.mesh, f.bad_vertices, [&f](int first, int count) {
        glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_SHORT, f.mesh->indices + first);
    });
    ++f.stats->draw_calls;
}

// A viewport-sized texture (width x height texels, a power of two at least the viewport) on
// unit 0, read at each pixel's own texel. Projective coordinates: the texture matrix maps the
// object-space position to (s q, t q, 0, q) with q the clip w, so s and t are the pixel's
// position in the texture (texel centres on pixel centres; it is nearest-sampled).
// reset_texture_matrix undoes the matrix after the draw.
void bind_screen_texture(const Frame& f, GLuint texture, int width, int height) {
    const float sx = 0.5f * (float)f.width / (float)width;
    const float sy = 0.5f * (float)f.height / (float)height;
    const float screen[16] = {sx, 0, 0, 0, 0, sy, 0, 0, 0, 0, 0, 0, sx, sy, 0, 1};
    float tm[16];
    srt::mat4_mul(screen, f.mvp, tm);
    bind_unit(GL_TEXTURE0, texture, pos(f), pos_stride(f));
    glTexCoordPointer(3, GL_FLOAT, pos_stride(f), pos(f));
    glMatrixMode(GL_TEXTURE);
    glLoadMatrixf(tm);
    glMatrixMode(GL_MODELVIEW);
}

void reset_texture_matrix() {
    glMatrixMode(GL_TEXTURE);
    glLoadIdentity();
    glMatrixMode(GL_MODELVIEW);
}

// A framebuffer-wide operation restricted to the object's visible pixels: its mesh with
// depth EQUAL (after the depth is laid), in a constant colour, optionally textured with the
// copy texture at the pixel's own position (the single-unit path's running sum). Counted
// with the full-screen passes it replaces.
void object_pass(Frame& f, bool textured, const float color[4]) {
    glDisableClientState(GL_COLOR_ARRAY);
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(3, GL_FLOAT, pos_stride(f), pos(f));
    glColor4f(color[0], color[1], color[2], color[3]);
    bind_unit(GL_TEXTURE1, 0, nullptr);
    if (textured) {
        bind_screen_texture(f, f.m->copy_texture, f.m->copy_width, f.m->copy_height);
        set_env_modulate(f, GL_TEXTURE0, GL_TEXTURE, 0, 1);
    } else {
        bind_unit(GL_TEXTURE0, 0, nullptr);
    }
    srt::for_each_drawable_run(*f.mesh, f.bad_vertices, [&f](int first, int count) {
        glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_SHORT, f.mesh->indices + first);
    });
    if (textured) reset_texture_matrix();
    ++f.stats->fullscreen_passes;
}

// Passes send colour / boost and scale by 4 in their last combiner stage (GL_RGB_SCALE
// accepts 1, 2 or 4): vertex colours stay below 1 at a 4x higher exposure.
float color_boost(const Frame& f, const sepal_fmt_pass& pass) {
    return srt::pass_color_boost(pass, f.m->texture_count);
}

// An untextured pass's combiner stage: unit 0 enabled with any complete texture (never
// sampled: the stage replaces by the primary colour) so that GL_RGB_SCALE applies.
void untextured_stage(Frame& f, const sepal_fmt_pass& pass) {
    bind_unit(GL_TEXTURE1, 0, nullptr);
    if (f.m->texture_count == 0) {
        bind_unit(GL_TEXTURE0, 0, nullptr);
        return;
    }
    glActiveTexture(GL_TEXTURE0);
    glClientActiveTexture(GL_TEXTURE0);
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, f.m->gl_textures[0]);
    glDisableClientState(GL_TEXTURE_COORD_ARRAY);
    set_env_modulate(f, GL_TEXTURE0, GL_PRIMARY_COLOR, 0, (GLint)(pass.rgb_scale * color_boost(f, pass)));
}

// Fills the colour array for one pass and light: pass colour x irradiance x exposure.
void fill_colors(const Frame& f, const sepal_fmt_pass& pass, int light) {
    const int n = f.mesh->vertex_count;
    srt::fill_pass_colors(f.m->info, pass, srt::pass_inputs(f.m, f.scratch, n, f.scene->light_count, light),
                          f.exposure / color_boost(f, pass), n, srt::pass_colors(f.scratch, n, f.scene->light_count));
}

// Two texture units: tex0 x tex1 x colour, added or subtracted by blending. With a
// per-pass diffuse map: colour x map (unit 0, the mesh's UVs), then the pass's textures on
// units 1 and 2; the scale in the last stage, so no stage before it exceeds 1 (each factor
// is at most 1) and the last clamps only what is white on screen anyway.
void pass_multitexture(Frame& f, const sepal_fmt_pass& pass, int light, bool inverted) {
    const GLint scale = (GLint)(pass.rgb_scale * color_boost(f, pass));
    const int textures = srt::pass_texture_count(pass);
    mesh_arrays(f, true);
    if (f.diffuse_texture) {
        bind_unit(GL_TEXTURE0, f.diffuse_texture, uv(f), uv_stride(f));
        set_env_modulate(f, GL_TEXTURE0, GL_PRIMARY_COLOR, GL_TEXTURE, textures == 0 ? scale : 1);
        bind_unit(GL_TEXTURE1, textures >= 1 ? f.m->gl_textures[pass.tex0] : 0,
                  textures >= 1 ? factor_uv(f, pass.tex0, light) : nullptr);
        if (textures >= 1) set_env_modulate(f, GL_TEXTURE1, GL_PREVIOUS, GL_TEXTURE, textures == 1 ? scale : 1);
        bind_unit(GL_TEXTURE2, textures == 2 ? f.m->gl_textures[pass.tex1] : 0,
                  textures == 2 ? factor_uv(f, pass.tex1, light) : nullptr);
        if (textures == 2) set_env_modulate(f, GL_TEXTURE2, GL_PREVIOUS, GL_TEXTURE, scale);
    } else if (textures == 0) {
        untextured_stage(f, pass);
    } else {
        bind_unit(GL_TEXTURE0, f.m->gl_textures[pass.tex0], factor_uv(f, pass.tex0, light));
        set_env_modulate(f, GL_TEXTURE0, GL_PRIMARY_COLOR, GL_TEXTURE, pass.op == SEPAL_OP_TEXTURE ? scale : 1);
        // A reciprocal pass's third factor is in its vertex colour (fill_colors).
        if (srt::pass_texture_count(pass) == 2) {
            bind_unit(GL_TEXTURE1, f.m->gl_textures[pass.tex1], factor_uv(f, pass.tex1, light));
            set_env_modulate(f, GL_TEXTURE1, GL_PREVIOUS, GL_TEXTURE, scale);
        } else {
            bind_unit(GL_TEXTURE1, 0, nullptr);
        }
    }
    // Laying depth: the nearest fragment's colour replaces an occluded one's, which is what
    // adding it to the cleared framebuffer gives.
    if (f.lays_depth) glDisable(GL_BLEND);
    else glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    // Subtracting: dst - src with the extension; in the inverted framebuffer, an add.
    const bool subtract = pass.blend == SEPAL_BLEND_SUBTRACT && !inverted;
    set_equation(f.m, subtract ? kFuncReverseSubtract : kFuncAdd);
    draw_mesh(f);
    set_equation(f.m, kFuncAdd);
    if (f.lays_depth) {  // laid: every later pass tests against it, as after a pre-pass
        f.lays_depth = false;
        glDepthMask(GL_FALSE);
        glDepthFunc(GL_EQUAL);
    }
    // Every other draw here uses units 0 and 1 only.
    if (f.diffuse_texture) bind_unit(GL_TEXTURE2, 0, nullptr);
}

void copy_to_accumulator(Frame& f) {
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, f.m->copy_texture);
    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, f.x0, f.y0, f.width, f.height);
    ++f.stats->copies;
    f.acc_valid = true;
}

// One texture unit (Kautz-McCool's two passes per product): the pass's contribution P is
// drawn alone into the colour buffer, the running sum (copy texture) is blended onto it,
// and the result is copied back.
void pass_single_unit(Frame& f, const sepal_fmt_pass& pass, int light, bool inverted) {
    static const float kWhite[4] = {1, 1, 1, 1};
    // Drawn with blending off, P replaces what the object's pixels held (the running sum
    // is in the copy texture); no other pixel is touched.
    glDisable(GL_BLEND);
    bind_unit(GL_TEXTURE1, 0, nullptr);
    if (srt::pass_texture_count(pass) == 2) {
        // The second factor first, alone: its 8-bit texels land in the framebuffer
        // exactly. Then first factor x colour through a multiplicative blend: the product
        // is rounded once, as on the two-unit path (colour x G first would round the
        // small intermediate G x colour to 8 bits and lose several levels).
        mesh_arrays(f, false);
        bind_unit(GL_TEXTURE0, f.m->gl_textures[pass.tex1], factor_uv(f, pass.tex1, light));
        set_env_modulate(f, GL_TEXTURE0, GL_TEXTURE, 0, 1);
        draw_mesh(f);
        glEnable(GL_BLEND);
        glBlendFunc(GL_DST_COLOR, GL_ZERO);
    }
    mesh_arrays(f, true);
    if (srt::pass_texture_count(pass) == 0) {
        untextured_stage(f, pass);
    } else {
        bind_unit(GL_TEXTURE0, f.m->gl_textures[pass.tex0], factor_uv(f, pass.tex0, light));
        set_env_modulate(f, GL_TEXTURE0, GL_PRIMARY_COLOR, GL_TEXTURE, (GLint)(pass.rgb_scale * color_boost(f, pass)));
    }
    draw_mesh(f);
    if (f.acc_valid) {
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
        const bool subtract = pass.blend == SEPAL_BLEND_SUBTRACT && !inverted;
        set_equation(f.m, subtract ? kFuncSubtract : kFuncAdd);  // acc - P, or acc + P
        object_pass(f, true, kWhite);
        set_equation(f.m, kFuncAdd);
    }
    copy_to_accumulator(f);
}

// Scale up: each pass over the object with blend (GL_DST_COLOR, GL_ONE) doubles its pixels.
void doublings(Frame& f, int n) {
    static const float kWhite[4] = {1, 1, 1, 1};
    glEnable(GL_BLEND);
    glBlendFunc(GL_DST_COLOR, GL_ONE);
    for (int i = 0; i < n; ++i) object_pass(f, false, kWhite);
}

// The object's pixels = 1 - themselves (and the running sum with them, on the single-unit
// path).
void invert(Frame& f) {
    static const float kWhite[4] = {1, 1, 1, 1};
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE_MINUS_DST_COLOR, GL_ZERO);
    object_pass(f, false, kWhite);
    if (f.m->single_unit) copy_to_accumulator(f);
}

// framebuffer *= the diffuse map at the mesh's UVs (nothing without one).
void diffuse_map(Frame& f, const sepal_draw_desc* d) {
    if (!d->diffuse_texture) return;
    glDepthFunc(GL_EQUAL);
    glEnable(GL_BLEND);
    glBlendFunc(GL_DST_COLOR, GL_ZERO);
    mesh_arrays(f, false);
    bind_unit(GL_TEXTURE1, 0, nullptr);
    glActiveTexture(GL_TEXTURE0);
    glClientActiveTexture(GL_TEXTURE0);
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, d->diffuse_texture);
    glEnableClientState(GL_TEXTURE_COORD_ARRAY);
    glTexCoordPointer(2, GL_FLOAT, uv_stride(f), uv(f));
    set_env_modulate(f, GL_TEXTURE0, GL_TEXTURE, 0, 1);
    draw_mesh(f);
}

// The accumulated sum written to the framebuffer bound at the draw: the object's mesh
// (depth LESS, as the pre-pass lays it, so what the engine drew in front still hides it),
// each pixel reading its own texel of the 8-bit sum (bind_screen_texture) times
// srt::write_scale (the vertex colour), plus srt::write_bias on the second unit, so that the
// framebuffer's truncation to n bits rounds to nearest. Replaces what the pixel held, as the
// first pass did.
void write_accumulated(Frame& f) {
    const srt::Material* m = f.m;
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glDisable(GL_BLEND);
    glDisableClientState(GL_COLOR_ARRAY);
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(3, GL_FLOAT, pos_stride(f), pos(f));
    glColor4f(srt::write_scale(m->caps.red_bits), srt::write_scale(m->caps.green_bits),
              srt::write_scale(m->caps.blue_bits), 1.0f);
    bind_screen_texture(f, m->acc_color, m->acc_width, m->acc_height);
    set_env_modulate(f, GL_TEXTURE0, GL_TEXTURE, GL_PRIMARY_COLOR, 1);
    // Unit 1 adds the constant; its texture is bound only so that the stage runs.
    glActiveTexture(GL_TEXTURE1);
    glClientActiveTexture(GL_TEXTURE1);
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, m->acc_color);
    glDisableClientState(GL_TEXTURE_COORD_ARRAY);
    const GLfloat bias[4] = {srt::write_bias(m->caps.red_bits), srt::write_bias(m->caps.green_bits),
                             srt::write_bias(m->caps.blue_bits), 0.0f};
    glTexEnvfv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, bias);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_COMBINE);
    glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_RGB, GL_ADD);
    glTexEnvi(GL_TEXTURE_ENV, GL_SRC0_RGB, GL_PREVIOUS);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND0_RGB, GL_SRC_COLOR);
    glTexEnvi(GL_TEXTURE_ENV, GL_SRC1_RGB, GL_CONSTANT);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND1_RGB, GL_SRC_COLOR);
    glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_ALPHA, GL_REPLACE);
    glTexEnvi(GL_TEXTURE_ENV, GL_SRC0_ALPHA, GL_PREVIOUS);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND0_ALPHA, GL_SRC_ALPHA);
    glTexEnvi(GL_TEXTURE_ENV, GL_RGB_SCALE, 1);
    f.env[1].valid = false;
    draw_mesh(f);
    // bind_screen_texture's matrix is unit 0's: left there, the frame's next object would
    // read its factors through it.
    glActiveTexture(GL_TEXTURE0);
    reset_texture_matrix();
    bind_unit(GL_TEXTURE1, 0, nullptr);
}

sepal_result draw_passes(const sepal_draw_desc* d, const srt::FramePrep& prep, sepal_draw_stats* stats, sepal_error* err,
                         Frame* out);

}  // namespace

namespace srt {

sepal_result draw_gles1(const sepal_draw_desc* d, const FramePrep& prep, sepal_draw_stats* stats, sepal_error* err) {
    const srt::Material* m = srt::material(d->material);
    if (!m->acc_fbo) return draw_passes(d, prep, stats, err, nullptr);
    // Framebuffers with fewer bits: the passes go to the 8-bit target, at the same size and
    // with the same matrices; then one write to the framebuffer bound now.
    const srt::SumTarget target = srt::enter_sum_target(m);
    Frame f;
    const sepal_result r = draw_passes(d, prep, stats, err, &f);
    srt::leave_sum_target(m, target);
    if (r != SEPAL_OK) return r;
    float mvp[16];  // f.mvp pointed into draw_passes' frame
    srt::mat4_mul(prep.proj, prep.view, mvp);
    f.mvp = mvp;
    write_accumulated(f);
    return srt::gl_check("the accumulated sum's write", err);
}

}  // namespace srt

namespace {

sepal_result draw_passes(const sepal_draw_desc* d, const srt::FramePrep& prep, sepal_draw_stats* stats, sepal_error* err,
                         Frame* out) {
    const srt::Material* m = srt::material(d->material);
    sepal_result r;
    float mvp[16];
    srt::mat4_mul(prep.proj, prep.view, mvp);
    GLint viewport[4];
    glGetIntegerv(GL_VIEWPORT, viewport);
    Frame f = {m, &prep.mesh, d->scene, d->scratch, d->width, d->height, viewport[0], viewport[1], mvp,
               prep.exposure, stats, false, prep.vertices.bad_vertices,
               prep.diffuse_per_pass ? (GLuint)d->diffuse_texture : 0u, false, {}};
    // The frame's begin set what every object shares (gles1_frame_begin); this object's
    // matrices and depth set-up here.
    glMatrixMode(GL_PROJECTION);
    glLoadMatrixf(prep.proj);
    glMatrixMode(GL_MODELVIEW);
    glLoadMatrixf(prep.view);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glDisable(GL_BLEND);
    bind_unit(GL_TEXTURE1, 0, nullptr);
    bind_unit(GL_TEXTURE0, 0, nullptr);
    srt::Gles1Step steps[srt::kMaxGles1Steps];  // ~12 KB of stack
    const int step_count = srt::gles1_schedule(m, prep, stats->doublings, steps);
    // Later passes test EQUAL, so each pixel's front surface is shaded once, and only the
    // object's visible pixels are touched. The depth they test comes from the first plan
    // pass when it adds on two units (drawn with LESS, depth writes and no blending, so it
    // replaces what the pixel held: f.lays_depth), else from a pre-pass in black (LESS,
    // no blending): the object's pixels start from 0 whatever the framebuffer held, as the
    // single-unit path's first pass, a subtract or an inversion need. Folding saves a
    // mesh pass per object.
    f.lays_depth = !m->single_unit && d->scene->light_count > 0 && step_count > 0 &&
                   steps[0].kind == srt::Gles1Step::kPass && !steps[0].inverted &&
                   m->passes[steps[0].pass].blend != SEPAL_BLEND_SUBTRACT;
    if (!f.lays_depth) {
        mesh_arrays(f, false);
        glColor4f(0, 0, 0, 0);
        draw_mesh(f);
        glDepthMask(GL_FALSE);
        glDepthFunc(GL_EQUAL);
        if ((r = srt::gl_check("depth pre-pass", err)) != SEPAL_OK) return r;
    }

    // Diffuse map (Fig. 13; a tree's blend maps): one more mesh pass multiplying the
    // framebuffer by the texture at the mesh's UVs, before the final doublings: there the
    // image is at the plan's exposure, so a highlight above 1 is still held (v 2^-k <= 1)
    // and comes out as v x w. After them it would be clipped at 1 first (a tree's shiny basis
    // under a blend weight < 1: docs/ist.md), at the price of the multiply's rounding doubled
    // k times.
    const int final_doubling =
        step_count > 0 && steps[step_count - 1].kind == srt::Gles1Step::kDouble ? step_count - 1 : step_count;
    for (int i = 0; i < step_count; ++i) {
        const srt::Gles1Step& step = steps[i];
        if (i == final_doubling && !prep.diffuse_per_pass) diffuse_map(f, d);
        if (step.kind == srt::Gles1Step::kDouble) {
            doublings(f, step.count);
            if (i + 1 < step_count && m->single_unit) copy_to_accumulator(f);  // the running sum, doubled
            continue;
        }
        if (step.kind == srt::Gles1Step::kInvert) {
            invert(f);
            continue;
        }
        const sepal_fmt_pass& pass = m->passes[step.pass];
        f.exposure = step.exposure;
        for (int l = 0; l < d->scene->light_count; ++l) {
            fill_colors(f, pass, l);
            if (m->single_unit)
                pass_single_unit(f, pass, l, step.inverted);
            else
                pass_multitexture(f, pass, l, step.inverted);
            if ((r = srt::gl_check("a plan pass", err)) != SEPAL_OK) return r;
        }
    }
    if (final_doubling == step_count && !prep.diffuse_per_pass) diffuse_map(f, d);
    if (out) *out = f;
    return srt::gl_check("the object's passes", err);
}

}  // namespace

extern "C" sepal_result sepal_texture_create_rgba8(const uint8_t* rgba, int width, int height, uint32_t* out,
                                               sepal_error* err) {
    if (!rgba || !out || width < 1 || height < 1 || (width & (width - 1)) || (height & (height - 1)))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "texture: NULL pixels or %dx%d is not a power-of-two size", width, height);
    GLuint name = 0;
    glGenTextures(1, &name);
    glBindTexture(GL_TEXTURE_2D, name);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexParameteri(GL_TEXTURE_2D, GL_GENERATE_MIPMAP, GL_TRUE);  // core in GL ES 1.1
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    sepal_result r = srt::gl_check("diffuse texture upload", err);
    if (r != SEPAL_OK) {
        glDeleteTextures(1, &name);
        return r;
    }
    *out = name;
    return srt::ok(err);
}

extern "C" void sepal_texture_destroy(uint32_t texture) {
    if (texture) glDeleteTextures(1, &texture);
}

// ---- the frame's GL state (sepal_frame.h's contract) ------------------------------------
namespace {

constexpr GLenum kBlendEquationQuery = 0x8009;  // GL_BLEND_EQUATION_OES
constexpr int kUnits = 3;                        // units 0..2: the passes' and the map's

struct ArrayState {
    GLint enabled, size, type, stride, buffer;
    void* pointer;
};

struct Gles1Saved {
    srt::CoreGlState core;
    GLboolean enables[6];
    GLint blend_src, blend_dst, blend_eq, shade_model, matrix_mode, client_unit, units;
    GLfloat current_color[4];
    GLfloat projection[16], modelview[16];
    struct Unit {
        GLboolean texture_2d;
        GLint binding;
        GLint env[11];
        GLfloat texture_matrix[16];
        ArrayState coords;
    } unit[kUnits];
    ArrayState vertex, color, normal;
};
static_assert(sizeof(Gles1Saved) <= srt::kSavedStateBytes, "sepal_frame.saved is too small");

// Beyond the enables both versions have (gl_clear.h).
const GLenum kEnables[6] = {GL_LIGHTING, GL_ALPHA_TEST, GL_FOG, GL_COLOR_LOGIC_OP, GL_COLOR_MATERIAL, GL_NORMALIZE};
const GLenum kEnvParams[11] = {GL_TEXTURE_ENV_MODE, GL_COMBINE_RGB,   GL_COMBINE_ALPHA, GL_SRC0_RGB,
                               GL_SRC1_RGB,         GL_SRC0_ALPHA,    GL_OPERAND0_RGB,  GL_OPERAND1_RGB,
                               GL_OPERAND0_ALPHA,   GL_RGB_SCALE,     GL_ALPHA_SCALE};

void save_array(GLenum array, GLenum size, GLenum type, GLenum stride, GLenum buffer, GLenum pointer, ArrayState* a) {
    a->enabled = glIsEnabled(array);
    glGetIntegerv(size, &a->size);
    glGetIntegerv(type, &a->type);
    glGetIntegerv(stride, &a->stride);
    glGetIntegerv(buffer, &a->buffer);
    glGetPointerv(pointer, &a->pointer);
}

template <class SetPointer>
void restore_array(GLenum array, const ArrayState& a, SetPointer set) {
    glBindBuffer(GL_ARRAY_BUFFER, (GLuint)a.buffer);
    set(a);
    a.enabled ? glEnableClientState(array) : glDisableClientState(array);
}

}  // namespace

namespace srt {

void gles1_frame_begin(const sepal_frame_desc& d, void* out) {
    Gles1Saved& s = *static_cast<Gles1Saved*>(out);
    memset(&s, 0, sizeof s);
    save_core_state(&s.core);
    for (int i = 0; i < 6; ++i) s.enables[i] = glIsEnabled(kEnables[i]);
    glGetIntegerv(GL_BLEND_SRC, &s.blend_src);
    glGetIntegerv(GL_BLEND_DST, &s.blend_dst);
    if (d.caps->blend_equation) glGetIntegerv(kBlendEquationQuery, &s.blend_eq);
    glGetIntegerv(GL_SHADE_MODEL, &s.shade_model);
    glGetIntegerv(GL_MATRIX_MODE, &s.matrix_mode);
    glGetIntegerv(GL_CLIENT_ACTIVE_TEXTURE, &s.client_unit);
    glGetFloatv(GL_CURRENT_COLOR, s.current_color);
    glGetFloatv(GL_PROJECTION_MATRIX, s.projection);
    glGetFloatv(GL_MODELVIEW_MATRIX, s.modelview);
    // The context's units, not the caps' (a mask may hide some; the draws still switch
    // units 0 and 1 off).
    GLint units = 0;
    glGetIntegerv(GL_MAX_TEXTURE_UNITS, &units);
    s.units = units < kUnits ? units : kUnits;
    for (int u = 0; u < s.units; ++u) {
        Gles1Saved::Unit& t = s.unit[u];
        glActiveTexture(GL_TEXTURE0 + u);
        glClientActiveTexture(GL_TEXTURE0 + u);
        t.texture_2d = glIsEnabled(GL_TEXTURE_2D);
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &t.binding);
        for (int k = 0; k < 11; ++k) glGetTexEnviv(GL_TEXTURE_ENV, kEnvParams[k], &t.env[k]);
        glGetFloatv(GL_TEXTURE_MATRIX, t.texture_matrix);
        save_array(GL_TEXTURE_COORD_ARRAY, GL_TEXTURE_COORD_ARRAY_SIZE, GL_TEXTURE_COORD_ARRAY_TYPE,
                   GL_TEXTURE_COORD_ARRAY_STRIDE, GL_TEXTURE_COORD_ARRAY_BUFFER_BINDING, GL_TEXTURE_COORD_ARRAY_POINTER,
                   &t.coords);
    }
    save_array(GL_VERTEX_ARRAY, GL_VERTEX_ARRAY_SIZE, GL_VERTEX_ARRAY_TYPE, GL_VERTEX_ARRAY_STRIDE,
               GL_VERTEX_ARRAY_BUFFER_BINDING, GL_VERTEX_ARRAY_POINTER, &s.vertex);
    save_array(GL_COLOR_ARRAY, GL_COLOR_ARRAY_SIZE, GL_COLOR_ARRAY_TYPE, GL_COLOR_ARRAY_STRIDE,
               GL_COLOR_ARRAY_BUFFER_BINDING, GL_COLOR_ARRAY_POINTER, &s.color);
    s.normal.enabled = glIsEnabled(GL_NORMAL_ARRAY);
    glGetIntegerv(GL_NORMAL_ARRAY_TYPE, &s.normal.type);
    glGetIntegerv(GL_NORMAL_ARRAY_STRIDE, &s.normal.stride);
    glGetIntegerv(GL_NORMAL_ARRAY_BUFFER_BINDING, &s.normal.buffer);
    glGetPointerv(GL_NORMAL_ARRAY_POINTER, &s.normal.pointer);
    begin_core_frame(d);
    // Arrays the passes do not use but a draw would still read: an application's normal or
    // texture-coordinate array left enabled over a pointer that is no longer valid crashes
    // a driver that fetches it (NVIDIA does, with lighting off; Mesa skips it).
    glDisableClientState(GL_NORMAL_ARRAY);
    for (int u = 0; u < s.units; ++u) {
        glClientActiveTexture(GL_TEXTURE0 + u);
        glDisableClientState(GL_TEXTURE_COORD_ARRAY);
    }
    glClientActiveTexture(GL_TEXTURE0);
    // Fixed-function stages an application may leave on would change every pass.
    for (int i = 0; i < 6; ++i) glDisable(kEnables[i]);
    glShadeModel(GL_SMOOTH);
    for (int u = 0; u < s.units; ++u) {
        glActiveTexture(GL_TEXTURE0 + u);
        glMatrixMode(GL_TEXTURE);
        glLoadIdentity();
    }
    glMatrixMode(GL_MODELVIEW);
}

void gles1_frame_end(const sepal_caps& caps, const void* in) {
    const Gles1Saved& s = *static_cast<const Gles1Saved*>(in);
    for (int i = 0; i < 6; ++i) set_enable(kEnables[i], s.enables[i]);
    glBlendFunc((GLenum)s.blend_src, (GLenum)s.blend_dst);
    if (caps.blend_equation && s.blend_eq) caps.blend_equation((GLenum)s.blend_eq);
    glShadeModel((GLenum)s.shade_model);
    glColor4f(s.current_color[0], s.current_color[1], s.current_color[2], s.current_color[3]);
    glMatrixMode(GL_PROJECTION);
    glLoadMatrixf(s.projection);
    glMatrixMode(GL_MODELVIEW);
    glLoadMatrixf(s.modelview);
    for (int u = 0; u < s.units; ++u) {
        const Gles1Saved::Unit& t = s.unit[u];
        glActiveTexture(GL_TEXTURE0 + u);
        glClientActiveTexture(GL_TEXTURE0 + u);
        set_enable(GL_TEXTURE_2D, t.texture_2d);
        glBindTexture(GL_TEXTURE_2D, (GLuint)t.binding);
        for (int k = 0; k < 11; ++k) glTexEnvi(GL_TEXTURE_ENV, kEnvParams[k], t.env[k]);
        glMatrixMode(GL_TEXTURE);
        glLoadMatrixf(t.texture_matrix);
        restore_array(GL_TEXTURE_COORD_ARRAY, t.coords,
                      [](const ArrayState& a) { glTexCoordPointer(a.size, (GLenum)a.type, a.stride, a.pointer); });
    }
    glMatrixMode((GLenum)s.matrix_mode);
    restore_array(GL_VERTEX_ARRAY, s.vertex,
                  [](const ArrayState& a) { glVertexPointer(a.size, (GLenum)a.type, a.stride, a.pointer); });
    restore_array(GL_COLOR_ARRAY, s.color,
                  [](const ArrayState& a) { glColorPointer(a.size, (GLenum)a.type, a.stride, a.pointer); });
    restore_array(GL_NORMAL_ARRAY, s.normal,
                  [](const ArrayState& a) { glNormalPointer((GLenum)a.type, a.stride, a.pointer); });
    glClientActiveTexture((GLenum)s.client_unit);
    restore_core_state(s.core);
}

void gles1_background(const float bg[3], sepal_draw_stats* stats) {
    // A quad at the far plane passes LEQUAL only where no surface is.
    if (!(bg[0] > 0.0f || bg[1] > 0.0f || bg[2] > 0.0f)) return;
    const float pos[12] = {-1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1};
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    bind_unit(GL_TEXTURE1, 0, nullptr);
    bind_unit(GL_TEXTURE0, 0, nullptr);
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(3, GL_FLOAT, 0, pos);
    glDisableClientState(GL_COLOR_ARRAY);
    glColor4f(bg[0], bg[1], bg[2], 1.0f);
    glDrawElements(GL_TRIANGLES, 6, GL_UNSIGNED_SHORT, quad_indices());
    ++stats->fullscreen_passes;
}

}  // namespace srt
