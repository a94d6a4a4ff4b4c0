// internal/maximum_inscribed_detail.h — the maximum-inscribed fallback on its own, for the
// tests that cross-check the fast path against it (not part of the public API).
#pragma once

#include <span>

#include "vcmm/geometry/maximum_inscribed.h"

namespace vcmm::geometry::internal {

/// The exhaustive method of maximum_inscribed.cpp (Delaunay triangulation of all points,
/// hull-boundary walk), whatever the fast path would have done. Preconditions as
/// maximum_inscribed_circle (not checked). O(n log n).
MaximumInscribedCircle maximum_inscribed_exhaustive(std::span<const Point2> points);

}  // namespace vcmm::geometry::internal
