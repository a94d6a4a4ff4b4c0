// internal/angular_walk.h — the cheap test behind angular_coverage's fast path, for callers
// inside vcmm::geometry that only need to know that a profile has no wide gap.
#pragma once

#include <span>

#include "vcmm/geometry/point.h"

namespace vcmm::geometry::internal {

/// True when the points, walked in input order as a closed polygon, go once round `center`
/// turning the same way by a certain angle at every step, and every step is shorter than
/// `limit_rad` (clamped to π/4; the comparison keeps a relative margin of 1e-6): then the
/// angular order is the input order and angular_coverage(points, center).largest_gap_rad <
/// limit_rad. False decides nothing. One SIMD pass over the points, no atan2
/// (angular_coverage.cpp).
bool has_angular_steps_below(std::span<const Point2> points, Point2 center, double limit_rad);

}  // namespace vcmm::geometry::internal
