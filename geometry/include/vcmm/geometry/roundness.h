// vcmm/geometry/roundness.h — one call for a roundness evaluation: optional Gaussian filter,
// then the requested ISO 12181-2 reference circles with their RON parameters, each evaluated
// on its own: a circle that does not exist for the profile (e.g. MI of a partial arc) is
// reported as undefined with the reason, and the others are still given.
#pragma once

#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vcmm/geometry/angular_coverage.h"
#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/minimum_circumscribed.h"
#include "vcmm/geometry/minimum_zone.h"
#include "vcmm/geometry/point.h"

namespace vcmm::geometry {

/// The ISO 12181-1 reference circle a roundness value refers to (docs/notation.md).
enum class ReferenceCircle {
  minimum_zone,           ///< MZCI, "MZ"
  maximum_inscribed,      ///< MICI, "MI"
  least_squares,          ///< LSCI, "LS"
  minimum_circumscribed,  ///< MCCI, "MC"
};

/// "MZ", "MI", "LS", "MC" (the file and CLI spelling).
std::string_view to_string(ReferenceCircle circle);
/// Parses "MZ", "MI", "LS", "MC" (exact, upper case); nullopt otherwise.
std::optional<ReferenceCircle> reference_circle_from_string(std::string_view text);

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
  /// How it was filtered: fft or nonuniform (closed profile), open_profile (a partial arc:
  /// an angular gap wider than λc/2; gaussian_filtered_open_profile).
  std::optional<FilterPath> filter_path;
  /// Coverage of the (filtered) profile about the centre of the first defined circle (LS,
  /// MZ, MI, MC in this order): a partial arc when not closed. Left at its defaults (all 0,
  /// closed) when no requested circle is defined.
  AngularCoverage coverage;
  /// The requested circles that exist (an unrequested circle is always empty).
  std::optional<LeastSquaresCircle> least_squares;
  std::optional<MinimumZoneCircle> minimum_zone;
  std::optional<MaximumInscribedCircle> maximum_inscribed;
  std::optional<MinimumCircumscribedCircle> minimum_circumscribed;
  /// The requested circles that do not exist for this profile, with the reason (the message
  /// of the fitter's UndefinedResult).
  std::map<ReferenceCircle, std::string> undefined;
  /// Cautions on circles that exist but are not a roundness reference for this profile: MI
  /// and MC of an arc covering less than 180° ("not a roundness reference on an arc < 180°":
  /// the MC of a short arc is the circle on its chord, its MI is not enclosed by the data).
  std::map<ReferenceCircle, std::string> cautions;

  /// How many of the requested circles exist.
  std::size_t defined_count() const;
};

/// Filters (if asked) and fits each requested circle to the (filtered) profile, on its own:
/// an UndefinedResult of one circle is recorded in `undefined` and the others are still
/// evaluated (no exception for an undefined circle). With a filter, a closed profile takes the
/// closed filter and a partial arc (a gap wider than λc/2) the open-profile one. Contact
/// indices refer to the input order. Throws InvalidInput for input no circle can be fitted to
/// (as the fitters and the filters: too few, non-finite, identical or collinear points; an
/// arc with an inner gap wider than λc/2). O(n log n) plus the fitters.
RoundnessEvaluation evaluate_roundness(std::span<const Point2> points,
                                       const RoundnessRequest& request);

}  // namespace vcmm::geometry
