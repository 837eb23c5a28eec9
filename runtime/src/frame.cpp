// Frames of many objects (see sepal_frame.h): object-space scenes, the GL frame's begin,
// draws and end.
#include <math.h>
#include <string.h>

#include "draw_internal.h"

namespace srt {

void mat4_mul(const float* a, const float* b, float* out) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            float s = 0.0f;
            for (int k = 0; k < 4; ++k) s += a[k * 4 + r] * b[c * 4 + k];
            out[c * 4 + r] = s;
        }
}

namespace {

// General 4 x 4 inverse (cofactors, in double); false when singular or not finite.
bool invert4(const float* m, double* inv) {
    double a[16];
    for (int i = 0; i < 16; ++i) a[i] = m[i];
    inv[0] = a[5] * a[10] * a[15] - a[5] * a[11] * a[14] - a[9] * a[6] * a[15] + a[9] * a[7] * a[14] +
             a[13] * a[6] * a[11] - a[13] * a[7] * a[10];
    inv[4] = -a[4] * a[10] * a[15] + a[4] * a[11] * a[14] + a[8] * a[6] * a[15] - a[8] * a[7] * a[14] -
             a[12] * a[6] * a[11] + a[12] * a[7] * a[10];
    inv[8] = a[4] * a[9] * a[15] - a[4] * a[11] * a[13] - a[8] * a[5] * a[15] + a[8] * a[7] * a[13] +
             a[12] * a[5] * a[11] - a[12] * a[7] * a[9];
    inv[12] = -a[4] * a[9] * a[14] + a[4] * a[10] * a[13] + a[8] * a[5] * a[14] - a[8] * a[6] * a[13] -
              a[12] * a[5] * a[10] + a[12] * a[6] * a[9];
    inv[1] = -a[1] * a[10] * a[15] + a[1] * a[11] * a[14] + a[9] * a[2] * a[15] - a[9] * a[3] * a[14] -
             a[13] * a[2] * a[11] + a[13] * a[3] * a[10];
    inv[5] = a[0] * a[10] * a[15] - a[0] * a[11] * a[14] - a[8] * a[2] * a[15] + a[8] * a[3] * a[14] +
             a[12] * a[2] * a[11] - a[12] * a[3] * a[10];
    inv[9] = -a[0] * a[9] * a[15] + a[0] * a[11] * a[13] + a[8] * a[1] * a[15] - a[8] * a[3] * a[13] -
             a[12] * a[1] * a[11] + a[12] * a[3] * a[9];
    inv[13] = a[0] * a[9] * a[14] - a[0] * a[10] * a[13] - a[8] * a[1] * a[14] + a[8] * a[2] * a[13] +
              a[12] * a[1] * a[10] - a[12] * a[2] * a[9];
    inv[2] = a[1] * a[6] * a[15] - a[1] * a[7] * a[14] - a[5] * a[2] * a[15] + a[5] * a[3] * a[14] +
             a[13] * a[2] * a[7] - a[13] * a[3] * a[6];
    inv[6] = -a[0] * a[6] * a[15] + a[0] * a[7] * a[14] + a[4] * a[2] * a[15] - a[4] * a[3] * a[14] -
             a[12] * a[2] * a[7] + a[12] * a[3] * a[6];
    inv[10] = a[0] * a[5] * a[15] - a[0] * a[7] * a[13] - a[4] * a[1] * a[15] + a[4] * a[3] * a[13] +
              a[12] * a[1] * a[7] - a[12] * a[3] * a[5];
    inv[14] = -a[0] * a[5] * a[14] + a[0] * a[6] * a[13] + a[4] * a[1] * a[14] - a[4] * a[2] * a[13] -
              a[12] * a[1] * a[6] + a[12] * a[2] * a[5];
    inv[3] = -a[1] * a[6] * a[11] + a[1] * a[7] * a[10] + a[5] * a[2] * a[11] - a[5] * a[3] * a[10] -
             a[9] * a[2] * a[7] + a[9] * a[3] * a[6];
    inv[7] = a[0] * a[6] * a[11] - a[0] * a[7] * a[10] - a[4] * a[2] * a[11] + a[4] * a[3] * a[10] +
             a[8] * a[2] * a[7] - a[8] * a[3] * a[6];
    inv[11] = -a[0] * a[5] * a[11] + a[0] * a[7] * a[9] + a[4] * a[1] * a[11] - a[4] * a[3] * a[9] -
              a[8] * a[1] * a[7] + a[8] * a[3] * a[5];
    inv[15] = a[0] * a[5] * a[10] - a[0] * a[6] * a[9] - a[4] * a[1] * a[10] + a[4] * a[2] * a[9] +
              a[8] * a[1] * a[6] - a[8] * a[2] * a[5];
    const double det = a[0] * inv[0] + a[1] * inv[4] + a[2] * inv[8] + a[3] * inv[12];
    if (!(fabs(det) > 1e-300) || !isfinite(det)) return false;
    for (int i = 0; i < 16; ++i) inv[i] /= det;
    return true;
}

bool finite16(const float* m) {
    for (int i = 0; i < 16; ++i)
        if (!isfinite(m[i])) return false;
    return true;
}

bool is_identity(const float* m) {
    for (int i = 0; i < 16; ++i)
        if (m[i] != (i % 5 == 0 ? 1.0f : 0.0f)) return false;
    return true;
}

}  // namespace

sepal_result object_space(const float view[16], const float model[16], const sepal_light* lights, int light_count,
                          ObjectSpace* out, sepal_error* err) {
    if (light_count < 0 || light_count > SEPAL_MAX_LIGHTS || (light_count > 0 && !lights))
        return fail(err, SEPAL_ERR_INVALID_ARGUMENT, "object: %d lights (0..%d, and a light array)", light_count,
                    SEPAL_MAX_LIGHTS);
    if (!finite16(view) || !finite16(model))
        return fail(err, SEPAL_ERR_INVALID_ARGUMENT, "object: a view or model matrix entry is not finite");
    for (int l = 0; l < light_count; ++l)
        for (int k = 0; k < 3; ++k)
            if (!isfinite(lights[l].position[k]) || !(lights[l].intensity[k] >= 0.0f) ||
                !isfinite(lights[l].intensity[k]))
                return fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                            "object: light %d has a non-finite position or an intensity not finite and >= 0", l);
    if (model[3] != 0.0f || model[7] != 0.0f || model[11] != 0.0f || model[15] != 1.0f)
        return fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                    "object: the model matrix is projective (its last row must be 0 0 0 1: an affine map)");
    const float* c[3] = {model, model + 4, model + 8};
    double n2[3], s2 = 0.0;
    for (int i = 0; i < 3; ++i) {
        n2[i] = (double)c[i][0] * c[i][0] + (double)c[i][1] * c[i][1] + (double)c[i][2] * c[i][2];
        s2 += n2[i] / 3.0;
    }
    const double det = (double)c[0][0] * ((double)c[1][1] * c[2][2] - (double)c[1][2] * c[2][1]) -
                       (double)c[1][0] * ((double)c[0][1] * c[2][2] - (double)c[0][2] * c[2][1]) +
                       (double)c[2][0] * ((double)c[0][1] * c[1][2] - (double)c[0][2] * c[1][1]);
    // Relative to the scale cubed: a matrix that nearly collapses a direction is singular.
    if (!(fabs(det) > 1e-12 * s2 * sqrt(s2)))
        return fail(err, SEPAL_ERR_INVALID_ARGUMENT, "object: the model matrix is singular (determinant %g)", det);
    if (det < 0.0)
        return fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                    "object: the model matrix has a negative determinant (%g): a mirror flips the triangles' winding "
                    "and the tangent frames' handedness; mirror the mesh itself instead",
                    det);
    // A similarity (columns orthogonal, equal lengths) keeps angles: shading in object space
    // with the eye and lights moved there is exact, and costs nothing per vertex.
    bool similar = true;
    for (int i = 0; i < 3 && similar; ++i) {
        similar = fabs(n2[i] - s2) <= 1e-3 * s2;
        const int j = (i + 1) % 3;
        const double dot = (double)c[i][0] * c[j][0] + (double)c[i][1] * c[j][1] + (double)c[i][2] * c[j][2];
        similar = similar && fabs(dot) <= 1e-3 * s2;
    }
    double inv_view[16], inv_model[16];
    if (!invert4(view, inv_view)) return fail(err, SEPAL_ERR_INVALID_ARGUMENT, "object: the view matrix is singular");
    if (!invert4(model, inv_model)) return fail(err, SEPAL_ERR_INVALID_ARGUMENT, "object: the model matrix is singular");
    sepal_scene* sc = &out->scene;
    memset(sc, 0, sizeof *sc);
    const double eye_w[3] = {inv_view[12] / inv_view[15], inv_view[13] / inv_view[15], inv_view[14] / inv_view[15]};
    // Any other affine map: shading in world space, each vertex moved there as it is read.
    out->transform = !similar;
    const bool move = similar && !is_identity(model);
    for (int k = 0; k < 3; ++k) {
        const double e = !move ? eye_w[k]
                               : inv_model[k] * eye_w[0] + inv_model[4 + k] * eye_w[1] + inv_model[8 + k] * eye_w[2] +
                                     inv_model[12 + k];
        sc->camera.eye[k] = (float)e;
    }
    sc->camera.up[2] = 1.0f;
    sc->light_count = light_count;
    for (int l = 0; l < light_count; ++l) {
        sc->lights[l] = lights[l];
        if (!move) continue;
        const float* p = lights[l].position;
        const bool point = lights[l].type == SEPAL_LIGHT_POINT;
        for (int k = 0; k < 3; ++k)
            sc->lights[l].position[k] = (float)(inv_model[k] * p[0] + inv_model[4 + k] * p[1] +
                                                inv_model[8 + k] * p[2] + (point ? inv_model[12 + k] : 0.0));
        if (point)
            for (int k = 0; k < 3; ++k) sc->lights[l].intensity[k] = (float)(lights[l].intensity[k] / s2);
    }
    for (int col = 0; col < 3; ++col)
        for (int r = 0; r < 3; ++r) {
            out->m[col * 3 + r] = model[col * 4 + r];
            out->n[col * 3 + r] = (float)inv_model[r * 4 + col];  // (M^-1)^T: column col, row r = M^-1[col][r]
        }
    for (int r = 0; r < 3; ++r) out->m[9 + r] = model[12 + r];
    mat4_mul(view, model, out->modelview);
    return ok(err);
}

}  // namespace srt

extern "C" void sepal_model_identity(float m[16]) {
    for (int i = 0; i < 16; ++i) m[i] = i % 5 == 0 ? 1.0f : 0.0f;
}

extern "C" sepal_result sepal_object_shading(const sepal_frame_desc* desc, const sepal_object* object,
                                             sepal_scene* scene, float clip_from_shading[16], sepal_vertex* vertices,
                                             int capacity, int* count, sepal_error* err) {
    if (!desc || !object || !scene || !clip_from_shading || (vertices && !count))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "object_shading: NULL argument");
    srt::ObjectSpace space;
    srt::MeshView mesh;
    sepal_result r = srt::object_view(desc->view, *object, &space, &mesh, err);
    if (r != SEPAL_OK) return r;
    *scene = space.scene;
    // World space (any other affine model) or the object's own (a similarity).
    srt::mat4_mul(desc->projection, space.transform ? desc->view : space.modelview, clip_from_shading);
    if (!vertices) return r;
    *count = mesh.vertex_count;
    if (capacity < mesh.vertex_count)
        return srt::fail(err, SEPAL_ERR_CAPACITY, "object_shading: room for %d vertices, the object has %d", capacity,
                         mesh.vertex_count);
    for (int i = 0; i < mesh.vertex_count; ++i) mesh.load(i, &vertices[i]);
    return r;
}

extern "C" sepal_result sepal_object_scene(const sepal_frame_desc* desc, const sepal_object* object,
                                           sepal_scene* scene, float clip_from_object[16], sepal_error* err) {
    if (!desc || !object || !scene || !clip_from_object)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "object_scene: NULL argument");
    srt::ObjectSpace space;
    const sepal_result r =
        srt::object_space(desc->view, object->model, object->lights, object->light_count, &space, err);
    if (r != SEPAL_OK) return r;
    if (space.transform)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "object_scene: the model matrix is not a similarity (rotation, translation, uniform scale > "
                         "0): its shading space is the world (sepal_object_shading)");
    *scene = space.scene;
    srt::mat4_mul(desc->projection, space.modelview, clip_from_object);
    return r;
}

extern "C" sepal_result sepal_frame_begin(sepal_frame* frame, const sepal_frame_desc* desc, sepal_error* err) {
    if (!frame || !desc || !desc->caps)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "frame: NULL frame, description or caps");
    if (desc->viewport[2] < 1 || desc->viewport[3] < 1)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "frame: viewport %dx%d is empty", desc->viewport[2],
                         desc->viewport[3]);
    if (!srt::finite16(desc->view) || !srt::finite16(desc->projection))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "frame: a view or projection entry is not finite");
    if (desc->caps->gles_version != 1 && desc->caps->gles_version != 2)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "frame: caps of GL ES version %d", desc->caps->gles_version);
    frame->desc = *desc;
    frame->active = 1;
    if (desc->caps->gles_version == 1)
        srt::gles1_frame_begin(*desc, frame->saved);
    else
        srt::gles2_frame_begin(*desc, frame->saved, 0);
    return srt::gl_check("frame begin", err);
}

extern "C" sepal_result sepal_frame_draw(sepal_frame* frame, const sepal_object* o, sepal_draw_stats* stats_out,
                                         sepal_error* err) {
    if (!frame || !frame->active) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "frame: draw outside begin/end");
    if (!o || !o->material || (!o->mesh && !o->vertices))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "frame: NULL object, material or mesh");
    const srt::Material* m = srt::material(o->material);
    if (m->texture_count == 0)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "frame: material not created (or destroyed)");
    if (m->context_lost)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "frame: the material's GL context was lost; sepal_material_restore it on the new context");
    const sepal_frame_desc& fd = frame->desc;
    if (m->caps.gles_version != fd.caps->gles_version)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "frame: a GL ES %d material in a GL ES %d frame",
                         m->caps.gles_version, fd.caps->gles_version);
    srt::ObjectSpace space;
    srt::MeshView mesh;
    sepal_result r = srt::object_view(fd.view, *o, &space, &mesh, err);
    if (r != SEPAL_OK) return r;
    sepal_draw_desc d = {};
    d.material = o->material;
    d.scene = &space.scene;
    d.width = fd.viewport[2];
    d.height = fd.viewport[3];
    d.scratch = fd.scratch;
    d.scratch_floats = fd.scratch_floats;
    d.diffuse_texture = o->diffuse_texture;
    d.mode = o->mode;
    srt::FramePrep prep;
    sepal_draw_stats local;
    sepal_draw_stats* stats = stats_out ? stats_out : &local;
    r = srt::prepare_frame(&d, mesh, space.modelview, fd.projection, fd.float_target != 0, &prep, stats, err);
    if (r != SEPAL_OK) return r;
    return m->caps.gles_version == 1 ? srt::draw_gles1(&d, prep, stats, err) : srt::draw_gles2(&d, prep, stats, err);
}

extern "C" sepal_result sepal_frame_end(sepal_frame* frame, sepal_error* err) {
    if (!frame || !frame->active) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "frame: end without begin");
    frame->active = 0;
    if (frame->desc.caps->gles_version == 1)
        srt::gles1_frame_end(*frame->desc.caps, frame->saved);
    else
        srt::gles2_frame_end(*frame->desc.caps, frame->saved);
    return srt::gl_check("frame end", err);
}
