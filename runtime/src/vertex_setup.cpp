// Per-vertex frames, factor texture coordinates and irradiance (see vertex_setup.h).
#include "vertex_setup.h"

#include <float.h>
#include <math.h>
#include <string.h>

namespace srt {

namespace {
constexpr float kHorizonLimit = 1e-3f;
constexpr float kHorizonSlack = 0.17364818f;  // sin 10 degrees: a 16 x 8 sphere's silhouette vertices

// One vertex, every light: the reference for the batched path below, and the path of every
// vertex it does not take (bad input, fallbacks, the eye at the vertex, overflow).
void setup_one(int i, sepal_param param, sepal_hemi_map map, const MeshView& mesh, const sepal_scene& scene,
               float* scratch, bool swapped, VertexSetupResult& r) {
    const int n = mesh.vertex_count;
    float* frames = vertex_frames(scratch, n, scene.light_count);
    sepal_vertex v;
    mesh.load(i, &v);
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
        }
        view_cosine(scratch, n, scene.light_count)[i] = 0.0f;
        return;
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

// The batched path: kBatch vertices at a time as arrays of each component, each step a loop
// of setup_one's float operations in setup_one's order, written with selects instead of
// branches so that the compiler vectorizes it (4 lanes on SSE2 or NEON; these files build
// with -O3 -fno-math-errno, see the Makefile). The results are setup_one's bit for bit
// (tests/runtime/vertex_setup_test.cpp compares them): IEEE arithmetic is the same in a
// lane as in a scalar. A lane that meets anything setup_one takes a branch for (a vertex
// that cannot be drawn, a frame or parameterization fallback, the eye or a point light at
// the vertex, an overflow) is marked and redone by setup_one.
constexpr int kBatch = 32;

struct Batch {
    // The vertices in the shading space, where the mesh is not a sepal_vertex array already.
    sepal_vertex loaded[kBatch];
    // The vertex (copied out of the mesh's interleaved layout), then its frame and wo.
    float px[kBatch], py[kBatch], pz[kBatch];
    float nx[kBatch], ny[kBatch], nz[kBatch];
    float tx[kBatch], ty[kBatch], tz[kBatch], tw[kBatch];
    float sx[kBatch], sy[kBatch], sz[kBatch];
    float wox[kBatch], woy[kBatch], woz[kBatch];
    // One light's results, before they are interleaved into the scratch layout.
    float gu[kBatch], gv[kBatch], hu[kBatch], hv[kBatch], e0[kBatch], e1[kBatch], e2[kBatch], cosine[kBatch];
    // Statistics of the lane over the lights so far (setup_one's, per lane).
    float sum[kBatch], lit_sum[kBatch], peak_max[kBatch], lit_max[kBatch];
    int below[kBatch];
    int slow[kBatch];
};

inline bool finite(float x) { return fabsf(x) <= FLT_MAX; }  // isfinite as a compare (vectorizes)

// The conditions below are combined with & on purpose: && would branch, and a loop with
// branches does not vectorize. clang warns about & between booleans with a call on one side.
#ifdef __clang__
#pragma clang diagnostic ignored "-Wbitwise-instead-of-logical"
#endif

// Frames, wo and cos(theta_o) of lanes [0, m); marks the lanes setup_one must redo.
void batch_frames(Batch& B, int m, const float eye[3]) {
    const float ex = eye[0], ey = eye[1], ez = eye[2];  // locals: no aliasing with B to rule out
    for (int j = 0; j < m; ++j) {
        // vertex_usable, then shading_frame's Gram-Schmidt (normalize3: sqrt, one divide).
        const float nn = B.nx[j] * B.nx[j] + B.ny[j] * B.ny[j] + B.nz[j] * B.nz[j];
        const bool usable = finite(B.px[j]) & finite(B.py[j]) & finite(B.pz[j]) & finite(B.nx[j]) &
                            finite(B.ny[j]) & finite(B.nz[j]) & (nn > 1e-30f);
        const float ln = sqrtf(nn);
        const float in = 1.0f / ln;
        const float n0 = B.nx[j] * in, n1 = B.ny[j] * in, n2 = B.nz[j] * in;
        const float d = B.tx[j] * n0 + B.ty[j] * n1 + B.tz[j] * n2;
        float t0 = B.tx[j] - d * n0, t1 = B.ty[j] - d * n1, t2 = B.tz[j] - d * n2;
        const float tt = t0 * t0 + t1 * t1 + t2 * t2;
        const float lt = sqrtf(tt);
        const float it = 1.0f / lt;
        t0 *= it, t1 *= it, t2 *= it;
        const float hand = B.tw[j] < 0.0f ? -1.0f : 1.0f;
        const float s0 = hand * (n1 * t2 - n2 * t1), s1 = hand * (n2 * t0 - n0 * t2), s2 = hand * (n0 * t1 - n1 * t0);
        // wo: the eye in the frame, lowered onto the horizon in setup_one's band.
        float e0 = ex - B.px[j], e1 = ey - B.py[j], e2 = ez - B.pz[j];
        const float le = sqrtf(e0 * e0 + e1 * e1 + e2 * e2);
        const float ie = 1.0f / le;
        e0 *= ie, e1 *= ie, e2 *= ie;
        const float w0 = e0 * t0 + e1 * t1 + e2 * t2, w1 = e0 * s0 + e1 * s1 + e2 * s2,
                    w2 = e0 * n0 + e1 * n1 + e2 * n2;
        const bool band = !(w2 > kHorizonLimit) & (w2 > -kHorizonSlack);
        const float lb = sqrtf(w0 * w0 + w1 * w1 + kHorizonLimit * kHorizonLimit);
        const float ib = 1.0f / lb;
        B.wox[j] = band ? w0 * ib : w0;
        B.woy[j] = band ? w1 * ib : w1;
        B.woz[j] = band ? kHorizonLimit * ib : w2;
        const bool ok = usable & (ln > 1e-20f) & finite(ln) & (tt > 1e-12f) & (lt > 1e-20f) & finite(lt) &
                        finite(B.tw[j]) & (le > 1e-20f) & finite(le) & ((!band) | ((lb > 1e-20f) & finite(lb)));
        B.slow[j] = !ok;
        B.nx[j] = n0, B.ny[j] = n1, B.nz[j] = n2;  // the raw normal is re-read from the mesh
        B.tx[j] = t0, B.ty[j] = t1, B.tz[j] = t2;
        B.sx[j] = s0, B.sy[j] = s1, B.sz[j] = s2;
        B.sum[j] = B.lit_sum[j] = B.peak_max[j] = B.lit_max[j] = 0.0f;
        B.below[j] = 0;
    }
}

// map() of param.cpp for both maps without a branch: d is the parabolic map's divisor or 1
// (pm = 1, om = 0 for parabolic, the other way round for xy; pm d + om is d or 1 exactly for
// a finite d, and x / 1 is x), so one loop serves both maps. (A select on `parabolic` itself
// would not vectorize: GCC 12 makes no lane mask of a scalar condition.)
inline void map_uv(float pm, float om, float a0, float a1, float a2, float* u, float* v) {
    float d = 1.0f + a2;
    d = d < 1e-4f ? 1e-4f : d;
    d = pm * d + om;
    *u = 0.5f * (a0 / d + 1.0f);
    *v = 0.5f * (a1 / d + 1.0f);
}

// v in param.cpp's Gram-Schmidt frame about the unit vector a (gs-half: a = h, v = wi;
// gs-mirror: a = r, v = wo); false where param.cpp takes its fallback frame (the lane is
// redone by setup_one).
inline bool gs_coords(float a0, float a1, float a2, float v0, float v1, float v2, float d[3]) {
    float p0 = a1 * a1 + a2 * a2, p1 = -a0 * a1, p2 = -a0 * a2;
    const bool ok = p0 > kGsMin2;
    const float ip = 1.0f / sqrtf(p0 * p0 + p1 * p1 + p2 * p2);
    p0 *= ip, p1 *= ip, p2 *= ip;
    const float q0 = a1 * p2 - a2 * p1, q1 = a2 * p0 - a0 * p2, q2 = a0 * p1 - a1 * p0;
    d[0] = v0 * p0 + v1 * p1 + v2 * p2;
    d[1] = v0 * q0 + v1 * q1 + v2 * q2;
    d[2] = v0 * a0 + v1 * a1 + v2 * a2;
    return ok;
}

// One light over lanes [0, m): param_texcoords (iv, vh, gs-half, axis or gs-mirror), cos(theta_i) and E,
// as setup_one computes them.
template <sepal_param P>
void batch_light_of(Batch& B, int m, const sepal_light& light, bool parabolic) {
    // light_direction without a branch: a directional light's direction is the same for every
    // vertex (normalized once; x - 0 and x * 1 are exact), a point light's is normalized here.
    const bool point = light.type == SEPAL_LIGHT_POINT;
    float dir[3] = {light.position[0], light.position[1], light.position[2]};
    if (!point) normalize3(dir);
    const float d0 = dir[0], d1 = dir[1], d2_ = dir[2], at = point ? 1.0f : 0.0f;
    const float I0 = light.intensity[0], I1 = light.intensity[1], I2 = light.intensity[2];
    const float pm = parabolic ? 1.0f : 0.0f, om = 1.0f - pm;
    for (int j = 0; j < m; ++j) {
        float l0 = d0 - at * B.px[j], l1 = d1 - at * B.py[j], l2 = d2_ - at * B.pz[j];
        const float d2 = l0 * l0 + l1 * l1 + l2 * l2;
        const float ld = sqrtf(d2);
        const float il = point ? 1.0f / ld : 1.0f;
        const float falloff = point ? 1.0f / d2 : 1.0f;
        l0 *= il, l1 *= il, l2 *= il;
        // (A directional light whose direction cannot be normalized fails this too: such a
        // lane is redone by setup_one, harmlessly.)
        bool ok = (d2 > 1e-12f) & (ld > 1e-20f) & finite(ld);
        const float wi0 = l0 * B.tx[j] + l1 * B.ty[j] + l2 * B.tz[j];
        const float wi1 = l0 * B.sx[j] + l1 * B.sy[j] + l2 * B.sz[j];
        const float wi2 = l0 * B.nx[j] + l1 * B.ny[j] + l2 * B.nz[j];
        const float wo0 = B.wox[j], wo1 = B.woy[j], wo2 = B.woz[j];
        const bool above = (wi2 > 0.0f) & (wo2 > 0.0f);
        if (P == SEPAL_PARAM_IV) {
            map_uv(pm, om, wi0, wi1, wi2, &B.gu[j], &B.gv[j]);
            map_uv(pm, om, wo0, wo1, wo2, &B.hu[j], &B.hv[j]);
        } else if (P == SEPAL_PARAM_AXIS) {  // G (alpha_i, alpha_o), H (beta_i, beta_o)
            axis_uv(wi0, wi1, wi2, &B.gu[j], &B.hu[j]);
            axis_uv(wo0, wo1, wo2, &B.gv[j], &B.hv[j]);
        } else if (P == SEPAL_PARAM_GS_MIRROR) {  // the frame about r = (-wi.x, -wi.y, wi.z)
            map_uv(pm, om, -wi0, -wi1, wi2, &B.gu[j], &B.gv[j]);
            float d[3];
            ok = ok & gs_coords(-wi0, -wi1, wi2, wo0, wo1, wo2, d);
            mirror_rim(d);
            map_uv(pm, om, d[0], d[1], d[2], &B.hu[j], &B.hv[j]);
        } else {
            float h0 = wi0 + wo0, h1 = wi1 + wo1, h2 = wi2 + wo2;
            const float lh = sqrtf(h0 * h0 + h1 * h1 + h2 * h2);
            const float ih = 1.0f / lh;
            h0 *= ih, h1 *= ih, h2 *= ih;
            ok = ok & (lh > 1e-12f) & finite(lh);
            if (P == SEPAL_PARAM_VH) {
                map_uv(pm, om, wo0, wo1, wo2, &B.gu[j], &B.gv[j]);
                map_uv(pm, om, h0, h1, h2, &B.hu[j], &B.hv[j]);
            } else {  // gs-half: param.cpp's Kautz-McCool frame
                map_uv(pm, om, h0, h1, h2, &B.gu[j], &B.gv[j]);
                float d[3];
                ok = ok & gs_coords(h0, h1, h2, wi0, wi1, wi2, d);
                map_uv(pm, om, d[0], d[1], d[2], &B.hu[j], &B.hv[j]);
            }
        }
        const float cosine = above ? wi2 : 0.0f;
        B.cosine[j] = cosine;
        // An overflow is looked for lit or not (more lanes redone, none missed): a test of the
        // selected value would be a select of conditions, which does not vectorize.
        const float f0 = I0 * falloff, f1 = I1 * falloff, f2 = I2 * falloff;
        ok = ok & (f0 <= FLT_MAX) & (f1 <= FLT_MAX) & (f2 <= FLT_MAX);
        const float e0 = above ? f0 : 0.0f, e1 = above ? f1 : 0.0f, e2 = above ? f2 : 0.0f;
        B.e0[j] = e0, B.e1[j] = e1, B.e2[j] = e2;
        float lit = e0 > 0.0f ? e0 : 0.0f;
        lit = e1 > lit ? e1 : lit;
        lit = e2 > lit ? e2 : lit;
        float peak = e0 * cosine > 0.0f ? e0 * cosine : 0.0f;
        peak = e1 * cosine > peak ? e1 * cosine : peak;
        peak = e2 * cosine > peak ? e2 * cosine : peak;
        float sum = B.sum[j] + peak, lit_sum = B.lit_sum[j] + lit;
        B.sum[j] = !(sum <= FLT_MAX) ? FLT_MAX : sum;
        B.lit_sum[j] = !(lit_sum <= FLT_MAX) ? FLT_MAX : lit_sum;
        B.peak_max[j] = peak > B.peak_max[j] ? peak : B.peak_max[j];
        B.lit_max[j] = lit > B.lit_max[j] ? lit : B.lit_max[j];
        B.below[j] += above ? 0 : 1;
        B.slow[j] |= ok ? 0 : 1;
    }
}

using BatchLight = void (*)(Batch& B, int m, const sepal_light& light, bool parabolic);

void setup_batched(BatchLight batch_light, sepal_param param, sepal_hemi_map map, const MeshView& mesh,
                   const sepal_scene& scene, float* scratch, VertexSetupResult& r, Batch& B) {
    const int n = mesh.vertex_count, lights = scene.light_count;
    float* frames = vertex_frames(scratch, n, lights);
    float* view = view_cosine(scratch, n, lights);
    for (int b = 0; b < n; b += kBatch) {
        const int m = n - b < kBatch ? n - b : kBatch;
        const sepal_vertex* vs = mesh.direct ? mesh.direct + b : B.loaded;
        if (!mesh.direct) mesh.load_range(b, m, B.loaded);
        for (int j = 0; j < m; ++j) {
            B.px[j] = vs[j].position[0], B.py[j] = vs[j].position[1], B.pz[j] = vs[j].position[2];
            B.nx[j] = vs[j].normal[0], B.ny[j] = vs[j].normal[1], B.nz[j] = vs[j].normal[2];
            B.tx[j] = vs[j].tangent[0], B.ty[j] = vs[j].tangent[1], B.tz[j] = vs[j].tangent[2];
            B.tw[j] = vs[j].tangent[3];
        }
        batch_frames(B, m, scene.camera.eye);
        for (int j = 0; j < m; ++j) {
            float* attr = frames + (size_t)kFrameFloats * (size_t)(b + j);
            for (int k = 0; k < 3; ++k) attr[k] = vs[j].normal[k];
            for (int k = 0; k < 4; ++k) attr[3 + k] = vs[j].tangent[k];
            view[b + j] = B.woz[j] > 0.0f ? B.woz[j] : 0.0f;
        }
        for (int l = 0; l < lights; ++l) {
            batch_light(B, m, scene.lights[l], map == SEPAL_MAP_PARABOLIC);
            float* g = light_g_uv(scratch, n, l) + 2 * (size_t)b;
            float* h = light_h_uv(scratch, n, l) + 2 * (size_t)b;
            float* e = light_irradiance(scratch, n, l) + 3 * (size_t)b;
            float* c = light_cosine(scratch, n, l) + b;
            for (int j = 0; j < m; ++j) {
                g[2 * j] = B.gu[j], g[2 * j + 1] = B.gv[j];
                h[2 * j] = B.hu[j], h[2 * j + 1] = B.hv[j];
                e[3 * j] = B.e0[j], e[3 * j + 1] = B.e1[j], e[3 * j + 2] = B.e2[j];
                c[j] = B.cosine[j];
            }
        }
        for (int j = 0; j < m; ++j) {
            if (B.slow[j]) {
                setup_one(b + j, param, map, mesh, scene, scratch, false, r);
                continue;
            }
            r.below_horizon += B.below[j];
            if (B.peak_max[j] > r.max_irradiance_single) r.max_irradiance_single = B.peak_max[j];
            if (B.lit_max[j] > r.max_lit_single) r.max_lit_single = B.lit_max[j];
            if (B.sum[j] > r.max_irradiance_sum) r.max_irradiance_sum = B.sum[j];
            if (B.lit_sum[j] > r.max_lit_sum) r.max_lit_sum = B.lit_sum[j];
        }
    }
}

}  // namespace

VertexSetupResult setup_vertices(sepal_param param, sepal_hemi_map map, const MeshView& mesh,
                                 const sepal_scene& scene, float* scratch, bool swapped) {
    VertexSetupResult r = {0.0f, 0.0f, 0.0f, 0.0f, 0, 0, 0, 0, 0};
    Batch batch;
    const BatchLight batch_light = param == SEPAL_PARAM_GS_HALF ? batch_light_of<SEPAL_PARAM_GS_HALF>
                                   : param == SEPAL_PARAM_VH    ? batch_light_of<SEPAL_PARAM_VH>
                                   : param == SEPAL_PARAM_IV    ? batch_light_of<SEPAL_PARAM_IV>
                                   : param == SEPAL_PARAM_AXIS  ? batch_light_of<SEPAL_PARAM_AXIS>
                                   : param == SEPAL_PARAM_GS_MIRROR ? batch_light_of<SEPAL_PARAM_GS_MIRROR>
                                                                : nullptr;
    if (batch_light && !swapped && (map == SEPAL_MAP_XY || map == SEPAL_MAP_PARABOLIC))
        setup_batched(batch_light, param, map, mesh, scene, scratch, r, batch);
    else
        for (int i = 0; i < mesh.vertex_count; ++i) setup_one(i, param, map, mesh, scene, scratch, swapped, r);
    return r;
}

VertexSetupResult setup_vertices_reference(sepal_param param, sepal_hemi_map map, const MeshView& mesh,
                                           const sepal_scene& scene, float* scratch, bool swapped) {
    VertexSetupResult r = {0.0f, 0.0f, 0.0f, 0.0f, 0, 0, 0, 0, 0};
    for (int i = 0; i < mesh.vertex_count; ++i) setup_one(i, param, map, mesh, scene, scratch, swapped, r);
    return r;
}

PassInputs pass_inputs(const srt::Material* m, float* scratch, int n, int lights, int light) {
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

float reciprocal_lookup(const srt::Material* m, uint32_t term, const float uv[2], int c) {
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
        const float s = uses_cosine ? scale * in.cosine[i] : scale * sepal_horizon_window(info.horizon, in.cosine[i]);
        float prof[3] = {1.0f, 1.0f, 1.0f};
        if (profile) diffuse_profile_rgb(in.profile, in.profile_side, SEPAL_FMT_DIFFUSE_RGB_F32, in.cosine[i], in.view_cosine[i], prof);
        for (int k = 0; k < 3; ++k) {
            float v = pass.color[k] * in.irradiance[3 * i + k] * s;
            if (profile) v *= prof[k];
            if (third) v *= reciprocal_lookup(in.material, term, in.swapped_uv + 2 * (size_t)i, k);
            rgba[4 * i + k] = v;
        }
        rgba[4 * i + 3] = 1.0f;
    }
}

TriangleCheck check_triangles(const MeshView& mesh, int bad_vertices) {
    TriangleCheck c = {0, 0, -1};
    for (int i = 0; i < mesh.index_count; ++i)
        if (mesh.indices[i] >= mesh.vertex_count) {
            c.bad_index = i;
            return c;
        }
    for (int t = 0; t + 2 < mesh.index_count; t += 3) {
        if (bad_vertices > 0) {
            sepal_vertex v[3];
            for (int k = 0; k < 3; ++k) mesh.load(mesh.indices[t + k], &v[k]);
            if (!vertex_usable(v[0]) || !vertex_usable(v[1]) || !vertex_usable(v[2])) {
                ++c.skipped;
                continue;
            }
        }
        // In object space: an affine map with det != 0 keeps zero areas zero and others not.
        const float* p[3] = {mesh.position(mesh.indices[t]), mesh.position(mesh.indices[t + 1]),
                             mesh.position(mesh.indices[t + 2])};
        float e1[3], e2[3];
        for (int k = 0; k < 3; ++k) e1[k] = p[1][k] - p[0][k], e2[k] = p[2][k] - p[0][k];
        const float cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0]};
        if (!(dot3(cr, cr) > 0.0f)) ++c.zero_area;  // as sepal_obj_load counts them
    }
    return c;
}

// Out of line and in this file's floating-point mode (no contraction): the batched and the
// one-vertex paths read vertices through this one function, so they see the same bits.
__attribute__((noinline)) void MeshView::load_range(int first, int count, sepal_vertex* out) const {
    if (direct) {
        memcpy(out, direct + first, (size_t)count * sizeof(sepal_vertex));
        return;
    }
    const unsigned char* p = attr[kPosition] + (size_t)first * stride[kPosition];
    const unsigned char* nr = attr[kNormal] + (size_t)first * stride[kNormal];
    const unsigned char* t = attr[kTangent] + (size_t)first * stride[kTangent];
    const unsigned char* uv = attr[kUv] + (size_t)first * stride[kUv];
    for (int j = 0; j < count; ++j) {
        sepal_vertex& v = out[j];
        memcpy(v.position, p + (size_t)j * stride[kPosition], sizeof v.position);
        memcpy(v.normal, nr + (size_t)j * stride[kNormal], sizeof v.normal);
        memcpy(v.tangent, t + (size_t)j * stride[kTangent], sizeof v.tangent);
        memcpy(v.uv, uv + (size_t)j * stride[kUv], sizeof v.uv);
    }
    if (!transform) return;
    for (int j = 0; j < count; ++j) {
        sepal_vertex& v = out[j];
        const float x = v.position[0], y = v.position[1], z = v.position[2];
        const float a = v.normal[0], b = v.normal[1], c = v.normal[2];
        const float tx = v.tangent[0], ty = v.tangent[1], tz = v.tangent[2];
        for (int r = 0; r < 3; ++r) {
            v.position[r] = m[r] * x + m[3 + r] * y + m[6 + r] * z + m[9 + r];
            v.normal[r] = n[r] * a + n[3 + r] * b + n[6 + r] * c;
            v.tangent[r] = m[r] * tx + m[3 + r] * ty + m[6 + r] * tz;
        }
    }
}

}  // namespace srt
