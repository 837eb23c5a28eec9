// The CPU backend (see sepal_draw_cpu in sepal_material.h).
#include <float.h>
#include <math.h>
#include <string.h>

#include "draw_internal.h"
#include "internal.h"
#include "sepal/sepal_frame.h"
#include "sepal/sepal_material.h"
#include "sepal/sepal_raster.h"
#include "vertex_setup.h"

namespace {

constexpr int kVaryings = 12;  // world position 3, normal 3, tangent 4, uv 2

struct Shader {
    const sepal_asset* asset;
    srt::AssetTerms terms;  // found once per frame
    const sepal_scene* scene;
    float* color;
    int width;
    sepal_draw_stats st;  // per-pixel counters
    const uint8_t* diffuse;
    int diffuse_w, diffuse_h;
};

// Bilinear, repeat wrapping, level 0: the diffuse map at a mesh UV (row 0 at v = 0).
float diffuse_sample(const Shader& s, float u, float v, int c) {
    // Repeat wrapping first, so no coordinate (huge, or NaN from a broken UV) overflows int.
    u = isfinite(u) ? u - floorf(u) : 0.0f;
    v = isfinite(v) ? v - floorf(v) : 0.0f;
    const float x = u * (float)s.diffuse_w - 0.5f, y = v * (float)s.diffuse_h - 0.5f;
    const float fx = floorf(x), fy = floorf(y), ax = x - fx, ay = y - fy;
    auto wrap = [](int k, int n) { return ((k % n) + n) % n; };
    const int x0 = wrap((int)fx, s.diffuse_w), x1 = wrap((int)fx + 1, s.diffuse_w);
    const int y0 = wrap((int)fy, s.diffuse_h), y1 = wrap((int)fy + 1, s.diffuse_h);
    auto at = [&](int i, int j) { return (float)s.diffuse[((size_t)j * s.diffuse_w + i) * 4 + c] / 255.0f; };
    return (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x1, y0)) + ay * ((1 - ax) * at(x0, y1) + ax * at(x1, y1));
}

void shade(void* user, int x, int y, float, const float* v) {
    Shader& s = *static_cast<Shader*>(user);
    const sepal_asset& a = *s.asset;
    srt::ShadingFrame fr;
    // The corners' frames are usable (bad vertices are not drawn, tangents repaired), but
    // interpolation can still cancel them out (opposite normals or tangents).
    if (srt::shading_frame(v + 3, v + 6, &fr)) ++s.st.pixel_frame_fallbacks;
    float to_eye[3] = {s.scene->camera.eye[0] - v[0], s.scene->camera.eye[1] - v[1], s.scene->camera.eye[2] - v[2]};
    srt::normalize3(to_eye);
    float wo[3];
    fr.to_local(to_eye, wo);
    float sum[3] = {0, 0, 0};
    for (int l = 0; l < s.scene->light_count; ++l) {
        const sepal_light& light = s.scene->lights[l];
        float to_light[3], wi[3];
        const float falloff = srt::light_direction(light, v, to_light);
        fr.to_local(to_light, wi);
        float f_cos[3];
        srt::PairCounts counts;
        const bool above = srt::eval_pair(a, s.terms, wi, wo, f_cos, &counts);
        s.st.param_fallbacks += counts.param_fallbacks;
        s.st.negative_clamped += counts.negative_clamped;
        if (!above) {
            ++s.st.below_horizon;
            continue;
        }
        for (int c = 0; c < 3; ++c) sum[c] += f_cos[c] * falloff * light.intensity[c];
    }
    float* out = s.color + ((size_t)y * (size_t)s.width + (size_t)x) * 3;
    for (int c = 0; c < 3; ++c) {
        out[c] = sum[c];
        if (s.diffuse) out[c] *= diffuse_sample(s, v[10], v[11], c);
        if (!(out[c] <= FLT_MAX)) {  // overflow (huge factors times a huge light) or inf * 0
            out[c] = isnan(out[c]) ? 0.0f : FLT_MAX;
            ++s.st.nonfinite_clamped;
        }
    }
}

}  // namespace

// The rasterizer's target limit (sepal_raster.h).
constexpr int kMaxCpuSide = 8192;

extern "C" size_t sepal_cpu_scratch_floats(int vertex_count) {
    return (size_t)(vertex_count > 0 ? vertex_count : 0) * (4 + kVaryings);
}

namespace {

// Before any pixel is written (and before the camera's matrices): the caller sized the
// buffers from these.
sepal_result check_size(int width, int height, sepal_error* err) {
    if (width < 1 || height < 1 || width > kMaxCpuSide || height > kMaxCpuSide)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "cpu: target %dx%d out of range 1..%d", width, height,
                         kMaxCpuSide);
    return SEPAL_OK;
}

// One object: mesh its vertices (d->mesh is not read), d->scene in its shading space, view
// (the modelview) and proj its matrices. keep: colour and depth stay where the object is
// not in front; otherwise both start cleared, the colour to the scene's background.
sepal_result cpu_object(const sepal_cpu_desc* d, const srt::MeshView& mesh, const float* view, const float* proj,
                        bool keep, sepal_error* err) {
    if (!d || !d->asset || !mesh.attr[srt::MeshView::kPosition] || !d->scene || !d->color || !d->depth || !d->scratch)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "cpu: NULL asset, mesh, scene or buffer");
    if (const sepal_result r = check_size(d->width, d->height, err)) return r;
    if (!srt::asset_parsed(*d->asset))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "cpu: the asset was not filled by sepal_asset_parse");
    if (d->scratch_floats < sepal_cpu_scratch_floats(mesh.vertex_count))
        return srt::fail(err, SEPAL_ERR_CAPACITY, "cpu: scratch holds %zu floats, needs %zu", d->scratch_floats,
                         sepal_cpu_scratch_floats(mesh.vertex_count));
    sepal_result r;
    const int n = mesh.vertex_count;
    float* clip = d->scratch;
    float* vary = d->scratch + 4 * (size_t)n;
    sepal_draw_stats st = {};
    for (int i = 0; i < n; ++i) {
        sepal_vertex v;
        mesh.load(i, &v);  // in the shading space
        const float* object_position = mesh.position(i);
        float* dst = vary + (size_t)i * kVaryings;
        if (!srt::vertex_usable(v)) {
            // A NaN clip position makes the rasterizer skip every triangle using it, as the
            // GL backends skip them.
            ++st.bad_vertices;
            for (int k = 0; k < 4; ++k) clip[4 * (size_t)i + k] = NAN;
            memset(dst, 0, kVaryings * sizeof(float));
            continue;
        }
        for (int row = 0; row < 4; ++row) {
            float acc = 0.0f;
            for (int k = 0; k < 4; ++k) {
                float m = 0.0f;  // (proj * view)[row][k], column-major
                for (int j = 0; j < 4; ++j) m += proj[j * 4 + row] * view[k * 4 + j];
                acc += m * (k < 3 ? object_position[k] : 1.0f);
            }
            clip[4 * (size_t)i + row] = acc;
        }
        memcpy(dst, v.position, 3 * sizeof(float));
        srt::ShadingFrame frame;
        if (srt::repaired_attributes(v, dst + 3, dst + 6, &frame)) ++st.fallback_tangents;
        memcpy(dst + 10, v.uv, 2 * sizeof(float));
    }
    const srt::TriangleCheck tri = srt::check_triangles(mesh, st.bad_vertices);
    if (tri.bad_index >= 0)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "cpu: index %d is %u; the mesh has %d vertices", tri.bad_index,
                         mesh.indices[tri.bad_index], n);
    st.skipped_triangles = tri.skipped;
    st.zero_area_triangles = tri.zero_area;
    sepal_raster_target target = {d->width, d->height, d->depth};
    if (!keep) sepal_frame_clear_cpu(d->width, d->height, d->scene->background, d->color, d->depth);
    // The rasterizer calls the shader for every fragment passing LEQUAL; the last one
    // written per pixel is the front surface, as GL's depth test gives.
    Shader s = {};
    s.asset = d->asset;
    s.scene = d->scene;
    s.color = d->color;
    s.width = d->width;
    if (d->diffuse_rgba && d->diffuse_width > 0 && d->diffuse_height > 0) {
        s.diffuse = d->diffuse_rgba;
        s.diffuse_w = d->diffuse_width;
        s.diffuse_h = d->diffuse_height;
    }
    srt::find_terms(*d->asset, &s.terms);
    sepal_raster_desc rd = {};
    rd.clip = clip;
    rd.vertex_count = n;
    rd.varyings = vary;
    rd.varying_count = kVaryings;
    rd.varying_stride = kVaryings;
    rd.indices = mesh.indices;
    rd.index_count = mesh.index_count;
    rd.cull = SEPAL_CULL_BACK;
    rd.depth_func = SEPAL_DEPTH_LEQUAL;
    rd.fragment = shade;
    rd.user = &s;
    r = sepal_raster_triangles(&target, &rd, err);
    if (d->stats) {
        sepal_draw_stats& out = *d->stats;
        out = st;
        out.draw_calls = 1;
        out.exposure = 1.0f;
        out.below_horizon = s.st.below_horizon;
        out.dim_lights = srt::dim_lights(d->asset->material, mesh, *d->scene);
        out.param_fallbacks = s.st.param_fallbacks;
        out.negative_clamped = s.st.negative_clamped;
        out.nonfinite_clamped = s.st.nonfinite_clamped;
        out.pixel_frame_fallbacks = s.st.pixel_frame_fallbacks;
    }
    return r;
}

}  // namespace

extern "C" sepal_result sepal_draw_cpu(const sepal_cpu_desc* d, sepal_error* err) {
    if (!d || !d->scene) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "cpu: NULL asset, mesh, scene or buffer");
    if (const sepal_result r = check_size(d->width, d->height, err)) return r;
    float view[16], proj[16];
    const sepal_result r = sepal_scene_matrices(d->scene, d->width, d->height, view, proj, err);
    if (r != SEPAL_OK) return r;
    if (!d->mesh) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "cpu: NULL asset, mesh, scene or buffer");
    return cpu_object(d, srt::MeshView(*d->mesh), view, proj, false, err);
}

extern "C" void sepal_frame_clear_cpu(int width, int height, const float rgb[3], float* color, float* depth) {
    const size_t pixels = (size_t)(width > 0 ? width : 0) * (size_t)(height > 0 ? height : 0);
    if (color)
        for (size_t p = 0; p < pixels; ++p)
            for (int c = 0; c < 3; ++c) color[p * 3 + c] = rgb ? rgb[c] : 0.0f;
    if (depth) {
        sepal_raster_target target = {width, height, depth};
        sepal_raster_clear_depth(&target);
    }
}

extern "C" sepal_result sepal_frame_draw_cpu(const sepal_frame_desc* f, const sepal_object* o, float* color,
                                             float* depth, float* scratch, size_t scratch_floats,
                                             sepal_draw_stats* stats, sepal_error* err) {
    if (!f || !o) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "cpu: NULL frame or object");
    srt::ObjectSpace space;
    srt::MeshView mesh;
    sepal_result r = srt::object_view(f->view, *o, &space, &mesh, err);
    if (r != SEPAL_OK) return r;
    sepal_cpu_desc d = {};
    d.asset = o->asset;
    d.scene = &space.scene;
    d.width = f->viewport[2];
    d.height = f->viewport[3];
    d.color = color;
    d.depth = depth;
    d.scratch = scratch;
    d.scratch_floats = scratch_floats;
    d.stats = stats;
    return cpu_object(&d, mesh, space.modelview, f->projection, true, err);
}
