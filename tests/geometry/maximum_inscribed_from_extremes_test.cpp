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
#include <vector>

#include "support/polar_profiles.h"
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
