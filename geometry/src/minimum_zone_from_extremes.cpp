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

#include <cmath>

#include "internal/extremal_circle.h"
#include "internal/profile_extremes.h"
#include "vcmm/geometry/minimum_zone.h"

namespace vcmm::geometry {
namespace {

constexpr const char* kCaller = "minimum_zone_ront_from_extremes";
using internal::kFirstBand;         // the subset policy: internal/profile_extremes.h
using internal::kSubsetNeighbours;
using internal::kSubsetRounds;
using internal::kUnitRoundoff;

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

}  // namespace vcmm::geometry
