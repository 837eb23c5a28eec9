// Inverse shade trees at run time (sepal_tree.h): parsing, creation, the composition of
// the bases' draws, and the CPU backend. The GL pieces live in tree_gl.cpp (shared), tree_gles1.cpp and
// tree_gles2.cpp.
#include <math.h>
#include <string.h>

#include "tree_internal.h"

static_assert(sizeof(sepal_tree_header) == 64, "tree header layout");
static_assert(sizeof(sepal_tree_basis) == 32, "tree basis layout");

namespace {

bool is_pow2(uint32_t v) { return v && !(v & (v - 1)); }

void add_stats(sepal_draw_stats* sum, const sepal_draw_stats& s, bool first) {
    sum->draw_calls += s.draw_calls;
    sum->fullscreen_passes += s.fullscreen_passes;
    sum->copies += s.copies;
    sum->doublings += s.doublings;
    if (first) sum->exposure = s.exposure, sum->exposure_stages = s.exposure_stages;
    sum->below_horizon += s.below_horizon;
    sum->dim_lights += s.dim_lights;
    sum->weaker_context += s.weaker_context;
    sum->fallback_tangents += s.fallback_tangents;
    sum->bad_vertices += s.bad_vertices;
    sum->skipped_triangles += s.skipped_triangles;
    sum->zero_area_triangles += s.zero_area_triangles;
    sum->param_fallbacks += s.param_fallbacks;
    sum->exposure_clamped |= s.exposure_clamped;
    sum->nonfinite_clamped += s.nonfinite_clamped;
    sum->negative_clamped += s.negative_clamped;
    sum->pixel_frame_fallbacks += s.pixel_frame_fallbacks;
}

}  // namespace

extern "C" sepal_result sepal_tree_parse(const void* bytes, size_t size, sepal_tree_asset* out, sepal_error* err) {
    if (!out || !bytes) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "tree: NULL argument");
    memset(out, 0, sizeof *out);
    if (size < sizeof(sepal_tree_header))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "tree: %zu bytes is too short for the 64-byte header", size);
    const uint8_t* base = (const uint8_t*)bytes;
    sepal_tree_header& h = out->header;
    memcpy(&h, base, sizeof h);
    if (memcmp(h.magic, SEPAL_TREE_MAGIC, 8) != 0)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "tree: bad magic (not a .sepaltree file)");
    if (h.version_major != SEPAL_TREE_VERSION_MAJOR)
        return srt::fail(err, SEPAL_ERR_UNSUPPORTED, "tree: format version %u.%u; this runtime reads %d.x",
                         h.version_major, h.version_minor, SEPAL_TREE_VERSION_MAJOR);
    if (h.header_bytes != sizeof h || h.file_bytes != size || size > SEPAL_TREE_MAX_FILE_BYTES)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "tree: header says %llu bytes (header %u), the buffer holds %zu (at most %u)",
                         (unsigned long long)h.file_bytes, h.header_bytes, size, SEPAL_TREE_MAX_FILE_BYTES);
    // The checksum over the whole file, its own field counted as 0.
    const size_t crc_at = offsetof(sepal_tree_header, crc);
    const uint8_t zero[4] = {0, 0, 0, 0};
    uint32_t crc = sepal_crc32(0, base, crc_at);
    crc = sepal_crc32(crc, zero, 4);
    crc = sepal_crc32(crc, base + crc_at + 4, size - crc_at - 4);
    if (crc != h.crc)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "tree: checksum mismatch (corrupt file): 0x%08x, expected 0x%08x",
                         crc, h.crc);
    if (h.basis_count < 1 || h.basis_count > SEPAL_TREE_MAX_BASES)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "tree: %u bases, outside 1..%d", h.basis_count,
                         SEPAL_TREE_MAX_BASES);
    if (!is_pow2(h.blend_width) || !is_pow2(h.blend_height) || h.blend_width > SEPAL_TREE_MAX_BLEND_SIDE ||
        h.blend_height > SEPAL_TREE_MAX_BLEND_SIDE)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "tree: blend maps %ux%u; powers of two up to %d",
                         h.blend_width, h.blend_height, SEPAL_TREE_MAX_BLEND_SIDE);
    for (uint32_t r = 0; r < 6; ++r)
        if (h.reserved[r]) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "tree: reserved header field %u not 0", r);
    const uint64_t table_end = sizeof h + (uint64_t)h.basis_count * sizeof(sepal_tree_basis);
    if (table_end > size) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "tree: basis table runs past the file");
    memcpy(out->table, base + sizeof h, h.basis_count * sizeof(sepal_tree_basis));
    const uint64_t blend_bytes = (uint64_t)h.blend_width * h.blend_height;
    for (uint32_t j = 0; j < h.basis_count; ++j) {
        const sepal_tree_basis& b = out->table[j];
        if (b.asset_offset % 8 || b.asset_offset < table_end || b.asset_bytes > size ||
            b.asset_offset > size - b.asset_bytes || b.blend_offset < table_end || b.blend_offset > size ||
            blend_bytes > size - b.blend_offset)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "tree: basis %u's asset or blend map lies outside the file", j);
        if (!isfinite(b.blend_scale) || b.blend_scale < 0 || b.reserved)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "tree: basis %u: bad blend scale or reserved field", j);
        sepal_error inner = {};
        if (sepal_asset_parse(base + b.asset_offset, (size_t)b.asset_bytes, &out->bases[j], &inner) != SEPAL_OK)
            return srt::fail(err, inner.code, "tree: basis %u: %s", j, inner.message);
        out->blend[j] = base + b.blend_offset;
    }
    return srt::ok(err);
}

extern "C" sepal_result sepal_tree_create(const sepal_caps* caps, const sepal_tree_asset* asset, int max_width,
                                          int max_height, sepal_tree* out, sepal_error* err) {
    if (!caps || !asset || !out) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "tree: NULL argument");
    memset(out, 0, sizeof *out);
    out->caps = *caps;
    out->max_width = max_width;
    out->max_height = max_height;
    for (uint32_t j = 0; j < asset->header.basis_count; ++j) {
        sepal_result r = sepal_material_create(caps, &asset->bases[j], max_width, max_height, &out->bases[j], err);
        if (r != SEPAL_OK) {
            sepal_tree_destroy(out);
            return r;
        }
        out->basis_count = j + 1;
    }
    sepal_result r = caps->gles_version == 1 ? srt::tree_create_textures(asset, out, err) : srt::tree_create_gles2(asset, out, err);
    if (r != SEPAL_OK) {
        sepal_tree_destroy(out);
        return r;
    }
    return srt::ok(err);
}

extern "C" void sepal_tree_destroy(sepal_tree* t) {
    if (!t) return;
    if (t->caps.gles_version == 1) srt::tree_destroy_textures(t);
    else srt::tree_destroy_gles2(t);
    for (uint32_t j = 0; j < t->basis_count; ++j) sepal_material_destroy(&t->bases[j]);
    t->basis_count = 0;
}

extern "C" sepal_result sepal_tree_draw(const sepal_tree_draw_desc* d, sepal_draw_stats* stats, sepal_error* err) {
    if (!d || !d->tree || !d->mesh || !d->scene)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "tree draw: NULL argument");
    const sepal_tree* t = d->tree;
    if (d->width < 1 || d->height < 1 || d->width > t->max_width || d->height > t->max_height)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "tree draw: viewport %dx%d outside 1..%dx%d", d->width,
                         d->height, t->max_width, t->max_height);
    sepal_draw_stats sum = {};
    if (d->mode == SEPAL_MODE_FUSED_PIXEL) {
        if (t->caps.gles_version != 2 || !t->program_fused)
            return srt::fail(err, SEPAL_ERR_UNSUPPORTED, "tree draw: no fused tree shader (%s)",
                             t->caps.gles_version != 2 ? "GL ES 2 only" : t->fused_reason);
        sepal_result r = srt::tree_draw_fused_gles2(d, &sum, err);
        if (stats) *stats = sum;
        return r;
    }
    if (d->mode != SEPAL_MODE_MULTIPASS)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "tree draw: mode %d (multipass or fused-pixel)", (int)d->mode);
    const bool es1 = t->caps.gles_version == 1;
    for (uint32_t j = 0; j < t->basis_count; ++j) {
        // Only the last basis draws the background: the others leave 0 behind the mesh,
        // so the sum holds it once.
        sepal_scene scene = *d->scene;
        if (j + 1 < t->basis_count) scene.background[0] = scene.background[1] = scene.background[2] = 0.0f;
        if (j > 0) {
            srt::tree_copy(t, d->width, d->height);
            ++sum.copies;
        }
        sepal_draw_desc dd = {};
        dd.material = &t->bases[j];
        dd.mesh = d->mesh;
        dd.scene = &scene;
        dd.width = d->width;
        dd.height = d->height;
        dd.scratch = d->scratch;
        dd.scratch_floats = d->scratch_floats;
        dd.diffuse_texture = t->blend_textures[j];
        dd.mode = SEPAL_MODE_MULTIPASS;
        sepal_draw_stats s = {};
        sepal_result r = sepal_draw(&dd, &s, err);
        if (r != SEPAL_OK) return r;
        add_stats(&sum, s, j == 0);
        if (j > 0) {
            es1 ? srt::tree_add_gles1(t, d->width, d->height) : srt::tree_add_gles2(t, d->width, d->height);
            ++sum.fullscreen_passes;
        }
        if ((r = srt::gl_check("tree composition", err)) != SEPAL_OK) return r;
    }
    if (stats) *stats = sum;
    return srt::ok(err);
}

extern "C" sepal_result sepal_tree_draw_cpu(const sepal_tree_cpu_desc* d, sepal_error* err) {
    if (!d || !d->asset || !d->mesh || !d->scene || !d->color || !d->accum || !d->depth || !d->blend_rgba)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "tree cpu: NULL argument");
    const sepal_tree_asset* a = d->asset;
    const size_t pixels = (size_t)d->width * (size_t)d->height;
    const uint32_t bw = a->header.blend_width, bh = a->header.blend_height;
    sepal_draw_stats sum = {};
    for (uint32_t j = 0; j < a->header.basis_count; ++j) {
        for (size_t i = 0; i < (size_t)bw * bh; ++i) {
            uint8_t* px = d->blend_rgba + 4 * i;
            px[0] = px[1] = px[2] = a->blend[j][i];
            px[3] = 255;
        }
        sepal_scene scene = *d->scene;
        if (j + 1 < a->header.basis_count) scene.background[0] = scene.background[1] = scene.background[2] = 0.0f;
        sepal_draw_stats s = {};
        sepal_cpu_desc c = {};
        c.asset = &a->bases[j];
        c.mesh = d->mesh;
        c.scene = &scene;
        c.width = d->width;
        c.height = d->height;
        c.color = j == 0 ? d->color : d->accum;
        c.depth = d->depth;
        c.scratch = d->scratch;
        c.scratch_floats = d->scratch_floats;
        c.diffuse_rgba = d->blend_rgba;
        c.diffuse_width = (int)bw;
        c.diffuse_height = (int)bh;
        c.stats = &s;
        sepal_result r = sepal_draw_cpu(&c, err);
        if (r != SEPAL_OK) return r;
        add_stats(&sum, s, j == 0);
        if (j > 0)
            for (size_t i = 0; i < 3 * pixels; ++i) d->color[i] += d->accum[i];
    }
    if (d->stats) *d->stats = sum;
    return srt::ok(err);
}
