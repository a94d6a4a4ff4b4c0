// internal/minimum_zone_exact.h — the exact annulus of a 2+2 contact quadruple, shared by
// make_minimum_zone_result (minimum_zone_common.cpp) and the fast path (minimum_zone.cpp).
// Not part of the public API.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>

#include "internal/exact.h"
#include "internal/precise_distance.h"
#include "vcmm/geometry/minimum_zone.h"
#include "vcmm/geometry/point.h"

namespace vcmm::geometry::internal {

/// The annulus whose outer circle passes through o1, o2 and inner circle through i1, i2,
/// all concentric: centre = intersection of the perpendicular bisectors of o1o2 and i1i2.
struct ExactAnnulus {
  RationalPoint center;
  Rational outer_sq;  ///< R² = |c − o1|²
  Rational inner_sq;  ///< r² = |c − i1|²
};

/// Exact annulus of the quadruple, or nullopt when a pair has coincident coordinates or the
/// two bisectors are parallel (no unique centre). Rational arithmetic (~30 operations, each
/// normalised by a gcd): used where exact comparisons are needed.
std::optional<ExactAnnulus> exact_annulus(std::span<const Point2> points,
                                          std::array<std::size_t, 2> outer,
                                          std::array<std::size_t, 2> inner);

/// The same annulus summarised by correctly rounded doubles, computed in integers without
/// any gcd (several times faster than exact_annulus): with every coordinate of the four
/// points an integer multiple of 2^E and integer local coordinates P = (p − o1)·2^−E, the
/// centre is c* = o1 + 2^E (X, Y)/D, R*² = 4^E NR/D², r*² = 4^E Nr/D²; each double below
/// is the nearest double of its exact value (MPFR division, one rounding), so the exact
/// value lies within half an ulp of it.
struct RoundedAnnulus {
  Point2 center;          ///< nearest doubles of c*
  double outer_sq = 0.0;  ///< nearest double of R*²
  double inner_sq = 0.0;  ///< nearest double of r*²
  double diff_sq = 0.0;   ///< nearest double of R*² − r*² (exact difference, then rounded)
  bool valid = false;     ///< r* < R* (false: the "inner" pair is not inside the outer circle)
  /// With low_parts: the outer and inner circle for the second-stage filter (double-double
  /// centre and radii², internal/precise_distance.h); otherwise not usable.
  PreciseCircle outer_precise, inner_precise;
};

/// nullopt when a pair has coincident coordinates or the bisectors are parallel. The low
/// parts (two more MPFR divisions per value) only when asked: few candidates need them.
std::optional<RoundedAnnulus> rounded_annulus(std::span<const Point2> points,
                                              std::array<std::size_t, 2> outer,
                                              std::array<std::size_t, 2> inner,
                                              bool low_parts = false);

/// make_minimum_zone_result (internal/minimum_zone_common.h) for an annulus already computed
/// by rounded_annulus on the same quadruple; `ronq`, when given, is used as RONq (the fast path
/// computes it in its containment pass) instead of a separate O(n) pass; with
/// `indices_normalised` the caller has already mapped duplicates to their lowest index.
MinimumZoneCircle make_minimum_zone_result(std::span<const Point2> points,
                                           const RoundedAnnulus& annulus,
                                           std::array<std::size_t, 2> outer,
                                           std::array<std::size_t, 2> inner,
                                           Certificate certificate,
                                           std::optional<double> ronq,
                                           bool indices_normalised = false);

/// Replaces each index by the lowest index whose point has the same coordinates. O(n).
void normalise_duplicate_indices(std::span<const Point2> points,
                                 std::span<std::size_t> indices);

}  // namespace vcmm::geometry::internal
