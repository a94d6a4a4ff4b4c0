// vcmm/geometry/least_squares.h — the least-squares (LS) reference circle, ISO 12181-1 / LSCI:
// the circle minimising the sum of squared radial (geometric) deviations.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "vcmm/geometry/point.h"
#include "vcmm/geometry/roundness_parameters.h"

namespace vcmm::geometry {

struct LeastSquaresCircle {
  Point2 center;
  double radius = 0.0;
  /// {index of the highest peak, index of the deepest valley} about this circle.
  std::vector<std::size_t> contacts;
  RoundnessParameters ron;  ///< about (center, radius)
  int iterations = 0;       ///< Gauss-Newton iterations used
};

/// Geometric least-squares circle: minimises Σ (|p_i − c| − R)² over (c, R), by
/// Gauss-Newton (R eliminated) on data shifted by their first point, started from the
/// algebraic (Kåsa) fit. Throws UndefinedResult when the data are too close to a straight
/// line for double precision (radius beyond ~1e8 times the extent).
/// Duplicated points count with their multiplicity.
/// Preconditions: ≥ 3 finite points, not all collinear, spanning 1e-50 … 1e50 mm (the range
/// in which its moments stay in double range) (InvalidInput).
/// Accuracy: reproduces NIST's Circle2d reference fits (60-digit) to ~1e-13 mm.
/// Complexity O(n) per iteration, typically 2 iterations on ring data (≤ 6 on NIST sets).
LeastSquaresCircle least_squares_circle(std::span<const Point2> points);

}  // namespace vcmm::geometry
