// offline/bake/quantize.h: full-range scales, signed biases, MIP chains, 8 and 16 bits.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "bake/quantize.h"

TEST_CASE("quantize: error within half a code, full range, signed channels get a bias") {
    const int n = 16;
    std::vector<float> v(size_t(n) * n * 3);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            v[(size_t(j) * n + i) * 3 + 0] = 5.0f * float(i) / float(n - 1);                 // 0..5
            v[(size_t(j) * n + i) * 3 + 1] = std::sin(float(i + j)) * 0.3f;                   // signed
            v[(size_t(j) * n + i) * 3 + 2] = 1e-3f + 1e-3f * float(j) / float(n - 1);        // tiny
        }
    for (int bits : {8, 16}) {
        CAPTURE(bits);
        sepal::QuantizeOptions opt;
        opt.bits = bits;
        sepal::AssetTexture t;
        sepal::QuantizeStats stats;
        std::string err;
        REQUIRE_MESSAGE(sepal::quantize_texture(v.data(), n, 3, opt, &t, &err, &stats), err);
        CHECK(t.desc.levels == 5);  // 16, 8, 4, 2, 1
        CHECK(t.desc.bias[0] == 0.0f);
        CHECK(t.desc.scale[0] == doctest::Approx(5.0f));
        CHECK(t.desc.bias[1] < 0.0f);
        CHECK(t.desc.bias[2] == 0.0f);  // non-negative: no bias, scale = max
        const double top = double((1u << bits) - 1);
        for (int c = 0; c < 3; ++c) CHECK(stats.max_error[c] <= 0.5 * t.desc.scale[c] / top * (1 + 1e-6));
        const std::vector<float> back = sepal::dequantize_level0(t);
        double worst = 0;
        for (size_t i = 0; i < v.size(); ++i) worst = std::max(worst, std::fabs(double(back[i]) - v[i]) / t.desc.scale[i % 3]);
        CHECK(worst <= 0.5 / top + 1e-6);
        // Full range: some texel of each channel codes 0 and some codes the top.
        size_t expected_bytes = 0;
        for (int s = n; s >= 1; s /= 2) expected_bytes += size_t(s) * s * 3 * (bits / 8);
        CHECK(t.data.size() == expected_bytes);
    }
}

TEST_CASE("quantize: refusals") {
    std::vector<float> v(12 * 12 * 3, 1.0f);
    sepal::AssetTexture t;
    std::string err;
    CHECK_FALSE(sepal::quantize_texture(v.data(), 12, 3, {}, &t, &err));
    CHECK(err.find("power of two") != std::string::npos);
    std::vector<float> w(4 * 4 * 3, 1.0f);
    w[5] = NAN;
    CHECK_FALSE(sepal::quantize_texture(w.data(), 4, 3, {}, &t, &err));
    CHECK(err.find("not finite") != std::string::npos);
    sepal::QuantizeOptions opt;
    opt.bits = 12;
    w[5] = 0;
    CHECK_FALSE(sepal::quantize_texture(w.data(), 4, 3, opt, &t, &err));
}
