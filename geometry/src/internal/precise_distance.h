// internal/precise_distance.h — the second stage of the fitters' floating filters: the sign
// of |p − c*|² − ρ² for an exact rational centre c* and squared radius ρ², evaluated in
// double-double arithmetic with a rigorous error bound. Not part of the public API.
//
// Why. The first-stage filters (internal/extremal_circle.cpp, the minimum-zone containment
// pass) round the centre to doubles, so they cannot place a point closer than ~1e-15 of the
// radius to the circle. On perfect circles (co-circular to the last ulp), ulp-level forms
// and zones of width 1e-13 mm every point lies in that band, and sending them all to exact
// rational predicates costs ~1 µs each. Here the centre is carried as an unevaluated sum of
// two doubles (error ~2⁻¹⁰⁶ relative) and the squared distance is formed with error-free
// transformations, so only points within ~1e-30 of the radius — in practice the exact ties
// (contacts, exactly co-circular points) — remain for the exact predicate.
//
// Notation: u = 2⁻⁵³. TwoSum(a, b) = (s, e) with s = fl(a + b), s + e = a + b exactly
// (Knuth; any magnitudes). TwoProduct(a, b) = (p, e) with p = fl(ab), p + e = ab exactly
// (Dekker's splitting, no FMA needed: exact while |a|, |b| < 2⁹⁹⁵ and no underflow).
// Both need round-to-nearest: never call these inside CGAL::Protect_FPU_rounding.
//
// The test. With c* = (h_x + l_x, h_y + l_y) + ε (|ε_x|, |ε_y| ≤ e_c) and scale s (a power
// of two):  p_x − h_x = a_x + b_x exactly (TwoSum);  m_x = fl(b_x − l_x), so the exact
// offset p_x − c*_x = a_x + m_x + η_x with |η_x| ≤ u|m_x| + e_c (+ 2⁻¹⁰⁰⁰ for underflow).
// After scaling every length by s (exact),
//   |p − c*|²s² − ρ²s² = T1 + [T2 + S2 + P2 + Q2 − L + 2a_x m_x + 2a_y m_y + m_x² + m_y²]
//                        + Σ (2(a + m)η + η²) − δ_ρ,
// where (P1, P2) = TwoProduct(a_x, a_x), (Q1, Q2) = TwoProduct(a_y, a_y), (S1, S2) =
// TwoSum(P1, Q1), (T1, T2) = TwoSum(S1, −H) and ρ²s² = H + L + δ_ρ, |δ_ρ| ≤ e_ρ. The bracket
// is summed in double: nine terms, each product rounded once, so its error is below
// 10u·Σ|terms|; the final addition to T1 errs by ≤ u|value|. The bound used adds 16u·Σ|terms|,
// 2u|value|, the η terms, e_ρ and 1e-300 (subnormal losses): generous factors, still ~1e-30
// of ρ²s² on unit-size data.
#pragma once

#include <gmp.h>

#include <cmath>

#include "vcmm/geometry/point.h"

namespace vcmm::geometry::internal {

/// hi + lo, |lo| ≤ ulp(hi)/2 (an unevaluated sum).
struct TwoDoubles {
  double hi = 0.0;
  double lo = 0.0;
};

/// Knuth's TwoSum: hi = fl(a + b), hi + lo = a + b exactly.
inline TwoDoubles two_sum(double a, double b) {
  const double s = a + b;
  const double bb = s - a;
  return {s, (a - (s - bb)) + (b - bb)};
}

/// Dekker's TwoProduct: hi = fl(ab), hi + lo = ab exactly (|a|, |b| < 2⁹⁹⁵, no underflow).
inline TwoDoubles two_product(double a, double b) {
  constexpr double kSplit = 134217729.0;  // 2²⁷ + 1
  const double p = a * b;
  const double ta = kSplit * a, tb = kSplit * b;
  const double ah = ta - (ta - a), al = a - ah;
  const double bh = tb - (tb - b), bl = b - bh;
  return {p, ((ah * bh - p) + ah * bl + al * bh) + al * bl};
}

/// num/den · 2^exp (den > 0) as hi + lo: hi its correctly rounded double, and
/// |num/den · 2^exp − hi − lo| ≤ *error (= 2⁻¹⁵⁹|hi| + u|lo| + 2⁻¹⁰⁰⁰). Out of the double
/// range (hi infinite or underflowed to 0 from a nonzero quotient): *error = inf.
TwoDoubles split_quotient(mpz_srcptr num, mpz_srcptr den, long exp, double* error);

/// An exact circle for the second-stage filter: centre c* and squared radius ρ².
struct PreciseCircle {
  TwoDoubles cx, cy;          ///< c* ≈ (cx.hi + cx.lo, cy.hi + cy.lo), unscaled
  double center_error = 0.0;  ///< per coordinate, unscaled
  TwoDoubles r2;              ///< ρ²·s² (scaled units)
  double r2_error = 0.0;      ///< |ρ²s² − r2.hi − r2.lo| ≤ r2_error
  double scale = 1.0;         ///< s, a power of two with ρs = O(1) (1: unscaled)
  /// false when some part is out of range (non-finite): every answer is then 0.
  bool usable = false;
};

/// |p − c*|²s² − ρ²s² ∈ [value − bound, value + bound] (rigorous; both infinite or NaN when
/// out of range). O(1), ~50 flops.
struct PreciseValue {
  double value = 0.0;
  double bound = 0.0;
};
PreciseValue precise_power_gap(const PreciseCircle& circle, Point2 p);

/// The sign of a PreciseValue when proven: +1, −1, or 0 (undecided: ask the exact test).
inline int sign_of(const PreciseValue& v) {
  if (v.value > v.bound) return 1;  // NaN or infinite bounds decide nothing
  if (v.value < -v.bound) return -1;
  return 0;
}

/// Sign of |p − c*|² − ρ²: +1 (strictly outside), −1 (strictly inside), 0 when the
/// double-double value cannot decide (ties: ask the exact predicate).
inline int precise_side(const PreciseCircle& circle, Point2 p) {
  return circle.usable ? sign_of(precise_power_gap(circle, p)) : 0;
}

/// Both circles of an annulus with one centre (`outer` and `inner` differ only in r2):
/// +1 strictly outside the outer circle, −1 strictly inside the inner one, 0 proven in the
/// closed annulus, 2 undecided. One evaluation: the inner gap is the outer one plus
/// R²s² − r²s², whose rounding is added to the bound.
int precise_annulus_side(const PreciseCircle& outer, const PreciseCircle& inner, Point2 p);

/// The in-circle determinant of (a, b, c, d) — CGAL's side_of_oriented_circle convention:
/// +1 when d lies inside the circle through a, b, c in counter-clockwise order (outside when
/// clockwise), −1 on the other side, 0 on the circle — from two floating stages: doubles
/// with Shewchuk's bound (iccerrboundA, J. R. Shewchuk, "Adaptive precision floating-point
/// arithmetic and fast robust geometric predicates", DCG 18, 1997), then double-double with
/// a running error bound (precise_distance.cpp). Returns 2 when neither decides (ties and
/// out-of-range values: ask CGAL's exact predicate). ~15 flops on general data, ~300 on
/// points co-circular to the last ulp. The first stage is inline (it decides general data).
int precise_incircle(Point2 a, Point2 b, Point2 c, Point2 d);  ///< the second stage alone
inline int filtered_incircle(Point2 a, Point2 b, Point2 c, Point2 d) {
  constexpr double kU = 0x1.0p-53;
  // Stage 1: doubles (Shewchuk's incircle, stage A).
  const double adx = a.x - d.x, ady = a.y - d.y, bdx = b.x - d.x, bdy = b.y - d.y;
  const double cdx = c.x - d.x, cdy = c.y - d.y;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy, cdxady = cdx * ady;
  const double adxcdy = adx * cdy, adxbdy = adx * bdy, bdxady = bdx * ady;
  const double alift = adx * adx + ady * ady, blift = bdx * bdx + bdy * bdy;
  const double clift = cdx * cdx + cdy * cdy;
  const double det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) +
                     clift * (adxbdy - bdxady);
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * alift +
                           (std::fabs(cdxady) + std::fabs(adxcdy)) * blift +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * clift;
  const double bound = (10.0 + 96.0 * kU) * kU * permanent;
  if (!(std::isfinite(det) && std::isfinite(bound))) return 2;
  if (det > bound) return 1;
  if (det < -bound) return -1;
  return precise_incircle(a, b, c, d);
}

/// |(p − c)·scale|² − s², c a double point, s a double (already in scaled units), scale a
/// power of two (1: unscaled), to ~u² relative to |p − c|² (double-double, no rigorous
/// bound): the linearised programs' costs on thin zones, where plain doubles lose the
/// ~1e-16 relative differences between the squared distances.
inline double precise_power(Point2 p, Point2 c, double s, double scale = 1.0) {
  TwoDoubles dx = two_sum(p.x, -c.x), dy = two_sum(p.y, -c.y);
  dx = {dx.hi * scale, dx.lo * scale};
  dy = {dy.hi * scale, dy.lo * scale};
  const TwoDoubles P = two_product(dx.hi, dx.hi), Q = two_product(dy.hi, dy.hi);
  const TwoDoubles K = two_product(s, s);
  const TwoDoubles S = two_sum(P.hi, Q.hi);
  const TwoDoubles T = two_sum(S.hi, -K.hi);
  return T.hi + (T.lo + S.lo + P.lo + Q.lo - K.lo + 2.0 * (dx.hi * dx.lo + dy.hi * dy.lo) +
                 (dx.lo * dx.lo + dy.lo * dy.lo));
}

}  // namespace vcmm::geometry::internal
