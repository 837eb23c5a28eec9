#include "util/thin_product.h"

#include <cstring>
#include <type_traits>
#include <vector>

namespace sepal {

namespace {

// Two doubles: an SSE2 or NEON register. Unaligned loads and stores go through memcpy.
typedef double V2 __attribute__((vector_size(16)));

inline V2 splat(double x) { return V2{x, x}; }

// B (m x k) as m rows of K2 = ceil(k / 2) vectors, the odd column padded with 0.
std::vector<V2> padded(const double* b, int m, int k, int k2) {
    std::vector<V2> p(size_t(m) * size_t(k2), splat(0.0));
    for (int r = 0; r < m; ++r) std::memcpy(&p[size_t(r) * size_t(k2)], b + size_t(r) * size_t(k), sizeof(double) * size_t(k));
    return p;
}

inline void unpad(const V2* acc, int k, double* out) {
    double t[kThinMaxCols];
    std::memcpy(t, acc, sizeof(V2) * size_t((k + 1) / 2));
    std::memcpy(out, t, sizeof(double) * size_t(k));
}

// L lines of A times B: the L x K2 sums stay in registers while A's rows stream past.
template <int K2, int L>
void lines(const double* a, size_t lda, int m, const V2* b, int k, double* out) {
    V2 acc[L][K2];
#pragma GCC unroll 8
    for (int l = 0; l < L; ++l)
#pragma GCC unroll 8
        for (int j = 0; j < K2; ++j) acc[l][j] = splat(0.0);
    for (int c = 0; c < m; ++c) {
        const V2* bc = b + size_t(c) * K2;
#pragma GCC unroll 8
        for (int l = 0; l < L; ++l) {
            const V2 x = splat(a[size_t(l) * lda + size_t(c)]);
#pragma GCC unroll 8
            for (int j = 0; j < K2; ++j) acc[l][j] += x * bc[j];
        }
    }
    for (int l = 0; l < L; ++l) unpad(acc[l], k, out + size_t(l) * size_t(k));
}

template <int K2>
void rows_kernel(const double* a, size_t lda, int n, int m, const V2* b, int k, double* out) {
    constexpr int L = 2;  // 2 x K2 sums + K2 of B: within 16 registers
    int l = 0;
    for (; l + L <= n; l += L) lines<K2, L>(a + size_t(l) * lda, lda, m, b, k, out + size_t(l) * size_t(k));
    for (; l < n; ++l) lines<K2, 1>(a + size_t(l) * lda, lda, m, b, k, out + size_t(l) * size_t(k));
}

// Columns c0 .. c0 + ni of A, transposed, times B: R rows of A (and of B) at a time, each
// column's K2 sums loaded once per R rows. The sums take the rows one at a time in order,
// so R changes the speed, never the result.
template <int K2, int R>
void cols_step(const double* a, size_t lda, int r, int ni, const V2* b, V2* acc) {
    V2 br[R][K2];
#pragma GCC unroll 8
    for (int q = 0; q < R; ++q)
#pragma GCC unroll 8
        for (int j = 0; j < K2; ++j) br[q][j] = b[size_t(r + q) * K2 + size_t(j)];
    const double* ar = a + size_t(r) * lda;
    for (int l = 0; l < ni; ++l) {
        V2 s[K2];
#pragma GCC unroll 8
        for (int j = 0; j < K2; ++j) s[j] = acc[size_t(l) * K2 + size_t(j)];
#pragma GCC unroll 8
        for (int q = 0; q < R; ++q) {
            const V2 x = splat(ar[size_t(q) * lda + size_t(l)]);
#pragma GCC unroll 8
            for (int j = 0; j < K2; ++j) s[j] += x * br[q][j];
        }
#pragma GCC unroll 8
        for (int j = 0; j < K2; ++j) acc[size_t(l) * K2 + size_t(j)] = s[j];
    }
}

template <int K2>
void cols_kernel(const double* a, size_t lda, int rows, int ni, const V2* b, int k, double* out) {
    constexpr int R = K2 <= 2 ? 4 : 2;  // R x K2 of B + K2 sums: within 16 registers
    std::vector<V2> acc(size_t(ni) * K2, splat(0.0));
    int r = 0;
    for (; r + R <= rows; r += R) cols_step<K2, R>(a, lda, r, ni, b, acc.data());
    for (; r < rows; ++r) cols_step<K2, 1>(a, lda, r, ni, b, acc.data());
    for (int l = 0; l < ni; ++l) unpad(&acc[size_t(l) * K2], k, out + size_t(l) * size_t(k));
}

// Calls f with the register width K2 (1..4 vectors of two doubles) as a compile-time constant.
template <typename F>
void with_width(int k2, F&& f) {
    switch (k2) {
        case 1: f(std::integral_constant<int, 1>{}); break;
        case 2: f(std::integral_constant<int, 2>{}); break;
        case 3: f(std::integral_constant<int, 3>{}); break;
        default: f(std::integral_constant<int, 4>{}); break;
    }
}

}  // namespace

bool thin_product(const double* a, size_t lda, int n, int m, const double* b, int k, double* out) {
    if (k < kThinMinCols || k > kThinMaxCols || n < 0 || m < 0) return false;
    const int k2 = (k + 1) / 2;
    const std::vector<V2> bp = padded(b, m, k, k2);
    with_width(k2, [&](auto w) { rows_kernel<decltype(w)::value>(a, lda, n, m, bp.data(), k, out); });
    return true;
}

bool thin_product_t(const double* a, size_t lda, int rows, int c0, int ni, const double* b, int k,
                    double* out) {
    if (k < kThinMinCols || k > kThinMaxCols || rows < 0 || c0 < 0 || ni < 0) return false;
    const int k2 = (k + 1) / 2;
    const std::vector<V2> bp = padded(b, rows, k, k2);
    a += c0;
    with_width(k2, [&](auto w) { cols_kernel<decltype(w)::value>(a, lda, rows, ni, bp.data(), k, out); });
    return true;
}

}  // namespace sepal
