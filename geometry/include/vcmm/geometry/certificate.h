// vcmm/geometry/certificate.h — what a reference-circle result proves about itself, and the
// independent exact checks of those proofs.
//
// Every minimum-zone (MZ), maximum-inscribed (MI) and minimum-circumscribed (MC) result
// carries its contact points and an optimality claim. The `verify` functions re-check the
// claim from the input doubles and the contact indices alone, exactly — rational arithmetic
// (CGAL::Exact_rational) behind a static floating-point filter with a proven error bound and
// interval filters (a sign is taken from floating point only when the bound proves it;
// docs/method.md §3), CGAL's exact predicates for the convex hull and the Delaunay
// triangulation, no square root — and share no code with the fitters. Cost on a noisy
// 3 600-point profile: ~0.1 ms per circle (docs/performance.md).
// verify() never throws on a wrong certificate: it returns valid = false and names the
// first failed condition (with indices); it throws InvalidInput only for non-finite input.
#pragma once

#include <span>
#include <string>

#include "vcmm/geometry/point.h"

namespace vcmm::geometry {

struct MinimumZoneCircle;
struct MaximumInscribedCircle;
struct MinimumCircumscribedCircle;

/// How far optimality of a reference circle is proven.
enum class Optimality {
  local,   ///< strict local optimum, proven exactly (e.g. MZ 2+2 alternation)
  global,  ///< global optimum, proven (convexity, or a region argument + exhaustion)
};

/// The proof attached to a result.
struct Certificate {
  Optimality optimality = Optimality::local;
  /// Plain-language statement of what was proven and how, e.g.
  /// "2+2 alternating contacts, containment exact; global: any better centre lies within
  ///  3.1e-12 mm of the centre, where 1 candidate quadruple was exhausted".
  std::string argument;
  /// For region arguments: every centre whose objective could beat the result lies within
  /// this distance (mm) of the reported centre. 0 when the argument is not a region one.
  double region_radius = 0.0;
};

/// Outcome of an independent check.
struct Verification {
  bool valid = false;
  std::string reason;  ///< empty when valid, else the first failed condition
  explicit operator bool() const { return valid; }
};

/// Re-checks an MZ result exactly: two outer and two inner contacts (distinct points); the
/// exact centre is the intersection of their perpendicular bisectors; every point lies in
/// the closed annulus, r² < R²; the contacts alternate strictly in angle about the exact
/// centre; the reported centre (4 ulp), radii (8 ulp) and RONt/RONp/RONv (16 ulp), ulps of
/// max(|c_x|, |c_y|, R), bracket the exact values; RONq ∈ [0, max(RONp, RONv)]. Zero width
/// (both lists the same 3 points): every point exactly on their circle.
/// A global claim is re-derived, not read from the certificate: it holds when the segments
/// o1o2 and i1i2 cross and every contact lies farther than R − r from the line through the
/// other pair (then no other centre is as good; see certificate.cpp, derivation (4)); else
/// by enumerating every (pair of hull vertices) × (Delaunay edge) as outer × inner contacts
/// — a narrower local minimum would be among them — and comparing with the convex-hull
/// width (the limit at infinity). When that enumeration would exceed 5e6 sets, the claim
/// is reported as not re-checkable (valid = false). The argument text and region_radius
/// are not used.
/// Throws InvalidInput only for non-finite input coordinates.
Verification verify(std::span<const Point2> points, const MinimumZoneCircle& mz);

/// Re-checks an MC result exactly: 2 contacts with the centre at their midpoint, or 3
/// contacts on one circle with the centre in their closed triangle; every point inside
/// or on the circle; reported centre/radius/RONt/RONv within a few ulps of the exact
/// values, RONp ≈ 0. Optimality is global by convexity whatever the claim.
Verification verify(std::span<const Point2> points, const MinimumCircumscribedCircle& mc);

/// Re-checks an MI result exactly: 3 contacts on one circle with the centre inside their
/// closed triangle — on an edge only when another input point on the circle lies strictly
/// beyond that edge (4+ co-circular contacts surrounding the centre, e.g. a rectangle's
/// corners: the circle is then a strict local maximum that no 3 contacts certify alone);
/// no point strictly inside the circle; the centre in the hull (implied by the triangle);
/// reported centre/radius/RONt/RONp within a few ulps, RONv ≈ 0. A global claim is
/// re-derived independently of the author's region argument: first an O(n) sufficient test
/// (the disks of radius r* about the points cover the disk about the centre that holds the
/// hull; docs/method.md §3), and where it cannot tell, exhaustively: every Delaunay circumcircle
/// (CGAL, exact predicates) centred in the closed convex hull has r² ≤ r*², and on every
/// hull edge longer than 2r* the exact lower envelope of the nearest-point distance stays
/// ≤ r* (certificate.cpp, derivation (5)).
Verification verify(std::span<const Point2> points, const MaximumInscribedCircle& mi);

}  // namespace vcmm::geometry
