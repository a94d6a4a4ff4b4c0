// tests/geometry/minimum_zone_test.cpp — the minimum-zone (MZ) circles: hand-checkable
// cases, sparse data and partial arcs against the exhaustive exact oracle, invariance
// properties, far-from-origin data, duplicated points, global-optimality claims, and one
// bad-input test per precondition. Every result is re-checked by verify() (certificate.cpp,
// independent exact checker) and by a small exact containment check of our own.
#include "vcmm/geometry/minimum_zone.h"

#include <gtest/gtest.h>

#include <CGAL/Exact_rational.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

#include "support/exhaustive_oracle.h"
#include "support/test_profiles.h"
#include "vcmm/geometry/certificate.h"

namespace vcmm::geometry {
namespace {

using Q = CGAL::Exact_rational;
using test::lobed_noisy_ring;
using test::ring_profile;
using test::RingSpec;

MinimumZoneOptions exchange_only() {
  MinimumZoneOptions o;
  o.method = MinimumZoneMethod::exchange;
  return o;
}

/// Our own exact check (independent of verify): the exact centre of the 2+2 contacts, all
/// points in the closed annulus, reported values near the exact ones.
void expect_exact_annulus(std::span<const Point2> pts, const MinimumZoneCircle& mz) {
  ASSERT_EQ(mz.outer_contacts.size(), 2u);
  ASSERT_EQ(mz.inner_contacts.size(), 2u);
  const Point2 a = pts[mz.outer_contacts[0]], b = pts[mz.outer_contacts[1]];
  const Point2 e = pts[mz.inner_contacts[0]], d = pts[mz.inner_contacts[1]];
  const Q bx = Q(b.x) - Q(a.x), by = Q(b.y) - Q(a.y);
  const Q ax = Q(d.x) - Q(e.x), ay = Q(d.y) - Q(e.y);
  const Q r1 = (Q(b.x) * Q(b.x) + Q(b.y) * Q(b.y) - Q(a.x) * Q(a.x) - Q(a.y) * Q(a.y)) / 2;
  const Q r2 = (Q(d.x) * Q(d.x) + Q(d.y) * Q(d.y) - Q(e.x) * Q(e.x) - Q(e.y) * Q(e.y)) / 2;
  const Q det = bx * ay - by * ax;
  ASSERT_NE(CGAL::sign(det), 0);
  const Q cx = (r1 * ay - by * r2) / det, cy = (bx * r2 - r1 * ax) / det;
  auto dist2 = [&](Point2 p) {
    const Q dx = Q(p.x) - cx, dy = Q(p.y) - cy;
    return Q(dx * dx + dy * dy);
  };
  const Q R2 = dist2(a), r2sq = dist2(e);
  EXPECT_EQ(dist2(b), R2);
  EXPECT_EQ(dist2(d), r2sq);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Q s = dist2(pts[i]);
    ASSERT_FALSE(s > R2) << "point " << i << " outside the outer circle";
    ASSERT_FALSE(s < r2sq) << "point " << i << " inside the inner circle";
  }
  const double R = std::sqrt(CGAL::to_double(R2)), r = std::sqrt(CGAL::to_double(r2sq));
  // Centre, radii within a few ulps; RONt within a few ulps of itself (not of R).
  const double ex = CGAL::to_double(cx), ey = CGAL::to_double(cy);
  EXPECT_NEAR(mz.center.x, ex, 4 * std::abs(ex) * 1.2e-16 + 1e-300);
  EXPECT_NEAR(mz.center.y, ey, 4 * std::abs(ey) * 1.2e-16 + 1e-300);
  EXPECT_NEAR(mz.outer_radius, R, 4 * R * 1.2e-16);
  EXPECT_NEAR(mz.inner_radius, r, 4 * r * 1.2e-16);
  const double w = CGAL::to_double(Q(R2 - r2sq)) / (R + r);
  EXPECT_NEAR(mz.ron.ront, w, 8 * w * 1.2e-16);
  EXPECT_DOUBLE_EQ(mz.ron.ronp, 0.5 * mz.ron.ront);
  EXPECT_DOUBLE_EQ(mz.ron.ronv, 0.5 * mz.ron.ront);
  // RONq about the mean circle, directly (long double).
  long double sum = 0.0L;
  const long double rm = 0.5L * (static_cast<long double>(mz.outer_radius) + mz.inner_radius);
  for (const Point2& p : pts) {
    const long double dx = static_cast<long double>(p.x) - mz.center.x;
    const long double dy = static_cast<long double>(p.y) - mz.center.y;
    const long double dev = std::sqrt(dx * dx + dy * dy) - rm;
    sum += dev * dev;
  }
  const double ronq = static_cast<double>(std::sqrt(sum / static_cast<long double>(pts.size())));
  EXPECT_NEAR(mz.ron.ronq, ronq, 1e-9 * ronq + 1e-14 * static_cast<double>(rm));
  EXPECT_LE(mz.ron.ronq, 0.5 * mz.ron.ront * (1 + 1e-9));
}

void expect_valid(std::span<const Point2> pts, const MinimumZoneCircle& mz) {
  const Verification v = verify(pts, mz);
  EXPECT_TRUE(v.valid) << v.reason << "\ncertificate: " << mz.certificate.argument;
  if (mz.outer_contacts.size() == 2) expect_exact_annulus(pts, mz);
}

std::set<std::pair<double, double>> as_set(std::span<const Point2> pts,
                                           const std::vector<std::size_t>& idx) {
  std::set<std::pair<double, double>> s;
  for (std::size_t i : idx) s.insert({pts[i].x, pts[i].y});
  return s;
}

/// Snaps coordinates to a 2^-30 mm grid so translations by grid multiples are exact.
std::vector<Point2> snapped(std::vector<Point2> pts) {
  for (Point2& p : pts) {
    p.x = std::ldexp(std::nearbyint(std::ldexp(p.x, 30)), -30);
    p.y = std::ldexp(std::nearbyint(std::ldexp(p.y, 30)), -30);
  }
  return pts;
}

// ── (a) cases checkable by hand ─────────────────────────────────────────────────────────

TEST(MinimumZone, FourPointsKnownAnnulusSharp) {
  // Outer (±3, 0) on R = 3, inner (0, ±2.5) on r = 2.5: centre (0, 0), RONt = 0.5.
  const std::vector<Point2> pts{{3, 0}, {0, 2.5}, {-3, 0}, {0, -2.5}};
  for (const MinimumZoneOptions& opt : {MinimumZoneOptions{}, exchange_only()}) {
    const MinimumZoneCircle mz = minimum_zone_circle(pts, opt);
    EXPECT_EQ(mz.center, (Point2{0, 0}));
    EXPECT_EQ(mz.outer_radius, 3.0);
    EXPECT_EQ(mz.inner_radius, 2.5);
    EXPECT_EQ(mz.ron.ront, 0.5);
    EXPECT_EQ(mz.outer_contacts, (std::vector<std::size_t>{0, 2}));
    EXPECT_EQ(mz.inner_contacts, (std::vector<std::size_t>{1, 3}));
    EXPECT_EQ(mz.certificate.optimality, Optimality::global) << mz.certificate.argument;
    expect_valid(pts, mz);
  }
}

TEST(MinimumZone, FourPointsKnownAnnulusByExhaustion) {
  // Outer (±2, 0), inner (0, ±1): width 1 equals the inner contacts' distance to the outer
  // pair's line, so the sharpness test is inconclusive; global by exhaustion (n ≤ 10).
  const std::vector<Point2> pts{{2, 0}, {0, 1}, {-2, 0}, {0, -1}};
  const MinimumZoneCircle mz = minimum_zone_circle(pts, exchange_only());
  EXPECT_EQ(mz.center, (Point2{0, 0}));
  EXPECT_EQ(mz.ron.ront, 1.0);
  EXPECT_EQ(mz.certificate.optimality, Optimality::global) << mz.certificate.argument;
  EXPECT_NE(mz.certificate.argument.find("exhausted"), std::string::npos);
  expect_valid(pts, mz);
}

TEST(MinimumZone, PureThreeLobeHasWidthTwiceTheAmplitude) {
  // r(θ) = R + a cos 3θ sampled at 360 angles including every peak and valley: MZ width 2a
  // (the centre stays at the symmetry centre). Three-fold ties: exercises the exact repair.
  for (const double a : {1e-3, 2e-4}) {
    RingSpec spec;
    spec.radius = 50.0;
    spec.n = 360;
    spec.harmonics = {{3, a, 0.0}};
    const std::vector<Point2> pts = ring_profile(spec);
    const MinimumZoneCircle mz = minimum_zone_circle(pts, exchange_only());
    EXPECT_NEAR(mz.ron.ront, 2 * a, 1e-12) << "a = " << a;
    EXPECT_NEAR(mz.center.x, 0.0, 1e-12);
    EXPECT_NEAR(mz.center.y, 0.0, 1e-12);
    expect_valid(pts, mz);
  }
}

TEST(MinimumZone, LobedShapesMatchTheirPeakToValley) {
  // Odd lobing of order k sampled with every peak and valley: width 2a.
  for (const int k : {5, 7, 15}) {
    RingSpec spec;
    spec.n = 72 * static_cast<std::size_t>(k);  // peaks every 72 samples, valleys between
    spec.harmonics = {{k, 5e-4, 0.0}};
    const std::vector<Point2> pts = ring_profile(spec);
    const MinimumZoneCircle mz = minimum_zone_circle(pts);
    EXPECT_NEAR(mz.ron.ront, 1e-3, 1e-12) << "k = " << k;
    expect_valid(pts, mz);
  }
}

TEST(MinimumZone, CoCircularPointsGiveZeroWidth) {
  // Pythagorean points: exactly on the circle of radius 5 about (0, 0).
  const std::vector<Point2> pts{{3, 4}, {4, 3}, {5, 0}, {0, 5}, {-3, 4}, {-5, 0}, {0, -5},
                                {4, -3}, {-4, -3}};
  const MinimumZoneCircle mz = minimum_zone_circle(pts);
  EXPECT_EQ(mz.ron.ront, 0.0);
  EXPECT_EQ(mz.ron.ronq, 0.0);
  EXPECT_EQ(mz.center, (Point2{0, 0}));
  EXPECT_EQ(mz.outer_radius, 5.0);
  EXPECT_EQ(mz.inner_radius, 5.0);
  EXPECT_EQ(mz.outer_contacts.size(), 3u);
  EXPECT_EQ(mz.outer_contacts, mz.inner_contacts);
  EXPECT_EQ(mz.certificate.optimality, Optimality::global);
  expect_valid(pts, mz);
}

TEST(MinimumZone, ThreePointsGiveZeroWidth) {
  const std::vector<Point2> pts{{0, 0}, {4, 0}, {0, 2}};
  const MinimumZoneCircle mz = minimum_zone_circle(pts, exchange_only());
  EXPECT_EQ(mz.ron.ront, 0.0);
  EXPECT_EQ(mz.center, (Point2{2, 1}));
  EXPECT_DOUBLE_EQ(mz.outer_radius, std::sqrt(5.0));
  EXPECT_EQ(mz.outer_contacts, (std::vector<std::size_t>{0, 1, 2}));
  expect_valid(pts, mz);
}

// ── (b) sparse data and partial arcs against the exhaustive oracle ─────────────────────

void expect_matches_oracle(std::span<const Point2> pts, const MinimumZoneCircle& mz) {
  const test::OracleMinimumZone oracle = test::oracle_minimum_zone(pts);
  ASSERT_EQ(oracle.status, test::OracleStatus::defined) << oracle.explanation;
  ASSERT_FALSE(oracle.zero_width);
  const auto z = test::exact_zone(pts, mz.outer_contacts[0], mz.outer_contacts[1],
                                  mz.inner_contacts[0], mz.inner_contacts[1]);
  ASSERT_TRUE(z.has_value());
  EXPECT_EQ(test::compare_sqrt_differences(z->outer2, z->inner2, oracle.outer2, oracle.inner2),
            0)
      << "width differs from the oracle's optimum " << test::cpp_literal(pts);
}

TEST(MinimumZone, SparseFourAndFivePointsMatchOracle) {
  int global = 0, total = 0;
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    for (const std::size_t n : {4u, 5u}) {
      // Points near a circle with large form (sparse roundness data).
      std::uint64_t st = seed * 7919 + n;
      std::vector<Point2> pts;
      for (std::size_t i = 0; i < n; ++i) {
        const double jitter = 0.6 * test::uniform01(st);
        const double t =
            2 * std::numbers::pi * (static_cast<double>(i) + jitter) / static_cast<double>(n);
        const double r = 10.0 + 0.5 * test::standard_normal(st);
        pts.push_back({r * std::cos(t), r * std::sin(t)});
      }
      const test::OracleMinimumZone oracle = test::oracle_minimum_zone(pts);
      if (oracle.status != test::OracleStatus::defined || oracle.zero_width) continue;
      SCOPED_TRACE(::testing::Message() << "seed " << seed << " n " << n << " "
                                        << test::cpp_literal(pts));
      for (const MinimumZoneOptions& opt : {MinimumZoneOptions{}, exchange_only()}) {
        const MinimumZoneCircle mz = minimum_zone_circle(pts, opt);
        ++total;
        global += mz.certificate.optimality == Optimality::global;
        expect_valid(pts, mz);
        expect_matches_oracle(pts, mz);
      }
    }
  }
  EXPECT_GT(total, 160);
  EXPECT_EQ(global, total);
}

TEST(MinimumZone, PartialArcsMatchOracleWhenSparse) {
  for (const double span_deg : {90.0, 30.0}) {
    for (std::uint64_t seed = 1; seed <= 10; ++seed) {
      RingSpec spec;
      spec.radius = 40.0;
      spec.n = 10;
      spec.span = span_deg * std::numbers::pi / 180.0;
      spec.start_angle = 0.3 * static_cast<double>(seed);
      spec.noise_sigma = 2e-3;
      spec.seed = seed;
      const std::vector<Point2> pts = ring_profile(spec);
      const test::OracleMinimumZone oracle = test::oracle_minimum_zone(pts);
      if (oracle.status != test::OracleStatus::defined) continue;
      SCOPED_TRACE(::testing::Message() << "span " << span_deg << " seed " << seed);
      const MinimumZoneCircle mz = minimum_zone_circle(pts);
      expect_valid(pts, mz);
      expect_matches_oracle(pts, mz);
    }
  }
}

TEST(MinimumZone, DensePartialArcsAreCertified) {
  for (const double span_deg : {90.0, 30.0}) {
    RingSpec spec;
    spec.n = 900;
    spec.span = span_deg * std::numbers::pi / 180.0;
    spec.start_angle = 0.7;
    spec.harmonics = {{2, 1e-4, 0.3}, {5, 3e-5, 1.0}};
    spec.noise_sigma = 5e-5;
    const std::vector<Point2> pts = ring_profile(spec);
    SCOPED_TRACE(::testing::Message() << "span " << span_deg);
    const MinimumZoneCircle mz = minimum_zone_circle(pts, exchange_only());
    expect_valid(pts, mz);
    EXPECT_NEAR(mz.outer_radius, 85.5, 0.01);
    // The automatic method agrees (same zone width).
    const MinimumZoneCircle mz_auto = minimum_zone_circle(pts);
    EXPECT_EQ(mz_auto.ron.ront, mz.ron.ront);
  }
}

// ── (b) properties ──────────────────────────────────────────────────────────────────────

TEST(MinimumZone, FarFromOriginSameWidthAsAtOrigin) {
  // 0.5 µm form on a 171 mm ring, centred at (0, 0) and at (900, −700) mm.
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    RingSpec spec;
    spec.harmonics = {{2, 1.5e-4, 0.3}, {3, 1e-4, 1.1}};
    spec.noise_sigma = 2e-5;
    spec.seed = seed;
    spec.n = 720;
    const MinimumZoneCircle at0 = minimum_zone_circle(ring_profile(spec));
    spec.center = {900.0, -700.0};
    const std::vector<Point2> far = ring_profile(spec);
    const MinimumZoneCircle atfar = minimum_zone_circle(far);
    EXPECT_NEAR(atfar.ron.ront, at0.ron.ront, 1e-12) << "seed " << seed;
    EXPECT_NEAR(atfar.center.x - 900.0, at0.center.x, 1e-9);
    EXPECT_NEAR(atfar.center.y + 700.0, at0.center.y, 1e-9);
    EXPECT_EQ(atfar.certificate.optimality, Optimality::global);
    expect_valid(far, atfar);
  }
}

TEST(MinimumZone, DuplicatedFirstPointIsReportedByLowestIndex) {
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    std::vector<Point2> pts = lobed_noisy_ring(360, seed);
    const MinimumZoneCircle plain = minimum_zone_circle(pts);
    // Rotate the scan so that a contact is the first point, then close it.
    const std::size_t c = plain.outer_contacts[seed % 2 == 0 ? 0 : 1];
    std::rotate(pts.begin(), pts.begin() + static_cast<std::ptrdiff_t>(c), pts.end());
    pts.push_back(pts.front());
    const MinimumZoneCircle mz = minimum_zone_circle(pts);
    EXPECT_EQ(mz.ron.ront, plain.ron.ront);
    for (const auto* list : {&mz.outer_contacts, &mz.inner_contacts}) {
      for (std::size_t i : *list) EXPECT_NE(i, pts.size() - 1) << "duplicate reported";
      EXPECT_NE(pts[(*list)[0]], pts[(*list)[1]]);
    }
    EXPECT_EQ(mz.outer_contacts[0], 0u);
    expect_valid(pts, mz);
  }
}

TEST(MinimumZone, AllDuplicatedClosedSparseScan) {
  // Five points, each listed twice: contacts must be distinct points, lowest indices.
  const std::vector<Point2> base{{10, 0}, {3.2, 9.4}, {-8.3, 5.7}, {-7.9, -6.3}, {2.9, -9.9}};
  std::vector<Point2> pts = base;
  pts.insert(pts.end(), base.begin(), base.end());
  const MinimumZoneCircle mz = minimum_zone_circle(pts);
  const MinimumZoneCircle ref = minimum_zone_circle(base);
  EXPECT_EQ(mz.outer_contacts, ref.outer_contacts);
  EXPECT_EQ(mz.inner_contacts, ref.inner_contacts);
  EXPECT_EQ(mz.ron.ront, ref.ron.ront);
  expect_valid(pts, mz);
}

TEST(MinimumZone, InvariantUnderExactTranslationRotationPermutation) {
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const std::vector<Point2> pts = snapped(lobed_noisy_ring(720, seed));
    const MinimumZoneCircle mz = minimum_zone_circle(pts);
    SCOPED_TRACE(::testing::Message() << "seed " << seed);
    // Translation by grid multiples: exact.
    std::vector<Point2> moved = pts;
    for (Point2& p : moved) p = {p.x + 500.0, p.y - 300.0};
    const MinimumZoneCircle mt = minimum_zone_circle(moved);
    EXPECT_EQ(mt.outer_contacts, mz.outer_contacts);
    EXPECT_EQ(mt.inner_contacts, mz.inner_contacts);
    EXPECT_EQ(mt.ron.ront, mz.ron.ront);
    EXPECT_EQ(mt.outer_radius, mz.outer_radius);
    // Rotation by 90°: exact.
    std::vector<Point2> turned = pts;
    for (Point2& p : turned) p = {-p.y, p.x};
    const MinimumZoneCircle mr = minimum_zone_circle(turned);
    EXPECT_EQ(mr.outer_contacts, mz.outer_contacts);
    EXPECT_EQ(mr.inner_contacts, mz.inner_contacts);
    EXPECT_EQ(mr.ron.ront, mz.ron.ront);
    EXPECT_EQ(mr.center, (Point2{-mz.center.y, mz.center.x}));
    // Permutation: same contacts as point sets.
    std::vector<Point2> shuffled = pts;
    std::mt19937_64 rng(seed);
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    const MinimumZoneCircle mp = minimum_zone_circle(shuffled);
    EXPECT_EQ(as_set(shuffled, mp.outer_contacts), as_set(pts, mz.outer_contacts));
    EXPECT_EQ(as_set(shuffled, mp.inner_contacts), as_set(pts, mz.inner_contacts));
    EXPECT_EQ(mp.ron.ront, mz.ron.ront);
    EXPECT_EQ(mp.center, mz.center);
    expect_valid(shuffled, mp);
  }
}

TEST(MinimumZone, TypicalRingsAreProvenGloballyOptimal) {
  for (const std::size_t n : {16u, 360u, 3600u}) {
    for (std::uint64_t seed = 1; seed <= 10; ++seed) {
      const std::vector<Point2> pts = lobed_noisy_ring(n, seed);
      const MinimumZoneCircle mz = minimum_zone_circle(pts, exchange_only());
      SCOPED_TRACE(::testing::Message() << "n " << n << " seed " << seed);
      EXPECT_EQ(mz.certificate.optimality, Optimality::global) << mz.certificate.argument;
      EXPECT_NE(mz.certificate.argument.find("unique global minimum"), std::string::npos);
      EXPECT_EQ(mz.certificate.region_radius, 0.0);
      EXPECT_GT(mz.ron.ront, 0.0);
      EXPECT_LT(mz.ron.ront, 2e-3);
      expect_valid(pts, mz);
    }
  }
}

TEST(MinimumZone, ExchangeAndOverlayAgree) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const std::vector<Point2> pts = lobed_noisy_ring(500, seed);
    const MinimumZoneCircle fast = minimum_zone_circle(pts, exchange_only());
    MinimumZoneOptions o;
    o.method = MinimumZoneMethod::overlay;
    const MinimumZoneCircle slow = minimum_zone_circle(pts, o);
    EXPECT_EQ(fast.ron.ront, slow.ron.ront) << "seed " << seed;
    EXPECT_EQ(fast.center, slow.center);
    EXPECT_EQ(as_set(pts, fast.outer_contacts), as_set(pts, slow.outer_contacts));
    EXPECT_EQ(as_set(pts, fast.inner_contacts), as_set(pts, slow.inner_contacts));
  }
}

TEST(MinimumZone, LocalCertificateWhenGlobalProofNotRequested) {
  const std::vector<Point2> pts = lobed_noisy_ring(360, 3);
  MinimumZoneOptions o = exchange_only();
  o.prove_global = false;
  const MinimumZoneCircle mz = minimum_zone_circle(pts, o);
  EXPECT_EQ(mz.certificate.optimality, Optimality::local);
  EXPECT_NE(mz.certificate.argument.find("alternating"), std::string::npos);
  expect_valid(pts, mz);
}

// ── (d) undefined results and bad input ─────────────────────────────────────────────────

TEST(MinimumZone, NearlyStraightDataIsUndefined) {
  // Zig-zag of ±1 µm about a straight line: every finite circle is worse than the strip,
  // which is approached only as the radius grows without bound.
  std::vector<Point2> pts;
  for (int i = 0; i < 20; ++i) pts.push_back({static_cast<double>(i), (i % 2 ? 1e-3 : -1e-3)});
  EXPECT_THROW(minimum_zone_circle(pts, exchange_only()), UndefinedResult);
  try {
    minimum_zone_circle(pts, exchange_only());
  } catch (const UndefinedResult& e) {
    EXPECT_NE(std::string(e.what()).find("minimum_zone_circle"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("straight"), std::string::npos);
  }
  EXPECT_THROW(minimum_zone_circle(pts), UndefinedResult);
}

TEST(MinimumZone, SparseNearlyStraightDataIsUndefinedExactly) {
  // Eight points zig-zagging by ±1 µm about a line: the exhaustive search of all
  // quadruples shows every finite zone is wider than the strip (the oracle agrees).
  std::vector<Point2> pts;
  for (int i = 0; i < 8; ++i) pts.push_back({static_cast<double>(i), (i % 2 ? 1e-3 : -1e-3)});
  ASSERT_EQ(test::oracle_minimum_zone(pts).status, test::OracleStatus::undefined);
  EXPECT_THROW(minimum_zone_circle(pts, exchange_only()), UndefinedResult);
  EXPECT_THROW(minimum_zone_circle(pts), UndefinedResult);
}

TEST(MinimumZone, RejectsBadInput) {
  const std::vector<Point2> two{{0, 0}, {1, 1}};
  EXPECT_THROW(minimum_zone_circle(two), InvalidInput);
  const std::vector<Point2> collinear{{0, 0}, {1, 1}, {2, 2}, {3, 3}};
  EXPECT_THROW(minimum_zone_circle(collinear), InvalidInput);
  const std::vector<Point2> same{{1, 1}, {1, 1}, {1, 1}};
  EXPECT_THROW(minimum_zone_circle(same), InvalidInput);
  std::vector<Point2> nan = lobed_noisy_ring(50, 1);
  nan[17].y = std::numeric_limits<double>::quiet_NaN();
  try {
    minimum_zone_circle(nan);
    ADD_FAILURE() << "NaN accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("minimum_zone_circle"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("17"), std::string::npos);
  }
  std::vector<Point2> inf = lobed_noisy_ring(50, 1);
  inf[3].x = std::numeric_limits<double>::infinity();
  EXPECT_THROW(minimum_zone_circle(inf), InvalidInput);
}

}  // namespace
}  // namespace vcmm::geometry
