#include "vcmm/geometry/roundness.h"

#include <span>

namespace vcmm::geometry {

RoundnessEvaluation evaluate_roundness(std::span<const Point2> points,
                                       const RoundnessRequest& request) {
  RoundnessEvaluation out;
  out.n_points = points.size();
  out.filter_cutoff_upr = request.filter_cutoff_upr;
  std::span<const Point2> profile = points;
  if (request.filter_cutoff_upr) {
    out.filtered_points = gaussian_filtered_profile(points, *request.filter_cutoff_upr).points;
    profile = out.filtered_points;
  }
  if (request.least_squares) out.least_squares = least_squares_circle(profile);
  if (request.minimum_zone)
    out.minimum_zone = minimum_zone_circle(profile, request.minimum_zone_options);
  if (request.maximum_inscribed) out.maximum_inscribed = maximum_inscribed_circle(profile);
  if (request.minimum_circumscribed)
    out.minimum_circumscribed = minimum_circumscribed_circle(profile);
  return out;
}

}  // namespace vcmm::geometry
