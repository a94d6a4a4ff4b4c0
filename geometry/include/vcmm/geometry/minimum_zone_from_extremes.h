// vcmm/geometry/minimum_zone_from_extremes.h — RONt about the minimum-zone circle (ISO 12181-2
// MZCI) of a smooth closed profile, computed exactly from a small subset of its points: the
// Monte Carlo loop's fast path (validation/spectral_trial.h), where a filtered 3 600-point
// profile's zone is decided by a few dozen points near its peaks and valleys.
#pragma once

#include <span>

#include "vcmm/geometry/point.h"
#include "vcmm/geometry/polar_profile.h"

namespace vcmm::geometry {

/// RONt about the minimum-zone circle of the profile `p` (mm), from a subset S of its points.
///
/// Argument: an annulus that is the (global) minimum zone of S and contains every point is
/// the minimum zone of all points — their minimum width is at least S's, and this annulus
/// achieves it. So: S's minimum zone (minimum_zone_circle, exact contacts, certified global);
/// then one vectorised pass over all points proves each point outside S inside the annulus
/// by a rigorous floating test (squared distance from the rounded centre within 64u of the
/// rounded radii' squares, beyond the rounding of all three, u = 2⁻⁵³); points it cannot
/// place (outside, or within rounding of a circle) join S and S is fitted again. The points
/// of S are inside by the fit's own exact certificate. So the zone is exactly the minimum
/// zone of all points, and its centre the same double as minimum_zone_circle(all points)
/// reports.
///
/// S starts as, per block of 16 consecutive points, the highest local maximum of the
/// deviations if it lies within 45 % of the peak-to-valley below the highest and the lowest
/// local minimum if within 45 % above the lowest, each with one neighbour either side: on a
/// band-limited profile (a filtered one) the contacts lie there — the reference's centre
/// differs from the deviations' origin by a shift whose harmonic-1 tilt moves a contact down
/// by at most 2|shift| (measured: ≤ 39 % on the example ring) and an extremum by less than a
/// sample. Points the test cannot place join with the same neighbours; after 6 fits (or when
/// S has fewer than 8 points) all points are fitted. Only the speed depends on these choices.
///
/// Returns max_j √D̃_j − min_j √D̃_j over all points, D̃_j the rounded squared distance of
/// point j from the centre: R − r to a few ulps (within 1e-13 mm of
/// minimum_zone_circle(points).ron.ront at R ~ 100 mm). Sets s.center to the centre, and
/// s.rounds, s.fell_back, s.subset (S) for inspection.
/// Preconditions: ≥ 8 points, one direction each, finite deviations (InvalidInput naming the
/// rule); throws as minimum_zone_circle. Complexity: one vectorised O(n) pass over the
/// deviations, squared distances only in the blocks that can reach the zone's circles, and
/// the minimum zone of |S| points (~170 of 3 600 on the filtered example ring; 1.02 fits a
/// call there).
double minimum_zone_ront_from_extremes(const PolarProfile& p, ExtremesScratch& s);

/// The same for a profile given as points (a filtered profile about its filter centre, e.g.
/// gaussian_filter.h's FilteredProfile, whose points lie on rays from it): RONt equal bit for
/// bit to minimum_zone_circle(points).ron.ront, and s.center to its centre.
///
/// The argument is the one above, which needs nothing polar: S's minimum zone (exact,
/// certified) whose annulus is proven to hold every other point is the minimum zone of all;
/// and the fitter's RONt, (R̃² − r̃²)/(R̃ + r̃) from the zone's exact squared radii, is a
/// function of that zone alone. Here S starts as, per block of 16 consecutive points, the
/// highest local maximum and the lowest local minimum of the squared distances D_o from
/// `origin` (cyclic) if within 45 % of their range of the top (resp. bottom), each with one
/// neighbour either side; the containment pass computes D̃ about the fitted centre for every point (no
/// deviation bounds to skip blocks with). `origin` (finite; e.g. the filter centre) and the
/// order of the points (consecutive points near each other, e.g. angular order) only steer
/// the speed: any order and any origin give the same, exact result.
/// Preconditions: ≥ 8 finite points (InvalidInput naming this function and the rule or the
/// point); otherwise throws as minimum_zone_circle(points) (e.g. collinear points, in its
/// name). Complexity: two vectorised O(n) passes and the
/// minimum zone of |S| points (~1 fit a call on a filtered 3 600-point ring).
double minimum_zone_ront_from_extremes(std::span<const Point2> points, Point2 origin,
                                       ExtremesScratch& s);

}  // namespace vcmm::geometry
