// gaussian_filter.cpp — the ISO 16610-21 Gaussian profile filter for closed (roundness)
// profiles, as used by ISO 12181-2 for roundness.
//
// Notation. Cut-off f_c (UPR), cut-off wavelength λ_c = 2π / f_c (rad), α = sqrt(ln 2 / π).
// Weighting function of a closed profile (ISO 16610-21:2011, 5.2), in angle θ:
//   s(θ) = 1/(α λ_c) · exp(−π (θ / (α λ_c))²), wrapped periodically (Σ_m s(θ + 2π m)),
// whose transmission for harmonic k (ISO 16610-21:2011, 5.3.1) is
//   H(k) = exp(−π (α k / f_c)²) = 2^−(k/f_c)²     (H(0) = 1, H(f_c) = ½, H(2 f_c) = 1/16).
// The filtered (mean-line) profile is the periodic convolution of the radial deviations
// with s; it is returned as points, so the short-wave component is input − output.
//
// Equiangular profiles (the FFT path). For samples at θ_j = θ₀ ± 2πj/n the periodic
// convolution acts on the trigonometric interpolant of the samples harmonic by harmonic, so
// the filter is exactly "multiply harmonic k by H(k)" for k ≤ n/2 (harmonics above n/2 do not
// exist in n samples; they alias and the filter treats each pair k, n − k as harmonic
// min(k, n − k)). This is done by a real FFT: no truncation of s, no end effects (the profile
// is closed), error ~ε·log n of the profile's amplitude. Start angle and rotational sense do
// not matter (H is real and even). Detection: every direction about the filter (LS) centre lies
// less than half a step off the grid θ_0 ± 2πj/n (cross and dot products with cached rotation
// tables, no arctangent): then sample j is nearer grid position j than any other and the input
// order is the angular order. Real scans are equiangular about the machine's nominal centre, not
// about the LS centre, so their angles sit off the grid by up to ~e/R (eccentricity e) plus the
// tangential part of the probing noise (~σ/R per sample, relative to sample 0); the FFT result
// is kept only when the first-order effect of that displacement, 2·δ_max·max|w'|, is at most
// 1e-3 of the filtered peak-to-valley (or 1e-10 mm) — see grid_error_is_negligible — otherwise
// the nonuniform path below is used. (The limit was a quarter step until 2026-11: dense scans
// then fell off the FFT path on noise alone — at 36 000 points of the 171 mm ring, 0.7 µm noise
// displaces samples by ~5e-5 rad against a quarter step of 4.4e-5 rad — and took the nonuniform
// path, ~500× slower, whose quadrature weights then fluctuate with the noise by ±30 % of a
// step; the equal weights of the scan's own grid are the standard discrete filter.) A closing point that repeats the first one
// (within a quarter step in angle: a closed scan) is detected: the two deviations at that angle
// are averaged, the n − 1 distinct angles are filtered, and the repeated point gets the
// filtered value of the first.
//
// Uneven spacing (the nonuniform path). ISO 16610-21 defines the filter as a convolution
// integral over the profile and, for equally spaced data, its discretisation; it does not
// prescribe a rule for uneven spacing (CMM scans with a slightly eccentric centre, touch
// points, gaps). We discretise the integral by the trapezoidal rule on the sorted angles:
//   w_i = Σ_j q_j s_w(θ_i − θ_j) d_j / Σ_j q_j s_w(θ_i − θ_j),
//   q_j = (θ_{j+1} − θ_{j−1}) / 2 (circular),   d_j the radial deviations,
// i.e. the quadrature weight of each sample times the wrapped weighting function, normalised by
// the sum of weights so that a constant deviation passes unchanged (the discrete analogue of
// ∫ s = 1) and a lone cluster of dense points cannot dominate its neighbourhood. On equally
// spaced data this is the standard discrete Gaussian filter. The weighting function is
// truncated at |θ| ≤ 4 α λ_c: there s(θ)/s(0) = e^−16π ≈ 1.5e-22 and the neglected mass is
// erfc(4√π) ≈ 2e-24 of the total — below double-precision rounding, so the truncation is exact
// in double (at ±3 α λ_c the neglected mass, ~1e-12 relative, would still show). Accuracy: the
// trapezoidal rule's error, small when α λ_c spans several samples (ISO 12181-2 sizes the
// number of points to the cut-off for this reason): first order in the spacing irregularity
// and second order in h / (α λ_c) — observed ≤ 5.3 · jitter · (h / α λ_c)² of a harmonic's
// amplitude, h the mean step and jitter the largest spacing error in steps (see the tests). A
// repeated angle (e.g. a closed scan's repeated first point) gives both samples half a weight:
// they are averaged. Complexity O(n · m), m = points within ±4 α λ_c ≈ 3.8 n / f_c; the
// kernel's symmetry halves the exponentials (≈ 3 ms at n = 3600, f_c = 50).
//
// Closedness. The profile must go once round its filter centre: sorted by angle about the LS
// centre, no two neighbours (including the wrap from the last to the first) may be more than
// λ_c / 2 = π / f_c apart — beyond that the weighting function has nothing to average over and
// the "closed profile" filter of ISO 16610-21, 5 would silently bridge the gap.
//
// Reconstruction. Point i is moved along its ray from the filter centre c to the filtered
// radius: q_i = p_i + (p_i − c) (w_i − d_i) / r_i, with r_i = |p_i − c|, d_i = r_i − R the
// deviation and w_i its filtered value — the input point plus a small correction, so far-from-
// origin data lose nothing beyond the final rounding. Same count and order as the input.
//
// FFT: internal/closed_filter.h (the filter of one size: real input of even length n runs as
// one complex FFT of length n/2) on internal/fft.h (mixed radix with Bluestein for large prime
// factors). Plans (twiddles, transmission) are cached per thread for the last few sizes. The
// vectorised passes here (first pass, grid check, reconstruction) have baseline, AVX2 and
// AVX-512 variants with the same bits (internal/isa.h).
#include "vcmm/geometry/gaussian_filter.h"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <numbers>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

#include "vcmm/geometry/least_squares.h"

#include "internal/aligned.h"
#include "internal/closed_filter.h"
#include "internal/fft.h"
#include "internal/isa.h"
#include "internal/least_squares_on_rays.h"
#include "internal/near_circle.h"
#include "internal/prevalidated.h"
#include "internal/vec.h"

namespace vcmm::geometry {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kAlpha = 0.46971863934982566;  // sqrt(ln 2 / π)

// The closed-profile filter of one size (real FFT + transmission): internal/closed_filter.h.
using internal::ClosedFilterPlan;
ClosedFilterPlan& plan_for(std::size_t n) {
  return internal::thread_local_plan<ClosedFilterPlan>(n);
}

void check_cutoff(const char* caller, double cutoff_upr) {
  if (!(std::isfinite(cutoff_upr) && cutoff_upr > 0.0)) {
    std::ostringstream os;
    os << caller << ": the cut-off must be a finite number of UPR > 0; got " << cutoff_upr;
    throw InvalidInput(os.str());
  }
}

// ---- the nonuniform path --------------------------------------------------------------------

double degrees(double rad) { return rad * 180.0 / kPi; }

/// Filtered deviations of an unevenly spaced closed profile (see the file header), in input
/// order. `angle` are the directions about the filter centre in (−π, π]. A gap wider than
/// λc/2 throws InvalidInput, or, with `not_closed` given, sets *not_closed and returns
/// nothing.
std::vector<double> filter_nonuniform(const std::vector<double>& angle,
                                      const std::vector<double>& deviation, double cutoff_upr,
                                      bool* not_closed = nullptr) {
  const std::size_t n = angle.size();
  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return angle[a] < angle[b] || (angle[a] == angle[b] && a < b);
  });

  // Closedness: the largest angular gap between neighbours (with the wrap) ≤ λ_c / 2.
  const double max_gap = kPi / cutoff_upr;
  std::vector<double> gap(n);  // gap[j]: from sorted j to sorted j + 1
  for (std::size_t j = 0; j < n; ++j) {
    const double next = j + 1 < n ? angle[order[j + 1]] : angle[order[0]] + 2 * kPi;
    gap[j] = next - angle[order[j]];
    if (gap[j] > max_gap) {
      if (not_closed) {
        *not_closed = true;
        return {};
      }
      std::ostringstream os;
      os << "gaussian_filtered_profile: profile is not closed: angular gap of "
         << degrees(gap[j]) << "° between points " << order[j] << " and "
         << order[j + 1 < n ? j + 1 : 0] << " exceeds λc/2 = " << degrees(max_gap)
         << "° (cut-off " << cutoff_upr << " UPR)";
      throw InvalidInput(os.str());
    }
  }

  // Sorted quadrature weights q_j and q_j·deviation_j.
  std::vector<double> theta(n), q(n), qd(n);
  for (std::size_t j = 0; j < n; ++j) {
    theta[j] = angle[order[j]];
    q[j] = 0.5 * (gap[j] + gap[(j + n - 1) % n]);
    qd[j] = q[j] * deviation[order[j]];
  }

  // Σ_j q_j s_w(θ_i − θ_j) (·deviation_j), the wrapped weighting function truncated at
  // |Δ| ≤ 4 α λ_c. The kernel is symmetric, so each pair (and each periodic image of it) is
  // visited once, from its lower sorted index going forward (Δ > 0, or Δ = 0 for equal
  // angles), and added to both ends: half the exponentials of a per-output window.
  const double width = kAlpha * 2 * kPi / cutoff_upr;  // α λ_c
  const double half_window = 4.0 * width;
  const double a = kPi / (width * width);               // s ∝ exp(−a Δ²)
  std::vector<double> num(qd), den(q);                  // the Δ = 0 self terms
  for (std::size_t i = 0; i < n; ++i) {
    double wrap = 0.0;  // 2π × the number of times j has wrapped past the end
    double num_i = 0.0, den_i = 0.0;
    for (std::size_t j = i + 1;; ++j) {
      if (j == n) {
        j = 0;
        wrap += 2 * kPi;
      }
      const double delta = theta[j] + wrap - theta[i];
      if (delta > half_window) break;
      const double g = std::exp(-a * delta * delta);
      num_i += g * qd[j];
      den_i += g * q[j];
      num[j] += g * qd[i];
      den[j] += g * q[i];
    }
    num[i] += num_i;
    den[i] += den_i;
  }
  std::vector<double> out(n);
  for (std::size_t j = 0; j < n; ++j) out[order[j]] = num[j] / den[j];
  return out;
}

// ---- equiangular detection ----------------------------------------------------------------------

/// Directions p_i − c about the filter centre, their lengths (r: set only off the series'
/// range, see filter_about) and reciprocal lengths, in
/// structure-of-arrays form (vectorised products), with the deviations, their filtered values,
/// the sines of the grid displacements and two scratch arrays. One per thread, kept between
/// calls: reallocating them per call cost ~10 page faults per array at n = 36 000.
struct Rays {
  using Array = Eigen::Map<Eigen::ArrayXd, Eigen::Aligned64>;
  Array x{nullptr, 0}, y{nullptr, 0}, r{nullptr, 0}, inv_r{nullptr, 0};
  Array deviation{nullptr, 0}, filtered{nullptr, 0}, sin_delta{nullptr, 0};
  Array scratch{nullptr, 0}, scratch2{nullptr, 0};

  /// Each array n long, starting on a cache line (internal/aligned.h: the vectorised passes
  /// and the FFT read and write them 8 doubles at a time); storage kept when n shrinks.
  void resize(Eigen::Index n) {
    if (n == size_) return;
    const Eigen::Index stride = (n + 7) / 8 * 8;
    if (static_cast<std::size_t>(9 * stride) > storage_.size())
      storage_.resize(static_cast<std::size_t>(9 * stride));
    double* p = storage_.data();
    for (Array* a : {&x, &y, &r, &inv_r, &deviation, &filtered, &sin_delta, &scratch,
                     &scratch2}) {
      new (a) Array(p, n);  // re-seating a Map: Eigen's documented placement new
      p += stride;
    }
    size_ = n;
  }

 private:
  internal::AlignedDoubles storage_;
  Eigen::Index size_ = -1;
};

/// cos(2πj/count), sin(2πj/count) for j < count, cached per thread for the last two sizes
/// (a closed scan repeating its first point is tried with n and then n − 1 rays).
struct GridTable {
  Eigen::Index size = 0;
  Eigen::ArrayXd cos, sin;
};
const GridTable& grid_table(Eigen::Index count) {
  thread_local std::array<GridTable, 2> cache;
  thread_local std::size_t next = 0;
  for (const GridTable& t : cache)
    if (t.size == count) return t;
  GridTable& t = cache[next];
  next = 1 - next;
  const double step = 2 * kPi / static_cast<double>(count);
  t.cos.resize(count);
  t.sin.resize(count);
  for (Eigen::Index j = 0; j < count; ++j) {
    t.cos[j] = std::cos(step * static_cast<double>(j));
    t.sin[j] = std::sin(step * static_cast<double>(j));
  }
  t.size = count;
  return t;
}

// ---- the grid check's first stage, vectorised per instruction set ---------------------------
// Maxima and minima of finite values are exact whatever the grouping, so the 2-, 4- and 8-wide
// variants (internal/isa.h) give the same values (a zero's sign aside, which only enters as a
// difference with itself).

/// Stage 1 of grid_error_is_negligible (see there): max_j |D_j|·max(|s_j|, |s_{j+1}|) with
/// D_j = w_{j+1} − w_j (cyclic), and the extremes of w.
struct GridSlopeBound {
  double worst, w_max, w_min;
};
template <int W>
[[gnu::always_inline]] inline GridSlopeBound grid_slope_bound_body(const double* w,
                                                                   const double* sd,
                                                                   Eigen::Index count) {
  using V = typename internal::VecOf<W>::type;
  using M = typename internal::VecOf<W>::mask;
  const auto abs = [](V x) { return V(M(x) & (M{} + 0x7fffffffffffffffLL)); };
  const auto vmax = [](V a, V b) { return a > b ? a : b; };
  const auto vmin = [](V a, V b) { return a < b ? a : b; };
  double worst = 0.0, w_max = w[count - 1], w_min = w[count - 1];
  const Eigen::Index pairs = count - 1;  // D_j for j < count − 1, then the wrap
  const Eigen::Index packed = pairs - pairs % W;
  V pworst = V{} + 0.0, pmax = V{} + w[0], pmin = pmax;
  for (Eigen::Index j = 0; j < packed; j += W) {
    const V wj = internal::load<V>(w + j);
    const V d = abs(internal::load<V>(w + j + 1) - wj);
    const V s0 = abs(internal::load<V>(sd + j));
    const V s1 = abs(internal::load<V>(sd + j + 1));
    pworst = vmax(pworst, vmax(d * s0, d * s1));
    pmax = vmax(pmax, wj);
    pmin = vmin(pmin, wj);
  }
  for (int l = 0; l < W; ++l) {
    worst = std::max(worst, pworst[l]);
    w_max = std::max(w_max, pmax[l]);
    w_min = std::min(w_min, pmin[l]);
  }
  for (Eigen::Index j = packed; j < pairs; ++j) {
    const double d = std::fabs(w[j + 1] - w[j]);
    worst = std::max({worst, d * std::fabs(sd[j]), d * std::fabs(sd[j + 1])});
    w_max = std::max(w_max, w[j]);
    w_min = std::min(w_min, w[j]);
  }
  const double d = std::fabs(w[0] - w[count - 1]);  // the wrap: D_{count−1}
  worst = std::max({worst, d * std::fabs(sd[count - 1]), d * std::fabs(sd[0])});
  return {worst, w_max, w_min};
}

GridSlopeBound grid_slope_bound_baseline(const double* w, const double* sd, Eigen::Index count) {
  return grid_slope_bound_body<2>(w, sd, count);
}
#if VCMM_GEOMETRY_X86
__attribute__((target("avx2"))) GridSlopeBound grid_slope_bound_avx2(const double* w,
                                                                     const double* sd,
                                                                     Eigen::Index count) {
  return grid_slope_bound_body<4>(w, sd, count);
}
__attribute__((target("avx512f,avx512dq,avx512vl"))) GridSlopeBound grid_slope_bound_avx512(
    const double* w, const double* sd, Eigen::Index count) {
  return grid_slope_bound_body<8>(w, sd, count);
}
#endif
GridSlopeBound grid_slope_bound(const double* w, const double* sd, Eigen::Index count) {
#if VCMM_GEOMETRY_X86
  if (internal::use_avx512()) return grid_slope_bound_avx512(w, sd, count);
  if (internal::use_avx2()) return grid_slope_bound_avx2(w, sd, count);
#endif
  return grid_slope_bound_baseline(w, sd, count);
}

/// The verdict on the grid displacements of `count` rays once max |sin δ_j| is known and
/// whether every |r_j| cos δ_j > 0: max_sin, or +∞ when some ray is half a step or more off its
/// grid position (then the samples are not in equiangular order).
double grid_verdict(Eigen::Index count, double max_sin, bool all_cos_positive) {
  const double step = 2 * kPi / static_cast<double>(count);
  if (!all_cos_positive || !(max_sin < std::sin(0.5 * step)))
    return std::numeric_limits<double>::infinity();
  return max_sin;
}

/// Largest |sin δ_j| of rays 0, …, count−1 against the equiangular grid θ_j = θ_0 +
/// σ·2πj/count (σ = ±1, the rotational sense of rays 0 → 1), with sin δ_j stored in
/// v.sin_delta; or +∞ when some ray is half a step or more off its grid position (then the
/// samples are not in equiangular order at all). Ray j is rotated back by σ·2πj/count with
/// cached cos/sin tables and compared with ray 0 by cross and dot products (no arctangent):
/// sin δ_j = (r_0 × r_j') / (|r_0||r_j|). (filter_about computes the same values for count = n
/// in its first pass; this is the separate pass for count = n − 1.)
double max_grid_displacement_sine(Rays& v, Eigen::Index count) {
  const GridTable& table = grid_table(count);
  const double sense = v.x[0] * v.y[1] - v.y[0] * v.x[1] >= 0.0 ? 1.0 : -1.0;
  const auto x = v.x.head(count), y = v.y.head(count);
  const auto c = table.cos.head(count);
  const auto sn = sense * table.sin.head(count);
  const auto xr = x * c + y * sn;  // ray j rotated by −σ·2πj/count
  const auto yr = y * c - x * sn;
  const double x0 = v.x[0] * v.inv_r[0], y0 = v.y[0] * v.inv_r[0];  // unit ray 0
  v.sin_delta.head(count) = (x0 * yr - y0 * xr) * v.inv_r.head(count);
  return grid_verdict(count, v.sin_delta.head(count).abs().maxCoeff(),
                      (x0 * xr + y0 * yr).minCoeff() > 0.0);
}

/// Accepts the FFT result w of samples whose angles are off the equiangular grid by δ_j
/// (sin δ_j in v.sin_delta, |sin δ_j| ≤ max_sin). Treating a sample at θ_j + δ_j as if it
/// were at θ_j changes the input by d'(θ_j)·δ_j to first order, and the output, read on the
/// sample's own ray, differs from the filtered profile there by w'(θ_j)·δ_j: to first order the
/// FFT result is off by E = w'δ − F(d'δ), F the filter (a positive kernel of unit mass), d'
/// the slope of the form, estimated from the filtered profile w (noise rides with its sample
/// and is not displaced). Accepted when max|E| is at most 1e-3 of the filtered peak-to-valley
/// or 1e-10 mm, so the FFT path never changes RONt by more than about 0.1 %; otherwise the
/// caller uses the nonuniform path, which takes the true angles. Two stages, the second only
/// when the first cannot decide:
///  1. the bound max|E| ≤ 2·max_j |w'_j δ_j|, |w'_j| taken as the larger of the two one-sided
///     slopes at j: one pass, no transform. This is the earlier rule, 2·δ_max·max|w'|, with
///     the maximum of the products in place of the product of the maxima (never larger), so
///     every profile that rule accepted is accepted unchanged.
///  2. E itself: g_j = w'_j δ_j with w' by the fourth-order central difference, F(g) by the
///     same FFT filter (one more transform pair). Displacements that vary from sample to
///     sample (the tangential part of probing noise, ~σ/R rad) average out in F(g);
///     displacements that vary slowly (an eccentric scan) cancel between the two terms.
///     (Simulated 3600-point ring scans with 0.7 µm noise: the earlier rule sent 41 % of them
///     to the ~40× slower nonuniform path; see docs/performance.md for the split now.)
bool grid_error_is_negligible(Rays& v, Eigen::Index count, double max_sin,
                              ClosedFilterPlan& plan, double cutoff_upr) {
  if (max_sin == 0.0) return true;
  if (!std::isfinite(max_sin)) return false;
  const double step = 2 * kPi / static_cast<double>(count);
  // |δ_j| ≤ |sin δ_j|·asin(s_max)/s_max (asin(s)/s grows with s), and δ_j has the sign of sin δ_j.
  const double to_angle = std::asin(max_sin) / max_sin / step;  // per unit of w difference
  const double* w = v.filtered.data();
  const double* sd = v.sin_delta.data();
  // Stage 1: |D_j| = |w_{j+1} − w_j| (cyclic); point j's slope bound is max(|D_{j−1}|, |D_j|),
  // so max_j slope_j·|s_j| = max(max_j |D_j||s_j|, max_j |D_j||s_{j+1}|). One vectorised
  // pass for these and the extremes of w (maxima are exact: the same values as separate
  // reductions), no branch per point.
  const auto [worst, w_max, w_min] = grid_slope_bound(w, sd, count);
  const double range = w_max - w_min;
  const double tolerance = std::max(1e-3 * range, 1e-10);
  if (2.0 * worst * to_angle <= tolerance) return true;
  if (count < 5) return false;
  // Stage 2: g in v.scratch, F(g) in v.scratch2.
  double* g = v.scratch.data();
  const auto at = [&](Eigen::Index j) { return w[(j % count + count) % count]; };
  const auto g_at = [&](Eigen::Index j, double w_m2, double w_m1, double w_p1, double w_p2) {
    const double central = (8.0 * (w_p1 - w_m1) - (w_p2 - w_m2)) / 12.0;
    g[j] = central * sd[j] * to_angle;
  };
  for (Eigen::Index j : {Eigen::Index{0}, Eigen::Index{1}, count - 2, count - 1})  // wrapping
    g_at(j, at(j - 2), at(j - 1), at(j + 1), at(j + 2));
  for (Eigen::Index j = 2; j < count - 2; ++j) g_at(j, w[j - 2], w[j - 1], w[j + 1], w[j + 2]);
  plan.apply(g, v.scratch2.data(), cutoff_upr);
  const double e_max = (v.scratch.head(count) - v.scratch2.head(count)).abs().maxCoeff();
  return e_max <= tolerance;
}

/// True when the last ray points the same way as the first (a repeated closing point), within
/// a quarter of a step of 2π/count.
bool repeats_first_direction(const Rays& v, Eigen::Index count) {
  const double step = 2 * kPi / static_cast<double>(count);
  const Eigen::Index last = v.x.size() - 1;
  const double cross = v.x[last] * v.y[0] - v.y[last] * v.x[0];
  const double dot = v.x[last] * v.x[0] + v.y[last] * v.y[0];
  return dot > 0.0 &&
         std::fabs(cross) * (v.inv_r[last] * v.inv_r[0]) <= std::sin(0.25 * step);
}

/// The cut-off's checks (finite, > 0, ≤ n/2), and the LS circle's when given.
void check_filter_parameters(std::span<const Point2> points, double cutoff_upr,
                             const char* caller, const LeastSquaresCircle* least_squares) {
  check_cutoff(caller, cutoff_upr);
  const std::size_t n = points.size();
  if (cutoff_upr > 0.5 * static_cast<double>(n)) {
    std::ostringstream os;
    os << caller << ": the cut-off must not exceed n/2 = " << 0.5 * static_cast<double>(n)
       << " UPR for " << n << " points (no harmonic above n/2 exists); got " << cutoff_upr;
    throw InvalidInput(os.str());
  }
  if (!least_squares) return;
  const Point2 c = least_squares->center;
  const double radius = least_squares->radius;
  if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(radius) && radius > 0.0)) {
    std::ostringstream os;
    os << caller << ": the least-squares circle must have a finite centre and a finite "
       << "radius > 0; got centre (x = " << c.x << ", y = " << c.y << "), radius " << radius;
    throw InvalidInput(os.str());
  }
}

/// points_validated: the caller vouches that the points passed least_squares_circle's check
/// (gaussian_filter.h); then only the count is checked here, not every point (the filter's
/// off-series branch checks them in full).
void check_filter_input(std::span<const Point2> points, double cutoff_upr, const char* caller,
                        const LeastSquaresCircle* least_squares = nullptr,
                        bool points_validated = false) {
  if (!points_validated || points.size() < 8) validate_profile(points, 8, caller);
  check_filter_parameters(points, cutoff_upr, caller, least_squares);
}

/// The first pass of filter_about (see there), as a function of its own with restrict
/// pointers so that GCC vectorises it. xy: the points as x, y pairs; tc, ts: the grid table
/// (ts times the sense σ here); (x0, y0): the unit ray 0. Stores the rays, the deviations, the
/// reciprocal lengths and sin δ_j; distances by the series of degree D of internal/
/// near_circle.h. Of s_j and |r_j| cos δ_j only the verdicts are needed (every |s_j| within
/// the series' range; every cos term > 0), kept as flags (integer OR: vectorised like the rest,
/// and exact — the same verdicts as max/min reductions). max |sin δ_j| likewise, as the
/// largest bit pattern of |sin δ_j| (non-negative doubles order as their 64-bit patterns: an
/// integer maximum, vectorised, exactly the value a floating maximum gives).
struct SetupPass {
  internal::NearCircle k;  ///< about the filter radius R
  double cx, cy;
  double dev0;   ///< R₀ − R (exact: R₀ is R to 26 bits)
  double s_max;  ///< the series' range
  double x0, y0, sense;
};
struct SetupVerdict {
  bool off_series;        ///< some |s_j| > s_max (or not a number)
  bool non_positive_cos;  ///< some |r_j| cos δ_j ≤ 0 (or not a number)
  double max_sin;         ///< max |sin δ_j|
};
template <int D>
[[gnu::always_inline]] inline SetupVerdict setup_pass_body(
    const SetupPass& p, Eigen::Index count, const double* __restrict xy,
    const double* __restrict tc, const double* __restrict ts, double* __restrict rx,
    double* __restrict ry, double* __restrict dev, double* __restrict inv,
    double* __restrict sin_delta) {
  const internal::NearCircle k = p.k;
  const double cx = p.cx, cy = p.cy, dev0 = p.dev0, s_max = p.s_max;
  const double x0 = p.x0, y0 = p.y0, sense = p.sense;
  std::int64_t off_series = 0, non_positive_cos = 0, max_sin_bits = 0;
  for (Eigen::Index i = 0; i < count; ++i) {
    const double dx = xy[2 * i] - cx, dy = xy[2 * i + 1] - cy;
    const double s = internal::near_circle_s(dx * dx + dy * dy, k);
    const double inv_i = internal::near_circle_inverse<D>(s, k);
    const double c = tc[i], sn = sense * ts[i];
    const double xr = dx * c + dy * sn, yr = dy * c - dx * sn;
    rx[i] = dx;
    ry[i] = dy;
    dev[i] = dev0 + internal::near_circle_offset<D>(s, k);  // (R₀ − R) + (r − R₀)
    inv[i] = inv_i;
    const double sd = (x0 * yr - y0 * xr) * inv_i;
    sin_delta[i] = sd;
    const auto bits = std::bit_cast<std::int64_t>(std::fabs(sd));
    max_sin_bits = max_sin_bits > bits ? max_sin_bits : bits;
    off_series |= static_cast<std::int64_t>(!(std::fabs(s) <= s_max));
    non_positive_cos |= static_cast<std::int64_t>(!(x0 * xr + y0 * yr > 0.0));
  }
  return {off_series != 0, non_positive_cos != 0, std::bit_cast<double>(max_sin_bits)};
}

/// The arrays of setup_pass_body (in the order of its parameters).
struct SetupArrays {
  const double *xy, *tc, *ts;
  double *rx, *ry, *dev, *inv, *sin_delta;
};

// The pass compiled for the baseline ISA and for AVX2, chosen per call (internal/isa.h): the
// same element-wise operations, so the same bits.
template <int D>
SetupVerdict setup_pass_baseline(const SetupPass& p, Eigen::Index count, const SetupArrays& a) {
  return setup_pass_body<D>(p, count, a.xy, a.tc, a.ts, a.rx, a.ry, a.dev, a.inv, a.sin_delta);
}
#if VCMM_GEOMETRY_X86
template <int D>
__attribute__((target("avx2"))) SetupVerdict setup_pass_avx2(const SetupPass& p,
                                                             Eigen::Index count,
                                                             const SetupArrays& a) {
  return setup_pass_body<D>(p, count, a.xy, a.tc, a.ts, a.rx, a.ry, a.dev, a.inv, a.sin_delta);
}
template <int D>
__attribute__((target("avx512f,avx512dq,avx512vl,prefer-vector-width=512"))) SetupVerdict
setup_pass_avx512(const SetupPass& p, Eigen::Index count, const SetupArrays& a) {
  return setup_pass_body<D>(p, count, a.xy, a.tc, a.ts, a.rx, a.ry, a.dev, a.inv, a.sin_delta);
}
#endif
template <int D>
SetupVerdict setup_pass_variant(const SetupPass& p, Eigen::Index count, const SetupArrays& a) {
#if VCMM_GEOMETRY_X86
  if (internal::use_avx512()) return setup_pass_avx512<D>(p, count, a);
  if (internal::use_avx2()) return setup_pass_avx2<D>(p, count, a);
#endif
  return setup_pass_baseline<D>(p, count, a);
}
/// The pass with the series of degree 3, 4 or 6.
SetupVerdict setup_pass(int degree, const SetupPass& p, Eigen::Index count,
                        const SetupArrays& a) {
  switch (degree) {
    case 3: return setup_pass_variant<3>(p, count, a);
    case 4: return setup_pass_variant<4>(p, count, a);
    default: return setup_pass_variant<6>(p, count, a);
  }
}

/// The reconstruction (file comment) in one vectorised pass: out (x, y pairs) = xy + (rx, ry)
/// (w − d) inv, element by element.
struct ReconstructionArrays {
  const double *xy, *rx, *ry, *w, *d, *inv;
  double* out;
};
[[gnu::always_inline]] inline void reconstruction_body(
    std::size_t n, const double* __restrict xy, const double* __restrict rx,
    const double* __restrict ry, const double* __restrict w, const double* __restrict d,
    const double* __restrict inv, double* __restrict out) {
  for (std::size_t i = 0; i < n; ++i) {
    const double t = (w[i] - d[i]) * inv[i];
    out[2 * i] = xy[2 * i] + rx[i] * t;
    out[2 * i + 1] = xy[2 * i + 1] + ry[i] * t;
  }
}
void reconstruct_baseline(const ReconstructionArrays& a, std::size_t n) {
  reconstruction_body(n, a.xy, a.rx, a.ry, a.w, a.d, a.inv, a.out);
}
#if VCMM_GEOMETRY_X86
__attribute__((target("avx2"))) void reconstruct_avx2(const ReconstructionArrays& a,
                                                      std::size_t n) {
  reconstruction_body(n, a.xy, a.rx, a.ry, a.w, a.d, a.inv, a.out);
}
__attribute__((target("avx512f,avx512dq,avx512vl,prefer-vector-width=512"))) void
reconstruct_avx512(const ReconstructionArrays& a, std::size_t n) {
  reconstruction_body(n, a.xy, a.rx, a.ry, a.w, a.d, a.inv, a.out);
}
#endif
void reconstruct(const ReconstructionArrays& a, std::size_t n) {
#if VCMM_GEOMETRY_X86
  if (internal::use_avx512()) return reconstruct_avx512(a, n);
  if (internal::use_avx2()) return reconstruct_avx2(a, n);
#endif
  reconstruct_baseline(a, n);
}

/// The filter of validated points about the circle (center, radius) (file comment), into
/// `out` (storage reused), and the LS circle of the output into *filtered_ls when asked.
/// deviation_bound: the largest |r_i − R| expected (RONt of the LS circle), which picks the
/// degree of the distance series (a wrong value costs time, never accuracy). With
/// `not_closed` given, a profile that is not closed sets it (and leaves `out` unusable)
/// instead of throwing. form_points false (with filtered_ls): `out.points` is left empty
/// when the FFT path was taken and the one step on the rays gave *filtered_ls (the caller
/// wants only that circle).
void filter_about(std::span<const Point2> points, double cutoff_upr, Point2 center,
                  double radius, double deviation_bound, FilterPathChoice choice,
                  const char* caller, FilteredProfile& out, LeastSquaresCircle* filtered_ls,
                  bool* not_closed = nullptr, bool form_points = true) {
  const std::size_t n = points.size();
  out.filter_center = center;
  out.mean_radius = radius;

  const auto count = static_cast<Eigen::Index>(n);
  thread_local Rays v;
  v.resize(count);
  // Rays p_i − c, and the radial deviations d_i = r_i − R and 1/r_i. Near the circle (|s_i| ≤
  // 2⁻⁹ for every point, s = (r² − R₀²)/R₀², R₀ = R to 26 bits: deviations up to ~1e-3 R, i.e.
  // any roundness profile) by the series of internal/near_circle.h: no square root or division
  // per point (the two cost ~6 µs at n = 3600), all in one vectorised pass, the range of s
  // checked after it. 1/r_i is within ½ ulp + 2⁻⁵⁹ relative of 1/√(r_i²), d_i = (R₀ − R) +
  // (r_i − R₀) rounds once at the size of the deviation. The degree is the smallest whose range
  // covers the deviations the caller expects (deviation_bound: RONt of the LS circle bounds
  // every |r_i − R|); when some point falls outside it the pass is redone with degree 6, and
  // beyond that range the direct formulas are used.
  // The same pass also measures the grid displacements for count = n (as
  // max_grid_displacement_sine would, from the same values): sin δ_j and |r_j| cos δ_j.
  const double cx = center.x, cy = center.y;
  SetupVerdict verdict{true, true, 0.0};
  const internal::NearCircle k = internal::near_circle_about(radius);
  for (int degree = internal::near_circle_degree_for(radius, deviation_bound); degree != 0;
       degree = degree < 6 ? 6 : 0) {
    // Unit ray 0 and the sense of rays 0 → 1, from the values the loop computes.
    const double ax = points[0].x - cx, ay = points[0].y - cy;
    const double bx = points[1].x - cx, by = points[1].y - cy;
    const double s0 = internal::near_circle_s(ax * ax + ay * ay, k);
    const double inv0 = degree == 3   ? internal::near_circle_inverse<3>(s0, k)
                        : degree == 4 ? internal::near_circle_inverse<4>(s0, k)
                                      : internal::near_circle_inverse<6>(s0, k);
    const double x0 = ax * inv0, y0 = ay * inv0;
    const double sense = ax * by - ay * bx >= 0.0 ? 1.0 : -1.0;
    const GridTable& table = grid_table(count);
    static_assert(sizeof(Point2) == 2 * sizeof(double), "Point2: two packed doubles");
    const SetupPass p{k,  cx, cy, k.r0 - radius, internal::near_circle_s_max(degree),
                      x0, y0, sense};
    verdict = setup_pass(degree, p, count,
                         {reinterpret_cast<const double*>(points.data()), table.cos.data(),
                          table.sin.data(), v.x.data(), v.y.data(), v.deviation.data(),
                          v.inv_r.data(), v.sin_delta.data()});
    if (!verdict.off_series) break;
  }
  const bool series = !verdict.off_series;
  if (!series) {
    // Points off the series' range (rare on roundness data) or not finite: the full check of
    // the points first (a caller may have skipped it, gaussian_filtered_least_squares_circle),
    // which names a non-finite point; then the direct formulas (the rays too: no series pass
    // may have run).
    validate_profile(points, 8, caller);
    for (Eigen::Index i = 0; i < count; ++i) {
      v.x[i] = points[static_cast<std::size_t>(i)].x - cx;
      v.y[i] = points[static_cast<std::size_t>(i)].y - cy;
    }
    v.r = (v.x.square() + v.y.square()).sqrt();
    if (!(v.r.minCoeff() > 0.0)) {
      Eigen::Index at_center = 0;
      v.r.minCoeff(&at_center);
      std::ostringstream os;
      os << caller << ": point " << at_center
         << " coincides with the least-squares centre; it has no direction to filter along";
      throw InvalidInput(os.str());
    }
    v.inv_r = v.r.inverse();
    v.deviation = v.r - radius;  // radial deviations d_i, finite by construction
  }

  bool done = false;
  if (choice == FilterPathChoice::nonuniform) {
    // the caller asked for the convolution with the true angles
  } else if (const double s = series ? grid_verdict(count, verdict.max_sin,
                                                    !verdict.non_positive_cos)
                                     : max_grid_displacement_sine(v, count);
             std::isfinite(s)) {
    ClosedFilterPlan& plan = plan_for(n);
    plan.apply(v.deviation.data(), v.filtered.data(), cutoff_upr);
    done = grid_error_is_negligible(v, count, s, plan, cutoff_upr);
  } else if (n >= 9 && repeats_first_direction(v, count - 1)) {
    // A closed scan repeating its first point: average the two deviations at that angle,
    // filter the n − 1 distinct angles, give the repeat the value of the first.
    if (const double s2 = max_grid_displacement_sine(v, count - 1); std::isfinite(s2)) {
      ClosedFilterPlan& plan = plan_for(n - 1);
      const double d0 = v.deviation[0];
      v.deviation[0] = 0.5 * (d0 + v.deviation[count - 1]);
      plan.apply(v.deviation.data(), v.filtered.data(), cutoff_upr);
      v.deviation[0] = d0;
      v.filtered[count - 1] = v.filtered[0];
      done = grid_error_is_negligible(v, count - 1, s2, plan, cutoff_upr);
    }
  }
  if (done) {
    out.path = FilterPath::fft;
  } else {
    out.path = FilterPath::nonuniform;
    std::vector<double> angle(n), dev(v.deviation.data(), v.deviation.data() + n);
    for (Eigen::Index i = 0; i < count; ++i)
      angle[static_cast<std::size_t>(i)] = std::atan2(v.y[i], v.x[i]);
    const std::vector<double> f = filter_nonuniform(angle, dev, cutoff_upr, not_closed);
    if (not_closed && *not_closed) return;
    v.filtered = Eigen::Map<const Eigen::ArrayXd>(f.data(), count);
  }

  // Output point i is c + (R + w_i) u_i on input ray i: its LS circle in one step from c
  // (least_squares.cpp, "Points on rays"); the full fit of the points where that step is not
  // exact.
  std::optional<LeastSquaresCircle> ls;
  if (filtered_ls) {
    ls = internal::least_squares_circle_on_rays(center, radius, v.filtered.data(), v.x.data(),
                                                v.y.data(), v.inv_r.data(), n);
    if (ls && !form_points && out.path == FilterPath::fft) {
      *filtered_ls = std::move(*ls);
      out.points.clear();
      return;
    }
  }
  // q_i = p_i + (p_i − c) (w_i − d_i) / r_i. A reused profile of n points is overwritten (no
  // value-initialisation).
  out.points.resize(n);
  reconstruct({reinterpret_cast<const double*>(points.data()), v.x.data(), v.y.data(),
               v.filtered.data(), v.deviation.data(), v.inv_r.data(),
               reinterpret_cast<double*>(out.points.data())},
              n);
  if (filtered_ls)
    *filtered_ls = ls ? std::move(*ls) : internal::fit_least_squares_circle(out.points);
}

/// filter_about, independent of the input order: when the points are not on an equiangular
/// grid in the order given (the FFT path fails), the same points sorted by their direction
/// about the centre are tried (ties: by x, then y, then input index), and the FFT result is
/// used when that order is equiangular — a shuffled scan gives the scan's result (to
/// rounding), not the nonuniform path's. Costs nothing on profiles given in angular order.
void filter_any_order(std::span<const Point2> points, double cutoff_upr,
                      const LeastSquaresCircle& ls, FilterPathChoice choice, const char* caller,
                      FilteredProfile& out, LeastSquaresCircle* filtered_ls,
                      bool* not_closed = nullptr, bool form_points = true) {
  const Point2 center = ls.center;
  const double radius = ls.radius, bound = ls.ron.ront;  // |r_i − R| ≤ RONt
  filter_about(points, cutoff_upr, center, radius, bound, choice, caller, out, filtered_ls,
               not_closed, form_points);
  if (not_closed && *not_closed) return;
  if (out.path == FilterPath::fft || choice == FilterPathChoice::nonuniform) return;
  const std::size_t n = points.size();
  std::vector<double> angle(n);
  for (std::size_t i = 0; i < n; ++i)
    angle[i] = std::atan2(points[i].y - center.y, points[i].x - center.x);
  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (angle[a] != angle[b]) return angle[a] < angle[b];
    if (points[a].x != points[b].x) return points[a].x < points[b].x;
    if (points[a].y != points[b].y) return points[a].y < points[b].y;
    return a < b;
  });
  bool identity = true;
  for (std::size_t j = 0; j < n && identity; ++j) identity = order[j] == j;
  if (identity) return;  // already in angular order: the spacing itself is uneven
  std::vector<Point2> sorted(n);
  for (std::size_t j = 0; j < n; ++j) sorted[j] = points[order[j]];
  FilteredProfile s;
  filter_about(sorted, cutoff_upr, center, radius, bound, choice, caller, s, nullptr);
  if (s.path != FilterPath::fft) return;
  for (std::size_t j = 0; j < n; ++j) out.points[order[j]] = s.points[j];
  out.path = FilterPath::fft;
  // Rare (a shuffled scan): the LS circle of the output in input order, by the full fit.
  if (filtered_ls) *filtered_ls = internal::fit_least_squares_circle(out.points);
}

}  // namespace

std::vector<double> gaussian_filter_closed(std::span<const double> deviations,
                                           double cutoff_upr) {
  constexpr const char* kCaller = "gaussian_filter_closed";
  if (deviations.size() < 2) {
    std::ostringstream os;
    os << kCaller << ": needs at least 2 deviations; got " << deviations.size();
    throw InvalidInput(os.str());
  }
  for (std::size_t i = 0; i < deviations.size(); ++i) {
    if (!std::isfinite(deviations[i])) {
      std::ostringstream os;
      os << kCaller << ": deviation " << i << " is not finite (" << deviations[i] << ")";
      throw InvalidInput(os.str());
    }
  }
  check_cutoff(kCaller, cutoff_upr);
  std::vector<double> out(deviations.size());
  plan_for(deviations.size()).apply(deviations.data(), out.data(), cutoff_upr);
  return out;
}

FilteredProfile gaussian_filtered_profile(std::span<const Point2> points, double cutoff_upr,
                                          FilterPathChoice choice) {
  constexpr const char* kCaller = "gaussian_filtered_profile";
  check_filter_input(points, cutoff_upr, kCaller);
  const LeastSquaresCircle ls = internal::fit_least_squares_circle(points);
  FilteredProfile out;
  filter_any_order(points, cutoff_upr, ls, choice, kCaller, out, nullptr);
  return out;
}

FilteredProfile gaussian_filtered_profile(std::span<const Point2> points, double cutoff_upr,
                                          const LeastSquaresCircle& least_squares,
                                          FilterPathChoice choice) {
  FilteredProfile out;
  gaussian_filtered_profile(points, cutoff_upr, least_squares, out, nullptr, choice);
  return out;
}

LeastSquaresCircle gaussian_filtered_least_squares_circle(std::span<const Point2> points,
                                                          double cutoff_upr,
                                                          const LeastSquaresCircle& least_squares,
                                                          bool points_validated) {
  constexpr const char* kCaller = "gaussian_filtered_profile";
  check_filter_input(points, cutoff_upr, kCaller, &least_squares, points_validated);
  thread_local FilteredProfile out;  // the points, formed only for the full fit
  LeastSquaresCircle filtered;
  filter_any_order(points, cutoff_upr, least_squares, FilterPathChoice::automatic, kCaller, out,
                   &filtered, nullptr, /*form_points=*/false);
  return filtered;
}

void gaussian_filtered_profile(std::span<const Point2> points, double cutoff_upr,
                               const LeastSquaresCircle& least_squares, FilteredProfile& out,
                               LeastSquaresCircle* filtered_least_squares,
                               FilterPathChoice choice, bool points_validated) {
  constexpr const char* kCaller = "gaussian_filtered_profile";
  check_filter_input(points, cutoff_upr, kCaller, &least_squares, points_validated);
  filter_any_order(points, cutoff_upr, least_squares, choice, kCaller, out,
                   filtered_least_squares);
}

bool internal::filter_closed_profile_if_closed(std::span<const Point2> points,
                                               double cutoff_upr,
                                               const LeastSquaresCircle& least_squares,
                                               FilteredProfile& out,
                                               LeastSquaresCircle* filtered_least_squares) {
  constexpr const char* kCaller = "gaussian_filtered_profile";
  check_filter_parameters(points, cutoff_upr, kCaller, &least_squares);
  bool not_closed = false;
  filter_any_order(points, cutoff_upr, least_squares, FilterPathChoice::automatic, kCaller, out,
                   filtered_least_squares, &not_closed);
  return !not_closed;
}

}  // namespace vcmm::geometry
