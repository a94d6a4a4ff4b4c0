// Tests of the spectral trial's numeric kernels (validation/src/internal/spectral_kernels.h):
// the matrix-vector product equals Eigen's `y.noalias() = A * x` bit for bit (the samples of
// the spectral trial must not change with the kernel, nor with the machine's instruction
// set), for shapes on both sides of Eigen's column blocking (128 columns) and row counts that
// exercise every vector width and the scalar tail; the peak-to-valley equals the scalar
// max − min. Fixed seeds, printed on failure.
#include "internal/spectral_kernels.h"

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace vcmm::validation::internal {
namespace {

TEST(SpectralKernels, ProductIsEigensGemvBitForBit) {
  std::mt19937_64 gen(42);
  std::normal_distribution<double> normal;
  for (const Eigen::Index rows : {1, 7, 8, 31, 32, 33, 206, 415}) {
    for (const Eigen::Index cols : {1, 5, 73, 127, 128, 130, 300}) {
      Eigen::MatrixXd a(rows, cols);
      Eigen::VectorXd x(cols);
      for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = normal(gen) * std::exp(normal(gen));
      for (Eigen::Index j = 0; j < cols; ++j) x[j] = normal(gen);
      Eigen::VectorXd eigen(rows);
      eigen.noalias() = a * x;
      std::vector<double> ours(static_cast<std::size_t>(rows), -1.0);
      column_major_product(a.data(), static_cast<std::size_t>(rows),
                           static_cast<std::size_t>(cols), x.data(), ours.data());
      for (Eigen::Index i = 0; i < rows; ++i)
        ASSERT_EQ(ours[static_cast<std::size_t>(i)], eigen[i])
            << "rows " << rows << ", cols " << cols << ", row " << i;
    }
  }
}

TEST(SpectralKernels, PeakToValleyOfScaledSum) {
  std::mt19937_64 gen(7);
  std::normal_distribution<double> normal;
  for (const std::size_t n : {1u, 7u, 8u, 9u, 360u, 3600u, 3601u}) {
    std::vector<double> f(n), s(n);
    for (std::size_t j = 0; j < n; ++j) {
      f[j] = normal(gen);
      s[j] = 1e-3 * normal(gen);
    }
    const double k = 1.0 + 1e-6 * normal(gen);
    double hi = -std::numeric_limits<double>::infinity(), lo = -hi;
    for (std::size_t j = 0; j < n; ++j) {
      hi = std::max(hi, k * f[j] + s[j]);
      lo = std::min(lo, k * f[j] + s[j]);
    }
    EXPECT_EQ(scaled_sum_peak_to_valley(k, f.data(), s.data(), n), hi - lo) << "n " << n;
  }
}

}  // namespace
}  // namespace vcmm::validation::internal
