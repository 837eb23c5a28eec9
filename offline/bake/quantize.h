// Quantization of float factor textures into the asset's 8- or 16-bit textures.
//
// Usage:
//   sepal::QuantizeOptions opt;  opt.bits = 8;  opt.mips = true;
//   sepal::AssetTexture tex; std::string err;
//   if (!sepal::quantize_texture(values, n, channels, opt, &tex, &err)) ...
//   // tex.desc: size, levels, channels, bits, scale and bias; tex.data: every level
//   std::vector<float> back = sepal::dequantize_level0(tex);   // for measuring the error
//
// Per channel, a texture stores q = (v - bias) / scale in [0, 1] with the full range
// used: bias = 0 and scale = max for non-negative channels, bias = min and scale =
// max - min for signed ones (the plan's correction passes handle the bias). MIP levels
// are 2x2 box averages of the float values, quantized with the level-0 scale and bias
// (averages stay inside [min, max]). Role and term are left for the caller.
// A texture whose values are all equal (a 1x1 factor, or an all-zero BRDF's) is exact:
// scale = the value (q = 1), or scale 0 and q = 0 when it is 0 or negative (stats count it).
// Limits: power-of-two sides 1..1024 (GL ES 1.1 needs powers of two and MIP chains; a 1x1
// texture has one level); values must be finite.
#pragma once
#include <string>
#include <vector>

#include "bake/asset_file.h"

namespace sepal {

struct QuantizeOptions {
    int bits = 8;      // 8 or 16
    bool mips = true;  // full MIP chain (GL ES 1.1 minification without aliasing)
};

struct QuantizeStats {
    double max_error[3] = {0, 0, 0};  // largest |v - dequantized| at level 0, per channel
    // Channels with scale 0 (every value equal: all 0, or one negative constant kept in the
    // bias): stored as q = 0, the value is the bias, exactly.
    int zero_scale_channels = 0;
    bool all_zero = false;  // every value of every channel is 0 (scale 0 and bias 0)
    // Codes that fell outside 0..2^bits-1 and were clamped, over every level. 0 by
    // construction (scale and bias span the level-0 values; MIP averages stay inside), so
    // a nonzero count is a bug, reported rather than hidden.
    int64_t clamped = 0;
};

bool quantize_texture(const float* values, int n, int channels, const QuantizeOptions& options,
                      AssetTexture* out, std::string* err, QuantizeStats* stats = nullptr);
// The stored q in [0, 1] of value k of the level-0 data (k = texel * channels + channel).
double texel_q(const AssetTexture& t, size_t k);
// The level-0 values the texture stands for: scale * q + bias.
std::vector<float> dequantize_level0(const AssetTexture& t);

}  // namespace sepal
