// minimum_circumscribed_circle: hand cases, an exact brute force over all pairs and triples
// (its own rational code, n ≤ 10, hundreds of seeds), far-from-origin data, invariance
// under translation / rotation by 90° / permutation, duplicates, a lobed ring with a known
// answer, bad input. Every result is re-checked by the independent verify().
#include <gtest/gtest.h>

#include <CGAL/Exact_rational.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "support/test_profiles.h"
#include "vcmm/geometry/certificate.h"
#include "vcmm/geometry/minimum_circumscribed.h"

namespace {

using vcmm::geometry::InvalidInput;
using vcmm::geometry::minimum_circumscribed_circle;
using vcmm::geometry::MinimumCircumscribedCircle;
using vcmm::geometry::Optimality;
using vcmm::geometry::Point2;
using vcmm::geometry::verify;
using Q = CGAL::Exact_rational;

struct QCircle {
  Q cx, cy, r2;
};

Q sq(const Q& a) { return a * a; }

/// The exact circle of the reported contacts (test-side code, shares nothing with the
/// library): midpoint for 2, circumcentre for 3.
QCircle circle_of(const std::vector<Point2>& p, const std::vector<std::size_t>& c) {
  const Q ax(p[c[0]].x), ay(p[c[0]].y), bx(p[c[1]].x), by(p[c[1]].y);
  if (c.size() == 2) {
    const Q cx = (ax + bx) / 2, cy = (ay + by) / 2;
    return {cx, cy, sq(ax - cx) + sq(ay - cy)};
  }
  const Q dx(p[c[2]].x), dy(p[c[2]].y);
  // Solve 2(b − a)·x = |b|² − |a|², 2(d − a)·x = |d|² − |a|².
  const Q a11 = 2 * (bx - ax), a12 = 2 * (by - ay), a21 = 2 * (dx - ax), a22 = 2 * (dy - ay);
  const Q r1 = sq(bx) + sq(by) - sq(ax) - sq(ay), r2 = sq(dx) + sq(dy) - sq(ax) - sq(ay);
  const Q det = a11 * a22 - a12 * a21;
  const Q cx = (r1 * a22 - r2 * a12) / det, cy = (a11 * r2 - a21 * r1) / det;
  return {cx, cy, sq(ax - cx) + sq(ay - cy)};
}

bool encloses(const QCircle& c, const std::vector<Point2>& p) {
  for (const Point2& q : p)
    if (sq(Q(q.x) - c.cx) + sq(Q(q.y) - c.cy) > c.r2) return false;
  return true;
}

/// Brute force: the smallest enclosing circle among all diametral pairs and all circles
/// through non-collinear triples (the MC is one of them).
Q brute_force_r2(const std::vector<Point2>& p) {
  bool have = false;
  Q best;
  const std::size_t n = p.size();
  auto consider = [&](const QCircle& c) {
    if ((!have || c.r2 < best) && encloses(c, p)) {
      best = c.r2;
      have = true;
    }
  };
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      if (p[i] == p[j]) continue;
      consider(circle_of(p, {i, j}));
      for (std::size_t k = j + 1; k < n; ++k) {
        const Q o = (Q(p[j].x) - Q(p[i].x)) * (Q(p[k].y) - Q(p[i].y)) -
                    (Q(p[j].y) - Q(p[i].y)) * (Q(p[k].x) - Q(p[i].x));
        if (o == 0) continue;
        consider(circle_of(p, {i, j, k}));
      }
    }
  return best;
}

void expect_valid(const std::vector<Point2>& p, const MinimumCircumscribedCircle& mc) {
  const auto v = verify(p, mc);
  EXPECT_TRUE(v.valid) << v.reason;
  EXPECT_EQ(mc.certificate.optimality, Optimality::global);
  EXPECT_FALSE(mc.certificate.argument.empty());
}

TEST(MinimumCircumscribed, TwoDiametralPoints) {
  const std::vector<Point2> p{{0, 0}, {2, 0}};
  const auto mc = minimum_circumscribed_circle(p);
  EXPECT_EQ(mc.center.x, 1.0);
  EXPECT_EQ(mc.center.y, 0.0);
  EXPECT_EQ(mc.radius, 1.0);
  auto c = mc.contacts;
  std::sort(c.begin(), c.end());
  EXPECT_EQ(c, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(mc.ron.ront, 0.0);
  expect_valid(p, mc);
}

TEST(MinimumCircumscribed, ObtuseTriangleIsDiametral) {
  const std::vector<Point2> p{{0, 0}, {4, 0}, {1, 1}};
  const auto mc = minimum_circumscribed_circle(p);
  EXPECT_EQ(mc.center.x, 2.0);
  EXPECT_EQ(mc.center.y, 0.0);
  EXPECT_EQ(mc.radius, 2.0);
  auto c = mc.contacts;
  std::sort(c.begin(), c.end());
  EXPECT_EQ(c, (std::vector<std::size_t>{0, 1}));
  // RONt = R − min distance = 2 − |(1,1) − (2,0)| = 2 − √2.
  EXPECT_NEAR(mc.ron.ront, 2.0 - std::sqrt(2.0), 4e-16);
  EXPECT_EQ(mc.ron.ronp, 0.0);
  expect_valid(p, mc);
}

TEST(MinimumCircumscribed, AcuteTriangleIsCircumscribed) {
  // Circumcentre (2, 5/6), radius 13/6.
  const std::vector<Point2> p{{0, 0}, {4, 0}, {2, 3}};
  const auto mc = minimum_circumscribed_circle(p);
  EXPECT_NEAR(mc.center.x, 2.0, 1e-15);
  EXPECT_NEAR(mc.center.y, 5.0 / 6.0, 2e-16);
  EXPECT_NEAR(mc.radius, 13.0 / 6.0, 5e-16);
  EXPECT_EQ(mc.contacts.size(), 3u);
  expect_valid(p, mc);
}

TEST(MinimumCircumscribed, SquareGivesADiagonal) {
  const std::vector<Point2> p{{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
  const auto mc = minimum_circumscribed_circle(p);
  EXPECT_EQ(mc.center.x, 0.0);
  EXPECT_EQ(mc.center.y, 0.0);
  EXPECT_NEAR(mc.radius, std::sqrt(2.0), 3e-16);
  ASSERT_EQ(mc.contacts.size(), 2u);  // a diameter suffices
  EXPECT_EQ((mc.contacts[0] + mc.contacts[1]) % 2, 0u);  // opposite corners
  expect_valid(p, mc);
}

TEST(MinimumCircumscribed, ManyExactlyCoCircularPoints) {
  // The 12 integer points on the circle of radius 5 plus interior points: more than three
  // co-circular supports; the contacts must still surround the centre.
  std::vector<Point2> p{{7, -3}, {8, -1}, {5, -2}};
  for (auto [x, y] : std::vector<std::pair<int, int>>{
           {5, 0}, {4, 3}, {3, 4}, {0, 5}, {-3, 4}, {-4, 3}, {-5, 0}, {-4, -3},
           {-3, -4}, {0, -5}, {3, -4}, {4, -3}})
    p.push_back({static_cast<double>(x) + 7.0, static_cast<double>(y) - 3.0});
  const auto mc = minimum_circumscribed_circle(p);
  EXPECT_EQ(mc.center.x, 7.0);
  EXPECT_EQ(mc.center.y, -3.0);
  EXPECT_EQ(mc.radius, 5.0);
  expect_valid(p, mc);
}

TEST(MinimumCircumscribed, PointsOnACircle) {
  std::vector<Point2> p;
  for (int k = 0; k < 100; ++k) {
    const double t = 2.0 * std::numbers::pi * k / 100.0;
    p.push_back({3.0 + 10.0 * std::cos(t), 4.0 + 10.0 * std::sin(t)});
  }
  const auto mc = minimum_circumscribed_circle(p);
  EXPECT_NEAR(mc.center.x, 3.0, 1e-13);
  EXPECT_NEAR(mc.center.y, 4.0, 1e-13);
  EXPECT_NEAR(mc.radius, 10.0, 1e-13);
  EXPECT_LT(mc.ron.ront, 1e-13);
  expect_valid(p, mc);
}

TEST(MinimumCircumscribed, DuplicatesReportTheLowestIndex) {
  // A closed scan repeats its first point; other points are repeated too.
  const std::vector<Point2> p{{1, 0}, {0, 1}, {-1, 0}, {0, -1}, {0.5, 0.5},
                              {1, 0}, {-1, 0}, {0, 1}, {1, 0}};
  const auto mc = minimum_circumscribed_circle(p);
  EXPECT_EQ(mc.radius, 1.0);
  for (std::size_t c : mc.contacts) {
    for (std::size_t i = 0; i < c; ++i) EXPECT_FALSE(p[i] == p[c]) << "contact " << c;
  }
  expect_valid(p, mc);
  const std::vector<Point2> two{{3, 3}, {3, 3}, {5, 3}, {5, 3}, {3, 3}};
  const auto m2 = minimum_circumscribed_circle(two);
  auto c = m2.contacts;
  std::sort(c.begin(), c.end());
  EXPECT_EQ(c, (std::vector<std::size_t>{0, 2}));
  EXPECT_EQ(m2.radius, 1.0);
  expect_valid(two, m2);
}

TEST(MinimumCircumscribed, CollinearPointsAreAccepted) {
  const std::vector<Point2> p{{0, 0}, {1, 1}, {3, 3}, {2, 2}};
  const auto mc = minimum_circumscribed_circle(p);
  EXPECT_EQ(mc.center.x, 1.5);
  EXPECT_EQ(mc.center.y, 1.5);
  EXPECT_NEAR(mc.radius, 1.5 * std::sqrt(2.0), 1e-15);
  expect_valid(p, mc);
}

TEST(MinimumCircumscribed, MatchesExactBruteForceOnRandomClouds) {
  for (std::uint64_t seed = 1; seed <= 400; ++seed) {
    const std::size_t n = 2 + seed % 9;  // 2 … 10
    std::vector<Point2> p = vcmm::test::random_points(n, seed, seed % 3 == 0 ? 1e-3 : 10.0);
    if (seed % 5 == 0) p.push_back(p[0]);  // a duplicate
    const auto mc = minimum_circumscribed_circle(p);
    const QCircle got = circle_of(p, mc.contacts);
    EXPECT_TRUE(got.r2 == brute_force_r2(p)) << "seed " << seed;
    EXPECT_TRUE(encloses(got, p)) << "seed " << seed;
    const auto v = verify(p, mc);
    EXPECT_TRUE(v.valid) << "seed " << seed << ": " << v.reason;
  }
}

TEST(MinimumCircumscribed, BruteForceOnNearlyCoCircularAndGridClouds) {
  // Hard regimes: points on a circle (near-degenerate in-circle decisions) and on a small
  // integer grid (exact co-circularity, collinear triples, ties).
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    std::uint64_t s = seed * 7919;
    const std::size_t n = 3 + seed % 8;
    std::vector<Point2> p;
    for (std::size_t i = 0; i < n; ++i) {
      if (seed % 2 == 0) {
        const double t = 2.0 * std::numbers::pi * vcmm::test::uniform01(s);
        p.push_back({1e3 + 2.0 * std::cos(t), -5.0 + 2.0 * std::sin(t)});
      } else {
        p.push_back({std::floor(5.0 * vcmm::test::uniform01(s)),
                     std::floor(5.0 * vcmm::test::uniform01(s))});
      }
    }
    if (std::all_of(p.begin(), p.end(), [&](const Point2& q) { return q == p[0]; })) continue;
    const auto mc = minimum_circumscribed_circle(p);
    EXPECT_TRUE(circle_of(p, mc.contacts).r2 == brute_force_r2(p)) << "seed " << seed;
    const auto v = verify(p, mc);
    EXPECT_TRUE(v.valid) << "seed " << seed << ": " << v.reason;
  }
}

TEST(MinimumCircumscribed, LobedRingHasTheMaximumRadius) {
  // r(θ) = R + a·cos 3θ with θ = 0 sampled: the three peaks (equilateral) are the contacts
  // and the MC circle is centred at the origin with radius R + a.
  vcmm::test::RingSpec spec;
  spec.radius = 10.0;
  spec.n = 3600;
  spec.harmonics = {{3, 0.01, 0.0}};
  const auto p = vcmm::test::ring_profile(spec);
  const auto mc = minimum_circumscribed_circle(p);
  EXPECT_NEAR(mc.radius, 10.01, 1e-13);
  EXPECT_NEAR(mc.center.x, 0.0, 1e-13);
  EXPECT_NEAR(mc.center.y, 0.0, 1e-13);
  EXPECT_EQ(mc.contacts.size(), 3u);
  EXPECT_NEAR(mc.ron.ront, 0.02, 1e-12);
  expect_valid(p, mc);
}

TEST(MinimumCircumscribed, NoisyRingsAtAllSizes) {
  for (std::size_t n : {16u, 360u, 3600u, 36000u}) {
    const auto p = vcmm::test::lobed_noisy_ring(n, 7);
    const auto mc = minimum_circumscribed_circle(p);
    // RONt against a direct (floating) evaluation.
    double rho_min = std::numeric_limits<double>::infinity();
    for (const Point2& q : p) rho_min = std::min(rho_min, std::hypot(q.x - mc.center.x, q.y - mc.center.y));
    EXPECT_NEAR(mc.ron.ront, mc.radius - rho_min, 1e-13) << "n = " << n;
    expect_valid(p, mc);
  }
}

TEST(MinimumCircumscribed, FarFromOrigin) {
  const auto near = vcmm::test::lobed_noisy_ring(3600, 3);
  const auto far = vcmm::test::lobed_noisy_ring(3600, 3, 5e-5, {1.0e6, -2.5e6});
  const auto a = minimum_circumscribed_circle(near);
  const auto b = minimum_circumscribed_circle(far);
  // The far profile is the near one shifted and rounded (ulp 4.7e-10 at 2.5e6): the radius
  // agrees to a few of those ulps, RONt likewise.
  EXPECT_NEAR(b.radius, a.radius, 2e-9);
  EXPECT_NEAR(b.ron.ront, a.ron.ront, 2e-9);
  expect_valid(far, b);
}

TEST(MinimumCircumscribed, InvariantUnderTranslationRotationAndPermutation) {
  // Coordinates on a 2⁻³⁰ grid, so that translating by 1024 is exact.
  auto p = vcmm::test::lobed_noisy_ring(360, 11, 5e-5, {0.25, -0.5});
  for (auto& x : p) x = {std::ldexp(std::round(std::ldexp(x.x, 30)), -30),
                         std::ldexp(std::round(std::ldexp(x.y, 30)), -30)};
  const auto ref = minimum_circumscribed_circle(p);
  const QCircle qref = circle_of(p, ref.contacts);
  // Translation by a power of two: exact in doubles for these magnitudes.
  std::vector<Point2> t(p), r(p), s(p);
  for (auto& q : t) q = {q.x + 1024.0, q.y - 512.0};
  for (auto& q : r) q = {-q.y, q.x};  // rotation by 90°: exact
  std::uint64_t st = 99;
  for (std::size_t i = s.size(); i > 1; --i)
    std::swap(s[i - 1], s[static_cast<std::size_t>(vcmm::test::uniform01(st) * static_cast<double>(i))]);
  const auto mt = minimum_circumscribed_circle(t);
  const auto mr = minimum_circumscribed_circle(r);
  const auto ms = minimum_circumscribed_circle(s);
  EXPECT_TRUE(circle_of(t, mt.contacts).r2 == qref.r2);
  EXPECT_TRUE(circle_of(r, mr.contacts).r2 == qref.r2);
  EXPECT_TRUE(circle_of(s, ms.contacts).r2 == qref.r2);
  EXPECT_EQ(mr.center.x, -ref.center.y);
  EXPECT_EQ(mr.center.y, ref.center.x);
  EXPECT_EQ(ms.center.x, ref.center.x);
  EXPECT_EQ(ms.center.y, ref.center.y);
  EXPECT_EQ(ms.radius, ref.radius);
  EXPECT_NEAR(mt.center.x - 1024.0, ref.center.x, 1e-12);
  expect_valid(t, mt);
  expect_valid(r, mr);
  expect_valid(s, ms);
}

TEST(MinimumCircumscribed, ExtremeMagnitudesScaleExactly) {
  // Scaling by 2^±600 is exact, so is the answer; the floating filter is off at these
  // magnitudes (squares leave the double range) and every decision is exact.
  const auto p = vcmm::test::lobed_noisy_ring(360, 21, 5e-5, {3.0, -1.0});
  const auto ref = minimum_circumscribed_circle(p);
  for (const int e : {600, -600}) {
    std::vector<Point2> q(p);
    for (auto& x : q) x = {std::ldexp(x.x, e), std::ldexp(x.y, e)};
    const auto mc = minimum_circumscribed_circle(q);
    EXPECT_EQ(mc.radius, std::ldexp(ref.radius, e)) << "2^" << e;
    EXPECT_EQ(mc.center.x, std::ldexp(ref.center.x, e)) << "2^" << e;
    EXPECT_EQ(mc.center.y, std::ldexp(ref.center.y, e)) << "2^" << e;
    auto a = mc.contacts, b = ref.contacts;
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    EXPECT_EQ(a, b) << "2^" << e;
    // Exact containment by the test's own rationals, and the independent check.
    EXPECT_TRUE(encloses(circle_of(q, mc.contacts), q)) << "2^" << e;
    EXPECT_TRUE(verify(q, mc).valid) << "2^" << e << ": " << verify(q, mc).reason;
  }
}

TEST(MinimumCircumscribed, RejectsBadInput) {
  auto message = [](const std::vector<Point2>& p) -> std::string {
    try {
      (void)minimum_circumscribed_circle(p);
    } catch (const InvalidInput& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(message({}).find("minimum_circumscribed_circle: needs at least 2 points"),
            std::string::npos);
  EXPECT_NE(message({{1, 1}}).find("needs at least 2 points"), std::string::npos);
  EXPECT_NE(message({{1, 1}, {1, 1}, {1, 1}}).find("identical"), std::string::npos);
  EXPECT_NE(message({{0, 0}, {std::numeric_limits<double>::quiet_NaN(), 1}}).find("point 1"),
            std::string::npos);
  EXPECT_NE(message({{0, 0}, {1, std::numeric_limits<double>::infinity()}}).find("non-finite"),
            std::string::npos);
}

}  // namespace
