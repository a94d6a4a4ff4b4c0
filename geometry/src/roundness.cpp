// roundness.cpp — one roundness evaluation: optional Gaussian filter, then the requested
// reference circles on the (filtered) profile.
//
// Each public fitter validates its input (validate_profile, O(n)). Here the profile the
// circles are fitted to is validated once: by the first requested fitter's public entry
// point (so every failure is reported exactly as before, by the function that would have
// thrown first), the others run on the same, already validated points through their
// internal twins (internal/prevalidated.h). LS, MZ and MI share one precondition (≥ 3
// finite points, not all collinear); MC's (≥ 2, not all identical) is weaker, so whichever
// comes first covers the rest. The filter validates the raw profile and builds the filtered
// one from it.
#include "vcmm/geometry/roundness.h"

#include <span>

#include "internal/prevalidated.h"

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
  bool validated = false;  // by a fitter with the (stricter) LS/MZ/MI precondition
  if (request.least_squares) {
    out.least_squares = least_squares_circle(profile);
    validated = true;
  }
  if (request.minimum_zone) {
    out.minimum_zone =
        validated ? internal::fit_minimum_zone_circle(profile, request.minimum_zone_options)
                  : minimum_zone_circle(profile, request.minimum_zone_options);
    validated = true;
  }
  if (request.maximum_inscribed) {
    out.maximum_inscribed = validated ? internal::fit_maximum_inscribed_circle(profile)
                                      : maximum_inscribed_circle(profile);
    validated = true;
  }
  if (request.minimum_circumscribed) {
    out.minimum_circumscribed = validated ? internal::fit_minimum_circumscribed_circle(profile)
                                          : minimum_circumscribed_circle(profile);
  }
  return out;
}

}  // namespace vcmm::geometry
