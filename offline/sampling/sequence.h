// 2D sample points in [0,1)^2 for one pixel's samples: the inputs of sepal_sampler_sample.
//
// Usage:
//   std::vector<float> u;                       // 2 per sample
//   sepal::pixel_points(sepal::SampleSequence::Sobol, spp, seed, pixel, &u);
//
// Sequences (each point of every sequence is uniformly distributed, so every estimator stays
// unbiased; only the correlations between a pixel's points differ):
//   random      independent uniform points
//   stratified  a jittered k x k grid when spp = k^2 (the paper: "all methods were
//               stratified"), else N-rooks (Latin hypercube: stratified in each axis)
//   sobol       the (0,2)-sequence (van der Corput, Sobol's second dimension) with a random
//               digital shift per pixel (XOR of 32-bit integers): a (0,m,2)-net for power-of-2
//               prefixes
// Determinism: the points depend only on (sequence, spp, seed, pixel).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace sepal {

enum class SampleSequence { Random, Stratified, Sobol };
const char* sequence_name(SampleSequence s);
bool parse_sequence(const std::string& s, SampleSequence* out);

void pixel_points(SampleSequence s, int spp, uint64_t seed, uint64_t pixel, std::vector<float>* u);

}  // namespace sepal
