// vcmm/geometry/minimum_zone_from_extremes.h — RONt about the minimum-zone circle (ISO 12181-2
// MZCI) of a smooth closed profile, computed exactly from a small subset of its points: the
// Monte Carlo loop's fast path (validation/spectral_trial.h), where a filtered 3 600-point
// profile's zone is decided by a few dozen points near its peaks and valleys.
#pragma once

#include <span>
#include <vector>

#include "vcmm/geometry/point.h"

namespace vcmm::geometry {

/// Reusable work arrays of minimum_zone_ront_from_extremes (one per thread).
struct MinimumZoneScratch {
  std::vector<Point2> subset;  ///< S at the end (its size: how much was needed)
  std::vector<unsigned char> member;
  std::vector<double> flag, squared_distance;
};

/// RONt about the minimum-zone circle of `points`, computed exactly from a subset: an annulus
/// that is minimal for a subset S and contains every point is minimal for all points (their
/// minimum width is at least S's, and this annulus achieves it). S starts as the peaks and
/// valleys of `deviations` (radial, about any centre near the profile's: they only pick S)
/// within a quarter of the peak-to-valley of the top or of the bottom, each with two
/// neighbours either side — where the contacts of a smooth, band-limited profile lie; the
/// minimum zone of S is checked against all points and the extremes of the violating lobes
/// (with their neighbours) are added until no point is outside (at most 6 rounds, then the
/// minimum zone of all points). Returns the spread of the distances of all points about S's
/// centre: S's width to rounding, i.e. minimum_zone_circle(points).ron.ront to ~1e-13 mm at
/// R ~ 100 mm (tests/geometry/minimum_zone_from_extremes_test.cpp). `scratch` is reused between
/// calls. Preconditions: ≥ 8 points and one deviation each (InvalidInput); throws as
/// minimum_zone_circle. Complexity: a few O(n) passes and the minimum zone of |S| points
/// (~130 of 3 600 on the filtered example ring: ~4× faster than the whole profile's).
double minimum_zone_ront_from_extremes(std::span<const Point2> points,
                                       std::span<const double> deviations,
                                       MinimumZoneScratch& scratch);

}  // namespace vcmm::geometry
