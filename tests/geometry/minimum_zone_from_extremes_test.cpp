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
#include <string>
#include <vector>

#include "support/polar_profiles.h"
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
