// Tests of the minimum zone from a subset of extremes (vcmm/geometry/minimum_zone_from_extremes.h)
// against the minimum zone of all points, over regimes: band-limited profiles of several
// bandwidths and sizes, unfiltered noise, a large centre offset (contacts deep below the
// starting band: several rounds), nearly perfect circles and exact circles (every point a
// near-tie), pure lobed forms (symmetric near-ties); seeds in the messages.
#include "vcmm/geometry/minimum_zone_from_extremes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>

#include "support/polar_profiles.h"
#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/minimum_zone.h"

namespace vcmm::geometry {
namespace {

/// The full fitter's centre and the spread of the distances about it, computed as the
/// function documents (rounded squared distances of the rounded points).
struct Reference {
  Point2 center;
  double spread = 0.0;
  double ront = 0.0;
};
Reference full_minimum_zone(const PolarProfile& p) {
  std::vector<Point2> points(p.size());
  for (std::size_t j = 0; j < p.size(); ++j) points[j] = polar_point(p, j);
  const MinimumZoneCircle mz = minimum_zone_circle(points);
  double hi = 0.0, lo = std::numeric_limits<double>::infinity();
  for (const Point2& q : points) {
    const double dx = q.x - mz.center.x, dy = q.y - mz.center.y;
    hi = std::max(hi, dx * dx + dy * dy);
    lo = std::min(lo, dx * dx + dy * dy);
  }
  return {mz.center, std::sqrt(hi) - std::sqrt(lo), mz.ron.ront};
}


// The same centre (bit for bit) as minimum_zone_circle on all points, the same spread about
// it, and RONt within 1e-12 mm of the fitter's own value, in every regime.
TEST(MinimumZoneFromExtremes, EqualsTheMinimumZoneOfAllPoints) {
  ExtremesScratch scratch;
  int rounds_above_one = 0;
  for (std::uint64_t seed = 1; seed <= 300; ++seed) {
    const test::PolarCase polar = test::polar_case(seed);
    const std::size_t n = polar.n;
    const PolarProfile profile = polar.profile();
    const Reference full = full_minimum_zone(profile);
    const double fast = minimum_zone_ront_from_extremes(profile, scratch);
    EXPECT_EQ(scratch.center, full.center) << "seed " << seed << ", n " << n;
    EXPECT_EQ(fast, full.spread) << "seed " << seed << ", n " << n;
    EXPECT_NEAR(fast, full.ront, 1e-12) << "seed " << seed << ", n " << n;
    rounds_above_one += scratch.rounds > 1 ? 1 : 0;
  }
  EXPECT_GT(rounds_above_one, 0);  // the offset regime exercises the rounds
}

// The points overload: RONt and centre bit for bit those of minimum_zone_circle(points), on
// every regime of the polar sweep (about an origin 3 µm off the profile's centre, and once
// with the points in a scrambled order and a far origin: only the speed may suffer), and
// on filtered noisy rings as the Monte Carlo trial makes them (rays from the filter centre).
TEST(MinimumZoneFromExtremes, PointsOverloadEqualsTheMinimumZoneOfAllPoints) {
  ExtremesScratch scratch;
  int rounds_above_one = 0, fell_back = 0;
  for (std::uint64_t seed = 1; seed <= 300; ++seed) {
    const test::PolarCase polar = test::polar_case(seed);
    const PolarProfile profile = polar.profile();
    std::vector<Point2> points(profile.size());
    for (std::size_t j = 0; j < points.size(); ++j) points[j] = polar_point(profile, j);
    const MinimumZoneCircle full = minimum_zone_circle(points);
    const double fast = minimum_zone_ront_from_extremes(points, {3e-3, -1e-3}, scratch);
    EXPECT_EQ(fast, full.ron.ront) << "seed " << seed << ", n " << points.size();
    EXPECT_EQ(scratch.center, full.center) << "seed " << seed << ", n " << points.size();
    rounds_above_one += scratch.rounds > 1 ? 1 : 0;
    fell_back += scratch.fell_back ? 1 : 0;
    if (seed % 50 == 0) {
      std::vector<Point2> scrambled(points.size());
      for (std::size_t j = 0; j < points.size(); ++j)
        scrambled[j] = points[(j * 7919) % points.size()];
      if (std::gcd(points.size(), std::size_t{7919}) != 1) continue;
      const MinimumZoneCircle f2 = minimum_zone_circle(scrambled);
      EXPECT_EQ(minimum_zone_ront_from_extremes(scrambled, {40.0, 40.0}, scratch), f2.ron.ront)
          << "scrambled, seed " << seed;
      EXPECT_EQ(scratch.center, f2.center) << "scrambled, seed " << seed;
    }
  }
  EXPECT_GT(rounds_above_one, 0);  // the offset regime exercises the rounds
  EXPECT_LT(fell_back, 300);       // (small, exact-circle and lobed cases fall back)

  // Filtered noisy rings far from the origin (a CMM's coordinates), 3 600 points at 50 UPR.
  int settled = 0;
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    const test::PolarCase polar = test::polar_case(6 * 4 * 5 * seed + 6 * 4 + 1);  // noise, 3600
    ASSERT_EQ(polar.n, 3600u);
    std::vector<Point2> ring(polar.n);
    for (std::size_t j = 0; j < polar.n; ++j) {
      const Point2 q = polar_point(polar.profile(), j);
      ring[j] = {412.5 + q.x + 2e-3 * std::cos(3.0 * static_cast<double>(j) * 2 * std::numbers::pi / 3600),
                 305.25 + q.y};
    }
    const FilteredProfile filtered =
        gaussian_filtered_profile(ring, 50.0, least_squares_circle(ring));
    const MinimumZoneCircle full = minimum_zone_circle(filtered.points);
    const double fast =
        minimum_zone_ront_from_extremes(filtered.points, filtered.filter_center, scratch);
    EXPECT_EQ(fast, full.ron.ront) << "filtered, seed " << seed;
    EXPECT_EQ(scratch.center, full.center) << "filtered, seed " << seed;
    settled += scratch.fell_back ? 0 : 1;
  }
  EXPECT_EQ(settled, 60);
}

// The points overload's bad input: too few points, a non-finite one (named), collinear data
// (named by the full fitter it falls back to).
TEST(MinimumZoneFromExtremes, PointsOverloadRejectsBadInput) {
  ExtremesScratch scratch;
  std::vector<Point2> few(7, Point2{1.0, 2.0});
  EXPECT_THROW(minimum_zone_ront_from_extremes(few, {0.0, 0.0}, scratch), InvalidInput);
  std::vector<Point2> ring(16);
  for (std::size_t j = 0; j < ring.size(); ++j) {
    const double a = 2 * std::numbers::pi * static_cast<double>(j) / 16;
    ring[j] = {85.0 * std::cos(a), 85.0 * std::sin(a) + 1e-4 * std::cos(3 * a)};
  }
  ring[5].y = std::numeric_limits<double>::quiet_NaN();
  try {
    minimum_zone_ront_from_extremes(ring, {0.0, 0.0}, scratch);
    ADD_FAILURE() << "no exception for a NaN point";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("point 5 has a non-finite coordinate"),
              std::string::npos)
        << e.what();
  }
  std::vector<Point2> line(16);
  for (std::size_t j = 0; j < line.size(); ++j) line[j] = {static_cast<double>(j), 2.0 * static_cast<double>(j)};
  try {
    minimum_zone_ront_from_extremes(line, {0.0, 0.0}, scratch);
    ADD_FAILURE() << "no exception for collinear points";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("collinear"), std::string::npos) << e.what();
  }
}

// Bad input: sizes, non-finite deviations, directions.
TEST(MinimumZoneFromExtremes, RejectsBadInput) {
  ExtremesScratch scratch;
  const PolarDirections directions = test::equiangular_directions(16);
  const std::vector<double> short_d(15, 0.0);
  EXPECT_THROW(minimum_zone_ront_from_extremes({85.0, short_d, &directions}, scratch),
               InvalidInput);
  EXPECT_THROW(minimum_zone_ront_from_extremes({85.0, std::vector<double>(16), nullptr}, scratch),
               InvalidInput);
  std::vector<double> d(16, 0.0);
  d[5] = std::numeric_limits<double>::quiet_NaN();
  try {
    minimum_zone_ront_from_extremes({85.0, d, &directions}, scratch);
    ADD_FAILURE() << "no exception for a NaN deviation";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("deviation 5 is not finite"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(PolarDirections(std::vector<double>(3, 1.0), std::vector<double>(3, 0.0)),
               InvalidInput);
  std::vector<double> c(8, 1.0), s(8, 0.0);
  c[2] = 0.0;
  EXPECT_THROW(PolarDirections(c, s), InvalidInput);
  EXPECT_THROW(PolarDirections(std::vector<double>(8, 1.0), std::vector<double>(9, 0.0)),
               InvalidInput);
}

}  // namespace
}  // namespace vcmm::geometry
