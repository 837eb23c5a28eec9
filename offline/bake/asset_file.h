// Writing .sepal assets (the format is runtime/include/sepal/sepal_format.h, shared with the reader).
//
// Usage:
//   sepal::AssetData a;  a.material = ...; a.textures.push_back(...); a.plan = ...; ...
//   std::string err;
//   if (!sepal::write_asset("out.sepal", a, &err)) ...
//
// encode_asset lays out header, chunk table and chunks (MATL, TEXR..., PLAN, META) with
// zeroed padding and reserved fields, so equal inputs give byte-identical files, then
// parses the result with the runtime's own reader: a writer bug cannot produce a file
// the runtime refuses. write_asset writes atomically.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "sepal/sepal_format.h"

namespace sepal {

struct AssetTexture {
    sepal_fmt_texture desc{};     // data_bytes is filled in by the encoder
    std::vector<uint8_t> data;  // all MIP levels, level 0 first
};

struct AssetData {
    sepal_fmt_material material{};
    std::vector<AssetTexture> textures;
    sepal_fmt_plan plan{};  // pass_count is filled in by the encoder
    std::vector<sepal_fmt_pass> passes;
    // The diffuse profile (format 2, DIFF chunk): side * side RGB samples in [0,1], or empty;
    // written in 16 bits (format 2.5, below).
    uint32_t diffuse_side = 0;
    std::vector<float> diffuse_profile;
    std::string meta;  // JSON manifest; may be empty
    // The device profile it was judged for (format 2.4, PROF chunk); none: the default.
    bool has_profile = false;
    sepal_fmt_profile profile{};
};

bool encode_asset(const AssetData& asset, std::vector<uint8_t>* out, std::string* err);
// True when the asset uses a version-2 feature (radiance or reciprocal flag, diffuse part or
// profile, DIFFUSE or RECIPROCAL pass, light range, device profile, horizon window); encode_asset writes
// version 1.0 otherwise.
bool asset_needs_version2(const AssetData& asset);
// True when the material's light range (2.3) is set: encode_asset then writes 2.3 and the
// 96-byte MATL chunk.
bool asset_has_light_range(const AssetData& asset);
// The header's minor version for a version-2 asset: 2.5 with a diffuse profile, 2.4 with a
// device profile, 2.3 with a light range, 2.2 for axis, 2.1 for reciprocal, else 2.0.
uint16_t asset_minor_version(const AssetData& asset);
// The DIFF chunk stores the diffuse profile in 16 bits (format 2.5): once per sample when its
// three channels round to the same value (SEPAL_FMT_DIFFUSE_GREY_U16), else per channel
// (RGB_U16), each the nearest of q / 65535. diffuse_u16_value(q) is what q reads back as,
// bit for bit the runtime's decoding: the bake stores its profile as such values, so what it
// judges is what it writes.
float diffuse_u16_value(uint16_t q);
bool write_asset(const std::string& path, const AssetData& asset, std::string* err);

}  // namespace sepal
