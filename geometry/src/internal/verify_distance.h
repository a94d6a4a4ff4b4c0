// internal/verify_distance.h — the floating-point filter of verify() (certificate.cpp only; the
// fitters never use it): squared distances and orientations about a rational centre c, computed
// in double with a rigorous forward error bound, so a sign is decided in floating point only
// when the bound proves it (a static filter in the sense of Shewchuk and CGAL's
// Static_filtered_predicate). Undecided cases go to verify()'s exact GMP path.
//
// Error bound (docs/method.md §3). c is known as c̃ with |c_x − c̃_x|, |c_y − c̃_y| ≤ δ (c̃ a
// double, from a correctly rounded interval enclosure of the rational). For input doubles p,
// ã = fl(p_x − c̃_x) differs from a = p_x − c_x by at most u|ã| + δ (u = 2⁻⁵³, round to nearest;
// a difference in the subnormal range is exact). With M ≥ |ã|, |b̃| and e = uM + δ:
//   squared distance  |fl(ã² + b̃²) − (a² + b²)| ≤ 4Me + 2e² + (4u + 2u²)M² + 2⁻¹⁰⁷³,
//   orientation       |fl(ũ_x ṽ_y − ũ_y ṽ_x) − cross(u, v)| ≤ 4Me + 2e² + (4u + 2u²)M² + 2⁻¹⁰⁷³,
// both ≤ (8u + 4u²)M² + (4 + 4u)δM + 2δ² + 2⁻¹⁰⁷³ < E(M) = 9uM² + 5δM + 3δ² + 4·DBL_MIN.
// The ~10 % slack of E's coefficients covers the rounding of E itself (a few u relative).
// Non-finite values (overflow, an unrepresentable centre) make every comparison undecided:
// NaN and ∞ never pass `>`.
#pragma once

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <utility>

#include "vcmm/geometry/point.h"

namespace vcmm::geometry::internal {

/// A rational point enclosed as (x ± delta, y ± delta).
struct ApproxCentre {
  double x = 0.0;
  double y = 0.0;
  double delta = 0.0;
};

/// From enclosures [lo, hi] of the two coordinates. delta = +∞ (every decision deferred to
/// the exact path) when an enclosure is not finite or the filter is switched off.
ApproxCentre approx_centre(std::pair<double, double> x, std::pair<double, double> y);

/// A squared distance in double and a bound on its error: |value − exact| ≤ error.
struct Distance2 {
  double value = 0.0;
  double error = 0.0;
};

/// E(M) above.
inline double filter_error_bound(double m, double delta) {
  constexpr double u = 0x1p-53;
  return 9.0 * u * m * m + 5.0 * delta * m + 3.0 * delta * delta + 4.0 * DBL_MIN;
}

/// |p − c|² with its error bound.
inline Distance2 distance2(Point2 p, const ApproxCentre& c) {
  const double a = p.x - c.x;
  const double b = p.y - c.y;
  const double m = std::max(std::fabs(a), std::fabs(b));  // finite inputs: no NaN here
  return {a * a + b * b, filter_error_bound(m, c.delta)};
}

/// sign(exact(a) − exact(b)) when the bounds prove it: +1 or −1; 0 means undecided (never
/// "equal": ties always go to the exact path).
inline int certain_sign(const Distance2& a, const Distance2& b) {
  const double diff = a.value - b.value;
  const double tol = (a.error + b.error) * (1.0 + 0x1p-30);  // covers the rounding of diff
  if (diff > tol) return 1;
  if (diff < -tol) return -1;
  return 0;
}

/// sign(cross(p − c, q − c)) (+1: c, p, q counter-clockwise) when the bound proves it; 0 means
/// undecided.
inline int certain_orientation(const ApproxCentre& c, Point2 p, Point2 q) {
  const double ux = p.x - c.x, uy = p.y - c.y, vx = q.x - c.x, vy = q.y - c.y;
  const double m = std::max(std::max(std::fabs(ux), std::fabs(uy)),
                            std::max(std::fabs(vx), std::fabs(vy)));
  const double v = ux * vy - uy * vx;
  const double tol = filter_error_bound(m, c.delta);
  if (v > tol) return 1;
  if (v < -tol) return -1;
  return 0;
}

/// Test hook: with the filter off every decision is deferred to the exact path (and the
/// fast MI global test is skipped), so tests can compare both paths on the same input.
/// Process-wide; not for concurrent use with verify() in other threads.
bool verify_filter_enabled();
void set_verify_filter_enabled(bool enabled);

}  // namespace vcmm::geometry::internal
