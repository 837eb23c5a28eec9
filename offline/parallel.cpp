#include "parallel.h"

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace sepal {

int default_threads() {
    const unsigned n = std::thread::hardware_concurrency();
    return n == 0 ? 1 : int(std::min(n, 64u));
}

void parallel_for(size_t n_chunks, int threads, const std::function<void(size_t)>& fn) {
    if (threads <= 0) threads = default_threads();
    threads = std::min(threads, 64);
    const size_t workers = std::min<size_t>(size_t(threads), n_chunks);
    if (workers <= 1) {
        for (size_t c = 0; c < n_chunks; ++c) fn(c);
        return;
    }
    // Chunks are handed out dynamically (they differ in cost), which is fine: every chunk's
    // result is independent of which thread computed it.
    std::atomic<size_t> next{0};
    auto work = [&]() {
        for (size_t c; (c = next.fetch_add(1)) < n_chunks;) fn(c);
    };
    std::vector<std::thread> pool;
    pool.reserve(workers - 1);
    for (size_t t = 1; t < workers; ++t) {
        // A thread that cannot be started only means fewer workers, never a failure.
        try {
            pool.emplace_back(work);
        } catch (...) {
            break;
        }
    }
    work();
    for (std::thread& t : pool) t.join();
}

}  // namespace sepal
