// roundness.cpp — one roundness evaluation: optional Gaussian filter, then the requested
// reference circles on the (filtered) profile.
//
// Each public fitter validates its input (validate_profile, O(n)). Here the profile the
// circles are fitted to is validated once, under the name of the first requested fitter,
// and the circles are fitted through their internal twins (internal/prevalidated.h). LS,
// MZ and MI share one precondition (≥ 3 finite points, not all collinear); MC's (≥ 2, not
// all identical) is weaker, so whichever comes first covers the rest. The filter
// validates the raw profile and builds the filtered one from it; the closed filter also
// returns the LS circle of its output (one Gauss-Newton step from the raw LS centre, as
// validation's ring evaluation takes it: the full fit's circle to ~1 ulp of the
// coordinates, gaussian_filter.h), so LS is not fitted a second time. An UndefinedResult of
// one circle (MI of an arc, MZ of nearly straight data) is recorded, not thrown: the other
// circles still come out.
#include "vcmm/geometry/roundness.h"

#include <cmath>
#include <span>

#include "internal/angular_walk.h"
#include "internal/extremal_circle.h"
#include "internal/prevalidated.h"

namespace vcmm::geometry {
namespace {

constexpr double kHalfTurn = 3.14159265358979323846;

/// Runs `fit`; an UndefinedResult is recorded under `circle` instead of thrown.
template <class Fit>
void fit_or_record(RoundnessEvaluation& out, ReferenceCircle circle, Fit fit) {
  try {
    fit();
  } catch (const UndefinedResult& e) {
    out.undefined[circle] = e.what();
  }
}

}  // namespace

std::string_view to_string(ReferenceCircle circle) {
  switch (circle) {
    case ReferenceCircle::minimum_zone: return "MZ";
    case ReferenceCircle::maximum_inscribed: return "MI";
    case ReferenceCircle::least_squares: return "LS";
    case ReferenceCircle::minimum_circumscribed: return "MC";
  }
  return "?";
}

std::optional<ReferenceCircle> reference_circle_from_string(std::string_view text) {
  if (text == "MZ") return ReferenceCircle::minimum_zone;
  if (text == "MI") return ReferenceCircle::maximum_inscribed;
  if (text == "LS") return ReferenceCircle::least_squares;
  if (text == "MC") return ReferenceCircle::minimum_circumscribed;
  return std::nullopt;
}

std::size_t RoundnessEvaluation::defined_count() const {
  return (least_squares ? 1u : 0u) + (minimum_zone ? 1u : 0u) + (maximum_inscribed ? 1u : 0u) +
         (minimum_circumscribed ? 1u : 0u);
}

RoundnessEvaluation evaluate_roundness(std::span<const Point2> points,
                                       const RoundnessRequest& request) {
  RoundnessEvaluation out;
  out.n_points = points.size();
  out.filter_cutoff_upr = request.filter_cutoff_upr;
  std::span<const Point2> profile = points;
  std::optional<LeastSquaresCircle> filtered_ls;  // of the closed filter's output, by the filter
  if (request.filter_cutoff_upr) {
    // A closed profile takes the closed filter; an arc (a gap wider than λc/2 = π/f_c, which
    // the closed filter refuses) the open-profile filter.
    const double cutoff = *request.filter_cutoff_upr;
    // validate_profile(points, 8, "gaussian_filtered_profile"), its finiteness part from the
    // moments of the LS fit's first pass.
    const LeastSquaresCircle raw_ls =
        internal::fit_least_squares_circle_checked(points, {8, "gaussian_filtered_profile"});
    LeastSquaresCircle* ls_out = request.least_squares ? &filtered_ls.emplace() : nullptr;
    FilteredProfile f;
    // The closed filter about the LS circle just fitted (the same fit it would repeat); it
    // builds its output on the rays from that centre and so gives the output's LS circle in
    // one Gauss-Newton step (gaussian_filter.h; the full fit where that step is not exact).
    // Closed or not: when no FFT-path profile can have a gap beyond λc/2 (its rays are each
    // less than half a step off an equiangular grid, so neighbours are less than 2 steps,
    // 4π/(n − 1), apart: below π/f_c with a margin far above rounding), the closed filter
    // decides it itself — its nonuniform path sorts the same angles angular_coverage would;
    // otherwise (f_c near n/4 or above) the coverage is taken first, as the filter cannot tell.
    const auto n = static_cast<double>(points.size());
    bool closed = false;
    if (n - 1.0 > 4.0 * cutoff * (1.0 + 1e-6)) {
      closed = internal::filter_closed_profile_if_closed(points, cutoff, raw_ls, f, ls_out);
    } else {
      const double max_gap = kHalfTurn / cutoff;
      closed = internal::has_angular_steps_below(points, raw_ls.center, max_gap) ||
               !(angular_coverage(points, raw_ls.center).largest_gap_rad > max_gap);
      if (closed) gaussian_filtered_profile(points, cutoff, raw_ls, f, ls_out);
    }
    if (!closed) {
      f = gaussian_filtered_open_profile(points, cutoff);
      filtered_ls.reset();
    }
    out.filter_path = f.path;
    out.filtered_points = std::move(f.points);
    profile = out.filtered_points;
  }
  // Validated once, by the first requested fitter's public entry point (so bad input is
  // reported as before, by the function that would have thrown first); the others run on the
  // same points through their internal twins. UndefinedResult is recorded per circle.
  bool validated = false;  // by a fitter with the (stricter) LS/MZ/MI precondition
  if (request.least_squares) {
    if (filtered_ls) {
      validate_profile(profile, 3, "least_squares_circle");
      out.least_squares = std::move(filtered_ls);
    } else {
      out.least_squares = least_squares_circle(profile);
    }
    validated = true;
  }
  if (request.minimum_zone) {
    if (!validated) validate_profile(profile, 3, "minimum_zone_circle");
    validated = true;
    fit_or_record(out, ReferenceCircle::minimum_zone, [&] {
      out.minimum_zone = internal::fit_minimum_zone_circle(profile, request.minimum_zone_options);
    });
  }
  // MI and MC start from the same stride sample (internal::sector_sample): taken once.
  std::optional<internal::SectorSample> sample;
  const auto shared_sample = [&]() -> const internal::SectorSample* {
    if (!(request.maximum_inscribed && request.minimum_circumscribed)) return nullptr;
    if (!sample) sample = internal::sector_sample(profile);
    return &*sample;
  };
  if (request.maximum_inscribed) {
    if (!validated) validate_profile(profile, 3, "maximum_inscribed_circle");
    validated = true;
    fit_or_record(out, ReferenceCircle::maximum_inscribed, [&] {
      out.maximum_inscribed = internal::fit_maximum_inscribed_circle(profile, shared_sample());
    });
  }
  if (request.minimum_circumscribed) {
    if (!validated) validate_profile(profile, 2, "minimum_circumscribed_circle", false);
    fit_or_record(out, ReferenceCircle::minimum_circumscribed, [&] {
      out.minimum_circumscribed =
          internal::fit_minimum_circumscribed_circle(profile, shared_sample());
    });
  }
  // Coverage about the centre of the first circle found (the filtered points lie on the rays
  // of the input points from the LS centre: the directions barely differ between centres).
  std::optional<Point2> center;
  if (out.least_squares) center = out.least_squares->center;
  else if (out.minimum_zone) center = out.minimum_zone->center;
  else if (out.maximum_inscribed) center = out.maximum_inscribed->center;
  else if (out.minimum_circumscribed) center = out.minimum_circumscribed->center;
  // No requested circle defined (only MI asked of an arc): the coverage still tells the user
  // why, so take it about the LS centre (issue 12: it read "0.00°, closed profile").
  if (!center) {
    try {
      center = internal::fit_least_squares_circle(profile).center;
    } catch (const std::exception&) {  // nearly straight data: no centre, no coverage
    }
  }
  if (center) out.coverage = angular_coverage(profile, *center);
  if (out.coverage.covered_rad < kHalfTurn) {
    const std::string caution = "not a roundness reference on an arc < 180°";
    if (out.maximum_inscribed) out.cautions[ReferenceCircle::maximum_inscribed] = caution;
    if (out.minimum_circumscribed)
      out.cautions[ReferenceCircle::minimum_circumscribed] = caution;
  }
  return out;
}

}  // namespace vcmm::geometry
