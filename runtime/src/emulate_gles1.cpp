// The GL ES 1.1 emulator (see sepal_emulate_draw in sepal_material.h): the multipass plan
// executed on the CPU with GL ES 1.1's arithmetic, for ranking bakes by what a device shows.
//
// How each GL step is modelled (llvmpipe, Mesa 22, is the reference it is tested against):
// - coverage and depth: the software rasterizer (sepal_raster.h, pixel-aligned with GL),
//   depth LESS as the pre-pass, so each pixel keeps its front-most triangle;
// - attributes: perspective-correct barycentrics of that triangle, from its homogeneous
//   clip coordinates (exact for clipped triangles too), evaluated at the pixel centre and at
//   the other pixels of its 2x2 quad (extrapolated, as GL's helper pixels are);
// - vertex colours: computed per vertex exactly as the executor fills them, clamped to [0,1]
//   (GL ES 1.1; the GL ES 2 multipass path does not clamp), then interpolated;
// - textures: 8-bit texels (16-bit rounded at upload as the runtime does), GL_LINEAR at
//   level 0 when magnified, else GL_LINEAR_MIPMAP_LINEAR with the level of detail from the
//   quad's texture-coordinate differences (rho = the longer of the x and y derivatives);
// - combiner: stage 0 colour x tex0 (x RGB_SCALE for one-texture passes), stage 1 x tex1 x
//   RGB_SCALE, each clamped to [0,1]; untextured passes are the colour alone;
// - framebuffer: n bits per channel (the desc's, 8 by default); each pass's fragment
//   rounded to 8 bits and added to the stored value widened to 8 bits with saturation (or
//   subtracted, clamped at 0), the sum truncated to n bits (llvmpipe blends an RGB565
//   buffer in 8 bits and keeps the top bits, with or without GL_DITHER); doublings,
//   inversions and stages exactly as the executor's schedule (draw_internal.h's
//   gles1_schedule), each stored the same way;
// - the background quad where no triangle covers a pixel.
// Not modelled: the one-texture-unit path and diffuse texture maps (refused).
#include <math.h>
#include <string.h>

#include "draw_internal.h"
#include "sepal/sepal_raster.h"
#include "sepal/internal/sepal_emulate.h"

namespace {

struct Coverage {
    float* tri;    // per pixel (row from the top): triangle index, or -1
    int width;
};

void record(void* user, int x, int y, float, const float* varyings) {
    Coverage& c = *static_cast<Coverage*>(user);
    c.tri[(size_t)y * (size_t)c.width + (size_t)x] = varyings[0];
}

// One texture as GL holds it: 8-bit codes per level.
struct Tex {
    const sepal_asset_texture* t;
    int levels;
    int channels;
};

inline float code(const sepal_asset_texture& t, int level, size_t idx) {
    if (t.desc.bits == 8) return (float)t.level_data[level][idx];
    uint16_t q;
    memcpy(&q, t.level_data[level] + 2 * idx, 2);
    return (float)((q * 255u + 32767u) / 65535u);  // as the upload rounds it
}

// GL_LINEAR in one level, clamp to edge; out[0..2] in [0,1] (a luminance texture: R=G=B).
void bilinear(const Tex& tx, int level, float u, float v, float out[3]) {
    const sepal_asset_texture& t = *tx.t;
    int w = (int)t.desc.width >> level, h = (int)t.desc.height >> level;
    if (w < 1) w = 1;
    if (h < 1) h = 1;
    const float x = u * (float)w - 0.5f, y = v * (float)h - 0.5f;
    const float fx = floorf(x), fy = floorf(y);
    const float ax = x - fx, ay = y - fy;
    int x0 = (int)fx, y0 = (int)fy;
    int x1 = x0 + 1, y1 = y0 + 1;
    auto clampi = [](int k, int n) { return k < 0 ? 0 : k >= n ? n - 1 : k; };
    x0 = clampi(x0, w), x1 = clampi(x1, w), y0 = clampi(y0, h), y1 = clampi(y1, h);
    const int ch = tx.channels;
    for (int c = 0; c < 3; ++c) {
        const int cc = ch == 1 ? 0 : c;
        auto at = [&](int i, int j) { return code(t, level, ((size_t)j * (size_t)w + (size_t)i) * (size_t)ch + (size_t)cc); };
        const float top = (1 - ax) * at(x0, y0) + ax * at(x1, y0);
        const float bottom = (1 - ax) * at(x0, y1) + ax * at(x1, y1);
        out[c] = ((1 - ay) * top + ay * bottom) / 255.0f;
    }
}

// GL_LINEAR_MIPMAP_LINEAR (or GL_LINEAR with one level) at level of detail lambda.
void sample(const Tex& tx, float u, float v, float lambda, float out[3]) {
    if (!(lambda > 0.0f) || tx.levels == 1) {
        bilinear(tx, 0, u, v, out);
        return;
    }
    const float top = (float)(tx.levels - 1);
    if (lambda >= top) {
        bilinear(tx, tx.levels - 1, u, v, out);
        return;
    }
    const int d = (int)floorf(lambda);
    const float frac = lambda - (float)d;
    float a[3], b[3];
    bilinear(tx, d, u, v, a);
    bilinear(tx, d + 1, u, v, b);
    for (int c = 0; c < 3; ++c) out[c] = (1 - frac) * a[c] + frac * b[c];
}

// Perspective-correct barycentrics of window positions for a triangle with clip coordinates
// c0, c1, c2: b' solves [x; y; w] b' = [ndc x; ndc y; 1], b = b' / sum(b'). The cofactors of
// that matrix are the triangle's, so they are computed once per triangle (pixels come in
// raster order, runs of one triangle) and each position costs three dot products instead
// of four determinants (four positions per pixel and pass).
struct TriangleSetup {
    int t = -1;
    bool ok = false;
    double cof[3][3];  // cof[i][k]: cofactor of element (i, k); b'_k = sum_i cof[i][k] r_i / det
    double det = 0;
    int width = 1, height = 1;

    void set(int tri, const float* c0, const float* c1, const float* c2, int w, int h) {
        t = tri;
        width = w;
        height = h;
        const double m[3][3] = {{c0[0], c1[0], c2[0]}, {c0[1], c1[1], c2[1]}, {c0[3], c1[3], c2[3]}};
        cof[0][0] = m[1][1] * m[2][2] - m[1][2] * m[2][1];
        cof[0][1] = m[1][2] * m[2][0] - m[1][0] * m[2][2];
        cof[0][2] = m[1][0] * m[2][1] - m[1][1] * m[2][0];
        cof[1][0] = m[0][2] * m[2][1] - m[0][1] * m[2][2];
        cof[1][1] = m[0][0] * m[2][2] - m[0][2] * m[2][0];
        cof[1][2] = m[0][1] * m[2][0] - m[0][0] * m[2][1];
        cof[2][0] = m[0][1] * m[1][2] - m[0][2] * m[1][1];
        cof[2][1] = m[0][2] * m[1][0] - m[0][0] * m[1][2];
        cof[2][2] = m[0][0] * m[1][1] - m[0][1] * m[1][0];
        det = m[0][0] * cof[0][0] + m[0][1] * cof[0][1] + m[0][2] * cof[0][2];
        ok = fabs(det) > 1e-30;
    }
    // Window position (wx, wy) in pixel units, y up.
    bool at(double wx, double wy, double b[3]) const {
        if (!ok) return false;
        const double nx = 2.0 * wx / width - 1.0, ny = 2.0 * wy / height - 1.0;
        double bp[3];
        for (int k = 0; k < 3; ++k) bp[k] = (cof[0][k] * nx + cof[1][k] * ny + cof[2][k]) / det;
        const double s = bp[0] + bp[1] + bp[2];
        if (!(fabs(s) > 1e-30)) return false;
        for (int k = 0; k < 3; ++k) b[k] = bp[k] / s;
        return true;
    }
};

inline float clamp01(float v) { return v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v; }
inline int to8(float v) { return (int)(clamp01(v) * 255.0f + 0.5f); }

// An 8-bit value as an n-bit channel stores it (its top n bits) and reads it back widened
// to 8 bits by repeating those bits (31 -> 255, 16 -> 132 for 5 bits): per channel, a
// table of the 256 results. 8 bits: the identity.
struct Channels {
    int bits[3];
    uint8_t stored[3][256];
    void set() {
        for (int c = 0; c < 3; ++c)
            for (int v = 0; v < 256; ++v) {
                const int n = bits[c], code = v >> (8 - n);
                int wide = 0;
                for (int filled = 0; filled < 8; filled += n) wide |= (code << (8 - n)) >> filled;
                stored[c][v] = (uint8_t)wide;
            }
    }
};

}  // namespace

extern "C" size_t sepal_emulate_scratch_floats(int width, int height, int vertex_count, int light_count) {
    if (width < 1 || height < 1 || vertex_count < 1 || light_count < 1) return 0;
    const size_t pixels = (size_t)width * (size_t)height;
    // vertex set-up, clip positions, triangle index per vertex (the rasterizer's varying),
    // depth and triangle per pixel, per-pixel 8-bit framebuffer (as floats), colours of one
    // pass for every light
    return srt::scratch_floats(vertex_count, light_count) + 4 * (size_t)vertex_count + 2 * pixels +
           4 * (size_t)vertex_count * (size_t)light_count;
}

namespace {

// Clip positions, as the GL pipeline computes them (proj * view * position); NaN for
// vertices GL would not draw.
void clip_positions(const srt::MeshView& mesh, const srt::FramePrep& prep, float* clip) {
    float mvp[16];
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) {
            float s = 0.0f;
            for (int k = 0; k < 4; ++k) s += prep.proj[k * 4 + row] * prep.view[c * 4 + k];
            mvp[c * 4 + row] = s;
        }
    for (int i = 0; i < mesh.vertex_count; ++i) {
        const float* p = mesh.position(i);  // object space, as GL takes it
        for (int row = 0; row < 4; ++row)
            clip[4 * (size_t)i + row] = mvp[row] * p[0] + mvp[4 + row] * p[1] + mvp[8 + row] * p[2] + mvp[12 + row];
        sepal_vertex v;
        mesh.load(i, &v);
        if (!srt::vertex_usable(v))
            for (int k = 0; k < 4; ++k) clip[4 * (size_t)i + k] = NAN;  // never drawn, as in GL
    }
}

// Coverage: the front-most triangle per pixel (depth LESS, as the pre-pass) into tri (-1:
// none); clear: start from a cleared depth buffer.
sepal_result coverage(const srt::MeshView& mesh, const float* clip, int W, int H, float* depth, bool clear,
                      float* tri, sepal_error* err) {
    for (size_t p = 0; p < (size_t)W * H; ++p) tri[p] = -1.0f;
    sepal_raster_target target = {W, H, depth};
    if (clear) sepal_raster_clear_depth(&target);
    Coverage cov = {tri, W};
    const int tris = mesh.index_count / 3;
    for (int t = 0; t < tris; ++t) {
        const uint16_t* idx = mesh.indices + 3 * t;
        float local_clip[12], var[3];
        for (int k = 0; k < 3; ++k) {
            memcpy(local_clip + 4 * k, clip + 4 * (size_t)idx[k], 4 * sizeof(float));
            var[k] = (float)t;  // constant over the triangle: exact after interpolation
        }
        static const uint16_t kLocal[3] = {0, 1, 2};
        sepal_raster_desc rd = {};
        rd.clip = local_clip;
        rd.vertex_count = 3;
        rd.varyings = var;
        rd.varying_count = 1;
        rd.varying_stride = 1;
        rd.indices = kLocal;
        rd.index_count = 3;
        rd.cull = SEPAL_CULL_BACK;
        rd.depth_func = SEPAL_DEPTH_LESS;
        rd.fragment = record;
        rd.user = &cov;
        if (const sepal_result r = sepal_raster_triangles(&target, &rd, err)) return r;
    }
    return SEPAL_OK;
}

// Step list for GL ES 2 multipass: the plan's order, inversion around subtractions, the
// frame's doublings at the end (draw_gles2's multipass + final doublings). Returns the count.
int gles2_steps(const srt::Material& m, float exposure, int doublings, srt::Gles1Step* steps) {
    int k = 0;
    bool inverted = false;
    for (uint32_t p = 0; p < m.plan.pass_count; ++p) {
        if (m.passes[p].blend == SEPAL_BLEND_SUBTRACT && m.subtract_by_inversion && !inverted) {
            steps[k++] = {srt::Gles1Step::kInvert, 0, 0, 0.0f, false};
            inverted = true;
        }
        steps[k++] = {srt::Gles1Step::kPass, 0, (uint16_t)p, exposure, inverted};
    }
    if (inverted) steps[k++] = {srt::Gles1Step::kInvert, 0, 0, 0.0f, true};
    steps[k++] = {srt::Gles1Step::kDouble, doublings, 0, 0.0f, false};
    return k;
}

// Doublings and inversions: drawn over the object's mesh, its pixels only, each result
// stored at the framebuffer's bits.
void fullscreen_step(const srt::Gles1Step& step, const float* tri, size_t pixels, const Channels& fbc, uint8_t* fb) {
    for (size_t p = 0; p < pixels; ++p)
        for (int c = 0; c < 3 && tri[p] >= 0.0f; ++c) {
            int v = fb[4 * p + c];
            if (step.kind == srt::Gles1Step::kInvert) v = fbc.stored[c][255 - v];
            else for (int k = 0; k < step.count && v < 255; ++k) v = fbc.stored[c][v * 2 > 255 ? 255 : v * 2];
            fb[4 * p + c] = (uint8_t)v;
        }
}

// The context the emulator stands for: two units on GL ES 1.1, the mask's capabilities off.
sepal_caps emulated_caps(const sepal_emulate_desc* e, const Channels& fbc) {
    sepal_caps caps = {};
    caps.gles_version = e->gles_version;
    caps.texture_units = e->gles_version == 2 ? 8 : 2;
    caps.max_texture_size = 8192;
    caps.has_blend_subtract = (e->mask & SEPAL_MASK_BLEND_SUBTRACT) ? 0 : 1;
    caps.has_fbo = (e->mask & SEPAL_MASK_FBO) ? 0 : 1;
    caps.mask = e->mask;
    caps.red_bits = fbc.bits[0], caps.green_bits = fbc.bits[1], caps.blue_bits = fbc.bits[2];
    return caps;
}

// The 8-bit sum's write (srt::accumulates): the object's pixels (those in front), each k v + h
// of its sum v (the combiner stages clamp), stored at the framebuffer's bits.
void write_sum(const Channels& fbc, const float* tri, size_t pixels, uint8_t* fb) {
    uint8_t written[3][256];  // per channel, what each 8-bit sum becomes
    for (int c = 0; c < 3; ++c) {
        const float k = srt::write_scale(fbc.bits[c]), h = srt::write_bias(fbc.bits[c]);
        for (int v = 0; v < 256; ++v) written[c][v] = fbc.stored[c][to8(clamp01(v / 255.0f * k) + h)];
    }
    for (size_t p = 0; p < pixels; ++p)
        if (tri[p] >= 0.0f)
            for (int c = 0; c < 3; ++c) fb[4 * p + c] = written[c][fb[4 * p + c]];
}

// The desc's version, mask, size and framebuffer bits (0 means 8), checked; out gets the bits'
// tables.
sepal_result check_desc(const sepal_emulate_desc* e, Channels* out, sepal_error* err) {
    if (e->gles_version != 1 && e->gles_version != 2)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "emulate: gles_version %d (1 or 2)", e->gles_version);
    if (e->mask & SEPAL_MASK_MULTITEXTURE)
        return srt::fail(err, SEPAL_ERR_UNSUPPORTED, "emulate: the one-texture-unit path is not emulated");
    if (e->width < 1 || e->height < 1 || e->width > 8192 || e->height > 8192)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "emulate: %dx%d out of 1..8192", e->width, e->height);
    const int given[3] = {e->red_bits, e->green_bits, e->blue_bits};
    for (int c = 0; c < 3; ++c) {
        out->bits[c] = given[c] == 0 ? 8 : given[c];
        if (out->bits[c] < 1 || out->bits[c] > 8)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "emulate: framebuffer bits %d/%d/%d (each 1..8, or 0 for 8)", given[0], given[1], given[2]);
    }
    out->set();
    return SEPAL_OK;
}

// One object: mesh its vertices (e->mesh is not read), e->scene in its shading space,
// modelview and proj its matrices. keep: the frame's depth (kept_depth) and colour stay
// where the object is not in front; otherwise the framebuffer starts cleared and gets the
// scene's background where nothing is drawn.
sepal_result emulate_object(const sepal_emulate_desc* e, const srt::MeshView& mesh, const float modelview[16],
                            const float proj[16], float* kept_depth, sepal_error* err) {
    const bool keep = kept_depth != nullptr;
    Channels fbc;
    if (const sepal_result checked = check_desc(e, &fbc, err)) return checked;
    const int W = e->width, H = e->height;
    const int n = mesh.vertex_count, lights = e->scene->light_count;
    const size_t need = sepal_emulate_scratch_floats(W, H, n, lights);
    if (need == 0 || e->scratch_floats < need)
        return srt::fail(err, SEPAL_ERR_CAPACITY, "emulate: scratch holds %zu floats, needs %zu", e->scratch_floats,
                         need);
    // The material as the executor would see it, without GL objects.
    const sepal_caps caps = emulated_caps(e, fbc);
    // Fewer than 8 bits: the executor sums the passes in an 8-bit target (srt::accumulates)
    // and writes the sum once, rounded; the passes then see 8 bits.
    const bool accumulated = srt::accumulates(caps, false);
    Channels pass_fbc = fbc;
    if (accumulated) pass_fbc.bits[0] = pass_fbc.bits[1] = pass_fbc.bits[2] = 8, pass_fbc.set();
    srt::Material m;
    sepal_result r = srt::material_plan(&caps, e->asset, W, H, &m, err);
    if (r != SEPAL_OK) return r;
    float* vscratch = e->scratch;
    float* clip = vscratch + srt::scratch_floats(n, lights);
    float* depth = keep ? kept_depth : clip + 4 * (size_t)n;
    float* tri = clip + 4 * (size_t)n + (size_t)W * H;
    float* colors = tri + (size_t)W * H;  // 4 n per light: the current pass's vertex colours
    sepal_draw_desc d = {};
    d.material = srt::storage(&m);
    d.scene = e->scene;
    d.width = W;
    d.height = H;
    d.scratch = vscratch;
    d.scratch_floats = srt::scratch_floats(n, lights);
    d.mode = SEPAL_MODE_MULTIPASS;
    srt::FramePrep prep;
    sepal_draw_stats local;
    sepal_draw_stats* stats = e->stats ? e->stats : &local;
    if ((r = srt::prepare_frame(&d, mesh, modelview, proj, false, &prep, stats, err)) != SEPAL_OK) return r;
    clip_positions(mesh, prep, clip);
    if ((r = coverage(mesh, clip, W, H, depth, !keep, tri, err)) != SEPAL_OK) return r;
    // Textures as GL holds them.
    Tex tex[SEPAL_FMT_MAX_TEXTURES];
    for (uint32_t i = 0; i < e->asset->texture_count; ++i)
        tex[i] = {&e->asset->textures[i], (int)e->asset->textures[i].desc.levels,
                  (int)e->asset->textures[i].desc.channels};
    srt::Gles1Step steps[srt::kMaxGles1Steps];
    int step_count = e->gles_version == 1 ? srt::gles1_schedule(&m, prep, stats->doublings, steps) : 0;
    const bool clamp_colors = e->gles_version == 1;
    const float* bg = e->scene->background;
    const bool background = bg[0] > 0.0f || bg[1] > 0.0f || bg[2] > 0.0f;
    // Per light and pass, the vertex colours; computed pass by pass below. Pixels are then
    // independent: every GL operation of the plan is per pixel (blending, full-screen
    // doublings and inversions), so each pixel runs the whole schedule.
    if (e->gles_version == 2) step_count = gles2_steps(m, prep.exposure, stats->doublings, steps);
    // The framebuffer: per channel the stored value widened to 8 bits (fbc says how).
    // The object's pixels start from 0 (the black pre-pass, or the first pass replacing);
    // the rest is kept (a frame) or cleared (sepal_emulate_draw).
    uint8_t* fb = e->rgba;
    for (size_t p = 0; p < (size_t)W * H; ++p)
        if (!keep || tri[p] >= 0.0f) fb[4 * p] = fb[4 * p + 1] = fb[4 * p + 2] = 0, fb[4 * p + 3] = 255;
    for (int s = 0; s < step_count; ++s) {
        const srt::Gles1Step& step = steps[s];
        if (step.kind != srt::Gles1Step::kPass) {
            fullscreen_step(step, tri, (size_t)W * H, pass_fbc, fb);
            continue;
        }
        const sepal_fmt_pass& pass = m.passes[step.pass];
        const int textures = srt::pass_texture_count(pass);
        // GL ES 1.1: colour / boost, and the boost back in the last combiner stage; GL ES 2:
        // the colour as it is, times rgb_scale in the shader.
        const float boost = e->gles_version == 1 ? srt::pass_color_boost(pass, m.texture_count) : 1.0f;
        const float stage_scale = e->gles_version == 1 ? (float)pass.rgb_scale * boost : (float)pass.rgb_scale;
        for (int l = 0; l < lights; ++l) {
            float* c = colors + 4 * (size_t)n * l;
            srt::fill_pass_colors(m.info, pass, srt::pass_inputs(&m, vscratch, n, lights, l), step.exposure / boost, n, c);
            if (clamp_colors)
                for (size_t k = 0; k < 4 * (size_t)n; ++k) c[k] = clamp01(c[k]);
        }
        const bool subtract = pass.blend == SEPAL_BLEND_SUBTRACT && !step.inverted;
        TriangleSetup setup;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const size_t p = (size_t)y * W + x;
                const int t = (int)tri[p];
                if (t < 0) continue;
                const uint16_t* idx = mesh.indices + 3 * t;
                if (t != setup.t)
                    setup.set(t, clip + 4 * (size_t)idx[0], clip + 4 * (size_t)idx[1], clip + 4 * (size_t)idx[2], W, H);
                // Window coordinates (y up) of the pixel and of its 2x2 quad's corner.
                const int wy = H - 1 - y;
                const int qx = x & ~1, qy = wy & ~1;
                double b[3], bx[3], by[3], bq[3];
                if (!setup.at(x + 0.5, wy + 0.5, b)) continue;
                const bool quad = setup.at(qx + 0.5, qy + 0.5, bq) && setup.at(qx + 1.5, qy + 0.5, bx) &&
                                  setup.at(qx + 0.5, qy + 1.5, by);
                for (int l = 0; l < lights; ++l) {
                    const float* cl = colors + 4 * (size_t)n * l;
                    float value[3];
                    for (int ch = 0; ch < 3; ++ch)
                        value[ch] = (float)(b[0] * cl[4 * idx[0] + ch] + b[1] * cl[4 * idx[1] + ch] +
                                            b[2] * cl[4 * idx[2] + ch]);
                    for (int unit = 0; unit < textures || unit == 0; ++unit) {
                        if (unit >= textures) {  // untextured: colour x the stage's scale, clamped
                            for (int ch = 0; ch < 3; ++ch) value[ch] = clamp01(value[ch] * stage_scale);
                            break;
                        }
                        const uint16_t ti = unit == 0 ? pass.tex0 : pass.tex1;
                        const float* uv = m.texture_role[ti] == SEPAL_ROLE_G ? srt::light_g_uv(vscratch, n, l)
                                                                            : srt::light_h_uv(vscratch, n, l);
                        auto at = [&](const double* w, int k) {
                            return (float)(w[0] * uv[2 * idx[0] + k] + w[1] * uv[2 * idx[1] + k] + w[2] * uv[2 * idx[2] + k]);
                        };
                        float lambda = 0.0f;
                        if (quad && tex[ti].levels > 1) {
                            const float tw = (float)tex[ti].t->desc.width, th = (float)tex[ti].t->desc.height;
                            const float dux = (at(bx, 0) - at(bq, 0)) * tw, dvx = (at(bx, 1) - at(bq, 1)) * th;
                            const float duy = (at(by, 0) - at(bq, 0)) * tw, dvy = (at(by, 1) - at(bq, 1)) * th;
                            const float rho2 = fmaxf(dux * dux + dvx * dvx, duy * duy + dvy * dvy);
                            lambda = rho2 > 0.0f ? 0.5f * log2f(rho2) : 0.0f;
                        }
                        float texel[3];
                        sample(tex[ti], at(b, 0), at(b, 1), lambda, texel);
                        // The last textured stage scales. GL ES 1.1 clamps each combiner stage;
                        // the GL ES 2 shader computes in float and only its output clamps.
                        const bool last = unit == textures - 1;
                        const float scale = last ? stage_scale : 1.0f;
                        for (int ch = 0; ch < 3; ++ch) {
                            value[ch] = value[ch] * texel[ch] * scale;
                            if (clamp_colors || last) value[ch] = clamp01(value[ch]);
                        }
                    }
                    for (int ch = 0; ch < 3; ++ch) {
                        const int src = to8(value[ch]);
                        int v = fb[4 * p + ch];
                        v = subtract ? (v - src < 0 ? 0 : v - src) : (v + src > 255 ? 255 : v + src);
                        fb[4 * p + ch] = pass_fbc.stored[ch][v];
                    }
                }
            }
    }
    if (accumulated) write_sum(fbc, tri, (size_t)W * H, fb);
    if (background && !keep)
        for (size_t p = 0; p < (size_t)W * H; ++p)
            if (tri[p] < 0.0f)
                for (int c = 0; c < 3; ++c) fb[4 * p + c] = fbc.stored[c][to8(bg[c])];
    return srt::ok(err);
}

}  // namespace

extern "C" sepal_result sepal_emulate_draw(const sepal_emulate_desc* e, sepal_error* err) {
    if (!e || !e->asset || !e->mesh || !e->scene || !e->rgba || !e->scratch)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "emulate: NULL asset, mesh, scene, output or scratch");
    float view[16], proj[16];
    const sepal_result r = sepal_scene_matrices(e->scene, e->width, e->height, view, proj, err);
    if (r != SEPAL_OK) return r;
    return emulate_object(e, srt::MeshView(*e->mesh), view, proj, nullptr, err);
}

extern "C" sepal_result sepal_frame_emulate(const sepal_frame_desc* f, const sepal_object* o, int gles_version,
                                           uint32_t mask, uint8_t* rgba, float* depth, float* scratch,
                                           size_t scratch_floats, sepal_draw_stats* stats, sepal_error* err) {
    if (!f || !o || !o->asset || !rgba || !depth || !scratch)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "emulate: NULL frame, object, asset or buffer");
    srt::ObjectSpace space;
    srt::MeshView mesh;
    sepal_result r = srt::object_view(f->view, *o, &space, &mesh, err);
    if (r != SEPAL_OK) return r;
    sepal_emulate_desc e = {};
    e.asset = o->asset;
    e.scene = &space.scene;
    e.width = f->viewport[2];
    e.height = f->viewport[3];
    e.gles_version = gles_version;
    e.mask = mask;
    e.rgba = rgba;
    e.scratch = scratch;
    e.scratch_floats = scratch_floats;
    e.stats = stats;
    return emulate_object(&e, mesh, space.modelview, f->projection, depth, err);
}
