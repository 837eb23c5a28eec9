// Per-vertex work shared by the material backends (internal): frames, directions,
// texture coordinates of the factors and irradiance per light, and the checks that keep
// odd meshes (degenerate tangents, NaN attributes, zero-area triangles) from drawing
// garbage, each counted.
#pragma once
#include "internal.h"
#include "mesh_view.h"
#include "sepal/sepal_format.h"
#include "material_state.h"
#include "sepal/sepal_material.h"
#include "sepal/sepal_scene.h"

namespace srt {

// Scratch layout for N vertices and L lights: per light l, at l * 10N: G uv (2N), H uv
// (2N), irradiance RGB E = I / d^2 (3N; 0 where the light or the eye is below the
// horizon), cos(theta_i) (1N; 0 there too), the G uv of the swapped pair (wo, wi) (2N:
// reciprocal materials' third lookup, x~; filled only for them); then 4N floats of colours for the pass being
// drawn; then 7N floats of per-vertex attributes as the per-pixel paths interpolate them
// (normal 3, tangent 4: the mesh's, with unusable tangents replaced; see
// repaired_attributes); then N floats of cos(theta_o) (0 for an eye below the horizon);
// then 4N floats of a second colour array (the fused path's diffuse term).
constexpr size_t kLightFloats = 10;
inline size_t scratch_floats(int vertices, int lights) {
    return (size_t)vertices * (kLightFloats * (size_t)lights + 4 + 7 + 1 + 4);
}
inline float* light_g_uv(float* s, int n, int l) { return s + (size_t)l * kLightFloats * n; }
inline float* light_h_uv(float* s, int n, int l) { return s + (size_t)l * kLightFloats * n + 2 * (size_t)n; }
inline float* light_irradiance(float* s, int n, int l) { return s + (size_t)l * kLightFloats * n + 4 * (size_t)n; }
inline float* light_cosine(float* s, int n, int l) { return s + (size_t)l * kLightFloats * n + 7 * (size_t)n; }
inline float* light_swapped_uv(float* s, int n, int l) { return s + (size_t)l * kLightFloats * n + 8 * (size_t)n; }
inline float* pass_colors(float* s, int n, int lights) { return s + (size_t)lights * kLightFloats * n; }
inline float* vertex_frames(float* s, int n, int lights) {
    return s + (size_t)lights * kLightFloats * n + 4 * (size_t)n;
}
constexpr int kFrameFloats = 7;
inline float* view_cosine(float* s, int n, int lights) { return vertex_frames(s, n, lights) + kFrameFloats * (size_t)n; }
inline float* second_colors(float* s, int n, int lights) { return view_cosine(s, n, lights) + (size_t)n; }

struct VertexSetupResult {
    // Of E cos(theta_i), what version-1 passes and DIFFUSE passes send:
    float max_irradiance_sum;     // max over vertices of sum over lights of the max channel
    float max_irradiance_single;  // max over vertices, lights and channels
    // Of E alone (lit vertex-light pairs), what a radiance material's textured passes send:
    float max_lit_sum, max_lit_single;
    int below_horizon;            // vertex-light pairs with light or eye below the horizon
    int fallback_tangents;        // vertices whose tangent was replaced
    int bad_vertices;             // vertices that cannot be drawn (see vertex_usable)
    int param_fallbacks;          // vertex-light pairs whose parameterization frame was undefined
    int nonfinite_clamped;        // irradiance channels that overflowed (or were NaN)
};

// Whether a pass's vertex colour carries cos(theta_i): every pass of a version-1 material
// (the factors are f), and DIFFUSE passes (the factors of a radiance material hold the cosine).
inline bool pass_uses_cosine(const sepal_fmt_material& m, const sepal_fmt_pass& p) {
    return p.op == SEPAL_OP_DIFFUSE || !(m.flags & SEPAL_MATERIAL_RADIANCE);
}
// The largest irradiance a pass's colour is multiplied by this frame (one light).
inline float pass_irradiance_peak(const VertexSetupResult& v, bool uses_cosine) {
    return uses_cosine ? v.max_irradiance_single : v.max_lit_single;
}

// What a pass's vertex colour is made of, for one light: E, cos(theta_i), for DIFFUSE
// passes with a profile, cos(theta_o) and the profile, and for RECIPROCAL passes the third
// lookup (tex0 at x~, from the material's copy).
struct PassInputs {
    const float* irradiance;    // 3 per vertex
    const float* cosine;        // cos(theta_i) per vertex
    const float* view_cosine;   // cos(theta_o) per vertex
    const float* profile;       // the material's diffuse profile, or NULL
    uint32_t profile_side;
    const float* swapped_uv;    // x~, 2 per vertex (reciprocal materials)
    const srt::Material* material;
};
// The RECIPROCAL pass's third factor: the stored q of term `term`'s G texture at uv,
// channel c (bilinear at level 0, clamped to the edge, as GL_LINEAR; the material's 8-bit copy).
float reciprocal_lookup(const srt::Material* m, uint32_t term, const float uv[2], int c);
PassInputs pass_inputs(const srt::Material* m, float* scratch, int n, int lights, int light);
// RGBA vertex colours of one pass and light: color * E (* cos) (* profile) * scale per
// vertex, alpha 1.
void fill_pass_colors(const sepal_fmt_material& info, const sepal_fmt_pass& pass, const PassInputs& in, float scale,
                      int n, float* rgba);

// Bad vertices get zero irradiance and finite coordinates; the draws skip their triangles.
// swapped: also fill light_swapped_uv (reciprocal materials).
// The common case (iv, vh, gs-half or axis; xy or parabolic map; not swapped) runs in batches
// the compiler vectorizes, with the same results bit for bit as the one-vertex-at-a-time
// reference below, which takes everything else and every vertex the batches leave to it.
VertexSetupResult setup_vertices(sepal_param param, sepal_hemi_map map, const MeshView& mesh,
                                 const sepal_scene& scene, float* scratch, bool swapped = false);
// One vertex at a time (tests compare the batched path against it).
VertexSetupResult setup_vertices_reference(sepal_param param, sepal_hemi_map map, const MeshView& mesh,
                                           const sepal_scene& scene, float* scratch, bool swapped = false);

struct TriangleCheck {
    int skipped;    // triangles with a bad vertex (not drawn)
    int zero_area;  // triangles with repeated or collinear corners (drawn; they cover nothing)
    int bad_index;  // the first index at or past vertex_count, or -1
};
// bad_vertices: from setup_vertices (0 skips the per-corner test).
TriangleCheck check_triangles(const MeshView& mesh, int bad_vertices);

// Calls draw(first_index, index_count) for each run of consecutive triangles whose
// vertices are all usable: one call for the whole mesh when bad_vertices is 0.
template <typename Draw>
void for_each_drawable_run(const MeshView& mesh, int bad_vertices, Draw draw) {
    if (bad_vertices == 0) {
        draw(0, mesh.index_count);
        return;
    }
    int start = 0;
    for (int t = 0; t < mesh.index_count; t += 3) {
        sepal_vertex v[3];
        for (int k = 0; k < 3; ++k) mesh.load(mesh.indices[t + k], &v[k]);
        const bool ok = vertex_usable(v[0]) && vertex_usable(v[1]) && vertex_usable(v[2]);
        if (!ok) {
            if (t > start) draw(start, t - start);
            start = t + 3;
        }
    }
    if (mesh.index_count > start) draw(start, mesh.index_count - start);
}

}  // namespace srt
