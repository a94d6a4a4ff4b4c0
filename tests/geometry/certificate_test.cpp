// tests/geometry/certificate_test.cpp — verify() on hand-made certificates a reader can
// check on paper: correct ones pass, each kind of wrong one fails naming the condition.
#include "vcmm/geometry/certificate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "support/test_profiles.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/minimum_circumscribed.h"
#include "vcmm/geometry/minimum_zone.h"

namespace vcmm::geometry {
namespace {

::testing::AssertionResult Fails(const Verification& v, const std::string& needle) {
  if (v.valid) return ::testing::AssertionFailure() << "verified, but should have failed";
  if (v.reason.find(needle) == std::string::npos)
    return ::testing::AssertionFailure() << "reason \"" << v.reason << "\" lacks \"" << needle
                                         << "\"";
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult Passes(const Verification& v) {
  if (v.valid) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << v.reason;
}

// ---- minimum zone --------------------------------------------------------------------------
// Centre (0, 0), R = 10 (outer contacts (±10, 0)), r = 9 (inner contacts (0, ±9)); the
// contacts alternate at 0°, 90°, 180°, 270°; the other points have |p|² in [81, 100].
std::vector<Point2> zone_points() {
  return {{10, 0}, {0, 9}, {-10, 0}, {0, -9}, {6, 7.5}, {-7, -6.5}, {-3, 9.25}, {8, -5.5}};
}

MinimumZoneCircle zone_result() {
  MinimumZoneCircle mz;
  mz.center = {0, 0};
  mz.outer_radius = 10;
  mz.inner_radius = 9;
  mz.outer_contacts = {0, 2};
  mz.inner_contacts = {1, 3};
  mz.ron = {1.0, 0.5, 0.5, 0.3};
  mz.certificate.optimality = Optimality::local;
  return mz;
}

TEST(CertificateMinimumZone, HandMadeZonePasses) {
  EXPECT_TRUE(Passes(verify(zone_points(), zone_result())));
  auto mz = zone_result();
  std::swap(mz.outer_contacts[0], mz.outer_contacts[1]);
  std::swap(mz.inner_contacts[0], mz.inner_contacts[1]);
  EXPECT_TRUE(Passes(verify(zone_points(), mz))) << "order within a pair is irrelevant";
}

TEST(CertificateMinimumZone, GlobalClaimHoldsByTheRegionArgument) {
  // Segments o1o2 and i1i2 cross at the centre; every contact is 9 or 10 from the other
  // pair's line, far more than the width 1: the centre is the unique minimum.
  auto mz = zone_result();
  mz.certificate.optimality = Optimality::global;
  EXPECT_TRUE(Passes(verify(zone_points(), mz)));
}

// Six integer points with two distinct local minima (found with the exhaustive oracle):
//  A: outer (6, 5), (2, 6); inner (4, 4), (3, 4): centre (3.5, 3.5),
//     R² = 8.5, r² = 0.5, width 2.2084;
//  B: outer (2, 6), (6, 2); inner (6, 5), (4, 4): centre (29/6, 29/6), R² = 338/36,
//     r² = 50/36, width 1.8856 — the global minimum.
// A is a valid local certificate; claimed global it must be refuted (the crossing test
// fails here, so the enumeration finds B).
std::vector<Point2> two_minima_points() {
  return {{6, 5}, {4, 4}, {4, 2}, {3, 4}, {2, 6}, {6, 2}};
}

MinimumZoneCircle two_minima_result(bool global_minimum) {
  MinimumZoneCircle mz;
  if (global_minimum) {
    mz.center = {29.0 / 6, 29.0 / 6};
    mz.outer_radius = std::sqrt(338.0) / 6;
    mz.inner_radius = std::sqrt(50.0) / 6;
    mz.outer_contacts = {4, 5};
    mz.inner_contacts = {0, 1};
  } else {
    mz.center = {3.5, 3.5};
    mz.outer_radius = std::sqrt(8.5);
    mz.inner_radius = std::sqrt(0.5);
    mz.outer_contacts = {0, 4};
    mz.inner_contacts = {1, 3};
  }
  const double w = mz.outer_radius - mz.inner_radius;
  mz.ron = {w, w / 2, w / 2, w / 4};
  return mz;
}

TEST(CertificateMinimumZone, GlobalClaimOnAWiderLocalMinimumIsRefuted) {
  auto mz = two_minima_result(false);
  EXPECT_TRUE(Passes(verify(two_minima_points(), mz)));
  mz.certificate.optimality = Optimality::global;
  EXPECT_TRUE(Fails(verify(two_minima_points(), mz),
                    "global optimality claim is false: a narrower zone exists"));
  auto best = two_minima_result(true);
  EXPECT_TRUE(Passes(verify(two_minima_points(), best)));
  best.certificate.optimality = Optimality::global;
  EXPECT_TRUE(Passes(verify(two_minima_points(), best)));
}

TEST(CertificateMinimumZone, ReportedValuesWithinAFewUlpsPass) {
  auto mz = zone_result();
  mz.center = {std::nextafter(0.0, 1.0), -1e-15};  // 1e-15 < 4 ulp(10) = 7.1e-15
  mz.outer_radius = std::nextafter(10.0, 11.0);
  mz.inner_radius = std::nextafter(9.0, 8.0);
  mz.ron.ront = std::nextafter(1.0, 2.0);
  EXPECT_TRUE(Passes(verify(zone_points(), mz)));
}

TEST(CertificateMinimumZone, WrongContactFails) {
  auto mz = zone_result();
  // (−7, −6.5) instead of (0, −9): the bisectors meet at (0, −0.3306…), r² ≈ 87.05, and
  // (0, −9) is then at distance² ≈ 75.15 from the centre.
  mz.inner_contacts = {1, 5};
  EXPECT_TRUE(Fails(verify(zone_points(), mz), "point 3 lies inside the inner circle"));
  mz = zone_result();
  mz.outer_contacts = {0, 4};  // (6, 7.5) as an outer contact: r² ≥ R² about that centre
  EXPECT_TRUE(Fails(verify(zone_points(), mz), "r^2 >= R^2"));
}

TEST(CertificateMinimumZone, NonAlternatingContactsFail) {
  // Outer (10, 0), (6, 8) and inner (-9, 0), (0, -9): the bisectors y = x/2 and y = x meet
  // at the origin, R = 10, r = 9, every point in the annulus, but the angular order is
  // o (0°), o (53°), i (180°), i (270°): a 2+2 set that does not alternate.
  const std::vector<Point2> pts{{10, 0}, {6, 8}, {-9, 0}, {0, -9}, {-6, 7.5}, {7, -6.5}};
  MinimumZoneCircle mz;
  mz.center = {0, 0};
  mz.outer_radius = 10;
  mz.inner_radius = 9;
  mz.outer_contacts = {0, 1};
  mz.inner_contacts = {2, 3};
  mz.ron = {1.0, 0.5, 0.5, 0.3};
  EXPECT_TRUE(Fails(verify(pts, mz), "do not alternate"));
}

TEST(CertificateMinimumZone, ThreePlusOneContactsFail) {
  auto mz = zone_result();
  mz.outer_contacts = {0, 2, 4};
  mz.inner_contacts = {1};
  EXPECT_TRUE(Fails(verify(zone_points(), mz), "needs 2 outer and 2 inner contacts"));
}

TEST(CertificateMinimumZone, PointOutsideTheZoneFails) {
  auto pts = zone_points();
  pts.push_back({0, 10.000000001});
  EXPECT_TRUE(Fails(verify(pts, zone_result()), "point 8 lies outside the outer circle"));
  pts.back() = {0, 8.999999999};
  EXPECT_TRUE(Fails(verify(pts, zone_result()), "point 8 lies inside the inner circle"));
}

TEST(CertificateMinimumZone, CentreOffByOneNanometreFails) {
  auto mz = zone_result();
  mz.center.x = 1e-9;
  EXPECT_TRUE(Fails(verify(zone_points(), mz), "reported centre"));
}

TEST(CertificateMinimumZone, RadiusOffFails) {
  auto mz = zone_result();
  mz.outer_radius = 10 + 1e-13;  // 56 ulp of 10
  EXPECT_TRUE(Fails(verify(zone_points(), mz), "reported outer radius"));
  mz = zone_result();
  mz.inner_radius = 9 - 1e-13;
  EXPECT_TRUE(Fails(verify(zone_points(), mz), "reported inner radius"));
  mz = zone_result();
  mz.ron.ront = 1 + 1e-13;
  EXPECT_TRUE(Fails(verify(zone_points(), mz), "reported RONt"));
  mz = zone_result();
  mz.ron.ronp = 0.6;
  EXPECT_TRUE(Fails(verify(zone_points(), mz), "reported RONp"));
  mz = zone_result();
  mz.outer_radius = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(Fails(verify(zone_points(), mz), "not finite"));
}

TEST(CertificateMinimumZone, IndexOutOfRangeFails) {
  auto mz = zone_result();
  mz.inner_contacts = {1, 8};
  EXPECT_TRUE(Fails(verify(zone_points(), mz), "inner_contacts[1] = 8 is out of range"));
}

TEST(CertificateMinimumZone, DuplicateContactPointsFail) {
  auto pts = zone_points();
  pts.push_back({10, 0});  // index 8 repeats index 0
  auto mz = zone_result();
  mz.outer_contacts = {0, 8};
  EXPECT_TRUE(Fails(verify(pts, mz), "outer contacts 0 and 8 are the same point"));
}

TEST(CertificateMinimumZone, ParallelBisectorsFail) {
  // Outer (±10, 0) and inner (±9, 0): both bisectors are the y axis.
  const std::vector<Point2> pts{{10, 0}, {-10, 0}, {9, 0}, {-9, 0}, {0, 9.5}};
  MinimumZoneCircle mz;
  mz.outer_contacts = {0, 1};
  mz.inner_contacts = {2, 3};
  EXPECT_TRUE(Fails(verify(pts, mz), "parallel"));
}

TEST(CertificateMinimumZone, InnerOutsideOuterFails) {
  // Swapping the roles: "outer" (0, ±9), "inner" (±10, 0) gives r² > R².
  auto mz = zone_result();
  std::swap(mz.outer_contacts, mz.inner_contacts);
  EXPECT_TRUE(Fails(verify(zone_points(), mz), "r^2 >= R^2"));
}

TEST(CertificateMinimumZone, CoCircularContactsAreNotAZone) {
  // All on the circle of radius 5: any 2+2 set about the origin has r² = R².
  const std::vector<Point2> pts{{5, 0}, {0, 5}, {-5, 0}, {0, -5}, {3, 4}, {-4, -3}};
  MinimumZoneCircle mz;
  mz.center = {0, 0};
  mz.outer_radius = mz.inner_radius = 5;
  mz.outer_contacts = {0, 2};
  mz.inner_contacts = {1, 3};
  EXPECT_TRUE(Fails(verify(pts, mz), "r^2 >= R^2"));
}

TEST(CertificateMinimumZone, ZeroWidthPassesAndFailsOffTheCircle) {
  std::vector<Point2> pts{{5, 0}, {0, 5}, {-5, 0}, {0, -5}, {3, 4}, {-4, 3}};
  MinimumZoneCircle mz;
  mz.center = {0, 0};
  mz.outer_radius = mz.inner_radius = 5;
  mz.outer_contacts = {0, 1, 2};
  mz.inner_contacts = {2, 0, 1};
  mz.certificate.optimality = Optimality::global;
  EXPECT_TRUE(Passes(verify(pts, mz)));
  pts.push_back({3, 4.0000001});
  EXPECT_TRUE(Fails(verify(pts, mz), "point 6 is not on the circle"));
  mz.inner_contacts = {0, 1, 3};
  EXPECT_TRUE(Fails(verify(pts, mz), "same 3 points"));
}

TEST(CertificateMinimumZone, NonFiniteInputThrows) {
  auto pts = zone_points();
  pts[5].y = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(verify(pts, zone_result()), InvalidInput);
  pts[5].y = std::numeric_limits<double>::infinity();
  try {
    verify(pts, zone_result());
    ADD_FAILURE() << "no exception";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("point 5"), std::string::npos) << e.what();
  }
}

// ---- minimum circumscribed ------------------------------------------------------------------

TEST(CertificateMinimumCircumscribed, DiametralPairPasses) {
  const std::vector<Point2> pts{{-5, 0}, {5, 0}, {0, 3}, {1, -2}, {3, 3}};
  MinimumCircumscribedCircle mc;
  mc.center = {0, 0};
  mc.radius = 5;
  mc.contacts = {0, 1};
  const double ront = 5 - std::sqrt(5.0);  // nearest point (1, -2)
  mc.ron = {ront, 0.0, ront, 1.0};
  mc.certificate.optimality = Optimality::global;
  EXPECT_TRUE(Passes(verify(pts, mc)));
  mc.ron.ront = 5 - 3.0;  // as if (0, 3) were the nearest
  EXPECT_TRUE(Fails(verify(pts, mc), "reported RONt"));
}

TEST(CertificateMinimumCircumscribed, ThreeContactsAroundTheCentrePass) {
  const std::vector<Point2> pts{{0, 5}, {-4, -3}, {4, -3}, {1, 1}, {-2, 3}};
  MinimumCircumscribedCircle mc;
  mc.center = {0, 0};
  mc.radius = 5;
  mc.contacts = {0, 1, 2};
  const double ront = 5 - std::sqrt(2.0);
  mc.ron = {ront, 0.0, ront, 1.0};
  EXPECT_TRUE(Passes(verify(pts, mc)));
}

TEST(CertificateMinimumCircumscribed, CentreOutsideContactHullFails) {
  // All three on the circle of radius 5 about the origin, but the triangle lies above y = 3.
  const std::vector<Point2> pts{{-4, 3}, {4, 3}, {0, 5}, {0, 4}};
  MinimumCircumscribedCircle mc;
  mc.center = {0, 0};
  mc.radius = 5;
  mc.contacts = {0, 1, 2};
  EXPECT_TRUE(Fails(verify(pts, mc), "outside the triangle of contacts 0, 1, 2"));
}

TEST(CertificateMinimumCircumscribed, PointOutsideFails) {
  const std::vector<Point2> pts{{-5, 0}, {5, 0}, {0, 3}, {0, -5.0000001}};
  MinimumCircumscribedCircle mc;
  mc.center = {0, 0};
  mc.radius = 5;
  mc.contacts = {0, 1};
  EXPECT_TRUE(Fails(verify(pts, mc), "point 3 lies outside the circle"));
}

TEST(CertificateMinimumCircumscribed, MalformedContactsFail) {
  const std::vector<Point2> pts{{-5, 0}, {5, 0}, {0, 3}, {5, 0}};
  MinimumCircumscribedCircle mc;
  mc.center = {0, 0};
  mc.radius = 5;
  mc.contacts = {1};
  EXPECT_TRUE(Fails(verify(pts, mc), "needs 2 or 3 contacts; got 1"));
  mc.contacts = {0, 4};
  EXPECT_TRUE(Fails(verify(pts, mc), "contacts[1] = 4 is out of range"));
  mc.contacts = {1, 3};
  EXPECT_TRUE(Fails(verify(pts, mc), "contacts 1 and 3 are the same point"));
  mc.contacts = {0, 1};
  mc.center = {1e-9, 0};
  EXPECT_TRUE(Fails(verify(pts, mc), "reported centre"));
  mc.center = {0, 0};
  mc.radius = 5 + 1e-12;
  EXPECT_TRUE(Fails(verify(pts, mc), "reported radius"));
}

// ---- maximum inscribed ----------------------------------------------------------------------
// Contacts at radius 5 on angles 0°, 120°, 240° (exact: (5, 0), (−2.5, ±4.33…) are not exact
// in binary, so use (5, 0), (−4, 3), (−4, −3): the origin is strictly inside their
// triangle); the other points lie farther out.
std::vector<Point2> inscribed_points() {
  return {{5, 0}, {-4, 3}, {-4, -3}, {0, 6}, {0, -6}, {4.5, 4.5}, {4.5, -4.5}, {-6, 0}};
}

MaximumInscribedCircle inscribed_result() {
  MaximumInscribedCircle mi;
  mi.center = {0, 0};
  mi.radius = 5;
  mi.contacts = {0, 1, 2};
  const double ront = std::sqrt(40.5) - 5;  // farthest: (4.5, ±4.5)
  mi.ron = {ront, ront, 0.0, 0.5};
  return mi;
}

TEST(CertificateMaximumInscribed, HandMadeCirclePasses) {
  EXPECT_TRUE(Passes(verify(inscribed_points(), inscribed_result())));
}

TEST(CertificateMaximumInscribed, CircleContainingAPointFails) {
  auto pts = inscribed_points();
  pts.push_back({1, 1});
  EXPECT_TRUE(Fails(verify(pts, inscribed_result()), "point 8 lies strictly inside the circle"));
}

TEST(CertificateMaximumInscribed, CentreOnTheTriangleEdgeFails) {
  // (5, 0), (−5, 0), (0, 5): the centre is on the edge from (5, 0) to (−5, 0), and no other
  // point lies on the circle below it: moving the centre down enlarges the empty circle.
  const std::vector<Point2> pts{{5, 0}, {-5, 0}, {0, 5}, {0, -6}};
  MaximumInscribedCircle mi;
  mi.center = {0, 0};
  mi.radius = 5;
  mi.contacts = {0, 1, 2};
  EXPECT_TRUE(Fails(verify(pts, mi), "lies on the edge 0-1 of the contact triangle"));
}

TEST(CertificateMaximumInscribed, CentreOutsideTheTriangleFails) {
  const std::vector<Point2> pts{{-4, 3}, {4, 3}, {0, 5}, {0, -6}, {6, 0}, {-6, 0}};
  MaximumInscribedCircle mi;
  mi.center = {0, 0};
  mi.radius = 5;
  mi.contacts = {0, 1, 2};
  EXPECT_TRUE(Fails(verify(pts, mi), "outside the triangle of contacts 0, 1, 2"));
}

TEST(CertificateMaximumInscribed, RectangleCornersSurroundTheCentre) {
  // The corners (±3, ±4) surround the origin; every triple of them has the origin on its
  // diagonal edge, and the fourth corner is the witness beyond it.
  const std::vector<Point2> pts{{3, 4}, {-3, 4}, {-3, -4}, {3, -4}, {0, 6}, {0, -6}, {6, 0}, {-6, 0}};
  MaximumInscribedCircle mi;
  mi.center = {0, 0};
  mi.radius = 5;
  mi.contacts = {0, 1, 2};
  mi.ron = {1.0, 1.0, 0.0, 0.5};
  mi.certificate.optimality = Optimality::global;
  EXPECT_TRUE(Passes(verify(pts, mi)));
  auto three = pts;
  three.erase(three.begin() + 3);  // without (3, −4) nothing lies beyond the diagonal
  EXPECT_TRUE(Fails(verify(three, mi), "lies on the edge 2-0 of the contact triangle"));
}

TEST(CertificateMaximumInscribed, MalformedContactsFail) {
  auto mi = inscribed_result();
  mi.contacts = {0, 1};
  EXPECT_TRUE(Fails(verify(inscribed_points(), mi), "needs 3 contacts; got 2"));
  mi.contacts = {0, 1, 9};
  EXPECT_TRUE(Fails(verify(inscribed_points(), mi), "contacts[2] = 9 is out of range"));
  auto pts = inscribed_points();
  pts.push_back({5, 0});
  mi.contacts = {0, 1, 8};
  EXPECT_TRUE(Fails(verify(pts, mi), "contacts 0 and 8 are the same point"));
  mi = inscribed_result();
  mi.center.y = -1e-9;
  EXPECT_TRUE(Fails(verify(inscribed_points(), mi), "reported centre"));
  mi = inscribed_result();
  mi.radius = 5 - 1e-12;
  EXPECT_TRUE(Fails(verify(inscribed_points(), mi), "reported radius"));
  mi = inscribed_result();
  mi.ron.ronv = 0.01;
  EXPECT_TRUE(Fails(verify(inscribed_points(), mi), "reported RONv"));
}

TEST(CertificateMaximumInscribed, GlobalClaimRecheckedIndependently) {
  // A closed ring: contacts at radius 5, the rest of a 12-gon at radius 5.5; the origin's
  // circle is the largest empty one in the hull.
  std::vector<Point2> pts{{5, 0}, {-4, 3}, {-4, -3}};
  for (int k = 0; k < 12; ++k) {
    const double t = 2 * 3.141592653589793 * (k + 0.5) / 12;
    pts.push_back({5.5 * std::cos(t), 5.5 * std::sin(t)});
  }
  auto mi = inscribed_result();
  // Farthest point at radius 5.5 (up to rounding of cos/sin): recompute RONt from the data.
  double far = 0;
  for (const auto& p : pts) far = std::max(far, std::hypot(p.x, p.y));
  mi.ron = {far - 5, far - 5, 0.0, 0.3};
  mi.certificate.optimality = Optimality::global;
  EXPECT_TRUE(Passes(verify(pts, mi)));
}

TEST(CertificateMaximumInscribed, FalseGlobalClaimIsRefuted) {
  // Same ring, but one gap: drop the 12-gon points near 90°, opening a larger empty circle
  // centred near the gap... simplest refutation: a second, larger empty triangle far away.
  // Points: the small circle's contacts and, to the right, a wide empty region whose
  // circumcircle (centre (20, 0), radius 10) lies inside the hull.
  std::vector<Point2> pts{{5, 0}, {-4, 3}, {-4, -3}, {0, 6}, {0, -6}, {-6, 0}};
  pts.insert(pts.end(), {{30, 0}, {14, 8}, {14, -8}, {40, 10}, {40, -10}});
  MaximumInscribedCircle mi;
  mi.center = {0, 0};
  mi.radius = 5;
  mi.contacts = {0, 1, 2};
  double far = 0;
  for (const auto& p : pts) far = std::max(far, std::hypot(p.x, p.y));
  mi.ron = {far - 5, far - 5, 0.0, 1.0};
  mi.certificate.optimality = Optimality::local;
  EXPECT_TRUE(Passes(verify(pts, mi))) << "a valid local maximum";
  mi.certificate.optimality = Optimality::global;
  EXPECT_TRUE(Fails(verify(pts, mi), "global optimality claim is false"));
}

TEST(CertificateMaximumInscribed, PartialArcRefutesGlobal) {
  // Contacts (0, −9), (±1, −7): circumcentre (0, −7.75), radius 1.25, strictly inside their
  // triangle; plus the lower half of a circle of radius 10 about the origin. The circle is
  // a valid local maximum, but far larger empty circles are centred in the hull (near the
  // chord closing the arc), so a global claim must be refuted.
  std::vector<Point2> pts{{0, -9}, {-1, -7}, {1, -7}};
  for (int k = 0; k <= 18; ++k) {
    const double t = 3.141592653589793 * (1 + k / 18.0);
    pts.push_back({10 * std::cos(t), 10 * std::sin(t)});
  }
  MaximumInscribedCircle mi;
  mi.contacts = {0, 1, 2};
  mi.center = {0.0, -7.75};
  mi.radius = 1.25;
  double far = 0;
  for (const auto& p : pts) far = std::max(far, std::hypot(p.x, p.y + 7.75));
  mi.ron = {far - 1.25, far - 1.25, 0.0, 1.0};
  EXPECT_TRUE(Passes(verify(pts, mi)));
  mi.certificate.optimality = Optimality::global;
  EXPECT_TRUE(Fails(verify(pts, mi), "global optimality claim is false"));
}

// ---- sensitivity: every single-contact mutation of a real certificate is rejected ----------

TEST(CertificateSensitivity, EveryContactMutationOfARealResultIsRejected) {
  const std::vector<Point2> pts = vcmm::test::lobed_noisy_ring(360, 5);
  const MinimumZoneCircle mz = minimum_zone_circle(pts);
  const MaximumInscribedCircle mi = maximum_inscribed_circle(pts);
  const MinimumCircumscribedCircle mc = minimum_circumscribed_circle(pts);
  ASSERT_TRUE(Passes(verify(pts, mz)));
  ASSERT_TRUE(Passes(verify(pts, mi)));
  ASSERT_TRUE(Passes(verify(pts, mc)));
  auto is_contact = [](const std::vector<std::size_t>& v, std::size_t k) {
    return std::find(v.begin(), v.end(), k) != v.end();
  };
  int accepted = 0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    if (!is_contact(mz.outer_contacts, k) && !is_contact(mz.inner_contacts, k)) {
      auto m = mz;
      m.outer_contacts[0] = k;
      accepted += verify(pts, m).valid;
      m = mz;
      m.inner_contacts[1] = k;
      accepted += verify(pts, m).valid;
    }
    if (!is_contact(mi.contacts, k)) {
      auto m = mi;
      m.contacts[0] = k;
      accepted += verify(pts, m).valid;
    }
    if (!is_contact(mc.contacts, k)) {
      auto m = mc;
      m.contacts[0] = k;
      accepted += verify(pts, m).valid;
    }
  }
  EXPECT_EQ(accepted, 0);
  // Centres moved by 8 ulp of the largest coordinate (tolerance 4 ulp) are rejected.
  const double u = std::nextafter(85.5, 100.0) - 85.5;
  auto m1 = mz;
  m1.center.x += 8 * u;
  EXPECT_TRUE(Fails(verify(pts, m1), "reported centre"));
  auto m2 = mi;
  m2.center.y -= 8 * u;
  EXPECT_TRUE(Fails(verify(pts, m2), "reported centre"));
  auto m3 = mc;
  m3.radius += 16 * u;
  EXPECT_TRUE(Fails(verify(pts, m3), "reported radius"));
}

}  // namespace
}  // namespace vcmm::geometry
