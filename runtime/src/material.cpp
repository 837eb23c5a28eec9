// Material creation: validation against the context's capabilities, texture upload.
#include <GLES/gl.h>
#include <string.h>

#include "internal.h"
#include "sepal/sepal_material.h"
#include "draw_internal.h"
#include "vertex_setup.h"

namespace {

// Uploads one texture with all its levels. 16-bit data is rounded to 8 bits row by row
// through a stack buffer (no allocation).
sepal_result upload(const sepal_asset_texture& t, GLuint name, bool wrap, bool mips, sepal_error* err) {
    const sepal_fmt_texture& d = t.desc;
    const GLenum format = d.channels == 1 ? GL_LUMINANCE : GL_RGB;
    glBindTexture(GL_TEXTURE_2D, name);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    uint32_t w = d.width, h = d.height;
    for (uint32_t level = 0; level < d.levels; ++level) {
        const uint8_t* src = t.level_data[level];
        if (d.bits == 8) {
            glTexImage2D(GL_TEXTURE_2D, (GLint)level, (GLint)format, (GLsizei)w, (GLsizei)h, 0, format,
                         GL_UNSIGNED_BYTE, src);
        } else {
            glTexImage2D(GL_TEXTURE_2D, (GLint)level, (GLint)format, (GLsizei)w, (GLsizei)h, 0, format,
                         GL_UNSIGNED_BYTE, nullptr);
            uint8_t row[SEPAL_FMT_MAX_TEXTURE_SIDE * 3];
            const size_t values = (size_t)w * d.channels;
            for (uint32_t y = 0; y < h; ++y) {
                for (size_t i = 0; i < values; ++i) {
                    uint16_t q;
                    memcpy(&q, src + (y * values + i) * 2, 2);
                    row[i] = (uint8_t)((q * 255u + 32767u) / 65535u);
                }
                glTexSubImage2D(GL_TEXTURE_2D, (GLint)level, 0, (GLint)y, (GLsizei)w, 1, format,
                                GL_UNSIGNED_BYTE, row);
            }
        }
        w = w > 1 ? w / 2 : 1;
        h = h > 1 ? h / 2 : 1;
    }
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
                    d.levels > 1 && mips ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    // Factors clamp at the hemisphere's rim; elevation/azimuth's H is periodic in phi.
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap ? GL_REPEAT : GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap ? GL_REPEAT : GL_CLAMP_TO_EDGE);
    return srt::gl_check("texture upload", err);
}

// Largest stored q of a texture, over every level and channel.
float max_q(const sepal_asset_texture& t) {
    const sepal_fmt_texture& d = t.desc;
    uint32_t best = 0;
    for (uint32_t level = 0; level < d.levels; ++level) {
        const uint8_t* p = t.level_data[level];
        const uint32_t values = t.level_bytes[level] / (d.bits / 8);
        for (uint32_t i = 0; i < values; ++i) {
            uint32_t q = p[i];
            if (d.bits == 16) {
                uint16_t v;
                memcpy(&v, p + 2 * i, 2);
                q = v;
            }
            if (q > best) best = q;
        }
    }
    return (float)best / (d.bits == 8 ? 255.0f : 65535.0f);
}

int next_pow2(int v) {
    int p = 1;
    while (p < v) p <<= 1;
    return p;
}

}  // namespace

namespace srt {

sepal_result material_plan(const sepal_caps* caps, const sepal_asset* asset, int max_width, int max_height,
                           srt::Material* out, sepal_error* err) {
    if (!caps || !asset || !out)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "material: NULL argument");
    memset(out, 0, sizeof *out);
    if (!srt::asset_parsed(*asset))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "material: the asset was not filled by sepal_asset_parse");
    if (max_width < 1 || max_height < 1 || max_width > caps->max_texture_size ||
        max_height > caps->max_texture_size)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "material: viewport %dx%d out of 1..%d",
                         max_width, max_height, caps->max_texture_size);
    const sepal_fmt_material& info = asset->material;
    if (caps->gles_version == 1 && !srt::param_per_vertex((sepal_param)info.param))
        return srt::fail(err, SEPAL_ERR_UNSUPPORTED,
                         "material: parameterization %u needs per-pixel evaluation (GL ES 2 or "
                         "CPU); GL ES 1.1 takes iv, gs-half, vh or axis",
                         info.param);
    for (uint32_t i = 0; i < asset->texture_count; ++i) {
        const sepal_fmt_texture& d = asset->textures[i].desc;
        if ((int)d.width > caps->max_texture_size || (int)d.height > caps->max_texture_size)
            return srt::fail(err, SEPAL_ERR_UNSUPPORTED, "material: texture %u is %ux%u, the GPU's limit is %d",
                             i, d.width, d.height, caps->max_texture_size);
    }
    out->caps = *caps;
    out->info = info;
    out->plan = asset->plan;
    memcpy(out->passes, asset->passes, asset->plan.pass_count * sizeof(sepal_fmt_pass));
    out->max_width = max_width;
    out->max_height = max_height;
    for (uint32_t p = 0; p < asset->plan.pass_count; ++p) {
        const sepal_fmt_pass& pass = asset->passes[p];
        // GL ES 1.1 clamps vertex colours at 1: passes send colour / 4 and scale by 4 in
        // the combiner (GL_RGB_SCALE), which buys two doublings of framebuffer precision
        // (internal.h). GL ES 2 attributes are not clamped.
        const float boost = srt::pass_color_boost(pass, asset->texture_count);
        for (int c = 0; c < 3; ++c) {
            const float v = caps->gles_version == 1 ? pass.color[c] / boost : 0.0f;
            if (v > out->pass_need[p]) out->pass_need[p] = v;
        }
        if (pass.blend == SEPAL_BLEND_SUBTRACT) out->has_negative_passes = 1;
        // One texture unit: a product pass forms colour x tex0 (x the combiner's scale)
        // before the blend multiplies it by tex1, and GL clamps that stage at 1: its peak
        // per unit irradiance bounds the exposure too (see sepal_draw).
        if (srt::pass_texture_count(pass) == 2 && caps->gles_version == 1 && caps->texture_units < 2) {
            const float q = max_q(asset->textures[pass.tex0]);
            for (int c = 0; c < 3; ++c) {
                const float v = pass.color[c] * q * (float)pass.rgb_scale;
                if (v > out->pass_need[p]) out->pass_need[p] = v;
            }
        }
        // Adds must come before subtracts so no partial sum clamps at 0 (writer's rule).
        if (pass.blend == SEPAL_BLEND_ADD && p > 0 && asset->passes[p - 1].blend == SEPAL_BLEND_SUBTRACT)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "material: plan adds after subtracting (pass %u); partial sums could clamp", p);
    }
    // GL ES 2 guarantees 8 texture units; the one-unit path exists for GL ES 1.1.
    out->single_unit = caps->gles_version == 1 && caps->texture_units < 2;
    // GL ES 2's fused per-pixel shader also samples the diffuse profile: one unit fewer.
    int group = (caps->texture_units - (asset->diffuse_profile && caps->gles_version == 2 ? 1 : 0)) / 2;
    if (group > 8) group = 8;
    if (group > (int)info.terms) group = (int)info.terms;
    out->fused_group = group > 0 ? group : 1;
    out->subtract_by_inversion = out->has_negative_passes && !caps->has_blend_subtract;
    sepal_profile_check(caps, asset, &out->weaker, nullptr);
    out->texture_count = asset->texture_count;
    if (asset->diffuse_profile) {
        out->diffuse_side = asset->diffuse_side;
        // Decoded once into floats (any layout): the per-vertex colours read it every frame.
        const size_t samples = (size_t)asset->diffuse_side * asset->diffuse_side;
        for (size_t k = 0; k < samples; ++k)
            for (int c = 0; c < 3; ++c)
                out->diffuse_profile[3 * k + (size_t)c] = srt::diffuse_sample(asset->diffuse_profile, asset->diffuse_layout, k, c);
    }
    for (uint32_t i = 0; i < asset->texture_count; ++i) {
        const sepal_fmt_texture& td = asset->textures[i].desc;
        out->texture_role[i] = td.role;
        out->term_textures[td.term][td.role] = i;  // the reader checked one G and one H per term
        out->texture_term[i] = td.term;
        for (int c = 0; c < 3; ++c) out->texture_scale[i][c] = td.scale[c], out->texture_bias[i][c] = td.bias[c];
        // Reciprocal materials: the G texture's level 0 for the per-vertex third lookup (the
        // reader bounded its side and the terms), rounded to 8 bits as the upload rounds it.
        if ((info.flags & SEPAL_MATERIAL_RECIPROCAL) && td.role == SEPAL_ROLE_G) {
            const size_t values = (size_t)td.width * td.height * td.channels;
            uint8_t* dst = out->reciprocal_g[td.term];
            const uint8_t* src = asset->textures[i].level_data[0];
            for (size_t k = 0; k < values; ++k) {
                if (td.bits == 8) {
                    dst[k] = src[k];
                } else {
                    uint16_t q;
                    memcpy(&q, src + 2 * k, 2);
                    dst[k] = (uint8_t)((q * 255u + 32767u) / 65535u);
                }
            }
            out->reciprocal_width[td.term] = td.width;
            out->reciprocal_height[td.term] = td.height;
        }
    }
    return srt::ok(err);
}

}  // namespace srt

namespace {

constexpr GLenum kFramebufferOES = 0x8D40, kRenderbufferOES = 0x8D41, kColorAttachment0OES = 0x8CE0,
                 kDepthAttachmentOES = 0x8D00, kDepthComponent16OES = 0x81A5, kFramebufferCompleteOES = 0x8CD5,
                 kFramebufferBindingOES = 0x8CA6;

void destroy_accumulator(srt::Material* m) {
    const auto& f = srt::fbo_functions(m);
    if (m->acc_fbo && f.delete_framebuffers) f.delete_framebuffers(1, &m->acc_fbo);
    if (m->acc_depth && f.delete_renderbuffers) f.delete_renderbuffers(1, &m->acc_depth);
    if (m->acc_color) glDeleteTextures(1, &m->acc_color);
    m->acc_fbo = m->acc_depth = m->acc_color = 0;
    m->acc_width = m->acc_height = 0;
}

// The 8-bit target of srt::accumulates, w x h (and on GL ES 2 the program that writes it).
// Where the context cannot make one (an incomplete framebuffer, a shader that does not
// build) the material keeps the per-pass path: what it drew before.
void create_accumulator(srt::Material* m, int w, int h) {
    const auto& f = srt::fbo_functions(m);
    GLint bound = 0;
    glGetIntegerv(kFramebufferBindingOES, &bound);
    glGenTextures(1, &m->acc_color);
    glBindTexture(GL_TEXTURE_2D, m->acc_color);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    // Nearest: the final write reads each pixel's own texel.
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    f.gen_renderbuffers(1, &m->acc_depth);
    f.bind_renderbuffer(kRenderbufferOES, m->acc_depth);
    f.renderbuffer_storage(kRenderbufferOES, kDepthComponent16OES, w, h);
    f.gen_framebuffers(1, &m->acc_fbo);
    f.bind_framebuffer(kFramebufferOES, m->acc_fbo);
    f.framebuffer_texture_2d(kFramebufferOES, kColorAttachment0OES, GL_TEXTURE_2D, m->acc_color, 0);
    f.framebuffer_renderbuffer(kFramebufferOES, kDepthAttachmentOES, kRenderbufferOES, m->acc_depth);
    const bool complete = f.check_framebuffer_status(kFramebufferOES) == kFramebufferCompleteOES;
    f.bind_framebuffer(kFramebufferOES, (GLuint)bound);
    while (glGetError() != GL_NO_ERROR) {
    }
    if (!complete || (m->caps.gles_version == 2 && !srt::create_gles2_sum_program(m))) {
        destroy_accumulator(m);
        return;
    }
    m->acc_width = w;
    m->acc_height = h;
}

sepal_result create(const sepal_caps* caps, const sepal_asset* asset, int max_width, int max_height,
                    bool float_target, srt::Material* out, sepal_error* err) {
    sepal_result r0 = srt::material_plan(caps, asset, max_width, max_height, out, err);
    if (r0 != SEPAL_OK) return r0;
    if (float_target && !(caps->gles_version == 2 && caps->has_float_target))
        return srt::fail(err, SEPAL_ERR_UNSUPPORTED,
                         "material: no half-float render target (needs GL ES 3 with GL_EXT_color_buffer_half_float "
                         "or _float; caps.has_float_target is 0)");
    out->float_target = float_target ? 1 : 0;
    // Without a current context every GL call is a silent no-op: the material would hold no
    // textures and draw nothing.
    if (!glGetString(GL_VERSION))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "material: no current GL context (make one current before sepal_material_create)");
    const sepal_fmt_material& info = asset->material;
    glGenTextures((GLsizei)asset->texture_count, out->gl_textures);
    for (uint32_t i = 0; i < asset->texture_count; ++i) {
        const sepal_fmt_texture& td = asset->textures[i].desc;
        const bool wrap = info.param == SEPAL_PARAM_ELEV_AZIM && td.role == SEPAL_ROLE_H;
        // The per-pixel-only parameterizations' H coordinates jump where their frame is
        // undefined (rusinkiewicz: phi_h at h = n; elev-azim: the phi seam), so GL's
        // derivative-based MIP selection would read the coarsest levels there (measured:
        // 14.7 dB against the CPU backend on a mirror scene, h = n everywhere). Those H
        // textures are sampled at level 0, as the CPU backend samples every texture.
        const bool pixel_only = info.param == SEPAL_PARAM_RUSINKIEWICZ || info.param == SEPAL_PARAM_ELEV_AZIM;
        sepal_result r = upload(asset->textures[i], out->gl_textures[i], wrap, !(pixel_only && td.role == SEPAL_ROLE_H), err);
        if (r != SEPAL_OK) {
            sepal_material_destroy(srt::storage(out));
            return r;
        }
    }
    if (caps->gles_version == 2) {
        sepal_result r = srt::create_gles2_programs(out, err);
        if (r != SEPAL_OK) {
            sepal_material_destroy(srt::storage(out));
            return r;
        }
    }
    if (out->single_unit) {
        out->copy_width = next_pow2(max_width);
        out->copy_height = next_pow2(max_height);
        if (out->copy_width > caps->max_texture_size || out->copy_height > caps->max_texture_size) {
            sepal_material_destroy(srt::storage(out));
            return srt::fail(err, SEPAL_ERR_UNSUPPORTED,
                             "material: the one-texture-unit path needs a %dx%d copy texture; the "
                             "GPU's limit is %d",
                             out->copy_width, out->copy_height, caps->max_texture_size);
        }
        glGenTextures(1, &out->copy_texture);
        glBindTexture(GL_TEXTURE_2D, out->copy_texture);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, out->copy_width, out->copy_height, 0, GL_RGB,
                     GL_UNSIGNED_BYTE, nullptr);
        // Nearest: full-screen passes sample the copy exactly at texel centres.
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        sepal_result r = srt::gl_check("copy texture", err);
        if (r != SEPAL_OK) {
            sepal_material_destroy(srt::storage(out));
            return r;
        }
    }
    // A float target is rounded once anyway (when shown). A target over the texture limit:
    // the per-pass path, as where the context cannot make one.
    const int acc_w = next_pow2(max_width), acc_h = next_pow2(max_height);
    if (srt::accumulates(*caps, out->single_unit != 0) && !float_target && acc_w <= caps->max_texture_size &&
        acc_h <= caps->max_texture_size && srt::fbo_functions(out).gen_framebuffers)
        create_accumulator(out, acc_w, acc_h);
    return srt::ok(err);
}

}  // namespace

namespace srt {

const FboFunctions& fbo_functions(const Material* m) {
    return m->caps.gles_version == 2 ? gles2_fbo_functions() : m->caps.fbo_es1;
}

SumTarget enter_sum_target(const Material* m) {
    SumTarget t;
    glGetIntegerv(kFramebufferBindingOES, &t.bound);
    glGetIntegerv(GL_VIEWPORT, t.viewport);
    // The engine's scissor box is in its framebuffer's coordinates: off in the target, back on
    // for the write.
    t.scissor = glIsEnabled(GL_SCISSOR_TEST);
    fbo_functions(m).bind_framebuffer(kFramebufferOES, m->acc_fbo);
    glViewport(0, 0, t.viewport[2], t.viewport[3]);
    glDisable(GL_SCISSOR_TEST);
    glDepthMask(GL_TRUE);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    return t;
}

void leave_sum_target(const Material* m, const SumTarget& t) {
    fbo_functions(m).bind_framebuffer(kFramebufferOES, (GLuint)t.bound);
    glViewport(t.viewport[0], t.viewport[1], t.viewport[2], t.viewport[3]);
    if (t.scissor) glEnable(GL_SCISSOR_TEST);
}

}  // namespace srt

extern "C" sepal_result sepal_material_create(const sepal_caps* caps, const sepal_asset* asset, int max_width,
                                              int max_height, sepal_material* out, sepal_error* err) {
    return create(caps, asset, max_width, max_height, false, srt::material(out), err);
}

extern "C" sepal_result sepal_material_create_float_target(const sepal_caps* caps, const sepal_asset* asset,
                                                           int max_width, int max_height, sepal_material* out,
                                                           sepal_error* err) {
    return create(caps, asset, max_width, max_height, true, srt::material(out), err);
}

extern "C" void sepal_material_get_info(const sepal_material* storage, sepal_material_info* out) {
    if (!out) return;
    memset(out, 0, sizeof *out);
    const srt::Material* m = srt::material(storage);
    if (!m || m->texture_count == 0) return;
    out->created = 1;
    out->gles_version = m->caps.gles_version;
    out->max_width = m->max_width;
    out->max_height = m->max_height;
    out->float_target = m->float_fbo != 0;
    out->single_unit = m->single_unit;
    out->subtracts = m->has_negative_passes;
    out->subtract_by_inversion = m->subtract_by_inversion;
    out->context_lost = m->context_lost;
    out->passes = (int)m->plan.pass_count;
    out->textures = (int)m->texture_count;
    out->weaker_context = m->weaker;
    out->accumulates = m->acc_fbo != 0;
}

extern "C" void sepal_material_context_lost(sepal_material* storage) {
    srt::Material* m = srt::material(storage);
    if (!m) return;
    // The names are meaningless now: forget them (a later glDelete* on a new context could
    // delete that context's objects of the same number).
    memset(m->gl_textures, 0, sizeof m->gl_textures);
    m->copy_texture = m->diffuse_texture = 0;
    m->acc_fbo = m->acc_color = m->acc_depth = m->program_accumulated = 0;
    m->program_pass = m->program_fullscreen = m->program_mesh_texture = 0;
    m->program_fused_vertex = m->program_fused_pixel = 0;
    m->float_fbo = m->float_color = m->float_depth = 0;
    m->context_lost = 1;
}

extern "C" sepal_result sepal_material_restore(sepal_material* storage, const sepal_caps* caps,
                                               const sepal_asset* asset, sepal_error* err) {
    srt::Material* m = srt::material(storage);
    if (!m || !caps || !asset) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "restore: NULL argument");
    if (!m->context_lost)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "restore: the material's context was not lost (call sepal_material_context_lost first)");
    if (asset->texture_count != m->texture_count || memcmp(&asset->plan, &m->plan, sizeof m->plan) != 0 ||
        memcmp(&asset->material, &m->info, sizeof m->info) != 0 ||
        memcmp(asset->passes, m->passes, m->plan.pass_count * sizeof(sepal_fmt_pass)) != 0)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "restore: the asset is not the one the material was created from");
    const int w = m->max_width, h = m->max_height;
    return create(caps, asset, w, h, m->float_target != 0, m, err);  // clears context_lost
}

extern "C" void sepal_material_destroy(sepal_material* storage) {
    srt::Material* m = srt::material(storage);
    if (!m) return;
    if (m->context_lost) {  // nothing to delete: the objects died with the context
        m->texture_count = 0;
        m->context_lost = 0;
        return;
    }
    if (m->texture_count) glDeleteTextures((GLsizei)m->texture_count, m->gl_textures);
    if (m->copy_texture) glDeleteTextures(1, &m->copy_texture);
    destroy_accumulator(m);
    srt::destroy_gles2_programs(m);
    m->texture_count = 0;
    m->copy_texture = 0;
}

extern "C" size_t sepal_draw_scratch_floats(int vertex_count, int light_count) {
    if (vertex_count < 1 || light_count < 1 || light_count > SEPAL_MAX_LIGHTS) return 0;  // as the CPU's and emulator's
    return srt::scratch_floats(vertex_count, light_count);
}
