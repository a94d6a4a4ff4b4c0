// The reference circles on degenerate but valid inputs (issue 11, item 3): perfect circles
// (points on a circle to the last ulp), ulp-level and smooth few-harmonic forms from 1e-13 to
// 1e-3 mm, and exactly co-circular points (a polygon with exact square symmetry, integer
// points on a circle). Every result must verify and claim global optimality; MZ is
// cross-checked against the Voronoi overlay, MI against the Delaunay exhaustion, all three
// against the exhaustive oracle on small sets (compared exactly: centres and squared radii
// as rationals); and the optimum must not move under exact rotation by 90°, exact
// translation and permutation. Speed is measured in the benchmarks, not here.
#include <gtest/gtest.h>

#include <CGAL/Exact_rational.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

// Internal headers (not installed): the tests reach them by their path in the source tree.
#include "../../geometry/src/internal/maximum_inscribed_detail.h"
#include "../../geometry/src/internal/minimum_zone_overlay_detail.h"
#include "support/exhaustive_oracle.h"
#include "support/test_profiles.h"
#include "vcmm/geometry/certificate.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/minimum_circumscribed.h"
#include "vcmm/geometry/minimum_zone.h"

namespace {

using namespace vcmm::geometry;
using vcmm::test::compare_sqrt_differences;
using vcmm::test::OracleStatus;
using Q = CGAL::Exact_rational;

// ---- the families -------------------------------------------------------------------------

/// r(θ) = R + a·(2 cos(2θ + 1) + 1.5 cos(3θ + 0.5) + cos 4θ)/2 about `center`: a = 0 a perfect
/// circle; these phases make the MI contacts nearly antipodal (a tiny contact cone).
std::vector<Point2> smooth_ring(std::size_t n, double a, Point2 center = {600.0, 500.0}) {
  vcmm::test::RingSpec spec;
  spec.center = center;
  spec.n = n;
  if (a > 0.0) spec.harmonics = {{2, a, 1.0}, {3, 0.75 * a, 0.5}, {4, 0.5 * a, 0.0}};
  return vcmm::test::ring_profile(spec);
}

struct Family {
  std::string name;
  std::vector<Point2> pts;
};

std::vector<Family> families(std::size_t n) {
  std::vector<Family> f = {
      {"perfect circle about (600, 500)", smooth_ring(n, 0.0)},
      {"perfect circle about the origin", smooth_ring(n, 0.0, {0.0, 0.0})},
      {"symmetric polygon", vcmm::test::symmetric_polygon(n)},
      {"integer points on a circle", vcmm::test::lattice_circle(n)},
  };
  for (const double a : {1e-13, 1e-11, 1e-9, 1e-7, 1e-5, 1e-3}) {
    std::ostringstream name;
    name << "smooth form, amplitude " << a << " mm";
    f.push_back({name.str(), smooth_ring(n, a)});
  }
  return f;
}

// ---- exact circles of the results ----------------------------------------------------------

struct QCircle {
  Q cx, cy, r2;
  friend bool operator==(const QCircle&, const QCircle&) = default;
};

/// The circle through 2 (diametral) or 3 input points, exactly.
QCircle circle_through(const std::vector<Point2>& p, const std::vector<std::size_t>& idx) {
  const Q ax(p[idx[0]].x), ay(p[idx[0]].y), bx(p[idx[1]].x), by(p[idx[1]].y);
  if (idx.size() == 2) {
    const Q cx = (ax + bx) / 2, cy = (ay + by) / 2;
    return {cx, cy, (ax - cx) * (ax - cx) + (ay - cy) * (ay - cy)};
  }
  const Q dx(p[idx[2]].x), dy(p[idx[2]].y);
  const Q ux = bx - ax, uy = by - ay, vx = dx - ax, vy = dy - ay;
  const Q det = 2 * (ux * vy - uy * vx);
  const Q u2 = ux * ux + uy * uy, v2 = vx * vx + vy * vy;
  const Q ox = (vy * u2 - uy * v2) / det, oy = (ux * v2 - vx * u2) / det;
  return {ax + ox, ay + oy, ox * ox + oy * oy};
}

struct QZone {
  Q cx, cy, outer2, inner2;
  friend bool operator==(const QZone&, const QZone&) = default;
};

QZone zone_of(const std::vector<Point2>& p, const MinimumZoneCircle& mz) {
  if (mz.outer_contacts.size() == 3) {
    const QCircle c = circle_through(p, mz.outer_contacts);
    return {c.cx, c.cy, c.r2, c.r2};
  }
  const auto z = vcmm::test::exact_zone(p, mz.outer_contacts[0], mz.outer_contacts[1],
                                        mz.inner_contacts[0], mz.inner_contacts[1]);
  EXPECT_TRUE(z.has_value());
  return z ? QZone{z->center.x, z->center.y, z->outer2, z->inner2} : QZone{};
}

struct Fits {
  MinimumZoneCircle mz;
  MaximumInscribedCircle mi;
  MinimumCircumscribedCircle mc;
};

Fits fit_and_verify(const std::vector<Point2>& p) {
  Fits f{minimum_zone_circle(p), maximum_inscribed_circle(p), minimum_circumscribed_circle(p)};
  const Verification vz = verify(p, f.mz), vi = verify(p, f.mi), vc = verify(p, f.mc);
  EXPECT_TRUE(vz.valid) << "MZ: " << vz.reason << "\n  " << f.mz.certificate.argument;
  EXPECT_TRUE(vi.valid) << "MI: " << vi.reason << "\n  " << f.mi.certificate.argument;
  EXPECT_TRUE(vc.valid) << "MC: " << vc.reason << "\n  " << f.mc.certificate.argument;
  EXPECT_EQ(f.mz.certificate.optimality, Optimality::global) << f.mz.certificate.argument;
  EXPECT_EQ(f.mi.certificate.optimality, Optimality::global) << f.mi.certificate.argument;
  EXPECT_EQ(f.mc.certificate.optimality, Optimality::global);
  return f;
}

// ---- (a) every family, two sizes: verified, global, ordered, on the fast paths -------------

TEST(DegenerateInputs, EveryFamilyVerifiesOnTheFastPaths) {
  for (const std::size_t n : {360, 3600}) {
    for (const Family& fam : families(n)) {
      SCOPED_TRACE(fam.name + ", n = " + std::to_string(n));
      const Fits f = fit_and_verify(fam.pts);
      EXPECT_LE(f.mi.radius, f.mc.radius);
      EXPECT_LE(f.mz.inner_radius, f.mz.outer_radius);
      // The fast paths settle these inputs: no Voronoi overlay, no full Delaunay exhaustion.
      EXPECT_EQ(f.mz.certificate.argument.find("overlay"), std::string::npos)
          << f.mz.certificate.argument;
      EXPECT_EQ(f.mi.certificate.argument.rfind("fast path", 0), 0u)
          << f.mi.certificate.argument;
    }
  }
}

TEST(DegenerateInputs, ExactlyCocircularPointsHaveZeroWidthAndTiedContacts) {
  for (const std::size_t n : {24, 360, 3600}) {
    const std::vector<Point2> p = vcmm::test::lattice_circle(n);
    SCOPED_TRACE("n = " + std::to_string(n));
    const Fits f = fit_and_verify(p);
    // MZ: zero width, the same 3 contacts on both lists.
    ASSERT_EQ(f.mz.outer_contacts.size(), 3u);
    EXPECT_EQ(f.mz.outer_contacts, f.mz.inner_contacts);
    EXPECT_EQ(f.mz.ron.ront, 0.0);
    // MI and MC: all three are the one circle through every point.
    const QCircle mz_circle = circle_through(p, f.mz.outer_contacts);
    EXPECT_EQ(circle_through(p, f.mi.contacts), mz_circle);
    EXPECT_EQ(circle_through(p, f.mc.contacts), mz_circle);
    EXPECT_EQ(f.mi.ron.ront, 0.0);
    EXPECT_EQ(f.mc.ron.ront, 0.0);
  }
}

// ---- (b) against the slower exact paths ---------------------------------------------------

TEST(DegenerateInputs, MinimumZoneMatchesTheVoronoiOverlay) {
  // The overlay is itself slow on these inputs (it exhausts near-degenerate diagrams): the
  // symmetric polygon is compared at n = 64.
  MinimumZoneOptions overlay;
  overlay.method = MinimumZoneMethod::overlay;
  for (const Family& fam : families(360)) {
    const std::vector<Point2> p =
        fam.name == "symmetric polygon" ? vcmm::test::symmetric_polygon(64) : fam.pts;
    SCOPED_TRACE(fam.name);
    const MinimumZoneCircle fast = minimum_zone_circle(p);
    const MinimumZoneCircle slow = minimum_zone_circle(p, overlay);
    EXPECT_EQ(zone_of(p, fast), zone_of(p, slow));
  }
}

TEST(DegenerateInputs, MaximumInscribedMatchesTheDelaunayExhaustion) {
  for (const std::size_t n : {360, 3600}) {
    for (const Family& fam : families(n)) {
      SCOPED_TRACE(fam.name + ", n = " + std::to_string(n));
      const MaximumInscribedCircle fast = maximum_inscribed_circle(fam.pts);
      const MaximumInscribedCircle slow = internal::maximum_inscribed_exhaustive(fam.pts);
      EXPECT_EQ(circle_through(fam.pts, fast.contacts), circle_through(fam.pts, slow.contacts));
    }
  }
}

TEST(DegenerateInputs, SmallSetsMatchTheExhaustiveOracle) {
  // n ≥ 16 so that the MI fast path runs (smaller sets go straight to the exhaustion).
  std::vector<Family> sets;
  for (const std::size_t n : {16, 24}) {
    sets.push_back({"perfect circle", smooth_ring(n, 0.0)});
    sets.push_back({"ulp-level form", smooth_ring(n, 1e-13)});
    sets.push_back({"symmetric polygon", vcmm::test::symmetric_polygon(n)});
    sets.push_back({"integer points on a circle", vcmm::test::lattice_circle(n)});
  }
  for (const Family& s : sets) {
    SCOPED_TRACE(s.name + ", n = " + std::to_string(s.pts.size()));
    const Fits f = fit_and_verify(s.pts);
    const auto omz = vcmm::test::oracle_minimum_zone(s.pts);
    ASSERT_EQ(omz.status, OracleStatus::defined) << omz.explanation;
    const QZone z = zone_of(s.pts, f.mz);
    EXPECT_EQ(z.cx, omz.center.x);
    EXPECT_EQ(z.cy, omz.center.y);
    EXPECT_EQ(compare_sqrt_differences(z.outer2, z.inner2, omz.outer2, omz.inner2), 0);
    const auto omi = vcmm::test::oracle_maximum_inscribed(s.pts);
    ASSERT_EQ(omi.status, OracleStatus::defined) << omi.explanation;
    EXPECT_EQ(circle_through(s.pts, f.mi.contacts),
              (QCircle{omi.center.x, omi.center.y, omi.radius2}));
    const auto omc = vcmm::test::oracle_minimum_circumscribed(s.pts);
    EXPECT_EQ(circle_through(s.pts, f.mc.contacts),
              (QCircle{omc.center.x, omc.center.y, omc.radius2}));
  }
}

// ---- (c) properties: the optimum does not move --------------------------------------------

struct Moved {
  std::string name;
  std::vector<Point2> pts;
  std::function<Point2(Point2)> map;  ///< the exact map applied to every point
};

void expect_same_optimum(const std::vector<Point2>& a, const std::vector<Point2>& b,
                         const std::function<std::pair<Q, Q>(const Q&, const Q&)>& map) {
  const Fits fa = fit_and_verify(a), fb = fit_and_verify(b);
  const QZone za = zone_of(a, fa.mz), zb = zone_of(b, fb.mz);
  const auto [zx, zy] = map(za.cx, za.cy);
  EXPECT_EQ(zx, zb.cx);
  EXPECT_EQ(zy, zb.cy);
  EXPECT_EQ(za.outer2, zb.outer2);
  EXPECT_EQ(za.inner2, zb.inner2);
  for (const auto& [ca, cb] :
       {std::pair{circle_through(a, fa.mi.contacts), circle_through(b, fb.mi.contacts)},
        std::pair{circle_through(a, fa.mc.contacts), circle_through(b, fb.mc.contacts)}}) {
    const auto [x, y] = map(ca.cx, ca.cy);
    EXPECT_EQ(x, cb.cx);
    EXPECT_EQ(y, cb.cy);
    EXPECT_EQ(ca.r2, cb.r2);
  }
}

TEST(DegenerateInputs, OptimaInvariantUnderRotationTranslationAndPermutation) {
  std::vector<Family> base = {
      {"perfect circle", smooth_ring(720, 0.0)},
      {"ulp-level form", smooth_ring(720, 1e-13)},
      {"smooth form 1e-4 mm", smooth_ring(720, 1e-4)},
      {"symmetric polygon", vcmm::test::symmetric_polygon(720)},
      {"integer points on a circle", vcmm::test::lattice_circle(720)},
  };
  for (const Family& fam : base) {
    SCOPED_TRACE(fam.name);
    {
      SCOPED_TRACE("rotated by 90 degrees");
      std::vector<Point2> r;
      for (const Point2& q : fam.pts) r.push_back({-q.y, q.x});
      expect_same_optimum(fam.pts, r, [](const Q& x, const Q& y) { return std::pair<Q, Q>{-y, x}; });
    }
    {
      // Exact only where the offset keeps every coordinate representable: checked first.
      const Point2 t{-512.125, -256.0625};
      std::vector<Point2> m;
      bool exact = true;
      for (const Point2& q : fam.pts) {
        m.push_back({q.x + t.x, q.y + t.y});
        exact = exact && m.back().x - t.x == q.x && m.back().y - t.y == q.y;
      }
      if (exact) {
        SCOPED_TRACE("translated");
        expect_same_optimum(fam.pts, m, [&](const Q& x, const Q& y) {
          return std::pair<Q, Q>{x + Q(t.x), y + Q(t.y)};
        });
      }
    }
    {
      SCOPED_TRACE("permuted");
      std::vector<Point2> s = fam.pts;
      std::uint64_t state = 7;
      for (std::size_t i = s.size(); i > 1; --i)
        std::swap(s[i - 1], s[static_cast<std::size_t>(vcmm::test::uniform01(state) *
                                                       static_cast<double>(i)) % i]);
      expect_same_optimum(fam.pts, s, [](const Q& x, const Q& y) { return std::pair<Q, Q>{x, y}; });
    }
  }
}

}  // namespace
