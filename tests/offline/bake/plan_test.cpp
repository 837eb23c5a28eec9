// The pass plan (offline/bake/plan.h): it rebuilds sum_k G_k H_k exactly, adds before
// subtracts, colours and partial sums within [0,1].
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>

#include "bake/plan.h"

namespace {

uint64_t rng_state = 0x9E3779B97F4A7C15ull;
double uniform() {  // splitmix64: deterministic across standard libraries
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return double((z ^ (z >> 31)) >> 11) / double(1ull << 53);
}

sepal::AssetData random_asset(uint32_t terms, bool signed_factors) {
    sepal::AssetData a;
    a.material.terms = terms;
    a.material.channels = 3;
    a.material.ratio[0] = a.material.ratio[1] = a.material.ratio[2] = 1.0f;
    for (uint32_t k = 0; k < terms; ++k)
        for (uint32_t role = 0; role < 2; ++role) {
            sepal::AssetTexture t;
            t.desc.role = role;
            t.desc.term = k;
            for (int c = 0; c < 3; ++c) {
                t.desc.scale[c] = float(0.1 + 20 * uniform());
                t.desc.bias[c] = signed_factors ? float(-t.desc.scale[c] * uniform()) : 0.0f;
            }
            if (signed_factors && k == 1 && role == 1) t.desc.bias[1] = 0.7f;  // mixed signs per channel
            a.textures.push_back(t);
        }
    return a;
}

}  // namespace

TEST_CASE("plan: reproduces sum_k (aG qG + bG)(aH qH + bH) for signed factors") {
    for (uint32_t terms : {1u, 3u, 5u}) {
        sepal::AssetData a = random_asset(terms, true);
        std::string err;
        REQUIRE_MESSAGE(sepal::build_plan(&a, &err), err);
        for (int trial = 0; trial < 200; ++trial) {
            double q[2 * 5];
            for (uint32_t i = 0; i < 2 * terms; ++i) q[i] = uniform();
            for (int c = 0; c < 3; ++c) {
                double expect = 0, magnitude = 0;
                for (uint32_t k = 0; k < terms; ++k) {
                    const sepal_fmt_texture& G = a.textures[2 * k].desc;
                    const sepal_fmt_texture& H = a.textures[2 * k + 1].desc;
                    expect += (G.scale[c] * q[2 * k] + G.bias[c]) * (H.scale[c] * q[2 * k + 1] + H.bias[c]);
                    magnitude += (G.scale[c] + std::fabs(G.bias[c])) * (H.scale[c] + std::fabs(H.bias[c]));
                }
                // Pass colours are floats: 2^-24 relative each, on terms that may cancel.
                const double got = sepal::plan_value(a, q, c);
                CHECK(std::fabs(got - expect) <= 1e-6 * magnitude);
            }
        }
    }
}

TEST_CASE("plan: order, bounds, and no correction passes for non-negative factors") {
    sepal::AssetData a = random_asset(3, true);
    std::string err;
    REQUIRE(sepal::build_plan(&a, &err));
    bool seen_subtract = false, ordered = true, has_product = false;
    double added[3] = {0, 0, 0};
    for (const sepal_fmt_pass& p : a.passes) {
        if (p.blend == SEPAL_BLEND_SUBTRACT) seen_subtract = true;
        if (p.blend == SEPAL_BLEND_ADD && seen_subtract) ordered = false;
        has_product = has_product || p.op == SEPAL_OP_PRODUCT;
        for (int c = 0; c < 3; ++c) {
            CHECK(p.color[c] >= 0.0f);
            CHECK(p.color[c] <= 1.0f);
            if (p.blend == SEPAL_BLEND_ADD) added[c] += p.color[c];
        }
    }
    CHECK(seen_subtract);
    CHECK(ordered);
    CHECK(has_product);
    for (double s : added) CHECK(s <= 1.0 + 1e-6);
    CHECK(a.plan.peak_partial_sum <= 1.0f);
    CHECK(a.plan.doublings > 0);

    sepal::AssetData nn = random_asset(3, false);
    REQUIRE(sepal::build_plan(&nn, &err));
    CHECK(nn.passes.size() == 3);  // one product per term, nothing else
    for (const sepal_fmt_pass& p : nn.passes) {
        CHECK(p.op == SEPAL_OP_PRODUCT);
        CHECK(p.blend == SEPAL_BLEND_ADD);
    }
}

TEST_CASE("plan: refusals") {
    sepal::AssetData a = random_asset(1, false);
    for (int c = 0; c < 3; ++c) a.textures[0].desc.scale[c] = 0.0f;
    std::string err;
    CHECK_FALSE(sepal::build_plan(&a, &err));
    CHECK(err.find("all-zero") != std::string::npos);
    a = random_asset(1, false);
    a.textures[0].desc.scale[0] = 1e9f;  // needs more than 16 doublings
    CHECK_FALSE(sepal::build_plan(&a, &err));
    CHECK(err.find("doublings") != std::string::npos);
    a = random_asset(2, false);
    a.textures.pop_back();
    CHECK_FALSE(sepal::build_plan(&a, &err));
    CHECK(err.find("lacks") != std::string::npos);
}
