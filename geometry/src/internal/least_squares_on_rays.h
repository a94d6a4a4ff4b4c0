// internal/least_squares_on_rays.h — the least-squares circle of points given on rays from a
// centre near their LS centre, in one Gauss-Newton step without square roots or divisions
// (least_squares.cpp, "Points on rays"). The filter uses it for the LS circle of its output,
// whose points it builds on the rays from the LS centre of its input. Not part of the API.
#pragma once

#include <cstddef>
#include <optional>

#include "vcmm/geometry/least_squares.h"

namespace vcmm::geometry::internal {

/// Points q_i = c + (R + w_i) u_i, i < n, with u_i = (ray_x_i, ray_y_i) · inv_length_i a unit
/// vector (to rounding) and |w_i| ≪ R. Returns the LS circle of the q_i (centre, radius,
/// contacts, ron; iterations = 1) when the Gauss-Newton step δ from c is at most 2⁻³⁰ of the
/// smallest R + w_i, where the step is exact to |δ|² / min(R + w) ≤ 2⁻⁶⁰ min(R + w) (see
/// least_squares.cpp); std::nullopt otherwise (the caller fits the points in full).
/// Precondition (not checked): n ≥ 3, every value finite, R > 0. O(n), two passes.
std::optional<LeastSquaresCircle> least_squares_circle_on_rays(
    Point2 center, double radius, const double* w, const double* ray_x, const double* ray_y,
    const double* inv_length, std::size_t n);

}  // namespace vcmm::geometry::internal
