// Tests of roundness_parameters (ISO 12181-1 RONt, RONp, RONv, RONq about a given circle):
// hand-checkable values, the clamping of RONp/RONv at zero, independence of RONt from the
// reference radius, accuracy far from the origin, invariances, and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "support/test_profiles.h"
#include "vcmm/geometry/roundness_parameters.h"

namespace {

using vcmm::geometry::InvalidInput;
using vcmm::geometry::Point2;
using vcmm::geometry::roundness_parameters;
using vcmm::geometry::RoundnessParameters;

/// Points at the given radii, on the axes in turn, about c.
std::vector<Point2> points_at_radii(Point2 c, const std::vector<double>& radii) {
  const Point2 dirs[] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
  std::vector<Point2> pts;
  for (std::size_t i = 0; i < radii.size(); ++i)
    pts.push_back({c.x + radii[i] * dirs[i % 4].x, c.y + radii[i] * dirs[i % 4].y});
  return pts;
}

TEST(RoundnessParameters, ByHand) {
  // Radii 1, 2, 3 about the origin, reference radius 2: deviations −1, 0, +1.
  const auto pts = points_at_radii({0, 0}, {1, 2, 3});
  const RoundnessParameters p = roundness_parameters(pts, {0, 0}, 2.0);
  EXPECT_DOUBLE_EQ(p.ront, 2.0);
  EXPECT_DOUBLE_EQ(p.ronp, 1.0);
  EXPECT_DOUBLE_EQ(p.ronv, 1.0);
  EXPECT_DOUBLE_EQ(p.ronq, std::sqrt(2.0 / 3.0));
}

TEST(RoundnessParameters, PerfectCircleIsZero) {
  const auto pts = points_at_radii({3, -4}, {5, 5, 5, 5});
  const RoundnessParameters p = roundness_parameters(pts, {3, -4}, 5.0);
  EXPECT_EQ(p.ront, 0.0);
  EXPECT_EQ(p.ronp, 0.0);
  EXPECT_EQ(p.ronv, 0.0);
  EXPECT_EQ(p.ronq, 0.0);
}

TEST(RoundnessParameters, PeakAndValleyClampAtZero) {
  const auto pts = points_at_radii({0, 0}, {1, 2, 3});
  // Reference circle outside every point (as for an MC circle): no peak, valley depth 3.
  const RoundnessParameters out = roundness_parameters(pts, {0, 0}, 4.0);
  EXPECT_EQ(out.ronp, 0.0);
  EXPECT_DOUBLE_EQ(out.ronv, 3.0);
  EXPECT_DOUBLE_EQ(out.ront, 2.0);
  EXPECT_DOUBLE_EQ(out.ronq, std::sqrt((9.0 + 4.0 + 1.0) / 3.0));
  // Reference circle inside every point (as for an MI circle): no valley.
  const RoundnessParameters in = roundness_parameters(pts, {0, 0}, 0.5);
  EXPECT_DOUBLE_EQ(in.ronp, 2.5);
  EXPECT_EQ(in.ronv, 0.0);
  EXPECT_DOUBLE_EQ(in.ront, 2.0);
  // A zero reference radius is a valid (if odd) reference.
  const RoundnessParameters zero = roundness_parameters(pts, {0, 0}, 0.0);
  EXPECT_DOUBLE_EQ(zero.ronp, 3.0);
  EXPECT_EQ(zero.ronv, 0.0);
}

TEST(RoundnessParameters, RontDoesNotDependOnTheReferenceRadius) {
  const auto pts = vcmm::test::lobed_noisy_ring(360, 4);
  const double base = roundness_parameters(pts, {0, 0}, 85.5).ront;
  for (double r : {0.0, 85.0, 85.5001, 100.0})
    EXPECT_EQ(roundness_parameters(pts, {0, 0}, r).ront, base) << "radius " << r;
}

TEST(RoundnessParameters, SinglePoint) {
  const RoundnessParameters p = roundness_parameters(std::vector<Point2>{{3, 4}}, {0, 0}, 4.0);
  EXPECT_EQ(p.ront, 0.0);
  EXPECT_DOUBLE_EQ(p.ronp, 1.0);
  EXPECT_EQ(p.ronv, 0.0);
  EXPECT_DOUBLE_EQ(p.ronq, 1.0);
}

TEST(RoundnessParameters, FarFromTheOriginLosesOnlyTheInputRounding) {
  // The same profile about (0, 0) and about (812.3, −555.1): coordinates 900 mm out carry
  // ½ ulp ≈ 5.7e-14 mm each, so the parameters agree to a few of those.
  const auto near = vcmm::test::lobed_noisy_ring(3600, 6);
  const Point2 far_center{812.3, -555.1};
  std::vector<Point2> far;
  for (const Point2& p : near) far.push_back({p.x + far_center.x, p.y + far_center.y});
  const RoundnessParameters a = roundness_parameters(near, {0, 0}, 85.5);
  const RoundnessParameters b = roundness_parameters(far, far_center, 85.5);
  EXPECT_NEAR(a.ront, b.ront, 4e-13);
  EXPECT_NEAR(a.ronp, b.ronp, 4e-13);
  EXPECT_NEAR(a.ronv, b.ronv, 4e-13);
  EXPECT_NEAR(a.ronq, b.ronq, 4e-13);
  EXPECT_GT(a.ront, 1e-4);  // a real profile: lobing + noise of a few tenths of a µm
}

TEST(RoundnessParameters, InvariantUnderPermutation) {
  auto pts = vcmm::test::lobed_noisy_ring(500, 2);
  const RoundnessParameters a = roundness_parameters(pts, {1e-6, -2e-6}, 85.5);
  std::reverse(pts.begin(), pts.end());
  std::rotate(pts.begin(), pts.begin() + 77, pts.end());
  const RoundnessParameters b = roundness_parameters(pts, {1e-6, -2e-6}, 85.5);
  EXPECT_EQ(a.ront, b.ront);
  EXPECT_EQ(a.ronp, b.ronp);
  EXPECT_EQ(a.ronv, b.ronv);
  EXPECT_NEAR(a.ronq, b.ronq, 1e-15);  // summation order
}

TEST(RoundnessParameters, ExtremeCoordinatesDoNotOverflow) {
  // |p − c|² overflows a double beyond ~1.3e154; the distance itself does not.
  const std::vector<Point2> pts = {{3e200, 0}, {0, 4e200}};
  const RoundnessParameters p = roundness_parameters(pts, {0, 0}, 3.5e200);
  EXPECT_DOUBLE_EQ(p.ront, 1e200);
  EXPECT_DOUBLE_EQ(p.ronp, 0.5e200);
  EXPECT_DOUBLE_EQ(p.ronv, 0.5e200);
}

// ---- bad input --------------------------------------------------------------------------------

void expect_invalid(const std::vector<Point2>& pts, Point2 c, double r, const std::string& fragment) {
  try {
    roundness_parameters(pts, c, r);
    ADD_FAILURE() << "expected InvalidInput mentioning '" << fragment << "'";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("roundness_parameters"), std::string::npos) << what;
    EXPECT_NE(what.find(fragment), std::string::npos) << what;
  }
}

// The evaluator (roundness_parameters.cpp) takes its distances from the near-circle series
// four at a time when every point is near the radius, else by square roots two at a time. It
// must equal the one-point-at-a-time definition: bit for bit on the square-root path (points
// at the centre, distance 0: the hypot fallback inside a pair), and on the series path RONt,
// RONp, RONv bit for bit (the series gives std::sqrt's distance but within 2⁻⁵⁹ r of a
// rounding midpoint) and RONq to its last bits (four partial sums instead of one; the
// tolerance is 1e-12 relative, measured ≤ 2.3e-13 over 3000 simulated rings): counts of
// every residue mod 4, far-from-origin data.
TEST(RoundnessParameters, EqualsTheScalarDefinitionBitForBit) {
  const auto reference = [](const std::vector<Point2>& p, Point2 c, double radius) {
    const auto dist = [](double dx, double dy) {
      const double r = std::sqrt(dx * dx + dy * dy);
      return std::isfinite(r) && r > 1e-150 ? r : std::hypot(dx, dy);
    };
    const double size = std::max(std::fabs(radius), dist(p[0].x - c.x, p[0].y - c.y));
    const int e = size > 0.0 && std::isfinite(size) ? std::ilogb(size) : 0;
    double r_max = 0.0, r_min = 0.0, sum = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double r = dist(p[i].x - c.x, p[i].y - c.y);
      r_max = i == 0 ? r : std::max(r_max, r);
      r_min = i == 0 ? r : std::min(r_min, r);
      const double d = (r - radius) * std::ldexp(1.0, -e);
      sum += d * d;
    }
    return RoundnessParameters{r_max - r_min, std::max(0.0, r_max - radius),
                               std::max(0.0, radius - r_min),
                               std::ldexp(std::sqrt(sum / double(p.size())), e)};
  };
  for (bool at_centre : {true, false}) {
    for (std::size_t n : {1u, 2u, 3u, 4u, 5u, 6u, 7u, 360u, 3601u, 3602u, 3603u}) {
      auto p = vcmm::test::lobed_noisy_ring(std::max<std::size_t>(n, 3), 11, 5e-5, {600, 500});
      p.resize(n);
      const Point2 c{600.0 + 3e-7, 500.0 - 2e-7};
      if (at_centre && n > 3) p[2] = p[n - 2] = c;  // the square-root path
      const RoundnessParameters got = roundness_parameters(p, c, 85.5);
      const RoundnessParameters want = reference(p, c, 85.5);
      EXPECT_EQ(got.ront, want.ront) << n;
      EXPECT_EQ(got.ronp, want.ronp) << n;
      EXPECT_EQ(got.ronv, want.ronv) << n;
      if (at_centre && n > 3)
        EXPECT_EQ(got.ronq, want.ronq) << n;
      else
        EXPECT_NEAR(got.ronq, want.ronq, 1e-12 * want.ronq) << n;
    }
  }
}

TEST(RoundnessParametersBadInput, NoPoints) { expect_invalid({}, {0, 0}, 1.0, "at least 1"); }

TEST(RoundnessParametersBadInput, NonFinitePoint) {
  expect_invalid({{0, 1}, {1, std::nan("")}}, {0, 0}, 1.0, "point 1");
}

TEST(RoundnessParametersBadInput, NonFiniteCentre) {
  const std::vector<Point2> pts = {{0, 1}, {1, 0}, {0, -1}};
  expect_invalid(pts, {std::nan(""), 0}, 1.0, "centre must be finite");
  expect_invalid(pts, {0, std::numeric_limits<double>::infinity()}, 1.0, "centre must be finite");
}

TEST(RoundnessParametersBadInput, NonFiniteRadius) {
  const std::vector<Point2> pts = {{0, 1}, {1, 0}, {0, -1}};
  expect_invalid(pts, {0, 0}, std::nan(""), "reference radius must be finite");
  expect_invalid(pts, {0, 0}, -std::numeric_limits<double>::infinity(),
                 "reference radius must be finite");
}

}  // namespace
