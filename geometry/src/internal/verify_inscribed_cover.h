// internal/verify_inscribed_cover.h — an O(n) sufficient test of the global claim of a
// maximum-inscribed circle, for verify() (certificate.cpp) before its Delaunay exhaustion.
//
// Claim: no empty circle centred in the convex hull H is larger than r, i.e. every x ∈ H has
// an input point within r. Given the exact MI circle (centre c, radius r, its 3 contacts at
// distance r surrounding c) and R = max_p |p − c| (so H ⊆ D(c, R)), with s = |x − c|:
//  (A) s ≤ 2γ, γ = the distance from c to the nearest edge line of the contact triangle: for a
//      unit direction d, some contact p_j has d·(p_j − c) ≥ γ (c sees the contacts within
//      half its largest gap G, and γ = r cos(G/2)), so |x − p_j|² = r² + s² − 2s d·(p_j − c)
//      ≤ r² + s² − 2sγ ≤ r².
//  (B) 2γ ≤ s ≤ R: walk the points as a closed polygon (input order, else sorted by angle
//      about c). When every step p_k → p_k+1 turns the same way about c, certainly (filtered
//      orientation), the wedges between consecutive rays cover every direction (the turns sum
//      to a positive multiple of 2π). In a wedge of angle α < π, a point x at distance t from
//      c is within α/2 of the ray of p_k or p_k+1 (ρ = |p − c| ∈ [r, R]), so its squared
//      distance to that point is ≤ f(t, ρ) = t² + ρ² − 2tρ cos(α/2). The chord gives the
//      angle: |p_k+1 − p_k|² ≥ 4ρ_k ρ_k+1 sin²(α/2) ≥ 4r² sin²(α/2), so cos²(α/2) ≥
//      1 − L²/(4r²) with L the longest step. f is convex in t and in ρ: it is ≤ r² on
//      [2γ, R] × [r, R] when it is at the four corners.
// All final comparisons are in interval arithmetic (rounding-mode protected), the per-point
// work in double with the bounds of verify_distance.h; any doubt answers false (the caller
// then runs the exact exhaustion).
#pragma once

#include <span>
#include <utility>

#include "verify_distance.h"
#include "vcmm/geometry/point.h"

namespace vcmm::geometry::internal {

/// Enclosures [lo, hi] of the exact quantities.
struct InscribedCoverInput {
  std::pair<double, double> inner2;        ///< r²
  std::pair<double, double> outer2;        ///< R² = max_p |p − c|²
  std::pair<double, double> outer_minus_inner2;  ///< R² − r²
  std::pair<double, double> gamma2;        ///< γ² (derivation (A))
};

/// True when (A) and (B) prove that every x with |x − c| ≤ R has an input point within r;
/// false when they cannot tell (which does not refute the claim). Always false while the
/// filter is switched off (set_verify_filter_enabled).
bool disks_cover_inscribed(std::span<const Point2> points, const ApproxCentre& c,
                           const InscribedCoverInput& in);

}  // namespace vcmm::geometry::internal
