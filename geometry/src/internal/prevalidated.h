// internal/prevalidated.h — the fitters without the public boundary's input check, for
// callers inside vcmm::geometry that have validated the same points already (the filter,
// evaluate_roundness): one O(n) validation per evaluation instead of one per entry point.
// Each equals its public namesake on input that passes the namesake's validate_profile
// call. Not part of the public API.
#pragma once

#include <limits>
#include <span>

#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/minimum_circumscribed.h"
#include "vcmm/geometry/minimum_zone.h"
#include "vcmm/geometry/roundness_parameters.h"

namespace vcmm::geometry::internal {

/// The checks of validate_profile(points, min_points, caller, require_non_collinear) after
/// the count and the finiteness of every coordinate (point.cpp): at least two distinct
/// points, and (if asked) not all collinear, with the same messages. For a caller that
/// establishes the count and the finiteness itself (least_squares_circle: from the moments of
/// its first pass). Precondition (not checked): every coordinate finite.
void validate_profile_shape(std::span<const Point2> points, std::size_t min_points,
                            const char* caller, bool require_non_collinear);

/// least_squares_circle(points) without validate_profile. Precondition (not checked): the
/// points passed validate_profile(points, 3, …) — ≥ 3 finite points, not all collinear.
LeastSquaresCircle fit_least_squares_circle(std::span<const Point2> points);

/// The input check of a caller that fits the LS circle first: validate_profile(points,
/// min_points, caller) (min_points ≥ 3).
struct ProfileCheck {
  std::size_t min_points = 3;
  const char* caller = "least_squares_circle";
};

/// least_squares_circle(points) with validate_profile(points, check.min_points, check.caller)
/// instead of its own check — the same refusals, in the same order, with the caller's name;
/// the finiteness of every coordinate decided from the moments of the fit's first pass (no
/// pass of its own). For evaluate_roundness, whose filter fits the raw profile first.
LeastSquaresCircle fit_least_squares_circle_checked(std::span<const Point2> points,
                                                    const ProfileCheck& check);

/// minimum_zone_circle(points, options) without validate_profile; precondition as above.
MinimumZoneCircle fit_minimum_zone_circle(std::span<const Point2> points,
                                          const MinimumZoneOptions& options);

struct SectorSample;  // internal/extremal_circle.h

/// maximum_inscribed_circle(points) without validate_profile; precondition as above.
/// `sample`: internal::sector_sample(points) when the caller has it (evaluate_roundness
/// takes it once for MI and MC), else taken here.
MaximumInscribedCircle fit_maximum_inscribed_circle(std::span<const Point2> points,
                                                    const SectorSample* sample = nullptr);

/// minimum_circumscribed_circle(points) without validate_profile. Precondition (not
/// checked): validate_profile(points, 2, …, false) — ≥ 2 finite points, not all identical.
/// `sample` as for fit_maximum_inscribed_circle.
MinimumCircumscribedCircle fit_minimum_circumscribed_circle(std::span<const Point2> points,
                                                            const SectorSample* sample = nullptr);

/// roundness_parameters(points, center, reference_radius) without its checks.
/// deviation_bound: the largest |r_i − R| expected (e.g. the circle's RONt), which picks the
/// degree of the near-circle series (roundness_parameters.cpp; a wrong or unknown (NaN) bound
/// costs time, never accuracy). Precondition (not checked): ≥ 1 finite point, finite centre
/// and radius.
RoundnessParameters roundness_parameters_of_valid(
    std::span<const Point2> points, Point2 center, double reference_radius,
    double deviation_bound = std::numeric_limits<double>::quiet_NaN());

struct RonqSums;  // internal/distance_scan.h

/// The power of two by which roundness_parameters scales the deviations it sums for RONq
/// about (center, reference_radius): the RonqSums input of a scan that takes them.
double ronq_inv_scale(std::span<const Point2> points, Point2 center, double reference_radius);

/// roundness_parameters_of_valid(points, center, reference_radius, deviation_bound).ronq,
/// bit for bit: from `sums` (taken in a scan's pass about the same centre, radius and
/// scale) when they are the sums it would take — the series of degree 3 and every point in
/// its range — otherwise by that call.
double ronq_of_valid(std::span<const Point2> points, Point2 center, double reference_radius,
                     double deviation_bound, const RonqSums& sums);

/// gaussian_filtered_profile(points, cutoff_upr, least_squares, out, filtered_least_squares)
/// without validate_profile, and false instead of its "profile is not closed" InvalidInput
/// (`out` is then unusable): the closed filter, or the verdict that the profile has an
/// angular gap wider than λc/2 — found on the nonuniform path by the filter's own sorted
/// angles (the gaps angular_coverage takes, bit for bit). The FFT path tests no gap: its
/// rays are each less than half a step off an equiangular grid, so neighbours are less than
/// 2 grid steps apart (4π/(n − 1) for a repeated closing point). Precondition (not
/// checked): the points passed validate_profile(points, 8, …); the other checks (cut-off,
/// circle) throw as there.
bool filter_closed_profile_if_closed(std::span<const Point2> points, double cutoff_upr,
                                     const LeastSquaresCircle& least_squares,
                                     FilteredProfile& out,
                                     LeastSquaresCircle* filtered_least_squares);

}  // namespace vcmm::geometry::internal
