// Tests of the ISO 16610-21 closed-profile Gaussian filter: exact per-harmonic transmission
// (H(0) = 1, H(f_c) = ½, H(2 f_c) = 1/16) for every standard cut-off, linearity, sizes of every
// kind (odd, prime: Bluestein), path detection, agreement of the FFT and nonuniform paths with
// the analytic filtered profile, invariances, and one bad-input test per precondition.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "support/test_profiles.h"
#include "vcmm/geometry/angular_coverage.h"
#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/roundness.h"

namespace {

using vcmm::geometry::FilteredProfile;
using vcmm::geometry::FilterPath;
using vcmm::geometry::gaussian_filter_closed;
using vcmm::geometry::gaussian_filtered_profile;
using vcmm::geometry::FilterPathChoice;
using vcmm::geometry::InvalidInput;
using vcmm::geometry::kStandardCutoffsUpr;
using vcmm::geometry::Point2;
using vcmm::test::Harmonic;
using vcmm::test::ring_profile;
using vcmm::test::RingSpec;

constexpr double kPi = std::numbers::pi;
constexpr double kAlpha = 0.46971863934982566;  // sqrt(ln 2 / π)

double transmission(double k, double cutoff) { return std::exp2(-(k / cutoff) * (k / cutoff)); }

/// A cos(2π k j / n + φ), j < n, with the angle reduced exactly (k j mod n) and evaluated in
/// long double: a naive k·2π·j/n in double is off by up to ~1e-12 rad at k j ~ 1e7, which would
/// put broadband noise of that size into a "pure" harmonic.
std::vector<double> harmonic(std::size_t n, std::size_t k, double amplitude, double phase) {
  std::vector<double> v(n);
  const long double two_pi = 2 * std::numbers::pi_v<long double>;
  for (std::size_t j = 0; j < n; ++j) {
    const long double angle =
        two_pi * static_cast<long double>((k * j) % n) / static_cast<long double>(n) + phase;
    v[j] = static_cast<double>(amplitude * std::cos(angle));
  }
  return v;
}

double max_abs_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::fabs(a[i] - b[i]));
  return m;
}

// ---- gaussian_filter_closed: transmission, by hand ------------------------------------------

TEST(GaussianFilterClosed, TransmissionAtZeroCutoffAndTwiceCutoff) {
  for (double fc : kStandardCutoffsUpr) {
    SCOPED_TRACE("cut-off " + std::to_string(fc) + " UPR");
    // n = 4 f_c + 1: odd, and 2 f_c ≤ n/2 is representable.
    const auto n = static_cast<std::size_t>(4 * fc + 1);
    // k = 0: a constant passes unchanged (H(0) = 1).
    const std::vector<double> constant(n, 2.5);
    const auto c = gaussian_filter_closed(constant, fc);
    for (double v : c) EXPECT_NEAR(v, 2.5, 1e-14);
    // k = f_c: 50 %; k = 2 f_c: 2^−4 = 6.25 %.
    const auto kc = static_cast<std::size_t>(fc);
    for (const auto& [k, h] : {std::pair{kc, 0.5}, std::pair{2 * kc, 0.0625}}) {
      const auto in = harmonic(n, k, 1.0, 0.7);
      const auto out = gaussian_filter_closed(in, fc);
      const auto expected = harmonic(n, k, h, 0.7);
      EXPECT_LT(max_abs_diff(out, expected), 1e-13) << "harmonic " << k;
    }
  }
}

TEST(GaussianFilterClosed, EveryHarmonicGetsItsTransmission) {
  const std::size_t n = 3600;
  const double fc = 50;
  for (std::size_t k : {1u, 2u, 7u, 25u, 49u, 50u, 51u, 100u, 150u, 333u, 1799u, 1800u}) {
    const auto out = gaussian_filter_closed(harmonic(n, k, 1.0, 0.2), fc);
    const double h = transmission(static_cast<double>(k), fc);
    EXPECT_LT(max_abs_diff(out, harmonic(n, k, h, 0.2)), 1e-14)
        << "harmonic " << k;
  }
}

TEST(GaussianFilterClosed, Linearity) {
  const std::size_t n = 1000;
  std::uint64_t state = 42;
  std::vector<double> x(n), y(n), z(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = vcmm::test::standard_normal(state);
    y[i] = vcmm::test::standard_normal(state);
    z[i] = 3.0 * x[i] - 0.5 * y[i];
  }
  const auto fx = gaussian_filter_closed(x, 150), fy = gaussian_filter_closed(y, 150),
             fz = gaussian_filter_closed(z, 150);
  for (std::size_t i = 0; i < n; ++i) EXPECT_NEAR(fz[i], 3.0 * fx[i] - 0.5 * fy[i], 1e-13);
}

// Against a direct O(n²) DFT in long double, for sizes of every kind: tiny, odd, powers of
// 2, 3, 5, 7, 11, 13, primes and prime squares (Bluestein's algorithm).
TEST(GaussianFilterClosed, MatchesDirectDftForAllSizes) {
  for (std::size_t n : {2u, 3u, 4u, 5u, 6u, 7u, 11u, 13u, 17u, 49u, 64u, 97u, 121u, 169u, 243u,
                        361u, 625u, 722u, 1009u, 1024u}) {
    SCOPED_TRACE("n = " + std::to_string(n));
    std::uint64_t state = n;
    std::vector<double> x(n);
    for (double& v : x) v = vcmm::test::standard_normal(state);
    const double fc = std::max(1.0, static_cast<double>(n) / 7.0);
    const auto y = gaussian_filter_closed(x, fc);
    // Roots of unity in long double; X_k = Σ_l x_l ω^{−kl}; y_j = (1/n) Σ_k H_k Re(X_k ω^{kj}).
    std::vector<long double> cs(n), sn(n);
    for (std::size_t m = 0; m < n; ++m) {
      const long double a = 2 * std::numbers::pi_v<long double> * static_cast<long double>(m) /
                            static_cast<long double>(n);
      cs[m] = std::cos(a);
      sn[m] = std::sin(a);
    }
    std::vector<long double> xr(n, 0), xi(n, 0);
    for (std::size_t k = 0; k < n; ++k) {
      for (std::size_t l = 0; l < n; ++l) {
        xr[k] += x[l] * cs[(k * l) % n];
        xi[k] -= x[l] * sn[(k * l) % n];
      }
      const long double h = transmission(static_cast<double>(std::min(k, n - k)), fc);
      xr[k] *= h;
      xi[k] *= h;
    }
    for (std::size_t j = 0; j < n; ++j) {
      long double acc = 0;
      for (std::size_t k = 0; k < n; ++k) acc += xr[k] * cs[(k * j) % n] - xi[k] * sn[(k * j) % n];
      EXPECT_NEAR(y[j], static_cast<double>(acc / static_cast<long double>(n)), 2e-15 * std::sqrt(static_cast<double>(n)));
    }
  }
}

TEST(GaussianFilterClosed, LargeSizesKeepTheirTransmission) {
  for (std::size_t n : {36000u, 36001u}) {  // smooth, and 36001 = 7 × 37 × 139 (Bluestein)
    const auto out = gaussian_filter_closed(harmonic(n, 500, 1.0, 0.0), 500);
    EXPECT_LT(max_abs_diff(out, harmonic(n, 500, 0.5, 0.0)), 1e-13) << "n = " << n;
  }
}

TEST(GaussianFilterClosed, ShiftAndReversalEquivariant) {
  const std::size_t n = 720;
  std::uint64_t state = 9;
  std::vector<double> x(n);
  for (double& v : x) v = vcmm::test::standard_normal(state);
  const auto fx = gaussian_filter_closed(x, 50);
  std::vector<double> shifted(x);
  std::rotate(shifted.begin(), shifted.begin() + 123, shifted.end());
  const auto fs = gaussian_filter_closed(shifted, 50);
  std::vector<double> reversed(x.rbegin(), x.rend());
  const auto fr = gaussian_filter_closed(reversed, 50);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_NEAR(fs[i], fx[(i + 123) % n], 1e-14);
    EXPECT_NEAR(fr[i], fx[n - 1 - i], 1e-14);
  }
}

void expect_invalid_closed(const std::vector<double>& x, double fc, const std::string& fragment) {
  try {
    gaussian_filter_closed(x, fc);
    ADD_FAILURE() << "expected InvalidInput mentioning '" << fragment << "'";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("gaussian_filter_closed"), std::string::npos) << what;
    EXPECT_NE(what.find(fragment), std::string::npos) << what;
  }
}

TEST(GaussianFilterClosedBadInput, TooFewValues) {
  expect_invalid_closed({}, 50, "at least 2");
  expect_invalid_closed({1.0}, 50, "at least 2");
}

TEST(GaussianFilterClosedBadInput, NonFiniteValue) {
  expect_invalid_closed({1.0, 2.0, std::nan(""), 4.0}, 1, "deviation 2");
  expect_invalid_closed({1.0, -std::numeric_limits<double>::infinity()}, 1, "deviation 1");
}

TEST(GaussianFilterClosedBadInput, CutoffNotPositive) {
  const std::vector<double> x(16, 1.0);
  expect_invalid_closed(x, 0.0, "cut-off");
  expect_invalid_closed(x, -15.0, "cut-off");
  expect_invalid_closed(x, std::nan(""), "cut-off");
  expect_invalid_closed(x, std::numeric_limits<double>::infinity(), "cut-off");
}

// ---- gaussian_filtered_profile -------------------------------------------------------------

/// Radial deviation of each filtered point about the filter's centre and mean radius.
std::vector<double> filtered_deviations(const FilteredProfile& f) {
  std::vector<double> d;
  for (const Point2& p : f.points)
    d.push_back(std::hypot(p.x - f.filter_center.x, p.y - f.filter_center.y) - f.mean_radius);
  return d;
}

constexpr double kPhase = 0.3;  // phase of the test harmonic

RingSpec single_harmonic_ring(std::size_t n, int k, double amplitude, double jitter,
                              std::uint64_t seed = 3, double phase = kPhase) {
  RingSpec spec;
  spec.n = n;
  spec.radius = 85.5;
  spec.center = {12.0, -7.0};
  spec.start_angle = 0.4;
  spec.harmonics = {Harmonic{k, amplitude, phase}};
  spec.angle_jitter = jitter;
  spec.seed = seed;
  return spec;
}

/// max_i |filtered deviation_i − H(k) A cos(k θ_i + φ)|, θ_i the input point's angle about
/// the filter centre.
double error_against_analytic(const std::vector<Point2>& pts, const FilteredProfile& f, int k,
                              double amplitude, double cutoff, double phase = kPhase) {
  const auto dev = filtered_deviations(f);
  double worst = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double theta =
        std::atan2(pts[i].y - f.filter_center.y, pts[i].x - f.filter_center.x);
    const double expected = transmission(k, cutoff) * amplitude * std::cos(k * theta + phase);
    worst = std::max(worst, std::fabs(dev[i] - expected));
  }
  return worst;
}

TEST(GaussianFilteredProfile, EquiangularTransmissionForEveryStandardCutoff) {
  const double amplitude = 1e-3;  // 1 µm
  for (double fc : kStandardCutoffsUpr) {
    const std::size_t n = fc < 1000 ? 3600 : 7200;
    for (int k : {2, static_cast<int>(fc), static_cast<int>(2 * fc)}) {
      SCOPED_TRACE("cut-off " + std::to_string(fc) + ", harmonic " + std::to_string(k));
      const auto pts = ring_profile(single_harmonic_ring(n, k, amplitude, 0.0));
      const FilteredProfile f = gaussian_filtered_profile(pts, fc);
      EXPECT_EQ(f.path, FilterPath::fft);
      ASSERT_EQ(f.points.size(), n);
      // Coordinates near 100 mm carry ~1e-14 mm rounding; the transmission is exact.
      EXPECT_LT(error_against_analytic(pts, f, k, amplitude, fc), 1e-12);
    }
  }
}

TEST(GaussianFilteredProfile, OutputPointsLieOnTheInputRays) {
  const auto pts = vcmm::test::lobed_noisy_ring(720, 5, 5e-5, {300.0, -450.0});
  const FilteredProfile f = gaussian_filtered_profile(pts, 50);
  ASSERT_EQ(f.points.size(), pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double ax = pts[i].x - f.filter_center.x, ay = pts[i].y - f.filter_center.y;
    const double bx = f.points[i].x - f.filter_center.x, by = f.points[i].y - f.filter_center.y;
    EXPECT_GT(ax * bx + ay * by, 0.0);
    EXPECT_LT(std::fabs(ax * by - ay * bx) / std::hypot(ax, ay), 1e-12);  // distance to the ray
  }
}

TEST(GaussianFilteredProfile, PerfectCirclePassesUnchangedOnBothPaths) {
  for (double jitter : {0.0, 0.5}) {
    RingSpec spec;
    spec.n = 500;
    spec.radius = 20.0;
    spec.center = {-800.0, 650.0};
    spec.angle_jitter = jitter;
    const auto pts = ring_profile(spec);
    const FilteredProfile f = gaussian_filtered_profile(
        pts, 150, jitter > 0 ? FilterPathChoice::nonuniform : FilterPathChoice::automatic);
    EXPECT_EQ(f.path, jitter > 0 ? FilterPath::nonuniform : FilterPath::fft);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      EXPECT_NEAR(f.points[i].x, pts[i].x, 1e-12);
      EXPECT_NEAR(f.points[i].y, pts[i].y, 1e-12);
    }
  }
}

TEST(GaussianFilteredProfile, PathDetectionAnyStartAndSenseAndClosingPoint) {
  auto pts = ring_profile(single_harmonic_ring(720, 30, 1e-3, 0.0));
  const FilteredProfile ref = gaussian_filtered_profile(pts, 50);
  EXPECT_EQ(ref.path, FilterPath::fft);

  // Clockwise order, starting elsewhere: same filtered points, re-indexed.
  std::vector<Point2> cw(pts.rbegin(), pts.rend());
  std::rotate(cw.begin(), cw.begin() + 100, cw.end());
  const FilteredProfile fcw = gaussian_filtered_profile(cw, 50);
  EXPECT_EQ(fcw.path, FilterPath::fft);
  for (std::size_t i = 0; i < cw.size(); ++i) {
    const std::size_t j = (pts.size() - 1 - (i + 100) % pts.size());
    EXPECT_NEAR(fcw.points[i].x, ref.points[j].x, 1e-12);
    EXPECT_NEAR(fcw.points[i].y, ref.points[j].y, 1e-12);
  }

  // A closed scan repeating its first point: still the FFT path; the repeat gets the first
  // point's filtered value (the same point when the repeat is exact). The harmonic's phase puts
  // the repeated point on the mean circle, so the repeat leaves the LS centre where it was
  // (any other point would move it by ~2 e_0 / n, an eccentricity the filter passes).
  const double phase0 = kPi / 2 - 30 * 0.4;  // cos(30 θ₀ + φ) = 0 at θ₀ = 0.4
  const auto pts0 = ring_profile(single_harmonic_ring(720, 30, 1e-3, 0.0, 3, phase0));
  std::vector<Point2> closed = pts0;
  closed.push_back(pts0.front());
  const FilteredProfile fcl = gaussian_filtered_profile(closed, 50);
  EXPECT_EQ(fcl.path, FilterPath::fft);
  EXPECT_NEAR(fcl.points.back().x, fcl.points.front().x, 1e-12);
  EXPECT_NEAR(fcl.points.back().y, fcl.points.front().y, 1e-12);
  EXPECT_LT(error_against_analytic(closed, fcl, 30, 1e-3, 50, phase0), 1e-12);

  // Samples off the grid: a small displacement whose first-order effect on the filtered
  // profile stays below 1e-3 of its peak-to-valley keeps the FFT path, and agrees with the
  // nonuniform path to that order; a large one (±0.2 step on a steep 30-lobe profile) does not.
  const auto slight = ring_profile(single_harmonic_ring(720, 30, 1e-3, 1e-4));
  const FilteredProfile fs = gaussian_filtered_profile(slight, 50);
  EXPECT_EQ(fs.path, FilterPath::fft);
  const FilteredProfile fsn = gaussian_filtered_profile(slight, 50, FilterPathChoice::nonuniform);
  for (std::size_t i = 0; i < slight.size(); ++i)
    EXPECT_NEAR(fs.points[i].x, fsn.points[i].x, 1e-3 * 2e-3) << i;
  RingSpec spec = single_harmonic_ring(720, 30, 1e-3, 0.4);
  EXPECT_EQ(gaussian_filtered_profile(ring_profile(spec), 50).path, FilterPath::nonuniform);
  // A 171 mm ring (200 nm of 5-lobe form) scanned equiangularly about a point 2 µm from its
  // centre, as a CMM scan about a slightly misaligned nominal centre: still the FFT path.
  std::vector<Point2> ecc_pts;
  for (int i = 0; i < 3600; ++i) {
    const double t = 2 * kPi * i / 3600.0, e = 2e-3;
    const double rho = 85.5 + 1e-4 * std::cos(5 * t);
    const double d = e * std::cos(t) + std::sqrt(rho * rho - e * e * std::sin(t) * std::sin(t));
    ecc_pts.push_back({d * std::cos(t), d * std::sin(t)});
  }
  EXPECT_EQ(gaussian_filtered_profile(ecc_pts, 50).path, FilterPath::fft);
}

// Dense scans: samples off the grid by more than a quarter step but less than half (what the
// tangential probing noise does to 36 000-point scans of the 171 mm ring) keep the FFT path
// when the first-order effect is small, and agree with the nonuniform path to the acceptance
// tolerance (1e-3 of the filtered peak-to-valley) plus its quadrature error; a sample half a
// step off or more breaks the angular order: the nonuniform path. (Under the earlier
// quarter-step rule the first profile took the nonuniform path.)
TEST(GaussianFilteredProfile, DisplacementsBetweenAQuarterAndHalfAStepKeepTheFftPath) {
  const double amplitude = 1e-4;
  for (std::uint64_t seed : {3u, 4u, 5u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    // Uniform angle jitter of ±¼ step about the grid: against sample 0's position (which
    // anchors the grid) samples sit up to ¼ step + |jitter of sample 0| off — beyond a quarter
    // step, below half (checked here on the angles about the filter centre).
    const std::size_t n = 7200;
    const auto pts = ring_profile(single_harmonic_ring(n, 2, amplitude, 0.5, seed));
    const FilteredProfile f = gaussian_filtered_profile(pts, 50);
    EXPECT_EQ(f.path, FilterPath::fft);
    const FilteredProfile fn = gaussian_filtered_profile(pts, 50, FilterPathChoice::nonuniform);
    ASSERT_EQ(fn.path, FilterPath::nonuniform);
    const double step = 2 * kPi / static_cast<double>(n);
    const auto angle = [&](std::size_t i) {
      return std::atan2(pts[i].y - f.filter_center.y, pts[i].x - f.filter_center.x);
    };
    double off_max = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double off = std::remainder(angle(i) - angle(0) - step * static_cast<double>(i),
                                        2 * kPi);
      off_max = std::max(off_max, std::fabs(off));
    }
    EXPECT_GT(off_max, 0.25 * step);
    EXPECT_LT(off_max, 0.5 * step);
    const auto d = filtered_deviations(f), dn = filtered_deviations(fn);
    const auto [lo, hi] = std::minmax_element(d.begin(), d.end());
    double worst = 0.0;
    for (std::size_t i = 0; i < d.size(); ++i) worst = std::max(worst, std::fabs(d[i] - dn[i]));
    EXPECT_LT(worst, 1e-3 * (*hi - *lo) + 1e-12);
    // ±0.55 step: some sample is half a step or more off its grid position.
    const auto far = ring_profile(single_harmonic_ring(n, 2, amplitude, 1.1, seed));
    EXPECT_EQ(gaussian_filtered_profile(far, 50).path, FilterPath::nonuniform);
  }
}

// The nonuniform path (trapezoidal quadrature of the convolution integral) against the analytic
// filtered profile H(k) A cos(kθ + φ), on profiles whose sampling angles are jittered by up to
// ±jitter/2 of a step h. Its error is first order in the jitter and second order in the step
// relative to the weighting function's width: observed max error ≤ 5.3 · jitter · (h/αλ_c)² · A
// over n ∈ {720, 3600}, f_c ∈ {15, 50, 150}, k ∈ {2, 10, f_c, 2 f_c}; the bound tested is 8×.
TEST(GaussianFilteredProfile, NonuniformPathMatchesAnalyticFilteredProfile) {
  const double amplitude = 1e-3;
  for (std::size_t n : {720u, 3600u}) {
    for (double fc : {15.0, 50.0, 150.0}) {
      for (double jitter : {0.01, 0.3}) {
        for (int k : {2, 10, static_cast<int>(fc), static_cast<int>(2 * fc)}) {
          if (k > static_cast<int>(n) / 4) continue;
          SCOPED_TRACE("n " + std::to_string(n) + ", cut-off " + std::to_string(fc) +
                       ", jitter " + std::to_string(jitter) + ", harmonic " + std::to_string(k));
          const auto pts = ring_profile(single_harmonic_ring(n, k, amplitude, jitter));
          const FilteredProfile f = gaussian_filtered_profile(pts, fc, FilterPathChoice::nonuniform);
          EXPECT_EQ(f.path, FilterPath::nonuniform);
          const double h_over_width = (2 * kPi / static_cast<double>(n)) / (kAlpha * 2 * kPi / fc);
          const double bound = 8.0 * jitter * h_over_width * h_over_width * amplitude + 1e-12;
          EXPECT_LT(error_against_analytic(pts, f, k, amplitude, fc), bound);
        }
      }
    }
  }
}

// Both paths on (nearly) the same data: the FFT path on the equiangular profile and the
// nonuniform path on the same profile with its sampling angles jittered by ±5e-5 of a step.
// After removing the profile's own change between the two sets of angles (known exactly:
// H(k) A [cos(kθ_jittered + φ) − cos(kθ_even + φ)]), they agree within the quadrature bound
// above (8 · 1e-4 · (h/αλ_c)² · A ≈ 7e-13 mm here) plus coordinate rounding, plus the
// difference of the two reference circles: the jitter moves the discrete LS centre by ~1e-11
// mm (harmonic 50 leaks into the sampled harmonic 1), and deviations about circles whose
// centres differ by Δc and radii by ΔR differ by up to |Δc| + |ΔR|.
TEST(GaussianFilteredProfile, EquiangularAndNonuniformPathsAgree) {
  const double amplitude = 1e-3;
  const auto even = ring_profile(single_harmonic_ring(3600, 50, amplitude, 0.0));
  const auto jittered = ring_profile(single_harmonic_ring(3600, 50, amplitude, 1e-4));
  const FilteredProfile fe = gaussian_filtered_profile(even, 50);
  const FilteredProfile fj = gaussian_filtered_profile(jittered, 50, FilterPathChoice::nonuniform);
  ASSERT_EQ(fe.path, FilterPath::fft);
  ASSERT_EQ(fj.path, FilterPath::nonuniform);
  const auto de = filtered_deviations(fe), dj = filtered_deviations(fj);
  const double h = transmission(50, 50);
  double worst = 0;
  for (std::size_t i = 0; i < even.size(); ++i) {
    const double te = std::atan2(even[i].y - fe.filter_center.y, even[i].x - fe.filter_center.x);
    const double tj =
        std::atan2(jittered[i].y - fj.filter_center.y, jittered[i].x - fj.filter_center.x);
    const double change = h * amplitude * (std::cos(50 * tj + kPhase) - std::cos(50 * te + kPhase));
    worst = std::max(worst, std::fabs(dj[i] - de[i] - change));
  }
  const double circles = std::hypot(fj.filter_center.x - fe.filter_center.x,
                                    fj.filter_center.y - fe.filter_center.y) +
                         std::fabs(fj.mean_radius - fe.mean_radius);
  EXPECT_LT(circles, 1e-10);
  EXPECT_LT(worst, 2e-12 + circles);
}

TEST(GaussianFilteredProfile, InvariantUnderRotationAndTranslation) {
  for (double jitter : {0.0, 0.4}) {
    RingSpec spec = single_harmonic_ring(900, 12, 2e-3, jitter);
    spec.harmonics.push_back(Harmonic{70, 5e-4, 1.0});
    const auto pts = ring_profile(spec);
    const FilteredProfile f = gaussian_filtered_profile(pts, 50);
    const double ca = std::cos(0.9), sa = std::sin(0.9);
    std::vector<Point2> moved;
    for (const Point2& p : pts) moved.push_back({ca * p.x - sa * p.y + 500, sa * p.x + ca * p.y - 250});
    const FilteredProfile fm = gaussian_filtered_profile(moved, 50);
    EXPECT_EQ(fm.path, f.path);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      EXPECT_NEAR(fm.points[i].x, ca * f.points[i].x - sa * f.points[i].y + 500, 1e-11);
      EXPECT_NEAR(fm.points[i].y, sa * f.points[i].x + ca * f.points[i].y - 250, 1e-11);
    }
  }
}

TEST(GaussianFilteredProfile, PrimeCountUsesTheFftPath) {
  const auto pts = ring_profile(single_harmonic_ring(997, 40, 1e-3, 0.0));
  const FilteredProfile f = gaussian_filtered_profile(pts, 50);
  EXPECT_EQ(f.path, FilterPath::fft);
  EXPECT_LT(error_against_analytic(pts, f, 40, 1e-3, 50), 1e-12);
}

TEST(GaussianFilteredProfile, ReportsTheLeastSquaresCentreAndRadius) {
  const auto pts = vcmm::test::lobed_noisy_ring(360, 8);
  const FilteredProfile f = gaussian_filtered_profile(pts, 15);
  EXPECT_NEAR(f.filter_center.x, 0.0, 1e-5);
  EXPECT_NEAR(f.filter_center.y, 0.0, 1e-5);
  EXPECT_NEAR(f.mean_radius, 85.5, 1e-5);
}

// The filter's first pass takes distances by a series whose degree it picks from the RONt of
// the LS circle it is given (internal/near_circle.h), redoing the pass with a wider series or
// with square roots when a point falls outside. An LS circle whose RONt says nothing (0: try
// the narrowest series first; NaN: unknown; huge: square roots at once) filters alike: the
// same path, the same points to within rounding — every degree is within an ulp of √.
TEST(GaussianFilteredProfile, AnyRontOfTheGivenLsCircleFiltersAlike) {
  for (const double form : {1e-4, 2e-3, 2e-2}) {  // |s| ~ 2e-5, 4e-4, 4e-3 on R = 10
    RingSpec spec;
    spec.center = {-40.0, 70.0};
    spec.radius = 10.0;
    spec.n = 1800;
    spec.harmonics = {Harmonic{2, form, 0.3}, Harmonic{3, 0.6 * form, 1.1},
                      Harmonic{15, 0.1 * form, 2.9}};
    spec.noise_sigma = 0.02 * form;
    const auto pts = ring_profile(spec);
    const auto ls = vcmm::geometry::least_squares_circle(pts);
    FilteredProfile base;
    vcmm::geometry::LeastSquaresCircle base_ls;
    gaussian_filtered_profile(pts, 50.0, ls, base, &base_ls);
    for (const double ront : {0.0, std::numeric_limits<double>::quiet_NaN(), 1e3}) {
      SCOPED_TRACE(::testing::Message() << "form " << form << ", RONt given " << ront);
      auto hint = ls;
      hint.ron.ront = ront;
      FilteredProfile f;
      vcmm::geometry::LeastSquaresCircle f_ls;
      gaussian_filtered_profile(pts, 50.0, hint, f, &f_ls);
      EXPECT_EQ(f.path, base.path);
      double worst = 0.0;
      for (std::size_t i = 0; i < pts.size(); ++i)
        worst = std::max({worst, std::fabs(f.points[i].x - base.points[i].x),
                          std::fabs(f.points[i].y - base.points[i].y)});
      EXPECT_LE(worst, 1e-13);  // a few ulps of the coordinates (~80 mm: ulp 1.4e-14)
      EXPECT_NEAR(f_ls.ron.ront, base_ls.ron.ront, 1e-13);
    }
  }
}

// ---- bad input ---------------------------------------------------------------------------------

void expect_invalid_profile(const std::vector<Point2>& pts, double fc, const std::string& fragment) {
  try {
    gaussian_filtered_profile(pts, fc);
    ADD_FAILURE() << "expected InvalidInput mentioning '" << fragment << "'";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("gaussian_filtered_profile"), std::string::npos) << what;
    EXPECT_NE(what.find(fragment), std::string::npos) << what;
  }
}

TEST(GaussianFilteredProfileBadInput, OpenArcIsNotClosed) {
  RingSpec spec;
  spec.n = 300;
  spec.span = 1.5 * kPi;  // 270°: a 90° gap
  const auto pts = ring_profile(spec);
  expect_invalid_profile(pts, 15, "profile is not closed: angular gap of 90");
}

TEST(GaussianFilteredProfileBadInput, GapJustAboveHalfTheCutoffWavelength) {
  // λ_c/2 = 180°/f_c = 3.6° at f_c = 50. Equiangular points every 1° with 4 points removed
  // leave a 5° gap (rejected); with 2 removed, a 3° gap (accepted, nonuniform path).
  const auto full = ring_profile(single_harmonic_ring(360, 5, 1e-3, 0.0));
  std::vector<Point2> wide(full.begin(), full.end() - 4), narrow(full.begin(), full.end() - 2);
  expect_invalid_profile(wide, 50, "exceeds");
  const FilteredProfile f = gaussian_filtered_profile(narrow, 50);
  EXPECT_EQ(f.path, FilterPath::nonuniform);
}

TEST(GaussianFilteredProfileBadInput, TooFewPoints) {
  RingSpec spec;
  spec.n = 7;
  expect_invalid_profile(ring_profile(spec), 2, "at least 8");
}

TEST(GaussianFilteredProfileBadInput, NonFinitePoint) {
  auto pts = ring_profile(single_harmonic_ring(64, 3, 1e-3, 0.0));
  pts[17].y = std::nan("");
  expect_invalid_profile(pts, 15, "point 17");
}

TEST(GaussianFilteredProfileBadInput, CutoffOutOfRange) {
  const auto pts = ring_profile(single_harmonic_ring(64, 3, 1e-3, 0.0));
  expect_invalid_profile(pts, 0.0, "cut-off");
  expect_invalid_profile(pts, -50, "cut-off");
  expect_invalid_profile(pts, std::nan(""), "cut-off");
  expect_invalid_profile(pts, 33, "n/2 = 32");
}

TEST(GaussianFilteredProfileBadInput, CollinearPoints) {
  std::vector<Point2> line;
  for (int i = 0; i < 10; ++i) line.push_back({1.0 * i, 2.0 * i});
  expect_invalid_profile(line, 2, "collinear");
}

}  // namespace

// ---- the open-profile filter (partial arcs) -------------------------------------------------

namespace {

std::vector<vcmm::geometry::Point2> open_arc(double span_deg, std::size_t n,
                                             const std::function<double(double)>& r_of) {
  std::vector<vcmm::geometry::Point2> p;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = span_deg * std::numbers::pi / 180.0 * double(i) / double(n - 1);
    const double r = r_of(t);
    p.push_back({3.0 + r * std::cos(t), -1.0 + r * std::sin(t)});
  }
  return p;
}

double radial(const vcmm::geometry::Point2& p, const vcmm::geometry::Point2& c) {
  return std::hypot(p.x - c.x, p.y - c.y);
}

TEST(OpenProfileFilter, LinearComponentsPassUpToTheEnds) {
  // A spiral r = 50 + 1e-3·θ over 120°: constant and linear parts of the deviation pass the
  // moment-preserving end treatment unchanged (a plain truncated mean would bend both ends).
  const auto p = open_arc(120.0, 600, [](double t) { return 50.0 + 1e-3 * t; });
  const auto f = vcmm::geometry::gaussian_filtered_open_profile(p, 50.0);
  EXPECT_EQ(f.path, vcmm::geometry::FilterPath::open_profile);
  double worst = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    worst = std::max(worst, std::fabs(radial(f.points[i], f.filter_center) -
                                      radial(p[i], f.filter_center)));
  // The LS circle of a spiral arc is not its centre of curvature, so the deviation about it is
  // not exactly linear in θ: the residual curvature is attenuated like a slow harmonic (2.5e-7
  // mm observed). A plain truncated mean would be off by ~2e-5 mm at the ends (the slope
  // 1e-3 mm/rad times the one-sided window's centroid, ~0.02 rad).
  EXPECT_LT(worst, 1e-6);
}

TEST(OpenProfileFilter, InteriorAttenuationIsTheGaussianTransmission) {
  // 270° arc carrying harmonics of order 50 (H = 1/2) and 200 (H = 2^-16 ≈ 0): away from the
  // ends the filtered deviation is half the order-50 wave and none of the order-200 one.
  const double a = 1e-3;
  const auto p = open_arc(270.0, 5400, [&](double t) {
    return 50.0 + a * std::cos(50.0 * t) + a * std::cos(200.0 * t);
  });
  const auto f = vcmm::geometry::gaussian_filtered_open_profile(p, 50.0);
  const vcmm::geometry::Point2 c = f.filter_center;
  double worst = 0.0;
  for (std::size_t i = 1000; i < 4400; ++i) {
    const double t = 270.0 * std::numbers::pi / 180.0 * double(i) / 5399.0;
    const double want = f.mean_radius + 0.5 * a * std::cos(50.0 * t);
    worst = std::max(worst, std::fabs(radial(f.points[i], c) - want));
  }
  // The LS radius absorbs the waves' mean over the arc, and the quadrature has its own small
  // error: 2 % of the amplitude.
  EXPECT_LT(worst, 0.02 * a);
}

TEST(OpenProfileFilter, GapsInsideTheArcAreRefusedAndEvaluateRoundnessChoosesIt) {
  auto p = open_arc(150.0, 300, [](double t) { return 20.0 + 1e-3 * std::cos(3 * t); });
  p.erase(p.begin() + 100, p.begin() + 140);  // a 20° hole inside the arc
  try {
    vcmm::geometry::gaussian_filtered_open_profile(p, 50.0);
    FAIL() << "no exception";
  } catch (const vcmm::geometry::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("not continuous"), std::string::npos) << e.what();
  }
  const auto arc = open_arc(150.0, 300, [](double t) { return 20.0 + 1e-3 * std::cos(3 * t); });
  vcmm::geometry::RoundnessRequest request;
  request.filter_cutoff_upr = 50.0;
  const auto e = vcmm::geometry::evaluate_roundness(arc, request);
  ASSERT_TRUE(e.filter_path.has_value());
  EXPECT_EQ(*e.filter_path, vcmm::geometry::FilterPath::open_profile);
  EXPECT_TRUE(e.minimum_zone.has_value());
  EXPECT_FALSE(e.coverage.closed);
}

}  // namespace

// evaluate_roundness lets the closed filter decide "closed or open" where it can (its
// nonuniform path sorts the angles angular_coverage takes; its FFT path cannot meet a gap
// of 2 grid steps) and takes the coverage first otherwise (cut-offs near or above n/4).
// Either way the choice must be the rule's: the open-profile filter exactly when the largest
// gap about the raw LS centre exceeds λc/2 = π/f_c. Rings with one gap of k missing steps,
// equiangular, jittered by up to 0.45 step, or perfectly round with one pair of neighbours
// 1.9 steps apart (FFT or nonuniform path), cut-offs on both sides of the gap, of n/4 and of
// n/3. Fixed seed.
TEST(OpenProfileFilter, EvaluateRoundnessChoosesOpenExactlyByTheCoverageRule) {
  std::mt19937_64 rng(1127);
  std::uniform_real_distribution<double> jitter(-0.45, 0.45);
  int open = 0, closed = 0;
  for (std::size_t n : {60u, 200u, 361u}) {
    for (std::size_t missing : {0u, 1u, 2u, 4u, 8u}) {
      for (int variant = 0; variant < 3; ++variant) {
        // 0: equiangular; 1: jittered; 2: a perfect circle (the FFT path's grid test then
        // passes whatever the displacement) with two neighbours 0.45 step apart the other
        // way: a gap of 1.9 steps on the FFT path.
        const bool jittered = variant == 1;
        std::vector<Point2> p;
        const double step = 2 * std::numbers::pi / double(n);
        for (std::size_t j = missing; j < n; ++j) {
          double shift = jittered ? jitter(rng) : 0.0;
          if (variant == 2 && j == n / 2) shift = -0.45;
          if (variant == 2 && j == n / 2 + 1) shift = 0.45;
          const double t = step * (double(j) + shift);
          const double form = variant == 2 ? 0.0 : 2e-3 * std::cos(3 * t) + 1e-3 * std::sin(5 * t);
          const double r = 40.0 + form;
          p.push_back({100.0 + r * std::cos(t), -50.0 + r * std::sin(t)});
        }
        const Point2 c = vcmm::geometry::least_squares_circle(p).center;
        const double gap = vcmm::geometry::angular_coverage(p, c).largest_gap_rad;
        for (double cutoff : {2.0, 5.0, 15.0, double(n) / 4.0 - 1.0, double(n) / 4.0,
                              double(n) / 4.0 + 1.0, double(n) / 3.6, double(n) / 3.0,
                              double(n) / 3.0 + 1.0, double(n - missing) / 2.0}) {
          const std::string what = "n " + std::to_string(n) + " missing " +
                                   std::to_string(missing) + " variant " +
                                   std::to_string(variant) + " cut-off " + std::to_string(cutoff);
          const bool want_open = gap > std::numbers::pi / cutoff;
          vcmm::geometry::RoundnessRequest request;
          request.filter_cutoff_upr = cutoff;
          request.maximum_inscribed = request.minimum_circumscribed = false;
          try {
            const auto e = vcmm::geometry::evaluate_roundness(p, request);
            ASSERT_TRUE(e.filter_path.has_value()) << what;
            EXPECT_EQ(*e.filter_path == FilterPath::open_profile, want_open) << what;
            (want_open ? open : closed) += 1;
          } catch (const InvalidInput& e) {
            // Only the open filter may refuse such a ring (e.g. a cut-off too high for it).
            EXPECT_TRUE(want_open) << what << ": " << e.what();
          }
        }
      }
    }
  }
  EXPECT_GT(open, 10);
  EXPECT_GT(closed, 10);
}
