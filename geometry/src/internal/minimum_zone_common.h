// internal/minimum_zone_common.h — pieces shared by the two minimum-zone methods (the fast
// exchange path in minimum_zone.cpp and the Voronoi-overlay method in
// minimum_zone_overlay.cpp). Not part of the public API.
#pragma once

#include <array>
#include <cstddef>
#include <span>

#include "vcmm/geometry/minimum_zone.h"

namespace vcmm::geometry::internal {

/// Builds the public result from a 2+2 contact quadruple (indices into `points`): the exact
/// centre (intersection of the perpendicular bisectors of outer[0]–outer[1] and
/// inner[0]–inner[1], in exact rationals), radii and RONt within a few ulps of their exact
/// values, RONp/RONv/RONq about the mean circle, contacts normalised to the lowest index among
/// duplicated points. `certificate` is stored as given. Precondition (checked, throws
/// std::logic_error): the bisectors intersect in one point, and r < R there.
MinimumZoneCircle make_minimum_zone_result(std::span<const Point2> points,
                                           std::array<std::size_t, 2> outer,
                                           std::array<std::size_t, 2> inner,
                                           Certificate certificate);

/// Zero-width result: all points lie exactly on the circle through points a, b, c.
MinimumZoneCircle make_cocircular_result(std::span<const Point2> points, std::size_t a,
                                         std::size_t b, std::size_t c);

}  // namespace vcmm::geometry::internal
