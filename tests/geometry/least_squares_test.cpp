// Tests of least_squares_circle: hand-checkable cases, properties over regimes (size,
// offset, arc span, density), agreement with an independent long-double fitter, and one
// bad-input test per precondition. Accuracy against NIST's reference fits is in
// nist_circle2d_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "../../geometry/src/internal/isa.h"
#include "../../geometry/src/internal/least_squares_on_rays.h"
#include "support/test_profiles.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/roundness_parameters.h"

namespace {

using vcmm::geometry::InvalidInput;
using vcmm::geometry::least_squares_circle;
using vcmm::geometry::LeastSquaresCircle;
using vcmm::geometry::Point2;
using vcmm::geometry::UndefinedResult;
using vcmm::test::Harmonic;
using vcmm::test::ring_profile;
using vcmm::test::RingSpec;

constexpr double kPi = std::numbers::pi;

// ---- an independent reference: full 3-parameter Gauss-Newton in long double ----------------
// Different formulation from the library (no elimination of R, no shifts, explicit 3x3
// normal equations), 64-bit significand: its answer is good to ~1e-17 relative, so it
// measures the library's double-precision error.
struct RefCircle {
  long double cx = 0, cy = 0, r = 0;
};

RefCircle reference_fit(const std::vector<Point2>& pts, RefCircle start) {
  RefCircle c = start;
  for (int it = 0; it < 200; ++it) {
    long double a[3][3] = {}, g[3] = {};
    for (const Point2& p : pts) {
      const long double dx = p.x - c.cx, dy = p.y - c.cy;
      const long double rr = std::sqrt(dx * dx + dy * dy);
      const long double j[3] = {-dx / rr, -dy / rr, -1.0L};  // ∂e/∂(cx, cy, R)
      const long double e = rr - c.r;
      for (int k = 0; k < 3; ++k) {
        g[k] += j[k] * e;
        for (int l = 0; l < 3; ++l) a[k][l] += j[k] * j[l];
      }
    }
    // Solve a δ = −g by Gaussian elimination with partial pivoting.
    long double m[3][4];
    for (int k = 0; k < 3; ++k) {
      for (int l = 0; l < 3; ++l) m[k][l] = a[k][l];
      m[k][3] = -g[k];
    }
    for (int col = 0; col < 3; ++col) {
      int piv = col;
      for (int k = col + 1; k < 3; ++k)
        if (std::fabs(m[k][col]) > std::fabs(m[piv][col])) piv = k;
      for (int l = 0; l < 4; ++l) std::swap(m[col][l], m[piv][l]);
      for (int k = col + 1; k < 3; ++k) {
        const long double f = m[k][col] / m[col][col];
        for (int l = col; l < 4; ++l) m[k][l] -= f * m[col][l];
      }
    }
    long double d[3];
    for (int k = 2; k >= 0; --k) {
      long double s = m[k][3];
      for (int l = k + 1; l < 3; ++l) s -= m[k][l] * d[l];
      d[k] = s / m[k][k];
    }
    c.cx += d[0];
    c.cy += d[1];
    c.r += d[2];
    if (std::fabs(d[0]) + std::fabs(d[1]) + std::fabs(d[2]) < 1e-18L * c.r) break;
  }
  return c;
}

long double center_error(const LeastSquaresCircle& fit, const RefCircle& ref) {
  const long double ex = fit.center.x - ref.cx, ey = fit.center.y - ref.cy;
  return std::sqrt(ex * ex + ey * ey);
}

std::vector<Point2> circle_points(Point2 c, double r, std::size_t n, double start = 0.0,
                                  double span = 2 * kPi) {
  std::vector<Point2> pts;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = start + span * static_cast<double>(i) / static_cast<double>(n);
    pts.push_back({c.x + r * std::cos(t), c.y + r * std::sin(t)});
  }
  return pts;
}

// ---- (a) cases a reader can check by hand ---------------------------------------------------

// Contacts are the first positions of the extreme distances: the peak and the valley each
// copied to a lower and a higher index (exact duplicates tie exactly), in either SIMD lane.
TEST(LeastSquaresCircle, TiedExtremesReportTheLowestIndex) {
  for (std::size_t n : {101u, 102u}) {
    std::vector<Point2> p = vcmm::test::lobed_noisy_ring(n, 3, 5e-5, {600.0, 500.0});
    const auto outward = [&](std::size_t i, double by) {
      const double dx = p[i].x - 600.0, dy = p[i].y - 500.0, r = std::hypot(dx, dy);
      p[i] = {600.0 + dx * (r + by) / r, 500.0 + dy * (r + by) / r};
    };
    outward(57, 2e-3);   // the peak
    outward(70, -2e-3);  // the valley
    for (std::size_t copy : {std::size_t{3}, std::size_t{58}, n - 1}) p[copy] = p[57];
    for (std::size_t copy : {std::size_t{4}, std::size_t{71}, n - 2}) p[copy] = p[70];
    const LeastSquaresCircle ls = least_squares_circle(p);
    EXPECT_EQ(ls.contacts[0], 3u) << n;
    EXPECT_EQ(ls.contacts[1], 4u) << n;
  }
}

TEST(LeastSquaresCircle, ExactIntegerCircle) {
  // The twelve integer points of the circle of radius 5 about (3, −2): (±5, 0), (0, ±5),
  // (±3, ±4), (±4, ±3).
  std::vector<Point2> pts;
  const int offsets[][2] = {{5, 0}, {-5, 0}, {0, 5},  {0, -5}, {3, 4},   {3, -4},
                            {-3, 4}, {-3, -4}, {4, 3}, {4, -3}, {-4, 3}, {-4, -3}};
  for (const auto& o : offsets) pts.push_back({3.0 + o[0], -2.0 + o[1]});
  const LeastSquaresCircle fit = least_squares_circle(pts);
  EXPECT_NEAR(fit.center.x, 3.0, 1e-14);
  EXPECT_NEAR(fit.center.y, -2.0, 1e-14);
  EXPECT_NEAR(fit.radius, 5.0, 1e-14);
  EXPECT_LT(fit.ron.ront, 1e-14);
  EXPECT_LT(fit.ron.ronq, 1e-14);
  EXPECT_GE(fit.iterations, 1);
  ASSERT_EQ(fit.contacts.size(), 2u);
}

TEST(LeastSquaresCircle, ThreePointsGiveTheCircumcircle) {
  // Right angle at the origin: the hypotenuse is a diameter.
  const std::vector<Point2> pts = {{0, 0}, {2, 0}, {0, 2}};
  const LeastSquaresCircle fit = least_squares_circle(pts);
  EXPECT_NEAR(fit.center.x, 1.0, 1e-15);
  EXPECT_NEAR(fit.center.y, 1.0, 1e-15);
  EXPECT_NEAR(fit.radius, std::sqrt(2.0), 1e-15);
  EXPECT_LT(fit.ron.ront, 1e-15);
}

TEST(LeastSquaresCircle, TwoLobeProfileByHand) {
  // r(θ) = R + a cos 2θ at n equiangular angles: by symmetry the LS centre is the origin;
  // with the centre there R = mean r = R (Σ cos 2θ_i = 0), RONt = 2a (θ = 0 and π/2 are
  // sampled), RONp = RONv = a, RONq = a/√2.
  RingSpec spec;
  spec.radius = 10.0;
  spec.n = 360;
  spec.harmonics = {Harmonic{2, 1e-3, 0.0}};
  const auto pts = ring_profile(spec);
  const LeastSquaresCircle fit = least_squares_circle(pts);
  EXPECT_NEAR(fit.center.x, 0.0, 1e-15);
  EXPECT_NEAR(fit.center.y, 0.0, 1e-15);
  EXPECT_NEAR(fit.radius, 10.0, 1e-14);
  EXPECT_NEAR(fit.ron.ront, 2e-3, 1e-14);
  EXPECT_NEAR(fit.ron.ronp, 1e-3, 1e-14);
  EXPECT_NEAR(fit.ron.ronv, 1e-3, 1e-14);
  EXPECT_NEAR(fit.ron.ronq, 1e-3 / std::sqrt(2.0), 1e-14);
  // Peak at θ = 0 or π (index 0 first), valley at θ = π/2 (index 90 first).
  EXPECT_EQ(fit.contacts[0], 0u);
  EXPECT_EQ(fit.contacts[1], 90u);
}

TEST(LeastSquaresCircle, EccentricOneLobe) {
  // Points on a circle of radius 2 about (0.5, 0): the fit recovers the circle, not the
  // origin — an eccentric profile is no form error.
  const auto pts = circle_points({0.5, 0.0}, 2.0, 64);
  const LeastSquaresCircle fit = least_squares_circle(pts);
  EXPECT_NEAR(fit.center.x, 0.5, 1e-15);
  EXPECT_NEAR(fit.center.y, 0.0, 1e-15);
  EXPECT_NEAR(fit.radius, 2.0, 1e-15);
}

// ---- (b) properties over regimes --------------------------------------------------------------

struct Regime {
  const char* name;
  double radius;
  Point2 center;
  std::size_t n;
  double span;  // 0 = full circle
  double form;  // amplitude of each of the harmonics (mm)
  double noise;
};

std::string regime_name(const ::testing::TestParamInfo<Regime>& param_info) {
  return param_info.param.name;
}

class LeastSquaresRegimes : public ::testing::TestWithParam<Regime> {};

std::vector<Point2> regime_profile(const Regime& g, std::uint64_t seed) {
  RingSpec spec;
  spec.center = g.center;
  spec.radius = g.radius;
  spec.n = g.n;
  spec.span = g.span;
  spec.start_angle = 0.37;
  spec.harmonics = {Harmonic{2, g.form, 0.3}, Harmonic{3, 0.6 * g.form, 1.1},
                    Harmonic{5, 0.3 * g.form, 2.0}, Harmonic{15, 0.1 * g.form, 2.9}};
  spec.noise_sigma = g.noise;
  spec.angle_jitter = 0.3;
  spec.seed = seed;
  return ring_profile(spec);
}

// Agreement with the long-double reference, started at the nominal circle. The bound is
// relative to the distance scale (radius + distance from the origin) and grows with the
// conditioning of short arcs, taken as (2π / span)².
TEST_P(LeastSquaresRegimes, MatchesLongDoubleReference) {
  const Regime g = GetParam();
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto pts = regime_profile(g, seed);
    const LeastSquaresCircle fit = least_squares_circle(pts);
    const RefCircle ref = reference_fit(pts, {g.center.x, g.center.y, g.radius});
    const double span = g.span > 0 ? g.span : 2 * kPi;
    const double conditioning = std::max(1.0, std::pow(2 * kPi / span, 2.0));
    const double scale = g.radius + std::hypot(g.center.x, g.center.y);
    // Observed: ≤ 2 eps·scale·conditioning over these regimes and seeds.
    const long double tol = 8.0L * std::numeric_limits<double>::epsilon() * scale * conditioning;
    EXPECT_LT(center_error(fit, ref), tol);
    EXPECT_LT(std::fabs(fit.radius - ref.r), tol);
    EXPECT_LE(fit.iterations, 10);
  }
}

TEST_P(LeastSquaresRegimes, RonIsAboutTheReportedCircle) {
  const Regime g = GetParam();
  const auto pts = regime_profile(g, 11);
  const LeastSquaresCircle fit = least_squares_circle(pts);
  const auto ron = vcmm::geometry::roundness_parameters(pts, fit.center, fit.radius);
  // Same quantities computed from the original coordinates: they differ only by the
  // rounding of |p − c| (a few ulps of the distance scale).
  const double tol = 16 * std::numeric_limits<double>::epsilon() *
                     (g.radius + std::hypot(g.center.x, g.center.y));
  EXPECT_NEAR(fit.ron.ront, ron.ront, tol);
  EXPECT_NEAR(fit.ron.ronp, ron.ronp, tol);
  EXPECT_NEAR(fit.ron.ronv, ron.ronv, tol);
  EXPECT_NEAR(fit.ron.ronq, ron.ronq, tol);
  // Contacts hold the extreme residuals.
  const auto dist = [&](std::size_t i) {
    return std::hypot(pts[i].x - fit.center.x, pts[i].y - fit.center.y);
  };
  for (std::size_t i = 0; i < pts.size(); ++i) {
    EXPECT_LE(dist(i), dist(fit.contacts[0]) + tol);
    EXPECT_GE(dist(i), dist(fit.contacts[1]) - tol);
  }
  // Σ e_i = 0 (R is the mean distance), so the peak is above and the valley below R.
  EXPECT_GE(fit.ron.ronp, 0.0);
  EXPECT_GE(fit.ron.ronv, 0.0);
  EXPECT_NEAR(fit.ron.ronp + fit.ron.ronv, fit.ron.ront, tol);
}

TEST_P(LeastSquaresRegimes, InvariantUnderRotationTranslationPermutation) {
  const Regime g = GetParam();
  const auto pts = regime_profile(g, 21);
  const LeastSquaresCircle fit = least_squares_circle(pts);
  const double span = g.span > 0 ? g.span : 2 * kPi;
  const double conditioning = std::max(1.0, std::pow(2 * kPi / span, 2.0));
  const double tol = 128 * std::numeric_limits<double>::epsilon() * conditioning *
                     (g.radius + std::hypot(g.center.x, g.center.y) + 900.0);

  // Rotation by 1 rad about the origin, then a translation by (−700, 550).
  const double ca = std::cos(1.0), sa = std::sin(1.0);
  std::vector<Point2> moved;
  for (const Point2& p : pts) moved.push_back({ca * p.x - sa * p.y - 700.0, sa * p.x + ca * p.y + 550.0});
  const LeastSquaresCircle fm = least_squares_circle(moved);
  EXPECT_NEAR(fm.center.x, ca * fit.center.x - sa * fit.center.y - 700.0, tol);
  EXPECT_NEAR(fm.center.y, sa * fit.center.x + ca * fit.center.y + 550.0, tol);
  EXPECT_NEAR(fm.radius, fit.radius, tol);
  EXPECT_NEAR(fm.ron.ront, fit.ron.ront, tol);

  // Reversal of the order (and a rotation of the start): same circle; contacts follow.
  std::vector<Point2> perm(pts.rbegin(), pts.rend());
  std::rotate(perm.begin(), perm.begin() + static_cast<std::ptrdiff_t>(perm.size() / 3), perm.end());
  const LeastSquaresCircle fp = least_squares_circle(perm);
  EXPECT_NEAR(fp.center.x, fit.center.x, tol);
  EXPECT_NEAR(fp.center.y, fit.center.y, tol);
  EXPECT_NEAR(fp.radius, fit.radius, tol);
  EXPECT_NEAR(fp.ron.ront, fit.ron.ront, tol);
}

// Regimes: radius 1 µm … 10 m, at the origin and ~900 mm away; full circles, 180°, 90°,
// 30° arcs; 3 … 36 000 points; smooth, lobed and noisy.
INSTANTIATE_TEST_SUITE_P(
    Regimes, LeastSquaresRegimes,
    ::testing::Values(
        Regime{"Ring3600", 85.5, {0, 0}, 3600, 0, 1e-4, 5e-5},
        Regime{"Ring3600Far", 85.5, {812.3, -555.1}, 3600, 0, 1e-4, 5e-5},
        Regime{"Ring36000", 85.5, {10, 20}, 36000, 0, 1e-4, 5e-5},
        Regime{"Tiny", 1e-3, {0.5, 0.25}, 200, 0, 1e-7, 1e-8},
        Regime{"Huge", 1e4, {-3e3, 2e3}, 720, 0, 1e-2, 1e-3},
        Regime{"RoughForm", 20.0, {1, 1}, 720, 0, 0.2, 0.01},
        // Deviations near the top of the distance series' range (|s| ≲ 2⁻⁹, near_circle.h),
        // and just beyond it: the first pass redone with degree 6, or with square roots.
        Regime{"SeriesEdge", 10.0, {-40, 70}, 1001, 0, 2e-3, 1e-4},
        Regime{"BeyondSeries", 10.0, {-40, 70}, 1001, 0, 6e-3, 1e-4},
        Regime{"Ring3601", 85.5, {0, 0}, 3601, 0, 1e-4, 5e-5},
        Regime{"Ring1007", 85.5, {1, 2}, 1007, 0, 1e-4, 5e-5},  // n mod 8 = 7
        Regime{"Half", 30.0, {100, 100}, 500, kPi, 1e-3, 1e-4},
        Regime{"Quarter", 30.0, {-900, 0}, 400, kPi / 2, 1e-3, 1e-4},
        Regime{"Arc30deg", 50.0, {0, 0}, 300, kPi / 6, 1e-4, 1e-5},
        Regime{"Arc30degFar", 50.0, {600, 600}, 300, kPi / 6, 1e-4, 1e-5},
        Regime{"Sparse5", 12.0, {3, 4}, 5, 0, 1e-3, 0},
        Regime{"Sparse3", 12.0, {3, 4}, 3, 0, 1e-3, 0},
        Regime{"Sparse4Arc", 12.0, {0, 0}, 4, kPi / 2, 1e-3, 0}),
    regime_name);

// The Gauss-Newton passes run as AVX-512, AVX2 or baseline (SSE2) code (internal/isa.h), with
// their sums in the same four lanes: the same bits whichever runs (each variant the CPU lacks
// falls back to the next narrower one).
TEST_P(LeastSquaresRegimes, InstructionSetVariantsGiveTheSameBits) {
  using vcmm::geometry::internal::IsaLevel;
  const Regime g = GetParam();
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const auto pts = regime_profile(g, seed);
    const LeastSquaresCircle fit = least_squares_circle(pts);
    for (const IsaLevel isa : {IsaLevel::avx2, IsaLevel::baseline}) {
      LeastSquaresCircle other;
      {
        const vcmm::geometry::internal::LimitIsa limit(isa);
        other = least_squares_circle(pts);
      }
      const int v = static_cast<int>(isa);
      EXPECT_EQ(std::memcmp(&fit.center, &other.center, sizeof fit.center), 0) << seed << v;
      EXPECT_EQ(std::memcmp(&fit.radius, &other.radius, sizeof fit.radius), 0) << seed << v;
      EXPECT_EQ(std::memcmp(&fit.ron, &other.ron, sizeof fit.ron), 0) << seed << v;
      EXPECT_EQ(fit.contacts, other.contacts) << seed << v;
      EXPECT_EQ(fit.iterations, other.iterations) << seed << v;
    }
  }
}

// The one step on rays (the filter's output, internal/least_squares_on_rays.h) runs as
// AVX-512 or baseline code: the same bits, for every n mod 8 (blocks of 8, packets of 2, an
// odd last point).
TEST(LeastSquaresCircleOnRays, InstructionSetVariantsGiveTheSameBits) {
  using vcmm::geometry::internal::IsaLevel;
  using vcmm::geometry::internal::least_squares_circle_on_rays;
  std::mt19937_64 rng(20261127);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (const std::size_t n : {3, 5, 8, 9, 12, 14, 15, 1007, 3600, 3601, 3602, 3604, 3606}) {
    // Rays from the centre, slightly off an equiangular grid and not of unit length.
    std::vector<double> w(n), rx(n), ry(n), inv(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double a = 2.0 * kPi * (static_cast<double>(i) + 1e-6 * noise(rng)) /
                       static_cast<double>(n);
      const double len = 85.5 * (1.0 + 1e-5 * noise(rng));
      rx[i] = len * std::cos(a);
      ry[i] = len * std::sin(a);
      inv[i] = 1.0 / std::hypot(rx[i], ry[i]);
      w[i] = 1e-4 * std::cos(3.0 * a + 0.3) + 1e-9 * noise(rng);  // LS centre ≈ c
    }
    const Point2 c{10.0, -20.0};
    const auto fit = least_squares_circle_on_rays(c, 85.5, w.data(), rx.data(), ry.data(),
                                                  inv.data(), n);
    ASSERT_TRUE(fit.has_value()) << n;
    for (const IsaLevel isa : {IsaLevel::avx2, IsaLevel::baseline}) {
      std::optional<LeastSquaresCircle> other;
      {
        const vcmm::geometry::internal::LimitIsa limit(isa);
        other = least_squares_circle_on_rays(c, 85.5, w.data(), rx.data(), ry.data(),
                                             inv.data(), n);
      }
      ASSERT_TRUE(other.has_value()) << n;
      EXPECT_EQ(std::memcmp(&fit->center, &other->center, sizeof fit->center), 0) << n;
      EXPECT_EQ(std::memcmp(&fit->radius, &other->radius, sizeof fit->radius), 0) << n;
      EXPECT_EQ(std::memcmp(&fit->ron, &other->ron, sizeof fit->ron), 0) << n;
      EXPECT_EQ(fit->contacts, other->contacts) << n;
    }
  }
}

TEST(LeastSquaresCircle, DuplicatesCountWithTheirMultiplicity) {
  RingSpec spec;
  spec.n = 40;
  spec.radius = 5.0;
  spec.harmonics = {Harmonic{3, 0.05, 0.4}};
  spec.noise_sigma = 0.01;
  const auto pts = ring_profile(spec);
  // Every point twice: the same circle.
  std::vector<Point2> twice;
  for (const Point2& p : pts) {
    twice.push_back(p);
    twice.push_back(p);
  }
  const LeastSquaresCircle a = least_squares_circle(pts), b = least_squares_circle(twice);
  EXPECT_NEAR(a.center.x, b.center.x, 1e-14);
  EXPECT_NEAR(a.center.y, b.center.y, 1e-14);
  EXPECT_NEAR(a.radius, b.radius, 1e-14);
  EXPECT_NEAR(a.ron.ronq, b.ron.ronq, 1e-15);
  // One point ten times: the weighted problem, checked against the reference fit of the
  // list that holds the copies.
  std::vector<Point2> heavy = pts;
  for (int k = 0; k < 9; ++k) heavy.push_back(pts[7]);
  const LeastSquaresCircle h = least_squares_circle(heavy);
  const RefCircle ref = reference_fit(heavy, {0, 0, 5.0});
  EXPECT_LT(center_error(h, ref), 1e-14L);
  EXPECT_LT(std::fabs(h.radius - ref.r), 1e-14L);
  EXPECT_GT(std::hypot(h.center.x - a.center.x, h.center.y - a.center.y), 1e-4);  // it moved
  // A closed scan that repeats its first point is accepted.
  std::vector<Point2> closed = pts;
  closed.push_back(pts.front());
  EXPECT_NO_THROW(least_squares_circle(closed));
}

TEST(LeastSquaresCircle, NearlyCollinearPointsGiveTheLargeCircle) {
  // Three points with a sagitta of 1e-6 over a chord of 2: R = (1 + s²)/(2s) ≈ 5e5.
  const double s = 1e-6;
  const std::vector<Point2> pts = {{-1, 0}, {0, s}, {1, 0}};
  const LeastSquaresCircle fit = least_squares_circle(pts);
  const double r = (1 + s * s) / (2 * s);
  EXPECT_NEAR(fit.radius, r, 1e-9 * r);
  EXPECT_NEAR(fit.center.y, s - r, 1e-9 * r);
  EXPECT_NEAR(fit.center.x, 0.0, 1e-9 * r);
}

TEST(LeastSquaresCircle, TooNearlyStraightForDoublePrecisionIsUndefined) {
  // Sagitta 1e-12 over a chord of 2 (R ≈ 5e11): the unit directions agree to 1e-24, below
  // double precision, so the Gauss-Newton matrix is singular in double. Not exactly collinear
  // (that is InvalidInput), but no circle can be fitted: UndefinedResult, saying why.
  const std::vector<Point2> pts = {{-1, 0}, {0, 1e-12}, {1, 0}, {0.5, 0.75e-12}};
  try {
    least_squares_circle(pts);
    ADD_FAILURE() << "expected UndefinedResult";
  } catch (const UndefinedResult& e) {
    EXPECT_NE(std::string(e.what()).find("straight line"), std::string::npos) << e.what();
  }
}

// ---- (d) bad input: one test per precondition -------------------------------------------------

void expect_invalid(const std::vector<Point2>& pts, const std::string& fragment) {
  try {
    least_squares_circle(pts);
    ADD_FAILURE() << "expected InvalidInput mentioning '" << fragment << "'";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("least_squares_circle"), std::string::npos) << what;
    EXPECT_NE(what.find(fragment), std::string::npos) << what;
  }
}

TEST(LeastSquaresCircleBadInput, TooFewPoints) {
  expect_invalid({}, "at least 3");
  expect_invalid({{0, 0}, {1, 1}}, "at least 3");
}

TEST(LeastSquaresCircleBadInput, NonFiniteCoordinate) {
  expect_invalid({{0, 0}, {1, 0}, {std::nan(""), 1}}, "point 2");
  expect_invalid({{0, 0}, {1, std::numeric_limits<double>::infinity()}, {0, 1}}, "point 1");
}

// The finiteness check runs inside the fit's first pass (from its moments): every position
// (the AVX-512 blocks, the 2-point packets, the odd last point, the first point the others are
// shifted by), NaN and ±∞, in x or in y, on every instruction-set variant — the same message as
// validate_profile's, naming the point.
TEST(LeastSquaresCircleBadInput, NonFiniteCoordinateAnywhereIsNamed) {
  using vcmm::geometry::internal::IsaLevel;
  const double bad[] = {std::nan(""), std::numeric_limits<double>::infinity(),
                        -std::numeric_limits<double>::infinity()};
  for (const std::size_t n : {std::size_t{3}, std::size_t{64}, std::size_t{101}}) {
    const auto ring = circle_points({812.3, -555.1}, 85.5, n);
    for (const IsaLevel isa : {IsaLevel::avx512, IsaLevel::avx2, IsaLevel::baseline}) {
      const vcmm::geometry::internal::LimitIsa limit(isa);
      for (std::size_t i = 0; i < n; ++i)
        for (const double v : bad)
          for (int coordinate = 0; coordinate < 2; ++coordinate) {
            auto pts = ring;
            (coordinate == 0 ? pts[i].x : pts[i].y) = v;
            std::string expected;
            try {
              validate_profile(pts, 3, "least_squares_circle");
            } catch (const InvalidInput& e) {
              expected = e.what();
            }
            ASSERT_NE(expected.find("point " + std::to_string(i) + " "), std::string::npos);
            try {
              least_squares_circle(pts);
              ADD_FAILURE() << "fitted with a non-finite point " << i;
            } catch (const InvalidInput& e) {
              EXPECT_EQ(std::string(e.what()), expected) << n << " " << i;
            }
          }
    }
  }
}

TEST(LeastSquaresCircleBadInput, CollinearOrIdentical) {
  expect_invalid({{0, 0}, {1, 1}, {2, 2}, {-5, -5}}, "collinear");
  expect_invalid({{0, 0}, {1, 1}, {0, 0}, {1, 1}}, "collinear");  // two distinct points
  expect_invalid({{3, 3}, {3, 3}, {3, 3}}, "identical");
}

// Issue 12: a circle of radius 1e70 mm was called "too close to a straight line". Spans
// outside 1e-50 … 1e50 mm are refused as such, naming the span; spans just inside still fit.
TEST(LeastSquaresCircle, SpanOutsideTheDoubleRangeOfItsMomentsIsNamed) {
  for (const double r : {1e70, 1e-70, 1e300, 1e-300}) {
    SCOPED_TRACE(r);
    try {
      least_squares_circle(circle_points({0, 0}, r, 100));
      ADD_FAILURE() << "fitted a circle of radius " << r;
    } catch (const InvalidInput& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("the points span "), std::string::npos) << what;
      EXPECT_NE(what.find("1e-50 to 1e+50 mm"), std::string::npos) << what;
      EXPECT_EQ(what.find("straight line"), std::string::npos) << what;
    }
  }
  for (const double r : {1e45, 1e-45}) {
    const LeastSquaresCircle fit = least_squares_circle(circle_points({3 * r, -r}, r, 100));
    EXPECT_NEAR(fit.radius / r, 1.0, 1e-12) << r;
    EXPECT_NEAR(fit.center.x / r, 3.0, 1e-12) << r;
  }
}

}  // namespace
