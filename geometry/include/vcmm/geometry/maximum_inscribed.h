// vcmm/geometry/maximum_inscribed.h — the maximum-inscribed (MI) reference circle,
// ISO 12181-1 / MICI: the largest circle that the profile encloses.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "vcmm/geometry/certificate.h"
#include "vcmm/geometry/point.h"
#include "vcmm/geometry/roundness_parameters.h"

namespace vcmm::geometry {

struct MaximumInscribedCircle {
  Point2 center;        ///< few ulps from the exact rational centre (a Voronoi vertex)
  double radius = 0.0;  ///< few ulps from the exact value
  /// 3 contact indices whose closed triangle contains the exact centre. The centre lies on
  /// an edge only when 4 or more points share the circle (e.g. a square); another profile
  /// point on the circle then lies strictly beyond that edge, so the contacts still surround
  /// the centre (verify() checks this). With more than 3 points exactly on the circle
  /// (co-circular data) the fast path reports an acute triple among them, the one nearest
  /// to 0°, 120°, 240° from the lowest-index contact when that is fatter than its own.
  std::vector<std::size_t> contacts;
  RoundnessParameters ron;  ///< about (center, radius): RONv = 0, RONt = RONp
  Certificate certificate;
};

/// Largest circle with no profile point inside it and its centre inside the profile's
/// convex hull. The optimum is a nearest-point Voronoi vertex with its three contacts
/// around it. Fast path: a linearised program on inner candidates from an algebraic (Kåsa)
/// centre estimate, confirmed on all points, proven global by a region argument (with a
/// Delaunay triangulation of the few points near the centre where that argument needs it);
/// Delaunay-based exhaustive method as fallback. Where several centres share the largest
/// radius exactly, any one of them is returned (each is certified).
/// Preconditions: ≥ 3 finite points, not collinear (InvalidInput). Throws UndefinedResult
/// when the largest empty circle in the hull is not surrounded by its contacts (partial
/// arcs, too sparse a profile): the MI circle is then not defined by ISO 12181.
/// Complexity: O(n) for round profiles; O(n log n) in the fallback.
MaximumInscribedCircle maximum_inscribed_circle(std::span<const Point2> points);

}  // namespace vcmm::geometry
