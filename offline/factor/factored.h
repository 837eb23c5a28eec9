// A separable BRDF approximation with float factors, and its evaluator.
//
// Usage:
//   const sepal::Factored& f = result.factored;        // from factor_brdf (factor.h)
//   glm::dvec3 rgb = sepal::evaluate(f, wi, wo);        // all terms
//   glm::dvec3 one = sepal::evaluate(f, wi, wo, 1);     // the first term only
//
// The approximation is
//   f(wi, wo) ~= ratio * sum_{k < terms} G_k(x) H_k(y),   (x, y) = param(wi, wo) (param.h)
// per channel: with colour == PerChannel the textures have 3 channels and ratio = (1,1,1);
// with colour == Luminance they have 1 channel (a factorization of the luminance) and ratio
// holds the per-channel multipliers (least-squares fit of each channel to the luminance).
// Each factor is an n x n texture of floats, row-major with row j = v, texel (i, j) centred
// at ((i + 0.5)/n, (j + 0.5)/n); row 0 is v = 0, as glTexImage2D expects it. Factors may be
// signed (SVD, multi-term ND); non_negative() says whether every value is >= 0. Every texel
// holds a value: texels outside the map's valid disk were filled from valid neighbours, so
// bilinear lookups at the rim are right.
// Reciprocal form (homomorphic factorization, homomorphic.h): with form == Reciprocal each
// term is G_k(x) H_k(y) G_k(x~), x~ the G coordinate of the swapped pair (wo, wi); with vh
// that is p(wo) q(h) p(wi), reciprocal by construction.
// The evaluator does what GL's GL_LINEAR does: bilinear between the four nearest texel
// centres, clamped to the edge (wrapped for elev-azim's azimuth factor); it returns 0 when
// wi or wo is at or below the horizon. It is shared by every error computation and the CPU
// backend, and is safe to call from several threads.
#pragma once
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "factor/param.h"

namespace sepal {

enum class ColourMode { PerChannel, Luminance };
const char* colour_name(ColourMode c);  // "rgb", "luminance"
bool parse_colour(const std::string& name, ColourMode* c);

// Rec. 709 luminance of linear RGB.
inline double luminance(const glm::dvec3& c) {
    return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}

struct FactorTexture {
    int n = 0, channels = 0;
    std::vector<float> data;  // (j * n + i) * channels + c

    FactorTexture() = default;
    FactorTexture(int n_, int channels_)
        : n(n_), channels(channels_), data(size_t(n_) * n_ * channels_, 0.0f) {}
    float& at(int i, int j, int c) { return data[(size_t(j) * n + i) * channels + c]; }
    float at(int i, int j, int c) const { return data[(size_t(j) * n + i) * channels + c]; }
};

struct FactorTerm {
    FactorTexture g, h;  // G_k(x), H_k(y)
};

// Sum: f ~= sum_k G_k(x) H_k(y). Reciprocal: f ~= sum_k G_k(x) H_k(y) G_k(x~) (above).
enum class Form { Sum, Reciprocal };

struct Factored {
    Form form = Form::Sum;
    Param param = Param::GsHalf;
    HemiMap map = HemiMap::XY;
    ColourMode colour = ColourMode::PerChannel;
    int n = 0;         // texture side of the G factors (H's may differ: terms[k].h.n)
    int channels = 3;  // of every texture: 3 (PerChannel) or 1 (Luminance)
    glm::dvec3 ratio{1, 1, 1};
    std::vector<FactorTerm> terms;
    std::string method;  // "svd", "nd", "nmf", "acls", "homomorphic"
    std::string source;  // the BRDF's spec
    // Radiance factors (the bake's, format version 2): the terms approximate
    // f cos(theta_i) - diffuse cos(theta_i) rather than f, and f = sum / cos + diffuse.
    // factor_brdf never sets these; evaluate() returns the sum of the terms either way.
    bool radiance = false;
    glm::dvec3 diffuse{0, 0, 0};
    // Radiance factors' horizon window c0 (sepal_horizon_window): the sum is multiplied by
    // min(1, cos_i / c0). 0: none.
    double horizon = 0;
    // Optional profile of the diffuse part over (cos theta_i, cos theta_o): side x side RGB
    // in [0,1], the format's DIFF chunk (sepal_diffuse_profile); side 0: constant.
    int diffuse_side = 0;
    std::vector<float> diffuse_profile;

    int term_count() const { return int(terms.size()); }
    bool non_negative() const;
    // The first k terms (a copy).
    Factored prefix(int k) const;
};

// Checks sizes and values (finite, consistent channels); false with the reason.
bool validate_factored(const Factored& f, std::string* err);

// The four texels (texel index j * n + i) and weights of GL_LINEAR at uv on an n x n
// texture, clamped to the edge or wrapped; clamped taps may repeat an index.
struct BilinearTaps {
    int index[4];
    double weight[4];
};
BilinearTaps bilinear_taps(int n, const glm::dvec2& uv, bool wrap);

// Bilinear lookup of all channels at texture coordinate uv into out[0..channels).
void bilinear_lookup(const FactorTexture& t, const glm::dvec2& uv, bool wrap, double* out);

// Reconstructs f(wi, wo) from the first `terms` terms (all when terms < 0).
glm::dvec3 evaluate(const Factored& f, const glm::dvec3& wi, const glm::dvec3& wo,
                    int terms = -1);
// The reflected radiance per unit irradiance the approximation stands for, f~ cos(theta_i):
// evaluate() x cos(theta_i), or for radiance factors evaluate() + diffuse profile cos(theta_i).
// 0 at or below the horizon.
glm::dvec3 evaluate_radiance(const Factored& f, const glm::dvec3& wi, const glm::dvec3& wo, int terms = -1);
// Every prefix at once: out[k] = the reconstruction from the first k + 1 terms;
// out must hold term_count() values.
void evaluate_prefixes(const Factored& f, const glm::dvec3& wi, const glm::dvec3& wo,
                       glm::dvec3* out);

}  // namespace sepal
