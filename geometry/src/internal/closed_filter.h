// geometry/src/internal/closed_filter.h — the ISO 16610-21 Gaussian filter of a closed,
// equiangular profile of one size: "multiply harmonic k by H(k) = 2^−(k/f_c)²" by a real FFT
// (gaussian_filter.cpp, "Equiangular profiles", says why that is the filter). Not part of the
// public API.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "internal/fft.h"
#include "internal/aligned.h"

namespace vcmm::geometry::internal {

/// The filter of n equiangular deviations, with its FFT plan, scratch and the transmission of
/// the last cut-off: one plan per thread (thread_local_plan, internal/fft.h). Real input of
/// even length n runs as one complex FFT of length n/2. Error ~ε·log n of the profile's
/// amplitude. The vectorised steps have instruction-set variants (internal/isa.h) that give the
/// same bits.
class ClosedFilterPlan {
 public:
  explicit ClosedFilterPlan(std::size_t n);

  std::size_t size() const { return n_; }

  /// out = filtered in (both of length n); cutoff_upr: f_c in UPR, finite and > 0 (the
  /// caller checks).
  void apply(const double* in, double* out, double cutoff_upr);

 private:
  void set_transmission(double cutoff_upr);
  void apply_even(const double* in, double* out);
  void apply_odd(const double* in, double* out);

  std::size_t n_;
  bool even_;
  ComplexFft fft_;
  AlignedDoubles re_, im_;
  std::vector<Cx> half_roots_;               // ω_n^k, k ≤ n/4 (even n)
  std::vector<double> roots_re_, roots_im_;  // the same, split
  double cutoff_ = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> h_;
};

}  // namespace vcmm::geometry::internal
