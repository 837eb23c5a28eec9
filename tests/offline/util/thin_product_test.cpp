// Thin products (offline/util/thin_product.h) against Eigen's general product: every
// supported width, odd sizes, column windows, chunk independence, and the widths it refuses.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cstdlib>
#include <vector>

#include "util/thin_product.h"

namespace {
using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Relative to the largest magnitude of the exact product: the kernels sum in another order
// than Eigen, so a few ulps of the sum's scale, never more.
double rel_diff(const RowMat& a, const RowMat& b) {
    return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1e-300);
}
}  // namespace

TEST_CASE("thin_product: A B and A^T B match Eigen for 2..8 columns, odd sizes and windows") {
    std::srand(7);
    const int rows = 37, cols = 23;  // odd: the 2-line and 4-row blocks leave tails
    const RowMat a = RowMat::Random(rows, cols);
    for (int k = sepal::kThinMinCols; k <= sepal::kThinMaxCols; ++k) {
        CAPTURE(k);
        const RowMat b0 = RowMat::Random(cols, k), b1 = RowMat::Random(rows, k);
        // A B over a band of rows (row stride = cols).
        RowMat out0 = RowMat::Constant(9, k, -1.0);
        REQUIRE(sepal::thin_product(&a(5, 0), size_t(cols), 9, cols, b0.data(), k, out0.data()));
        CHECK(rel_diff(out0, a.middleRows(5, 9) * b0) < 1e-14);
        // A^T B over a window of columns, and the same window cut into chunks: identical.
        const int c0 = 3, ni = 17;
        RowMat out1 = RowMat::Constant(ni, k, -1.0), parts(ni, k);
        REQUIRE(sepal::thin_product_t(a.data(), size_t(cols), rows, c0, ni, b1.data(), k, out1.data()));
        CHECK(rel_diff(out1, a.middleCols(c0, ni).transpose() * b1) < 1e-14);
        for (int i = 0; i < ni; i += 5) {
            const int n = std::min(5, ni - i);
            REQUIRE(sepal::thin_product_t(a.data(), size_t(cols), rows, c0 + i, n, b1.data(), k, &parts(i, 0)));
        }
        CHECK(parts == out1);
    }
}

TEST_CASE("thin_product: widths outside 2..8 are refused and leave the output alone") {
    const RowMat a = RowMat::Ones(4, 4), b = RowMat::Ones(4, 9);
    RowMat out = RowMat::Constant(4, 9, 5.0);
    for (int k : {0, 1, 9}) {
        CAPTURE(k);
        CHECK_FALSE(sepal::thin_product(a.data(), 4, 4, 4, b.data(), k, out.data()));
        CHECK_FALSE(sepal::thin_product_t(a.data(), 4, 4, 0, 4, b.data(), k, out.data()));
        CHECK((out.array() == 5.0).all());
    }
    // Empty products are fine: nothing to write.
    CHECK(sepal::thin_product(a.data(), 4, 0, 4, b.data(), 2, out.data()));
    CHECK(sepal::thin_product_t(a.data(), 4, 0, 0, 4, b.data(), 2, out.data()));
    CHECK(out(0, 0) == 0.0);  // rows = 0: the sums are empty, so 0
}
