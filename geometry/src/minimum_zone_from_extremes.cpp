// minimum_zone_from_extremes.cpp — RONt about the minimum-zone circle of a smooth closed
// profile computed exactly from a subset of its points (vcmm/geometry/minimum_zone_from_extremes.h:
// the argument, the subset, the rounds; the passes: internal/profile_extremes.h).
//
// The containment test. The fit on S gives the centre c̃ (each coordinate the nearest double
// of the exact centre c*, so |c̃ − c*| ≤ δ = u(|c̃x| + |c̃y|)) and radii R̃, r̃ within a few ulps
// of R*, r*. For a point p, D̃ = fl(fl(px − c̃x)² + fl(py − c̃y)²) is within 4u of |p − c̃|²,
// which is within 2δ|p − c̃| + δ² of |p − c*|². So D̃ ≤ (R̃ − 2δ)²(1 − 64u) proves |p − c*| < R*
// and D̃ ≥ (r̃ + 2δ)²(1 + 64u) proves |p − c*| > r*, with ample room for the radii's ulps (64u
// ≈ 7e-15 relative). The same margins the other way prove a point outside; in between
// (within ~1e-14 relative of a circle: contacts, exact ties) the point joins S and the exact
// fit decides it.
#include "vcmm/geometry/minimum_zone_from_extremes.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "internal/extremal_circle.h"
#include "internal/profile_extremes.h"
#include "vcmm/geometry/minimum_zone.h"
#include "vcmm/geometry/point.h"

namespace vcmm::geometry {
namespace {

constexpr const char* kCaller = "minimum_zone_ront_from_extremes";
using internal::kFirstBand;         // the subset policy: internal/profile_extremes.h
using internal::kSubsetNeighbours;
using internal::kSubsetRounds;
using internal::kUnitRoundoff;
using internal::kRangeBlock;

}  // namespace

double minimum_zone_ront_from_extremes(const PolarProfile& p, ExtremesScratch& s) {
  const std::size_t n = p.size();
  const internal::ValueRange d = internal::deviation_ranges(p, s, kCaller);
  internal::clear_subset(n, s);
  const double band = kFirstBand * (d.hi - d.lo);
  internal::add_deviation_extremes(p, s, d.hi - band, d.lo + band, kSubsetNeighbours);
  s.fell_back = false;
  for (s.rounds = 1; s.rounds <= kSubsetRounds && s.subset_index.size() >= 8; ++s.rounds) {
    internal::collect_subset(p, s);
    const MinimumZoneCircle mz = minimum_zone_circle(s.subset);
    const Point2 c = mz.center;
    const double delta = kUnitRoundoff * (std::fabs(c.x) + std::fabs(c.y));
    const double outer_in = (mz.outer_radius - 2 * delta) * (mz.outer_radius - 2 * delta);
    const double inner_out = (mz.inner_radius + 2 * delta) * (mz.inner_radius + 2 * delta);
    // Points outside S not proven inside the annulus join S (violators and the undecided).
    std::size_t added = 0;
    const internal::ValueRange r2 = internal::distances_beyond(
        p, s, c, outer_in * (1.0 - 64 * kUnitRoundoff), inner_out * (1.0 + 64 * kUnitRoundoff),
        [&](std::size_t j, double) {
          if (!s.member[j]) added += internal::add_with_neighbours(j, kSubsetNeighbours, n, s);
        });
    if (added == 0) {
      s.center = c;
      return std::sqrt(r2.hi) - std::sqrt(r2.lo);
    }
  }
  // All points (S too small to fit, or not settled after kSubsetRounds fits).
  s.fell_back = true;
  s.subset_index.resize(n);
  for (std::size_t j = 0; j < n; ++j) s.subset_index[j] = j;
  internal::collect_subset(p, s);
  s.center = minimum_zone_circle(s.subset).center;
  const internal::ValueRange r2 =
      internal::distances_beyond(p, s, s.center, 0.0, 0.0, [](std::size_t, double) {});
  return std::sqrt(r2.hi) - std::sqrt(r2.lo);
}

double minimum_zone_ront_from_extremes(std::span<const Point2> points, Point2 origin,
                                       ExtremesScratch& s) {
  const std::size_t n = points.size();
  const std::optional<internal::ValueRange> range = internal::origin_distance_extremes(
      points, origin, s, "minimum_zone_ront_from_extremes (points)");
  s.fell_back = false;
  s.rounds = 0;
  if (range) {
    const double hi = range->hi, lo = range->lo;
    const double band = kFirstBand * (hi - lo);
    internal::add_value_extremes(s.distance2, s, hi - band, lo + band, kSubsetNeighbours);
    for (s.rounds = 1; s.rounds <= kSubsetRounds && s.subset_index.size() >= 8; ++s.rounds) {
      internal::collect_subset(points, s);
      MinimumZoneCircle mz;
      try {
        mz = minimum_zone_circle(s.subset);
      } catch (const std::exception&) {
        break;  // S collinear or nearly straight: all points decide (and name the problem)
      }
      // The containment test of the polar overload (file comment), on every point: one
      // vectorised pass with each block's range; only the blocks reaching beyond the proven
      // band (those of S's contacts, and violators) are looked at point by point.
      const Point2 c = mz.center;
      const double delta = kUnitRoundoff * (std::fabs(c.x) + std::fabs(c.y));
      const double outer_in = (mz.outer_radius - 2 * delta) * (mz.outer_radius - 2 * delta);
      const double inner_out = (mz.inner_radius + 2 * delta) * (mz.inner_radius + 2 * delta);
      const double above = outer_in * (1.0 - 64 * kUnitRoundoff);
      const double below = inner_out * (1.0 + 64 * kUnitRoundoff);
      internal::squared_distances(points, c, s.distance2.data(), s);
      std::size_t added = 0;
      for (std::size_t b = 0; b < s.peak_hi.size(); ++b) {
        if (!(s.peak_hi[b] > above) && !(s.valley_lo[b] < below)) continue;
        const std::size_t last = std::min(n, (b + 1) * kRangeBlock);
        for (std::size_t j = b * kRangeBlock; j < last; ++j) {
          const double v = s.distance2[j];
          if ((v > above || v < below) && !s.member[j])
            added += internal::add_with_neighbours(j, kSubsetNeighbours, n, s);
        }
      }
      if (added == 0) {
        s.center = c;
        return mz.ron.ront;
      }
    }
  }
  // All points (not all finite squares, S too small or degenerate, or not settled).
  s.fell_back = true;
  const MinimumZoneCircle mz = minimum_zone_circle(points);
  s.center = mz.center;
  return mz.ron.ront;
}

}  // namespace vcmm::geometry
