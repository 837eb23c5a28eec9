#include "bake/asset_file.h"

#include <cmath>
#include <cstring>
#include <memory>

#include "sepal/sepal_asset.h"
#include "util/io.h"

namespace sepal {
namespace {

void append(std::vector<uint8_t>* v, const void* p, size_t n) {
    const uint8_t* b = static_cast<const uint8_t*>(p);
    v->insert(v->end(), b, b + n);
}

void pad8(std::vector<uint8_t>* v) {
    while (v->size() % 8) v->push_back(0);
}

// The DIFF chunk's samples (format 2.5): the nearest q / 65535 of each value (encode_asset
// has refused values outside [0,1]), once per sample when its three channels round alike
// (GREY_U16), else per channel (RGB_U16).
uint16_t diffuse_u16(float v) { return uint16_t(std::lround(double(v) * 65535.0)); }

std::vector<uint16_t> diffuse_profile_u16(const std::vector<float>& rgb, uint32_t* layout) {
    bool grey = true;
    for (size_t k = 0; k + 2 < rgb.size() && grey; k += 3)
        grey = diffuse_u16(rgb[k]) == diffuse_u16(rgb[k + 1]) && diffuse_u16(rgb[k]) == diffuse_u16(rgb[k + 2]);
    *layout = grey ? SEPAL_FMT_DIFFUSE_GREY_U16 : SEPAL_FMT_DIFFUSE_RGB_U16;
    std::vector<uint16_t> q;
    q.reserve(grey ? rgb.size() / 3 : rgb.size());
    for (size_t k = 0; k < rgb.size(); k += grey ? 3 : 1) q.push_back(diffuse_u16(rgb[k]));
    return q;
}

}  // namespace

bool encode_asset(const AssetData& asset, std::vector<uint8_t>* out, std::string* err) {
    struct Payload {
        uint32_t tag;
        std::vector<uint8_t> bytes;
    };
    std::vector<Payload> chunks;
    {
        Payload p{SEPAL_FMT_TAG_MATERIAL, {}};
        // 2.3's light range only from 2.3: older assets stay byte-identical.
        const bool ranged = asset_needs_version2(asset) && asset_minor_version(asset) >= SEPAL_FMT_VERSION_MINOR_LIGHT_RANGE;
        append(&p.bytes, &asset.material, ranged ? sizeof asset.material : size_t(SEPAL_FMT_MATERIAL_BYTES_V2));
        chunks.push_back(std::move(p));
    }
    for (const AssetTexture& t : asset.textures) {
        Payload p{SEPAL_FMT_TAG_TEXTURE, {}};
        sepal_fmt_texture d = t.desc;
        d.data_bytes = t.data.size();
        append(&p.bytes, &d, sizeof d);
        append(&p.bytes, t.data.data(), t.data.size());
        chunks.push_back(std::move(p));
    }
    {
        Payload p{SEPAL_FMT_TAG_PLAN, {}};
        sepal_fmt_plan plan = asset.plan;
        plan.pass_count = uint32_t(asset.passes.size());
        append(&p.bytes, &plan, sizeof plan);
        append(&p.bytes, asset.passes.data(), asset.passes.size() * sizeof(sepal_fmt_pass));
        chunks.push_back(std::move(p));
    }
    if (!asset.diffuse_profile.empty()) {
        Payload p{SEPAL_FMT_TAG_DIFFUSE, {}};
        sepal_fmt_diffuse d{};
        d.side = asset.diffuse_side;
        for (size_t k = 0; k < asset.diffuse_profile.size(); ++k)
            if (!(asset.diffuse_profile[k] >= 0.0f && asset.diffuse_profile[k] <= 1.0f)) {
                if (err)
                    *err = "asset: diffuse profile value " + std::to_string(asset.diffuse_profile[k]) +
                           " outside [0,1] (sample " + std::to_string(k / 3) + ", channel " + std::to_string(k % 3) + ")";
                return false;
            }
        const std::vector<uint16_t> q = diffuse_profile_u16(asset.diffuse_profile, &d.layout);
        append(&p.bytes, &d, sizeof d);
        append(&p.bytes, q.data(), q.size() * sizeof(uint16_t));
        chunks.push_back(std::move(p));
    }
    if (asset.has_profile) {
        Payload p{SEPAL_FMT_TAG_PROFILE, {}};
        append(&p.bytes, &asset.profile, sizeof asset.profile);
        chunks.push_back(std::move(p));
    }
    if (!asset.meta.empty()) {
        Payload p{SEPAL_FMT_TAG_META, {}};
        append(&p.bytes, asset.meta.data(), asset.meta.size());
        chunks.push_back(std::move(p));
    }
    if (chunks.size() > SEPAL_FMT_MAX_CHUNKS) {
        if (err) *err = "asset: too many chunks (" + std::to_string(chunks.size()) + ")";
        return false;
    }
    std::vector<uint8_t> file(sizeof(sepal_fmt_header) + chunks.size() * sizeof(sepal_fmt_chunk), 0);
    pad8(&file);
    std::vector<sepal_fmt_chunk> table;
    for (const Payload& p : chunks) {
        sepal_fmt_chunk c{};
        c.tag = p.tag;
        c.offset = file.size();
        c.size = p.bytes.size();
        c.crc = sepal_crc32(0, p.bytes.data(), p.bytes.size());
        table.push_back(c);
        append(&file, p.bytes.data(), p.bytes.size());
        pad8(&file);
    }
    std::memcpy(file.data() + sizeof(sepal_fmt_header), table.data(), table.size() * sizeof(sepal_fmt_chunk));
    sepal_fmt_header h{};
    std::memcpy(h.magic, SEPAL_FMT_MAGIC, 8);
    // The oldest version that can say it: assets without version-2 features stay 1.0,
    // byte-identical to what earlier writers produced.
    const bool v2 = asset_needs_version2(asset);
    h.version_major = v2 ? SEPAL_FMT_VERSION_MAJOR : 1;
    // 2.1 only for reciprocal materials, 2.2 only for axis ones: other version-2 assets stay
    // 2.0, byte for byte.
    h.version_minor = v2 ? asset_minor_version(asset) : 0;
    h.header_bytes = sizeof h;
    h.file_bytes = file.size();
    h.chunk_count = uint32_t(chunks.size());
    // The header checksum covers the header (with this field 0) and the chunk table.
    std::memcpy(file.data(), &h, sizeof h);
    h.header_crc = sepal_crc32(0, file.data(), sizeof h + table.size() * sizeof(sepal_fmt_chunk));
    std::memcpy(file.data(), &h, sizeof h);
    // The runtime's reader is the judge of what a valid asset is.
    auto check = std::make_unique<sepal_asset>();  // ~8 KB: not on the stack
    sepal_error e{};
    if (sepal_asset_parse(file.data(), file.size(), check.get(), &e) != SEPAL_OK) {
        if (err) *err = std::string("asset encoder produced an invalid asset: ") + e.message;
        return false;
    }
    *out = std::move(file);
    return true;
}

bool asset_needs_version2(const AssetData& a) {
    const sepal_fmt_material& m = a.material;
    bool v2 = m.flags != 0 || m.diffuse[0] != 0.0f || m.diffuse[1] != 0.0f || m.diffuse[2] != 0.0f ||
              !a.diffuse_profile.empty();
    for (const sepal_fmt_pass& p : a.passes) v2 = v2 || p.op == SEPAL_OP_DIFFUSE || p.op == SEPAL_OP_RECIPROCAL;
    v2 = v2 || m.param == SEPAL_PARAM_AXIS || m.param == SEPAL_PARAM_GS_MIRROR;  // 2.2, 2.6
    return v2 || asset_has_light_range(a) || a.has_profile || m.horizon != 0.0f;  // 2.3, 2.4, 2.7
}

float diffuse_u16_value(uint16_t q) { return float(q) / 65535.0f; }

uint16_t asset_minor_version(const AssetData& a) {
    return a.material.horizon > 0.0f                          ? SEPAL_FMT_VERSION_MINOR_HORIZON
           : a.material.param == SEPAL_PARAM_GS_MIRROR        ? SEPAL_FMT_VERSION_MINOR_MIRROR
           : !a.diffuse_profile.empty()                       ? SEPAL_FMT_VERSION_MINOR_DIFFUSE16
           : a.has_profile                                    ? SEPAL_FMT_VERSION_MINOR_PROFILE
           : asset_has_light_range(a)                         ? SEPAL_FMT_VERSION_MINOR_LIGHT_RANGE
           : a.material.param == SEPAL_PARAM_AXIS             ? SEPAL_FMT_VERSION_MINOR_AXIS
           : a.material.flags & SEPAL_MATERIAL_RECIPROCAL     ? SEPAL_FMT_VERSION_MINOR_RECIPROCAL
                                                              : 0;
}

bool asset_has_light_range(const AssetData& a) {
    const sepal_fmt_material& m = a.material;
    return m.white_level != 0.0f || m.irradiance_min != 0.0f || m.irradiance_max != 0.0f || m.cone_degrees != 0.0f ||
           m.max_lights != 0;
}

bool write_asset(const std::string& path, const AssetData& asset, std::string* err) {
    std::vector<uint8_t> bytes;
    return encode_asset(asset, &bytes, err) && write_file_atomic(path, bytes.data(), bytes.size(), err);
}

}  // namespace sepal
