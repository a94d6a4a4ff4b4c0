// internal/extremal_circle.cpp — exact circles and the rigorous floating filter shared by
// the MC and MI fitters.
//
// The floating filter (ExactCircle::inside_below / outside_above)
// ----------------------------------------------------------------
// All lengths are taken in scaled units (× s, s = 2^k chosen so that R*·s ∈ [0.7, 1.5)):
// scaling by a power of two is exact, so the analysis below is that of unit-size circles
// and holds for any input magnitude (no overflow or underflow of the squares).
// Let e = |p − c̃|·s and D̃ = fl(X² + Y²) with X = fl(px − c̃x)·s, Y likewise (a difference
// whose exact value is subnormal is exact). Each of the five roundings is a factor
// (1 + ε), |ε| ≤ u, so D̃ = e²·θ with θ ∈ [(1 − u)⁴, (1 + u)⁴]:
//   e² ≤ D̃(1 + 4.1u),   e² ≥ D̃(1 − 4u).
// With d = |p − c*|·s, |d − e| ≤ δ (δ in scaled units). The scaled radius r̃ (below)
// gives R*s ∈ [r̃(1 − 2.3u), r̃(1 + 2.3u)]; we use the rounded bounds R_lo = fl(r̃(1 − 4u))
// ≤ R*s and R_hi = fl(r̃(1 + 4u)) ≥ R*s.
//  * strictly inside: d ≤ e + δ < R_lo  ⇐  D̃(1 + 4.1u) < (R_lo − δ)².
//    inside_below = fl(fl(R_lo − δ)²)·(1 − 16u) ≤ (R_lo − δ)²(1 − 11.9u) after its own
//    three roundings, so D̃ < inside_below implies the condition.
//  * strictly outside: d ≥ e − δ > R_hi  ⇐  D̃(1 − 4u) > (R_hi + δ)².
//    outside_above = fl(fl(R_hi + δ)²)·(1 + 16u) ≥ (R_hi + δ)²(1 + 11.9u).
// The 16u factors are the error terms above with a margin of ~4u for the thresholds' own
// roundings: generous, and still a band of only ~1e-15 relative around the circle.
// Subnormal or overflowing D̃ values are far below or far above the thresholds (≈ 1), where
// the decision stays right (an overflowed D̃ = +inf does mean e > 1e154 > R_hi + δ). The
// filter is off (every test exact) when s or δ·s leaves the double range or δ·s > R̃·s/4.
//
// δ: ratio_to_double is within 1.25 ulp (≤ 2.5u|x|, or a subnormal ulp) of the exact
// value, so |c̃ − c*| ≤ 2.6u(|c̃x| + |c̃y|) + 2⁻¹⁰⁷³; we use δ = 4u(|c̃x| + |c̃y|) + 2⁻¹⁰⁷²
// (× s, + 1e-300). R*²s² is within 1.25 ulp (2.5u relative) of its double, whose sqrt r̃
// is rounded once: R*·s ∈ [r̃(1 − 2.3u), r̃(1 + 2.3u)].
//
// dot_sign: with ã = fl(a − o), b̃ = fl(b − o) (componentwise, relative error ≤ u each) the
// value ṽ = fl(fl(ãx·b̃x) + fl(ãy·b̃y)) differs from the exact (a − o)·(b − o) by at most
// ((1 + u)⁴ − 1)·(|ãx·b̃x| + |ãy·b̃y|)(1 + u) ≤ 4.01u·S; we demand |ṽ| > 8u·S + 1e-300
// (the absolute term covers underflow of the products; S is rounded upwards by the
// factor 2 margin). Non-finite values (overflow) go to the exact predicate.
#include "internal/extremal_circle.h"
#include "internal/vec.h"
#include "vcmm/internal/simd_clones.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <stdexcept>

namespace vcmm::geometry::internal {

namespace {

// ---- exact integer representation ----------------------------------------------------
// A finite double x ≠ 0 is m·2^k with m an integer, |m| < 2^53 (frexp, then scale the
// fraction by 2^53: exact, also for subnormals).
int exponent_of(double x) {
  int e = 0;
  (void)std::frexp(x, &e);
  return e - 53;
}

constexpr int kNoExponent = std::numeric_limits<int>::max();

int min_exponent(std::initializer_list<double> xs) {
  int e = kNoExponent;
  for (double x : xs)
    if (x != 0.0) e = std::min(e, exponent_of(x));
  return e == kNoExponent ? 0 : e;
}

/// x / 2^e as an exact integer; precondition: x is a multiple of 2^e.
mpz_class scaled(double x, int e) {
  if (x == 0.0) return 0;
  int k = 0;
  const double f = std::frexp(x, &k);
  mpz_class z(static_cast<long>(std::ldexp(f, 53)));
  const int shift = k - 53 - e;
  if (shift > 0) z <<= static_cast<unsigned long>(shift);
  return z;
}

mpz_class shifted(const mpz_class& z, int s) {
  return s > 0 ? mpz_class(z << static_cast<unsigned long>(s)) : z;
}

/// out = x·2^−e for a multiple x of 2^e (as `scaled`, without temporaries).
void set_scaled(mpz_ptr out, double x, int e) {
  if (x == 0.0) {
    mpz_set_ui(out, 0);
    return;
  }
  int k = 0;
  const double f = std::frexp(x, &k);
  mpz_set_d(out, std::ldexp(f, 53));
  mpz_mul_2exp(out, out, static_cast<mp_bitcnt_t>(k - 53 - e));
}

/// GMP integers reused across calls, per thread (issue 11): the exact circles below are
/// built a few times per fit (MI ~3, MC ~2 per evaluation), and their temporaries were
/// ~40 heap allocations a circle. Every use writes a variable before reading it, so no
/// value leaks from one call to the next; the arithmetic (and so every result) is the same.
struct CircleScratch {
  mpz_t ax, ay, ux, uy, vx, vy, t, u2, v2;  // the circle's construction
  mpz_t q, a, d2;                           // ratio_frexp, ratio_to_double, finish
  mpz_t gx, gy, gn;                         // exact_power_gap, compare_radius
  CircleScratch() { mpz_inits(ax, ay, ux, uy, vx, vy, t, u2, v2, q, a, d2, gx, gy, gn, nullptr); }
  ~CircleScratch() { mpz_clears(ax, ay, ux, uy, vx, vy, t, u2, v2, q, a, d2, gx, gy, gn, nullptr); }
  CircleScratch(const CircleScratch&) = delete;
  CircleScratch& operator=(const CircleScratch&) = delete;
};

CircleScratch& circle_scratch() {
  thread_local CircleScratch s;
  return s;
}

/// n/d = m·2^x with m ∈ [0.5, 1) (n, d > 0): the integer quotient is taken with ≥ 54
/// significant bits (truncation error < 2⁻⁵⁴ relative) and then truncated to 53 bits, so
/// m·2^x is within 1.25 ulp of n/d. Returns m; x in `exp`.
double ratio_frexp(mpz_srcptr n, mpz_srcptr d, long& exp) {
  long s = 55 + static_cast<long>(mpz_sizeinbase(d, 2)) -
           static_cast<long>(mpz_sizeinbase(n, 2));
  if (s < 0) s = 0;
  mpz_ptr q = circle_scratch().q;
  mpz_mul_2exp(q, n, static_cast<mp_bitcnt_t>(s));
  mpz_tdiv_q(q, q, d);  // truncating division
  long ex = 0;
  const double mant = mpz_get_d_2exp(&ex, q);
  exp = ex - s;
  return mant;
}

/// n/d · 2^e to double (d > 0), within 1.25 ulp (plus the rounding of ldexp into the
/// subnormal range; ±inf beyond the double range).
double ratio_to_double(mpz_srcptr n, mpz_srcptr d, long e) {
  if (mpz_sgn(n) == 0) return 0.0;
  mpz_ptr a = circle_scratch().a;
  mpz_abs(a, n);
  long x = 0;
  const double mant = ratio_frexp(a, d, x);
  const double v = std::ldexp(mant, static_cast<int>(std::clamp(x + e, -4000L, 4000L)));
  return mpz_sgn(n) < 0 ? -v : v;
}

void finish(ExactCircle& c) {
  const long e = c.exponent;
  c.center_d = {ratio_to_double(c.nx.get_mpz_t(), c.den.get_mpz_t(), e),
                ratio_to_double(c.ny.get_mpz_t(), c.den.get_mpz_t(), e)};
  c.scale = 1.0;
  c.scale_exponent = 0;
  c.radius_scaled = 0.0;
  c.radius = 0.0;
  c.filter_usable = false;
  if (sgn(c.r2num) == 0) return;
  // R*² = m·2^T, m ∈ [0.5, 1); scale s = 2^k with k = −⌊T/2⌋ puts R*²·s² in [0.5, 2).
  long x = 0;
  mpz_ptr den2 = circle_scratch().d2;
  mpz_mul(den2, c.den.get_mpz_t(), c.den.get_mpz_t());
  const double m = ratio_frexp(c.r2num.get_mpz_t(), den2, x);
  const long t = x + 2 * e;
  const long k = -((t >= 0 ? t : t - 1) / 2);  // −⌊t/2⌋
  c.scale_exponent = static_cast<int>(std::clamp(k, -4000L, 4000L));
  c.scale = std::ldexp(1.0, static_cast<int>(std::clamp(k, -1022L, 1023L)));
  const double r2s = std::ldexp(m, static_cast<int>(t + 2 * k));  // exact: in [0.5, 2)
  c.radius_scaled = std::sqrt(r2s);
  c.radius = std::ldexp(c.radius_scaled, static_cast<int>(-c.scale_exponent));
  const double cx = std::fabs(c.center_d.x), cy = std::fabs(c.center_d.y);
  const double u = kUnitRoundoff;
  // δ in scaled units: 1.25 ulp per coordinate (≤ 2.5u|c|), or a subnormal ulp each.
  c.center_error_scaled =
      (4.0 * u * (cx + cy) + 0x1p-1072) * c.scale + 1e-300;
  c.filter_usable = c.support_size >= 2 && k > -1022 && k < 1023 &&
                    std::isfinite(c.center_error_scaled) &&
                    c.center_error_scaled < 0.25 * c.radius_scaled;
  if (!c.filter_usable) return;
  const double r_lo = c.radius_scaled * (1.0 - 4.0 * u);
  const double r_hi = c.radius_scaled * (1.0 + 4.0 * u);
  const double delta = c.center_error_scaled;
  const double m_in = r_lo - delta;
  c.inside_below = (m_in * m_in) * (1.0 - 16.0 * u);
  const double m_out = r_hi + delta;
  c.outside_above = (m_out * m_out) * (1.0 + 16.0 * u);
}

}  // namespace

namespace {

/// The power of two sample_scale gives for the largest offset m.
double scale_of_extent(double m) {
  if (!(m > 0.0) || !std::isfinite(m)) return 1.0;
  int e = 0;
  (void)std::frexp(m, &e);  // m = f·2^e, f ∈ [0.5, 1)
  return std::ldexp(1.0, std::clamp(-e, -1022, 1023));
}

#pragma GCC diagnostic ignored "-Wpsabi"  // 64-byte vectors inside the kernels only
using V8 = VecOf<8>::type;  // internal/vec.h
using M8 = VecOf<8>::mask;

/// max(0, |x_k − cx|, |y_k − cy|) over k < m, NaN never taken (as sample_scale's
/// std::max({m, a, b}) in order: the largest of the others, exact in any order), lane-wise.
VCMM_SIMD_CLONES double max_abs_offset(const double* x, const double* y, std::size_t m,
                                       double cx, double cy) {
  V8 acc = V8{};
  std::size_t k = 0;
  for (; k + 8 <= m; k += 8) {
    V8 vx, vy;
    std::memcpy(&vx, x + k, sizeof vx);
    std::memcpy(&vy, y + k, sizeof vy);
    const V8 dx = vx - cx, dy = vy - cy;
    const V8 ax = dx < 0.0 ? -dx : dx, ay = dy < 0.0 ? -dy : dy;  // as std::fabs (no −0)
    acc = acc < ax ? ax : acc;
    acc = acc < ay ? ay : acc;
  }
  double r = 0.0;
  for (int l = 0; l < 8; ++l) r = r < acc[l] ? acc[l] : r;
  for (; k < m; ++k) r = std::max({r, std::fabs(x[k] - cx), std::fabs(y[k] - cy)});
  return r;
}

/// kasa_center's terms, lane-wise: u = (x − mx)·s, v = (y − my)·s and the seven products its
/// moment sums add (uu, uv, vv, uu·u, vv·v, u·vv, v·uu: the scalar expressions), into
/// out[j·m + k].
/// kasa_terms' expressions for one value or one vector of u and v (always inlined: no
/// vector crosses a call boundary, internal/vec.h).
template <class T>
[[gnu::always_inline]] inline void store_kasa_terms(T u, T v, double* out, std::size_t m) {
  const T uu = u * u, vv = v * v;
  const T t[7] = {uu, u * v, vv, uu * u, vv * v, u * vv, v * uu};
  for (std::size_t j = 0; j < 7; ++j) std::memcpy(out + j * m, &t[j], sizeof t[j]);
}

VCMM_SIMD_CLONES void kasa_terms(const double* x, const double* y, std::size_t m, double mx,
                                 double my, double s, double* out) {
  std::size_t k = 0;
  for (; k + 8 <= m; k += 8) {
    V8 vx, vy;
    std::memcpy(&vx, x + k, sizeof vx);
    std::memcpy(&vy, y + k, sizeof vy);
    store_kasa_terms<V8>((vx - mx) * s, (vy - my) * s, out + k, m);
  }
  for (; k < m; ++k) store_kasa_terms<double>((x[k] - mx) * s, (y[k] - my) * s, out + k, m);
}

}  // namespace

double sample_scale(std::span<const Point2> points, Point2 c, std::size_t stride) {
  double m = 0.0;
  for (std::size_t i = 0; i < points.size(); i += stride)
    m = std::max({m, std::fabs(points[i].x - c.x), std::fabs(points[i].y - c.y)});
  return scale_of_extent(m);
}

WarmStart kasa_center(std::span<const Point2> points) {
  // A warm start needs no more than ~256 points: take every stride-th one (a measured
  // profile is ordered along the contour, so a stride keeps the angular coverage).
  const std::size_t stride = std::max<std::size_t>(1, points.size() / 256);
  // The sample gathered once into x and y (each strided point is a cache line of its own;
  // the passes below then read it contiguously), its mean summed on the way; then the
  // scale and the terms of the moments lane-wise, and the moments summed in sample order
  // (the sums' order fixes their bits).
  const std::size_t m = (points.size() + stride - 1) / stride;
  thread_local std::vector<double> buffer;
  buffer.resize(9 * m);
  double* x = buffer.data();
  double* y = x + m;
  double* terms = y + m;
  double count = 0.0, mx = 0.0, my = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    const Point2& p = points[k * stride];
    x[k] = p.x;
    y[k] = p.y;
    mx += p.x;
    my += p.y;
    count += 1.0;
  }
  mx /= count;
  my /= count;
  if (!std::isfinite(mx) || !std::isfinite(my)) {  // sums overflowed: use a point
    mx = points[0].x;
    my = points[0].y;
  }
  // Work on (p − mean)·s, s a power of two making the coordinates O(1) (sample_scale): no
  // overflow of the third moments whatever the input magnitude.
  const double sc = scale_of_extent(max_abs_offset(x, y, m, mx, my));
  kasa_terms(x, y, m, mx, my, sc, terms);
  double suu = 0, suv = 0, svv = 0, suuu = 0, svvv = 0, suvv = 0, svuu = 0;
  for (std::size_t k = 0; k < m; ++k) {
    suu += terms[k];
    suv += terms[m + k];
    svv += terms[2 * m + k];
    suuu += terms[3 * m + k];
    svvv += terms[4 * m + k];
    suvv += terms[5 * m + k];
    svuu += terms[6 * m + k];
  }
  // Bullock's centred Kåsa system: [suu suv; suv svv]·(a, b) = ½(suuu + suvv, svvv + svuu).
  const double det = suu * svv - suv * suv;
  // Relative singularity test: det ≥ 1e-12·suu·svv keeps the warm start finite; the value
  // is irrelevant to correctness.
  if (!(det > 1e-12 * suu * svv) || !std::isfinite(det)) return {{mx, my}, sc};
  const double rx = 0.5 * (suuu + suvv), ry = 0.5 * (svvv + svuu);
  const double a = (rx * svv - ry * suv) / det / sc;
  const double b = (ry * suu - rx * suv) / det / sc;
  const Point2 c{mx + a, my + b};
  if (!std::isfinite(c.x) || !std::isfinite(c.y)) return {{mx, my}, sc};
  return {c, sc};
}

namespace {

/// d2 = dx² + dy² of (x − cx)·s0, (y − cy)·s0 for m values, and of phi = pseudo_angle(dx, dy)
/// the occupancy bucket min(⌊phi·64⌋, 255) and the sector min(⌊phi·sector_scale⌋,
/// sector_last); lane by lane the scalar expressions (pseudo_angle's branches as selects, its
/// division and the truncations vectorised); compiled for AVX-512, AVX2 and the baseline.
VCMM_SIMD_CLONES void sample_angles(const double* x, const double* y, std::size_t m,
                                    Point2 c, double s0, double sector_scale,
                                    int sector_last, double* d2, std::int32_t* bucket,
                                    std::int32_t* sector) {
  using I8 = std::int32_t __attribute__((vector_size(32)));
  std::size_t k = 0;
  for (; k + 8 <= m; k += 8) {
    V8 vx, vy;
    std::memcpy(&vx, x + k, sizeof vx);
    std::memcpy(&vy, y + k, sizeof vy);
    const V8 dx = (vx - c.x) * s0, dy = (vy - c.y) * s0;
    const V8 d = dx * dx + dy * dy;
    const V8 ax = dx < 0.0 ? -dx : dx, ay = dy < 0.0 ? -dy : dy;
    const V8 sum = ax + ay;
    const V8 t = ay / sum;
    const V8 right = dy >= 0.0 ? t : 4.0 - t, left = dy >= 0.0 ? 2.0 - t : 2.0 + t;
    const V8 p = sum == 0.0 ? V8{} : (dx >= 0.0 ? right : left);
    std::memcpy(d2 + k, &d, sizeof d);
    // Truncations of values in [0, 256] and [0, sectors] (4 − tiny may round up to 4: clamp).
    I8 b = __builtin_convertvector(p * 64.0, I8);
    I8 q = __builtin_convertvector(p * sector_scale, I8);
    b = b > 255 ? I8{} + 255 : b;
    q = q > sector_last ? I8{} + sector_last : q;
    std::memcpy(bucket + k, &b, sizeof b);
    std::memcpy(sector + k, &q, sizeof q);
  }
  for (; k < m; ++k) {
    const double dx = (x[k] - c.x) * s0, dy = (y[k] - c.y) * s0;
    d2[k] = dx * dx + dy * dy;
    const double p = pseudo_angle(dx, dy);
    bucket[k] = std::min(static_cast<std::int32_t>(p * 64.0), 255);
    sector[k] = std::min(static_cast<std::int32_t>(p * sector_scale), sector_last);
  }
}

}  // namespace

namespace {

/// range_extreme's kernel for one direction and tie rule: per lane the extreme and its index
/// (strict comparisons keep a lane's first, non-strict its last; NaN never taken, as in the
/// walk), then across lanes, then the tail point by point.
template <bool kFarthest, bool kLast>
[[gnu::always_inline]] inline void range_extreme_body(const Point2* points, std::size_t lo,
                                                      std::size_t count, Point2 c,
                                                      double scale, std::size_t& index,
                                                      double& value) {
  constexpr double kWorst = (kFarthest ? -1.0 : 1.0) * std::numeric_limits<double>::infinity();
  const auto take = [](double d, double best) {
    if constexpr (kFarthest) return kLast ? d >= best : d > best;
    else return kLast ? d <= best : d < best;
  };
  const double* xy = reinterpret_cast<const double*>(points + lo);
  std::size_t k = 0, best = 0;
  double best_d = kWorst;
  if (count >= 8) {
    V8 bv = V8{} + kWorst;
    M8 bi = M8{}, at = {0, 1, 2, 3, 4, 5, 6, 7};
    for (; k + 8 <= count; k += 8) {
      V8 a, b;
      std::memcpy(&a, xy + 2 * k, sizeof a);
      std::memcpy(&b, xy + 2 * k + 8, sizeof b);
      const V8 dx = (__builtin_shufflevector(a, b, 0, 2, 4, 6, 8, 10, 12, 14) - c.x) * scale;
      const V8 dy = (__builtin_shufflevector(a, b, 1, 3, 5, 7, 9, 11, 13, 15) - c.y) * scale;
      const V8 d = dx * dx + dy * dy;
      M8 t;
      if constexpr (kFarthest) t = kLast ? d >= bv : d > bv;
      else t = kLast ? d <= bv : d < bv;
      bv = t ? d : bv;
      bi = t ? at : bi;
      at += 8;
    }
    for (int l = 0; l < 8; ++l)
      if (kFarthest ? bv[l] > best_d : bv[l] < best_d) best_d = bv[l];
    bool found = false;
    for (int l = 0; l < 8; ++l)
      if (bv[l] == best_d) {
        const auto idx = static_cast<std::size_t>(bi[l]);
        if (!found || (kLast ? idx > best : idx < best)) best = idx;
        found = true;
      }
  }
  for (; k < count; ++k) {
    const double d = scaled_distance2(points[lo + k], c, scale);
    if (take(d, best_d)) {
      best = k;
      best_d = d;
    }
  }
  index = lo + best;
  value = best_d;
}

VCMM_SIMD_CLONES void range_extreme_kernel(const Point2* points, std::size_t lo,
                                           std::size_t count, Point2 c, double scale,
                                           bool farthest, bool last_on_tie,
                                           std::size_t& index, double& value) {
  if (farthest) {
    if (last_on_tie) range_extreme_body<true, true>(points, lo, count, c, scale, index, value);
    else range_extreme_body<true, false>(points, lo, count, c, scale, index, value);
  } else {
    if (last_on_tie) range_extreme_body<false, true>(points, lo, count, c, scale, index, value);
    else range_extreme_body<false, false>(points, lo, count, c, scale, index, value);
  }
}

}  // namespace

void range_extreme(const Point2* points, std::size_t lo, std::size_t count, Point2 c,
                   double scale, bool farthest, bool last_on_tie, std::size_t& index,
                   double& value) {
  range_extreme_kernel(points, lo, count, c, scale, farthest, last_on_tie, index, value);
}

SectorSample sector_sample(std::span<const Point2> points) {
  const std::size_t n = points.size();
  SectorSample out;
  out.warm = kasa_center(points);
  const Point2 c0 = out.warm.center;
  out.stride = std::max<std::size_t>(1, n / 512);
  out.sectors = std::clamp<std::size_t>(n / out.stride / 8, 4, 64);
  out.nearest.assign(out.sectors, n);
  out.farthest.assign(out.sectors, n);
  // The sample's squared distances and pseudo-angles, on (p − c0)·s0 (s0 a power of two:
  // coordinates O(1) whatever the input magnitude; the sectors are invariant under the
  // scaling), then per sector the first sample point of the smallest and of the largest
  // distance (strict comparisons in sample order). A scan in angular order visits a
  // sector's samples in one run: the run's extremes are kept in registers by selects (the
  // comparisons of noisy data are unpredictable) and merged into the sector's at its end,
  // strictly, so the first extreme point still wins.
  const std::size_t m = (n + out.stride - 1) / out.stride;
  thread_local std::vector<double> buffer;
  thread_local std::vector<std::int32_t> buckets;
  buffer.resize(3 * m);
  buckets.resize(2 * m);
  double* x = buffer.data();
  double* y = x + m;
  double* d2 = y + m;
  std::int32_t* bucket_of = buckets.data();
  std::int32_t* sector_of = bucket_of + m;
  for (std::size_t k = 0; k < m; ++k) {
    x[k] = points[k * out.stride].x;
    y[k] = points[k * out.stride].y;
  }
  const double scale = static_cast<double>(out.sectors) / 4.0;
  sample_angles(x, y, m, c0, out.warm.scale, scale, static_cast<int>(out.sectors) - 1, d2,
                bucket_of, sector_of);
  std::array<double, 64> near, far;
  near.fill(std::numeric_limits<double>::infinity());
  far.fill(-1.0);
  std::array<std::uint64_t, 4> occupied{};
  unsigned word = 0;
  std::uint64_t bits = 0;
  std::size_t run = out.sectors;  // the current run's sector (none yet)
  double run_near = 0.0, run_far = 0.0;
  std::size_t run_near_at = 0, run_far_at = 0;
  const auto merge_run = [&] {
    if (run == out.sectors) return;
    if (run_near < near[run]) {
      near[run] = run_near;
      out.nearest[run] = run_near_at;
    }
    if (run_far > far[run]) {
      far[run] = run_far;
      out.farthest[run] = run_far_at;
    }
  };
  for (std::size_t k = 0; k < m; ++k) {
    const std::size_t i = k * out.stride;
    const auto bucket = static_cast<unsigned>(bucket_of[k]);
    if ((bucket >> 6) != word) {  // runs of one 64-bit word too: its bits kept in a register
      occupied[word] |= bits;
      word = bucket >> 6;
      bits = 0;
    }
    bits |= std::uint64_t{1} << (bucket & 63u);
    const auto s = static_cast<std::size_t>(sector_of[k]);
    const double d = d2[k];
    if (s != run) {
      merge_run();
      run = s;
      run_near = std::numeric_limits<double>::infinity();
      run_far = -1.0;
    }
    const bool nearer = d < run_near, farther = d > run_far;
    run_near = nearer ? d : run_near;
    run_near_at = nearer ? i : run_near_at;
    run_far = farther ? d : run_far;
    run_far_at = farther ? i : run_far_at;
  }
  merge_run();
  occupied[word] |= bits;
  out.occupied = occupied;
  return out;
}

ExactCircle exact_point_circle(Point2 a) {
  ExactCircle c;
  c.support_size = 1;
  c.support[0] = a;
  c.exponent = min_exponent({a.x, a.y});
  c.nx = scaled(a.x, c.exponent);
  c.ny = scaled(a.y, c.exponent);
  c.den = 1;
  c.r2num = 0;
  finish(c);
  return c;
}

ExactCircle exact_diametral_circle(Point2 a, Point2 b) {
  ExactCircle c;
  c.support_size = 2;
  c.support[0] = a;
  c.support[1] = b;
  const int e = min_exponent({a.x, a.y, b.x, b.y});
  CircleScratch& w = circle_scratch();
  set_scaled(w.ax, a.x, e);
  set_scaled(w.ay, a.y, e);
  set_scaled(w.ux, b.x, e);
  set_scaled(w.uy, b.y, e);
  // centre = (a + b)/2, centre − a = (b − a)/2.
  c.exponent = e;
  c.den = 2;
  mpz_add(c.nx.get_mpz_t(), w.ax, w.ux);
  mpz_add(c.ny.get_mpz_t(), w.ay, w.uy);
  mpz_ptr ox = c.ox.get_mpz_t(), oy = c.oy.get_mpz_t();
  mpz_sub(ox, w.ux, w.ax);  // centre − a = (b − a)/2, den = 2
  mpz_sub(oy, w.uy, w.ay);
  mpz_ptr r2 = c.r2num.get_mpz_t();
  mpz_mul(r2, ox, ox);
  mpz_addmul(r2, oy, oy);
  finish(c);
  return c;
}

ExactCircle exact_circumcircle(Point2 a, Point2 b, Point2 cc) {
  ExactCircle c;
  c.support_size = 3;
  c.support = {a, b, cc};
  const int e = min_exponent({a.x, a.y, b.x, b.y, cc.x, cc.y});
  CircleScratch& w = circle_scratch();
  set_scaled(w.ax, a.x, e);
  set_scaled(w.ay, a.y, e);
  // Relative to a: u = b − a, v = c − a; centre − a = (v_y|u|² − u_y|v|², u_x|v|² − v_x|u|²)/d
  // with d = 2(u_x v_y − u_y v_x) (Cramer on the bisector equations 2u·x = |u|², 2v·x = |v|²).
  set_scaled(w.ux, b.x, e);
  mpz_sub(w.ux, w.ux, w.ax);
  set_scaled(w.uy, b.y, e);
  mpz_sub(w.uy, w.uy, w.ay);
  set_scaled(w.vx, cc.x, e);
  mpz_sub(w.vx, w.vx, w.ax);
  set_scaled(w.vy, cc.y, e);
  mpz_sub(w.vy, w.vy, w.ay);
  mpz_ptr d = c.den.get_mpz_t();
  mpz_mul(d, w.ux, w.vy);
  mpz_mul(w.t, w.uy, w.vx);
  mpz_sub(d, d, w.t);
  mpz_mul_2exp(d, d, 1);
  if (mpz_sgn(d) == 0)
    throw std::logic_error("exact_circumcircle: collinear support points (internal error)");
  mpz_mul(w.u2, w.ux, w.ux);
  mpz_addmul(w.u2, w.uy, w.uy);
  mpz_mul(w.v2, w.vx, w.vx);
  mpz_addmul(w.v2, w.vy, w.vy);
  mpz_ptr ox = c.ox.get_mpz_t(), oy = c.oy.get_mpz_t();
  mpz_mul(ox, w.vy, w.u2);
  mpz_submul(ox, w.uy, w.v2);
  mpz_mul(oy, w.ux, w.v2);
  mpz_submul(oy, w.vx, w.u2);
  if (mpz_sgn(d) < 0) {
    mpz_neg(d, d);
    mpz_neg(ox, ox);
    mpz_neg(oy, oy);
  }
  c.exponent = e;
  mpz_ptr nx = c.nx.get_mpz_t(), ny = c.ny.get_mpz_t();
  mpz_mul(nx, w.ax, d);
  mpz_add(nx, nx, ox);
  mpz_mul(ny, w.ay, d);
  mpz_add(ny, ny, oy);
  mpz_ptr r2 = c.r2num.get_mpz_t();
  mpz_mul(r2, ox, ox);
  mpz_addmul(r2, oy, oy);
  finish(c);
  return c;
}

int compare_radius(const ExactCircle& a, const ExactCircle& b) {
  const int m = std::min(a.exponent, b.exponent);
  CircleScratch& w = circle_scratch();
  mpz_mul(w.gx, a.r2num.get_mpz_t(), b.den.get_mpz_t());
  mpz_mul(w.gx, w.gx, b.den.get_mpz_t());
  mpz_mul_2exp(w.gx, w.gx, static_cast<mp_bitcnt_t>(2 * (a.exponent - m)));
  mpz_mul(w.gy, b.r2num.get_mpz_t(), a.den.get_mpz_t());
  mpz_mul(w.gy, w.gy, a.den.get_mpz_t());
  mpz_mul_2exp(w.gy, w.gy, static_cast<mp_bitcnt_t>(2 * (b.exponent - m)));
  const int s = mpz_cmp(w.gx, w.gy);
  return s < 0 ? -1 : (s > 0 ? 1 : 0);
}

bool same_center(const ExactCircle& a, const ExactCircle& b) {
  const int m = std::min(a.exponent, b.exponent);
  return shifted(a.nx * b.den, a.exponent - m) == shifted(b.nx * a.den, b.exponent - m) &&
         shifted(a.ny * b.den, a.exponent - m) == shifted(b.ny * a.den, b.exponent - m);
}

const PreciseCircle& ExactCircle::precise() const {
  if (precise_) return *precise_;
  PreciseCircle pc;
  if (support_size >= 2) {
    // centre = n/den · 2^e; R*²s² = r2num/den² · 2^(2e + 2k), s = 2^k.
    double ex = 0.0, ey = 0.0, er = 0.0;
    pc.cx = split_quotient(nx.get_mpz_t(), den.get_mpz_t(), exponent, &ex);
    pc.cy = split_quotient(ny.get_mpz_t(), den.get_mpz_t(), exponent, &ey);
    const mpz_class den2 = den * den;
    pc.r2 = split_quotient(r2num.get_mpz_t(), den2.get_mpz_t(),
                           2L * exponent + 2L * scale_exponent, &er);
    pc.center_error = std::max(ex, ey);
    pc.r2_error = er;
    pc.scale = scale;
    pc.usable = filter_usable && std::isfinite(pc.center_error) && std::isfinite(er);
  }
  precise_ = pc;
  return *precise_;
}

namespace {

/// GMP integers reused across calls (no allocation per test): the exact tie test below
/// runs once per co-circular point, i.e. for every point of exactly co-circular data.
struct TieScratch {
  mpz_t px, py, t;
  TieScratch() { mpz_inits(px, py, t, nullptr); }
  ~TieScratch() { mpz_clears(px, py, t, nullptr); }
  TieScratch(const TieScratch&) = delete;
  TieScratch& operator=(const TieScratch&) = delete;
};

/// Lowest set bit of a finite nonzero double: v = odd · 2^result.
int low_bit_exponent(double v) {
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(v);
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  std::uint64_t mantissa = bits & ((std::uint64_t{1} << 52) - 1);
  if (biased != 0) mantissa |= std::uint64_t{1} << 52;
  return (biased != 0 ? biased : 1) - 1075 + std::countr_zero(mantissa);
}

/// Exact sign of |p − c*|² − R*² in the circle's integers: |P·den − N|² − r2num with
/// P = p·2^−e (precondition: p's coordinates are multiples of 2^e). When p − support[0]
/// is below 2^(53+e) (data of one magnitude: always), the offsets D = (p − a)·2^−e are
/// exact machine integers and |D·den − o|² is formed with one-limb multipliers; otherwise
/// the absolute form.
int integer_side(const ExactCircle& circle, Point2 p) {
  thread_local TieScratch s;
  const Point2 a = circle.support[0];
  const int e = circle.exponent;
  const double dx = p.x - a.x, dy = p.y - a.y;  // exact when the test below passes
  const double sx = std::ldexp(dx, -e), sy = std::ldexp(dy, -e);
  if ((p.x == 0.0 || low_bit_exponent(p.x) >= e) && (p.y == 0.0 || low_bit_exponent(p.y) >= e) &&
      std::fabs(sx) < 0x1.0p53 && std::fabs(sy) < 0x1.0p53) {
    // p and a lie on the 2^e grid, so p − a is a multiple of 2^e; below 2^(53+e) it is a
    // double and its computed value exact (a rounded value would be ≥ 2^(53+e)).
    mpz_mul_si(s.px, circle.den.get_mpz_t(), static_cast<long>(sx));
    mpz_sub(s.px, s.px, circle.ox.get_mpz_t());
    mpz_mul_si(s.py, circle.den.get_mpz_t(), static_cast<long>(sy));
    mpz_sub(s.py, s.py, circle.oy.get_mpz_t());
    mpz_mul(s.t, s.px, s.px);
    mpz_addmul(s.t, s.py, s.py);
    return mpz_cmp(s.t, circle.r2num.get_mpz_t());
  }
  set_scaled(s.px, p.x, circle.exponent);
  set_scaled(s.py, p.y, circle.exponent);
  mpz_mul(s.px, s.px, circle.den.get_mpz_t());
  mpz_sub(s.px, s.px, circle.nx.get_mpz_t());
  mpz_mul(s.py, s.py, circle.den.get_mpz_t());
  mpz_sub(s.py, s.py, circle.ny.get_mpz_t());
  mpz_mul(s.t, s.px, s.px);
  mpz_addmul(s.t, s.py, s.py);
  return mpz_cmp(s.t, circle.r2num.get_mpz_t());
}

}  // namespace

CGAL::Bounded_side exact_side(const ExactCircle& circle, Point2 p, double* gap) {
  // The supports (and their duplicates) lie on the circle by construction: every pass
  // meets them in its ambiguous band, and they need no arithmetic at all.
  for (int k = 0; k < circle.support_size; ++k)
    if (p == circle.support[static_cast<std::size_t>(k)]) {
      if (gap != nullptr) *gap = 0.0;
      return CGAL::ON_BOUNDARY;
    }
  if (circle.filter_usable && circle.precise().usable) {
    const PreciseValue v = precise_power_gap(circle.precise(), p);
    if (gap != nullptr) *gap = v.value;
    const int s = sign_of(v);
    if (s < 0) return CGAL::ON_BOUNDED_SIDE;
    if (s > 0) return CGAL::ON_UNBOUNDED_SIDE;
  }
  // Ties: the circle's own integers when p lies on its grid (always for data of one
  // magnitude), else CGAL's predicates on the supports.
  if (circle.support_size >= 2 && (p.x == 0.0 || exponent_of(p.x) >= circle.exponent) &&
      (p.y == 0.0 || exponent_of(p.y) >= circle.exponent)) {
    const int s = integer_side(circle, p);
    return s < 0 ? CGAL::ON_BOUNDED_SIDE : (s == 0 ? CGAL::ON_BOUNDARY : CGAL::ON_UNBOUNDED_SIDE);
  }
  switch (circle.support_size) {
    case 1:
      return p == circle.support[0] ? CGAL::ON_BOUNDARY : CGAL::ON_UNBOUNDED_SIDE;
    case 2: {
      const int s = dot_sign(p, circle.support[0], circle.support[1]);
      return s < 0 ? CGAL::ON_BOUNDED_SIDE : (s == 0 ? CGAL::ON_BOUNDARY : CGAL::ON_UNBOUNDED_SIDE);
    }
    default: {
      const EPoint a = to_epick(circle.support[0]), b = to_epick(circle.support[1]),
                   c = to_epick(circle.support[2]);
      return side_of_circumcircle(a, b, c, CGAL::orientation(a, b, c), to_epick(p));
    }
  }
}

int dot_sign(Point2 o, Point2 a, Point2 b) {
  const double ax = a.x - o.x, ay = a.y - o.y, bx = b.x - o.x, by = b.y - o.y;
  const double px = ax * bx, py = ay * by;
  const double v = px + py;
  const double bound = 8.0 * kUnitRoundoff * (std::fabs(px) + std::fabs(py)) + 1e-300;
  if (std::isfinite(v) && std::isfinite(bound)) {
    if (v > bound) return 1;
    if (v < -bound) return -1;
  }
  switch (CGAL::angle(to_epick(a), to_epick(o), to_epick(b))) {
    case CGAL::ACUTE:
      return 1;
    case CGAL::RIGHT:
      return 0;
    default:
      return -1;
  }
}

mpq_class exact_r2(const ExactCircle& circle) {
  mpq_class q(circle.r2num, mpz_class(circle.den * circle.den));
  q.canonicalize();
  const long e2 = 2L * circle.exponent;
  if (e2 > 0) q <<= static_cast<unsigned long>(e2);
  if (e2 < 0) q >>= static_cast<unsigned long>(-e2);
  return q;
}

double exact_power_gap(const ExactCircle& circle, Point2 p) {
  // Common exponent e' = min(e, exponents of p); shift the circle's integers by e − e':
  // num = r2num·4^s − |P·den − N·2^s|² with P = p·2^−e'.
  const int e = std::min(circle.exponent, min_exponent({p.x, p.y}));
  const auto s = static_cast<mp_bitcnt_t>(circle.exponent - e);
  CircleScratch& w = circle_scratch();
  set_scaled(w.gx, p.x, e);
  mpz_mul(w.gx, w.gx, circle.den.get_mpz_t());
  mpz_mul_2exp(w.t, circle.nx.get_mpz_t(), s);
  mpz_sub(w.gx, w.gx, w.t);
  set_scaled(w.gy, p.y, e);
  mpz_mul(w.gy, w.gy, circle.den.get_mpz_t());
  mpz_mul_2exp(w.t, circle.ny.get_mpz_t(), s);
  mpz_sub(w.gy, w.gy, w.t);
  mpz_mul_2exp(w.gn, circle.r2num.get_mpz_t(), 2 * s);
  mpz_submul(w.gn, w.gx, w.gx);
  mpz_submul(w.gn, w.gy, w.gy);
  mpz_mul(w.d2, circle.den.get_mpz_t(), circle.den.get_mpz_t());
  // Value · scale² = num/den² · 2^(2e' + 2k).
  return ratio_to_double(w.gn, w.d2, 2L * e + 2L * circle.scale_exponent);
}

}  // namespace vcmm::geometry::internal
