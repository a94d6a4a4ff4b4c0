// vcmm/geometry/profile_harmonics.h — harmonic (Fourier) analysis of a closed profile's radial
// deviations about a circle, and its re-synthesis with a gain per harmonic (docs/method.md,
// "Harmonic analysis").
//
// Notation. Points p_i, circle (centre c, radius R), radial deviations d_i = |p_i − c| − R at
// the directions θ_i of p_i − c (counter-clockwise from +x, so the coefficients do not depend
// on where the profile starts or its sense):
//   d(θ) = a_0 + Σ_{k=1}^{K} (a_k cos kθ + b_k sin kθ),   power of harmonic k: P_k = a_k² + b_k²
// (a harmonic A cos(kθ + φ) has P_k = A²; its peak-to-valley is 2A).
//
// Two paths:
//   fft         the points lie in angular order (either sense, any start) on an equiangular
//               grid θ_j = θ_0 ± 2πj/n: the coefficients are the DFT of the d_j, exact for a
//               band-limited profile (k ≤ n/2; higher harmonics alias onto min(k, n − k), as
//               they must with n samples). Samples slightly off the grid (real scans are
//               equiangular about the machine's nominal centre, not about the fitted one) are
//               taken at their grid angle when K · max_j |δ_j| ≤ 0.01 rad, δ_j the angular offset:
//               the phase error of harmonic k is k·δ_j, so every coefficient up to K is then
//               right to 1 % of its harmonic's amplitude.
//   quadrature  otherwise: C_k = (1/2π) Σ_j q_j d_j e^{−ikθ_j} on the points sorted by angle,
//               trapezoidal weights q_j = (θ_{j+1} − θ_{j−1})/2 (circular). Exact for harmonics
//               well resolved by the local spacing; a harmonic whose half wavelength π/k is
//               shorter than an angular gap of the data is not resolved there.
// Re-synthesis: with gains g_0 … g_K, point i is moved along its ray from c to the deviation
//   d'_i = Σ_{k ≤ K} g_k (a_k cos kθ_i + b_k sin kθ_i)
// (harmonics above K are dropped: their gain is 0). On the fft path this is the inverse DFT at
// the grid angles (so all gains 1 and K = ⌊n/2⌋ give back the input to rounding); on the
// quadrature path the direct sum at the true angles.
#pragma once

#include <complex>
#include <cstddef>
#include <span>
#include <vector>

#include "vcmm/geometry/point.h"

namespace vcmm::geometry {

enum class HarmonicsPath { fft, quadrature };

/// The harmonic content of one closed profile about one circle (file comment). Reusable: a
/// later analyse() reuses its storage (the Monte Carlo loop analyses one profile per trial).
/// Not safe to share between threads while analyse() runs; const members are.
class ProfileHarmonics {
 public:
  ProfileHarmonics() = default;
  /// Analyses `points` about (center, radius) up to harmonic `max_order`.
  /// Preconditions (InvalidInput, naming the value): ≥ 8 finite points, no point at the
  /// centre, a finite centre, a finite radius > 0, 1 ≤ max_order ≤ n/2.
  /// Complexity: O(n log n) on the fft path (a complex FFT of length n, Bluestein for large
  /// prime factors), O(n log n + n·K) on the quadrature path.
  ProfileHarmonics(std::span<const Point2> points, Point2 center, double radius,
                   std::size_t max_order);
  void analyse(std::span<const Point2> points, Point2 center, double radius,
               std::size_t max_order);

  std::size_t max_order() const { return max_order_; }
  std::size_t point_count() const { return points_.size(); }
  HarmonicsPath path() const { return path_; }
  Point2 center() const { return center_; }
  double radius() const { return radius_; }
  /// a_k, b_k (mm), k = 0 … max_order (b_0 = 0).
  double cos_mm(std::size_t k) const { return a_.at(k); }
  double sin_mm(std::size_t k) const { return b_.at(k); }
  /// P_k = a_k² + b_k² (mm²).
  double power_mm2(std::size_t k) const { return a_.at(k) * a_.at(k) + b_.at(k) * b_.at(k); }
  /// The radial deviations d_i of the analysed points (mm), input order.
  std::span<const double> deviations_mm() const { return deviation_; }

  /// The analysed points moved along their rays to d'_i (file comment), input order.
  /// gains.size() must be max_order + 1 and every gain finite (InvalidInput). `out` is resized
  /// to n (storage reused). O(n log n) (fft) or O(n·K) (quadrature).
  void synthesize(std::span<const double> gains, std::vector<Point2>& out) const;
  std::vector<Point2> synthesized(std::span<const double> gains) const;

 private:
  std::vector<Point2> points_;
  std::vector<double> deviation_, inv_r_;
  Point2 center_{};
  double radius_ = 0.0;
  std::size_t max_order_ = 0;
  HarmonicsPath path_ = HarmonicsPath::fft;
  // fft path: the DFT X_k of d_j (k = 0 … n − 1), the grid's sense σ and start θ_0.
  std::vector<double> x_re_, x_im_;
  double sense_ = 1.0, theta0_ = 0.0;
  // quadrature path: the true angles of the points, input order.
  std::vector<double> theta_;
  std::vector<double> a_, b_;
};

}  // namespace vcmm::geometry
