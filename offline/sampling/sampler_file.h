// Sampler files: building, writing and loading the data of runtime/include/sepal/sepal_sampler.h
// (the format is defined there, once, for this writer and the runtime's reader).
//
// Usage:
//   sepal::SamplerData d = ...;                 // from fit_factored, make_cosine_sampler, ...
//   std::string err;
//   if (!sepal::write_sampler("ct.smp", d, &err)) ...          // atomic, validated
//   sepal::Sampler s;
//   if (!s.read("ct.smp", &err)) ...                          // or s.build(d, &err)
//   sepal_sampler_view v; sepal_sampler_set_view(&s.get(), wo, &v); ...
//
// encode_sampler lays out header, desc and arrays with zeroed padding and reserved fields
// (equal inputs give byte-identical files), then parses the result with the runtime's own
// reader, so a writer bug cannot produce a file the runtime refuses.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "sepal/sepal_sampler.h"

namespace sepal {

struct SamplerData {
    uint32_t kind = SEPAL_SAMPLER_COSINE;  // sepal_sampler_kind
    sepal_smp_desc desc{};
    // The arrays of sepal_sampler.h, each with exactly the length its counts give.
    std::vector<float> z_edges, F, u_cdf, v_cdf, colour_a, colour_b, colour_c, tables;
    std::vector<sepal_smp_lobe> lobes;
};

bool encode_sampler(const SamplerData& d, std::vector<uint8_t>* out, std::string* err);
bool write_sampler(const std::string& path, const SamplerData& d, std::string* err);

// A parsed sampler with its own (aligned) copy of the bytes. Movable, not copyable.
class Sampler {
  public:
    Sampler() = default;
    Sampler(Sampler&&) = default;
    Sampler& operator=(Sampler&&) = default;
    Sampler(const Sampler&) = delete;
    Sampler& operator=(const Sampler&) = delete;

    bool load(const uint8_t* bytes, size_t size, std::string* err);
    bool build(const SamplerData& d, std::string* err);  // encode + load
    bool read(const std::string& path, std::string* err);
    bool loaded() const { return size_ > 0; }
    const sepal_sampler& get() const { return s_; }
    size_t bytes() const { return size_; }
    const uint8_t* data() const { return reinterpret_cast<const uint8_t*>(storage_.data()); }

  private:
    std::vector<uint64_t> storage_;
    size_t size_ = 0;
    sepal_sampler s_{};
};

// Builds a CDF of n + 1 floats (exactly 0 first, exactly 1 last, non-decreasing) from n
// non-negative masses; all-zero masses give a uniform CDF. Returns the sum of the masses.
double masses_to_cdf(const double* masses, int n, float* cdf);

}  // namespace sepal
