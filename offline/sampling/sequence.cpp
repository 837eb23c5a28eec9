#include "sampling/sequence.h"

#include <algorithm>
#include <cmath>

#include "util/parallel.h"

namespace sepal {
namespace {

// Floats in [0,1) from 32-bit integers (24 significant bits: never rounds up to 1).
inline float unit(uint32_t bits) { return float(bits >> 8) * (1.0f / 16777216.0f); }

uint32_t reverse_bits(uint32_t v) {
    v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    v = ((v >> 4) & 0x0F0F0F0Fu) | ((v & 0x0F0F0F0Fu) << 4);
    v = ((v >> 8) & 0x00FF00FFu) | ((v & 0x00FF00FFu) << 8);
    return (v >> 16) | (v << 16);
}

// Sobol's second dimension: generator matrix of the primitive polynomial x + 1.
uint32_t sobol2(uint32_t i) {
    uint32_t r = 0;
    for (uint32_t v = 1u << 31; i; i >>= 1, v ^= v >> 1)
        if (i & 1) r ^= v;
    return r;
}

}  // namespace

const char* sequence_name(SampleSequence s) {
    return s == SampleSequence::Random ? "random" : s == SampleSequence::Stratified ? "stratified" : "sobol";
}

bool parse_sequence(const std::string& s, SampleSequence* out) {
    if (s == "random") *out = SampleSequence::Random;
    else if (s == "stratified") *out = SampleSequence::Stratified;
    else if (s == "sobol") *out = SampleSequence::Sobol;
    else return false;
    return true;
}

void pixel_points(SampleSequence s, int spp, uint64_t seed, uint64_t pixel, std::vector<float>* u) {
    u->assign(size_t(spp) * 2, 0.0f);
    SplitMix64 rng(splitmix64(seed) ^ (pixel * 0xd1b54a32d192ed03ULL));
    auto bits = [&] { return uint32_t(rng.next() >> 32); };
    switch (s) {
        case SampleSequence::Random:
            for (float& x : *u) x = unit(bits());
            return;
        case SampleSequence::Stratified: {
            const int k = int(std::lround(std::sqrt(double(spp))));
            if (k * k == spp) {
                for (int a = 0; a < k; ++a)
                    for (int b = 0; b < k; ++b) {
                        const size_t i = size_t(a) * k + b;
                        (*u)[2 * i] = std::min((a + unit(bits())) / k, 0x1.fffffep-1f);
                        (*u)[2 * i + 1] = std::min((b + unit(bits())) / k, 0x1.fffffep-1f);
                    }
                return;
            }
            std::vector<int> perm(static_cast<size_t>(spp));
            for (int i = 0; i < spp; ++i) perm[size_t(i)] = i;
            for (int i = spp - 1; i > 0; --i) std::swap(perm[size_t(i)], perm[size_t(rng.next() % uint64_t(i + 1))]);
            for (int i = 0; i < spp; ++i) {
                (*u)[2 * size_t(i)] = std::min((i + unit(bits())) / spp, 0x1.fffffep-1f);
                (*u)[2 * size_t(i) + 1] = std::min((perm[size_t(i)] + unit(bits())) / spp, 0x1.fffffep-1f);
            }
            return;
        }
        case SampleSequence::Sobol: {
            const uint32_t sx = bits(), sy = bits();
            for (int i = 0; i < spp; ++i) {
                (*u)[2 * size_t(i)] = unit(reverse_bits(uint32_t(i)) ^ sx);
                (*u)[2 * size_t(i) + 1] = unit(sobol2(uint32_t(i)) ^ sy);
            }
            return;
        }
    }
}

}  // namespace sepal
