// internal/minimum_zone_overlay.h — the general exact minimum-zone method: overlay of the
// nearest-point Voronoi diagram (all points) and the farthest-point Voronoi diagram (convex
// hull vertices), decided with exact predicates. Global optimum; the fallback of the fast
// path and an oracle in the tests.
#pragma once

#include <span>

#include "vcmm/geometry/minimum_zone.h"

namespace vcmm::geometry::internal {

/// Globally optimal MZ circles (certificate.optimality = global). Preconditions as
/// minimum_zone_circle (validated by the caller). Throws UndefinedResult when the infimum is
/// not attained (nearly straight data). Complexity O(n log n + n·h) worst case.
MinimumZoneCircle minimum_zone_overlay(std::span<const Point2> points);

}  // namespace vcmm::geometry::internal
