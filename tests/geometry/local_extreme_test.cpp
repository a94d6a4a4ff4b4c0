// local_extreme_test.cpp — internal::local_extreme (the MC, MI and MZ fitters' local
// refinement), whose windows are taken by internal::range_extreme on contiguous ranges,
// against the step-by-step walk it replaces: the same point for every start index (windows
// wrapping past 0 and n − 1 both ways), both directions of extreme, windows of 0 … 40 (every
// tail length of the 8-lane ranges), noisy data (no ties), quantised data (ties in every
// lane: the first extreme in walk order must win) and a NaN point (never taken). Fixed seeds.
#include "internal/extremal_circle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

using vcmm::geometry::Point2;
namespace internal = vcmm::geometry::internal;

/// The reference: the step-by-step walk local_extreme was before its windows were ranges.
template <bool kFarthest>
std::size_t walk(const std::vector<Point2>& points, std::size_t i, Point2 c, double scale,
                 std::size_t window, std::size_t limit) {
  const std::size_t n = points.size();
  const auto better = [](double a, double b) { return kFarthest ? a > b : a < b; };
  const double d0 = internal::scaled_distance2(points[i], c, scale);
  std::size_t best = i;
  double best_d = d0;
  window = std::min(window, limit);
  for (const bool forward : {true, false}) {
    const auto next = [&](std::size_t j) {
      return forward ? (j + 1 == n ? 0 : j + 1) : (j == 0 ? n - 1 : j - 1);
    };
    std::size_t j = i;
    double dj = d0;
    for (std::size_t step = 1; step <= window; ++step) {
      j = next(j);
      dj = internal::scaled_distance2(points[j], c, scale);
      if (better(dj, best_d)) {
        best = j;
        best_d = dj;
      }
    }
    for (std::size_t step = window + 1; step <= limit; ++step) {
      const std::size_t k = next(j);
      const double dk = internal::scaled_distance2(points[k], c, scale);
      if (!better(dk, dj)) break;
      j = k;
      dj = dk;
      if (better(dj, best_d)) {
        best = j;
        best_d = dj;
      }
    }
  }
  return best;
}

std::vector<Point2> ring(std::size_t n, double quantum, std::size_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 2e-3);
  std::vector<Point2> p(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double t = 6.283185307179586 * static_cast<double>(k) / static_cast<double>(n);
    double r = 10.0 + 0.01 * std::cos(3.0 * t) + noise(rng);
    if (quantum > 0.0) r = std::round(r / quantum) * quantum;
    p[k] = {r * std::cos(t), r * std::sin(t)};
  }
  return p;
}

void expect_same(const std::vector<Point2>& p, Point2 c, double scale) {
  const std::size_t n = p.size();
  for (std::size_t window : {0u, 1u, 7u, 8u, 9u, 15u, 16u, 17u, 23u, 40u})
    for (std::size_t limit : {window, window + 5, n / 2})
      for (std::size_t i = 0; i < n; ++i) {
        ASSERT_EQ(internal::local_extreme<true>(p, i, c, scale, window, limit),
                  walk<true>(p, i, c, scale, window, limit))
            << "farthest, n " << n << ", i " << i << ", window " << window;
        ASSERT_EQ(internal::local_extreme<false>(p, i, c, scale, window, limit),
                  walk<false>(p, i, c, scale, window, limit))
            << "nearest, n " << n << ", i " << i << ", window " << window;
      }
}

TEST(LocalExtreme, MatchesTheStepByStepWalkOnNoisyData) {
  for (std::size_t n : {3u, 9u, 41u, 100u})
    expect_same(ring(n, 0.0, 11 + n), {0.001, -0.002}, 0.0625);
}

TEST(LocalExtreme, FirstExtremeInWalkOrderWinsTies) {
  // Distances quantised to 4 levels about the exact centre (0, 0): long runs of equal D̃.
  for (std::size_t n : {24u, 64u, 97u}) {
    std::vector<Point2> p(n);
    for (std::size_t k = 0; k < n; ++k) {
      const double r = 1.0 + 0.25 * static_cast<double>((k * 7 / 5) % 4);
      p[k] = {(k % 2) ? r : -r, 0.0};
    }
    expect_same(p, {0.0, 0.0}, 1.0);
    expect_same(ring(n, 1e-2, 5 + n), {0.0, 0.0}, 1.0);
  }
}

TEST(LocalExtreme, NaNIsNeverTaken) {
  std::vector<Point2> p = ring(50, 0.0, 3);
  p[20] = {std::numeric_limits<double>::quiet_NaN(), 0.0};
  expect_same(p, {0.0, 0.0}, 1.0);
}

}  // namespace
