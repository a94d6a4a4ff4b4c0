// vcmm/geometry/angular_coverage.h — how much of the circle a profile covers: the directions
// of its points about a centre, the largest angular gap between neighbours, and whether the
// profile is closed or a partial arc (docs/method.md, "Partial arcs").
#pragma once

#include <cstddef>
#include <span>

#include "vcmm/geometry/point.h"

namespace vcmm::geometry {

struct AngularCoverage {
  /// 2π minus the largest gap: the angle the profile spans (rad, in (0, 2π)).
  double covered_rad = 0.0;
  /// The largest angle between directions that are neighbours in angular order, the wrap from
  /// the last direction to the first included (rad).
  double largest_gap_rad = 0.0;
  /// Direction (rad, (−π, π], counter-clockwise from +x) where the largest gap starts; the
  /// profile runs from gap_end_rad = gap_start_rad + largest_gap_rad round to gap_start_rad.
  double gap_start_rad = 0.0;
  /// Indices of the points on either side of the largest gap (input order).
  std::size_t gap_start_index = 0, gap_end_index = 0;
  /// Closed: the largest gap is at most 3 equiangular steps (3 · 2π/n) — a full profile with
  /// uneven spacing or a few missing points; otherwise a partial arc.
  bool closed = true;
};

/// The coverage of `points` about `center` (e.g. the LS centre); points at the centre have no
/// direction and are left out. Preconditions (InvalidInput): finite points and centre, ≥ 2
/// points away from the centre. O(n): the largest gap by pigeonhole buckets, no sort; a scan
/// given in angular order (either sense) takes atan2 only for the few steps that can be the
/// largest gap, with the same result bit for bit (~5 µs at n = 3 600, angular_coverage.cpp).
AngularCoverage angular_coverage(std::span<const Point2> points, Point2 center);

}  // namespace vcmm::geometry
