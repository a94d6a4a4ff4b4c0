// internal/near_circle.h — distances and reciprocal distances of points to a centre when they
// all lie close to a known radius, without square root or division (the LS fit's Gauss-Newton
// passes, least_squares.cpp; the Gaussian filter's first pass, gaussian_filter.cpp). Square
// root and division cost ~2–3 cycles an element each on x86 whatever the vector width, a
// multiply or add ~10× less; at 3 600 points two of each per pass were most of a pass.
//
// Notation. q = dx² + dy² (a double, as computed by the caller), R₀ a reference radius with at
// most 26 significant bits (so R₀² is exact in double), s = (q − R₀²)/R₀². Then
//   r   = √q   = R₀ √(1 + s)   = R₀ + R₀ (s/2 − s²/8 + s³/16 − 5s⁴/128 + 7s⁵/256 − 21s⁶/1024 …)
//   1/r        = (1/R₀)(1 + s)^−½ = 1/R₀ + (1/R₀)(−s/2 + 3s²/8 − 5s³/16 + 35s⁴/128 − 63s⁵/256
//                                              + 231s⁶/1024 − 429s⁷/2048 …)
// (binomial series, |s| < 1). Truncated after s^D, the remainder of either series is at most
// its first omitted term over (1 − |s|): the coefficients |c_k| of both series decrease in k,
// and for s > 0 the series alternate, for s < 0 every term has the sign of the first omitted
// one, a geometric majorant bounds the tail. The larger first omitted coefficient is that of
// 1/r: 35/128 (D = 3), 63/256 (D = 4), 429/2048 (D = 6). Each degree is used only where
// |s| ≤ s_max(D), chosen so that the truncation is below 2⁻⁶¹ relative:
//   D = 3: s_max = 2⁻¹⁵ (35/128 · 2⁻⁶⁰ / (1 − 2⁻¹⁵) < 2⁻⁶¹·⁸)   deviations up to ~1.5e-5 R
//   D = 4: s_max = 2⁻¹² (63/256 · 2⁻⁶⁰ / (1 − 2⁻¹²) < 2⁻⁶²)     deviations up to ~1.2e-4 R
//   D = 6: s_max = 2⁻⁹  (429/2048 · 2⁻⁶³ / (1 − 2⁻⁹) < 2⁻⁶⁵)    deviations up to ~1e-3 R
// (|r/R₀ − 1| ≈ |s|/2). Beyond 2⁻⁹ the caller takes square root and division.
//
// Evaluation. q − R₀² is exact (Sterbenz: q within a factor 2 of R₀² for |s| ≤ ½); s =
// fl((q − R₀²)·fl(1/R₀²)) is within 2u of the exact quotient (u = 2⁻⁵³), which moves R₀·s/2 by
// ≤ u R₀ |s| ≤ 2⁻⁶² R₀. The correction R₀·P(s) = s·(a₁ + s·(a₂ + … + s·a_D)) is evaluated by
// Horner with a_k = R₀·c_k exact (c_k = m/2^j with m ≤ 21: at most 31 significant bits), each
// step rounding at the size of the term it forms, ≤ R₀|s|/2: the accumulated error is below
// 3u R₀ |s| ≤ 2⁻⁶⁰ R₀. r = fl(R₀ + R₀·P(s)) then rounds once. So
//   |r − √q| ≤ ½ ulp(r) + ε,   ε ≤ 2⁻⁵⁹ r ≤ 2⁻⁶ ulp(r)   (truncation + s + Horner),
// i.e. r is the correctly rounded √q except where √q lies within ε of a rounding midpoint,
// where it is the neighbour: never more than 1 ulp from std::sqrt(q), and equal to it for all
// but a fraction ~ε/ulp of the points (tests/geometry/near_circle_test.cpp measures both).
// The error of q itself (the caller's rounding of dx² + dy², ≤ 1 ulp of q, i.e. ½ ulp of r)
// is the same for √q and is not counted here.
// 1/r = fl(h + (l + s·(b₁ + s·(b₂ + … + s·b_D)))) with 1/R₀ = h + l as a double-double
// (h = fl(1/R₀), l = fl((1 − R₀h)·h), the residual 1 − R₀h exact in one fma, see
// near_circle_about) and b_k = fl(h·d_k): the same bound, ½ ulp + ε, against 1/√q — closer
// than std::sqrt followed by a division (two roundings, up to ~1 ulp).
//
// Use. One NearCircle per pass (near_circle_about(radius)); per point s = near_circle_s(q),
// then near_circle_offset<D>(s) = R₀·P(s) (the caller adds R₀ for r, or R₀ − R for a deviation
// from another radius R), near_circle_inverse<D>(s) = 1/r. The caller tracks max|s| (or a flag
// for |s| > s_max(D)) in the same pass, branch-free, and redoes the pass with a larger degree or
// with square root and division when it exceeds s_max(D) — so the series is only ever used
// where the bound above holds. The templates take double or GCC vector types (element-wise,
// the same operations in the same order: the baseline and AVX2 variants of a pass give the same
// bits; the project is compiled with -ffp-contract=off, so no FMA is formed).
// Precondition: q finite or +∞ (then s = +∞ > s_max); 2⁻⁵⁰⁰ ≤ radius ≤ 2⁵⁰⁰.
#pragma once

#include <cmath>

// The templates below take 32-byte vectors by value in the baseline compilation too (their AVX2
// instantiations are always inlined into target("avx2") functions: no vector crosses a call
// boundary); GCC's note that such a call "changes the ABI" does not apply. GCC reports it at
// the end of the translation unit, so it is silenced for the including file.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace vcmm::geometry::internal {

/// The degrees implemented and their ranges of |s| (see the file comment).
constexpr int kNearCircleMaxDegree = 6;
constexpr double near_circle_s_max(int degree) {
  return degree == 3 ? 0x1p-15 : degree == 4 ? 0x1p-12 : degree == 6 ? 0x1p-9 : 0.0;
}

/// The smallest implemented degree whose range covers |s| ≤ s_bound, or 0 when none does
/// (s_bound > 2⁻⁹ or not a number: use square root and division).
constexpr int near_circle_degree(double s_bound) {
  return s_bound <= near_circle_s_max(3)   ? 3
         : s_bound <= near_circle_s_max(4) ? 4
         : s_bound <= near_circle_s_max(6) ? 6
                                           : 0;
}

/// Whether the kernel may be used about `radius`: 2⁻⁵⁰⁰ ≤ radius ≤ 2⁵⁰⁰ (R₀² and the products
/// of near_circle_about stay normal and exact).
constexpr bool near_circle_radius_ok(double radius) {
  return radius >= 0x1p-500 && radius <= 0x1p500;
}

/// The degree for a pass about `radius` whose distances r are expected within deviation_bound
/// of it: |r/R₀ − 1| ≤ t = deviation_bound/radius + 2⁻²⁵ (R₀'s rounding), so |s| = |(r/R₀)² − 1|
/// ≤ t (2 + t), plus 2⁻⁵⁰ for the rounding of q. 0 (square root and division) where no degree
/// covers that or the radius is out of range; a bound that is not a number ≥ 0 (unknown) gives
/// degree 6. The pass checks |s| all the same: a wrong bound costs a redo, never accuracy.
inline int near_circle_degree_for(double radius, double deviation_bound) {
  if (!near_circle_radius_ok(radius)) return 0;
  if (!(deviation_bound >= 0.0)) return 6;
  const double t = deviation_bound / radius + 0x1p-25;
  return near_circle_degree(t * (2.0 + t) + 0x1p-50);
}

/// The constants of one pass about a reference radius.
struct NearCircle {
  double r0 = 0.0;         ///< R₀: the radius rounded to 26 significant bits
  double r0_sq = 0.0;      ///< R₀², exact
  double inv_r0_sq = 0.0;  ///< fl(1/R₀²)
  double inv_hi = 0.0;     ///< fl(1/R₀)
  double inv_lo = 0.0;     ///< 1/R₀ − inv_hi, to a relative 2⁻⁵³
  double a[kNearCircleMaxDegree] = {};  ///< R₀·c_k, k = 1..6 (√ series), exact
  double b[kNearCircleMaxDegree] = {};  ///< fl(inv_hi·d_k), k = 1..6 (1/√ series)
};

/// The constants about `radius` (R₀ = radius to 26 bits, |R₀ − radius| ≤ 2⁻²⁶ radius).
/// Precondition: 2⁻⁵⁰⁰ ≤ radius ≤ 2⁵⁰⁰ (R₀² normal, the products below exact).
inline NearCircle near_circle_about(double radius) {
  NearCircle k;
  // Veltkamp's split with 2²⁷ + 1: the high part has at most 53 − 27 = 26 significant bits.
  const double c = 134217729.0 * radius;
  k.r0 = c - (c - radius);
  k.r0_sq = k.r0 * k.r0;
  k.inv_r0_sq = 1.0 / k.r0_sq;
  k.inv_hi = 1.0 / k.r0;
  // 1 − R₀·h is exact in one fma: with R₀ = m·2^e (m < 2²⁶) and h = n·2^f (n < 2⁵³), R₀h and 1
  // are multiples of 2^(e+f) (R₀h ≈ 1 puts e + f ≤ −77), and |1 − R₀h| ≤ R₀·ulp(h)/2 < 2^(25+e+f):
  // the residual has at most 25 significant bits.
  k.inv_lo = std::fma(-k.r0, k.inv_hi, 1.0) * k.inv_hi;
  constexpr double kSqrt[kNearCircleMaxDegree] = {0.5,         -0.125,       0.0625,
                                                  -5.0 / 128,  7.0 / 256,    -21.0 / 1024};
  constexpr double kInvSqrt[kNearCircleMaxDegree] = {-0.5,        0.375,       -0.3125,
                                                     35.0 / 128,  -63.0 / 256, 231.0 / 1024};
  for (int j = 0; j < kNearCircleMaxDegree; ++j) {
    k.a[j] = k.r0 * kSqrt[j];
    k.b[j] = k.inv_hi * kInvSqrt[j];
  }
  return k;
}

/// s = (q − R₀²)/R₀² for one value or a vector of them.
template <class T>
[[gnu::always_inline]] inline T near_circle_s(const T& q, const NearCircle& k) {
  return (q - k.r0_sq) * k.inv_r0_sq;
}

/// R₀·P_D(s) ≈ √q − R₀ (unrounded by the final addition): r = R₀ + this, or a deviation from
/// another radius R as (R₀ − R) + this. Valid for |s| ≤ near_circle_s_max(D).
template <int D, class T>
[[gnu::always_inline]] inline T near_circle_offset(const T& s, const NearCircle& k) {
  static_assert(near_circle_s_max(D) > 0.0, "near_circle: degrees 3, 4 and 6 only");
  T p = s * k.a[D - 1];
  for (int j = D - 2; j >= 0; --j) p = s * (k.a[j] + p);
  return p;
}

/// 1/√q, for |s| ≤ near_circle_s_max(D).
template <int D, class T>
[[gnu::always_inline]] inline T near_circle_inverse(const T& s, const NearCircle& k) {
  static_assert(near_circle_s_max(D) > 0.0, "near_circle: degrees 3, 4 and 6 only");
  T p = s * k.b[D - 1];
  for (int j = D - 2; j >= 0; --j) p = s * (k.b[j] + p);
  return k.inv_hi + (k.inv_lo + p);
}

}  // namespace vcmm::geometry::internal
