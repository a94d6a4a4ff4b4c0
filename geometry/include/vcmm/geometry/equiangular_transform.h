// vcmm/geometry/equiangular_transform.h — the real Fourier series of a closed sequence sampled
// on an equiangular grid, by index, and its inverse (docs/method.md, "Harmonic analysis").
//
// Notation. n samples v_j, j = 0 … n − 1, at the grid angles 2πj/n (the index is the angle: a
// profile's start angle and sense are the caller's), K = ⌊n/2⌋:
//   v_j = a_0 + Σ_{k=1}^{K} (a_k cos(2πkj/n) + b_k sin(2πkj/n)),
//   a_0 = (1/n) Σ v_j,   a_k = (2/n) Σ v_j cos(2πkj/n),   b_k = (2/n) Σ v_j sin(2πkj/n)  (0<k<n/2),
//   and for even n the Nyquist term a_{n/2} = (1/n) Σ (−1)^j v_j, b_{n/2} = 0.
// This is the convention of the Gaussian filter's FFT path (gaussian_filter.h): filtering is
// multiplying a_k, b_k by H(k). Independent N(0, v) samples have independent coefficients with
// var a_0 = v/n, var a_k = var b_k = 2v/n (0 < k < n/2), var a_{n/2} = v/n (exact, any n).
#pragma once

#include <cstddef>
#include <memory>
#include <span>

namespace vcmm::geometry {

/// The transform of one size n ≥ 2 (file comment). Holds its FFT plan and scratch: one object
/// per thread (not safe to share while a member runs). Accuracy: ~ε·log n of the largest
/// amplitude (the mixed-radix FFT of geometry/src/internal/fft.h).
class EquiangularTransform {
 public:
  /// Throws InvalidInput for n < 2. O(n) (plan).
  explicit EquiangularTransform(std::size_t n);
  ~EquiangularTransform();
  EquiangularTransform(EquiangularTransform&&) noexcept;
  EquiangularTransform& operator=(EquiangularTransform&&) noexcept;

  std::size_t size() const;
  /// a_k, b_k for k = 0 … K (K = ⌊n/2⌋) of `values` (size n); `cos`, `sin` of size K + 1.
  /// InvalidInput on a size mismatch. O(n log n).
  void coefficients(std::span<const double> values, std::span<double> cos,
                    std::span<double> sin);
  /// v_j, j < n, from a_k, b_k for k = 0 … cos.size() − 1 (≤ K; higher harmonics are zero;
  /// b_0 and b_{n/2} are ignored). `out` of size n. InvalidInput on a size mismatch.
  /// O(n log n): for even n one complex FFT of length n/2 (~7.5 µs at n = 3600 on a 2.1 GHz
  /// Xeon with AVX2, docs/performance.md).
  void values(std::span<const double> cos, std::span<const double> sin, std::span<double> out);

 private:
  struct Plan;
  std::unique_ptr<Plan> plan_;
};

}  // namespace vcmm::geometry
