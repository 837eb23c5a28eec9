// Deterministic multi-threading and random numbers for the factorization engine.
//
// Usage:
//   sepal::parallel_for(n_chunks, threads, [&](size_t chunk) { ... });
//   sepal::SplitMix64 rng(seed); double u = rng.uniform();
//
// Determinism regardless of thread count: callers cut their work into a fixed number of
// chunks that does not depend on the thread count, each chunk writes only its own outputs,
// and reductions combine per-chunk partial results in chunk order afterwards. Threads only
// decide who computes a chunk, never what it computes.
// The generator is written out (splitmix64) because std:: distributions differ between
// standard libraries; sample i of a stream is counter_uniform(seed, i), so a chunk can
// produce its samples without the others.
// Limits: threads <= 64; a worker's exception would terminate the process, so the work
// functions given here must not throw (they report failures through their own outputs).
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>

namespace sepal {

// Threads to use when the caller says 0: std::thread::hardware_concurrency(), at least 1.
int default_threads();

// Runs fn(0) .. fn(n_chunks - 1), on up to `threads` threads (0 = default_threads()).
void parallel_for(size_t n_chunks, int threads, const std::function<void(size_t)>& fn);
// The same, also passing the worker's index in [0, workers(n_chunks, threads)), for
// per-worker scratch buffers that live across calls.
void parallel_for_workers(size_t n_chunks, int threads,
                          const std::function<void(size_t chunk, int worker)>& fn);
int workers(size_t n_chunks, int threads);

// splitmix64 (Steele, Lea, Flood 2014): tiny, fast, and the same everywhere.
inline uint64_t splitmix64(uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

// A uniform double in [0, 1) with 53 random bits.
inline double to_unit(uint64_t bits) { return double(bits >> 11) * (1.0 / 9007199254740992.0); }

// The i-th uniform of the stream `seed` (counter-based: no state, any order).
inline double counter_uniform(uint64_t seed, uint64_t i) {
    return to_unit(splitmix64(splitmix64(seed) ^ (i * 0xd1b54a32d192ed03ULL)));
}

class SplitMix64 {
  public:
    explicit SplitMix64(uint64_t seed) : state_(seed) {}
    uint64_t next() {
        state_ += 0x9e3779b97f4a7c15ULL;
        uint64_t z = state_;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
    double uniform() { return to_unit(next()); }

  private:
    uint64_t state_;
};

}  // namespace sepal
