// .sepal asset parsing and validation (see sepal_format.h). Zero-copy, no allocation.
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include "internal.h"
#include "sepal/sepal_asset.h"
#include "sepal/sepal_scene.h"

static_assert(sizeof(sepal_fmt_header) == 64, "header layout");
static_assert(sizeof(sepal_fmt_chunk) == 24, "chunk layout");
static_assert(sizeof(sepal_fmt_material) == 96, "material layout");
static_assert(sizeof(sepal_fmt_texture) == 72, "texture layout");
static_assert(sizeof(sepal_fmt_plan) == 32, "plan layout");
static_assert(sizeof(sepal_fmt_pass) == 24, "pass layout");
static_assert(sizeof(sepal_fmt_diffuse) == 16, "diffuse profile layout");
static_assert(sizeof(sepal_fmt_profile) == 48, "device profile layout");

namespace srt {

float diffuse_sample(const void* profile, uint32_t layout, size_t k, int c) {
    const uint8_t* b = (const uint8_t*)profile;
    if (layout == SEPAL_FMT_DIFFUSE_RGB_F32) {
        float v;
        memcpy(&v, b + 4 * (k * 3 + (size_t)c), 4);
        return v;
    }
    uint16_t q;
    memcpy(&q, b + 2 * (layout == SEPAL_FMT_DIFFUSE_GREY_U16 ? k : k * 3 + (size_t)c), 2);
    return (float)q / 65535.0f;
}

void diffuse_profile_rgb(const void* profile, uint32_t side, uint32_t layout, float cos_i, float cos_o, float out[3]) {
    if (!profile || side < 2 || layout >= SEPAL_FMT_DIFFUSE_LAYOUT_COUNT) {
        out[0] = out[1] = out[2] = 1.0f;
        return;
    }
    const float n = (float)(side - 1);
    // Clamped to [0,1], NaN to 0: (int)NaN is undefined (found by the fuzz harness).
    const float x = (cos_i >= 0.0f ? (cos_i <= 1.0f ? cos_i : 1.0f) : 0.0f) * n;
    const float y = (cos_o >= 0.0f ? (cos_o <= 1.0f ? cos_o : 1.0f) : 0.0f) * n;
    int i0 = (int)x, j0 = (int)y;
    if (i0 > (int)side - 2) i0 = (int)side - 2;
    if (j0 > (int)side - 2) j0 = (int)side - 2;
    const float ax = x - (float)i0, ay = y - (float)j0;
    for (int c = 0; c < 3; ++c) {
        auto at = [&](int i, int j) { return diffuse_sample(profile, layout, (size_t)j * side + (size_t)i, c); };
        out[c] = (1 - ay) * ((1 - ax) * at(i0, j0) + ax * at(i0 + 1, j0)) +
                 ay * ((1 - ax) * at(i0, j0 + 1) + ax * at(i0 + 1, j0 + 1));
    }
}

}  // namespace srt

extern "C" float sepal_horizon_window(float horizon, float cos_i) {
    if (!(cos_i > 0.0f)) return 0.0f;
    return horizon > 0.0f && cos_i < horizon ? cos_i / horizon : 1.0f;
}

extern "C" float sepal_diffuse_profile(const void* profile, uint32_t side, uint32_t layout, float cos_i, float cos_o,
                                       int c) {
    float rgb[3];
    srt::diffuse_profile_rgb(profile, side, layout, cos_i, cos_o, rgb);
    return c >= 0 && c < 3 ? rgb[c] : 1.0f;
}

namespace {

bool is_pow2(uint32_t v) { return v && !(v & (v - 1)); }

// Reserved words are written as 0; a reader that ignored them could not give them a meaning later.
bool all_zero(const void* p, size_t n) {
    const uint8_t* b = (const uint8_t*)p;
    for (size_t i = 0; i < n; ++i)
        if (b[i]) return false;
    return true;
}

uint32_t mip_levels(uint32_t w, uint32_t h) {
    uint32_t n = 1;
    while (w > 1 || h > 1) w = w > 1 ? w / 2 : 1, h = h > 1 ? h / 2 : 1, ++n;
    return n;
}

const char* tag_name(uint32_t tag, char buf[5]) {
    for (int i = 0; i < 4; ++i) {
        const char c = (char)((tag >> (8 * i)) & 0xFF);
        buf[i] = (c >= 32 && c < 127) ? c : '?';
    }
    buf[4] = '\0';
    return buf;
}

sepal_result parse_texture(const uint8_t* p, uint64_t size, uint32_t index, sepal_asset_texture* t,
                         sepal_error* err) {
    if (size < sizeof(sepal_fmt_texture))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: texture %u chunk too small", index);
    memcpy(&t->desc, p, sizeof t->desc);
    const sepal_fmt_texture& d = t->desc;
    if (!is_pow2(d.width) || !is_pow2(d.height) || d.width > SEPAL_FMT_MAX_TEXTURE_SIDE ||
        d.height > SEPAL_FMT_MAX_TEXTURE_SIDE)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: texture %u is %ux%u; sides must be powers of two up to %d", index,
                         d.width, d.height, SEPAL_FMT_MAX_TEXTURE_SIDE);
    const uint32_t full = mip_levels(d.width, d.height);
    if (d.levels != 1 && d.levels != full)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: texture %u has %u MIP levels; 1 or the full chain (%u)", index,
                         d.levels, full);
    if ((d.channels != 1 && d.channels != 3) || (d.bits != 8 && d.bits != 16))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: texture %u has %u channels of %u bits; 1 or 3 channels of 8 or 16",
                         index, d.channels, d.bits);
    if (d.role >= SEPAL_ROLE_COUNT)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: texture %u role %u unknown", index, d.role);
    for (int c = 0; c < 4; ++c)
        if (!(fabsf(d.scale[c]) <= SEPAL_FMT_MAX_FACTOR) || !(fabsf(d.bias[c]) <= SEPAL_FMT_MAX_FACTOR))
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "asset: texture %u channel %d scale %g or bias %g is not finite or beyond +-%g", index, c,
                             (double)d.scale[c], (double)d.bias[c], (double)SEPAL_FMT_MAX_FACTOR);
    if (d.reserved0 != 0)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: texture %u reserved word is 0x%x (must be 0)", index,
                         d.reserved0);
    uint64_t offset = sizeof(sepal_fmt_texture);
    uint32_t w = d.width, h = d.height;
    for (uint32_t l = 0; l < d.levels; ++l) {
        const uint64_t bytes = (uint64_t)w * h * d.channels * (d.bits / 8);
        if (offset + bytes > size)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "asset: texture %u level %u runs past its chunk", index, l);
        t->level_data[l] = p + offset;
        t->level_bytes[l] = (uint32_t)bytes;
        offset += bytes;
        w = w > 1 ? w / 2 : 1;
        h = h > 1 ? h / 2 : 1;
    }
    if (offset != size || d.data_bytes != offset - sizeof(sepal_fmt_texture))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: texture %u data is %llu bytes, its levels need %llu", index,
                         (unsigned long long)(size - sizeof(sepal_fmt_texture)),
                         (unsigned long long)(offset - sizeof(sepal_fmt_texture)));
    return SEPAL_OK;
}

// The plan must draw the factors' sum, the one f the CPU backend and the fused shaders read
// from the textures: per term and channel, the PRODUCT (or RECIPROCAL) pass weight
// ratio sG sH (times sG for reciprocal), the TEXTURE passes ratio sG bH and ratio bG sH, the
// CONSTANT passes sum_k ratio bG bH and the DIFFUSE pass the material's diffuse, each as
// sign x colour x rgb_scale x 2^doublings. Only float rounding may differ (the writer's
// colours are float(ldexp(value, -doublings))).
bool plan_matches_factors(const sepal_asset& a, char* what, size_t what_size) {
    const sepal_fmt_material& m = a.material;
    const bool reciprocal = (m.flags & SEPAL_MATERIAL_RECIPROCAL) != 0;
    // want/got per channel: [0, T) products, [T, 2T) G-textures, [2T, 3T) H-textures, 3T the
    // constant, 3T+1 the diffuse part.
    enum { kMaxSlots = 3 * SEPAL_FMT_MAX_TERMS + 2 };
    const uint32_t T = m.terms, kConst = 3 * T, kDiffuse = 3 * T + 1;
    double want[kMaxSlots][3] = {}, got[kMaxSlots][3] = {};
    int textures_of[SEPAL_FMT_MAX_TERMS][SEPAL_ROLE_COUNT];
    for (uint32_t i = 0; i < a.texture_count; ++i)
        textures_of[a.textures[i].desc.term][a.textures[i].desc.role] = (int)i;
    for (uint32_t k = 0; k < T; ++k) {
        const sepal_fmt_texture& G = a.textures[textures_of[k][SEPAL_ROLE_G]].desc;
        const sepal_fmt_texture& H = a.textures[textures_of[k][SEPAL_ROLE_H]].desc;
        for (int c = 0; c < 3; ++c) {
            const int t = m.channels == 1 ? 0 : c;
            const double r = m.ratio[c], sg = G.scale[t], sh = H.scale[t], bg = G.bias[t], bh = H.bias[t];
            want[k][c] = r * sg * sh * (reciprocal ? sg : 1.0);
            want[T + k][c] = r * sg * bh;
            want[2 * T + k][c] = r * bg * sh;
            want[kConst][c] += r * bg * bh;
        }
    }
    for (int c = 0; c < 3; ++c) want[kDiffuse][c] = m.diffuse[c];
    const double unit = ldexp(1.0, (int)a.plan.doublings);
    for (uint32_t i = 0; i < a.plan.pass_count; ++i) {
        const sepal_fmt_pass& p = a.passes[i];
        uint32_t slot = kConst;
        if (p.op == SEPAL_OP_PRODUCT || p.op == SEPAL_OP_RECIPROCAL) slot = a.textures[p.tex0].desc.term;
        else if (p.op == SEPAL_OP_TEXTURE) {
            const sepal_fmt_texture& d = a.textures[p.tex0].desc;
            slot = (d.role == SEPAL_ROLE_G ? T : 2 * T) + d.term;
        } else if (p.op == SEPAL_OP_DIFFUSE) slot = kDiffuse;
        const double sign = p.blend == SEPAL_BLEND_SUBTRACT ? -1.0 : 1.0;
        for (int c = 0; c < 3; ++c) got[slot][c] += sign * (double)p.color[c] * (double)p.rgb_scale * unit;
    }
    double biggest = 0.0;
    for (uint32_t s = 0; s <= kDiffuse; ++s)
        for (int c = 0; c < 3; ++c) biggest = fmax(biggest, fabs(want[s][c]));
    for (uint32_t s = 0; s <= kDiffuse; ++s)
        for (int c = 0; c < 3; ++c) {
            const double w = want[s][c], g = got[s][c];
            if (fabs(g - w) <= 1e-4 * fabs(w) + 1e-6 * biggest) continue;
            const char* part = s < T ? (reciprocal ? "G H G" : "G H") : s < 2 * T ? "G's texture" : s < 3 * T ? "H's texture"
                             : s == kConst ? "constant" : "diffuse";
            const uint32_t term = s < 3 * T ? s % T : 0;
            if (s < 3 * T)
                snprintf(what, what_size, "term %u's %s part weighs %g in channel %d, its factors say %g", term, part,
                         g, c, w);
            else
                snprintf(what, what_size, "the %s part weighs %g in channel %d, the material says %g", part, g, c, w);
            return false;
        }
    return true;
}

}  // namespace

extern "C" uint32_t sepal_crc32(uint32_t crc, const void* data, size_t size) {
    // Bitwise with a 16-entry table: small code, fast enough for assets of a few MB.
    static const uint32_t kTable[16] = {
        0x00000000u, 0x1DB71064u, 0x3B6E20C8u, 0x26D930ACu, 0x76DC4190u, 0x6B6B51F4u,
        0x4DB26158u, 0x5005713Cu, 0xEDB88320u, 0xF00F9344u, 0xD6D6A3E8u, 0xCB61B38Cu,
        0x9B64C2B0u, 0x86D3D2D4u, 0xA00AE278u, 0xBDBDF21Cu};
    const uint8_t* p = (const uint8_t*)data;
    crc = ~crc;
    for (size_t i = 0; i < size; ++i) {
        crc = (crc >> 4) ^ kTable[(crc ^ p[i]) & 0x0F];
        crc = (crc >> 4) ^ kTable[(crc ^ (p[i] >> 4)) & 0x0F];
    }
    return ~crc;
}

namespace {
// An asset written before the light range (2.3) says its white level only in its META
// ("white_level": W, the bake's cap): read it, and take 1/W as the dimmest light it holds for
// (below it the cap no longer shows white). No allocation: a bounded copy for strtod.
void meta_white_level(const char* meta, uint32_t bytes, sepal_fmt_material* m) {
    static const char key[] = "\"white_level\":";
    const size_t k = sizeof key - 1;
    for (uint32_t i = 0; meta && i + k < bytes; ++i) {
        if (memcmp(meta + i, key, k) != 0) continue;
        char num[40] = {0};
        size_t n = 0;
        for (uint32_t j = i + (uint32_t)k; j < bytes && n + 1 < sizeof num && meta[j] != ',' && meta[j] != '}'; ++j)
            num[n++] = meta[j];
        char* end = nullptr;
        const double w = strtod(num, &end);
        if (end != num && w > 0.0 && w <= SEPAL_FMT_MAX_FACTOR && 1.0 / w <= SEPAL_FMT_MAX_FACTOR) {
            m->white_level = (float)w;
            m->irradiance_min = m->irradiance_max = (float)(1.0 / w);
        }
        return;
    }
}
// The header and the chunk table's bounds and checksum; table_end: where the table ends.
sepal_result parse_header(const uint8_t* base, size_t size, sepal_fmt_header* hp, uint64_t* table_end_out,
                          sepal_error* err) {
    sepal_fmt_header& h = *hp;
    memcpy(&h, base, sizeof h);
    uint64_t& table_end = *table_end_out;
    if (memcmp(h.magic, SEPAL_FMT_MAGIC, 8) != 0)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: bad magic (not a .sepal file)");
    if (h.version_major < SEPAL_FMT_VERSION_MAJOR_OLDEST || h.version_major > SEPAL_FMT_VERSION_MAJOR)
        return srt::fail(err, SEPAL_ERR_UNSUPPORTED,
                         "asset: format version %u.%u; this runtime reads versions %d.x to %d.x",
                         h.version_major, h.version_minor, SEPAL_FMT_VERSION_MAJOR_OLDEST,
                         SEPAL_FMT_VERSION_MAJOR);
    if (h.file_bytes != size)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: header says %llu bytes, the buffer holds %zu (truncated or padded)",
                         (unsigned long long)h.file_bytes, size);
    if (size > SEPAL_FMT_MAX_FILE_BYTES)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: %zu bytes is over the %u-byte limit",
                         size, SEPAL_FMT_MAX_FILE_BYTES);
    if (h.chunk_count < 1 || h.chunk_count > SEPAL_FMT_MAX_CHUNKS)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: %u chunks (1..%d)", h.chunk_count,
                         SEPAL_FMT_MAX_CHUNKS);
    table_end = sizeof(sepal_fmt_header) + (uint64_t)h.chunk_count * sizeof(sepal_fmt_chunk);
    if (table_end > size)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: chunk table runs past the end of the file");
    // The header checksum covers the header (with the checksum field 0) and the table.
    sepal_fmt_header zeroed = h;
    zeroed.header_crc = 0;
    uint32_t crc = sepal_crc32(0, &zeroed, sizeof zeroed);
    crc = sepal_crc32(crc, base + sizeof(sepal_fmt_header), (size_t)(table_end - sizeof(sepal_fmt_header)));
    if (h.header_bytes != sizeof(sepal_fmt_header) || crc != h.header_crc)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: header checksum mismatch (corrupt header or chunk table)");
    if (h.flags != 0 || !all_zero(h.reserved, sizeof h.reserved))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: header flags 0x%x or reserved bytes not 0 (must be 0)",
                         h.flags);
    return SEPAL_OK;
}

// The material chunk's values against the header's version (an older asset's white level
// from its META); reciprocal, has_diffuse: what the plan must then draw.
sepal_result check_material(const sepal_fmt_header& h, sepal_asset* out, bool* reciprocal_out, bool* has_diffuse_out,
                            sepal_error* err) {
    sepal_fmt_material& m = out->material;
    {
        const float range[4] = {m.white_level, m.irradiance_min, m.irradiance_max, m.cone_degrees};
        for (float v : range)
            if (!(v >= 0.0f && v <= SEPAL_FMT_MAX_FACTOR))
                return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                                 "asset: light range value %g (white level, irradiances, cone) outside 0..%g",
                                 (double)v, (double)SEPAL_FMT_MAX_FACTOR);
        if (m.irradiance_min > m.irradiance_max || m.cone_degrees > 180.0f || m.max_lights > SEPAL_MAX_LIGHTS ||
            !all_zero(m.reserved1, sizeof m.reserved1))
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "asset: light range irradiance %g..%g, cone %g degrees (0..180), %u lights (0..%d) "
                             "or reserved words not 0",
                             (double)m.irradiance_min, (double)m.irradiance_max, (double)m.cone_degrees,
                             m.max_lights, SEPAL_MAX_LIGHTS);
        if (m.white_level == 0.0f && m.irradiance_min == 0.0f) meta_white_level(out->meta, out->meta_bytes, &m);
    }
    if (m.horizon != 0.0f) {
        if (!(m.horizon > 0.0f && m.horizon <= 1.0f))
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: horizon window %g outside (0, 1] (0: none)",
                             (double)m.horizon);
        if (!(m.flags & SEPAL_MATERIAL_RADIANCE))
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "asset: a horizon window (%g) on a material that is not a radiance one", (double)m.horizon);
        if (h.version_major < 2 || (h.version_major == 2 && h.version_minor < SEPAL_FMT_VERSION_MINOR_HORIZON))
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "asset: the horizon window needs version 2.7 (this file is %u.%u)", h.version_major,
                             h.version_minor);
    }
    if (m.param >= SEPAL_PARAM_COUNT || m.map >= SEPAL_MAP_COUNT || m.color_mode >= SEPAL_COLOR_COUNT)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: unknown parameterization %u, map %u or colour mode %u", m.param,
                         m.map, m.color_mode);
    for (int c = 0; c < 3; ++c)
        if (!(m.ratio[c] >= 0.0f && m.ratio[c] <= SEPAL_FMT_MAX_RATIO))
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: colour ratio %g outside 0..%g",
                             (double)m.ratio[c], (double)SEPAL_FMT_MAX_RATIO);
    if (m.reserved0 != 0)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: material reserved word is 0x%x (must be 0)",
                         m.reserved0);
    if (!(m.ratio[0] + m.ratio[1] + m.ratio[2] > 0.0f))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: colour ratio is all zero");
    // The bake's error figures: a number, or NaN when not measured; never infinite.
    if (isinf(m.error_quantized) || isinf(m.error_float) || isinf(m.error_relative))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: error figures %g %g %g: finite, or NaN (not measured)",
                         (double)m.error_quantized, (double)m.error_float, (double)m.error_relative);
    if ((m.channels == 1) != (m.color_mode == SEPAL_COLOR_LUMINANCE))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: %u channels with colour mode %u (luminance has 1)",
                         m.channels, m.color_mode);
    if (m.param == SEPAL_PARAM_AXIS &&
        (h.version_major < 2 || (h.version_major == 2 && h.version_minor < SEPAL_FMT_VERSION_MINOR_AXIS)))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: the axis parameterization needs version 2.2 (this file is %u.%u)", h.version_major,
                         h.version_minor);
    if (m.param == SEPAL_PARAM_GS_MIRROR &&
        (h.version_major < 2 || (h.version_major == 2 && h.version_minor < SEPAL_FMT_VERSION_MINOR_MIRROR)))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: the gs-mirror parameterization needs version 2.6 (this file is %u.%u)",
                         h.version_major, h.version_minor);
    // Version 1 left these words reserved (written as 0).
    if (h.version_major < 2 && !all_zero(&m.flags, sizeof m.flags + sizeof m.diffuse))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: a version-1 material with flags or a diffuse part (reserved in version 1: must be 0)");
    if (m.flags & ~SEPAL_MATERIAL_KNOWN_FLAGS)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: unknown material flags 0x%x",
                         m.flags & ~SEPAL_MATERIAL_KNOWN_FLAGS);
    // Reciprocal materials (2.1): not radiance ones, a bounded copy for the runtime.
    const bool reciprocal = *reciprocal_out = (m.flags & SEPAL_MATERIAL_RECIPROCAL) != 0;
    if (reciprocal && (h.version_major < 2 || (h.version_major == 2 && h.version_minor < SEPAL_FMT_VERSION_MINOR_RECIPROCAL) ||
                       (m.flags & SEPAL_MATERIAL_RADIANCE) || m.terms > SEPAL_FMT_MAX_RECIPROCAL_TERMS))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: a reciprocal material needs version 2.1 (this file is %u.%u), no radiance flag, "
                         "and at most %d terms (it has %u)",
                         h.version_major, h.version_minor, SEPAL_FMT_MAX_RECIPROCAL_TERMS, m.terms);
    bool& has_diffuse = *has_diffuse_out;
    has_diffuse = false;
    for (int c = 0; c < 3; ++c) {
        if (!(m.diffuse[c] >= 0.0f && m.diffuse[c] <= SEPAL_FMT_MAX_RATIO))
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: diffuse %g outside 0..%g",
                             (double)m.diffuse[c], (double)SEPAL_FMT_MAX_RATIO);
        has_diffuse = has_diffuse || m.diffuse[c] > 0.0f;
    }
    if (m.terms < 1 || m.terms > SEPAL_FMT_MAX_TERMS || (m.channels != 1 && m.channels != 3))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: %u terms (1..%d), %u channels (1 or 3)",
                         m.terms, SEPAL_FMT_MAX_TERMS, m.channels);
    return SEPAL_OK;
}

// Pass i of the plan: op, blend, texture slots and what they hold, colour, scale, order.
sepal_result check_pass(const sepal_asset* out, uint32_t i, bool reciprocal, sepal_error* err) {
    const sepal_fmt_pass& p = out->passes[i];
    const sepal_fmt_plan& plan = out->plan;
    const sepal_fmt_header& h = out->header;
    const int needs = p.op == SEPAL_OP_PRODUCT || p.op == SEPAL_OP_RECIPROCAL ? 2 : p.op == SEPAL_OP_TEXTURE ? 1 : 0;
    if (p.op >= SEPAL_OP_COUNT || p.blend >= SEPAL_BLEND_COUNT || (p.op == SEPAL_OP_DIFFUSE && h.version_major < 2))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: pass %u has unknown op %u or blend %u",
                         i, p.op, p.blend);
    // A reciprocal material draws RECIPROCAL passes only (or the all-zero plan's one
    // CONSTANT pass); the op needs the material (and so version 2.1).
    if (reciprocal ? !(p.op == SEPAL_OP_RECIPROCAL || (p.op == SEPAL_OP_CONSTANT && plan.pass_count == 1))
                   : p.op == SEPAL_OP_RECIPROCAL)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: pass %u has op %u in a %s material", i, p.op,
                         reciprocal ? "reciprocal" : "non-reciprocal");
    if (p.op == SEPAL_OP_DIFFUSE && p.blend != SEPAL_BLEND_ADD)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: pass %u subtracts the diffuse part", i);
    const uint16_t tex[2] = {p.tex0, p.tex1};
    for (int k = 0; k < 2; ++k) {
        const bool used = k < needs;
        if (used ? tex[k] >= out->texture_count : tex[k] != SEPAL_FMT_NO_TEXTURE)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "asset: pass %u texture slot %d is %u (%u textures; unused slots "
                             "must be 0xFFFF)",
                             i, k, tex[k], out->texture_count);
    }
    if (p.op == SEPAL_OP_RECIPROCAL) {
        const sepal_fmt_texture& g = out->textures[p.tex0].desc;
        const sepal_fmt_texture& hh = out->textures[p.tex1].desc;
        if (p.blend != SEPAL_BLEND_ADD || g.role != SEPAL_ROLE_G || hh.role != SEPAL_ROLE_H || g.term != hh.term)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "asset: reciprocal pass %u must add one term's G (tex0) and H (tex1) texture", i);
    }
    // A product is one term's G (slot 0) times the same term's H (slot 1): what the CPU
    // backend and the fused shaders sum (G_k H_k), so the plan paths draw the same thing.
    if (p.op == SEPAL_OP_PRODUCT) {
        const sepal_fmt_texture& a = out->textures[p.tex0].desc;
        const sepal_fmt_texture& b = out->textures[p.tex1].desc;
        if (a.role != SEPAL_ROLE_G || b.role != SEPAL_ROLE_H || a.term != b.term)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "asset: pass %u multiplies texture %u (term %u %s) by texture %u (term %u %s); a product "
                             "is one term's G times its H",
                             i, p.tex0, a.term, a.role == SEPAL_ROLE_G ? "G" : "H", p.tex1, b.term,
                             b.role == SEPAL_ROLE_G ? "G" : "H");
    }
    for (int c = 0; c < 3; ++c)
        if (!(p.color[c] >= 0.0f && p.color[c] <= 1.0f))
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "asset: pass %u colour %g outside [0,1]", i, (double)p.color[c]);
    if (p.rgb_scale != 1 && p.rgb_scale != 2 && p.rgb_scale != 4)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: pass %u rgb_scale %u (1, 2 or 4)", i,
                         p.rgb_scale);
    // Every add before every subtract, so no partial sum clamps at 0 in a [0,1]
    // framebuffer: part of what a valid plan is, for every backend (the GL ones cannot
    // draw it otherwise; the CPU one would draw what GL cannot).
    if (p.blend == SEPAL_BLEND_ADD && i > 0 && out->passes[i - 1].blend == SEPAL_BLEND_SUBTRACT)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: pass %u adds after pass %u subtracts (a plan adds everything first)", i, i - 1);
    return SEPAL_OK;
}

sepal_result parse_profile(const uint8_t* p, uint64_t size, sepal_asset* out, sepal_error* err) {
    if (out->has_profile || size != sizeof(sepal_fmt_profile))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: PROF chunk duplicated or of size %llu (expected %zu)",
                         (unsigned long long)size, sizeof(sepal_fmt_profile));
    sepal_fmt_profile& f = out->profile;
    memcpy(&f, p, sizeof f);
    out->has_profile = 1;
    const size_t n = strnlen(f.name, sizeof f.name);
    bool name_ok = n > 0 && n < sizeof f.name;
    for (size_t i = 0; i < n; ++i)
        name_ok = name_ok && ((f.name[i] >= 'a' && f.name[i] <= 'z') || (f.name[i] >= '0' && f.name[i] <= '9') ||
                              f.name[i] == '-');
    for (size_t i = n; i < sizeof f.name; ++i) name_ok = name_ok && f.name[i] == 0;
    if (!name_ok)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: PROF chunk's name is not 1..15 characters of [a-z0-9-] padded with zeros");
    const uint32_t bits[3] = {f.red_bits, f.green_bits, f.blue_bits};
    for (uint32_t b : bits)
        if (b < 1 || b > 8)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: profile %s has %u framebuffer bits (1..8)",
                             f.name, b);
    const uint32_t side = f.max_texture_size;
    if (f.texture_units < 1 || f.texture_units > 32 || side < 1 || side > SEPAL_FMT_MAX_TEXTURE_SIDE ||
        (side & (side - 1)) != 0)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: profile %s has %u texture units (1..32) and texture limit %u (a power of two, 1..%d)",
                         f.name, f.texture_units, side, SEPAL_FMT_MAX_TEXTURE_SIDE);
    if ((f.flags & ~SEPAL_PROFILE_KNOWN_FLAGS) != 0 || !all_zero(f.reserved, sizeof f.reserved))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: profile %s has unknown flags or reserved words", f.name);
    return SEPAL_OK;
}

// Without a PROF chunk: the default profile, held to the asset's own largest texture.
void default_profile(sepal_asset* out) {
    sepal_fmt_profile& f = out->profile;
    memset(&f, 0, sizeof f);
    memcpy(f.name, "default", 8);
    f.red_bits = f.green_bits = f.blue_bits = SEPAL_FMT_DEFAULT_PROFILE_BITS;
    f.texture_units = SEPAL_FMT_DEFAULT_PROFILE_UNITS;
    f.flags = SEPAL_PROFILE_BLEND_SUBTRACT;
    for (uint32_t i = 0; i < out->texture_count; ++i) {
        const sepal_fmt_texture& d = out->textures[i].desc;
        f.max_texture_size = d.width > f.max_texture_size ? d.width : f.max_texture_size;
        f.max_texture_size = d.height > f.max_texture_size ? d.height : f.max_texture_size;
    }
}

// The DIFF chunk (format 2): a diffuse profile of side x side RGB samples in [0,1], as
// floats (2.0 on) or 16-bit (2.5 on).
sepal_result parse_diffuse(const sepal_fmt_header& h, const uint8_t* p, uint64_t size, sepal_asset* out,
                           sepal_error* err) {
    sepal_fmt_diffuse dh;
    if (out->diffuse_profile || h.version_major < 2 || size < sizeof dh)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: DIFF chunk duplicated, too small or in a version-1 file");
    memcpy(&dh, p, sizeof dh);
    if (!all_zero(dh.reserved, sizeof dh.reserved))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: DIFF chunk's reserved words are not 0");
    if (dh.layout >= SEPAL_FMT_DIFFUSE_LAYOUT_COUNT ||
        (dh.layout != SEPAL_FMT_DIFFUSE_RGB_F32 && h.version_minor < SEPAL_FMT_VERSION_MINOR_DIFFUSE16))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: diffuse profile layout %u (0..%d; 1 and 2 from format 2.%d on) in a 2.%u file",
                         dh.layout, SEPAL_FMT_DIFFUSE_LAYOUT_COUNT - 1, SEPAL_FMT_VERSION_MINOR_DIFFUSE16,
                         (unsigned)h.version_minor);
    const uint64_t values = (uint64_t)dh.side * dh.side * (dh.layout == SEPAL_FMT_DIFFUSE_GREY_U16 ? 1 : 3);
    const uint64_t value_bytes = dh.layout == SEPAL_FMT_DIFFUSE_RGB_F32 ? sizeof(float) : sizeof(uint16_t);
    if (dh.side < 2 || dh.side > SEPAL_FMT_MAX_DIFFUSE_SIDE || size != sizeof dh + values * value_bytes)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: diffuse profile of side %u (2..%d), layout %u, in a %llu-byte chunk", dh.side,
                         SEPAL_FMT_MAX_DIFFUSE_SIDE, dh.layout, (unsigned long long)size);
    out->diffuse_profile = p + sizeof dh;
    out->diffuse_side = dh.side;
    out->diffuse_layout = dh.layout;
    // 16-bit samples are in [0,1] by construction.
    for (uint32_t k = 0; dh.layout == SEPAL_FMT_DIFFUSE_RGB_F32 && k < dh.side * dh.side * 3; ++k) {
        float v;
        memcpy(&v, out->diffuse_profile + 4 * (size_t)k, 4);
        if (!(v >= 0.0f && v <= 1.0f))
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: diffuse profile value %g outside [0,1]",
                             (double)v);
    }
    return SEPAL_OK;
}

// The default profile without a PROF chunk; every texture at or under the profile's limit.
sepal_result finish_profile(sepal_asset* out, sepal_error* err) {
    if (!out->has_profile) default_profile(out);
    for (uint32_t i = 0; i < out->texture_count; ++i) {
        const sepal_fmt_texture& d = out->textures[i].desc;
        if (d.width > out->profile.max_texture_size || d.height > out->profile.max_texture_size)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: texture %u is %ux%u, over its profile %s's limit %u",
                             i, d.width, d.height, out->profile.name, out->profile.max_texture_size);
    }
    return SEPAL_OK;
}

}  // namespace

extern "C" sepal_result sepal_asset_parse(const void* bytes, size_t size, sepal_asset* out,
                                      sepal_error* err) {
    const uint16_t probe = 1;
    if (*(const uint8_t*)&probe != 1)
        return srt::fail(err, SEPAL_ERR_UNSUPPORTED, "asset: big-endian hosts are not supported");
    if (!out) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: NULL argument");
    memset(out, 0, sizeof *out);
    if (size < sizeof(sepal_fmt_header))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: %zu bytes is too short for the 64-byte header (truncated?)", size);
    if (!bytes) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: NULL bytes");
    const uint8_t* base = (const uint8_t*)bytes;
    sepal_fmt_header& h = out->header;
    uint64_t table_end = 0;
    if (const sepal_result r = parse_header(base, size, &h, &table_end, err)) return r;
    bool have_material = false, have_plan = false;
    const uint8_t* plan_payload = nullptr;
    uint64_t plan_size = 0;
    char name[5];
    for (uint32_t i = 0; i < h.chunk_count; ++i) {
        sepal_fmt_chunk c;
        memcpy(&c, base + sizeof(sepal_fmt_header) + (size_t)i * sizeof c, sizeof c);
        if (c.offset % 8 != 0 || c.offset < table_end || c.offset > size || c.size > size - c.offset)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "asset: chunk %u ('%s') at offset %llu size %llu lies outside the file",
                             i, tag_name(c.tag, name), (unsigned long long)c.offset,
                             (unsigned long long)c.size);
        const uint8_t* p = base + c.offset;
        if (sepal_crc32(0, p, (size_t)c.size) != c.crc)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: chunk %u ('%s') checksum mismatch",
                             i, tag_name(c.tag, name));
        if (c.tag == SEPAL_FMT_TAG_MATERIAL) {
            // 96 bytes from 2.3 (the light range), 64 before.
            const bool ranged = h.version_major > 2 ||
                                (h.version_major == 2 && h.version_minor >= SEPAL_FMT_VERSION_MINOR_LIGHT_RANGE);
            const size_t expected = ranged ? sizeof(sepal_fmt_material) : SEPAL_FMT_MATERIAL_BYTES_V2;
            if (have_material || c.size != expected)
                return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                                 "asset: MATL chunk duplicated or of size %llu (expected %zu in version %u.%u)",
                                 (unsigned long long)c.size, expected, h.version_major, h.version_minor);
            memcpy(&out->material, p, expected);
            have_material = true;
        } else if (c.tag == SEPAL_FMT_TAG_TEXTURE) {
            if (out->texture_count >= SEPAL_FMT_MAX_TEXTURES)
                return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: more than %d textures",
                                 SEPAL_FMT_MAX_TEXTURES);
            sepal_result r = parse_texture(p, c.size, out->texture_count,
                                         &out->textures[out->texture_count], err);
            if (r != SEPAL_OK) return r;
            ++out->texture_count;
        } else if (c.tag == SEPAL_FMT_TAG_PLAN) {
            if (have_plan)
                return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: PLAN chunk duplicated");
            plan_payload = p;
            plan_size = c.size;
            have_plan = true;
        } else if (c.tag == SEPAL_FMT_TAG_DIFFUSE) {
            if (const sepal_result r = parse_diffuse(h, p, c.size, out, err)) return r;
        } else if (c.tag == SEPAL_FMT_TAG_PROFILE) {
            if (const sepal_result r = parse_profile(p, c.size, out, err)) return r;
        } else if (c.tag == SEPAL_FMT_TAG_META) {
            if (c.size > SEPAL_FMT_MAX_META_BYTES)
                return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: META over %u bytes",
                                 SEPAL_FMT_MAX_META_BYTES);
            out->meta = (const char*)p;
            out->meta_bytes = (uint32_t)c.size;
        }
    }
    if (!have_material || !have_plan || out->texture_count == 0)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: missing %s chunk",
                         !have_material ? "MATL" : !have_plan ? "PLAN" : "TEXR");
    const sepal_fmt_material& m = out->material;
    bool reciprocal = false, has_diffuse = false;
    if (const sepal_result r = check_material(h, out, &reciprocal, &has_diffuse, err)) return r;
    // Every term has exactly one G and one H texture, with the material's channels.
    uint32_t seen[SEPAL_FMT_MAX_TERMS][SEPAL_ROLE_COUNT] = {};
    for (uint32_t i = 0; i < out->texture_count; ++i) {
        const sepal_fmt_texture& d = out->textures[i].desc;
        if (d.term >= m.terms || d.channels != m.channels)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "asset: texture %u belongs to term %u with %u channels; the material "
                             "has %u terms of %u channels",
                             i, d.term, d.channels, m.terms, m.channels);
        ++seen[d.term][d.role];
        if (reciprocal && d.role == SEPAL_ROLE_G &&
            (d.width > SEPAL_FMT_MAX_RECIPROCAL_SIDE || d.height > SEPAL_FMT_MAX_RECIPROCAL_SIDE))
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "asset: texture %u is a reciprocal G texture of %ux%u (at most %dx%d)", i, d.width,
                             d.height, SEPAL_FMT_MAX_RECIPROCAL_SIDE, SEPAL_FMT_MAX_RECIPROCAL_SIDE);
    }
    for (uint32_t k = 0; k < m.terms; ++k)
        if (seen[k][SEPAL_ROLE_G] != 1 || seen[k][SEPAL_ROLE_H] != 1)
            return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                             "asset: term %u needs one G and one H texture (has %u and %u)", k,
                             seen[k][SEPAL_ROLE_G], seen[k][SEPAL_ROLE_H]);
    if (plan_size < sizeof(sepal_fmt_plan))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: PLAN chunk too small");
    memcpy(&out->plan, plan_payload, sizeof out->plan);
    const sepal_fmt_plan& plan = out->plan;
    if (!all_zero(plan.reserved, sizeof plan.reserved))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: plan's reserved words are not 0");
    if (plan.pass_count < 1 || plan.pass_count > SEPAL_FMT_MAX_PASSES ||
        plan_size != sizeof(sepal_fmt_plan) + (uint64_t)plan.pass_count * sizeof(sepal_fmt_pass))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: plan of %u passes (1..%d) in a %llu-byte chunk", plan.pass_count,
                         SEPAL_FMT_MAX_PASSES, (unsigned long long)plan_size);
    if (plan.doublings > SEPAL_FMT_MAX_DOUBLINGS || !(plan.peak_partial_sum > 0.0f) ||
        !(plan.peak_partial_sum <= 1.0f))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: plan has %u doublings (0..%d) or peak partial sum %g (0..1]",
                         plan.doublings, SEPAL_FMT_MAX_DOUBLINGS, (double)plan.peak_partial_sum);
    memcpy(out->passes, plan_payload + sizeof(sepal_fmt_plan), plan.pass_count * sizeof(sepal_fmt_pass));
    uint32_t diffuse_passes = 0;
    for (uint32_t i = 0; i < plan.pass_count; ++i) {
        if (const sepal_result r = check_pass(out, i, reciprocal, err)) return r;
        if (out->passes[i].op == SEPAL_OP_DIFFUSE) ++diffuse_passes;
    }
    if (out->diffuse_profile && !has_diffuse)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "asset: a diffuse profile without a diffuse part");
    // The diffuse part is drawn by exactly one DIFFUSE pass (the other backends read it from
    // the material): both or neither.
    if (diffuse_passes != (has_diffuse ? 1u : 0u))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: %u DIFFUSE passes for a material %s a diffuse part (one iff it has one)",
                         diffuse_passes, has_diffuse ? "with" : "without");
    char what[200];
    if (!plan_matches_factors(*out, what, sizeof what))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "asset: the pass plan does not draw the factors: %s (every backend must draw one f)", what);
    if (const sepal_result r = finish_profile(out, err)) return r;
    return srt::ok(err);
}
