#include "bake/export.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "bake/asset_brdf.h"
#include "util/image.h"
#include "util/io.h"
#include "util/json.h"

namespace sepal {
namespace {

struct ExportInfo {
    std::string source, param, map, colour, method;
    int terms = 0;
    float ratio[3] = {1, 1, 1};
    // What the textures' sum is drawn with (the material's flags, diffuse part, white level
    // and light range): without it nobody outside the runtime can recompute what they stand for.
    bool radiance = false, reciprocal = false;
    double diffuse[3] = {0, 0, 0};
    int diffuse_side = 0;
    const float* diffuse_profile = nullptr;  // side * side * 3, index (j * side + i) * 3 + c
    double white_level = 0;
    double horizon = 0;  // the radiance factors' horizon window (format 2.7; 0: none)
    const sepal_fmt_material* range = nullptr;  // light range (format 2.3), when declared
};

// The manifest's account of how the textures are drawn, and the diffuse profile as a PFM.
bool export_shading(const ExportInfo& info, const std::string& dir, Json* manifest, std::string* err) {
    Json& m = *manifest;
    m["radiance"] = info.radiance;
    m["reciprocal"] = info.reciprocal;
    m["diffuse"] = {info.diffuse[0], info.diffuse[1], info.diffuse[2]};
    if (info.diffuse_side > 0) {
        const int n = info.diffuse_side;
        Image img(n, n, 3);
        for (int y = 0; y < n; ++y)  // image row y shows profile row (cos_o index) n - 1 - y
            for (int i = 0; i < n * 3; ++i)
                img.data[size_t(y) * n * 3 + i] = info.diffuse_profile[size_t(n - 1 - y) * n * 3 + i];
        if (!write_pfm(dir + "/diffuse_profile.pfm", img, err)) return false;
        m["diffuse_profile"] = {{"file", "diffuse_profile.pfm"},
                                {"side", n},
                                {"layout", "RGB in [0,1]; column i at cos(theta_i) = i / (side - 1), row j from the "
                                           "bottom at cos(theta_o) = j / (side - 1); bilinear between nodes"}};
    } else {
        m["diffuse_profile"] = nullptr;
    }
    m["white_level"] = info.white_level > 0 ? Json(info.white_level) : Json(nullptr);
    m["horizon"] = info.horizon > 0 ? Json(info.horizon) : Json(nullptr);
    if (info.range)
        m["light_range"] = {{"irradiance_min", double(info.range->irradiance_min)},
                            {"irradiance_max", double(info.range->irradiance_max)},
                            {"cone_degrees", double(info.range->cone_degrees)},
                            {"max_lights", int(info.range->max_lights)}};
    m["evaluation"] = "f_c cos(theta_i) = " +
                      evaluation_formula(info.radiance, info.reciprocal, info.diffuse_side > 0, info.white_level > 0,
                                         info.horizon) +
                      ", per channel c; G_k, H_k = scale * q + bias sampled bilinearly at the pair's coordinates "
                      "(param, map); `sepal eval ASSET` prints it";
    return true;
}

const char* kParamNames[] = {"iv", "gs-half", "vh", "rusinkiewicz", "elev-azim", "axis", "gs-mirror"};

// Writes every texture's levels and level-0 floats, then the manifest.
bool export_textures(const std::vector<AssetTexture>& textures, const ExportInfo& info, const std::string& dir,
                     std::string* err) {
    if (!make_dirs(dir, err)) return false;
    Json manifest = {{"source", info.source}, {"param", info.param}, {"map", info.map},
                     {"colour", info.colour}, {"method", info.method}, {"terms", info.terms},
                     {"ratio", {info.ratio[0], info.ratio[1], info.ratio[2]}}};
    manifest["layout"] =
        "term<k>_<G|H>_mip<l>.png: stored codes q in [0,1] per MIP level, value = scale * q + bias per channel; "
        "term<k>_<G|H>.pfm: level-0 values; images flipped so v grows upwards (bottom row = texture row 0)";
    if (!export_shading(info, dir, &manifest, err)) return false;
    manifest["textures"] = Json::array();
    for (const AssetTexture& t : textures) {
        const sepal_fmt_texture& d = t.desc;
        const int ch = int(d.channels), bytes = d.bits == 16 ? 2 : 1;
        const std::string base = dir + "/term" + std::to_string(d.term) + (d.role == SEPAL_ROLE_G ? "_G" : "_H");
        Json files = Json::array();
        size_t offset = 0;
        for (uint32_t l = 0; l < d.levels; ++l) {
            const int w = std::max(1, int(d.width >> l)), h = std::max(1, int(d.height >> l));
            const size_t count = size_t(w) * h * ch;
            if (offset + count * bytes > t.data.size()) {
                if (err) *err = base + ": texture data shorter than its " + std::to_string(d.levels) + " levels";
                return false;
            }
            std::vector<uint16_t> codes(count);
            for (int y = 0; y < h; ++y)  // image row y shows texture row h - 1 - y
                for (size_t i = 0; i < size_t(w) * ch; ++i) {
                    const size_t k = offset + (size_t(h - 1 - y) * w * ch + i) * bytes;
                    codes[size_t(y) * w * ch + i] =
                        bytes == 2 ? uint16_t(t.data[k] | (t.data[k + 1] << 8)) : uint16_t(t.data[k]);
                }
            offset += count * bytes;
            const std::string png = base + "_mip" + std::to_string(l) + ".png";
            bool ok;
            if (bytes == 2) {
                ok = write_png16(png, w, h, ch, codes, err);
            } else {
                Image img(w, h, ch);
                for (size_t i = 0; i < count; ++i) img.data[i] = float(codes[i]) / 255.0f;
                ok = write_png(png, img, err);
            }
            if (!ok) return false;
            files.push_back(png.substr(dir.size() + 1));
            if (l == 0 && (ch == 1 || ch == 3)) {
                Image values(w, h, ch);
                const double top = bytes == 2 ? 65535.0 : 255.0;
                for (size_t i = 0; i < count; ++i)
                    values.data[i] = float(d.scale[i % ch] * (codes[i] / top) + d.bias[i % ch]);
                if (!write_pfm(base + ".pfm", values, err)) return false;
                files.push_back(base.substr(dir.size() + 1) + ".pfm");
            }
        }
        Json x = {{"term", int(d.term)},      {"role", d.role == SEPAL_ROLE_G ? "G" : "H"},
                  {"size", int(d.width)},     {"levels", int(d.levels)},
                  {"channels", ch},           {"bits", int(d.bits)}};
        x["scale"] = Json::array();
        x["bias"] = Json::array();
        for (int c = 0; c < ch; ++c) x["scale"].push_back(double(d.scale[c])), x["bias"].push_back(double(d.bias[c]));
        x["files"] = std::move(files);
        manifest["textures"].push_back(std::move(x));
    }
    return write_json_file(dir + "/manifest.json", manifest, err);
}

// A float factor as 16-bit codes over its own range (non-negative: bias 0; signed: bias min).
AssetTexture codes16(const FactorTexture& f, int term, bool g) {
    AssetTexture t;
    t.desc.width = t.desc.height = uint32_t(f.n);
    t.desc.channels = uint32_t(f.channels);
    t.desc.levels = 1;
    t.desc.bits = 16;
    t.desc.term = uint32_t(term);
    t.desc.role = g ? SEPAL_ROLE_G : SEPAL_ROLE_H;
    for (int c = 0; c < f.channels; ++c) {
        double lo = 0, hi = 0;
        for (size_t i = size_t(c); i < f.data.size(); i += size_t(f.channels))
            lo = std::min(lo, double(f.data[i])), hi = std::max(hi, double(f.data[i]));
        t.desc.bias[c] = float(lo);
        t.desc.scale[c] = float(hi - lo);
    }
    t.data.resize(f.data.size() * 2);
    for (size_t i = 0; i < f.data.size(); ++i) {
        const int c = int(i % size_t(f.channels));
        const double s = t.desc.scale[c], q = s > 0 ? (f.data[i] - t.desc.bias[c]) / s : 0.0;
        const uint16_t v = uint16_t(std::lround(std::clamp(q, 0.0, 1.0) * 65535.0));
        t.data[2 * i] = uint8_t(v & 0xff), t.data[2 * i + 1] = uint8_t(v >> 8);  // little-endian, as assets
    }
    return t;
}

}  // namespace

bool export_asset(const AssetData& a, const std::string& dir, std::string* err) {
    ExportInfo info;
    Json meta;
    if (!a.meta.empty() && parse_json(a.meta, "asset META", &meta, nullptr)) {
        json_string(JsonField{meta, ""}, "spec", &info.source, nullptr);
        json_string(JsonField{meta, ""}, "method", &info.method, nullptr);
    }
    info.param = kParamNames[a.material.param % SEPAL_PARAM_COUNT];
    const bool angles = a.material.param == SEPAL_PARAM_ELEV_AZIM || a.material.param == SEPAL_PARAM_AXIS;
    info.map = angles ? "angles" : a.material.map == SEPAL_MAP_XY ? "xy" : "parabolic";
    info.colour = a.material.color_mode == SEPAL_COLOR_PER_CHANNEL ? "rgb" : "luminance";
    info.terms = int(a.material.terms);
    std::copy(a.material.ratio, a.material.ratio + 3, info.ratio);
    info.radiance = (a.material.flags & SEPAL_MATERIAL_RADIANCE) != 0;
    info.reciprocal = (a.material.flags & SEPAL_MATERIAL_RECIPROCAL) != 0;
    std::copy(a.material.diffuse, a.material.diffuse + 3, info.diffuse);
    if (a.diffuse_side > 0 && a.diffuse_profile.size() == size_t(a.diffuse_side) * a.diffuse_side * 3) {
        info.diffuse_side = int(a.diffuse_side);
        info.diffuse_profile = a.diffuse_profile.data();
    }
    info.white_level = a.material.white_level;
    info.horizon = a.material.horizon;
    if (asset_has_light_range(a)) info.range = &a.material;
    return export_textures(a.textures, info, dir, err);
}

bool export_factored(const Factored& f, const std::string& dir, std::string* err) {
    ExportInfo info;
    info.source = f.source;
    info.param = param_name(f.param);
    info.map = angle_textures(f.param) ? "angles" : map_name(f.map);
    info.colour = colour_name(f.colour);
    info.method = f.method;
    info.terms = f.term_count();
    info.ratio[0] = float(f.ratio.x), info.ratio[1] = float(f.ratio.y), info.ratio[2] = float(f.ratio.z);
    info.radiance = f.radiance;
    info.horizon = f.radiance ? f.horizon : 0.0;
    info.reciprocal = f.form == Form::Reciprocal;
    for (int c = 0; c < 3; ++c) info.diffuse[c] = f.diffuse[c];
    if (f.diffuse_side > 0 && f.diffuse_profile.size() == size_t(f.diffuse_side) * f.diffuse_side * 3) {
        info.diffuse_side = f.diffuse_side;
        info.diffuse_profile = f.diffuse_profile.data();
    }
    std::vector<AssetTexture> textures;
    for (int k = 0; k < f.term_count(); ++k) {
        textures.push_back(codes16(f.terms[size_t(k)].g, k, true));
        textures.push_back(codes16(f.terms[size_t(k)].h, k, false));
    }
    return export_textures(textures, info, dir, err);
}

}  // namespace sepal
