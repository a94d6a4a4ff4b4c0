// vcmm/geometry/maximum_inscribed_from_extremes.h — RONt about the maximum-inscribed circle
// (ISO 12181-2 MICI) of a smooth closed profile, computed exactly from a small subset of its
// points: the Monte Carlo loop's fast path (validation/spectral_trial.h), the MI analogue of
// minimum_zone_from_extremes.h.
#pragma once

#include <span>

#include "vcmm/geometry/point.h"
#include "vcmm/geometry/polar_profile.h"

namespace vcmm::geometry {

/// RONt about the maximum-inscribed circle of the profile `p` (mm), from a subset S of its
/// points, equal bit for bit to maximum_inscribed_circle(all points).ron.ront.
///
/// Argument (r(c) = distance from c to the nearest point; MI = the maximiser of r over the
/// convex hull H of the points, surrounded by its contacts). Let C_S (centre c_S, radius r_S)
/// be the MI circle of S (maximum_inscribed_circle, exact contacts, certified global for S).
/// (1) If no point of the profile lies strictly inside C_S (a rigorous floating filter, then
/// the exact predicate), C_S is empty for all points, centred in H_S ⊆ H and surrounded by its
/// contacts, so the MI radius r* of all points is ≥ r_S. (2) If the MI centre c* lay outside
/// H_S, then c* ∈ H \ H_S: with S's points sorted by angle about the origin (all angular
/// gaps Δ < π/2, once around), c* is beyond the chord ab of two consecutive ones, within
/// ρ_max = max |p_j| of the origin, so r* ≤ |c* − a| ≤ ρ_max Δ + ρ_max − min(|a|, |b|) cos(Δ/2);
/// S holds every (n/32)th point, at most every 64th (anchors), which keeps this below r_S/2
/// on any round profile
/// (checked every call, with Δ bounded from the directions' chord). So c* ∈ H_S, where
/// r(c*) ≤ r_S(c*) ≤ r_S: r* = r_S, and C_S is the MI circle of all points (the same exact
/// circle; where several centres share the largest radius exactly, the full fitter may report
/// another). RONt is then computed as the fitter does: (ρ_f² − r*²)/(ρ̃_f + r̃) with the
/// numerator exact, f the farthest point (lowest index on ties), found among the points whose
/// deviations can reach the highest one's squared distance.
///
/// S starts as, per block of 16 points, the lowest local minimum of the deviations within
/// 45 % of the peak-to-valley above the lowest, with one neighbour either side, and the
/// anchors; points found inside C_S join with their neighbours and S is fitted again (at
/// most 6 fits; then, or when the hull bound fails, S's fit is undefined, or the directions
/// are not unit vectors to 1e-9, all points are fitted). Sets s.center, s.rounds,
/// s.fell_back, s.subset.
/// Preconditions: ≥ 8 points, one direction each, finite deviations (InvalidInput naming the
/// rule); throws as maximum_inscribed_circle. Complexity: one vectorised O(n) pass, squared
/// distances only in the blocks that can matter, and the MI of |S| points (~140 of 3 600 on
/// the filtered example ring).
double maximum_inscribed_ront_from_extremes(const PolarProfile& p, ExtremesScratch& s);

/// The same for a profile given as points (a filtered profile about its filter centre,
/// gaussian_filter.h's FilteredProfile): RONt equal bit for bit to
/// maximum_inscribed_circle(points).ron.ront, s.center its centre.
///
/// The argument above with the polar quantities taken about `origin`: S (the lowest local
/// minima of the squared distances D_o from `origin` per block of 16 within 45 % of their
/// range of the bottom, with a neighbour either side, and every (n/32)th point, at most every
/// 64th) is fitted; its points' directions about `origin`, computed and normalised, must go
/// once around it in index order with gaps below π/2, and the hull bound uses their
/// distances from it and ρ_max = √max D_o; every point's D̃ about the centre is computed (no
/// deviation bounds), those that may be inside C_S go to the exact predicate, and the
/// farthest is the first holding the largest D̃. Else (or after 6 fits) all points are
/// fitted. `origin` and the order only steer the speed, except that a profile not in angular
/// order about `origin` always takes the full fit.
/// Preconditions: ≥ 8 finite points (InvalidInput naming the function); throws as
/// maximum_inscribed_circle. Complexity: two vectorised O(n) passes a round and the MI of |S|
/// points.
double maximum_inscribed_ront_from_extremes(std::span<const Point2> points, Point2 origin,
                                            ExtremesScratch& s);

}  // namespace vcmm::geometry
