#include "ist/tree_asset.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

#include "bake/asset_file.h"
#include "bake/bake.h"
#include "ist/ist_util.h"
#include "sepal/sepal_tree.h"

namespace sepal {

using ist_detail::fail;

namespace {
int pow2_at_least(int v) {
    int p = 1;
    while (p < v) p *= 2;
    return p;
}
void put(std::vector<uint8_t>* out, size_t at, const void* data, size_t size) {
    std::memcpy(out->data() + at, data, size);
}
}  // namespace

bool encode_tree_asset(const ShadeTree& t, const TreeAssetOptions& o, std::vector<uint8_t>* out, TreeAssetInfo* info,
                       std::string* err) {
    if (!validate_tree(t, err)) return false;
    if (t.basis_count() > SEPAL_TREE_MAX_BASES) return fail(err, "tree asset: at most 8 bases");
    const int bw = std::min(pow2_at_least(t.blend.width), SEPAL_TREE_MAX_BLEND_SIDE);
    const int bh = std::min(pow2_at_least(t.blend.height), SEPAL_TREE_MAX_BLEND_SIDE);
    const int k = t.basis_count();
    TreeAssetInfo inf;
    inf.blend_width = bw;
    inf.blend_height = bh;
    std::vector<std::vector<uint8_t>> assets(static_cast<size_t>(k)), maps(static_cast<size_t>(k));
    for (int j = 0; j < k; ++j) {
        // The map on the power-of-two grid, and its largest weight.
        std::vector<double> w(size_t(bw) * bh);
        double peak = 0;
        for (int y = 0; y < bh; ++y)
            for (int x = 0; x < bw; ++x) {
                const double v = std::max(0.0, t.blend.sample(j, (x + 0.5) / bw, (y + 0.5) / bh));
                w[size_t(y) * bw + x] = v;
                peak = std::max(peak, v);
            }
        const double scale = peak > 0 ? peak : 1.0;
        maps[size_t(j)].resize(w.size());
        for (size_t i = 0; i < w.size(); ++i)
            maps[size_t(j)][i] = uint8_t(std::lround(std::min(1.0, w[i] / scale) * 255.0));
        Factored f = t.textures(j);
        for (FactorTerm& term : f.terms)
            for (float& v : term.h.data) v = float(v * scale);
        QuantizeOptions q;
        q.bits = o.bits;
        q.mips = o.mips;
        AssetData a;
        if (!make_asset(f, f.term_count(), q, &a, err)) return fail(err, "tree asset: basis " + std::to_string(j) + ": " + *err);
        if (!encode_asset(a, &assets[size_t(j)], err)) return false;
        inf.blend_scale.push_back(float(scale));
        inf.passes.push_back(int(a.passes.size()));
    }
    // Layout: header, table, blend maps, then each asset at an 8-byte boundary.
    const size_t table = sizeof(sepal_tree_header) + size_t(k) * sizeof(sepal_tree_basis);
    size_t at = table + size_t(k) * size_t(bw) * bh;
    std::vector<sepal_tree_basis> rows(static_cast<size_t>(k));
    for (int j = 0; j < k; ++j) {
        at = (at + 7) / 8 * 8;
        rows[size_t(j)].blend_offset = table + size_t(j) * size_t(bw) * bh;
        rows[size_t(j)].asset_offset = at;
        rows[size_t(j)].asset_bytes = assets[size_t(j)].size();
        rows[size_t(j)].blend_scale = inf.blend_scale[size_t(j)];
        at += assets[size_t(j)].size();
    }
    if (at > SEPAL_TREE_MAX_FILE_BYTES) return fail(err, "tree asset: " + std::to_string(at) + " bytes, over the format's limit");
    std::vector<uint8_t> bytes(at, 0);
    sepal_tree_header h = {};
    std::memcpy(h.magic, SEPAL_TREE_MAGIC, 8);
    h.version_major = SEPAL_TREE_VERSION_MAJOR;
    h.version_minor = SEPAL_TREE_VERSION_MINOR;
    h.header_bytes = sizeof h;
    h.file_bytes = at;
    h.basis_count = uint32_t(k);
    h.blend_width = uint32_t(bw);
    h.blend_height = uint32_t(bh);
    put(&bytes, 0, &h, sizeof h);
    put(&bytes, sizeof h, rows.data(), rows.size() * sizeof(sepal_tree_basis));
    for (int j = 0; j < k; ++j) {
        put(&bytes, rows[size_t(j)].blend_offset, maps[size_t(j)].data(), maps[size_t(j)].size());
        put(&bytes, rows[size_t(j)].asset_offset, assets[size_t(j)].data(), assets[size_t(j)].size());
    }
    h.crc = sepal_crc32(0, bytes.data(), bytes.size());
    put(&bytes, 0, &h, sizeof h);
    auto check = std::make_unique<sepal_tree_asset>();
    sepal_error e = {};
    if (sepal_tree_parse(bytes.data(), bytes.size(), check.get(), &e) != SEPAL_OK)
        return fail(err, std::string("tree asset: the runtime refuses what was written: ") + e.message);
    inf.bytes = bytes.size();
    *out = std::move(bytes);
    if (info) *info = inf;
    return true;
}

}  // namespace sepal
