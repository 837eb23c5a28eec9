// sepal_preview_draw: validation shared by both GL ES versions, then dispatch.
#include "preview.h"

#include <GLES2/gl2.h>
#include <math.h>

namespace {
bool is_pow2(int v) { return v > 0 && (v & (v - 1)) == 0; }
}  // namespace

uint32_t srt::preview_texture(const sepal_preview_desc& d) {
    static const uint8_t kWhite[4] = {255, 255, 255, 255};
    GLuint tex = 0;
    glActiveTexture(GL_TEXTURE0);
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, d.texture ? d.texture_width : 1, d.texture ? d.texture_height : 1, 0,
                 GL_RGBA, GL_UNSIGNED_BYTE, d.texture ? d.texture : kWhite);
    return tex;
}

extern "C" sepal_result sepal_preview_draw(const sepal_caps* caps, const sepal_preview_desc* desc,
                                       sepal_error* err) {
    if (!caps || !desc || !desc->mesh || !desc->mesh->vertices || !desc->mesh->indices)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "preview: caps, desc or mesh is NULL");
    if (desc->mesh->index_count % 3 != 0)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "preview: index count %d is not a multiple of 3",
                         desc->mesh->index_count);
    if (desc->texture) {
        const int w = desc->texture_width, h = desc->texture_height;
        if (!is_pow2(w) || !is_pow2(h) || w > caps->max_texture_size ||
            h > caps->max_texture_size)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "preview: texture %dx%d must be powers of two up to %d", w, h,
                             caps->max_texture_size);
    }
    const float* l = desc->light_dir_eye;
    const float len = sqrtf(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    if (!(len > 1e-6f) || !isfinite(len))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "preview: light direction is zero or not finite");
    const float dir[3] = {l[0] / len, l[1] / len, l[2] / len};
    if (caps->gles_version == 1) return srt::preview_gles1(*caps, *desc, dir, err);
    if (caps->gles_version == 2) return srt::preview_gles2(*caps, *desc, dir, err);
    return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "preview: caps.gles_version %d",
                     caps->gles_version);
}
