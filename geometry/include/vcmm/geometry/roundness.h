// vcmm/geometry/roundness.h — one call for a roundness evaluation: optional Gaussian filter,
// then the requested ISO 12181-2 reference circles with their RON parameters.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/minimum_circumscribed.h"
#include "vcmm/geometry/minimum_zone.h"
#include "vcmm/geometry/point.h"

namespace vcmm::geometry {

struct RoundnessRequest {
  bool least_squares = true;
  bool minimum_zone = true;
  bool maximum_inscribed = true;
  bool minimum_circumscribed = true;
  std::optional<double> filter_cutoff_upr;  ///< none: unfiltered
  MinimumZoneOptions minimum_zone_options;
};

struct RoundnessEvaluation {
  std::size_t n_points = 0;
  std::optional<double> filter_cutoff_upr;
  /// The filtered profile the circles were fitted to (empty when unfiltered); certificates
  /// refer to these points.
  std::vector<Point2> filtered_points;
  std::optional<LeastSquaresCircle> least_squares;
  std::optional<MinimumZoneCircle> minimum_zone;
  std::optional<MaximumInscribedCircle> maximum_inscribed;
  std::optional<MinimumCircumscribedCircle> minimum_circumscribed;
};

/// Filters (if asked) and fits the requested circles to the (filtered) profile. Contact
/// indices refer to the input order. Exceptions as the individual functions.
RoundnessEvaluation evaluate_roundness(std::span<const Point2> points,
                                       const RoundnessRequest& request);

}  // namespace vcmm::geometry
