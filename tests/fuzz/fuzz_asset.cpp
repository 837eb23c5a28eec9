// The asset parser, sepal_asset_parse: the bytes as they are, then with the checksums fixed
// up (fuzz.h) so mutations reach the fields. An accepted asset is walked the way the
// backends read it; every pointer must lie inside the buffer and every promise hold.
#include <cmath>
#include <cstring>

#include "fuzz/fuzz.h"
#include "sepal/sepal_asset.h"

namespace {

uint32_t walk(const sepal_asset& a, const uint8_t* base, size_t size) {
    const char* h = "asset";
    auto inside = [&](const void* p, size_t n) {
        const uint8_t* q = static_cast<const uint8_t*>(p);
        return q >= base && n <= size && size_t(q - base) <= size - n;
    };
    uint32_t sum = 0;
    sepal_fuzz::check(a.texture_count >= 1 && a.texture_count <= SEPAL_FMT_MAX_TEXTURES, h, "texture count");
    for (uint32_t i = 0; i < a.texture_count; ++i) {
        const sepal_asset_texture& t = a.textures[i];
        sepal_fuzz::check(t.desc.term < a.material.terms && t.desc.role < SEPAL_ROLE_COUNT, h, "texture term or role");
        for (uint32_t l = 0; l < t.desc.levels; ++l) {
            sepal_fuzz::check(inside(t.level_data[l], t.level_bytes[l]), h, "texture level outside the buffer");
            sum = sepal_crc32(sum, t.level_data[l], t.level_bytes[l]);
        }
        for (int c = 0; c < 4; ++c)
            sepal_fuzz::check(std::isfinite(t.desc.scale[c]) && std::isfinite(t.desc.bias[c]), h, "non-finite scale");
    }
    sepal_fuzz::check(a.plan.pass_count >= 1 && a.plan.pass_count <= SEPAL_FMT_MAX_PASSES, h, "pass count");
    for (uint32_t p = 0; p < a.plan.pass_count; ++p) {
        const sepal_fmt_pass& pass = a.passes[p];
        if (pass.op == SEPAL_OP_PRODUCT || pass.op == SEPAL_OP_TEXTURE)
            sepal_fuzz::check(pass.tex0 < a.texture_count, h, "pass texture out of range");
        if (pass.op == SEPAL_OP_PRODUCT) sepal_fuzz::check(pass.tex1 < a.texture_count, h, "pass texture out of range");
    }
    if (a.meta) {
        sepal_fuzz::check(inside(a.meta, a.meta_bytes), h, "META outside the buffer");
        sum = sepal_crc32(sum, a.meta, a.meta_bytes);
    }
    if (a.diffuse_profile) {
        const size_t sample_bytes = a.diffuse_layout == SEPAL_FMT_DIFFUSE_RGB_F32 ? 12 : a.diffuse_layout == SEPAL_FMT_DIFFUSE_RGB_U16 ? 6 : 2;
        sepal_fuzz::check(inside(a.diffuse_profile, size_t(a.diffuse_side) * a.diffuse_side * sample_bytes), h,
                          "diffuse profile outside the buffer");
        for (float ci : {-1.0f, 0.0f, 0.3f, 1.0f, 2.0f, NAN})
            for (int c = 0; c < 3; ++c) {
                const float v = sepal_diffuse_profile(a.diffuse_profile, a.diffuse_side, a.diffuse_layout, ci, 0.5f, c);
                sepal_fuzz::check(v >= 0.0f && v <= 1.0f, h, "diffuse profile value outside [0,1]");
            }
    }
    return sum;
}

void parse(const uint8_t* data, size_t size) {
    static sepal_asset asset;
    sepal_error err = {};
    const sepal_result r = sepal_asset_parse(data, size, &asset, &err);
    if (r != SEPAL_OK) {
        sepal_fuzz::check(err.code == r && err.message[0] != '\0', "asset", "a refusal without a message");
        sepal_fuzz::check(std::strncmp(err.message, "asset: ", 7) == 0, "asset", "a message that does not say where");
        return;
    }
    walk(asset, data, size);
}

}  // namespace

extern "C" int sepal_fuzz_asset(const uint8_t* data, size_t size) {
    parse(data, size);
    std::vector<uint8_t> fixed(data, data + size);
    sepal_fuzz::fix_asset_checksums(&fixed);
    parse(fixed.data(), fixed.size());
    return 0;
}
