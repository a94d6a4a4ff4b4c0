// internal/exact.h — the kernels and exact helpers shared by the fitters (not by the
// independent checker in certificate.cpp, which keeps its own).
//
// Epick: double coordinates, exact (filtered) predicates — every combinatorial decision.
// Exact_rational (GMP mpq): exact constructions such as bisector intersections.
#pragma once

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>

#include "vcmm/geometry/point.h"

namespace vcmm::geometry::internal {

using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;
using EPoint = Epick::Point_2;
using Rational = CGAL::Exact_rational;

inline EPoint to_epick(Point2 p) { return EPoint(p.x, p.y); }

/// An exact rational point.
struct RationalPoint {
  Rational x;
  Rational y;
};

inline RationalPoint to_rational(Point2 p) { return {Rational(p.x), Rational(p.y)}; }

/// Nearest-ish double of an exact rational (GMP's mpq_get_d truncates: within 1 ulp).
inline double to_double(const Rational& q) { return CGAL::to_double(q); }
inline Point2 to_point(const RationalPoint& p) { return {to_double(p.x), to_double(p.y)}; }

inline Rational squared_distance(const RationalPoint& a, const RationalPoint& b) {
  const Rational dx = a.x - b.x;
  const Rational dy = a.y - b.y;
  return dx * dx + dy * dy;
}

}  // namespace vcmm::geometry::internal
