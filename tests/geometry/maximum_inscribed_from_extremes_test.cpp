// Tests of the maximum-inscribed circle from a subset of extremes
// (vcmm/geometry/maximum_inscribed_from_extremes.h) against maximum_inscribed_circle on all
// points, over the regimes of the minimum-zone analogue's test: band-limited profiles of
// several bandwidths and sizes, unfiltered noise, a large centre offset (the inner contacts
// far from the starting valleys: several rounds), nearly perfect and exact circles, pure lobed
// forms (symmetric near-ties); seeds in the messages.
#include "vcmm/geometry/maximum_inscribed_from_extremes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "support/polar_profiles.h"
#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/maximum_inscribed.h"

namespace vcmm::geometry {
namespace {


// RONt bit for bit as maximum_inscribed_circle on all points reports it, in every regime
// (and the same centre where the MI is unique: not on exact circles or symmetric lobes).
TEST(MaximumInscribedFromExtremes, EqualsTheMaximumInscribedCircleOfAllPoints) {
  ExtremesScratch scratch;
  int fast_paths = 0, rounds_above_one = 0;
  for (std::uint64_t seed = 1; seed <= 300; ++seed) {
    const test::PolarCase polar = test::polar_case(seed);
    const auto regime = polar.regime;
    const std::size_t n = polar.n;
    const PolarProfile profile = polar.profile();
    std::vector<Point2> points(n);
    for (std::size_t j = 0; j < n; ++j) points[j] = polar_point(profile, j);
    const MaximumInscribedCircle full = maximum_inscribed_circle(points);
    const double fast = maximum_inscribed_ront_from_extremes(profile, scratch);
    EXPECT_EQ(fast, full.ron.ront) << "seed " << seed << ", n " << n;
    if (regime != test::PolarRegime::circle && regime != test::PolarRegime::lobed &&
        regime != test::PolarRegime::near_circle) {
      EXPECT_EQ(scratch.center, full.center) << "seed " << seed << ", n " << n;
    }
    fast_paths += scratch.fell_back ? 0 : 1;
    rounds_above_one += !scratch.fell_back && scratch.rounds > 1 ? 1 : 0;
  }
  EXPECT_GT(fast_paths, 150);  // most profiles are decided by their subset
  EXPECT_GT(rounds_above_one, 0);
}

// The points overload: RONt bit for bit maximum_inscribed_circle(points)'s (and its centre
// where the MI is unique) on the polar sweep about an origin 3 µm off (also in a scrambled
// order, which takes the full fit), and on filtered noisy rings far from the origin, which
// the subset must decide.
TEST(MaximumInscribedFromExtremes, PointsOverloadEqualsTheMaximumInscribedCircleOfAllPoints) {
  ExtremesScratch scratch;
  int fast_paths = 0;
  for (std::uint64_t seed = 1; seed <= 300; ++seed) {
    const test::PolarCase polar = test::polar_case(seed);
    const PolarProfile profile = polar.profile();
    std::vector<Point2> points(polar.n);
    for (std::size_t j = 0; j < polar.n; ++j) points[j] = polar_point(profile, j);
    const MaximumInscribedCircle full = maximum_inscribed_circle(points);
    const double fast = maximum_inscribed_ront_from_extremes(points, {3e-3, -1e-3}, scratch);
    EXPECT_EQ(fast, full.ron.ront) << "seed " << seed << ", n " << polar.n;
    if (polar.regime != test::PolarRegime::circle && polar.regime != test::PolarRegime::lobed &&
        polar.regime != test::PolarRegime::near_circle) {
      EXPECT_EQ(scratch.center, full.center) << "seed " << seed << ", n " << polar.n;
    }
    fast_paths += scratch.fell_back ? 0 : 1;
    if (seed % 50 == 0 && polar.n % 7919 != 0) {
      std::vector<Point2> scrambled(polar.n);
      for (std::size_t j = 0; j < polar.n; ++j) scrambled[j] = points[(j * 7919) % polar.n];
      EXPECT_EQ(maximum_inscribed_ront_from_extremes(scrambled, {40.0, 40.0}, scratch),
                maximum_inscribed_circle(scrambled).ron.ront)
          << "scrambled, seed " << seed;
    }
  }
  EXPECT_GT(fast_paths, 100);
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    const test::PolarCase polar = test::polar_case(120 * seed + 25);  // noise regime, 3600
    ASSERT_EQ(polar.n, 3600u);
    std::vector<Point2> ring(polar.n);
    for (std::size_t j = 0; j < polar.n; ++j) {
      const Point2 q = polar_point(polar.profile(), j);
      const double a = 2 * std::numbers::pi * static_cast<double>(j) / 3600;
      ring[j] = {412.5 + q.x + 2e-3 * std::cos(3.0 * a), 305.25 + q.y};
    }
    const FilteredProfile filtered =
        gaussian_filtered_profile(ring, 50.0, least_squares_circle(ring));
    const MaximumInscribedCircle full = maximum_inscribed_circle(filtered.points);
    EXPECT_EQ(maximum_inscribed_ront_from_extremes(filtered.points, filtered.filter_center,
                                                   scratch),
              full.ron.ront)
        << "filtered, seed " << seed;
    EXPECT_EQ(scratch.center, full.center) << "filtered, seed " << seed;
    EXPECT_FALSE(scratch.fell_back) << "filtered, seed " << seed;
  }
}

// The points overload's bad input: too few points, a non-finite one (named).
TEST(MaximumInscribedFromExtremes, PointsOverloadRejectsBadInput) {
  ExtremesScratch scratch;
  EXPECT_THROW(maximum_inscribed_ront_from_extremes(std::vector<Point2>(7, Point2{1.0, 2.0}),
                                                    {0.0, 0.0}, scratch),
               InvalidInput);
  std::vector<Point2> ring(16);
  for (std::size_t j = 0; j < ring.size(); ++j) {
    const double a = 2 * std::numbers::pi * static_cast<double>(j) / 16;
    ring[j] = {85.0 * std::cos(a), 85.0 * std::sin(a) + 1e-4 * std::cos(3 * a)};
  }
  ring[5].x = std::numeric_limits<double>::infinity();
  try {
    maximum_inscribed_ront_from_extremes(ring, {0.0, 0.0}, scratch);
    ADD_FAILURE() << "no exception for an infinite point";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("point 5 has a non-finite coordinate"),
              std::string::npos)
        << e.what();
  }
}

TEST(MaximumInscribedFromExtremes, RejectsBadInput) {
  ExtremesScratch scratch;
  const PolarDirections directions = test::equiangular_directions(16);
  EXPECT_THROW(
      maximum_inscribed_ront_from_extremes({85.0, std::vector<double>(15), &directions}, scratch),
      InvalidInput);
  std::vector<double> d(16, 0.0);
  d[3] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(maximum_inscribed_ront_from_extremes({85.0, d, &directions}, scratch),
               InvalidInput);
}

}  // namespace
}  // namespace vcmm::geometry
