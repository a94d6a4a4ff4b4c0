// Tests of vcmm/geometry/angular_coverage.h and the per-circle outcomes of evaluate_roundness on
// partial arcs (vcmm/geometry/roundness.h).
#include "vcmm/geometry/angular_coverage.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "vcmm/geometry/certificate.h"
#include "vcmm/geometry/roundness.h"

namespace vcmm::geometry {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<Point2> arc(double span_deg, std::size_t n, double start_deg = 20.0) {
  std::vector<Point2> p;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = (start_deg + span_deg * double(i) / double(n - 1)) * kPi / 180.0;
    const double r = 10.0 + 0.001 * std::cos(3.0 * t);
    p.push_back({5.0 + r * std::cos(t), -3.0 + r * std::sin(t)});
  }
  return p;
}

TEST(AngularCoverage, ArcSpanGapAndEndsByHand) {
  const auto p = arc(100.0, 201);
  const AngularCoverage c = angular_coverage(p, {5.0, -3.0});
  EXPECT_NEAR(c.covered_rad * 180.0 / kPi, 100.0, 1e-9);
  EXPECT_NEAR(c.largest_gap_rad * 180.0 / kPi, 260.0, 1e-9);
  EXPECT_NEAR(c.gap_start_rad * 180.0 / kPi, 120.0, 1e-9);
  EXPECT_EQ(c.gap_start_index, 200u);
  EXPECT_EQ(c.gap_end_index, 0u);
  EXPECT_FALSE(c.closed);
}

TEST(AngularCoverage, ClosedProfilesWithJitterOrAFewMissingPointsAreClosed) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> jitter(-0.4, 0.4);
  std::vector<Point2> p;
  for (int i = 0; i < 360; ++i) {
    if (i == 100 || i == 101) continue;  // two missing points: a gap of three steps
    const double t = (i + jitter(rng)) * kPi / 180.0;
    p.push_back({std::cos(t), std::sin(t)});
  }
  const AngularCoverage c = angular_coverage(p, {0.0, 0.0});
  EXPECT_TRUE(c.closed);
  EXPECT_GT(c.covered_rad, 2.0 * kPi - 4.0 * kPi / 180.0);
  // A 10° hole makes it an arc.
  std::vector<Point2> holed;
  for (int i = 0; i < 360; ++i)
    if (i < 200 || i > 210) holed.push_back({std::cos(i * kPi / 180.0), std::sin(i * kPi / 180.0)});
  EXPECT_FALSE(angular_coverage(holed, {0.0, 0.0}).closed);
}

TEST(AngularCoverage, InvariantUnderPermutationAndRotation) {
  auto p = arc(250.0, 500);
  const AngularCoverage a = angular_coverage(p, {5.0, -3.0});
  std::mt19937_64 rng(9);
  std::shuffle(p.begin(), p.end(), rng);
  const AngularCoverage b = angular_coverage(p, {5.0, -3.0});
  EXPECT_EQ(a.covered_rad, b.covered_rad);
  EXPECT_EQ(a.largest_gap_rad, b.largest_gap_rad);
  const auto q = arc(250.0, 500, 200.0);  // the same arc turned by 180°: across ±π
  EXPECT_NEAR(angular_coverage(q, {5.0, -3.0}).covered_rad, a.covered_rad, 1e-12);
}

// Scans in angular order take the fast path (angular_coverage.cpp: atan2 for a few candidate
// steps only); the same points shuffled take the general path (an atan2 per point, buckets).
// The two must agree bit for bit, indices mapped through the permutation, over closed scans
// either way round, with jitter, missing points, far centres and an exactly equiangular ring
// (many tied steps: the fast path declines), and across θ = ±π at any start angle.
TEST(AngularCoverage, ScanOrderFastPathEqualsGeneralPathBitForBit) {
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 400; ++trial) {
    const std::size_t n = 16 + static_cast<std::size_t>(unit(rng) * 4000.0);
    const double start = unit(rng) * 2.0 * kPi, sense = (trial / 4) % 2 ? 1.0 : -1.0;
    const double jitter = trial % 5 == 0 ? 0.0 : unit(rng) * 0.45;
    const Point2 c{trial % 3 ? 0.0 : 900.0 * unit(rng), trial % 3 ? 0.0 : -400.0 * unit(rng)};
    std::vector<Point2> p;
    for (std::size_t i = 0; i < n; ++i) {
      if (trial % 7 == 1 && (i == n / 3 || i == n / 3 + 1)) continue;  // a missing pair
      const double t = start + sense * (double(i) + jitter * (unit(rng) - 0.5)) * 2.0 * kPi /
                                   double(n);
      const double r = 85.5 + (trial % 5 == 0 ? 0.0 : 1e-3 * (unit(rng) - 0.5));
      p.push_back({c.x + r * std::cos(t), c.y + r * std::sin(t)});
    }
    std::vector<std::size_t> perm(p.size());
    for (std::size_t i = 0; i < perm.size(); ++i) perm[i] = i;
    std::shuffle(perm.begin(), perm.end(), rng);
    std::vector<Point2> q(p.size());
    for (std::size_t i = 0; i < perm.size(); ++i) q[i] = p[perm[i]];
    // A centre off the points' own by 0 to 1 µm: the LS centre of a filtered profile is not
    // theirs either, and the closer it is, the more steps tie to the last ulps.
    const double off = trial % 4 == 0 ? 0.0 : trial % 4 == 1 ? 1e-3 : trial % 4 == 2 ? 1e-7 : 1e-10;
    const Point2 at{c.x + off * (unit(rng) - 0.5), c.y + off * (unit(rng) - 0.5)};
    const AngularCoverage a = angular_coverage(p, at), b = angular_coverage(q, at);
    EXPECT_EQ(a.largest_gap_rad, b.largest_gap_rad) << "trial " << trial << " n " << n;
    EXPECT_EQ(a.covered_rad, b.covered_rad) << trial;
    EXPECT_EQ(a.gap_start_rad, b.gap_start_rad) << trial;
    EXPECT_EQ(a.gap_start_index, perm[b.gap_start_index]) << trial;
    EXPECT_EQ(a.gap_end_index, perm[b.gap_end_index]) << trial;
    EXPECT_EQ(a.closed, b.closed) << trial;
  }
}

// Points on the axis through the centre with y = −0 (atan2(−0, x < 0) = −π: the smallest
// angle, not the largest), in scan order and shuffled, either way round.
TEST(AngularCoverage, NegativeZeroOnTheAxisKeepsItsAtan2Side) {
  for (double sense : {1.0, -1.0}) {
    std::vector<Point2> p;
    for (int i = 0; i < 64; ++i) {
      const double t = sense * i * kPi / 32.0;
      p.push_back({std::cos(t), std::sin(t)});
    }
    p[32] = {-1.0, -0.0};  // θ = π
    p[0] = {1.0, -0.0};    // θ = 0
    const AngularCoverage a = angular_coverage(p, {0.0, 0.0});
    std::vector<Point2> q(p.rbegin(), p.rend());  // the other way round
    std::rotate(q.begin(), q.begin() + 5, q.end());
    std::mt19937_64 rng(5);
    std::vector<Point2> r = p;
    std::shuffle(r.begin(), r.end(), rng);
    for (const auto& other : {q, r}) {
      const AngularCoverage b = angular_coverage(other, {0.0, 0.0});
      EXPECT_EQ(a.largest_gap_rad, b.largest_gap_rad) << sense;
      EXPECT_EQ(a.gap_start_rad, b.gap_start_rad) << sense;
      EXPECT_EQ(p[a.gap_start_index], other[b.gap_start_index]) << sense;
      EXPECT_EQ(p[a.gap_end_index], other[b.gap_end_index]) << sense;
    }
  }
}

TEST(AngularCoverage, PointsAtTheCentreAreLeftOutAndBadInputRefused) {
  std::vector<Point2> p = {{1, 0}, {0, 0}, {-1, 0}, {0, 1}};
  const AngularCoverage c = angular_coverage(p, {0, 0});
  EXPECT_NEAR(c.largest_gap_rad, kPi, 1e-15);  // from (-1,0) round through -y to (1,0)
  EXPECT_THROW(angular_coverage(std::vector<Point2>{{0, 0}, {1, 0}}, {0, 0}), InvalidInput);
  EXPECT_THROW(angular_coverage(std::vector<Point2>{{1, 0}}, {0, 0}), InvalidInput);
  EXPECT_THROW(angular_coverage(p, {NAN, 0}), InvalidInput);
  p[2].x = INFINITY;
  EXPECT_THROW(angular_coverage(p, {0, 0}), InvalidInput);
}

// The failing cases: a 90° and a 100° arc. LS and MZ are defined (MZ certified), MI is
// undefined with its reason, MC is defined with the caution; no exception.
TEST(EvaluateRoundnessPerCircle, PartialArcsKeepEveryDefinedCircle) {
  for (double span : {90.0, 100.0, 170.0}) {
    const auto p = arc(span, 200);
    const RoundnessEvaluation e = evaluate_roundness(p, {});
    EXPECT_TRUE(e.least_squares.has_value()) << span;
    ASSERT_TRUE(e.minimum_zone.has_value()) << span;
    EXPECT_TRUE(verify(p, *e.minimum_zone).valid) << span;
    EXPECT_FALSE(e.maximum_inscribed.has_value()) << span;
    ASSERT_EQ(e.undefined.count(ReferenceCircle::maximum_inscribed), 1u) << span;
    EXPECT_NE(e.undefined.at(ReferenceCircle::maximum_inscribed).find("not defined"),
              std::string::npos);
    ASSERT_TRUE(e.minimum_circumscribed.has_value());
    EXPECT_EQ(e.cautions.at(ReferenceCircle::minimum_circumscribed),
              "not a roundness reference on an arc < 180°");
    EXPECT_EQ(e.defined_count(), 3u);
    EXPECT_FALSE(e.coverage.closed);
    EXPECT_NEAR(e.coverage.covered_rad * 180.0 / kPi, span, 0.1) << span;
  }
  // 200°: MI exists; no caution (the arc covers more than half the circle).
  const auto p = arc(200.0, 200);
  const RoundnessEvaluation e = evaluate_roundness(p, {});
  EXPECT_TRUE(e.maximum_inscribed.has_value());
  EXPECT_TRUE(e.cautions.empty());
  // Only MI asked on a short arc: nothing defined, no exception.
  RoundnessRequest mi_only;
  mi_only.least_squares = mi_only.minimum_zone = mi_only.minimum_circumscribed = false;
  const RoundnessEvaluation none = evaluate_roundness(arc(90.0, 200), mi_only);
  EXPECT_EQ(none.defined_count(), 0u);
  EXPECT_EQ(none.undefined.size(), 1u);
  // Issue 12: the coverage then read "0°, closed"; it is the arc's, about the LS centre.
  EXPECT_FALSE(none.coverage.closed);
  EXPECT_NEAR(none.coverage.covered_rad * 180.0 / kPi, 90.0, 0.5);
}

TEST(ReferenceCircleNames, RoundTrip) {
  for (auto c : {ReferenceCircle::minimum_zone, ReferenceCircle::maximum_inscribed,
                 ReferenceCircle::least_squares, ReferenceCircle::minimum_circumscribed})
    EXPECT_EQ(reference_circle_from_string(to_string(c)), c);
  EXPECT_FALSE(reference_circle_from_string("mz").has_value());
}

}  // namespace
}  // namespace vcmm::geometry

namespace vcmm::geometry {
namespace {

// Issue 11: with a filter, RONt depended on the order of the points (a shuffled scan took the
// nonuniform path: 1.584 against 1.807 µm at 120 points and 50 UPR). Now any order gives the
// scan's result to the rounding of the LS fit's sums, and contacts name the same points.
TEST(OrderIndependence, ShuffledProfilesGiveTheSameFilteredRoundness) {
  std::mt19937_64 rng(21);
  std::normal_distribution<double> noise(0.0, 0.5e-3);
  for (std::size_t n : {120u, 361u, 3600u}) {
    std::vector<Point2> p;
    for (std::size_t i = 0; i < n; ++i) {
      const double t = 2.0 * kPi * double(i) / double(n);
      const double r = 85.5 + 2e-3 * std::cos(2 * t) + noise(rng);
      p.push_back({600.0 + r * std::cos(t), 500.0 + r * std::sin(t)});
    }
    RoundnessRequest request;
    request.filter_cutoff_upr = std::min(50.0, double(n) / 2.0);
    const RoundnessEvaluation a = evaluate_roundness(p, request);
    std::vector<std::size_t> perm(n);
    for (std::size_t i = 0; i < n; ++i) perm[i] = i;
    std::shuffle(perm.begin(), perm.end(), rng);
    std::vector<Point2> q(n);
    for (std::size_t i = 0; i < n; ++i) q[i] = p[perm[i]];
    const RoundnessEvaluation b = evaluate_roundness(q, request);
    ASSERT_TRUE(a.minimum_zone && b.minimum_zone && a.maximum_inscribed && b.maximum_inscribed);
    EXPECT_NEAR(a.minimum_zone->ron.ront, b.minimum_zone->ron.ront, 1e-12) << n;
    EXPECT_NEAR(a.maximum_inscribed->ron.ront, b.maximum_inscribed->ron.ront, 1e-12) << n;
    EXPECT_NEAR(a.least_squares->ron.ront, b.least_squares->ron.ront, 1e-12) << n;
    // The same contacts, named by their input indices.
    for (std::size_t k = 0; k < 2; ++k)
      EXPECT_EQ(perm[b.minimum_zone->outer_contacts[k]], a.minimum_zone->outer_contacts[k]) << n;
    // Filtered point i of the shuffled input is filtered point perm[i] of the original.
    for (std::size_t i = 0; i < n; i += 7) {
      EXPECT_NEAR(b.filtered_points[i].x, a.filtered_points[perm[i]].x, 1e-10) << n;
      EXPECT_NEAR(b.filtered_points[i].y, a.filtered_points[perm[i]].y, 1e-10) << n;
    }
  }
}

}  // namespace
}  // namespace vcmm::geometry
