// Per-vertex frames, factor texture coordinates and irradiance (see vertex_setup.h).
#include "vertex_setup.h"

#include <float.h>
#include <math.h>

namespace srt {

namespace {
constexpr float kHorizonLimit = 1e-3f;
constexpr float kHorizonSlack = 0.17364818f;  // sin 10 degrees: a 16 x 8 sphere's silhouette vertices
}  // namespace

VertexSetupResult setup_vertices(sepal_param param, sepal_hemi_map map, const sepal_mesh& mesh,
                                 const sepal_scene& scene, float* scratch, bool swapped) {
    VertexSetupResult r = {0.0f, 0.0f, 0.0f, 0.0f, 0, 0, 0, 0, 0};
    const int n = mesh.vertex_count;
    float* frames = vertex_frames(scratch, n, scene.light_count);
    for (int i = 0; i < n; ++i) {
        const sepal_vertex& v = mesh.vertices[i];
        float* attr = frames + (size_t)kFrameFloats * i;
        if (!vertex_usable(v)) {
            // Never drawn (its triangles are skipped): finite placeholders only.
            ++r.bad_vertices;
            static const float kAttr[kFrameFloats] = {0, 0, 1, 1, 0, 0, 1};
            for (int k = 0; k < kFrameFloats; ++k) attr[k] = kAttr[k];
            for (int l = 0; l < scene.light_count; ++l) {
                float* g = light_g_uv(scratch, n, l) + 2 * (size_t)i;
                float* h = light_h_uv(scratch, n, l) + 2 * (size_t)i;
                float* e = light_irradiance(scratch, n, l) + 3 * (size_t)i;
                g[0] = g[1] = h[0] = h[1] = 0.5f;
                e[0] = e[1] = e[2] = 0.0f;
                if (swapped) {
                    float* x = light_swapped_uv(scratch, n, l) + 2 * (size_t)i;
                    x[0] = x[1] = 0.5f;
                }
                light_cosine(scratch, n, l)[i] = 0.0f;
                view_cosine(scratch, n, scene.light_count)[i] = 0.0f;
            }
            continue;
        }
        ShadingFrame fr;
        if (repaired_attributes(v, attr, attr + 3, &fr)) ++r.fallback_tangents;
        float to_eye[3] = {scene.camera.eye[0] - v.position[0], scene.camera.eye[1] - v.position[1],
                           scene.camera.eye[2] - v.position[2]};
        const bool eye_apart = normalize3(to_eye);
        float wo[3];
        fr.to_local(to_eye, wo);
        // A vertex of a front-facing triangle can see the eye below its own horizon (its
        // normal already points past the silhouette). A zero there would darken the whole
        // rim triangle, since GL interpolates vertex colours and coordinates, while the
        // pixels inside it see the eye just above their interpolated horizon: the vertex
        // takes that limit, the eye lowered onto its horizon. Only just below it (a vertex
        // normal leans past the face's by about half the mesh's angular spacing): a surface
        // that faces away from the eye stays black.
        // (Per vertex only: the per-pixel paths see the eye from each pixel, and a triangle
        // whose three vertices all lie in this band is lit here and black there.)
        if (eye_apart && !(wo[2] > kHorizonLimit) && wo[2] > -kHorizonSlack) {
            wo[2] = kHorizonLimit;
            if (!normalize3(wo)) wo[0] = 0.0f, wo[1] = 0.0f, wo[2] = 1.0f;
        }
        view_cosine(scratch, n, scene.light_count)[i] = wo[2] > 0.0f ? wo[2] : 0.0f;
        float sum = 0.0f, lit_sum = 0.0f;
        for (int l = 0; l < scene.light_count; ++l) {
            const sepal_light& light = scene.lights[l];
            float to_light[3];
            const float falloff = light_direction(light, v.position, to_light);
            float wi[3];
            fr.to_local(to_light, wi);
            float* g = light_g_uv(scratch, n, l) + 2 * (size_t)i;
            float* h = light_h_uv(scratch, n, l) + 2 * (size_t)i;
            float* e = light_irradiance(scratch, n, l) + 3 * (size_t)i;
            // Every parameterization: the per-pixel-only ones' coordinates go unused, but
            // their horizon test and fallbacks count (the fused-pixel path's stats).
            const int above = param_texcoords(param, map, wi, wo, g, h, true, &r.param_fallbacks);
            if (swapped) {  // x~: G at (wo, wi); its frame fallbacks are this pair's, not counted twice
                float unused[2];
                param_texcoords(param, map, wo, wi, light_swapped_uv(scratch, n, l) + 2 * (size_t)i, unused, true,
                                nullptr);
            }
            const float cosine = above > 0 ? wi[2] : 0.0f;
            light_cosine(scratch, n, l)[i] = cosine;
            if (above <= 0) ++r.below_horizon;
            float peak = 0.0f, lit = 0.0f;
            for (int k = 0; k < 3; ++k) {
                e[k] = above > 0 ? light.intensity[k] * falloff : 0.0f;
                if (!(e[k] <= FLT_MAX)) {  // overflow (a huge intensity over a tiny distance)
                    e[k] = isnan(e[k]) ? 0.0f : FLT_MAX;
                    ++r.nonfinite_clamped;
                }
                if (e[k] > lit) lit = e[k];
                if (e[k] * cosine > peak) peak = e[k] * cosine;
            }
            sum += peak;
            lit_sum += lit;
            if (!(sum <= FLT_MAX)) sum = FLT_MAX;
            if (!(lit_sum <= FLT_MAX)) lit_sum = FLT_MAX;
            if (peak > r.max_irradiance_single) r.max_irradiance_single = peak;
            if (lit > r.max_lit_single) r.max_lit_single = lit;
        }
        if (sum > r.max_irradiance_sum) r.max_irradiance_sum = sum;
        if (lit_sum > r.max_lit_sum) r.max_lit_sum = lit_sum;
    }
    return r;
}

PassInputs pass_inputs(const sepal_material* m, float* scratch, int n, int lights, int light) {
    PassInputs in;
    in.irradiance = light_irradiance(scratch, n, light);
    in.cosine = light_cosine(scratch, n, light);
    in.view_cosine = view_cosine(scratch, n, lights);
    in.profile = m->diffuse_side ? m->diffuse_profile : nullptr;
    in.profile_side = m->diffuse_side;
    in.swapped_uv = light_swapped_uv(scratch, n, light);
    in.material = m;
    return in;
}

float reciprocal_lookup(const sepal_material* m, uint32_t term, const float uv[2], int c) {
    const int w = (int)m->reciprocal_width[term], h = (int)m->reciprocal_height[term];
    const int ch = (int)m->info.channels, cc = ch == 1 ? 0 : c;
    const uint8_t* t = m->reciprocal_g[term];
    const float x = uv[0] * (float)w - 0.5f, y = uv[1] * (float)h - 0.5f;
    const float fx = floorf(x), fy = floorf(y), ax = x - fx, ay = y - fy;
    auto clampi = [](float k, int size) { return k < 0.0f ? 0 : k >= (float)(size - 1) ? size - 1 : (int)k; };
    const int x0 = clampi(fx, w), x1 = clampi(fx + 1.0f, w), y0 = clampi(fy, h), y1 = clampi(fy + 1.0f, h);
    auto at = [&](int i, int j) { return (float)t[((size_t)j * (size_t)w + (size_t)i) * (size_t)ch + (size_t)cc]; };
    return ((1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x1, y0)) + ay * ((1 - ax) * at(x0, y1) + ax * at(x1, y1))) /
           255.0f;
}

void fill_pass_colors(const sepal_fmt_material& info, const sepal_fmt_pass& pass, const PassInputs& in, float scale,
                      int n, float* rgba) {
    const bool uses_cosine = pass_uses_cosine(info, pass);
    const bool profile = pass.op == SEPAL_OP_DIFFUSE && in.profile;
    const bool third = pass.op == SEPAL_OP_RECIPROCAL && in.material;
    const uint32_t term = third ? in.material->texture_term[pass.tex0] : 0;
    for (int i = 0; i < n; ++i) {
        // Per channel: a luminance material's colour ratio is in the pass colour.
        const float s = uses_cosine ? scale * in.cosine[i] : scale;
        for (int k = 0; k < 3; ++k) {
            float v = pass.color[k] * in.irradiance[3 * i + k] * s;
            if (profile) v *= sepal_diffuse_profile(in.profile, in.profile_side, in.cosine[i], in.view_cosine[i], k);
            if (third) v *= reciprocal_lookup(in.material, term, in.swapped_uv + 2 * (size_t)i, k);
            rgba[4 * i + k] = v;
        }
        rgba[4 * i + 3] = 1.0f;
    }
}

TriangleCheck check_triangles(const sepal_mesh& mesh, int bad_vertices) {
    TriangleCheck c = {0, 0, -1};
    for (int i = 0; i < mesh.index_count; ++i)
        if (mesh.indices[i] >= mesh.vertex_count) {
            c.bad_index = i;
            return c;
        }
    for (int t = 0; t + 2 < mesh.index_count; t += 3) {
        const sepal_vertex* v[3] = {&mesh.vertices[mesh.indices[t]], &mesh.vertices[mesh.indices[t + 1]],
                                  &mesh.vertices[mesh.indices[t + 2]]};
        if (bad_vertices > 0 && (!vertex_usable(*v[0]) || !vertex_usable(*v[1]) || !vertex_usable(*v[2]))) {
            ++c.skipped;
            continue;
        }
        float e1[3], e2[3];
        for (int k = 0; k < 3; ++k)
            e1[k] = v[1]->position[k] - v[0]->position[k], e2[k] = v[2]->position[k] - v[0]->position[k];
        const float cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0]};
        if (!(dot3(cr, cr) > 0.0f)) ++c.zero_area;  // as sepal_obj_load counts them
    }
    return c;
}

}  // namespace srt
