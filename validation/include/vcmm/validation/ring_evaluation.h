// vcmm/validation/ring_evaluation.h — the measurands of a ring-gauge section from its profile:
// the LS diameter and RONt after the ISO 16610-21 Gaussian filter about the chosen ISO 12181-2
// reference circle (docs/validation.md, "The ring-gauge experiment").
//
// f: the points are projected on the workpiece XY plane (the ring axis is workpiece Z);
//   diameter = 2 · r_LS of the unfiltered profile (ISO 12181-2 LSCI, the seed study's diameter);
//   roundness = RONt of the ISO 16610-21 Gaussian-filtered profile about the chosen reference
//   circle (MZ by default; MI in the seed study).
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "vcmm/errormodel/measurement.h"
#include "vcmm/geometry/point.h"
#include "vcmm/validation/reference_values.h"  // ReferenceCircle

namespace vcmm::validation {

/// How the measurands are evaluated from a profile.
struct RingEvaluationOptions {
  ReferenceCircle reference = ReferenceCircle::minimum_zone;
  /// ISO 16610-21 cut-off (UPR) applied before the roundness evaluation; none: unfiltered.
  /// The diameter is always the LS diameter of the unfiltered points.
  std::optional<double> filter_cutoff_upr = 50.0;
};

/// Index of each measurand in the Monte Carlo sample vector.
enum RingMeasurand : std::size_t { diameter = 0, roundness = 1 };
inline constexpr std::size_t ring_measurand_count = 2;

/// The measurands of one ring measurement (mm).
struct RingMeasurands {
  double diameter_mm = 0.0;   ///< 2 · r_LS, unfiltered profile
  double roundness_mm = 0.0;  ///< RONt of the (filtered) profile about the reference circle
};

/// A profile evaluated in detail (for reports): the measurands and the deviations about the
/// reference circle.
struct RingProfileEvaluation {
  RingMeasurands measurands;
  geometry::Point2 reference_center;   ///< centre of the reference circle (filtered profile)
  double reference_radius_mm = 0.0;    ///< MZ: (R + r)/2; MI, MC, LS: the circle's radius
  /// Per input point, in input order: the angle about reference_center (rad, [0, 2π)), the
  /// radial deviation of the unfiltered point and of the filtered point from the reference
  /// radius (mm).
  std::vector<double> angle_rad, deviation_mm, filtered_deviation_mm;
};

/// Projects the measurement's points on the workpiece XY plane.
std::vector<geometry::Point2> ring_profile(const errormodel::Measurement& m);

/// The measurands of a ring profile (file comment). Preconditions as the geometry functions:
/// ≥ 8 finite points forming a closed profile when filtered (geometry::InvalidInput);
/// geometry::UndefinedResult where a reference circle does not exist. O(n log n).
RingMeasurands evaluate_ring(std::span<const geometry::Point2> profile,
                             const RingEvaluationOptions& options);
RingMeasurands evaluate_ring(const errormodel::Measurement& m, const RingEvaluationOptions& options);

/// RONt of `profile` as given (no filter) about the reference circle `circle` (mm). Throws as
/// the geometry fitters. O(n log n).
double ront_about(std::span<const geometry::Point2> profile, ReferenceCircle circle);

/// As evaluate_ring, with the deviations about the reference circle. O(n log n).
RingProfileEvaluation evaluate_ring_profile(std::span<const geometry::Point2> profile,
                                            const RingEvaluationOptions& options);

}  // namespace vcmm::validation
