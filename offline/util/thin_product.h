// Products of a large row-major matrix with a thin one (2 to 8 columns),
// without packing: the ALS normal equations (factor_als.cpp) and the measurement planner's
// pool scans (measure_plan.cpp).
//
// Usage:
//   // out (n x K) = A (n x m) * B (m x K); A row-major with row stride lda, B and out row-major
//   if (!sepal::thin_product(a, lda, n, m, b, K, out)) { ...general product... }
//   // out (ni x K) = A(:, c0 .. c0 + ni)^T * B, A (rows x ...) row-major, B (rows x K)
//   if (!sepal::thin_product_t(a, lda, rows, c0, ni, b, K, out)) { ... }
//
// Why not Eigen's product: a general matrix product copies ("packs") its operands into
// cache-friendly panels on every call; with K <= 8 output columns the copy of the large
// operand costs as much as the multiply-adds (perf: half of the IST bench's time was
// Eigen's gemm_pack_rhs + gebp_kernel for 2304 x 1344 times 1344 x 4). These kernels stream
// the large operand once, keeping the K sums of one or two lines in registers (GCC/Clang
// vector extensions: 2 doubles per register on SSE2 and NEON alike). Measured on this
// project's shapes (2304 x 1344, K = 4), Eigen's product against these: 3.2 and 2.2 ms (A B),
// 4.6 and 2.8 ms (A^T B).
//
// Determinism: every output is a sum in a fixed order (along the long dimension, one term
// at a time) that depends on neither the call's blocking nor the thread count, so results
// are the same however a caller cuts its lines into chunks. They differ from Eigen's in
// the last bits (another summation order).
// Limits: 2 <= K <= 8, else the functions return false and write nothing (K = 1 is a
// matrix-vector product, which Eigen does without packing; past 8 the register blocking
// here is no faster than Eigen's, measured);
// n, m, rows, ni >= 0; out must not alias a or b. No shared state: callers run chunks of
// lines on several threads at once.
#pragma once
#include <cstddef>

namespace sepal {

constexpr int kThinMinCols = 2, kThinMaxCols = 8;

bool thin_product(const double* a, size_t lda, int n, int m, const double* b, int k, double* out);
bool thin_product_t(const double* a, size_t lda, int rows, int c0, int ni, const double* b, int k,
                    double* out);

}  // namespace sepal
