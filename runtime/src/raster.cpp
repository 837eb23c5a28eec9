// Software rasterizer with GL's conventions (see sepal_raster.h for the rules).
#include <math.h>
#include <string.h>

#include "internal.h"
#include "sepal/sepal_raster.h"

namespace {

constexpr int kSubBits = 8;  // 1/256 pixel, as Mesa's llvmpipe snaps vertices
constexpr int64_t kSub = int64_t(1) << kSubBits;
constexpr int kMaxClipVerts = 9;  // 3 + one per clip plane
// Guard band: x and y are clipped at |x| <= kGuard w so snapped coordinates stay small.
constexpr float kGuard = 4.0f;

struct ClipVertex {
    float pos[4];
    float var[SEPAL_RASTER_MAX_VARYINGS];
};

// Plane distance: inside when >= 0. Plane 0 is GL's near plane z >= -w.
float plane_distance(int plane, const float* p) {
    switch (plane) {
        case 0: return p[2] + p[3];
        case 1: return kGuard * p[3] - p[0];
        case 2: return kGuard * p[3] + p[0];
        case 3: return kGuard * p[3] - p[1];
        default: return kGuard * p[3] + p[1];
    }
}

// Sutherland-Hodgman against one plane; returns the new vertex count.
int clip_polygon(int plane, const ClipVertex* in, int n, ClipVertex* out, int nvar) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
        const ClipVertex& a = in[i];
        const ClipVertex& b = in[(i + 1) % n];
        const float da = plane_distance(plane, a.pos), db = plane_distance(plane, b.pos);
        if (da >= 0) out[m++] = a;
        if ((da >= 0) != (db >= 0)) {
            const float t = da / (da - db);
            ClipVertex& c = out[m++];
            for (int k = 0; k < 4; ++k) c.pos[k] = a.pos[k] + t * (b.pos[k] - a.pos[k]);
            for (int k = 0; k < nvar; ++k) c.var[k] = a.var[k] + t * (b.var[k] - a.var[k]);
        }
    }
    return m;
}

struct WindowVertex {
    int64_t x, y;     // snapped window position, 1/kSub pixel
    float z;          // window depth
    float inv_w;
    const float* var;  // varyings (from the clipped polygon)
};

// Whether samples exactly on edge a->b of a counter-clockwise (y up) triangle belong to
// it: left edges (going down) and bottom edges (horizontal, going right) do.
bool edge_owns_ties(const WindowVertex& a, const WindowVertex& b) {
    return b.y < a.y || (b.y == a.y && b.x > a.x);
}

void draw_triangle(sepal_raster_target* t, const sepal_raster_desc* d, WindowVertex v0,
                   WindowVertex v1, WindowVertex v2) {
    int64_t area = (v1.x - v0.x) * (v2.y - v0.y) - (v2.x - v0.x) * (v1.y - v0.y);
    if (area == 0) return;  // zero-area triangles draw nothing, as in GL
    if (area < 0) {
        if (d->cull == SEPAL_CULL_BACK) return;
        WindowVertex tmp = v1;  // make it counter-clockwise; attributes travel along
        v1 = v2;
        v2 = tmp;
        area = -area;
    }
    const WindowVertex* v[3] = {&v0, &v1, &v2};
    int64_t min_x = v0.x, max_x = v0.x, min_y = v0.y, max_y = v0.y;
    for (int i = 1; i < 3; ++i) {
        if (v[i]->x < min_x) min_x = v[i]->x;
        if (v[i]->x > max_x) max_x = v[i]->x;
        if (v[i]->y < min_y) min_y = v[i]->y;
        if (v[i]->y > max_y) max_y = v[i]->y;
    }
    // Pixels whose centre (px + 0.5) may lie inside the box.
    int x0 = (int)((min_x - kSub / 2 + (kSub - 1)) >> kSubBits);
    int x1 = (int)((max_x - kSub / 2) >> kSubBits);
    int y0 = (int)((min_y - kSub / 2 + (kSub - 1)) >> kSubBits);
    int y1 = (int)((max_y - kSub / 2) >> kSubBits);
    if (x0 < 0) x0 = 0;
    if (y0 < 0) y0 = 0;
    if (x1 > t->width - 1) x1 = t->width - 1;
    if (y1 > t->height - 1) y1 = t->height - 1;
    // Edge i is opposite vertex i: e0 = v1->v2, e1 = v2->v0, e2 = v0->v1.
    const WindowVertex* ea[3] = {&v1, &v2, &v0};
    const WindowVertex* eb[3] = {&v2, &v0, &v1};
    int64_t tie[3];
    for (int i = 0; i < 3; ++i) tie[i] = edge_owns_ties(*ea[i], *eb[i]) ? 0 : 1;
    const double inv_area = 1.0 / (double)area;
    const int nvar = d->varying_count;
    float out[SEPAL_RASTER_MAX_VARYINGS];
    // Edge functions stepped per pixel: the same exact integers as evaluating each from
    // scratch (a row starts from scratch; x steps add (ea.y - eb.y) pixels), a third of the
    // work in the loop that dominated planner and CPU-backend time.
    int64_t step[3];
    for (int i = 0; i < 3; ++i) step[i] = (ea[i]->y - eb[i]->y) * kSub;
    const int64_t sx0 = ((int64_t)x0 << kSubBits) + kSub / 2;
    for (int py = y0; py <= y1; ++py) {
        const int64_t sy = ((int64_t)py << kSubBits) + kSub / 2;
        int64_t r[3];  // e[i] - tie[i] at (px, py): the pixel is inside when all three are >= 0
        for (int i = 0; i < 3; ++i)
            r[i] = (eb[i]->x - ea[i]->x) * (sy - ea[i]->y) - (eb[i]->y - ea[i]->y) * (sx0 - ea[i]->x) - tie[i];
        bool entered = false;
        for (int px = x0; px <= x1; ++px, r[0] += step[0], r[1] += step[1], r[2] += step[2]) {
            if ((r[0] | r[1] | r[2]) < 0) {
                if (entered) break;  // a triangle is convex: past its right edge, nothing more
                continue;
            }
            entered = true;
            const int64_t e[3] = {r[0] + tie[0], r[1] + tie[1], r[2] + tie[2]};
            const double b0 = (double)e[0] * inv_area, b1 = (double)e[1] * inv_area,
                         b2 = (double)e[2] * inv_area;
            const float z = (float)(b0 * v0.z + b1 * v1.z + b2 * v2.z);
            float& stored = t->depth[(size_t)py * (size_t)t->width + (size_t)px];
            const bool pass = d->depth_func == SEPAL_DEPTH_ALWAYS ||
                              (d->depth_func == SEPAL_DEPTH_LESS ? z < stored : z <= stored);
            if (!pass) continue;
            if (!d->no_depth_write) stored = z;
            // Perspective-correct: interpolate v/w and 1/w linearly in screen space.
            const double p0 = b0 * v0.inv_w, p1 = b1 * v1.inv_w, p2 = b2 * v2.inv_w;
            const double q = 1.0 / (p0 + p1 + p2);
            for (int k = 0; k < nvar; ++k)
                out[k] = (float)((p0 * v0.var[k] + p1 * v1.var[k] + p2 * v2.var[k]) * q);
            d->fragment(d->user, px, t->height - 1 - py, z, out);
        }
    }
}

}  // namespace

extern "C" void sepal_raster_clear_depth(sepal_raster_target* t) {
    if (!t || !t->depth || t->width < 1 || t->height < 1 || t->width > 8192 || t->height > 8192) return;
    const size_t n = (size_t)t->width * (size_t)t->height;
    for (size_t i = 0; i < n; ++i) t->depth[i] = 1.0f;
}

extern "C" sepal_result sepal_raster_triangles(sepal_raster_target* t, const sepal_raster_desc* d,
                                           sepal_error* err) {
    if (!t || !t->depth || !d || !d->clip || !d->indices || !d->fragment)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "raster: target, depth, clip positions, indices or fragment is NULL");
    if (t->width < 1 || t->height < 1 || t->width > 8192 || t->height > 8192)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "raster: target %dx%d out of range",
                         t->width, t->height);
    if (d->varying_count < 0 || d->varying_count > SEPAL_RASTER_MAX_VARYINGS ||
        (d->varying_count > 0 && (!d->varyings || d->varying_stride < d->varying_count)))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "raster: %d varyings (stride %d): at most %d, stride >= count",
                         d->varying_count, d->varying_stride, SEPAL_RASTER_MAX_VARYINGS);
    if (d->index_count % 3 != 0 || d->vertex_count < 0 || d->vertex_count > 65535)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "raster: %d indices (not a multiple of 3) or %d vertices", d->index_count,
                         d->vertex_count);
    for (int i = 0; i < d->index_count; ++i)
        if (d->indices[i] >= d->vertex_count)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "raster: index %d refers to vertex %d of %d", i, d->indices[i],
                             d->vertex_count);
    const int nvar = d->varying_count;
    const float half_w = 0.5f * (float)t->width, half_h = 0.5f * (float)t->height;
    for (int tri = 0; tri < d->index_count; tri += 3) {
        ClipVertex poly_a[kMaxClipVerts], poly_b[kMaxClipVerts];
        bool finite = true;
        for (int k = 0; k < 3; ++k) {
            const int vi = d->indices[tri + k];
            memcpy(poly_a[k].pos, d->clip + 4 * vi, 4 * sizeof(float));
            for (int c = 0; c < 4; ++c) finite = finite && isfinite(poly_a[k].pos[c]);
            for (int c = 0; c < nvar; ++c) poly_a[k].var[c] = d->varyings[(size_t)vi * d->varying_stride + c];
        }
        if (!finite) continue;  // a broken vertex draws nothing rather than garbage
        int n = 3;
        ClipVertex* in = poly_a;
        ClipVertex* out = poly_b;
        for (int plane = 0; plane < 5 && n >= 3; ++plane) {
            n = clip_polygon(plane, in, n, out, nvar);
            ClipVertex* swap = in;
            in = out;
            out = swap;
        }
        if (n < 3) continue;
        WindowVertex w[kMaxClipVerts];
        bool ok = true;
        for (int k = 0; k < n; ++k) {
            const float* p = in[k].pos;
            if (!(p[3] > 0.0f)) {
                ok = false;
                break;
            }
            const float inv_w = 1.0f / p[3];
            const double wx = ((double)p[0] * inv_w + 1.0) * half_w;
            const double wy = ((double)p[1] * inv_w + 1.0) * half_h;
            w[k].x = (int64_t)llround(wx * (double)kSub);
            w[k].y = (int64_t)llround(wy * (double)kSub);
            w[k].z = 0.5f * (p[2] * inv_w + 1.0f);
            w[k].inv_w = inv_w;
            w[k].var = in[k].var;
        }
        if (!ok) continue;
        for (int k = 1; k + 1 < n; ++k) draw_triangle(t, d, w[0], w[k], w[k + 1]);
    }
    return srt::ok(err);
}
