// Tests of vcmm/geometry/claim_check.h: the exact circles claimed back are feasible and optimal,
// perturbed claims are not and their excess equals the RONt about the claim minus the exact one,
// infeasible radii name the violating points, and bad claims are refused.
#include "vcmm/geometry/claim_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/minimum_circumscribed.h"
#include "vcmm/geometry/minimum_zone.h"

namespace vcmm::geometry {
namespace {

std::vector<Point2> ring(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.3e-3);
  std::vector<Point2> p;
  for (int i = 0; i < 720; ++i) {
    const double t = 2.0 * std::numbers::pi * i / 720.0;
    const double r = 85.5 + 2e-3 * std::cos(2 * t + 0.3) + 1e-3 * std::cos(3 * t) + noise(rng);
    p.push_back({600.0 + r * std::cos(t), 500.0 + r * std::sin(t)});
  }
  return p;
}

/// RONt about a centre: the greatest minus the least distance.
double spread(const std::vector<Point2>& p, Point2 c) {
  double lo = 1e300, hi = 0.0;
  for (const Point2& q : p) {
    const double d = std::hypot(q.x - c.x, q.y - c.y);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  return hi - lo;
}

TEST(ClaimCheck, TheExactCirclesClaimedBackAreOptimal) {
  const auto p = ring(1);
  const auto mz = minimum_zone_circle(p);
  ClaimCheck c = check_claimed_circle(p, {ReferenceCircle::minimum_zone, mz.center,
                                          std::pair{mz.inner_radius, mz.outer_radius}});
  EXPECT_TRUE(c.exact_certified);
  EXPECT_LE(std::abs(c.excess_ront), c.tolerance);
  EXPECT_EQ(c.center_distance, 0.0);
  EXPECT_EQ(c.exact_contacts.size(), 4u);
  // The rounded radii may put a contact a rounding outside; the claim without radii is the
  // tightest annulus about the centre and optimal.
  c = check_claimed_circle(p, {ReferenceCircle::minimum_zone, mz.center, std::nullopt});
  EXPECT_TRUE(c.feasible);
  EXPECT_TRUE(c.optimal) << c.excess_ront << " > " << c.tolerance;
  const auto mi = maximum_inscribed_circle(p);
  c = check_claimed_circle(p, {ReferenceCircle::maximum_inscribed, mi.center, std::nullopt});
  EXPECT_TRUE(c.optimal);
  const auto mc = minimum_circumscribed_circle(p);
  c = check_claimed_circle(p, {ReferenceCircle::minimum_circumscribed, mc.center, std::nullopt});
  EXPECT_TRUE(c.optimal);
  const auto ls = least_squares_circle(p);
  c = check_claimed_circle(p, {ReferenceCircle::least_squares, ls.center, std::nullopt});
  EXPECT_TRUE(c.optimal);
  c = check_claimed_circle(p, {ReferenceCircle::least_squares, {ls.center.x + 1e-8, ls.center.y},
                               std::nullopt});
  EXPECT_FALSE(c.optimal);  // 10 nm off vcmm's LS centre: a different fit
}

TEST(ClaimCheck, AShiftedCentreIsNotOptimalAndItsExcessIsTheSpreadDifference) {
  const auto p = ring(2);
  const auto mz = minimum_zone_circle(p);
  for (double shift : {1e-6, 1e-4, 1e-3}) {
    const Point2 c{mz.center.x + shift, mz.center.y - 0.5 * shift};
    const ClaimCheck k = check_claimed_circle(p, {ReferenceCircle::minimum_zone, c, std::nullopt});
    EXPECT_TRUE(k.feasible);
    EXPECT_FALSE(k.optimal) << shift;
    EXPECT_GT(k.excess_ront, 0.0);
    EXPECT_NEAR(k.claimed_ront, spread(p, c), 1e-15);
    EXPECT_NEAR(k.excess_ront, spread(p, c) - mz.ron.ront, 1e-15);
    EXPECT_NEAR(k.center_distance, std::hypot(shift, 0.5 * shift), 2e-13);  // ulp(600) = 1.1e-13
  }
}

TEST(ClaimCheck, InfeasibleRadiiNameTheViolatingPoints) {
  const auto p = ring(3);
  const auto mz = minimum_zone_circle(p);
  // A zone 10 nm too narrow on each side: the contacts fall outside.
  ClaimCheck k = check_claimed_circle(
      p, {ReferenceCircle::minimum_zone, mz.center,
          std::pair{mz.inner_radius + 1e-5, mz.outer_radius - 1e-5}});
  EXPECT_FALSE(k.feasible);
  EXPECT_FALSE(k.optimal);
  EXPECT_GE(k.violations, 4u);
  for (std::size_t i : mz.outer_contacts)
    EXPECT_NE(std::find(k.violating.begin(), k.violating.end(), i), k.violating.end()) << i;
  EXPECT_LT(k.excess_ront, 0.0);  // narrower than the optimum: only because it is infeasible
  // MI: a larger radius is infeasible, a smaller one feasible but short of the optimum.
  const auto mi = maximum_inscribed_circle(p);
  k = check_claimed_circle(p, {ReferenceCircle::maximum_inscribed, mi.center,
                               std::pair{mi.radius + 1e-6, mi.radius + 1e-6}});
  EXPECT_FALSE(k.feasible);
  k = check_claimed_circle(p, {ReferenceCircle::maximum_inscribed, mi.center,
                               std::pair{mi.radius - 1e-6, mi.radius - 1e-6}});
  EXPECT_TRUE(k.feasible);
  EXPECT_FALSE(k.optimal);
  EXPECT_NEAR(k.radius_excess, 1e-6, 3e-14);  // ulp(85.5) = 1.4e-14
  // MC: a smaller radius is infeasible.
  const auto mc = minimum_circumscribed_circle(p);
  k = check_claimed_circle(p, {ReferenceCircle::minimum_circumscribed, mc.center,
                               std::pair{mc.radius - 1e-6, mc.radius - 1e-6}});
  EXPECT_FALSE(k.feasible);
}

// Exactness of the containment test: a point exactly on the claimed circle is inside it.
TEST(ClaimCheck, ContainmentIsDecidedExactlyAtTheBoundary) {
  // (3, 4) and (5, 0) are exactly at distance 5 from the origin.
  const std::vector<Point2> p = {{3, 4}, {5, 0}, {-4, 3}, {0, -5}, {-3, -4}, {4, -3}};
  ClaimCheck k = check_claimed_circle(
      p, {ReferenceCircle::minimum_circumscribed, {0, 0}, std::pair{5.0, 5.0}});
  EXPECT_TRUE(k.feasible);
  EXPECT_TRUE(k.optimal);
  k = check_claimed_circle(p, {ReferenceCircle::minimum_circumscribed, {0, 0},
                               std::pair{std::nextafter(5.0, 0.0), std::nextafter(5.0, 0.0)}});
  EXPECT_FALSE(k.feasible);
  EXPECT_EQ(k.violations, 6u);
}

TEST(ClaimCheck, BadClaimsAreRefused) {
  const auto p = ring(4);
  EXPECT_THROW(check_claimed_circle(p, {ReferenceCircle::minimum_zone, {NAN, 0}, std::nullopt}),
               InvalidInput);
  EXPECT_THROW(check_claimed_circle(p, {ReferenceCircle::minimum_zone, {600, 500},
                                        std::pair{2.0, 1.0}}),
               InvalidInput);
  EXPECT_THROW(check_claimed_circle(p, {ReferenceCircle::minimum_zone, {600, 500},
                                        std::pair{-1.0, 1.0}}),
               InvalidInput);
}

}  // namespace
}  // namespace vcmm::geometry
