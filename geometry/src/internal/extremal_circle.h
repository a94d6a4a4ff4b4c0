// internal/extremal_circle.h — pieces shared by the minimum-circumscribed (MC) and the
// maximum-inscribed (MI) fitters: a cheap centre estimate, a division-light pseudo-angle,
// exact circles through 1, 2 or 3 input points and the rigorous floating filter that lets
// an O(n) pass decide "strictly inside / strictly outside / ask the exact predicate".
// Not part of the public API.
//
// Notation: p_i input points (doubles, taken as exact rationals), c* an exact rational
// centre, R*² its exact squared radius, c̃ = c* rounded to doubles, δ ≥ |c̃ − c*|.
// u = 2⁻⁵³ is the unit roundoff.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include <gmpxx.h>

#include "internal/distance_scan.h"
#include "internal/exact.h"
#include "internal/precise_distance.h"
#include "vcmm/geometry/point.h"

namespace vcmm::geometry::internal {

inline constexpr double kUnitRoundoff = 0x1.0p-53;

/// Algebraic (Kåsa) circle centre of (a stride sample of at most ~512) points, on
/// coordinates centred at their mean and scaled by a power of two to O(1), as a warm start
/// only: correctness never depends on it. Falls back to the mean when the 2×2 system is
/// singular (collinear-looking data). O(min(n, 512)).
struct WarmStart {
  Point2 center;
  double scale = 1.0;  ///< power of two making (p − center)·scale O(1) over the sample
};
WarmStart kasa_center(std::span<const Point2> points);

/// The warm start of the MC and MI fast paths, from one stride sample of ~512 points (every
/// max(1, ⌊n/512⌋)-th): the Kåsa centre c₀ (kasa_center) and, per pseudo-angle sector about
/// it (`sectors` = clamp(samples/8, 4, 64) of them, sector ⌊pseudo_angle·sectors/4⌋ of
/// (p − c₀)·scale), the first sample point nearest to c₀ (MI's candidates) and the first
/// farthest (MC's), n for an empty sector; and 256 occupancy buckets (bucket
/// ⌊pseudo_angle·64⌋, MI's global proof). evaluate_roundness takes it once for both fitters;
/// each fitter takes its own otherwise. O(min(n, 512)) with a division per sample point.
struct SectorSample {
  WarmStart warm;
  std::size_t stride = 1, sectors = 0;
  std::vector<std::size_t> nearest, farthest;
  std::array<std::uint64_t, 4> occupied{};
};
SectorSample sector_sample(std::span<const Point2> points);

/// A power of two s with max(|px − cx|, |py − cy|)·s ∈ [0.5, 1) over the stride sample, so
/// that warm-start arithmetic on (p − c)·s neither overflows nor underflows for any input
/// magnitude (1 when the sample is degenerate). Scaling by s is exact.
double sample_scale(std::span<const Point2> points, Point2 c, std::size_t stride);

/// Monotone "diamond" pseudo-angle of the direction (dx, dy) ≠ 0, in [0, 4): one unit per
/// quadrant. Within a quadrant it is s/(c + s) of the true angle θ (c = |cos|, s = |sin|),
/// whose derivative 1/(c + s)² lies in [1/2, 1] per radian: a pseudo-angle gap g
/// corresponds to a true angular gap Δθ with g ≤ Δθ ≤ 2g (radians). No division by zero:
/// returns 0 for (0, 0). A few ulps of rounding (documented where it is used).
inline double pseudo_angle(double dx, double dy) {
  const double ax = dx < 0 ? -dx : dx;
  const double ay = dy < 0 ? -dy : dy;
  const double sum = ax + ay;
  if (sum == 0.0) return 0.0;
  const double t = ay / sum;  // in [0, 1]
  if (dx >= 0) return dy >= 0 ? t : 4.0 - t;  // quadrants I and IV
  return dy >= 0 ? 2.0 - t : 2.0 + t;         // quadrants II and III
}

/// An exact circle defined by 1 (radius 0), 2 (diametral) or 3 (circumscribed) input
/// points, with its rounded centre and radius and the bounds of the floating filter.
///
/// Exact representation (integers, no gcd): every coordinate of the supports is an
/// integer multiple of 2^e (e = the smallest exponent of their 53-bit mantissas), and
///   centre = (nx, ny)/den · 2^e,   R*² = r2num/den² · 2^(2e),   den > 0.
/// Integer arithmetic on a few 64-bit limbs (GMP mpz) costs well under a microsecond,
/// against several for canonicalised rationals.
struct ExactCircle {
  int support_size = 0;
  std::array<Point2, 3> support{};
  mpz_class nx, ny, den, r2num;
  /// The centre relative to the first support: (nx, ny) − support[0]·2^−e·den.
  mpz_class ox, oy;
  int exponent = 0;
  Point2 center_d;             ///< c̃: each coordinate within 1.25 ulp of the exact value
  double radius = 0.0;         ///< within ~1 ulp of the exact radius (R*)
  /// Filter units: lengths × scale (a power of two, 2^scale_exponent, with R*·scale ≈ 1),
  /// so that squares never leave the double range whatever the input magnitude.
  double scale = 1.0;
  int scale_exponent = 0;
  double radius_scaled = 0.0;        ///< r̃ = R*·scale within ~1 ulp
  double center_error_scaled = 0.0;  ///< δ·scale, δ ≥ |c̃ − c*| (rigorous)
  /// For D̃ = fl(X² + Y²), X = fl(px − c̃x)·scale, Y likewise (see scan_distances):
  ///   D̃ < inside_below  ⇒ |p − c*| < R* (strictly inside, proven);
  ///   D̃ > outside_above ⇒ |p − c*| > R* (strictly outside, proven);
  /// otherwise ask the exact predicate. Derivation in extremal_circle.cpp.
  double inside_below = -1.0;
  double outside_above = 0.0;
  bool filter_usable = false;  ///< false when the bounds are meaningless: all tests exact

  /// The second-stage filter (internal/precise_distance.h), built on first use: points in
  /// the first stage's ~1e-15 band are placed by double-double arithmetic, so only exact
  /// ties reach the exact predicate (perfect circles put every point in that band).
  const PreciseCircle& precise() const;

 private:
  mutable std::optional<PreciseCircle> precise_;
};

/// D̃ of one point, as computed by scan_distances.
inline double scaled_distance2(Point2 p, Point2 c, double scale) {
  const double dx = (p.x - c.x) * scale, dy = (p.y - c.y) * scale;
  return dx * dx + dy * dy;
}

/// The most extreme D̃ (largest when `farthest`, else smallest; NaN never taken) of the
/// points [lo, lo + count) about c, as scaled_distance2 computes it, and its index: among
/// equal extremes the lowest index (`last_on_tie` false) or the highest. count ≥ 1; with no
/// comparable value, ±∞ (never better than a D̃ strictly). Lane-wise over 8 points at a time
/// (AVX-512, AVX2 or the baseline).
void range_extreme(const Point2* points, std::size_t lo, std::size_t count, Point2 c,
                   double scale, bool farthest, bool last_on_tie, std::size_t& index,
                   double& value);

/// Local refinement of a round's supports without an O(n) pass (a warm-start helper:
/// correctness never depends on it). From input index i, looks along the input order
/// (cyclically, both ways) at the `window` neighbours each way and on beyond them while
/// the scaled squared distance D̃ from c keeps strictly increasing (kFarthest) or
/// decreasing (!kFarthest), at most `limit` steps a way, and returns the most extreme
/// point seen (i itself when none is more extreme). On a profile scanned in angular order
/// the supports of a circle fitted to a sparse candidate set sit a few indices off the
/// contacts of the full set (near a smooth extremum a small centre shift moves it along
/// the profile), or in a neighbouring valley of the same sector; the walk finds those
/// points, which would otherwise be the violators of the next full pass. The windows are
/// taken by range_extreme on their (at most two) contiguous ranges: the point a step-by-step
/// walk with strict comparisons would keep (the first extreme in walk order).
template <bool kFarthest>
std::size_t local_extreme(std::span<const Point2> points, std::size_t i, Point2 c,
                          double scale, std::size_t window, std::size_t limit) {
  if (points.size() < 2) return i;
  const std::size_t n = points.size();
  const auto better = [](double a, double b) { return kFarthest ? a > b : a < b; };
  const double d0 = scaled_distance2(points[i], c, scale);
  std::size_t best = i;
  double best_d = d0;
  window = std::min(window, limit);
  // Windows shorter than n (each point at most once) by ranges; a window wrapping onto
  // itself, or d0 NaN (nothing better), step by step.
  const bool by_ranges = window < n && d0 == d0;
  for (const bool forward : {true, false}) {
    const auto next = [&](std::size_t j) {
      return forward ? (j + 1 == n ? 0 : j + 1) : (j == 0 ? n - 1 : j - 1);
    };
    std::size_t j = i;
    double dj = d0;
    if (by_ranges && window > 0) {
      // The window in walk order: [i + 1, i + w] forward (then from 0 on a wrap), [i − w, i)
      // backward (then up to n on a wrap), a range's first extreme in walk order its lowest
      // index forward and its highest backward; each taken only when strictly better.
      std::size_t lo[2], count[2];
      int ranges = 1;
      if (forward) {
        const std::size_t first = i + 1 == n ? 0 : i + 1;
        lo[0] = first;
        count[0] = std::min(window, n - first);
        if (count[0] < window) {
          lo[1] = 0;
          count[1] = window - count[0];
          ranges = 2;
        }
      } else {
        count[0] = std::min(window, i);
        lo[0] = i - count[0];
        if (count[0] < window) {
          count[1] = window - count[0];
          lo[1] = n - count[1];
          ranges = 2;
        }
      }
      for (int r = 0; r < ranges; ++r) {
        if (count[r] == 0) continue;
        std::size_t k = 0;
        double v = 0.0;
        range_extreme(points.data(), lo[r], count[r], c, scale, kFarthest, !forward, k, v);
        if (better(v, best_d)) {
          best = k;
          best_d = v;
        }
      }
      j = forward ? (i + window) % n : (i + n - window) % n;
      dj = scaled_distance2(points[j], c, scale);
    } else {
      // The window: every neighbour, branch-free selects (noisy data: unpredictable).
      for (std::size_t step = 1; step <= window; ++step) {
        j = next(j);
        dj = scaled_distance2(points[j], c, scale);
        const bool b = better(dj, best_d);
        best = b ? j : best;
        best_d = b ? dj : best_d;
      }
    }
    // Beyond it: on while the distance keeps moving the same way.
    for (std::size_t step = window + 1; step <= limit; ++step) {
      const std::size_t k = next(j);
      const double dk = scaled_distance2(points[k], c, scale);
      if (!better(dk, dj)) break;
      j = k;
      dj = dk;
      if (better(dj, best_d)) {
        best = j;
        best_d = dj;
      }
    }
  }
  return best;
}

/// Exact comparison of the radii of two circles (−1, 0, +1).
int compare_radius(const ExactCircle& a, const ExactCircle& b);
/// Exact equality of the centres.
bool same_center(const ExactCircle& a, const ExactCircle& b);

ExactCircle exact_point_circle(Point2 a);
ExactCircle exact_diametral_circle(Point2 a, Point2 b);
/// Precondition: a, b, c not collinear (std::logic_error otherwise).
ExactCircle exact_circumcircle(Point2 a, Point2 b, Point2 c);

/// Exact side of p with respect to the circle: ON_BOUNDED_SIDE (strictly inside),
/// ON_BOUNDARY, ON_UNBOUNDED_SIDE — the double-double filter (circle.precise()), then
/// CGAL's filtered exact predicates on the support points for the ties. `gap`, when given,
/// receives the double-double |p − c*|²s² − R*²s² when that stage ran (a ranking key far
/// finer than the first stage's squared distances), and is left alone otherwise.
CGAL::Bounded_side exact_side(const ExactCircle& circle, Point2 p, double* gap = nullptr);

/// Exact sign of the dot product (a − o)·(b − o): +1, 0, −1. Used as the angle at o of the
/// triangle (a, o, b) (acute / right / obtuse) and as the side of o with respect to the
/// circle of diameter ab (−1 strictly inside, 0 on it, +1 strictly outside). A floating
/// evaluation with a rigorous error bound decides almost always; CGAL's exact Angle_2
/// otherwise. Derivation in extremal_circle.cpp.
int dot_sign(Point2 o, Point2 a, Point2 b);

/// Exact side of t with respect to the circle through p, q, r, whose (non-collinear)
/// orientation o is given: CGAL's statically filtered side_of_oriented_circle, re-signed
/// by the orientation (cheaper than side_of_bounded_circle, which has no static filter).
inline CGAL::Bounded_side side_of_circumcircle(const EPoint& p, const EPoint& q,
                                               const EPoint& r, CGAL::Orientation o,
                                               const EPoint& t) {
  const CGAL::Oriented_side s = CGAL::side_of_oriented_circle(p, q, r, t);
  if (s == CGAL::ON_ORIENTED_BOUNDARY) return CGAL::ON_BOUNDARY;
  return (s == CGAL::ON_POSITIVE_SIDE) == (o == CGAL::COUNTERCLOCKWISE)
             ? CGAL::ON_BOUNDED_SIDE
             : CGAL::ON_UNBOUNDED_SIDE;
}

/// R*² as a canonical GMP rational (for the rare exact comparisons with other rationals).
mpq_class exact_r2(const ExactCircle& circle);

/// Exact (R*² − |p − c*|²)·scale² rounded to double (within 1.25 ulp; sign exact): RON
/// deviations without cancellation, in the filter's scaled units.
double exact_power_gap(const ExactCircle& circle, Point2 p);

}  // namespace vcmm::geometry::internal
