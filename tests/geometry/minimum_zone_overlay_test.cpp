// tests/geometry/minimum_zone_overlay_test.cpp — the exact minimum-zone method by overlay of
// the nearest- and farthest-point Voronoi diagrams (internal::minimum_zone_overlay).
//
// (a) hand cases; (b) a brute-force cross-check written here, independent of the library:
// every 2+2 quadruple (two outer, two inner points) in exact rationals, kept when its
// annulus holds every point, least width — the global minimum whenever it is attained —
// over random small sets, near-degenerate sets (circle points perturbed by 1e-12, integer
// grids with many co-circular quadruples); (c) the pruned method equals the exhaustive
// overlay on rings, arcs and far-from-origin data; (d) speed at n = 360, 3600, 36000.
// Random cases print their seed through SCOPED_TRACE.
#include <gtest/gtest.h>

#include <CGAL/Exact_rational.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

// Internal header (not installed): the tests reach it by its path in the source tree.
#include "../../geometry/src/internal/minimum_zone_overlay_detail.h"
#include "support/test_profiles.h"
#include "vcmm/geometry/certificate.h"

namespace {

using vcmm::geometry::InvalidInput;
using vcmm::geometry::MinimumZoneCircle;
using vcmm::geometry::Optimality;
using vcmm::geometry::Point2;
using vcmm::geometry::UndefinedResult;
namespace internal = vcmm::geometry::internal;
using Q = CGAL::Exact_rational;

// ---- an exact brute-force minimum zone, independent of the library ---------------------

int sgn(const Q& q) { return static_cast<int>(CGAL::sign(q)); }

/// sign(e + √u − √v), u, v ≥ 0: the sign of √u − √v is that of u − v; when e has the
/// opposite sign, compare |e| with |√u − √v| by squaring: e² vs u + v − 2√(uv).
int sign_e_plus_root_difference(const Q& e, const Q& u, const Q& v) {
  const int s1 = sgn(u - v);
  const int se = sgn(e);
  if (se == 0) return s1;
  if (s1 == 0 || s1 == se) return se;
  const Q g = e * e - u - v;  // sign(|e| − |√u − √v|) = sign(g + 2√(uv))
  int s;
  if (sgn(g) >= 0) s = (sgn(g) > 0 || sgn(u * v) > 0) ? 1 : 0;
  else s = sgn(4 * u * v - g * g);
  return se * s;
}

/// sign((√a − √b) − (√c − √d)) = sign((√a + √d) − (√b + √c)); squaring both non-negative
/// sums gives sign(e + 2√(ad) − 2√(bc)) with e = a + d − b − c.
int compare_widths(const Q& a, const Q& b, const Q& c, const Q& d) {
  return sign_e_plus_root_difference(a + d - b - c, 4 * a * d, 4 * b * c);
}

struct Zone {
  Q cx, cy, R2, r2;
};

/// The annulus of a 2+2 quadruple: centre on both bisectors (exact Cramer), or nothing
/// when they are parallel.
std::optional<Zone> quadruple_zone(const std::vector<Point2>& p, std::size_t o1, std::size_t o2,
                                   std::size_t i1, std::size_t i2) {
  const Q ax(p[o1].x), ay(p[o1].y), bx(p[o2].x), by(p[o2].y);
  const Q cx(p[i1].x), cy(p[i1].y), dx(p[i2].x), dy(p[i2].y);
  // 2(b − a)·x = |b|² − |a|², 2(d − c)·x = |d|² − |c|²
  const Q a11 = 2 * (bx - ax), a12 = 2 * (by - ay), r1 = bx * bx + by * by - ax * ax - ay * ay;
  const Q a21 = 2 * (dx - cx), a22 = 2 * (dy - cy), r2 = dx * dx + dy * dy - cx * cx - cy * cy;
  const Q det = a11 * a22 - a12 * a21;
  if (CGAL::is_zero(det)) return std::nullopt;
  Zone z;
  z.cx = (r1 * a22 - a12 * r2) / det;
  z.cy = (a11 * r2 - a21 * r1) / det;
  z.R2 = (z.cx - ax) * (z.cx - ax) + (z.cy - ay) * (z.cy - ay);
  z.r2 = (z.cx - cx) * (z.cx - cx) + (z.cy - cy) * (z.cy - cy);
  return z;
}

struct BruteForce {
  bool found = false;
  Zone zone;
};

/// Least-width 2+2 annulus holding every point (exhaustive, O(n⁵)); a double filter
/// discards the quadruples that clearly fail containment before the exact test.
BruteForce brute_force_minimum_zone(const std::vector<Point2>& p) {
  const std::size_t n = p.size();
  BruteForce best;
  for (std::size_t o1 = 0; o1 < n; ++o1)
    for (std::size_t o2 = o1 + 1; o2 < n; ++o2)
      for (std::size_t i1 = 0; i1 < n; ++i1)
        for (std::size_t i2 = i1 + 1; i2 < n; ++i2) {
          if (i1 == o1 || i1 == o2 || i2 == o1 || i2 == o2) continue;
          // Double filter (only when well conditioned).
          const double a11 = p[o2].x - p[o1].x, a12 = p[o2].y - p[o1].y;
          const double a21 = p[i2].x - p[i1].x, a22 = p[i2].y - p[i1].y;
          const double det = a11 * a22 - a12 * a21;
          if (std::abs(det) > 1e-6 * std::hypot(a11, a12) * std::hypot(a21, a22)) {
            const double r1 = (p[o2].x * p[o2].x + p[o2].y * p[o2].y - p[o1].x * p[o1].x -
                               p[o1].y * p[o1].y) / 2;
            const double r2 = (p[i2].x * p[i2].x + p[i2].y * p[i2].y - p[i1].x * p[i1].x -
                               p[i1].y * p[i1].y) / 2;
            const double x = (r1 * a22 - a12 * r2) / det, y = (a11 * r2 - a21 * r1) / det;
            auto d2 = [&](std::size_t k) {
              return (p[k].x - x) * (p[k].x - x) + (p[k].y - y) * (p[k].y - y);
            };
            const double R2 = d2(o1), rr2 = d2(i1), tol = 1e-6 * (R2 + 1.0);
            bool clear_fail = rr2 > R2 + tol;
            for (std::size_t k = 0; k < n && !clear_fail; ++k)
              clear_fail = d2(k) > R2 + tol || d2(k) < rr2 - tol;
            if (clear_fail) continue;
          }
          const auto z = quadruple_zone(p, o1, o2, i1, i2);
          if (!z || !(z->r2 < z->R2)) continue;
          bool holds = true;
          for (std::size_t k = 0; k < n && holds; ++k) {
            const Q px(p[k].x), py(p[k].y);
            const Q d2 = (px - z->cx) * (px - z->cx) + (py - z->cy) * (py - z->cy);
            holds = d2 <= z->R2 && d2 >= z->r2;
          }
          if (!holds) continue;
          if (!best.found || compare_widths(z->R2, z->r2, best.zone.R2, best.zone.r2) < 0) {
            best.found = true;
            best.zone = *z;
          }
        }
  return best;
}

/// Minimal width of the point set (its convex hull), brute force in double.
double minimal_width(const std::vector<Point2>& p) {
  double w = INFINITY;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = 0; j < p.size(); ++j) {
      const double ex = p[j].x - p[i].x, ey = p[j].y - p[i].y, len = std::hypot(ex, ey);
      if (len == 0.0) continue;
      double lo = 0.0, hi = 0.0;
      for (const Point2& q : p) {
        const double h = (ex * (q.y - p[i].y) - ey * (q.x - p[i].x)) / len;
        lo = std::min(lo, h);
        hi = std::max(hi, h);
      }
      if (lo > -1e-12 * len || hi < 1e-12 * len) w = std::min(w, hi - lo);
    }
  return w;
}

bool all_cocircular_or_collinear(const std::vector<Point2>& p) {
  // Exact: every point on the circle (or line) through the first three distinct points.
  std::vector<Point2> d;
  for (const Point2& q : p)
    if (std::find(d.begin(), d.end(), q) == d.end()) d.push_back(q);
  if (d.size() <= 3) return true;
  auto lift = [](const Point2& q) {
    const Q x(q.x), y(q.y);
    return std::array<Q, 3>{x, y, x * x + y * y};
  };
  const auto a = lift(d[0]), b = lift(d[1]), c = lift(d[2]);
  for (std::size_t k = 3; k < d.size(); ++k) {
    const auto e = lift(d[k]);
    // in-circle determinant (collinear triples give the line test as a special case)
    const Q m11 = b[0] - a[0], m12 = b[1] - a[1], m13 = b[2] - a[2];
    const Q m21 = c[0] - a[0], m22 = c[1] - a[1], m23 = c[2] - a[2];
    const Q m31 = e[0] - a[0], m32 = e[1] - a[1], m33 = e[2] - a[2];
    const Q det = m11 * (m22 * m33 - m23 * m32) - m12 * (m21 * m33 - m23 * m31) +
                  m13 * (m21 * m32 - m22 * m31);
    if (!CGAL::is_zero(det)) return false;
  }
  return true;
}

/// Exact zone of a reported result.
Zone reported_zone(const std::vector<Point2>& p, const MinimumZoneCircle& mz) {
  const auto z = quadruple_zone(p, mz.outer_contacts.at(0), mz.outer_contacts.at(1),
                                mz.inner_contacts.at(0), mz.inner_contacts.at(1));
  EXPECT_TRUE(z.has_value()) << "reported contacts have parallel bisectors";
  return z.value_or(Zone{});
}

/// Runs the method on a small set and compares with the brute force, exactly.
void expect_matches_brute_force(const std::vector<Point2>& p) {
  if (all_cocircular_or_collinear(p)) return;  // covered by the hand cases
  const BruteForce bf = brute_force_minimum_zone(p);
  const double w_min = minimal_width(p);
  try {
    const MinimumZoneCircle mz = internal::minimum_zone_overlay(p);
    EXPECT_EQ(mz.certificate.optimality, Optimality::global);
    ASSERT_TRUE(bf.found) << "the method found a zone the brute force did not";
    const Zone z = reported_zone(p, mz);
    EXPECT_EQ(compare_widths(z.R2, z.r2, bf.zone.R2, bf.zone.r2), 0)
        << "width " << mz.ron.ront << " vs brute force "
        << std::sqrt(CGAL::to_double(bf.zone.R2)) - std::sqrt(CGAL::to_double(bf.zone.r2));
    EXPECT_LE(mz.ron.ront, w_min * (1 + 1e-9) + 1e-15);
    if (mz.certificate.argument.find("degenerate") == std::string::npos) {
      const auto v = vcmm::geometry::verify(p, mz);
      EXPECT_TRUE(v.valid) << v.reason;
    }
  } catch (const UndefinedResult& e) {
    // Not attained: every feasible 2+2 annulus is at least as wide as the hull.
    if (bf.found) {
      const double w = std::sqrt(CGAL::to_double(bf.zone.R2)) -
                       std::sqrt(CGAL::to_double(bf.zone.r2));
      EXPECT_GE(w, w_min * (1 - 1e-9)) << e.what();
    }
  }
}

// ---- hand cases ------------------------------------------------------------------------

TEST(MinimumZoneOverlay, FourAlternatingPoints) {
  const std::vector<Point2> p{{2, 0}, {0, 1}, {-2, 0}, {0, -1}};
  const MinimumZoneCircle mz = internal::minimum_zone_overlay(p);
  EXPECT_EQ(mz.center.x, 0.0);
  EXPECT_EQ(mz.center.y, 0.0);
  EXPECT_DOUBLE_EQ(mz.outer_radius, 2.0);
  EXPECT_DOUBLE_EQ(mz.inner_radius, 1.0);
  EXPECT_DOUBLE_EQ(mz.ron.ront, 1.0);
  std::vector<std::size_t> outer = mz.outer_contacts, inner = mz.inner_contacts;
  std::sort(outer.begin(), outer.end());
  std::sort(inner.begin(), inner.end());
  EXPECT_EQ(outer, (std::vector<std::size_t>{0, 2}));
  EXPECT_EQ(inner, (std::vector<std::size_t>{1, 3}));
  EXPECT_EQ(mz.certificate.optimality, Optimality::global);
  const auto v = vcmm::geometry::verify(p, mz);
  EXPECT_TRUE(v.valid) << v.reason;
}

TEST(MinimumZoneOverlay, SquareWithTwoInnerPoints) {
  // Unit-circle square plus two points at radius √2/2 on a diagonal: the centre stays at
  // the origin by symmetry, width 1 − √2/2.
  const std::vector<Point2> p{{1, 0}, {0, 1}, {-1, 0}, {0, -1}, {0.5, 0.5}, {-0.5, -0.5}};
  const MinimumZoneCircle mz = internal::minimum_zone_overlay(p);
  EXPECT_NEAR(mz.ron.ront, 1.0 - std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(mz.center.x, 0.0, 1e-15);
  EXPECT_NEAR(mz.center.y, 0.0, 1e-15);
  expect_matches_brute_force(p);
}

TEST(MinimumZoneOverlay, CocircularPointsGiveZeroWidth) {
  const std::vector<Point2> p{{5, 0}, {3, 4}, {0, 5}, {-4, 3}, {-5, 0}, {0, -5}, {4, -3}};
  internal::OverlayStatistics stats;
  const MinimumZoneCircle mz = internal::minimum_zone_overlay(p, {}, &stats);
  EXPECT_TRUE(stats.cocircular);
  EXPECT_EQ(mz.ron.ront, 0.0);
  EXPECT_DOUBLE_EQ(mz.outer_radius, 5.0);
  EXPECT_EQ(mz.outer_contacts.size(), 3u);
  const auto v = vcmm::geometry::verify(p, mz);
  EXPECT_TRUE(v.valid) << v.reason;
}

TEST(MinimumZoneOverlay, ThreePointsAreCocircular) {
  const std::vector<Point2> p{{0, 0}, {4, 0}, {0, 3}, {4, 0}};  // with a duplicate
  const MinimumZoneCircle mz = internal::minimum_zone_overlay(p);
  EXPECT_EQ(mz.ron.ront, 0.0);
  EXPECT_DOUBLE_EQ(mz.center.x, 2.0);
  EXPECT_DOUBLE_EQ(mz.center.y, 1.5);
  EXPECT_DOUBLE_EQ(mz.outer_radius, 2.5);
  for (std::size_t i : mz.outer_contacts) EXPECT_NE(i, 3u) << "duplicate: lowest index";
}

TEST(MinimumZoneOverlay, CollinearPointsAreRejected) {
  const std::vector<Point2> p{{0, 0}, {1, 1}, {2, 2}, {1, 1}};
  EXPECT_THROW(internal::minimum_zone_overlay(p), InvalidInput);
}

TEST(MinimumZoneOverlay, ThreeLobedProfileHasTwiceTheAmplitude) {
  // r(θ) = R + a cos 3θ sampled at 360 angles including the peaks and valleys: by symmetry
  // the zone is centred at the origin and its width is 2a (to the rounding of the input).
  for (double a : {1e-3, 2e-5}) {
    vcmm::test::RingSpec spec;
    spec.n = 360;
    spec.radius = 20.0;
    spec.harmonics = {{3, a, 0.0}};
    const std::vector<Point2> p = vcmm::test::ring_profile(spec);
    const MinimumZoneCircle mz = internal::minimum_zone_overlay(p);
    EXPECT_NEAR(mz.ron.ront, 2 * a, 1e-13) << "a = " << a;
    EXPECT_NEAR(mz.center.x, 0.0, 1e-12);
    EXPECT_NEAR(mz.center.y, 0.0, 1e-12);
    const auto v = vcmm::geometry::verify(p, mz);
    EXPECT_TRUE(v.valid) << v.reason;
  }
}

TEST(MinimumZoneOverlay, TwoLobedEllipseLikeProfile) {
  // r = R + a cos 2θ: width 2a, centre at the origin.
  vcmm::test::RingSpec spec;
  spec.n = 72;
  spec.radius = 10.0;
  spec.harmonics = {{2, 1e-3, 0.0}};
  const std::vector<Point2> p = vcmm::test::ring_profile(spec);
  const MinimumZoneCircle mz = internal::minimum_zone_overlay(p);
  EXPECT_NEAR(mz.ron.ront, 2e-3, 1e-14);
  EXPECT_NEAR(std::hypot(mz.center.x, mz.center.y), 0.0, 1e-12);
  const auto v = vcmm::geometry::verify(p, mz);
  EXPECT_TRUE(v.valid) << v.reason;
}

TEST(MinimumZoneOverlay, DuplicatesAreHarmlessAndReportTheLowestIndex) {
  std::vector<Point2> p = vcmm::test::lobed_noisy_ring(720, 3);
  const MinimumZoneCircle base = internal::minimum_zone_overlay(p);
  // A closed scan repeats its first point; duplicate every contact as well, at the end.
  std::vector<Point2> q = p;
  q.push_back(p.front());
  for (std::size_t i : base.outer_contacts) q.push_back(p[i]);
  for (std::size_t i : base.inner_contacts) q.push_back(p[i]);
  for (std::size_t i = 0; i < p.size(); i += 7) q.push_back(p[i]);
  const MinimumZoneCircle mz = internal::minimum_zone_overlay(q);
  EXPECT_EQ(mz.center, base.center);
  EXPECT_EQ(mz.ron.ront, base.ron.ront);
  for (std::size_t i : mz.outer_contacts) EXPECT_LT(i, p.size());
  for (std::size_t i : mz.inner_contacts) EXPECT_LT(i, p.size());
  const auto v = vcmm::geometry::verify(q, mz);
  EXPECT_TRUE(v.valid) << v.reason;
}

TEST(MinimumZoneOverlay, NearlyStraightDataIsUndefined) {
  // A zigzag between the lines y = 0 and y = h: any finite centre bends the zone, which is
  // then wider than h (sagitta); the width only tends to h as the centre recedes.
  std::vector<Point2> p;
  for (int i = 0; i < 200; ++i) p.push_back({0.05 * i, (i % 2) * 1e-4});
  try {
    internal::minimum_zone_overlay(p);
    ADD_FAILURE() << "expected UndefinedResult";
  } catch (const UndefinedResult& e) {
    EXPECT_NE(std::string(e.what()).find("not attained"), std::string::npos) << e.what();
  }
  // Small versions go through the exhaustive path and must agree with the brute force.
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::vector<Point2> s;
    std::uint64_t st = seed;
    for (int i = 0; i < 8; ++i)
      s.push_back({static_cast<double>(i), 1e-3 * vcmm::test::uniform01(st)});
    expect_matches_brute_force(s);
  }
}

TEST(MinimumZoneOverlay, ThreeRayDegeneracyIsAStrictMinimumWithoutAlternation) {
  // o_k = 10 v_k, i_k = 5 v_k on three rays from the origin: f'(0; u) > 0 in every
  // direction (a strict minimum, the global one — the brute force agrees), yet the contacts
  // occupy three directions only, so no 2+2 subset alternates strictly. The method reports
  // a 2+2 with crossing bisectors and says so in the certificate; verify() (strict
  // alternation) rejects it by design.
  const std::vector<Point2> p{{10, 0}, {0, 10}, {-6, -8}, {5, 0}, {0, 5}, {-3, -4}};
  const MinimumZoneCircle mz = internal::minimum_zone_overlay(p);
  EXPECT_EQ(mz.center.x, 0.0);
  EXPECT_EQ(mz.center.y, 0.0);
  EXPECT_DOUBLE_EQ(mz.ron.ront, 5.0);
  EXPECT_NE(mz.certificate.argument.find("degenerate"), std::string::npos)
      << mz.certificate.argument;
  expect_matches_brute_force(p);
}

TEST(MinimumZoneOverlay, FewerThanThreeDistinctPointsAreRejected) {
  const std::vector<Point2> p{{1, 2}, {3, 4}, {1, 2}, {3, 4}};
  try {
    internal::minimum_zone_overlay(p);
    ADD_FAILURE() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("3 distinct points"), std::string::npos) << e.what();
  }
}

TEST(MinimumZoneOverlay, CertificateStatesTheExhaustion) {
  const std::vector<Point2> p = vcmm::test::lobed_noisy_ring(1000, 5);
  const MinimumZoneCircle mz = internal::minimum_zone_overlay(p);
  EXPECT_EQ(mz.certificate.optimality, Optimality::global);
  EXPECT_NE(mz.certificate.argument.find("exhausted"), std::string::npos);
  EXPECT_NE(mz.certificate.argument.find("minimum attained"), std::string::npos);
  // Every centre that could beat the result lies within region_radius of the centre.
  EXPECT_GT(mz.certificate.region_radius, 0.0);
  EXPECT_LT(mz.certificate.region_radius, 1e-11);
  // Small sets: the whole overlay, no region.
  const MinimumZoneCircle small = internal::minimum_zone_overlay(vcmm::test::random_points(9, 4));
  EXPECT_EQ(small.certificate.region_radius, 0.0);
  EXPECT_NE(small.certificate.argument.find("all "), std::string::npos);
}

// ---- brute-force cross-checks ----------------------------------------------------------

TEST(MinimumZoneOverlay, RandomSmallSetsMatchBruteForce) {
  for (std::size_t n = 4; n <= 10; ++n)
    for (std::uint64_t seed = 1; seed <= 50; ++seed) {
      SCOPED_TRACE("n " + std::to_string(n) + " seed " + std::to_string(seed));
      expect_matches_brute_force(vcmm::test::random_points(n, seed * 1000 + n));
    }
}

TEST(MinimumZoneOverlay, PerturbedCirclesMatchBruteForce) {
  // Points within 1e-12 of a circle: every quadruple is nearly co-circular.
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::uint64_t st = seed * 7919;
    const std::size_t n = 5 + seed % 6;
    std::vector<Point2> p;
    for (std::size_t i = 0; i < n; ++i) {
      const double t = 2 * std::numbers::pi * vcmm::test::uniform01(st);
      const double r = 1.0 + 1e-12 * (vcmm::test::uniform01(st) - 0.5);
      p.push_back({r * std::cos(t), r * std::sin(t)});
    }
    expect_matches_brute_force(p);
  }
}

TEST(MinimumZoneOverlay, IntegerGridsMatchBruteForce) {
  // Subsets of a 5×5 grid: many co-circular quadruples, parallel bisectors, ties.
  for (std::uint64_t seed = 1; seed <= 120; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::uint64_t st = seed * 104729;
    const std::size_t n = 4 + seed % 7;
    std::vector<Point2> p;
    while (p.size() < n) {
      const Point2 q{std::floor(5 * vcmm::test::uniform01(st)),
                     std::floor(5 * vcmm::test::uniform01(st))};
      if (std::find(p.begin(), p.end(), q) == p.end()) p.push_back(q);
    }
    expect_matches_brute_force(p);
  }
}

TEST(MinimumZoneOverlay, SymmetricDegenerateSetsMatchBruteForce) {
  const std::vector<std::vector<Point2>> sets{
      // concentric squares, rotated: 8 contacts, all ties
      {{2, 0}, {0, 2}, {-2, 0}, {0, -2}, {1, 1}, {-1, 1}, {-1, -1}, {1, -1}},
      // three rays with an outer and an inner point each (the degenerate strict minimum)
      {{10, 0}, {0, 10}, {-6, -8}, {5, 0}, {0, 5}, {-3, -4}},
      // a rectangle with its centre point
      {{0, 0}, {4, 0}, {4, 2}, {0, 2}, {2, 1}},
      // regular-ish octagon on integer points plus inner points
      {{5, 0}, {4, 3}, {3, 4}, {0, 5}, {-3, 4}, {-4, 3}, {-5, 0}, {0, -5}, {1, 0}, {0, 1}},
  };
  for (std::size_t k = 0; k < sets.size(); ++k) {
    SCOPED_TRACE("set " + std::to_string(k));
    expect_matches_brute_force(sets[k]);
  }
}

// ---- the pruned method against the exhaustive overlay -----------------------------------

void expect_pruned_equals_full(const std::vector<Point2>& p, double max_region = 1e-9) {
  internal::OverlayStatistics s_pruned, s_full;
  const MinimumZoneCircle a = internal::minimum_zone_overlay(p, {true}, &s_pruned);
  const MinimumZoneCircle b = internal::minimum_zone_overlay(p, {false}, &s_full);
  EXPECT_TRUE(s_pruned.region_used);
  const Zone za = reported_zone(p, a), zb = reported_zone(p, b);
  EXPECT_EQ(compare_widths(za.R2, za.r2, zb.R2, zb.r2), 0);
  EXPECT_EQ(a.center, b.center);
  const auto v = vcmm::geometry::verify(p, a);
  EXPECT_TRUE(v.valid) << v.reason;
  EXPECT_GT(a.certificate.region_radius, 0.0);
  EXPECT_LT(a.certificate.region_radius, max_region);
}

TEST(MinimumZoneOverlay, PrunedEqualsExhaustiveOnRings) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    expect_pruned_equals_full(vcmm::test::lobed_noisy_ring(200, seed));
    // Noise-dominated: the hull keeps a fraction of the points.
    expect_pruned_equals_full(vcmm::test::lobed_noisy_ring(300, seed, 2e-3));
  }
}

TEST(MinimumZoneOverlay, PartialArcsMatchExhaustiveOverlay) {
  for (double span : {0.3, 1.5, 3.5}) {
    SCOPED_TRACE("span " + std::to_string(span));
    vcmm::test::RingSpec spec;
    spec.n = 150;
    spec.radius = 25.0;
    spec.span = span;
    spec.start_angle = 0.4;
    spec.noise_sigma = 2e-4;
    spec.harmonics = {{3, 3e-4, 0.2}};
    // Short arcs determine their centre poorly: the proven region is larger (0.1 mm at
    // 0.3 rad here) but still exhausted exactly.
    expect_pruned_equals_full(vcmm::test::ring_profile(spec), 1.0);
  }
}

TEST(MinimumZoneOverlay, FarFromOriginWithMicrometreForm) {
  // A ring centred 900 mm from the origin with µm-level form: the centre and the width keep
  // their accuracy (exact arithmetic on the input doubles).
  for (std::uint64_t seed = 1; seed <= 2; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const std::vector<Point2> p = vcmm::test::lobed_noisy_ring(200, seed, 5e-5, {900.0, -900.0});
    expect_pruned_equals_full(p);
    const MinimumZoneCircle mz = internal::minimum_zone_overlay(p);
    const MinimumZoneCircle centred =
        internal::minimum_zone_overlay(vcmm::test::lobed_noisy_ring(200, seed));
    // Same shape (up to the rounding of the shifted coordinates, ~1e-13 mm).
    EXPECT_NEAR(mz.ron.ront, centred.ron.ront, 1e-11);
    EXPECT_NEAR(mz.center.x - 900.0, centred.center.x, 1e-9);
    EXPECT_NEAR(mz.center.y + 900.0, centred.center.y, 1e-9);
  }
}

// ---- speed --------------------------------------------------------------------------------

TEST(MinimumZoneOverlay, DenseRingsUseATinyRegion) {
  for (std::size_t n : {360u, 3600u, 36000u}) {
    const std::vector<Point2> p = vcmm::test::lobed_noisy_ring(n, 1);
    internal::OverlayStatistics stats;
    double best_ms = INFINITY;
    MinimumZoneCircle mz;
    for (int rep = 0; rep < 3; ++rep) {
      const auto t0 = std::chrono::steady_clock::now();
      mz = internal::minimum_zone_overlay(p, {}, &stats);
      const auto t1 = std::chrono::steady_clock::now();
      best_ms = std::min(best_ms, std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
    std::printf("[ overlay  ] n = %zu: %.2f ms (best of 3), RONt = %.6f um, hull %zu, region "
                "%.2g mm, sites %zu far / %zu near, %zu x %zu edges, %zu candidates\n",
                n, best_ms, mz.ron.ront * 1e3, stats.hull_vertices, stats.region_radius,
                stats.far_sites, stats.near_sites, stats.fvd_edges_in_region,
                stats.nvd_edges_in_region, stats.candidates);
    EXPECT_TRUE(stats.region_used);
    EXPECT_LE(stats.edge_pairs, 100u);
    EXPECT_LT(best_ms, 2000.0);  // generous: shared machines; typical figures in the report
    const auto v = vcmm::geometry::verify(p, mz);
    EXPECT_TRUE(v.valid) << v.reason;
  }
}

}  // namespace
