// internal/inscribed_region.h — the region argument of the maximum-inscribed (MI) fast path:
// how far from a strict local maximum c* (radius r*, three contacts) a centre in the convex
// hull H can still be as good. Not part of the public API.
//
// Notation: scaled units (lengths × s, the circle's power of two, r* ≈ 1); for a centre
// c = c* + t·e (|e| = 1, t > 0) and a point p at distance ρ_p ≥ r* from c* in direction
// w_p, exactly
//   |c − p|² = ρ_p² − 2tρ_p (w_p·e) + t²,                                              (1)
// so r(c) < r* as soon as some point has
//   w_p·e > q_p(t) = (ε_p + t²)/(2tρ_p),   ε_p = ρ_p² − r*² ≥ 0                          (2)
// — a cap of directions about w_p. Three arguments cover t ∈ (0, R_max] (H lies in the
// disc of radius R_max = max ρ_p about c*):
//   (a) contact cone: the contacts have ε = 0, and with β the distance from 0 to the
//       boundary of the triangle of their directions, (2) holds for some contact whenever
//       t < 2r*β =: t1 (the original fast-path argument);
//   (b) angular coverage: every direction has a point within angle h, and the worst ε is
//       R_max² − r*²: (2) holds for t in [t_cov, 2r* cos h), t_cov ≈ (R_max² − r*²)/(2R_max
//       cos h) — the profile's peak-to-valley about c*;
//   (c) multi-scale caps, for the gap [t1, t_cov] that a nearly antipodal contact pair
//       leaves (β tiny: smooth 2-lobe forms, some perfect circles): on [t_a, t_b] the bound
//       q_p(t) is convex in t, so the caps of half-angle arccos(max(q_p(t_a), q_p(t_b)))
//       hold for the whole interval; if they cover the circle of directions, so does (2).
//       Intervals halve from t_cov down to t1; per angular bucket (of 1024) only the point
//       of least ε is used (it has the widest cap at every scale up to its bucket's width).
// When (c) fails on [t_b/2, t_b], every centre of H at least as good as c* lies within
// ρ* = t_b of c*: the caller exhausts the Delaunay triangulation of the points that can be
// nearest from that disc (those within r* + 2ρ* of c*), instead of all points.
// Every floating quantity enters with a rigorous margin (comments in the source).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "internal/extremal_circle.h"
#include "vcmm/geometry/point.h"

namespace vcmm::geometry::internal {

struct InscribedRegion {
  /// r(c) < r* for every c ∈ H, c ≠ c*: c* is the unique maximiser over H.
  bool proven = false;
  /// Otherwise, when finite: r(c) < r* for every c ∈ H with |c − c*| ≥ radius (scaled
  /// units), and the closed disc of radius 2·radius about c* lies in the interior of H.
  double radius = 0.0;
  double t1 = 0.0;       ///< the contact-cone radius of (a) (scaled units)
  double t_cov = 0.0;    ///< where (b) starts (scaled units)
  int scales = 0;        ///< intervals of (c) checked
};

/// The argument above for the exact circle `circle` (no point strictly inside, contacts
/// surrounding its centre: the caller has checked both). `max_d2` is the largest first-stage
/// squared distance (scaled) of the last pass; `occupied` the 256 pseudo-angle occupancy
/// buckets of a point sample about `c0`.
InscribedRegion inscribed_region(std::span<const Point2> points, const ExactCircle& circle,
                                 const std::array<std::size_t, 3>& contacts, double max_d2,
                                 const std::array<std::uint64_t, 4>& occupied, Point2 c0);

}  // namespace vcmm::geometry::internal
