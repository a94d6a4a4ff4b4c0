// vcmm/geometry/roundness_parameters.h — the ISO 12181-1 roundness parameters of a profile
// about a given reference circle.
#pragma once

#include <span>

#include "vcmm/geometry/point.h"

namespace vcmm::geometry {

/// Roundness parameters (ISO 12181-1:2011) of a profile about a reference circle with
/// centre c and radius R_ref. With d_i = |p_i − c| − R_ref the local roundness deviation:
///   RONp = max(0, max_i d_i)        peak-to-reference
///   RONv = max(0, −min_i d_i)       reference-to-valley (a depth, reported positive)
///   RONt = max_i d_i − min_i d_i    peak-to-valley (independent of R_ref)
///   RONq = sqrt(mean_i d_i²)        root mean square
/// Lengths in the input's unit.
struct RoundnessParameters {
  double ront = 0.0;
  double ronp = 0.0;
  double ronv = 0.0;
  double ronq = 0.0;
};

/// Evaluates RoundnessParameters in double precision on coordinates taken relative to the
/// centre (so far-from-origin data loses nothing beyond the rounding of |p − c|).
/// Preconditions: points validated by the caller, finite centre and radius (InvalidInput).
/// Complexity O(n).
RoundnessParameters roundness_parameters(std::span<const Point2> points, Point2 center,
                                         double reference_radius);

}  // namespace vcmm::geometry
