// tests/geometry/certificate_filter_test.cpp — the floating-point filter of verify()
// (geometry/src/internal/verify_distance.h) and its fast MI global test
// (internal/verify_inscribed_cover.h): the filter never contradicts exact arithmetic, it
// defers exact ties and near-ties of an ulp, and verify() answers exactly the same — valid or
// not, with the same reason — with the filter on and with it forced off (every decision by
// the exact path), on noisy, perfect, exactly co-circular and ulp-perturbed profiles.
#include <gtest/gtest.h>

#include <CGAL/Exact_rational.h>
#include <CGAL/Interval_nt.h>

#include <cmath>
#include <utility>
#include <cstdint>
#include <string>
#include <vector>

#include "../../geometry/src/internal/verify_distance.h"
#include "../../geometry/src/internal/verify_inscribed_cover.h"
#include "support/test_profiles.h"
#include "vcmm/geometry/certificate.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/minimum_circumscribed.h"
#include "vcmm/geometry/minimum_zone.h"

namespace vcmm::geometry {
namespace {

using Q = CGAL::Exact_rational;
namespace in = internal;

/// Filter switched off for the lifetime of the guard.
struct ExactOnly {
  ExactOnly() { in::set_verify_filter_enabled(false); }
  ~ExactOnly() { in::set_verify_filter_enabled(true); }
  ExactOnly(const ExactOnly&) = delete;
  ExactOnly& operator=(const ExactOnly&) = delete;
};

template <class Circle>
Verification verify_exact_only(const std::vector<Point2>& pts, const Circle& c) {
  const ExactOnly guard;
  return verify(pts, c);
}

/// verify() with and without the filter: same verdict, same reason.
template <class Circle>
::testing::AssertionResult SameWithAndWithoutFilter(const std::vector<Point2>& pts,
                                                    const Circle& c, bool expect_valid) {
  const Verification filtered = verify(pts, c);
  const Verification exact = verify_exact_only(pts, c);
  if (filtered.valid != exact.valid || filtered.reason != exact.reason)
    return ::testing::AssertionFailure()
           << "filtered: " << filtered.valid << " '" << filtered.reason << "'; exact: "
           << exact.valid << " '" << exact.reason << "'";
  if (filtered.valid != expect_valid)
    return ::testing::AssertionFailure() << "both " << (filtered.valid ? "valid" : "invalid")
                                         << ": " << filtered.reason;
  return ::testing::AssertionSuccess();
}

Q square(const Q& v) { return v * v; }

in::ApproxCentre approx_of(const Q& x, const Q& y) {
  return in::approx_centre(CGAL::to_interval(x), CGAL::to_interval(y));
}

int exact_sign(const Q& v) { return static_cast<int>(CGAL::sign(v)); }

// ---- the filter itself ------------------------------------------------------------------------

TEST(VerifyFilter, NeverContradictsTheExactSignAndDefersNearTies) {
  // Centres that are not doubles (thirds, sevenths: the enclosure has width 1 ulp), points on
  // or within a few ulps of a circle about them, far from the origin (NIST-like offsets).
  std::uint64_t state = 20261126;
  int decided = 0, deferred = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const double off = trial % 2 ? 600.0 : 1e5;
    const Q cx = Q(off) + Q(1) / Q(3 + trial % 5), cy = Q(off / 2) + Q(2) / Q(7);
    const in::ApproxCentre c = approx_of(cx, cy);
    const double radius = 85.5;
    const double t = 6.283185307179586 * test::uniform01(state);
    const double t2 = 6.283185307179586 * test::uniform01(state);
    Point2 p{CGAL::to_double(cx) + radius * std::cos(t), CGAL::to_double(cy) + radius * std::sin(t)};
    Point2 q{CGAL::to_double(cx) + radius * std::cos(t2), CGAL::to_double(cy) + radius * std::sin(t2)};
    // Nudge p by 0..4 ulps (trial % 5), or put it 1 µm off (every 7th trial).
    for (int k = 0; k < trial % 5; ++k) p.x = std::nextafter(p.x, 1e300);
    if (trial % 7 == 0) p.y += 1e-3;
    const Q dp = square(Q(p.x) - cx) + square(Q(p.y) - cy);
    const Q dq = square(Q(q.x) - cx) + square(Q(q.y) - cy);
    const int s = in::certain_sign(in::distance2(p, c), in::distance2(q, c));
    if (s != 0) {
      EXPECT_EQ(s, exact_sign(dp - dq)) << "trial " << trial;
      ++decided;
    } else {
      ++deferred;
    }
    const Q cross = (Q(p.x) - cx) * (Q(q.y) - cy) - (Q(p.y) - cy) * (Q(q.x) - cx);
    const int o = in::certain_orientation(c, p, q);
    if (o != 0) {
      EXPECT_EQ(o, exact_sign(cross)) << "trial " << trial;
    }
  }
  EXPECT_GT(decided, 40) << "the 1 mm offsets must be decided in floating point";
  EXPECT_GT(deferred, 40) << "ulp-level differences must go to the exact path";
}

TEST(VerifyFilter, ExactTiesAreNeverDecided) {
  // p and its mirror image through the exact centre (a dyadic rational) are exactly equally
  // far from it.
  const Q cx = Q(600) + Q(1) / Q(1024), cy = Q(500) - Q(3) / Q(4096);
  const in::ApproxCentre c = approx_of(cx, cy);
  for (const Point2 p : {Point2{685.5, 500.25}, Point2{600.125, 414.5}, Point2{540.0, 561.0}}) {
    const Point2 mirror{CGAL::to_double(Q(2) * cx - Q(p.x)), CGAL::to_double(Q(2) * cy - Q(p.y))};
    ASSERT_EQ(Q(2) * cx - Q(p.x), Q(mirror.x)) << "the mirror must be exact";
    EXPECT_EQ(in::certain_sign(in::distance2(p, c), in::distance2(mirror, c)), 0);
    EXPECT_EQ(in::certain_orientation(c, p, mirror), 0);  // collinear through c
  }
}

TEST(VerifyFilter, SwitchedOffDecidesNothing) {
  const ExactOnly guard;
  const in::ApproxCentre c = approx_of(Q(0), Q(0));
  EXPECT_EQ(in::certain_sign(in::distance2({10, 0}, c), in::distance2({1, 0}, c)), 0);
  EXPECT_EQ(in::certain_orientation(c, {1, 0}, {0, 1}), 0);
}

// ---- verify() with and without the filter -------------------------------------------------

std::vector<std::vector<Point2>> profiles() {
  test::RingSpec perfect;
  perfect.center = {600.0, 500.0};
  perfect.n = 720;
  return {test::lobed_noisy_ring(3600, 20261122, 5e-5),
          test::lobed_noisy_ring(360, 7, 1e-5, {498.0, 305.25}),
          test::ring_profile(perfect),
          test::symmetric_polygon(360),
          test::lattice_circle(360)};
}

TEST(VerifyFilter, FittedCertificatesGiveTheSameAnswerAsTheExactPath) {
  for (const auto& pts : profiles()) {
    SCOPED_TRACE(std::to_string(pts.size()) + " points");
    EXPECT_TRUE(SameWithAndWithoutFilter(pts, minimum_zone_circle(pts), true));
    EXPECT_TRUE(SameWithAndWithoutFilter(pts, maximum_inscribed_circle(pts), true));
    EXPECT_TRUE(SameWithAndWithoutFilter(pts, minimum_circumscribed_circle(pts), true));
  }
}

TEST(VerifyFilter, OneUlpOutsideTheCircumscribedCircleIsCaughtByTheExactPath) {
  // Every point of the lattice circle lies exactly on the MC circle: the filter can decide
  // none of them. Moving one point 1 ulp outward (x grows at angle ~0) must fail; 1 ulp
  // inward must pass; both exactly as the exact path says.
  std::vector<Point2> pts = test::lattice_circle(360);
  const MinimumCircumscribedCircle mc = minimum_circumscribed_circle(pts);
  ASSERT_TRUE(verify(pts, mc));
  std::size_t east = 0;
  for (std::size_t k = 0; k < pts.size(); ++k)
    if (pts[k].x > pts[east].x) east = k;
  bool is_contact = false;
  for (std::size_t k : mc.contacts) is_contact = is_contact || k == east;
  ASSERT_FALSE(is_contact) << "pick a point that is not a contact";
  std::vector<Point2> out = pts, in_ = pts;
  out[east].x = std::nextafter(out[east].x, 1e300);
  in_[east].x = std::nextafter(in_[east].x, -1e300);
  EXPECT_TRUE(SameWithAndWithoutFilter(out, mc, false));
  EXPECT_FALSE(verify(out, mc).reason.find("point " + std::to_string(east) + " lies outside") ==
               std::string::npos)
      << verify(out, mc).reason;
  // One ulp inward: RONt changes by far less than the tolerance of the reported value.
  EXPECT_TRUE(SameWithAndWithoutFilter(in_, mc, true));
}

TEST(VerifyFilter, OneUlpInsideTheInscribedCircleIsCaughtByTheExactPath) {
  std::vector<Point2> pts = test::lattice_circle(360);
  const MaximumInscribedCircle mi = maximum_inscribed_circle(pts);
  ASSERT_TRUE(verify(pts, mi));
  std::size_t east = 0;
  for (std::size_t k = 0; k < pts.size(); ++k)
    if (pts[k].x > pts[east].x) east = k;
  std::vector<Point2> nudged = pts;
  nudged[east].x = std::nextafter(nudged[east].x, -1e300);
  EXPECT_TRUE(SameWithAndWithoutFilter(nudged, mi, false));
  EXPECT_NE(verify(nudged, mi).reason.find("lies strictly inside"), std::string::npos);
}

TEST(VerifyFilter, OneUlpOutsideTheMinimumZoneIsCaughtByTheExactPath) {
  // A zone certificate on the noisy ring, then one extra point: an outer contact moved 1 ulp
  // away from the centre, or an inner contact moved 1 ulp towards it (along x). Both differ
  // from the zone's radii by far less than the filter's error bound.
  std::vector<Point2> pts = test::lobed_noisy_ring(3600, 20261122, 5e-5);
  const MinimumZoneCircle mz = minimum_zone_circle(pts);
  ASSERT_TRUE(verify(pts, mz));
  const Point2 o = pts[mz.outer_contacts[0]];
  const Point2 i = pts[mz.inner_contacts[0]];
  const double dx = o.x - mz.center.x, ix = i.x - mz.center.x;
  std::vector<Point2> out = pts, in_ = pts;
  out.push_back({std::nextafter(o.x, dx > 0 ? 1e300 : -1e300), o.y});
  in_.push_back({std::nextafter(i.x, ix > 0 ? -1e300 : 1e300), i.y});
  EXPECT_TRUE(SameWithAndWithoutFilter(out, mz, false));
  EXPECT_NE(verify(out, mz).reason.find("point 3600 lies outside the outer circle"),
            std::string::npos);
  EXPECT_TRUE(SameWithAndWithoutFilter(in_, mz, false));
  EXPECT_NE(verify(in_, mz).reason.find("point 3600 lies inside the inner circle"),
            std::string::npos);
}

// ---- the fast MI global test ----------------------------------------------------------------

in::InscribedCoverInput cover_input(const MaximumInscribedCircle& mi,
                                    const std::vector<Point2>& pts, const Q& cx, const Q& cy) {
  const Point2 a = pts[mi.contacts[0]], b = pts[mi.contacts[1]], d = pts[mi.contacts[2]];
  const Q r2 = square(Q(a.x) - cx) + square(Q(a.y) - cy);
  Q far2(0);
  for (const Point2& p : pts) {
    const Q d2 = square(Q(p.x) - cx) + square(Q(p.y) - cy);
    if (d2 > far2) far2 = d2;
  }
  Q g2(-1);
  const Point2 t[3] = {a, b, d};
  for (int k = 0; k < 3; ++k) {
    const Point2 s = t[k], e = t[(k + 1) % 3];
    const Q ex = Q(e.x) - Q(s.x), ey = Q(e.y) - Q(s.y);
    const Q cr = ex * (cy - Q(s.y)) - ey * (cx - Q(s.x));
    const Q g = cr * cr / (ex * ex + ey * ey);
    if (g2 < Q(0) || g < g2) g2 = g;
  }
  return {CGAL::to_interval(r2), CGAL::to_interval(far2), CGAL::to_interval(far2 - r2),
          CGAL::to_interval(g2)};
}

TEST(VerifyFilter, FastInscribedTestProvesANoisyRingAndRefusesAFalseClaim) {
  // The noisy ring: the exact circumcentre of the contacts, then the O(n) test alone proves
  // the global claim (in input order and shuffled).
  std::vector<Point2> pts = test::lobed_noisy_ring(3600, 20261122, 5e-5);
  const MaximumInscribedCircle mi = maximum_inscribed_circle(pts);
  const Point2 a = pts[mi.contacts[0]], b = pts[mi.contacts[1]], d = pts[mi.contacts[2]];
  // Circumcentre, exactly (Cramer).
  const Q ax(a.x), ay(a.y), bx(b.x), by(b.y), dx(d.x), dy(d.y);
  const Q ex = bx - ax, ey = by - ay, fx = dx - ax, fy = dy - ay;
  const Q det = ex * fy - ey * fx;
  const Q g = (bx * bx + by * by - ax * ax - ay * ay) / Q(2);
  const Q h = (dx * dx + dy * dy - ax * ax - ay * ay) / Q(2);
  const Q cx = (g * fy - ey * h) / det, cy = (ex * h - fx * g) / det;
  const in::InscribedCoverInput input = cover_input(mi, pts, cx, cy);
  EXPECT_TRUE(in::disks_cover_inscribed(pts, approx_of(cx, cy), input));
  std::vector<Point2> shuffled = pts;
  std::uint64_t state = 5;
  for (std::size_t k = shuffled.size() - 1; k > 0; --k)
    std::swap(shuffled[k], shuffled[static_cast<std::size_t>(test::uniform01(state) * static_cast<double>(k + 1))]);
  EXPECT_TRUE(in::disks_cover_inscribed(shuffled, approx_of(cx, cy), input));
  {
    const ExactOnly guard;
    EXPECT_FALSE(in::disks_cover_inscribed(pts, approx_of(cx, cy), input));
  }
  // Sound: it never accepts a false claim. The set of
  // CertificateMaximumInscribed.FalseGlobalClaimIsRefuted: a larger empty circle centred at
  // (20, 0) lies in the hull.
  const std::vector<Point2> bad{{5, 0}, {-4, 3}, {-4, -3}, {0, 6}, {0, -6}, {-6, 0},
                                {30, 0}, {14, 8}, {14, -8}, {40, 10}, {40, -10}};
  MaximumInscribedCircle small;
  small.contacts = {0, 1, 2};
  EXPECT_FALSE(in::disks_cover_inscribed(bad, approx_of(Q(0), Q(0)),
                                         cover_input(small, bad, Q(0), Q(0))));
}

}  // namespace
}  // namespace vcmm::geometry
