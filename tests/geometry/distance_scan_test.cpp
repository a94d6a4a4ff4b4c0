// distance_scan_test.cpp — internal::scan_distances (internal/extremal_circle.h), the O(n)
// pass of the MC and MI fitters, against the plain loop it replaces: the same extreme (value
// and lowest index on ties) and the same flagged indices in the same order, bit for bit, in
// both ISA variants (AVX2 and baseline), for sizes 1 … 40 (every tail length), duplicated
// points (ties in every lane), thresholds that flag none, some and all points. Fixed seeds.
#include "internal/extremal_circle.h"
#include "internal/isa.h"

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

TEST(DistanceScan, AllPointsEqualReportIndexZero) {
  const std::vector<Point2> p(9, Point2{1.0, 2.0});
  expect_plain<internal::Track::kNearest>(p, {0.0, 0.0}, 1.0, 0.0, "identical");
  expect_plain<internal::Track::kFarthest>(p, {0.0, 0.0}, 1.0, 0.0, "identical");
}

}  // namespace
