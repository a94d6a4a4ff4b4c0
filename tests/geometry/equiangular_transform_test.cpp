// Tests of the equiangular real Fourier transform (vcmm/geometry/equiangular_transform.h).
#include "vcmm/geometry/equiangular_transform.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/point.h"

namespace vcmm::geometry {
namespace {

constexpr double kPi = std::numbers::pi;

// By hand: a_0 + a_2 cos 2θ + b_3 sin 3θ sampled at 2πj/n gives back exactly those three.
TEST(EquiangularTransform, RecoversAHandMadeSeriesForEvenAndOddSizes) {
  for (const std::size_t n : {8u, 9u, 16u, 3600u, 3607u}) {
    std::vector<double> v(n);
    for (std::size_t j = 0; j < n; ++j) {
      const double t = 2 * kPi * static_cast<double>(j) / static_cast<double>(n);
      v[j] = 0.5 + 1.25 * std::cos(2 * t) - 0.75 * std::sin(3 * t);
    }
    EquiangularTransform tr(n);
    std::vector<double> a(n / 2 + 1), b(n / 2 + 1);
    tr.coefficients(v, a, b);
    for (std::size_t k = 0; k <= n / 2; ++k) {
      EXPECT_NEAR(a[k], k == 0 ? 0.5 : k == 2 ? 1.25 : 0.0, 1e-13) << "n " << n << " k " << k;
      EXPECT_NEAR(b[k], k == 3 ? -0.75 : 0.0, 1e-13) << "n " << n << " k " << k;
    }
    std::vector<double> back(n);
    tr.values(a, b, back);
    for (std::size_t j = 0; j < n; ++j) ASSERT_NEAR(back[j], v[j], 1e-13) << "n " << n;
  }
}

// Property: analysis then synthesis is the identity on random data, including the Nyquist
// term, and synthesis from a truncated set equals the direct sum.
TEST(EquiangularTransform, RoundTripAndTruncatedSynthesisMatchTheDirectSum) {
  std::mt19937_64 gen(7);  // seed printed by the assertion messages' n
  std::normal_distribution<double> z;
  for (const std::size_t n : {10u, 15u, 360u, 3600u}) {
    std::vector<double> v(n);
    for (double& x : v) x = z(gen);
    EquiangularTransform tr(n);
    std::vector<double> a(n / 2 + 1), b(n / 2 + 1), back(n);
    tr.coefficients(v, a, b);
    tr.values(a, b, back);
    for (std::size_t j = 0; j < n; ++j) ASSERT_NEAR(back[j], v[j], 1e-12) << "n " << n;
    const std::size_t count = std::min<std::size_t>(5, n / 2 + 1);
    tr.values(std::span<const double>(a).first(count), std::span<const double>(b).first(count),
              back);
    for (std::size_t j = 0; j < n; j += 7) {
      double s = a[0];
      for (std::size_t k = 1; k < count; ++k) {
        const double t = 2 * kPi * static_cast<double>(k * j) / static_cast<double>(n);
        s += a[k] * std::cos(t) + b[k] * std::sin(t);
      }
      ASSERT_NEAR(back[j], s, 1e-12) << "n " << n << " j " << j;
    }
  }
}

// The convention is the Gaussian filter's: multiplying a_k, b_k by H(k) is the filter.
TEST(EquiangularTransform, GainPerHarmonicIsTheGaussianFilter) {
  const std::size_t n = 3600;
  std::mt19937_64 gen(11);
  std::normal_distribution<double> z;
  std::vector<double> v(n);
  for (double& x : v) x = 1e-3 * z(gen);
  EquiangularTransform tr(n);
  std::vector<double> a(n / 2 + 1), b(n / 2 + 1), out(n);
  tr.coefficients(v, a, b);
  for (std::size_t k = 0; k <= n / 2; ++k) {
    const double h = std::exp2(-std::pow(static_cast<double>(k) / 50.0, 2));
    a[k] *= h;
    b[k] *= h;
  }
  tr.values(a, b, out);
  const std::vector<double> filtered = gaussian_filter_closed(v, 50.0);
  for (std::size_t j = 0; j < n; ++j) ASSERT_NEAR(out[j], filtered[j], 1e-17);
}

TEST(EquiangularTransform, RejectsBadSizes) {
  EXPECT_THROW(EquiangularTransform(1), InvalidInput);
  EquiangularTransform tr(8);
  std::vector<double> v(7), a(5), b(5), out(8);
  EXPECT_THROW(tr.coefficients(v, a, b), InvalidInput);
  std::vector<double> big(6);
  EXPECT_THROW(tr.values(big, big, out), InvalidInput);
}

}  // namespace
}  // namespace vcmm::geometry
