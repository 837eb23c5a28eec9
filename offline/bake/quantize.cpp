#include "bake/quantize.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace sepal {

bool quantize_texture(const float* values, int n, int channels, const QuantizeOptions& opt, AssetTexture* out,
                      std::string* err, QuantizeStats* stats) {
    auto fail = [&](const std::string& m) {
        if (err) *err = "quantize: " + m;
        return false;
    };
    if (n < 1 || n > SEPAL_FMT_MAX_TEXTURE_SIDE || (n & (n - 1)))
        return fail("texture side " + std::to_string(n) + " is not a power of two in 1..1024 (GL ES 1.1 needs one)");
    if (channels != 1 && channels != 3) return fail(std::to_string(channels) + " channels (1 or 3)");
    if (opt.bits != 8 && opt.bits != 16) return fail(std::to_string(opt.bits) + " bits (8 or 16)");
    const size_t count = size_t(n) * n;
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (int c = 0; c < channels; ++c) {
        lo[c] = hi[c] = values[c];
        for (size_t i = 0; i < count; ++i) {
            const float v = values[i * channels + c];
            if (!std::isfinite(v)) return fail("texel " + std::to_string(i) + " is not finite");
            lo[c] = std::min(lo[c], v);
            hi[c] = std::max(hi[c], v);
        }
    }
    AssetTexture t;
    t.desc.width = t.desc.height = uint32_t(n);
    t.desc.channels = uint32_t(channels);
    t.desc.bits = uint32_t(opt.bits);
    for (int c = 0; c < 4; ++c) {
        const int s = c < channels ? c : 0;
        const bool signed_channel = lo[s] < 0.0f;
        t.desc.bias[c] = signed_channel ? lo[s] : 0.0f;
        t.desc.scale[c] = signed_channel ? hi[s] - lo[s] : hi[s];
        if (!std::isfinite(t.desc.scale[c]))
            return fail("channel " + std::to_string(s) + " spans " + std::to_string(lo[s]) + ".." +
                        std::to_string(hi[s]) + ", beyond float range");
    }
    const double top = double((1u << opt.bits) - 1);
    int64_t clamped = 0;
    std::vector<float> level(values, values + count * channels);
    int side = n;
    uint32_t levels = 0;
    while (true) {
        ++levels;
        for (size_t i = 0; i < size_t(side) * side; ++i)
            for (int c = 0; c < channels; ++c) {
                const double scale = t.desc.scale[c];
                const double q = scale > 0 ? (double(level[i * channels + c]) - t.desc.bias[c]) / scale : 0.0;
                // Rounding may put q a hair outside [0, 1]; only a code outside the range counts.
                const double x = q * top;
                if (!(x > -0.5 && x < top + 0.5)) ++clamped;
                const uint32_t code = uint32_t(std::lround(std::clamp(q, 0.0, 1.0) * top));
                if (opt.bits == 8) {
                    t.data.push_back(uint8_t(code));
                } else {
                    t.data.push_back(uint8_t(code & 0xFF));
                    t.data.push_back(uint8_t(code >> 8));
                }
                if (levels == 1 && stats) {
                    const double back = scale * double(code) / top + t.desc.bias[c];
                    stats->max_error[c] = std::max(stats->max_error[c], std::fabs(back - level[i * channels + c]));
                }
            }
        if (!opt.mips || side == 1) break;
        const int half = side / 2;
        std::vector<float> next(size_t(half) * half * channels);
        for (int j = 0; j < half; ++j)
            for (int i = 0; i < half; ++i)
                for (int c = 0; c < channels; ++c) {
                    auto at = [&](int x, int y) { return double(level[(size_t(y) * side + x) * channels + c]); };
                    next[(size_t(j) * half + i) * channels + c] =
                        float(0.25 * (at(2 * i, 2 * j) + at(2 * i + 1, 2 * j) + at(2 * i, 2 * j + 1) + at(2 * i + 1, 2 * j + 1)));
                }
        level.swap(next);
        side = half;
    }
    t.desc.levels = levels;
    if (stats) {
        stats->clamped = clamped;
        stats->zero_scale_channels = 0;
        stats->all_zero = true;
        for (int c = 0; c < channels; ++c) {
            if (t.desc.scale[c] == 0.0f) ++stats->zero_scale_channels;
            if (t.desc.scale[c] != 0.0f || t.desc.bias[c] != 0.0f) stats->all_zero = false;
        }
    }
    *out = std::move(t);
    return true;
}

double texel_q(const AssetTexture& t, size_t k) {
    if (t.desc.bits == 8) return t.data[k] / 255.0;
    return double(uint32_t(t.data[2 * k]) | (uint32_t(t.data[2 * k + 1]) << 8)) / 65535.0;  // little-endian
}

std::vector<float> dequantize_level0(const AssetTexture& t) {
    const size_t count = size_t(t.desc.width) * t.desc.height * t.desc.channels;
    std::vector<float> v(count);
    for (size_t i = 0; i < count; ++i) {
        const int c = int(i % t.desc.channels);
        v[i] = float(t.desc.scale[c] * texel_q(t, i) + t.desc.bias[c]);
    }
    return v;
}

}  // namespace sepal
