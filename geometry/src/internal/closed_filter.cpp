// geometry/src/internal/closed_filter.cpp — the closed-profile Gaussian filter of one size
// (internal/closed_filter.h): real FFT, transmission H(k) = 2^−(k/f_c)², inverse FFT.
//
// Even n = 2N runs as one complex FFT of length N (apply_even); odd n as a complex FFT of
// length n with zero imaginary parts. The input's split into even and odd samples is done by
// the FFT's first pass (forward_from_interleaved); the spectrum step of each harmonic pair is
// compiled per instruction set like the FFT's passes (internal/isa.h): the same operations on
// each element, no reduction, so the same bits from every variant.
#include "internal/closed_filter.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "internal/isa.h"

namespace vcmm::geometry::internal {
namespace {

/// The step of ClosedFilterPlan::apply_even (see there) for the pairs (k, N − k), 1 ≤ k ≤
/// `pairs` < N − k, in place on (re, im) of length N = half: the operations of the Cx code
/// there, written out on doubles so that the compiler vectorises across k (the N − k side
/// read and written backwards); the same values bit for bit.
[[gnu::always_inline]] inline void spectrum_pairs_body(std::size_t pairs, std::size_t half,
                                                       double* __restrict lr,
                                                       double* __restrict li,
                                                       const double* __restrict h,
                                                       const double* __restrict wr,
                                                       const double* __restrict wi) {
  double* __restrict hr = lr + half;  // hr[−k] = re[N − k]
  double* __restrict hi = li + half;
  const double* __restrict hh = h + half;
  for (std::size_t k = 1; k <= pairs; ++k) {
    const auto j = static_cast<std::ptrdiff_t>(k);
    const double ar = lr[k], ai = li[k], br = hr[-j], bi = -hi[-j];
    const double er = 0.5 * (ar + br), ei = 0.5 * (ai + bi);
    const double orr = 0.5 * (ai - bi), oi = -(0.5 * (ar - br));  // −i (a − b)/2
    const double hp = 0.5 * (h[k] + hh[-j]), hm = 0.5 * (h[k] - hh[-j]);
    const double c = wr[k], d = wi[k], nd = -d;
    const double wo_r = c * orr - d * oi, wo_i = c * oi + d * orr;  // ω^k O
    const double e2r = hp * er + hm * wo_r, e2i = hp * ei + hm * wo_i;
    const double we_r = c * er - nd * ei, we_i = c * ei + nd * er;  // conj(ω^k) E
    const double o2r = hm * we_r + hp * orr, o2i = hm * we_i + hp * oi;
    lr[k] = e2r - o2i;  // E' + i O'
    li[k] = e2i + o2r;
    hr[-j] = e2r + o2i;  // conj E' + i conj O'
    hi[-j] = o2r - e2i;
  }
}

// The variants (internal/isa.h); GCC vectorises the AVX-512 ones 8 wide only when asked to
// prefer 512-bit vectors.
void spectrum_pairs_baseline(std::size_t pairs, std::size_t half, double* lr, double* li,
                             const double* h, const double* wr, const double* wi) {
  spectrum_pairs_body(pairs, half, lr, li, h, wr, wi);
}
#if VCMM_GEOMETRY_X86
__attribute__((target("avx2"))) void spectrum_pairs_avx2(std::size_t pairs, std::size_t half,
                                                         double* lr, double* li,
                                                         const double* h, const double* wr,
                                                         const double* wi) {
  spectrum_pairs_body(pairs, half, lr, li, h, wr, wi);
}
__attribute__((target("avx512f,avx512dq,avx512vl,prefer-vector-width=512"))) void
spectrum_pairs_avx512(std::size_t pairs, std::size_t half, double* lr, double* li,
                      const double* h, const double* wr, const double* wi) {
  spectrum_pairs_body(pairs, half, lr, li, h, wr, wi);
}
#endif

void spectrum_pairs(std::size_t pairs, std::size_t half, double* lr, double* li,
                    const double* h, const double* wr, const double* wi) {
#if VCMM_GEOMETRY_X86
  if (use_avx512()) return spectrum_pairs_avx512(pairs, half, lr, li, h, wr, wi);
  if (use_avx2()) return spectrum_pairs_avx2(pairs, half, lr, li, h, wr, wi);
#endif
  spectrum_pairs_baseline(pairs, half, lr, li, h, wr, wi);
}

}  // namespace

ClosedFilterPlan::ClosedFilterPlan(std::size_t n)
    : n_(n), even_(n % 2 == 0), fft_(even_ ? n / 2 : n), re_(fft_.size()), im_(fft_.size()) {
  if (even_) {
    half_roots_.resize(n / 4 + 1);
    roots_re_.resize(n / 4 + 1);
    roots_im_.resize(n / 4 + 1);
    for (std::size_t k = 0; k <= n / 4; ++k) {
      half_roots_[k] = unit_root(k, n);
      roots_re_[k] = half_roots_[k].re;
      roots_im_[k] = half_roots_[k].im;
    }
  }
}

void ClosedFilterPlan::apply(const double* in, double* out, double cutoff_upr) {
  set_transmission(cutoff_upr);
  if (even_)
    apply_even(in, out);
  else
    apply_odd(in, out);
}

/// H(k) for k = 0..⌊n/2⌋, with the 1/(FFT length) of the inverse transform folded in.
void ClosedFilterPlan::set_transmission(double cutoff_upr) {
  if (cutoff_upr == cutoff_) return;
  cutoff_ = cutoff_upr;
  const std::size_t half = n_ / 2;
  h_.assign(half + 1, 0.0);
  const double norm = 1.0 / static_cast<double>(fft_.size());
  for (std::size_t k = 0; k <= half; ++k) {
    const double ratio = static_cast<double>(k) / cutoff_upr;
    // H(k) = 2^−(k/f_c)². Below 2^−1000 (k > 31.6 f_c) it is set to 0: the products with
    // it would be subnormal (slow) and are 1e-301 of that harmonic's amplitude.
    if (ratio * ratio > 1000.0) break;  // the rest stays 0
    h_[k] = std::exp2(-ratio * ratio) * norm;
  }
}

// Even n = 2N: z_j = x_{2j} + i x_{2j+1}, Z = FFT_N(z). The spectrum of x is X_k = E_k +
// ω^k O_k (ω = e^{−2πi/n}) with E_k = (Z_k + conj Z_{N−k})/2 and O_k = (Z_k − conj Z_{N−k})/(2i),
// the transforms of the even and odd samples; X_{N−k} = conj(E_k − ω^k O_k). After
// Y_k = H_k X_k the even/odd transforms of the output are, with H± = (H_k ± H_{N−k})/2,
//   E'_k = H+ E_k + H− ω^k O_k,   O'_k = H− conj(ω^k) E_k + H+ O_k,
// and Z'_k = E'_k + i O'_k, Z'_{N−k} = conj E'_k + i conj O'_k; y_{2j} + i y_{2j+1} is the
// inverse FFT of Z'. Each pair (k, N − k) is done in place in one step.
void ClosedFilterPlan::apply_even(const double* in, double* out) {
  const std::size_t half = n_ / 2;
  fft_.forward_from_interleaved(in, re_.data(), im_.data());
  // The pairs 1 ≤ k < N − k vectorised (spectrum_pairs), then k = 0 and k = N/2 here.
  const std::size_t pairs = (half - 1) / 2;
  spectrum_pairs(pairs, half, re_.data(), im_.data(), h_.data(), roots_re_.data(),
                 roots_im_.data());
  for (std::size_t k = 0; 2 * k <= half; k = k == 0 ? pairs + 1 : half) {
    const std::size_t k2 = k == 0 ? 0 : half - k;  // partner index (Z_N ≡ Z_0)
    const Cx a{re_[k], im_[k]}, b{re_[k2], -im_[k2]};
    const Cx e = 0.5 * (a + b);
    const Cx o = times_minus_i(0.5 * (a - b));
    const double hp = 0.5 * (h_[k] + h_[half - k]), hm = 0.5 * (h_[k] - h_[half - k]);
    const Cx w = half_roots_[k];
    const Cx e2 = hp * e + hm * (w * o);
    const Cx o2 = hm * (conj(w) * e) + hp * o;
    re_[k] = e2.re - o2.im;  // E' + i O'
    im_[k] = e2.im + o2.re;
    if (k2 != k) {
      re_[k2] = e2.re + o2.im;  // conj E' + i conj O'
      im_[k2] = o2.re - e2.im;
    }
  }
  fft_.inverse_interleaved(re_.data(), im_.data(), out);  // y_2j + i y_2j+1
}

void ClosedFilterPlan::apply_odd(const double* in, double* out) {
  std::copy(in, in + n_, re_.begin());
  std::fill(im_.begin(), im_.end(), 0.0);
  fft_.forward(re_.data(), im_.data());
  for (std::size_t k = 0; k < n_; ++k) {
    const double h = h_[std::min(k, n_ - k)];
    re_[k] *= h;
    im_[k] *= h;
  }
  fft_.inverse(re_.data(), im_.data());
  std::copy(re_.begin(), re_.end(), out);
}

}  // namespace vcmm::geometry::internal
