// Tests of vcmm/geometry/profile_harmonics.h: analytic profiles on both paths, start/sense
// invariance, re-synthesis, the Gaussian filter as a gain, bad input.
#include "vcmm/geometry/profile_harmonics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "vcmm/geometry/gaussian_filter.h"

namespace vcmm::geometry {
namespace {

constexpr double kPi = std::numbers::pi;

struct Harmonic {
  int k;
  double a, b;  // mm
};

/// Points at angles θ_j (rad) about (cx, cy) with radius R + Σ a cos kθ + b sin kθ.
std::vector<Point2> profile_at(const std::vector<double>& theta, const std::vector<Harmonic>& h,
                               double cx = 3.0, double cy = -2.0, double radius = 85.5) {
  std::vector<Point2> out;
  for (double t : theta) {
    double r = radius;
    for (const auto& x : h) r += x.a * std::cos(x.k * t) + x.b * std::sin(x.k * t);
    out.push_back({cx + r * std::cos(t), cy + r * std::sin(t)});
  }
  return out;
}

std::vector<double> grid(std::size_t n, double start, double sense = 1.0) {
  std::vector<double> t(n);
  for (std::size_t j = 0; j < n; ++j) t[j] = start + sense * 2.0 * kPi * double(j) / double(n);
  return t;
}

const std::vector<Harmonic> kForm = {{2, 0.4e-3, -0.1e-3}, {3, 0.05e-3, 0.2e-3}, {7, -0.03e-3, 0.0},
                                     {17, 0.0, 0.01e-3}};

void expect_coefficients(const ProfileHarmonics& h, const std::vector<Harmonic>& form, double tol) {
  for (std::size_t k = 1; k <= h.max_order(); ++k) {
    double a = 0, b = 0;
    for (const auto& x : form)
      if (static_cast<std::size_t>(x.k) == k) a = x.a, b = x.b;
    EXPECT_NEAR(h.cos_mm(k), a, tol) << "k = " << k;
    EXPECT_NEAR(h.sin_mm(k), b, tol) << "k = " << k;
  }
}

TEST(ProfileHarmonics, EquiangularProfileTakesTheFftPathAndRecoversEveryHarmonic) {
  const auto pts = profile_at(grid(360, 0.3), kForm);
  const ProfileHarmonics h(pts, {3.0, -2.0}, 85.5, 50);
  EXPECT_EQ(h.path(), HarmonicsPath::fft);
  // The radial deviation of an exact harmonic sum is exact; the coefficients to rounding.
  expect_coefficients(h, kForm, 1e-13);
  EXPECT_NEAR(h.cos_mm(0), 0.0, 1e-13);
  // P = a² + b²: an error δ in the coefficients (~1e-16 mm here) moves it by ~2|a|δ.
  EXPECT_NEAR(h.power_mm2(2), 0.4e-3 * 0.4e-3 + 0.1e-3 * 0.1e-3, 2.0 * 0.41e-3 * 1e-15);
}

TEST(ProfileHarmonics, StartAngleAndSenseDoNotChangeTheCoefficients) {
  for (double start : {0.0, 1.0, -2.5}) {
    for (double sense : {1.0, -1.0}) {
      const auto pts = profile_at(grid(400, start, sense), kForm);
      const ProfileHarmonics h(pts, {3.0, -2.0}, 85.5, 40);
      EXPECT_EQ(h.path(), HarmonicsPath::fft);
      expect_coefficients(h, kForm, 1e-13);
    }
  }
}

TEST(ProfileHarmonics, SparseAndFftSynthesisAgreeForOddAndEvenCounts) {
  // Few non-zero gains take the direct sums, many the inverse FFT: the same deviations.
  for (std::size_t n : {360u, 361u, 3600u}) {
    std::mt19937_64 rng(n);
    std::normal_distribution<double> noise(0.0, 0.3e-3);
    std::vector<double> theta = grid(n, 0.7, -1.0);
    auto pts = profile_at(theta, kForm);
    for (std::size_t j = 0; j < n; ++j) {
      const double e = noise(rng);
      pts[j].x += e * std::cos(theta[j]);
      pts[j].y += e * std::sin(theta[j]);
    }
    const std::size_t K = n / 2;
    const ProfileHarmonics h(pts, {3.0, -2.0}, 85.5, K);
    ASSERT_EQ(h.path(), HarmonicsPath::fft);
    std::vector<double> sparse(K + 1, 0.0), dense(K + 1, 0.0);
    for (std::size_t k : {0u, 1u, 2u, 3u, 7u, 17u}) sparse[k] = dense[k] = 0.9;
    for (std::size_t k = 20; k <= K; ++k) dense[k] = 1e-300;  // non-zero: forces the FFT
    const auto a = h.synthesized(sparse), b = h.synthesized(dense);
    for (std::size_t j = 0; j < n; ++j) {
      EXPECT_NEAR(a[j].x, b[j].x, 1e-12) << "n = " << n << ", j = " << j;
      EXPECT_NEAR(a[j].y, b[j].y, 1e-12) << "n = " << n << ", j = " << j;
    }
    // All gains 1 reproduce the input (odd n: no Nyquist term; even n: with it).
    const auto back = h.synthesized(std::vector<double>(K + 1, 1.0));
    for (std::size_t j = 0; j < n; ++j) EXPECT_NEAR(back[j].x, pts[j].x, 1e-12) << n;
  }
}

TEST(ProfileHarmonics, NyquistHarmonicIsRepresented) {
  const std::size_t n = 64;
  const std::vector<Harmonic> h32 = {{32, 0.2e-3, 0.0}};
  const auto pts = profile_at(grid(n, 0.0), h32);
  const ProfileHarmonics h(pts, {3.0, -2.0}, 85.5, 32);
  EXPECT_NEAR(h.cos_mm(32), 0.2e-3, 1e-14);
  // Synthesis with all gains 1 gives the input back.
  const auto back = h.synthesized(std::vector<double>(33, 1.0));
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_NEAR(back[i].x, pts[i].x, 1e-12);
    EXPECT_NEAR(back[i].y, pts[i].y, 1e-12);
  }
}

TEST(ProfileHarmonics, UnevenSamplesTakeTheQuadraturePath) {
  std::mt19937_64 rng(7);  // seed printed by the failure message through the expectations
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  const std::size_t n = 720;
  std::vector<double> theta(n);
  for (std::size_t j = 0; j < n; ++j) theta[j] = 2.0 * kPi * (double(j) + jitter(rng)) / double(n);
  const auto pts = profile_at(theta, kForm);
  const ProfileHarmonics h(pts, {3.0, -2.0}, 85.5, 30);
  EXPECT_EQ(h.path(), HarmonicsPath::quadrature);
  // Trapezoidal quadrature of a smooth periodic integrand with irregular steps: first order
  // in the irregularity and second in the step (h = 2π/720): ~1e-3 of the amplitudes here.
  expect_coefficients(h, kForm, 2e-6);
}

TEST(ProfileHarmonics, GaussianTransmissionAsGainsEqualsTheFilter) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 0.5e-3);
  const std::size_t n = 3600;
  std::vector<double> theta = grid(n, 0.1);
  auto pts = profile_at(theta, kForm);
  // White noise along the rays keeps the samples on the grid.
  for (std::size_t j = 0; j < n; ++j) {
    const double e = noise(rng);
    pts[j].x += e * std::cos(theta[j]);
    pts[j].y += e * std::sin(theta[j]);
  }
  const LeastSquaresCircle ls = least_squares_circle(pts);
  const double fc = 50.0;
  const ProfileHarmonics h(pts, ls.center, ls.radius, n / 2);
  ASSERT_EQ(h.path(), HarmonicsPath::fft);
  std::vector<double> gains(n / 2 + 1);
  for (std::size_t k = 0; k < gains.size(); ++k) gains[k] = std::exp2(-(double(k) / fc) * (double(k) / fc));
  const auto mine = h.synthesized(gains);
  const auto filtered = gaussian_filtered_profile(pts, fc, ls);
  for (std::size_t j = 0; j < n; ++j) {
    EXPECT_NEAR(mine[j].x, filtered.points[j].x, 1e-11) << j;
    EXPECT_NEAR(mine[j].y, filtered.points[j].y, 1e-11) << j;
  }
}

TEST(ProfileHarmonics, FftAndQuadratureAgreeOnAFinelySampledProfile) {
  const auto pts = profile_at(grid(2000, 0.0), kForm);
  const ProfileHarmonics fft(pts, {3.0, -2.0}, 85.5, 20);
  // Force the quadrature path: the same points, every other one nudged off the grid.
  auto nudged = pts;
  std::vector<double> theta = grid(2000, 0.0);
  for (std::size_t j = 1; j < theta.size(); j += 2) theta[j] += 0.2 * 2.0 * kPi / 2000.0;
  nudged = profile_at(theta, kForm);
  const ProfileHarmonics quad(nudged, {3.0, -2.0}, 85.5, 20);
  ASSERT_EQ(fft.path(), HarmonicsPath::fft);
  ASSERT_EQ(quad.path(), HarmonicsPath::quadrature);
  for (std::size_t k = 0; k <= 20; ++k) {
    EXPECT_NEAR(fft.cos_mm(k), quad.cos_mm(k), 1e-8) << k;
    EXPECT_NEAR(fft.sin_mm(k), quad.sin_mm(k), 1e-8) << k;
  }
  // Band-limited synthesis on the quadrature path reproduces the profile.
  const auto back = quad.synthesized(std::vector<double>(21, 1.0));
  for (std::size_t j = 0; j < nudged.size(); ++j) EXPECT_NEAR(back[j].x, nudged[j].x, 1e-8);
}

TEST(ProfileHarmonics, BadInputIsRefusedWithTheReason) {
  const auto pts = profile_at(grid(64, 0.0), kForm);
  EXPECT_THROW(ProfileHarmonics(std::span(pts).first(5), {3.0, -2.0}, 85.5, 2), InvalidInput);
  EXPECT_THROW(ProfileHarmonics(pts, {3.0, -2.0}, 85.5, 33), InvalidInput);
  EXPECT_THROW(ProfileHarmonics(pts, {3.0, -2.0}, 85.5, 0), InvalidInput);
  EXPECT_THROW(ProfileHarmonics(pts, {NAN, -2.0}, 85.5, 4), InvalidInput);
  EXPECT_THROW(ProfileHarmonics(pts, {3.0, -2.0}, -1.0, 4), InvalidInput);
  auto bad = pts;
  bad[5].x = INFINITY;
  try {
    ProfileHarmonics h(bad, {3.0, -2.0}, 85.5, 4);
    FAIL() << "no exception";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("point 5"), std::string::npos) << e.what();
  }
  const ProfileHarmonics h(pts, {3.0, -2.0}, 85.5, 4);
  EXPECT_THROW(h.synthesized(std::vector<double>(4, 1.0)), InvalidInput);
  EXPECT_THROW(h.synthesized(std::vector<double>{1, 1, NAN, 1, 1}), InvalidInput);
}

}  // namespace
}  // namespace vcmm::geometry
