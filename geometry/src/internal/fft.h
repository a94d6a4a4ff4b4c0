// geometry/src/internal/fft.h — the complex FFT of the geometry module (used by the Gaussian
// filter and the harmonic analysis of closed profiles). Not part of the public API.
//
// A small mixed-radix Stockham FFT (radices 8, 4, 2, 5, 9, 3 and 7/11/13 by direct DFT) with
// Bluestein's chirp-z algorithm for sizes with a larger prime factor (prime n costs ~6 FFTs of a
// smooth size ≥ 2n). Eigen's kissfft backend was measured first: 41 µs for a forward + inverse
// real transform at n = 3600 and 0.13 s at the prime n = 3607 (its generic radix is O(p²)),
// against a 30 µs budget (gaussian_filter.cpp). The passes are written on vectors of doubles
// (GCC/Clang vector extensions) and compiled three times, for the package's baseline ISA, for
// AVX2 and for AVX-512, the widest the CPU has chosen once at run time; all give the same bits
// (fft_variants). A plan holds its own scratch: one plan per thread.
#pragma once

#include <algorithm>
#include <cstddef>
#include <memory>
#include <string_view>
#include <vector>

#include "aligned.h"  // (relative: benchmarks and tests include this header by path)

namespace vcmm::geometry::internal {

// ---- complex arithmetic without the NaN-recovery path of std::complex multiplication ----------
struct Cx {
  double re = 0.0;
  double im = 0.0;
};
inline Cx operator+(Cx a, Cx b) { return {a.re + b.re, a.im + b.im}; }
inline Cx operator-(Cx a, Cx b) { return {a.re - b.re, a.im - b.im}; }
inline Cx operator*(Cx a, Cx b) { return {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re}; }
inline Cx operator*(double s, Cx a) { return {s * a.re, s * a.im}; }
inline Cx conj(Cx a) { return {a.re, -a.im}; }
inline Cx times_minus_i(Cx a) { return {a.im, -a.re}; }  // a · (−i)

/// exp(−2πi j / n), correctly rounded to within an ulp or so: the angle is formed and reduced
/// in long double (64-bit significand) before rounding to double.
Cx unit_root(std::size_t j, std::size_t n);

/// A complex DFT of one size on split storage (real and imaginary parts in separate arrays, so
/// that the compiler vectorises each butterfly across independent sub-transforms).
class ComplexFft {
 public:
  explicit ComplexFft(std::size_t n);
  std::size_t size() const { return n_; }
  /// In place: X_k = Σ_j x_j e^{−2πi jk/n} (unnormalised).
  void forward(double* re, double* im);
  /// In place: x_j = Σ_k X_k e^{+2πi jk/n} (unnormalised). Exchanging the real and imaginary
  /// parts maps z to i conj(z), and DFT(i conj z) = i conj(IDFT(z)).
  void inverse(double* re, double* im) { forward(im, re); }
  /// inverse() with the result written interleaved, out[2j] = Re x_j, out[2j + 1] = Im x_j, by
  /// its last pass (re and im are left as scratch): the same values, one pass less for callers
  /// that want pairs (the real transforms of even length). out: 2n doubles, not re or im.
  void inverse_interleaved(double* re, double* im, double* out);
  /// forward() of x_j = in[2j] + i in[2j + 1] (in: 2n doubles, not re or im), the result in
  /// (re, im): the same values, with the split into real and imaginary parts done by the first
  /// pass's loads (radix 2, 4 or 8 first; else a split first).
  void forward_from_interleaved(const double* in, double* re, double* im);
  /// forward() by the named instruction-set variant (fft_variants(); std::invalid_argument for
  /// another name): for tests and benchmarks — every variant gives the same bits.
  void forward_with(std::string_view variant, double* re, double* im);

  struct Stage {
    std::size_t radix = 0;
    std::size_t m = 0;                 // sub-transform length after this stage
    std::vector<double> tw_re, tw_im;  // [(u − 1) m + p] = ω_L^{p u}, L = radix · m
    std::vector<Cx> roots;             // ω_radix^t, generic radices only
  };
  /// Interleaved input or output of a run: in[2j] + i in[2j + 1] as the input (then re, im
  /// only receive the result), out[2j + first], out[2j + 1 − first] for the result.
  struct PassIo {
    const double* in = nullptr;
    double* out = nullptr;
    int first = 0;
  };
  /// All passes of a plan on (re, im) with scratch (sr, si): one per instruction-set variant.
  using StagePasses = void (*)(const Stage* stages, std::size_t count, double* re,
                               double* im, double* sr, double* si, const PassIo& io);

 private:
  static std::size_t smooth_size_at_least(std::size_t v);
  void setup_bluestein();
  static StagePasses selected_passes();
  void run(StagePasses passes, double* re, double* im, const PassIo& io);
  void bluestein(StagePasses passes, double* re, double* im);

  std::size_t n_;
  std::vector<Stage> stages_;
  AlignedDoubles scratch_re_, scratch_im_;
  std::unique_ptr<ComplexFft> conv_;  // Bluestein only
  std::vector<Cx> chirp_, chirp_hat_;
  AlignedDoubles work_re_, work_im_;
};

/// An instruction-set variant of the FFT's passes, compiled from the same source: "baseline"
/// (the package's target ISA) and, on x86-64 CPUs that have them, "avx2" (4 doubles a vector)
/// and "avx512" (8 doubles a vector; F, DQ, VL); no FMA. Same operations in the same order, so
/// the same bits on every machine (internal/isa.h; tests/geometry/fft_test.cpp); forward()
/// uses the last (widest) one unless a ForceBaselineIsa is alive on the thread.
struct FftVariant {
  std::string_view name;
  ComplexFft::StagePasses passes;
};
/// The variants this CPU can run, baseline first.
const std::vector<FftVariant>& fft_variants();

/// The plan of size n from a small per-thread cache of `capacity` sizes (most recently used
/// first). Plans hold their own scratch, so a thread-local cache is also what makes concurrent
/// calls safe. Plan: constructible from the size, with size().
template <class Plan, std::size_t capacity = 8>
Plan& thread_local_plan(std::size_t n) {
  thread_local std::vector<std::unique_ptr<Plan>> cache;
  for (std::size_t i = 0; i < cache.size(); ++i) {
    if (cache[i]->size() == n) {
      std::rotate(cache.begin(), cache.begin() + static_cast<std::ptrdiff_t>(i),
                  cache.begin() + static_cast<std::ptrdiff_t>(i) + 1);
      return *cache.front();
    }
  }
  if (cache.size() == capacity) cache.pop_back();
  cache.insert(cache.begin(), std::make_unique<Plan>(n));
  return *cache.front();
}

}  // namespace vcmm::geometry::internal
