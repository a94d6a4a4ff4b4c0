// vcmm/geometry/minimum_circumscribed.h — the minimum-circumscribed (MC) reference circle,
// ISO 12181-1 / MCCI: the smallest circle enclosing the profile.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "vcmm/geometry/certificate.h"
#include "vcmm/geometry/point.h"
#include "vcmm/geometry/roundness_parameters.h"

namespace vcmm::geometry {

struct MinimumCircumscribedCircle {
  Point2 center;        ///< few ulps from the exact rational centre
  double radius = 0.0;  ///< few ulps from the exact value
  /// 2 (diametral) or 3 contact indices; the exact centre lies in their closed hull.
  std::vector<std::size_t> contacts;
  RoundnessParameters ron;  ///< about (center, radius): RONp = 0, RONt = RONv
  Certificate certificate;  ///< always global (the problem is convex)
};

/// Smallest enclosing circle. Welzl / move-to-front with exact predicates on the support
/// points (no constructed circle is ever tested), run on per-sector candidates around an algebraic
/// (Kåsa) centre estimate and confirmed on all points (violators join and it repeats).
/// Preconditions: ≥ 2 finite points, not all identical (InvalidInput).
/// Complexity: expected O(n).
MinimumCircumscribedCircle minimum_circumscribed_circle(std::span<const Point2> points);

}  // namespace vcmm::geometry
