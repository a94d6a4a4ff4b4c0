// maximum_inscribed_from_extremes.cpp — RONt about the maximum-inscribed circle of a smooth
// closed profile computed exactly from a subset of its points
// (vcmm/geometry/maximum_inscribed_from_extremes.h: the argument; the passes:
// internal/profile_extremes.h; the exact circle and its filter: internal/extremal_circle.h).
#include "vcmm/geometry/maximum_inscribed_from_extremes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "internal/extremal_circle.h"
#include "internal/profile_extremes.h"
#include "vcmm/geometry/maximum_inscribed.h"

namespace vcmm::geometry {
namespace {

constexpr const char* kCaller = "maximum_inscribed_ront_from_extremes";
using internal::kFirstBand;         // the subset policy: internal/profile_extremes.h
using internal::kSubsetNeighbours;
using internal::kSubsetRounds;
using internal::kUnitRoundoff;
/// Every k-th point is in S, k = n/32 but at most 64: angular gaps ≤ 2π/32 (0.11 rad at
/// n = 3600), so the hull bound is ≲ 0.2 ρ, far below r_S/2 (header).
constexpr std::size_t kAnchors = 32, kMaxAnchorStep = 64;

/// The hull bound of the header for S sorted by index: true when every circle centred in
/// H \ H_S is provably smaller than r_S/2. Needs unit directions (to 1e-9) in angular order
/// once around the origin; false otherwise (then the caller fits all points).
bool hull_bound_holds(const PolarProfile& p, std::vector<std::size_t>& sorted, double r_max,
                      double r_s) {
  const PolarDirections& u = *p.directions;
  if (!(u.norm2_hi() <= 1.0 + 1e-9 && u.norm2_lo() >= 1.0 - 1e-9)) return false;
  std::sort(sorted.begin(), sorted.end());
  const auto cs = u.cos(), sn = u.sin();
  // Unit vectors to 1e-9: a chord c between two of them bounds the angle Δ between them by
  // c(1 − 1e-8) ≤ Δ ≤ 1.12c for Δ ≤ π/2 (2 sin(Δ/2) ≥ Δ·2√2/π there, √2·π/4 < 1.12).
  double sense = 0.0, chord_sum = 0.0, worst = 0.0;
  const std::size_t m = sorted.size();
  for (std::size_t i = 0; i < m; ++i) {
    const std::size_t a = sorted[i], b = sorted[(i + 1) % m];
    const double cross = cs[a] * sn[b] - sn[a] * cs[b];
    const double dot = cs[a] * cs[b] + sn[a] * sn[b];
    if (!(dot > 0.0) || cross == 0.0) return false;  // a gap ≥ π/2 or a repeated direction
    if (sense == 0.0) sense = cross;
    if ((cross > 0.0) != (sense > 0.0)) return false;  // not in one angular order
    const double ex = cs[a] - cs[b], ey = sn[a] - sn[b];
    const double chord = std::sqrt(ex * ex + ey * ey);
    chord_sum += chord;
    const double delta = 1.12 * chord;
    const double rho_min = std::min(p.base_radius + p.deviation[a], p.base_radius + p.deviation[b]);
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
  for (s.rounds = 1; s.rounds <= kSubsetRounds && s.subset_index.size() >= 8; ++s.rounds) {
    internal::collect_subset(p, s);
    MaximumInscribedCircle mi;
    try {
      mi = maximum_inscribed_circle(s.subset);
    } catch (const UndefinedResult&) {
      break;  // S's MI is not defined (too sparse a subset): all points decide
    }
    sorted = s.subset_index;
    if (!hull_bound_holds(p, sorted, r_max, mi.radius)) break;
    const internal::ExactCircle circle = internal::exact_circumcircle(
        s.subset[mi.contacts[0]], s.subset[mi.contacts[1]], s.subset[mi.contacts[2]]);
    if (!circle.filter_usable) break;
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
    // RONt as maximum_inscribed_circle computes it (make_result there), bit for bit.
    s.center = c;
    const Point2 f = polar_point(p, farthest);
    const double max_d2 = internal::scaled_distance2(f, c, circle.scale);
    const double gap_s = -internal::exact_power_gap(circle, f);
    return gap_s > 0.0 ? std::ldexp(gap_s / (std::sqrt(max_d2) + circle.radius_scaled),
                                    -circle.scale_exponent)
                       : 0.0;
  }
  s.fell_back = true;
  s.subset_index.resize(n);
  for (std::size_t j = 0; j < n; ++j) s.subset_index[j] = j;
  internal::collect_subset(p, s);
  const MaximumInscribedCircle mi = maximum_inscribed_circle(s.subset);
  s.center = mi.center;
  return mi.ron.ront;
}

}  // namespace vcmm::geometry
