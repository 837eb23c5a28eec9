// GL capability detection, shared by the GL ES 1.1 and GL ES 2 paths.
#include "internal.h"

#include <GLES2/gl2.h>
#include <stdio.h>
#include <string.h>

namespace {
// GL ES 1.1's GL_MAX_TEXTURE_UNITS; not in the ES 2 header this file includes.
constexpr GLenum kMaxTextureUnitsES1 = 0x84E2;
}  // namespace

namespace srt {
int gles_major_version(const char* version) {
    static const char kPrefix[] = "OpenGL ES";
    if (!version || strncmp(version, kPrefix, sizeof kPrefix - 1) != 0) return 0;
    const char* p = version + sizeof kPrefix - 1;
    if (p[0] == '-' && (p[1] == 'C') && (p[2] == 'M' || p[2] == 'L')) p += 3;
    if (*p != ' ') return 0;
    ++p;
    if (*p < '1' || *p > '9' || p[1] != '.') return 0;
    return *p - '0';
}

sepal_result gl_check(const char* what, sepal_error* err) {
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) return SEPAL_OK;
    while (glGetError() != GL_NO_ERROR) {
    }
    return fail(err, SEPAL_ERR_GL, "GL error 0x%04x after %s", (unsigned)e, what);
}
}  // namespace srt

extern "C" sepal_result sepal_query_caps(int gles_version, uint32_t mask, sepal_proc_loader get_proc,
                                     sepal_caps* out, sepal_error* err) {
    if (!out) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "sepal_query_caps: out is NULL");
    if (gles_version != 1 && gles_version != 2)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "sepal_query_caps: gles_version %d is not 1 or 2", gles_version);
    memset(out, 0, sizeof *out);
    while (glGetError() != GL_NO_ERROR) {
    }
    const char* version = (const char*)glGetString(GL_VERSION);
    const char* renderer = (const char*)glGetString(GL_RENDERER);
    const char* ext = (const char*)glGetString(GL_EXTENSIONS);
    if (!version)
        return srt::fail(err, SEPAL_ERR_UNSUPPORTED,
                         "no current GL context (glGetString(GL_VERSION) returned NULL)");
    snprintf(out->version, sizeof out->version, "%s", version);
    snprintf(out->renderer, sizeof out->renderer, "%s", renderer ? renderer : "?");
    const int major = srt::gles_major_version(version);
    if (major == 0)
        return srt::fail(err, SEPAL_ERR_UNSUPPORTED,
                         "the current context is not GL ES: GL_VERSION is '%s'", version);
    if ((gles_version == 1) != (major == 1))
        return srt::fail(err, SEPAL_ERR_UNSUPPORTED,
                         "asked for GL ES %d paths but the current context is '%s'",
                         gles_version, version);
    out->gles_version = gles_version;
    GLint units = 0, max_size = 0;
    glGetIntegerv(gles_version == 1 ? kMaxTextureUnitsES1 : GL_MAX_TEXTURE_IMAGE_UNITS, &units);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    out->texture_units = units;
    out->max_texture_size = max_size;
    GLint bits[3] = {0, 0, 0};
    glGetIntegerv(GL_RED_BITS, &bits[0]);
    glGetIntegerv(GL_GREEN_BITS, &bits[1]);
    glGetIntegerv(GL_BLUE_BITS, &bits[2]);
    out->red_bits = bits[0];
    out->green_bits = bits[1];
    out->blue_bits = bits[2];
    out->dither = glIsEnabled(GL_DITHER) ? 1 : 0;
    if (gles_version == 1) {
        out->has_blend_subtract = srt::has_extension(ext, "GL_OES_blend_subtract");
        out->has_fbo = srt::has_extension(ext, "GL_OES_framebuffer_object");
        out->has_npot = srt::has_extension(ext, "GL_OES_texture_npot");
    } else {
        out->has_blend_subtract = 1;  // core in ES 2.0
        out->has_fbo = 1;             // core in ES 2.0
        out->has_npot = major >= 3 || srt::has_extension(ext, "GL_OES_texture_npot");
        out->has_float_target = major >= 3 && (srt::has_extension(ext, "GL_EXT_color_buffer_half_float") ||
                                               srt::has_extension(ext, "GL_EXT_color_buffer_float"));
    }
    // Subtractive blending needs its entry point too (not exported by GL ES 1.1 libraries).
    if (out->has_blend_subtract) {
        sepal_gl_proc f = nullptr;
        if (get_proc) f = get_proc(gles_version == 1 ? "glBlendEquationOES" : "glBlendEquation");
        if (!f && gles_version == 2) f = (sepal_gl_proc)&glBlendEquation;  // core: linked directly
        out->blend_equation = (void (*)(unsigned int))f;
        if (!f) out->has_blend_subtract = 0;
    }
    // GL ES 1.1's framebuffer objects: every entry point or none.
    if (gles_version == 1 && out->has_fbo && get_proc) {
        auto& f = out->fbo_es1;
        f.gen_framebuffers = (decltype(f.gen_framebuffers))get_proc("glGenFramebuffersOES");
        f.delete_framebuffers = (decltype(f.delete_framebuffers))get_proc("glDeleteFramebuffersOES");
        f.bind_framebuffer = (decltype(f.bind_framebuffer))get_proc("glBindFramebufferOES");
        f.framebuffer_texture_2d = (decltype(f.framebuffer_texture_2d))get_proc("glFramebufferTexture2DOES");
        f.gen_renderbuffers = (decltype(f.gen_renderbuffers))get_proc("glGenRenderbuffersOES");
        f.delete_renderbuffers = (decltype(f.delete_renderbuffers))get_proc("glDeleteRenderbuffersOES");
        f.bind_renderbuffer = (decltype(f.bind_renderbuffer))get_proc("glBindRenderbufferOES");
        f.renderbuffer_storage = (decltype(f.renderbuffer_storage))get_proc("glRenderbufferStorageOES");
        f.framebuffer_renderbuffer = (decltype(f.framebuffer_renderbuffer))get_proc("glFramebufferRenderbufferOES");
        f.check_framebuffer_status = (decltype(f.check_framebuffer_status))get_proc("glCheckFramebufferStatusOES");
        if (!f.gen_framebuffers || !f.delete_framebuffers || !f.bind_framebuffer || !f.framebuffer_texture_2d ||
            !f.gen_renderbuffers || !f.delete_renderbuffers || !f.bind_renderbuffer || !f.renderbuffer_storage ||
            !f.framebuffer_renderbuffer || !f.check_framebuffer_status)
            memset(&f, 0, sizeof f);
    }
    if (glGetError() != GL_NO_ERROR)
        return srt::fail(err, SEPAL_ERR_GL, "GL error while querying capabilities");
    out->mask = mask;
    if (mask & SEPAL_MASK_BLEND_SUBTRACT) out->has_blend_subtract = 0, out->blend_equation = nullptr;
    if (mask & SEPAL_MASK_MULTITEXTURE) out->texture_units = out->texture_units > 0 ? 1 : 0;
    if ((mask & SEPAL_MASK_THIRD_UNIT) && out->texture_units > 2) out->texture_units = 2;
    if (mask & SEPAL_MASK_FBO) out->has_fbo = 0, memset(&out->fbo_es1, 0, sizeof out->fbo_es1);
    if (mask & SEPAL_MASK_NPOT) out->has_npot = 0;
    if (mask & SEPAL_MASK_FLOAT_TARGET) out->has_float_target = 0;
    if (out->texture_units < 1)
        return srt::fail(err, SEPAL_ERR_UNSUPPORTED, "context reports no texture units");
    return srt::ok(err);
}
