// maximum_inscribed_circle: hand cases (square with and without an inner point, equilateral
// triangle, lobed ring), UndefinedResult (partial arc, obtuse triangle, sparse clouds), an
// exact brute force of its own (all triples' circumcircles: surrounded, empty, and the
// hull-boundary maximum) on small sets, far-from-origin data, invariance under
// permutation / rotation by 90°, duplicates, bad input. Every defined result is re-checked
// by the independent verify().
#include <gtest/gtest.h>

#include <CGAL/Exact_rational.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "support/test_profiles.h"
#include "vcmm/geometry/certificate.h"
#include "vcmm/geometry/maximum_inscribed.h"

namespace {

using vcmm::geometry::InvalidInput;
using vcmm::geometry::maximum_inscribed_circle;
using vcmm::geometry::MaximumInscribedCircle;
using vcmm::geometry::Optimality;
using vcmm::geometry::Point2;
using vcmm::geometry::UndefinedResult;
using vcmm::geometry::verify;
using Q = CGAL::Exact_rational;

Q sq(const Q& a) { return a * a; }

struct QPt {
  Q x, y;
};
QPt q(Point2 p) { return {Q(p.x), Q(p.y)}; }
Q d2(const QPt& a, const QPt& b) { return sq(a.x - b.x) + sq(a.y - b.y); }
Q dot(const QPt& o, const QPt& a, const QPt& b) {
  return (a.x - o.x) * (b.x - o.x) + (a.y - o.y) * (b.y - o.y);
}
int orient(const QPt& a, const QPt& b, const QPt& c) {
  const Q o = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  return o > 0 ? 1 : (o < 0 ? -1 : 0);
}

struct QCircle {
  QPt c;
  Q r2;
};

std::optional<QCircle> circumcircle(const QPt& a, const QPt& b, const QPt& d) {
  const Q a11 = 2 * (b.x - a.x), a12 = 2 * (b.y - a.y), a21 = 2 * (d.x - a.x),
          a22 = 2 * (d.y - a.y);
  const Q det = a11 * a22 - a12 * a21;
  if (det == 0) return std::nullopt;
  const Q r1 = sq(b.x) + sq(b.y) - sq(a.x) - sq(a.y), r2 = sq(d.x) + sq(d.y) - sq(a.x) - sq(a.y);
  const QPt c{(r1 * a22 - r2 * a12) / det, (a11 * r2 - a21 * r1) / det};
  return QCircle{c, d2(a, c)};
}

QCircle circle_of(const std::vector<Point2>& p, const MaximumInscribedCircle& mi) {
  return *circumcircle(q(p[mi.contacts[0]]), q(p[mi.contacts[1]]), q(p[mi.contacts[2]]));
}

/// Convex hull (ccw, no collinear vertices) by gift wrapping on exact orientations.
std::vector<QPt> hull_of(const std::vector<QPt>& p) {
  std::size_t start = 0;
  for (std::size_t i = 1; i < p.size(); ++i)
    if (p[i].x < p[start].x || (p[i].x == p[start].x && p[i].y < p[start].y)) start = i;
  std::vector<QPt> h;
  std::size_t cur = start;
  do {
    h.push_back(p[cur]);
    std::size_t nxt = cur == 0 ? 1 : 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (i == cur) continue;
      const int o = orient(p[cur], p[nxt], p[i]);
      if (o < 0 || (o == 0 && d2(p[cur], p[i]) > d2(p[cur], p[nxt]))) nxt = i;
    }
    cur = nxt;
  } while (cur != start && h.size() <= p.size());
  return h;
}

/// Brute force (test-side, exact): M = the largest r² among empty circles through ≥ 3
/// points whose centre is strictly inside the hull of their co-circular points; B = the
/// largest r² on the hull boundary (at bisector crossings of all pairs). The MI is defined
/// iff M exists and M ≥ B. A floating screen (1e-6 relative, far above rounding) skips
/// triples whose circle clearly contains a point.
struct Brute {
  bool defined = false;
  Q r2;
  QPt c;
};

Brute brute_force(const std::vector<Point2>& in) {
  std::vector<Point2> d(in);
  std::sort(d.begin(), d.end(), [](Point2 a, Point2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  d.erase(std::unique(d.begin(), d.end()), d.end());
  std::vector<QPt> p;
  for (Point2 x : d) p.push_back(q(x));
  const std::size_t n = p.size();
  Brute best;
  bool have = false;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      for (std::size_t k = j + 1; k < n; ++k) {
        // Floating screen.
        {
          const double ax = d[i].x, ay = d[i].y, bx = d[j].x - ax, by = d[j].y - ay,
                       cx = d[k].x - ax, cy = d[k].y - ay;
          const double den = 2 * (bx * cy - by * cx);
          if (den == 0) {
            // possibly collinear: decide exactly below
          } else {
            const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
            const double ox = ax + (cy * b2 - by * c2) / den, oy = ay + (bx * c2 - cx * b2) / den;
            const double r2 = (ox - ax) * (ox - ax) + (oy - ay) * (oy - ay);
            bool inside = false;
            for (const Point2& s : d) {
              const double e2 = (s.x - ox) * (s.x - ox) + (s.y - oy) * (s.y - oy);
              if (e2 < r2 * (1 - 1e-6)) {
                inside = true;
                break;
              }
            }
            if (inside) continue;
          }
        }
        const auto cc = circumcircle(p[i], p[j], p[k]);
        if (!cc) continue;
        std::vector<QPt> on;
        bool empty = true;
        for (const QPt& s : p) {
          const Q e = d2(s, cc->c);
          if (e < cc->r2) {
            empty = false;
            break;
          }
          if (e == cc->r2) on.push_back(s);
        }
        if (!empty) continue;
        bool surrounded = false;
        for (std::size_t a = 0; a < on.size() && !surrounded; ++a)
          for (std::size_t b = 0; b < on.size() && !surrounded; ++b)
            for (std::size_t e = 0; e < on.size() && !surrounded; ++e) {
              if (a == b || b == e || a == e) continue;
              const Q da = dot(on[a], on[b], on[e]), db = dot(on[b], on[a], on[e]),
                      de = dot(on[e], on[a], on[b]);
              if (da > 0 && db > 0 && de > 0) surrounded = true;
              if (db == 0) {  // right angle at b: hypotenuse a-e is a diameter
                const int ob = orient(on[a], on[e], on[b]);
                for (const QPt& f : on)
                  if (orient(on[a], on[e], f) == -ob) surrounded = true;
              }
            }
        if (!surrounded) continue;
        if (!have || cc->r2 > best.r2) {
          best.r2 = cc->r2;
          best.c = cc->c;
          have = true;
        }
      }
  if (!have) return best;
  const std::vector<QPt> h = hull_of(p);
  for (std::size_t e = 0; e < h.size(); ++e) {
    const QPt& u = h[e];
    const QPt& w = h[(e + 1) % h.size()];
    if (d2(u, w) <= 4 * best.r2) continue;  // B ≤ |e|²/4 ≤ M on this edge
    for (std::size_t a = 0; a < n; ++a)
      for (std::size_t b = a + 1; b < n; ++b) {
        const Q den = 2 * ((w.x - u.x) * (p[b].x - p[a].x) + (w.y - u.y) * (p[b].y - p[a].y));
        if (den == 0) continue;
        const Q t = (d2(u, p[b]) - d2(u, p[a])) / den;
        if (t < 0 || t > 1) continue;
        const QPt x{u.x + t * (w.x - u.x), u.y + t * (w.y - u.y)};
        Q r2 = d2(x, p[0]);
        for (const QPt& s : p) r2 = std::min(r2, d2(x, s));
        if (r2 > best.r2) return Brute{};  // boundary beats every surrounded vertex
      }
  }
  best.defined = true;
  return best;
}

void expect_valid(const std::vector<Point2>& p, const MaximumInscribedCircle& mi) {
  const auto v = verify(p, mi);
  EXPECT_TRUE(v.valid) << v.reason;
  EXPECT_EQ(mi.certificate.optimality, Optimality::global);
  EXPECT_FALSE(mi.certificate.argument.empty());
}

bool is_fast_path(const MaximumInscribedCircle& mi) {
  return mi.certificate.argument.rfind("fast path", 0) == 0;
}

TEST(MaximumInscribed, SquareWithAnInnerPoint) {
  // Corners (±1, ±1) and p = (0, −0.5): the circle through (−1, 1), (1, 1) and p has centre
  // (0, 7/12) and radius 13/12 (acute triangle, no corner inside), the largest of the
  // three surrounded Voronoi vertices (the side ones have radius √1.015625).
  for (const Point2 off : {Point2{0, 0}, Point2{5, -3}, Point2{-0.1, 0.3}}) {
    const std::vector<Point2> p{{off.x + 1, off.y + 1}, {off.x - 1, off.y + 1},
                                {off.x - 1, off.y - 1}, {off.x + 1, off.y - 1},
                                {off.x + 0, off.y - 0.5}};
    const auto mi = maximum_inscribed_circle(p);
    EXPECT_NEAR(mi.center.x, off.x, 1e-15);
    EXPECT_NEAR(mi.center.y, off.y + 7.0 / 12.0, 1e-15);
    EXPECT_NEAR(mi.radius, 13.0 / 12.0, 1e-15);
    auto c = mi.contacts;
    std::sort(c.begin(), c.end());
    EXPECT_EQ(c, (std::vector<std::size_t>{0, 1, 4}));
    expect_valid(p, mi);
  }
}

TEST(MaximumInscribed, CoCircularSquare) {
  // Four co-circular corners: the Voronoi vertex (the centre) is shared by 4 points and no
  // 3 of them hold it strictly inside their triangle; the 3 reported contain it in their
  // closed triangle and the certificate names the 4th.
  const std::vector<Point2> p{{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
  const auto mi = maximum_inscribed_circle(p);
  EXPECT_EQ(mi.center.x, 0.0);
  EXPECT_EQ(mi.center.y, 0.0);
  EXPECT_NEAR(mi.radius, std::sqrt(2.0), 3e-16);
  ASSERT_EQ(mi.contacts.size(), 3u);
  EXPECT_NE(mi.certificate.argument.find("4 co-circular"), std::string::npos)
      << mi.certificate.argument;
  EXPECT_EQ(mi.certificate.optimality, Optimality::global);
  // The centre lies on an edge of the 3 contacts' triangle; verify() accepts it because the
  // 4th corner, on the same circle, lies strictly beyond that edge.
  const auto v = verify(p, mi);
  EXPECT_TRUE(v.valid) << v.reason;
}

TEST(MaximumInscribed, EquilateralTriangle) {
  const double h = std::sqrt(3.0);
  const std::vector<Point2> p{{0, 0}, {2, 0}, {1, h}};
  const auto mi = maximum_inscribed_circle(p);
  EXPECT_NEAR(mi.center.x, 1.0, 1e-15);
  EXPECT_NEAR(mi.center.y, 1.0 / h, 1e-15);
  EXPECT_NEAR(mi.radius, 2.0 / h, 1e-15);
  expect_valid(p, mi);
}

TEST(MaximumInscribed, LobedRingHasRadiusRMinusA) {
  // r(θ) = R + a·cos 3θ, n divisible by 6: the valleys at 60°, 180°, 300° (radius R − a)
  // surround the origin, every other point is farther: MI = (origin, R − a), fast path.
  vcmm::test::RingSpec spec;
  spec.radius = 10.0;
  spec.n = 3600;
  spec.harmonics = {{3, 0.01, 0.0}};
  const auto p = vcmm::test::ring_profile(spec);
  const auto mi = maximum_inscribed_circle(p);
  EXPECT_NEAR(mi.radius, 9.99, 1e-13);
  EXPECT_NEAR(mi.center.x, 0.0, 1e-13);
  EXPECT_NEAR(mi.center.y, 0.0, 1e-13);
  EXPECT_NEAR(mi.ron.ront, 0.02, 1e-12);
  EXPECT_EQ(mi.ron.ronv, 0.0);
  EXPECT_TRUE(is_fast_path(mi)) << mi.certificate.argument;
  // Contacts 120° apart: beta = cos 60° = 1/2, so the contact-cone disc has radius r*.
  EXPECT_NEAR(mi.certificate.region_radius, 9.99, 1e-9);
  expect_valid(p, mi);
}

TEST(MaximumInscribed, NoisyRingsAtAllSizesTakeTheFastPath) {
  for (std::size_t n : {16u, 360u, 3600u, 36000u}) {
    for (std::uint64_t seed : {1u, 2u, 3u}) {
      const auto p = vcmm::test::lobed_noisy_ring(n, seed);
      const auto mi = maximum_inscribed_circle(p);
      double rho_max = 0.0;
      for (const Point2& x : p)
        rho_max = std::max(rho_max, std::hypot(x.x - mi.center.x, x.y - mi.center.y));
      EXPECT_NEAR(mi.ron.ront, rho_max - mi.radius, 1e-13) << "n = " << n;
      if (n >= 360) {
        EXPECT_TRUE(is_fast_path(mi)) << "n = " << n << ", seed " << seed;
      }
      if (n <= 3600) expect_valid(p, mi);  // the verifier's exhaustion is O(n log n) + slow
    }
  }
}

TEST(MaximumInscribed, UndefinedForPartialArcs) {
  for (std::size_t n : {100u, 3600u}) {
    vcmm::test::RingSpec spec;
    spec.radius = 10.0;
    spec.n = n;
    spec.span = std::numbers::pi / 2;
    spec.noise_sigma = 1e-4;
    const auto p = vcmm::test::ring_profile(spec);
    try {
      (void)maximum_inscribed_circle(p);
      ADD_FAILURE() << "expected UndefinedResult for a 90° arc, n = " << n;
    } catch (const UndefinedResult& e) {
      EXPECT_NE(std::string(e.what()).find("maximum_inscribed_circle"), std::string::npos);
      EXPECT_NE(std::string(e.what()).find("not defined"), std::string::npos) << e.what();
    }
  }
}

TEST(MaximumInscribed, UndefinedForAnObtuseTriangle) {
  const std::vector<Point2> p{{0, 0}, {4, 0}, {1, 1}};
  EXPECT_THROW((void)maximum_inscribed_circle(p), UndefinedResult);
  // A right triangle: the circumcentre is on the hypotenuse (hull boundary).
  const std::vector<Point2> r{{0, 0}, {4, 0}, {0, 3}};
  EXPECT_THROW((void)maximum_inscribed_circle(r), UndefinedResult);
}

TEST(MaximumInscribed, MatchesExactBruteForceOnSmallSets) {
  // Regimes: closed sets near a circle (defined), random clouds (often undefined: the
  // largest empty circle sits on the hull boundary), small integer grids (co-circular).
  int defined = 0, undefined = 0;
  for (std::uint64_t seed = 1; seed <= 300; ++seed) {
    std::uint64_t s = seed * 104729;
    const std::size_t n = 3 + seed % 8;  // 3 … 10
    std::vector<Point2> p;
    const int regime = static_cast<int>(seed % 3);
    for (std::size_t i = 0; i < n; ++i) {
      if (regime == 0) {
        const double t = 2 * std::numbers::pi * (static_cast<double>(i) + 0.4 * vcmm::test::uniform01(s)) / static_cast<double>(n);
        const double r = 1.0 + 0.3 * (vcmm::test::uniform01(s) - 0.5);
        p.push_back({r * std::cos(t), r * std::sin(t)});
      } else if (regime == 1) {
        p.push_back({vcmm::test::uniform01(s), vcmm::test::uniform01(s)});
      } else {
        p.push_back({std::floor(4 * vcmm::test::uniform01(s)), std::floor(4 * vcmm::test::uniform01(s))});
      }
    }
    if (seed % 7 == 0) p.push_back(p[0]);
    bool collinear = true;
    for (std::size_t i = 2; i < p.size() && collinear; ++i)
      for (std::size_t j = 1; j < i && collinear; ++j)
        if (orient(q(p[0]), q(p[j]), q(p[i])) != 0) collinear = false;
    if (collinear) continue;
    const Brute b = brute_force(p);
    try {
      const auto mi = maximum_inscribed_circle(p);
      ASSERT_TRUE(b.defined) << "seed " << seed << ": brute force says undefined, got r = " << mi.radius;
      const QCircle got = circle_of(p, mi);
      EXPECT_TRUE(got.r2 == b.r2) << "seed " << seed << ": r " << mi.radius << " vs brute "
                                  << std::sqrt(CGAL::to_double(b.r2));
      ++defined;
      const auto v = verify(p, mi);
      EXPECT_TRUE(v.valid) << "seed " << seed << ": " << v.reason;
    } catch (const UndefinedResult& e) {
      EXPECT_FALSE(b.defined) << "seed " << seed << ": " << e.what();
      ++undefined;
    }
  }
  EXPECT_GT(defined, 50);
  EXPECT_GT(undefined, 20);
}

TEST(MaximumInscribed, MatchesBruteForceOnSetsLargeEnoughForTheFastPath) {
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    std::uint64_t s = seed * 15485863;
    const std::size_t n = 16 + seed % 7;
    std::vector<Point2> p;
    for (std::size_t i = 0; i < n; ++i) {
      const double t = 2 * std::numbers::pi * (static_cast<double>(i) + 0.4 * vcmm::test::uniform01(s)) / static_cast<double>(n);
      const double r = 5.0 + 0.2 * (vcmm::test::uniform01(s) - 0.5);
      p.push_back({3.0 + r * std::cos(t), -1.0 + r * std::sin(t)});
    }
    const Brute b = brute_force(p);
    ASSERT_TRUE(b.defined) << "seed " << seed;
    const auto mi = maximum_inscribed_circle(p);
    EXPECT_TRUE(circle_of(p, mi).r2 == b.r2) << "seed " << seed;
    expect_valid(p, mi);
  }
}

TEST(MaximumInscribed, FarFromOrigin) {
  const auto near = vcmm::test::lobed_noisy_ring(3600, 5);
  const auto far = vcmm::test::lobed_noisy_ring(3600, 5, 5e-5, {-3.0e5, 7.0e5});
  const auto a = maximum_inscribed_circle(near);
  const auto b = maximum_inscribed_circle(far);
  // Shifted data are rounded to ulp(7e5) ≈ 1.2e-10: radius and RONt agree to a few ulps.
  EXPECT_NEAR(b.radius, a.radius, 1e-9);
  EXPECT_NEAR(b.ron.ront, a.ron.ront, 1e-9);
  EXPECT_TRUE(is_fast_path(b)) << b.certificate.argument;
  expect_valid(far, b);
}

TEST(MaximumInscribed, InvariantUnderRotationAndPermutation) {
  const auto p = vcmm::test::lobed_noisy_ring(720, 17, 5e-5, {0.125, 0.5});
  const auto ref = maximum_inscribed_circle(p);
  std::vector<Point2> r(p), s(p);
  for (auto& x : r) x = {-x.y, x.x};
  std::uint64_t st = 5;
  for (std::size_t i = s.size(); i > 1; --i)
    std::swap(s[i - 1], s[static_cast<std::size_t>(vcmm::test::uniform01(st) * static_cast<double>(i))]);
  const auto mr = maximum_inscribed_circle(r);
  const auto ms = maximum_inscribed_circle(s);
  EXPECT_TRUE(circle_of(r, mr).r2 == circle_of(p, ref).r2);
  EXPECT_TRUE(circle_of(s, ms).r2 == circle_of(p, ref).r2);
  EXPECT_EQ(mr.center.x, -ref.center.y);
  EXPECT_EQ(mr.center.y, ref.center.x);
  EXPECT_EQ(ms.center.x, ref.center.x);
  EXPECT_EQ(ms.center.y, ref.center.y);
  EXPECT_EQ(ms.radius, ref.radius);
  expect_valid(r, mr);
  expect_valid(s, ms);
}

TEST(MaximumInscribed, DuplicatesAndClosedScans) {
  // A closed scan repeats its first point; contacts report the lowest index.
  vcmm::test::RingSpec spec;
  spec.radius = 10.0;
  spec.n = 360;
  spec.harmonics = {{3, 0.01, std::numbers::pi}};  // valleys at 0°, 120°, 240°
  auto p = vcmm::test::ring_profile(spec);
  const std::size_t n = p.size();
  p.push_back(p[0]);
  p.push_back(p[120]);
  const auto mi = maximum_inscribed_circle(p);
  for (std::size_t c : mi.contacts) EXPECT_LT(c, n);
  auto c = mi.contacts;
  std::sort(c.begin(), c.end());
  EXPECT_EQ(c, (std::vector<std::size_t>{0, 120, 240}));
  EXPECT_NEAR(mi.radius, 9.99, 1e-13);
  expect_valid(p, mi);
  // Small sets with duplicates go through the exhaustive method.
  const std::vector<Point2> t{{0, 0}, {2, 0}, {0, 0}, {1, 1.5}, {2, 0}, {1, 1.5}};
  const auto mt = maximum_inscribed_circle(t);
  auto ct = mt.contacts;
  std::sort(ct.begin(), ct.end());
  EXPECT_EQ(ct, (std::vector<std::size_t>{0, 1, 3}));
  expect_valid(t, mt);
}

TEST(MaximumInscribed, ExtremeMagnitudesScaleExactly) {
  const auto p = vcmm::test::lobed_noisy_ring(360, 21, 5e-5, {3.0, -1.0});
  const auto ref = maximum_inscribed_circle(p);
  for (const int e : {600, -600}) {
    std::vector<Point2> scaled(p);
    for (auto& x : scaled) x = {std::ldexp(x.x, e), std::ldexp(x.y, e)};
    const auto mi = maximum_inscribed_circle(scaled);
    EXPECT_EQ(mi.radius, std::ldexp(ref.radius, e)) << "2^" << e;
    EXPECT_EQ(mi.center.x, std::ldexp(ref.center.x, e)) << "2^" << e;
    EXPECT_EQ(mi.center.y, std::ldexp(ref.center.y, e)) << "2^" << e;
    EXPECT_NEAR(mi.certificate.region_radius / std::ldexp(ref.certificate.region_radius, e),
                1.0, 1e-12);
    auto a = mi.contacts, b = ref.contacts;
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    EXPECT_EQ(a, b) << "2^" << e;
    // Exact emptiness by the test's own rationals (verify() is not used here: at these
    // magnitudes its ulp tolerance overflows — reported to its author).
    const QCircle c = circle_of(scaled, mi);
    for (const Point2& x : scaled) EXPECT_FALSE(d2(q(x), c.c) < c.r2) << "2^" << e;
  }
}

/// The randomized sweep's ring `seed` (the generator of the regression inputs below).
std::vector<Point2> sweep_ring(int seed) {
  std::uint64_t s = static_cast<std::uint64_t>(seed) * 977;
  vcmm::test::RingSpec spec;
  spec.seed = static_cast<std::uint64_t>(seed);
  spec.radius = 1.0 + 100.0 * vcmm::test::uniform01(s);
  spec.n = static_cast<std::size_t>(16 + vcmm::test::uniform01(s) * 3000);
  spec.noise_sigma = spec.radius * 1e-6 * vcmm::test::uniform01(s);
  const int harmonics = 1 + static_cast<int>(vcmm::test::uniform01(s) * 4);
  for (int h = 0; h < harmonics; ++h) {
    const int order = 1 + static_cast<int>(vcmm::test::uniform01(s) * 20);
    const double amplitude = spec.radius * 2e-6 * vcmm::test::uniform01(s);
    spec.harmonics.push_back({order, amplitude, 6.28 * vcmm::test::uniform01(s)});
  }
  return vcmm::test::ring_profile(spec);
}

TEST(MaximumInscribed, NearlySemicircularContactsAreDecidedLocally) {
  // A very round profile whose MI contacts lie nearly on a half circle (beta ~ 3e-7): the
  // contact-cone disc (radius 2r*beta ~ 7e-6 mm) is smaller than the radial spread. The
  // fast path used to hand such inputs to the exhaustive method over all points; now caps
  // of directions at halving scales close most of the gap and only the points near the
  // contacts are triangulated (region_radius > 0: the exhausted disc). verify() re-derives
  // the global claim from a Delaunay triangulation of all points.
  // (Regression inputs found by a randomized sweep: seed 217 of its generator went this
  // way until the fast path's local refinement of the contacts (branch lib-circles2) let
  // the program find the MI's own, better-spread contacts first — it stays as a fast-path
  // case; seed 907 still reaches the exhaustion.)
  {
    const auto p = sweep_ring(217);
    const auto mi = maximum_inscribed_circle(p);
    EXPECT_TRUE(is_fast_path(mi)) << mi.certificate.argument;
    EXPECT_EQ(mi.contacts, (std::vector<std::size_t>{544, 686, 1598}));
    expect_valid(p, mi);
  }
  const auto p = sweep_ring(907);
  const auto mi = maximum_inscribed_circle(p);
  EXPECT_TRUE(is_fast_path(mi)) << mi.certificate.argument;
  EXPECT_GT(mi.certificate.region_radius, 0.0);
  EXPECT_NE(mi.certificate.argument.find("exhausted"), std::string::npos)
      << mi.certificate.argument;
  expect_valid(p, mi);
}

TEST(MaximumInscribed, RejectsBadInput) {
  auto message = [](const std::vector<Point2>& p) -> std::string {
    try {
      (void)maximum_inscribed_circle(p);
    } catch (const InvalidInput& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(message({{0, 0}, {1, 0}}).find("maximum_inscribed_circle: needs at least 3 points"),
            std::string::npos);
  EXPECT_NE(message({{0, 0}, {1, 1}, {2, 2}, {3, 3}}).find("collinear"), std::string::npos);
  EXPECT_NE(message({{0, 0}, {1, 0}, {0, std::numeric_limits<double>::quiet_NaN()}}).find("point 2"),
            std::string::npos);
}

}  // namespace
