// vcmm/geometry/claim_check.h — cross-checking another program's reference circle against the
// exact one (docs/method.md §9, "Checking a claimed circle").
//
// A claim is a centre c and, optionally, its radii: MZ the inner and outer radius r ≤ R; MI,
// MC and LS one radius. Without radii the tightest ones for c are taken (MZ: the least and the
// greatest distance |p − c|; MI: the least; MC: the greatest; LS: the mean).
//   feasible   the claimed circles satisfy the reference's containment rule on every point,
//              decided exactly (|p − c|² against r², floating filter with a rigorous bound and
//              GMP rationals in the band it cannot decide): MZ r ≤ |p − c| ≤ R; MI no point
//              strictly inside r; MC no point strictly outside R (LS: no rule, always true)
//   RONt       about the claim: MZ R − r; MI max|p − c| − r; MC R − min|p − c|; LS max − min
//   excess     claimed RONt − exact RONt (mm); for MI and MC also the radius shortfall
//              r* − r, resp. excess R − R* (the quantity the circle optimises)
//   optimal    feasible and within the resolution of the claim: moving the centre by δ changes
//              every distance |p − c| by at most |δ|, so a minimax RONt by at most 2|δ| and the
//              best radius for the centre by at most |δ|. With ρ the claim's resolution per
//              coordinate (half a unit in the last digit written, 0 for exact doubles),
//              tolerance = 2√2·ρ + 4 (ulp(|c_x|) + ulp(|c_y|)) + 8 ulp(radius) for the RONt
//              excess, and radius_tolerance = √2·ρ + the same ulps for the MI shortfall and
//              the MC excess of the radius. LS (a numerical fit,
//              vcmm's within ~1e-13 mm of NIST's 60-digit references): the claimed centre and
//              radius within 1e-9 mm of vcmm's.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "vcmm/geometry/point.h"
#include "vcmm/geometry/roundness.h"

namespace vcmm::geometry {

struct ClaimedCircle {
  ReferenceCircle reference = ReferenceCircle::minimum_zone;
  Point2 center;
  /// MZ: {inner, outer}; MI, MC, LS: {radius, radius}. Absent: the tightest for the centre.
  std::optional<std::pair<double, double>> radii;
  /// Resolution of the claimed centre per coordinate (mm): half a unit in the last decimal the
  /// other program wrote (5e-13 for 12 decimals); 0 when the centre is exactly these doubles.
  double center_resolution_mm = 0.0;
};

struct ClaimCheck {
  ReferenceCircle reference = ReferenceCircle::minimum_zone;
  double claimed_inner_radius = 0.0, claimed_outer_radius = 0.0;  ///< as given or derived
  bool radii_given = false;
  bool feasible = true;
  std::size_t violations = 0;               ///< points breaking the containment rule
  std::vector<std::size_t> violating;       ///< their indices (the first 10)
  double claimed_ront = 0.0;                ///< RONt about the claim (mm)
  double exact_ront = 0.0;                  ///< RONt about the exact circle (mm)
  double excess_ront = 0.0;                 ///< claimed − exact (mm)
  double radius_excess = 0.0;               ///< MI: r* − r; MC: R − R*; MZ, LS: 0
  double center_distance = 0.0;             ///< |c − c*| (mm)
  double tolerance = 0.0;                   ///< on the RONt excess (file comment)
  double radius_tolerance = 0.0;            ///< on the MI/MC radius (file comment)
  bool optimal = false;
  /// The exact circle: centre, radii (MZ: inner, outer; others: radius twice), contacts
  /// (indices into the points), its certificate's text and whether verify() accepted it.
  Point2 exact_center;
  double exact_inner_radius = 0.0, exact_outer_radius = 0.0;
  std::vector<std::size_t> exact_contacts;
  std::string exact_certificate;
  bool exact_certified = false;
};

/// Checks `claim` against the exact reference circle of `points` (file comment). Preconditions
/// (InvalidInput): as the reference's fitter; a finite centre and finite radii with
/// 0 ≤ r ≤ R; a finite center_resolution_mm ≥ 0. Throws UndefinedResult where the exact circle does not exist (then nothing can
/// be optimal). O(n) plus the fitter (exact arithmetic only in the filter's uncertain band).
ClaimCheck check_claimed_circle(std::span<const Point2> points, const ClaimedCircle& claim);

}  // namespace vcmm::geometry
