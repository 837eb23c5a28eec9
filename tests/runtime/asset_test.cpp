// The .sepal format: writer/reader round trip, determinism, and refusal of corrupt,
// truncated and oversized files (runtime/include/sepal/sepal_format.h, offline/bake/asset_file.h).
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <string>

#include "bake/asset_file.h"
#include "bake/plan.h"
#include "fuzz/fuzz.h"
#include "sepal/sepal_asset.h"

namespace {

// One term, 4x4 RGB textures with the full MIP chain, one product pass.
sepal::AssetData small_asset() {
    sepal::AssetData a;
    a.material.param = SEPAL_PARAM_GS_HALF;
    a.material.map = SEPAL_MAP_XY;
    a.material.color_mode = SEPAL_COLOR_PER_CHANNEL;
    a.material.terms = 1;
    a.material.channels = 3;
    a.material.ratio[0] = a.material.ratio[1] = a.material.ratio[2] = 1.0f;
    a.material.error_quantized = 0.01f;
    a.material.error_float = 0.009f;
    a.material.error_relative = 0.05f;
    for (uint32_t role = 0; role < 2; ++role) {
        sepal::AssetTexture t;
        t.desc.width = t.desc.height = 4;
        t.desc.levels = 3;  // 4x4, 2x2, 1x1
        t.desc.channels = 3;
        t.desc.bits = 8;
        t.desc.role = role;
        t.desc.term = 0;
        for (int c = 0; c < 4; ++c) t.desc.scale[c] = 2.0f, t.desc.bias[c] = 0.0f;
        for (int i = 0; i < (16 + 4 + 1) * 3; ++i) t.data.push_back(uint8_t(i * 7 + role));
        a.textures.push_back(t);
    }
    a.plan.doublings = 2;
    a.plan.peak_partial_sum = 0.9f;
    sepal_fmt_pass p{};
    p.op = SEPAL_OP_PRODUCT;
    p.blend = SEPAL_BLEND_ADD;
    p.tex0 = 0;
    p.tex1 = 1;
    p.color[0] = p.color[1] = p.color[2] = 1.0f;  // times 2^2 doublings: the factors' 2 x 2
    p.rgb_scale = 1;
    a.passes.push_back(p);
    a.meta = "{\"spec\": \"test\"}";
    return a;
}

std::vector<uint8_t> encode(const sepal::AssetData& a) {
    std::vector<uint8_t> bytes;
    std::string err;
    REQUIRE_MESSAGE(sepal::encode_asset(a, &bytes, &err), err);
    return bytes;
}

sepal_result parse(const std::vector<uint8_t>& bytes, std::string* msg) {
    auto asset = std::make_unique<sepal_asset>();
    sepal_error e{};
    const sepal_result r = sepal_asset_parse(bytes.data(), bytes.size(), asset.get(), &e);
    *msg = e.message;
    return r;
}

// Recomputes every chunk checksum and the header checksum, so a test can reach the
// reader's deeper checks with a deliberately inconsistent file (the fuzz harnesses' fix-up).
void reseal(std::vector<uint8_t>* b) { sepal_fuzz::fix_asset_checksums(b); }

// Offset of chunk i's payload.
size_t chunk_offset(const std::vector<uint8_t>& b, int i) {
    sepal_fmt_chunk c;
    std::memcpy(&c, b.data() + sizeof(sepal_fmt_header) + size_t(i) * sizeof c, sizeof c);
    return size_t(c.offset);
}

template <typename T>
void poke(std::vector<uint8_t>* b, size_t offset, T value) {
    std::memcpy(b->data() + offset, &value, sizeof value);
}

}  // namespace

TEST_CASE("asset: round trip keeps every field and pixel; encoding is deterministic") {
    const sepal::AssetData a = small_asset();
    const std::vector<uint8_t> bytes = encode(a);
    CHECK(bytes == encode(a));
    auto asset = std::make_unique<sepal_asset>();
    sepal_error e{};
    REQUIRE_MESSAGE(sepal_asset_parse(bytes.data(), bytes.size(), asset.get(), &e) == SEPAL_OK, e.message);
    CHECK(asset->material.param == SEPAL_PARAM_GS_HALF);
    CHECK(asset->material.error_quantized == 0.01f);
    REQUIRE(asset->texture_count == 2);
    CHECK(asset->textures[1].desc.role == SEPAL_ROLE_H);
    CHECK(asset->textures[1].level_bytes[2] == 3);
    CHECK(std::memcmp(asset->textures[1].level_data[0], a.textures[1].data.data(), 48) == 0);
    CHECK(asset->textures[1].level_data[2][2] == a.textures[1].data[62]);
    CHECK(asset->plan.pass_count == 1);
    CHECK(asset->plan.doublings == 2);
    CHECK(asset->passes[0].color[1] == 1.0f);
    CHECK(std::string(asset->meta, asset->meta_bytes) == a.meta);
}

TEST_CASE("asset: CRC-32 is the standard one") {
    CHECK(sepal_crc32(0, "123456789", 9) == 0xCBF43926u);  // the published check value
    CHECK(sepal_crc32(sepal_crc32(0, "1234", 4), "56789", 5) == 0xCBF43926u);
}

TEST_CASE("asset: the writer refuses what the reader would refuse") {
    sepal::AssetData a = small_asset();
    a.textures[0].desc.width = 3;
    std::vector<uint8_t> bytes;
    std::string err;
    CHECK_FALSE(sepal::encode_asset(a, &bytes, &err));
    CHECK(err.find("powers of two") != std::string::npos);
    a = small_asset();
    a.passes[0].color[0] = 1.5f;
    CHECK_FALSE(sepal::encode_asset(a, &bytes, &err));
    CHECK(err.find("outside [0,1]") != std::string::npos);
}

TEST_CASE("asset: one validity for every backend: a plan that adds after subtracting, infinite errors") {
    // Class 7 (one validity for every backend): the reader refuses these, so no backend meets
    // them at load.
    sepal::AssetData a = small_asset();
    sepal_fmt_pass sub = a.passes[0];
    sub.blend = SEPAL_BLEND_SUBTRACT;
    a.passes.insert(a.passes.begin(), sub);  // subtract, then add
    std::vector<uint8_t> bytes;
    std::string err;
    CHECK_FALSE(sepal::encode_asset(a, &bytes, &err));  // the writer checks with the reader
    CHECK(err.find("pass 1 adds after pass 0 subtracts") != std::string::npos);
    a = small_asset();
    a.passes.push_back(a.passes[0]);
    a.passes.push_back(a.passes[0]);
    a.passes[1].color[0] = a.passes[1].color[1] = a.passes[1].color[2] = 0.5f;
    a.passes[2] = a.passes[1];
    a.passes[2].blend = SEPAL_BLEND_SUBTRACT;  // add, add, then subtract (net the factors): valid
    CHECK_MESSAGE(sepal::encode_asset(a, &bytes, &err), err);
    a = small_asset();
    a.material.error_relative = INFINITY;
    CHECK_FALSE(sepal::encode_asset(a, &bytes, &err));
    CHECK(err.find("finite, or NaN") != std::string::npos);
    a.material.error_relative = NAN;  // not measured: fine
    CHECK_MESSAGE(sepal::encode_asset(a, &bytes, &err), err);
}

TEST_CASE("asset: one validity for every backend: reserved words, products, factor magnitudes (class 7)") {
    // Class 7: the reader refuses each of these.
    const std::vector<uint8_t> good = encode(small_asset());
    const size_t mat = chunk_offset(good, 0), tex = chunk_offset(good, 1), plan = chunk_offset(good, 3);
    struct Case {
        const char* what;
        std::function<void(std::vector<uint8_t>*)> corrupt;
        const char* message;
    };
    const Case cases[] = {
        {"header flags", [](std::vector<uint8_t>* b) { poke<uint32_t>(b, 28, 1); }, "reserved bytes not 0"},
        {"header reserved", [](std::vector<uint8_t>* b) { (*b)[63] = 1; }, "reserved bytes not 0"},
        {"material reserved", [mat](std::vector<uint8_t>* b) { poke<uint32_t>(b, mat + 20, 7); }, "material reserved word"},
        {"texture reserved", [tex](std::vector<uint8_t>* b) { poke<uint32_t>(b, tex + 28, 7); }, "texture 0 reserved word"},
        {"plan reserved", [plan](std::vector<uint8_t>* b) { poke<uint32_t>(b, plan + 12, 7); }, "plan's reserved words"},
        {"version-1 flags", [mat](std::vector<uint8_t>* b) { poke<uint32_t>(b, mat + 48, 1); }, "reserved in version 1"},
        // G x G: the plan paths would draw G_0 G_0, the CPU backend and fused shaders G_0 H_0.
        {"G x G product", [plan](std::vector<uint8_t>* b) { poke<uint16_t>(b, plan + 32 + 6, 0); },
         "a product is one term's G times its H"},
        {"H x G product",
         [plan](std::vector<uint8_t>* b) {
             poke<uint16_t>(b, plan + 32 + 4, 1);
             poke<uint16_t>(b, plan + 32 + 6, 0);
         },
         "multiplies texture 1 (term 0 H) by texture 0 (term 0 G)"},
        // 3.4e38 x 3.4e38 overflows: the CPU backend's f would be inf (clamped to FLT_MAX, or
        // NaN to 0, in the picture).
        {"scale 3.4e38", [tex](std::vector<uint8_t>* b) { poke<float>(b, tex + 32, 3.4e38f); }, "beyond +-1e+15"},
        {"bias -1e16", [tex](std::vector<uint8_t>* b) { poke<float>(b, tex + 48, -1e16f); }, "beyond +-1e+15"},
        {"ratio 1e30", [mat](std::vector<uint8_t>* b) { poke<float>(b, mat + 36, 1e30f); }, "colour ratio 1e+30 outside 0..1e+06"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.what);
        std::vector<uint8_t> b = good;
        c.corrupt(&b);
        reseal(&b);
        std::string msg;
        CHECK(parse(b, &msg) == SEPAL_ERR_INVALID_ARGUMENT);
        CHECK_MESSAGE(msg.find(c.message) != std::string::npos, msg);
    }
    // The writer checks with the reader: it cannot write them either.
    sepal::AssetData a = small_asset();
    a.textures[0].desc.scale[0] = 3.4e38f;
    std::vector<uint8_t> bytes;
    std::string err;
    CHECK_FALSE(sepal::encode_asset(a, &bytes, &err));
    CHECK(err.find("beyond +-1e+15") != std::string::npos);
}

TEST_CASE("asset: corrupt, truncated and oversized files are refused with a clear message") {
    const std::vector<uint8_t> good = encode(small_asset());
    const size_t mat = chunk_offset(good, 0), tex = chunk_offset(good, 1), tex_h = chunk_offset(good, 2),
                 plan = chunk_offset(good, 3);
    struct Case {
        const char* what;
        std::function<void(std::vector<uint8_t>*)> damage;
        const char* expect;
    };
    const Case cases[] = {
        {"empty", [](std::vector<uint8_t>* b) { b->clear(); }, "too short"},
        {"truncated", [](std::vector<uint8_t>* b) { b->pop_back(); }, "truncated"},
        {"padded", [](std::vector<uint8_t>* b) { b->push_back(0); }, "truncated or padded"},
        {"bad magic", [](std::vector<uint8_t>* b) { (*b)[0] = 'X'; }, "bad magic"},
        {"newer major version", [](std::vector<uint8_t>* b) { poke<uint16_t>(b, 8, 3); }, "format version 3"},
        {"flipped header bit", [](std::vector<uint8_t>* b) { (*b)[40] ^= 1; }, "header checksum"},
        {"flipped table bit", [](std::vector<uint8_t>* b) { (*b)[64 + 4] ^= 1; }, "header checksum"},
        {"flipped pixel", [tex](std::vector<uint8_t>* b) { (*b)[tex + 80] ^= 0x10; }, "checksum mismatch"},
        {"no chunks", [](std::vector<uint8_t>* b) { poke<uint32_t>(b, 24, 0); reseal(b); }, "0 chunks"},
        {"absurd chunk count", [](std::vector<uint8_t>* b) { poke<uint32_t>(b, 24, 100000); reseal(b); },
         "chunks (1..64)"},
        {"chunk outside the file",
         [](std::vector<uint8_t>* b) { poke<uint64_t>(b, 64 + 8, uint64_t(1) << 40); reseal(b); }, "outside the file"},
        {"non-power-of-two texture", [tex](std::vector<uint8_t>* b) { poke<uint32_t>(b, tex, 3); reseal(b); },
         "powers of two"},
        {"oversized texture", [tex](std::vector<uint8_t>* b) { poke<uint32_t>(b, tex, 4096); reseal(b); },
         "powers of two up to 1024"},
        {"wrong MIP count", [tex](std::vector<uint8_t>* b) { poke<uint32_t>(b, tex + 8, 2); reseal(b); },
         "MIP levels"},
        {"16 channels", [tex](std::vector<uint8_t>* b) { poke<uint32_t>(b, tex + 12, 16); reseal(b); },
         "channels"},
        {"NaN scale", [tex](std::vector<uint8_t>* b) { poke<float>(b, tex + 32, NAN); reseal(b); }, "not finite"},
        {"unknown parameterization", [mat](std::vector<uint8_t>* b) { poke<uint32_t>(b, mat, 9); reseal(b); },
         "unknown parameterization"},
        {"too many terms", [mat](std::vector<uint8_t>* b) { poke<uint32_t>(b, mat + 12, 99); reseal(b); },
         "terms"},
        {"pass count beyond the chunk",
         [plan](std::vector<uint8_t>* b) { poke<uint32_t>(b, plan, 5); reseal(b); }, "plan of 5 passes"},
        {"pass texture out of range",
         [plan](std::vector<uint8_t>* b) { poke<uint16_t>(b, plan + 32 + 4, 7); reseal(b); }, "texture slot 0 is 7"},
        {"pass colour above 1",
         [plan](std::vector<uint8_t>* b) { poke<float>(b, plan + 32 + 8, 3.0f); reseal(b); }, "outside [0,1]"},
        {"NaN peak partial sum", [plan](std::vector<uint8_t>* b) { poke<float>(b, plan + 8, NAN); reseal(b); },
         "peak partial sum"},
        {"absurd doublings", [plan](std::vector<uint8_t>* b) { poke<uint32_t>(b, plan + 4, 40); reseal(b); },
         "doublings"},
        {"missing H texture", [tex_h](std::vector<uint8_t>* b) { poke<uint32_t>(b, tex_h + 20, 0); reseal(b); },
         "one G and one H"},
    };
    int refused = 0;
    for (const Case& c : cases) {
        const std::string what = c.what;
        CAPTURE(what);
        std::vector<uint8_t> b = good;
        c.damage(&b);
        std::string msg;
        CHECK(parse(b, &msg) != SEPAL_OK);
        CHECK_MESSAGE(msg.find(c.expect) != std::string::npos, msg);
        refused += msg.find(c.expect) != std::string::npos;
    }
    CHECK(refused >= 20);
    // Sanity: the untouched file parses.
    std::string msg;
    CHECK(parse(good, &msg) == SEPAL_OK);
}

namespace {

// The passes of an encoded asset, found through its PLAN chunk (for edits behind the writer).
sepal_fmt_pass* plan_passes(std::vector<uint8_t>* b) {
    sepal_fmt_header h;
    std::memcpy(&h, b->data(), sizeof h);
    for (uint32_t i = 0; i < h.chunk_count; ++i) {
        sepal_fmt_chunk c;
        std::memcpy(&c, b->data() + sizeof h + i * sizeof c, sizeof c);
        if (std::memcmp(&c.tag, "PLAN", 4) == 0)
            return reinterpret_cast<sepal_fmt_pass*>(b->data() + c.offset + sizeof(sepal_fmt_plan));
    }
    FAIL("no PLAN chunk");
    return nullptr;
}

}  // namespace

TEST_CASE("asset: the pass plan must draw the factors, for every backend alike") {
    // Two terms with signed factors: every kind of pass, the way the writer plans them.
    sepal::AssetData a = small_asset();
    a.material.terms = 2;
    for (uint32_t role = 0; role < 2; ++role) {
        sepal::AssetTexture t = a.textures[role];
        t.desc.term = 1;
        for (int c = 0; c < 4; ++c) t.desc.scale[c] = 0.5f, t.desc.bias[c] = role ? -0.1f : 0.2f;
        a.textures.push_back(t);
    }
    std::string err, msg;
    REQUIRE_MESSAGE(sepal::build_plan(&a, &err), err);
    const std::vector<uint8_t> good = encode(a);
    REQUIRE(parse(good, &msg) == SEPAL_OK);
    const uint32_t passes = uint32_t(a.passes.size());
    // Every colour 0 (the GL backends drew black, the CPU the factors).
    std::vector<uint8_t> b = good;
    sepal_fmt_pass* p = plan_passes(&b);
    for (uint32_t i = 0; i < passes; ++i)
        for (float& c : p[i].color) c = 0.0f;
    reseal(&b);
    CHECK(parse(b, &msg) == SEPAL_ERR_INVALID_ARGUMENT);
    CHECK_MESSAGE(msg.find("the pass plan does not draw the factors: term 0's G H part weighs 0") != std::string::npos,
                  msg);
    // Term 0 drawn twice, term 1 never: the product pass of term 1 reads term 0's textures.
    b = good;
    p = plan_passes(&b);
    uint32_t changed = 0;
    for (uint32_t i = 0; i < passes; ++i)
        if (p[i].op == SEPAL_OP_PRODUCT && p[i].tex0 == 2) p[i].tex0 = 0, p[i].tex1 = 1, ++changed;
    REQUIRE(changed >= 1);
    reseal(&b);
    CHECK(parse(b, &msg) == SEPAL_ERR_INVALID_ARGUMENT);
    CHECK_MESSAGE(msg.find("term 0's G H part") != std::string::npos, msg);
    // One colour a little off (a tenth of a percent): refused too; float rounding is not.
    b = good;
    p = plan_passes(&b);
    p[0].color[1] *= 1.001f;
    reseal(&b);
    CHECK(parse(b, &msg) == SEPAL_ERR_INVALID_ARGUMENT);
    CHECK(msg.find("channel 1") != std::string::npos);
    b = good;
    p = plan_passes(&b);
    p[0].color[1] = std::nextafter(p[0].color[1], 0.0f);
    reseal(&b);
    CHECK_MESSAGE(parse(b, &msg) == SEPAL_OK, msg);
}
