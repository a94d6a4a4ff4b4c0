// maximum_inscribed_from_extremes.cpp — RONt about the maximum-inscribed circle of a smooth
// closed profile computed exactly from a subset of its points
// (vcmm/geometry/maximum_inscribed_from_extremes.h: the argument; the passes:
// internal/profile_extremes.h; the exact circle and its filter: internal/extremal_circle.h).
#include "vcmm/geometry/maximum_inscribed_from_extremes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <vector>

#include "internal/extremal_circle.h"
#include "internal/profile_extremes.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/point.h"

namespace vcmm::geometry {
namespace {

constexpr const char* kCaller = "maximum_inscribed_ront_from_extremes";
using internal::kFirstBand;         // the subset policy: internal/profile_extremes.h
using internal::kSubsetNeighbours;
using internal::kSubsetRounds;
using internal::kUnitRoundoff;
using internal::kRangeBlock;
/// Every k-th point is in S, k = n/32 but at most 64: angular gaps ≤ 2π/32 (0.11 rad at
/// n = 3600), so the hull bound is ≲ 0.2 ρ, far below r_S/2 (header).
constexpr std::size_t kAnchors = 32, kMaxAnchorStep = 64;

/// The hull bound of the header for the points of S in index order, given by their unit
/// directions (cs, sn; unit to 1e-9) about the origin and their distances rho from it: true
/// when every circle centred in H \ H_S is provably smaller than r_S/2. False when they are
/// not in one angular order once around the origin with gaps below π/2 (then the caller fits
/// all points).
bool hull_bound_holds(std::span<const double> cs, std::span<const double> sn,
                      std::span<const double> rho, double r_max, double r_s) {
  // Unit vectors to 1e-9: a chord c between two of them bounds the angle Δ between them by
  // c(1 − 1e-8) ≤ Δ ≤ 1.12c for Δ ≤ π/2 (2 sin(Δ/2) ≥ Δ·2√2/π there, √2·π/4 < 1.12).
  double sense = 0.0, chord_sum = 0.0, worst = 0.0;
  const std::size_t m = cs.size();
  for (std::size_t i = 0; i < m; ++i) {
    const std::size_t a = i, b = (i + 1) % m;
    const double cross = cs[a] * sn[b] - sn[a] * cs[b];
    const double dot = cs[a] * cs[b] + sn[a] * sn[b];
    if (!(dot > 0.0) || cross == 0.0) return false;  // a gap ≥ π/2 or a repeated direction
    if (sense == 0.0) sense = cross;
    if ((cross > 0.0) != (sense > 0.0)) return false;  // not in one angular order
    const double ex = cs[a] - cs[b], ey = sn[a] - sn[b];
    const double chord = std::sqrt(ex * ex + ey * ey);
    chord_sum += chord;
    const double delta = 1.12 * chord;
    const double rho_min = std::min(rho[a], rho[b]);
    worst = std::max(worst, r_max * delta + r_max - rho_min * (1.0 - delta * delta / 8.0));
  }
  // Σ Δ is a multiple of 2π within [Σ c (1 − 1e-8), 1.12 Σ c]: once around iff that range
  // holds 2π and not 4π.
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  if (!(chord_sum * (1.0 - 1e-8) <= kTwoPi * (1.0 + 1e-12) && 1.12 * chord_sum < 2.0 * kTwoPi))
    return false;
  // Rounding of these few flops is ~1e-15 relative: a factor 2 of margin covers it.
  return worst < 0.5 * r_s;
}

/// RONt about the MI circle `circle` with farthest point f, as maximum_inscribed_circle
/// computes it (make_result there), bit for bit: (ρ_f² − r*²)/(ρ̃_f + r̃), numerator exact.
double inscribed_ront(const internal::ExactCircle& circle, Point2 f) {
  const double max_d2 = internal::scaled_distance2(f, circle.center_d, circle.scale);
  const double gap_s = -internal::exact_power_gap(circle, f);
  return gap_s > 0.0 ? std::ldexp(gap_s / (std::sqrt(max_d2) + circle.radius_scaled),
                                  -circle.scale_exponent)
                     : 0.0;
}

/// The MI circle of S (s.subset) as an exact circle, when S's MI is defined (not for a
/// degenerate or too sparse S), `hull_bound(r_S)` holds and the circle's floating filter is
/// usable; else nullopt (the caller fits all points).
template <class HullBound>
std::optional<internal::ExactCircle> subset_circle(const ExtremesScratch& s,
                                                   HullBound hull_bound) {
  MaximumInscribedCircle mi;
  try {
    mi = maximum_inscribed_circle(s.subset);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (!hull_bound(mi.radius)) return std::nullopt;
  internal::ExactCircle circle = internal::exact_circumcircle(
      s.subset[mi.contacts[0]], s.subset[mi.contacts[1]], s.subset[mi.contacts[2]]);
  if (!circle.filter_usable) return std::nullopt;
  return circle;
}

/// Directions and distances of S's points (sorted by index) for hull_bound_holds.
struct HullInput {
  std::vector<double> cs, sn, rho;
  void resize(std::size_t m) {
    cs.resize(m);
    sn.resize(m);
    rho.resize(m);
  }
};

/// The hull bound for a polar profile: its own directions (unit to 1e-9, else false) and radii.
bool polar_hull_bound_holds(const PolarProfile& p, std::vector<std::size_t>& sorted,
                            double r_max, double r_s, HullInput& h) {
  const PolarDirections& u = *p.directions;
  if (!(u.norm2_hi() <= 1.0 + 1e-9 && u.norm2_lo() >= 1.0 - 1e-9)) return false;
  std::sort(sorted.begin(), sorted.end());
  h.resize(sorted.size());
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    h.cs[i] = u.cos()[sorted[i]];
    h.sn[i] = u.sin()[sorted[i]];
    h.rho[i] = p.base_radius + p.deviation[sorted[i]];
  }
  return hull_bound_holds(h.cs, h.sn, h.rho, r_max, r_s);
}

}  // namespace

double maximum_inscribed_ront_from_extremes(const PolarProfile& p, ExtremesScratch& s) {
  const std::size_t n = p.size();
  const internal::ValueRange d = internal::deviation_ranges(p, s, kCaller);
  internal::clear_subset(n, s);
  internal::add_deviation_extremes(p, s, std::numeric_limits<double>::infinity(),
                                   d.lo + kFirstBand * (d.hi - d.lo), kSubsetNeighbours);
  const std::size_t step = std::clamp<std::size_t>(n / kAnchors, 1, kMaxAnchorStep);
  for (std::size_t j = 0; j < n; j += step) internal::add_with_neighbours(j, 0, n, s);
  // ρ_max: |p_j| ≤ (R₀ + d_j)|u_j|(1 + 3u); the directions are unit to 1e-9 (checked below).
  const double r_max = (p.base_radius + d.hi) * (1.0 + 1e-8);
  // The highest deviation's point: its squared distance bounds the farthest one's below.
  const std::size_t highest = internal::index_of_highest(p, s);
  s.fell_back = false;
  std::vector<std::size_t> sorted;
  HullInput hull;
  for (s.rounds = 1; s.rounds <= kSubsetRounds && s.subset_index.size() >= 8; ++s.rounds) {
    internal::collect_subset(p, s);
    const std::optional<internal::ExactCircle> fitted =
        subset_circle(s, [&](double r_s) {
          sorted = s.subset_index;
          return polar_hull_bound_holds(p, sorted, r_max, r_s, hull);
        });
    if (!fitted) break;
    const internal::ExactCircle& circle = *fitted;
    // Points with D̃ s² ≤ outside_above may be inside (below, unscaled: exact power of two);
    // points above the highest deviation's D̃ (less a margin) may be the farthest.
    const double s2 = circle.scale * circle.scale;
    const double below = circle.outside_above / s2;
    const Point2 c = circle.center_d;
    const double above = internal::polar_squared_distance(p, highest, c) * (1.0 - 64 * kUnitRoundoff);
    std::size_t added = 0, farthest = n;
    double far_d2 = -1.0;
    internal::distances_beyond(p, s, c, above, below, [&](std::size_t j, double x) {
      if (x > above && x > far_d2) {  // increasing j: the lowest index on ties
        far_d2 = x;
        farthest = j;
      }
      if (!(x < below) || s.member[j]) return;
      const Point2 q = polar_point(p, j);
      if (x * s2 < circle.inside_below ||
          internal::exact_side(circle, q) == CGAL::ON_BOUNDED_SIDE)
        added += internal::add_with_neighbours(j, kSubsetNeighbours, n, s);
    });
    if (added > 0) continue;
    if (farthest == n) break;  // cannot happen (highest is visited); all points decide
    s.center = c;
    return inscribed_ront(circle, polar_point(p, farthest));
  }
  s.fell_back = true;
  s.subset_index.resize(n);
  for (std::size_t j = 0; j < n; ++j) s.subset_index[j] = j;
  internal::collect_subset(p, s);
  const MaximumInscribedCircle mi = maximum_inscribed_circle(s.subset);
  s.center = mi.center;
  return mi.ron.ront;
}

double maximum_inscribed_ront_from_extremes(std::span<const Point2> points, Point2 origin,
                                            ExtremesScratch& s) {
  const std::size_t n = points.size();
  const std::optional<internal::ValueRange> range = internal::origin_distance_extremes(
      points, origin, s, "maximum_inscribed_ront_from_extremes (points)");
  double* d = s.distance2.data();
  s.fell_back = false;
  s.rounds = 0;
  if (range) {
    const double hi = range->hi, lo = range->lo;
    internal::add_value_extremes(s.distance2, s, std::numeric_limits<double>::infinity(),
                                 lo + kFirstBand * (hi - lo), kSubsetNeighbours);
    const std::size_t step = std::clamp<std::size_t>(n / kAnchors, 1, kMaxAnchorStep);
    for (std::size_t j = 0; j < n; j += step) internal::add_with_neighbours(j, 0, n, s);
    // ρ_max ≥ max |p_j − o|: √D̃ is within 3u of it.
    const double r_max = std::sqrt(hi) * (1.0 + 1e-8);
    std::vector<std::size_t> sorted;
    HullInput hull;
    for (s.rounds = 1; s.rounds <= kSubsetRounds && s.subset_index.size() >= 8; ++s.rounds) {
      internal::collect_subset(points, s);
      const std::optional<internal::ExactCircle> fitted = subset_circle(s, [&](double r_s) {
        // The hull bound with the directions and distances of S's points about the origin
        // (unit to a few ulps: far within the 1e-9 the bound allows).
        sorted = s.subset_index;
        std::sort(sorted.begin(), sorted.end());
        hull.resize(sorted.size());
        for (std::size_t i = 0; i < sorted.size(); ++i) {
          const double vx = points[sorted[i]].x - origin.x, vy = points[sorted[i]].y - origin.y;
          const double len = std::sqrt(vx * vx + vy * vy);
          hull.cs[i] = vx / len;
          hull.sn[i] = vy / len;
          hull.rho[i] = len;
        }
        return hull_bound_holds(hull.cs, hull.sn, hull.rho, r_max, r_s);
      });
      if (!fitted) break;
      const internal::ExactCircle& circle = *fitted;
      // D̃ about c for every point (vectorised, with per-block ranges): points with
      // D̃ s² ≤ outside_above may be inside; the farthest is the first holding the largest D̃.
      const double s2 = circle.scale * circle.scale;
      const double below = circle.outside_above / s2;
      const Point2 c = circle.center_d;
      internal::squared_distances(points, c, d, s);
      std::size_t added = 0;
      double far_d2 = -1.0;
      for (std::size_t b = 0; b < s.peak_hi.size(); ++b) far_d2 = std::max(far_d2, s.peak_hi[b]);
      for (std::size_t b = 0; b < s.valley_lo.size(); ++b) {
        if (!(s.valley_lo[b] < below)) continue;
        const std::size_t last = std::min(n, (b + 1) * kRangeBlock);
        for (std::size_t j = b * kRangeBlock; j < last; ++j) {
          if (!(d[j] < below) || s.member[j]) continue;
          if (d[j] * s2 < circle.inside_below ||
              internal::exact_side(circle, points[j]) == CGAL::ON_BOUNDED_SIDE)
            added += internal::add_with_neighbours(j, kSubsetNeighbours, n, s);
        }
      }
      if (added > 0) continue;
      std::size_t farthest = 0;
      while (d[farthest] != far_d2) ++farthest;  // the lowest index on ties
      s.center = c;
      return inscribed_ront(circle, points[farthest]);
    }
  }
  s.fell_back = true;
  const MaximumInscribedCircle mi = maximum_inscribed_circle(points);
  s.center = mi.center;
  return mi.ron.ront;
}

}  // namespace vcmm::geometry
