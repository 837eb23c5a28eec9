#include "util/parallel.h"

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace sepal {

int default_threads() {
    const unsigned n = std::thread::hardware_concurrency();
    return n == 0 ? 1 : int(std::min(n, 64u));
}

int workers(size_t n_chunks, int threads) {
    if (threads <= 0) threads = default_threads();
    threads = std::min(threads, 64);
    return int(std::max<size_t>(1, std::min<size_t>(size_t(threads), n_chunks)));
}

void parallel_for_workers(size_t n_chunks, int threads,
                          const std::function<void(size_t, int)>& fn) {
    const int n = workers(n_chunks, threads);
    if (n <= 1) {
        for (size_t c = 0; c < n_chunks; ++c) fn(c, 0);
        return;
    }
    // Chunks are handed out dynamically (they differ in cost), which is fine: every chunk's
    // result is independent of which thread computed it.
    std::atomic<size_t> next{0};
    auto work = [&](int worker) {
        for (size_t c; (c = next.fetch_add(1)) < n_chunks;) fn(c, worker);
    };
    std::vector<std::thread> pool;
    pool.reserve(size_t(n - 1));
    for (int t = 1; t < n; ++t) {
        // A thread that cannot be started only means fewer workers, never a failure.
        try {
            pool.emplace_back(work, t);
        } catch (...) {
            break;
        }
    }
    work(0);
    for (std::thread& t : pool) t.join();
}

void parallel_for(size_t n_chunks, int threads, const std::function<void(size_t)>& fn) {
    parallel_for_workers(n_chunks, threads, [&](size_t c, int) { fn(c); });
}

}  // namespace sepal
