// vcmm/geometry/minimum_zone.h — the minimum-zone (MZ) reference circles, ISO 12181-1 / MZCI:
// two concentric circles enclosing the profile with the least radial
// separation R − r (Chebyshev / minimax annulus). RONt about MZ is R − r.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "vcmm/geometry/certificate.h"
#include "vcmm/geometry/point.h"
#include "vcmm/geometry/roundness_parameters.h"

namespace vcmm::geometry {

struct MinimumZoneCircle {
  Point2 center;             ///< nearest double (few ulps) to the exact rational centre
  double inner_radius = 0.0; ///< r, within a few ulps of the exact value
  double outer_radius = 0.0; ///< R, within a few ulps of the exact value
  /// Contact indices (0-based, into the input): two outer (on R) and two inner (on r),
  /// alternating in angle about the centre. For zero width (all points on one circle) both
  /// lists hold the same three points that define the circle. Among duplicated points the
  /// lowest index is reported.
  std::vector<std::size_t> outer_contacts;
  std::vector<std::size_t> inner_contacts;
  /// About the mean circle (R + r)/2: RONt = R − r (few ulps), RONp = RONv = (R − r)/2.
  RoundnessParameters ron;
  Certificate certificate;
};

enum class MinimumZoneMethod {
  automatic,  ///< exchange method warm-started at LS; overlay when it cannot certify
  exchange,   ///< fast path only (throws std::runtime_error if it cannot certify)
  overlay,    ///< nearest/farthest Voronoi overlay on the exact predicates, O(n·h)
};

struct MinimumZoneOptions {
  MinimumZoneMethod method = MinimumZoneMethod::automatic;
  /// Try to prove global optimality (region argument; costs little on round profiles).
  bool prove_global = true;
};

/// Minimum-zone circles of a profile (full circle, partial arc or sparse points).
/// Preconditions: ≥ 3 finite points, not all collinear (InvalidInput). Throws
/// UndefinedResult where no finite minimum exists (the zone width only tends to its
/// infimum as the radius grows without bound, e.g. nearly straight data).
/// Exactness: the contact set is decided with exact predicates; the centre is the exact
/// intersection of two perpendicular bisectors (a rational point) rounded once.
/// Complexity: O(n) for round profiles (LS warm start, O(n) containment passes, exact
/// arithmetic only for the deciding candidates); O(n·h) worst case in the overlay.
MinimumZoneCircle minimum_zone_circle(std::span<const Point2> points,
                                      const MinimumZoneOptions& options = {});

}  // namespace vcmm::geometry
