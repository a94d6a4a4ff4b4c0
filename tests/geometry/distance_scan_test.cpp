// distance_scan_test.cpp — the passes of internal/distance_scan.h against the plain loops
// they replace: scan_distances (the MC and MI fitters' pass) gives the same extreme (value and
// lowest index on ties) and the same flagged indices in the same order, distance_extremes
// (the MZ fitter's per-block seeding and pricing) the same first nearest and farthest points
// of every index range, bit for bit, in both ISA variants (AVX2 and baseline), for sizes
// 1 … 40 (every tail length), duplicated points (ties in every lane), thresholds that flag
// none, some and all points; and RONq's sums taken in a scan's pass give roundness_parameters'
// RONq bit for bit (every size 3 … 40 and 3600, both variants), and are refused where that
// evaluation would not take them. Fixed seeds.
#include "internal/distance_scan.h"
#include "internal/isa.h"
#include "internal/prevalidated.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace {

using vcmm::geometry::Point2;
namespace internal = vcmm::geometry::internal;

/// The reference: the scalar loop scan_distances was before it was vectorised.
template <internal::Track kTrack>
internal::DistanceScan plain_scan(const std::vector<Point2>& p, Point2 c, double scale,
                                  double threshold, std::vector<std::size_t>& flagged) {
  constexpr bool kMin = kTrack == internal::Track::kNearest;
  double best = kMin ? std::numeric_limits<double>::infinity() : -1.0;
  std::size_t arg = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double dx = (p[i].x - c.x) * scale, dy = (p[i].y - c.y) * scale;
    const double d2 = dx * dx + dy * dy;
    if (kMin ? d2 < best : d2 > best) {
      best = d2;
      arg = i;
    }
    if (kMin ? d2 >= threshold : d2 <= threshold) flagged.push_back(i);
  }
  return {best, arg};
}

template <internal::Track kTrack>
void expect_plain(const std::vector<Point2>& p, Point2 c, double scale, double threshold,
                  const std::string& what) {
  std::vector<std::size_t> want_flags{7};  // appended to, not cleared
  const internal::DistanceScan want = plain_scan<kTrack>(p, c, scale, threshold, want_flags);
  for (bool baseline : {false, true}) {
    std::optional<internal::ForceBaselineIsa> force;
    if (baseline) force.emplace();
    std::vector<std::size_t> flags{7};
    const internal::DistanceScan got =
        internal::scan_distances<kTrack>(p, c, scale, threshold, flags);
    EXPECT_EQ(got.d2, want.d2) << what << " baseline " << baseline;
    EXPECT_EQ(got.index, want.index) << what << " baseline " << baseline;
    EXPECT_EQ(flags, want_flags) << what << " baseline " << baseline;
  }
}

TEST(DistanceScan, EqualsThePlainLoopForEverySizeTieAndThreshold) {
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> angle(0.0, 6.283185307179586);
  std::normal_distribution<double> noise(0.0, 1e-4);
  const Point2 c{600.0, 500.0};
  for (std::size_t n = 1; n <= 40; ++n) {
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<Point2> p(n);
      for (Point2& q : p) {
        const double t = angle(rng), r = 85.5 + noise(rng);
        q = {c.x + r * std::cos(t), c.y + r * std::sin(t)};
      }
      // Ties: copies of random points at random places (the extremes among them).
      if (n > 2 && trial % 2 == 1)
        for (std::size_t k = 0; k < n / 3; ++k) p[rng() % n] = p[rng() % n];
      const double scale = 1.0 / 128.0;
      const double r2 = (85.5 / 128.0) * (85.5 / 128.0);
      const std::string what = "n " + std::to_string(n) + " trial " + std::to_string(trial);
      for (double threshold : {r2 * (1 - 1e-6), r2, r2 * (1 + 1e-6), 0.0, 1e300, -1e300}) {
        expect_plain<internal::Track::kNearest>(p, c, scale, threshold, what);
        expect_plain<internal::Track::kFarthest>(p, c, scale, threshold, what);
      }
    }
  }
}

/// distance_extremes over [lo, hi) against the plain loop, both ISA variants.
void expect_plain_extremes(const std::vector<Point2>& p, std::size_t lo, std::size_t hi,
                           Point2 c, const std::string& what) {
  internal::DistanceExtremes want{lo, lo, -1.0, std::numeric_limits<double>::infinity()};
  for (std::size_t i = lo; i < hi; ++i) {
    const double dx = p[i].x - c.x, dy = p[i].y - c.y;
    const double s = dx * dx + dy * dy;
    if (s > want.smax) {
      want.smax = s;
      want.imax = i;
    }
    if (s < want.smin) {
      want.smin = s;
      want.imin = i;
    }
  }
  for (bool baseline : {false, true}) {
    std::optional<internal::ForceBaselineIsa> force;
    if (baseline) force.emplace();
    const internal::DistanceExtremes got = internal::distance_extremes(p, lo, hi, c);
    EXPECT_EQ(got.smax, want.smax) << what << " baseline " << baseline;
    EXPECT_EQ(got.imax, want.imax) << what << " baseline " << baseline;
    EXPECT_EQ(got.smin, want.smin) << what << " baseline " << baseline;
    EXPECT_EQ(got.imin, want.imin) << what << " baseline " << baseline;
  }
}

TEST(DistanceScan, ExtremesOfEveryRangeEqualThePlainLoop) {
  std::mt19937_64 rng(20261128);
  std::uniform_real_distribution<double> angle(0.0, 6.283185307179586);
  std::normal_distribution<double> noise(0.0, 1e-4);
  const Point2 c{600.0, 500.0};
  std::vector<Point2> p(64);
  for (int trial = 0; trial < 40; ++trial) {
    for (Point2& q : p) {
      const double t = angle(rng), r = 85.5 + noise(rng);
      q = {c.x + r * std::cos(t), c.y + r * std::sin(t)};
    }
    if (trial % 2 == 1)
      for (int k = 0; k < 20; ++k) p[rng() % p.size()] = p[rng() % p.size()];
    for (std::size_t lo = 0; lo < 20; ++lo)
      for (std::size_t hi = lo + 1; hi <= p.size(); hi += 3)
        expect_plain_extremes(p, lo, hi, c,
                              "trial " + std::to_string(trial) + " [" + std::to_string(lo) +
                                  ", " + std::to_string(hi) + ")");
  }
}

TEST(DistanceScan, AllPointsEqualReportIndexZero) {
  const std::vector<Point2> p(9, Point2{1.0, 2.0});
  expect_plain<internal::Track::kNearest>(p, {0.0, 0.0}, 1.0, 0.0, "identical");
  expect_plain<internal::Track::kFarthest>(p, {0.0, 0.0}, 1.0, 0.0, "identical");
}

/// RONq from the sums of a scan's pass against roundness_parameters' own evaluation about the
/// same circle: the same bits, and the sums in use (s within the degree-3 range).
TEST(DistanceScan, RonqSumsOfThePassEqualRoundnessParameters) {
  std::mt19937_64 rng(20261129);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1e-4);
  const Point2 c{600.0, 500.0};
  const double radius = 85.5, bound = 1e-3;  // deviations ≤ ~0.5 µm: degree 3
  std::vector<std::size_t> sizes;
  for (std::size_t n = 3; n <= 40; ++n) sizes.push_back(n);
  sizes.push_back(3600);
  for (const std::size_t n : sizes) {
    std::vector<Point2> p(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double t =
          6.283185307179586 * (static_cast<double>(i) + unit(rng)) / static_cast<double>(n);
      const double r = radius + noise(rng);
      p[i] = {c.x + r * std::cos(t), c.y + r * std::sin(t)};
    }
    const double want =
        internal::roundness_parameters_of_valid(p, c, radius, bound).ronq;
    for (bool baseline : {false, true}) {
      std::optional<internal::ForceBaselineIsa> force;
      if (baseline) force.emplace();
      for (const bool farthest : {false, true}) {
        internal::RonqSums sums;
        sums.radius = radius;
        sums.inv_scale = internal::ronq_inv_scale(p, c, radius);
        std::vector<std::size_t> flags;
        if (farthest)
          internal::scan_distances<internal::Track::kFarthest>(p, c, 1.0, 0.0, flags, &sums);
        else
          internal::scan_distances<internal::Track::kNearest>(p, c, 1.0, 1e300, flags, &sums);
        EXPECT_LE(sums.s_max, 0x1p-15) << "n = " << n;
        EXPECT_EQ(internal::ronq_of_valid(p, c, radius, bound, sums), want)
            << "n = " << n << " baseline " << baseline << " farthest " << farthest;
        // Sums that are not the evaluation's own are not used: another radius, or a bound
        // that takes another degree, still give its RONq.
        internal::RonqSums wrong = sums;
        wrong.sum_dd *= 2.0;
        wrong.radius = radius * (1.0 + 1e-9);
        EXPECT_EQ(internal::ronq_of_valid(p, c, radius, bound, wrong), want) << n;
        EXPECT_EQ(internal::ronq_of_valid(p, c, radius, 0.5, sums),
                  internal::roundness_parameters_of_valid(p, c, radius, 0.5).ronq)
            << n;
      }
    }
  }
}

}  // namespace
