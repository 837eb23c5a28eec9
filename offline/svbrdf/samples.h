// A tabulated SVBRDF (spatially varying BRDF): per texel, BRDF samples on one shared set
// of direction pairs, with a confidence per sample (0 = missing). The input of the
// inverse shade trees (Lawrence et al. 2006); docs/ist.md documents the folder format.
//
// Usage:
//   sepal::SvbrdfSamples s; std::string err;
//   if (!sepal::read_svbrdf("card/", &s, &err)) { fprintf(stderr, "%s\n", err.c_str()); }
//   glm::dvec3 f = s.value(texel, pair);  float c = s.confidence(texel, pair);
//   sepal::write_svbrdf("copy/", s, &err);
//
// Texels: index = y * width + x, row y = 0 first (an image's top row); texel (x, y) sits at
// mesh UV ((x + 0.5)/width, (y + 0.5)/height), row 0 at v = 0 as sepal's diffuse maps.
// Directions: unit vectors in the local frame of brdf.h (n = +z, t = +x), both pointing away
// from the surface, both above the horizon. Values: linear RGB BRDF values per steradian
// (the cosine is not included), finite and >= 0 where the confidence is > 0.
// A pair may belong to a view (a group of pairs sharing wo, for example one camera
// position) and carry an albedo weight (the solid angle of its light in that view's
// quadrature): the basis BRDFs' energy constraint bounds sum weight * f * cos(theta_i) per
// view by 1. Pairs without a view or with weight 0 take no part in it.
//
// Folder format (version 1): DIR/svbrdf.json lists width, height and the pairs, each with
// wi, wo, an image (PFM, RGB float, width x height: the values of every texel for that
// pair), optionally a confidence image (8-bit grey PNG, confidence = byte / 255; absent:
// 1 everywhere), a view index and an albedo weight. Image paths are relative to DIR.
// Reading refuses (naming the file and what is wrong): a missing or malformed JSON, an
// unknown format or version, sizes out of bounds, directions that are not unit or below the
// horizon, images of the wrong size or kind, NaN or inf values (util/image.h refuses such
// PFMs); negative values are not refused but become missing samples (confidence 0),
// counted in SvbrdfCounts.
// Limits: width and height 1..kMaxSide, 1..kMaxPairs pairs, texels x pairs x 16 bytes at
// most max_memory_mb (default 4096) in memory.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace sepal {

struct DirPair {
    glm::dvec3 wi{0, 0, 1}, wo{0, 0, 1};
    int view = -1;              // -1: none
    double albedo_weight = 0;   // sr: this pair's light in its view's quadrature
};

struct SvbrdfSamples {
    static constexpr int kMaxSide = 4096;
    static constexpr int kMaxPairs = 4096;

    int width = 0, height = 0;
    std::vector<DirPair> pairs;
    std::vector<float> values;  // [(texel * pairs + p) * 3 + c]
    std::vector<float> conf;    // [texel * pairs + p], 0..1

    int texels() const { return width * height; }
    int pair_count() const { return int(pairs.size()); }
    // Allocates width x height x pairs samples, all 0 with confidence 1.
    void resize(int w, int h, const std::vector<DirPair>& p);
    glm::dvec3 value(int texel, int pair) const {
        const float* v = &values[(size_t(texel) * pairs.size() + size_t(pair)) * 3];
        return glm::dvec3(v[0], v[1], v[2]);
    }
    float confidence(int texel, int pair) const { return conf[size_t(texel) * pairs.size() + size_t(pair)]; }
    void set(int texel, int pair, const glm::dvec3& v, float c) {
        float* d = &values[(size_t(texel) * pairs.size() + size_t(pair)) * 3];
        d[0] = float(v.x), d[1] = float(v.y), d[2] = float(v.z);
        conf[size_t(texel) * pairs.size() + size_t(pair)] = c;
    }
};

// Checks sizes, directions and values (as the reader does); false with the first problem.
bool validate_svbrdf(const SvbrdfSamples& s, std::string* err);

struct SvbrdfCounts {
    int64_t samples = 0;    // texels x pairs
    int64_t missing = 0;    // confidence 0 (given, or set by the reader)
    int64_t negative = 0;   // negative values read: made missing
};
SvbrdfCounts count_samples(const SvbrdfSamples& s);

struct SvbrdfReadOptions {
    double max_memory_mb = 4096;
};
bool read_svbrdf(const std::string& dir, SvbrdfSamples* out, std::string* err,
                 SvbrdfCounts* counts = nullptr, const SvbrdfReadOptions& o = SvbrdfReadOptions());
// Writes DIR/svbrdf.json and DIR/pairs/pNNNN.pfm (+ cNNNN.png where some confidence is
// below 1), each file atomically; creates DIR.
bool write_svbrdf(const std::string& dir, const SvbrdfSamples& s, std::string* err);

// Sets the confidence of a random share (0..1) of the samples to 0 (a counter-based
// random choice per sample: the same seed drops the same samples); returns how many.
int64_t drop_samples(SvbrdfSamples* s, double share, uint64_t seed);

}  // namespace sepal
