// tests/support/exhaustive_oracle.h — brute-force exact reference circles for small point
// sets (n ≤ 12), independent of the fitters (it shares no code with geometry/src) and of
// verify() (its own predicates: template filters Interval_nt → Exact_rational for the
// minimum zone, CGAL Epick exact predicates for the circumscribed/inscribed circles).
//
// Minimum zone (MZ): every strict local minimum of f(c) = R(c) − r(c) is a strictly
// alternating 2+2 contact set whose exact annulus (centre = intersection of the two
// perpendicular bisectors) holds every point; conversely every such set is a strict
// local minimum (first-order sharp). The oracle enumerates all of them and takes the
// narrowest; the all-co-circular set has zero width. As |c| → ∞, f tends to the
// convex-hull width W, so the minimum exists iff the narrowest local minimum is at most
// W wide (if inf f < W it is attained in a bounded region, hence at a local minimum; if
// every local minimum is wider than W, inf f = W is not attained).
// Widths √R² − √r² are compared exactly without square roots by repeated squaring
// (compare_sqrt_differences; derivation in exhaustive_oracle.cpp).
//
// Minimum circumscribed (MC): the smallest circle through 2 (diametral) or 3 points that
// encloses all; supports = every pair/triple on that circle whose closed hull holds the
// centre.
//
// Maximum inscribed (MI): the largest empty circle with its centre in the closed convex
// hull. Candidates: Voronoi vertices (empty circumcircles of triples) in the hull and the
// points where a bisector of two nearest points crosses a hull edge. Defined when a
// maximum is attained at a Voronoi vertex whose co-circular points surround it (a strict
// local maximum); its supports are the triples among them whose closed triangle holds the
// centre (with 4+ co-circular contacts, e.g. a rectangle, the centre may lie on an edge).
//
// Indices refer to the input; duplicated points are represented by their lowest index.
// Cost: MZ O(n⁵) with early exits (~1 ms at n = 12), MC/MI O(n⁴).
#pragma once

#include <CGAL/Exact_rational.h>

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "vcmm/geometry/point.h"

namespace vcmm::test {

using geometry::Point2;
using Rational = CGAL::Exact_rational;

struct RationalPoint {
  Rational x;
  Rational y;
};
bool operator==(const RationalPoint& a, const RationalPoint& b);

/// sign((√a − √b) − (√c − √d)) for rationals a, b, c, d ≥ 0, exactly.
int compare_sqrt_differences(const Rational& a, const Rational& b, const Rational& c,
                             const Rational& d);

enum class OracleStatus {
  defined,    ///< the optimum exists and has a certificate of the documented form
  undefined,  ///< no optimum of the documented form (MZ: no finite minimum; MI: the
              ///< largest empty circle in the hull is not surrounded by its contacts)
};
const char* to_string(OracleStatus s);

struct ZoneSupport {
  std::array<std::size_t, 2> outer{};  ///< sorted
  std::array<std::size_t, 2> inner{};  ///< sorted
  RationalPoint center;
  Rational outer2;  ///< R²
  Rational inner2;  ///< r²
};

struct OracleMinimumZone {
  OracleStatus status = OracleStatus::undefined;
  bool zero_width = false;   ///< all distinct points on one circle (centre/outer2 set)
  RationalPoint center;      ///< of the narrowest local minimum (first of `optima`)
  Rational outer2;
  Rational inner2;
  std::vector<ZoneSupport> optima;  ///< every narrowest valid 2+2 set (ties)
  std::vector<ZoneSupport> locals;  ///< every valid 2+2 set (= every strict local minimum)
  Rational hull_width2;             ///< W²
  std::string explanation;
};

OracleMinimumZone oracle_minimum_zone(std::span<const Point2> points);

struct OracleCircle {
  OracleStatus status = OracleStatus::undefined;
  RationalPoint center;
  Rational radius2;
  /// Every contact set of the documented form (sorted indices) attaining the optimum.
  std::vector<std::vector<std::size_t>> supports;
  struct Local {
    std::vector<std::size_t> contacts;  ///< sorted
    RationalPoint center;
    Rational radius2;
  };
  /// MI only: every support (as above) of every strict local maximum of the distance to
  /// the nearest point, whether optimal or not.
  std::vector<Local> locals;
  std::string explanation;
};

OracleCircle oracle_minimum_circumscribed(std::span<const Point2> points);
OracleCircle oracle_maximum_inscribed(std::span<const Point2> points);

/// The exact 2+2 zone of given contacts (nullopt if the bisectors are parallel).
std::optional<ZoneSupport> exact_zone(std::span<const Point2> points, std::size_t o1,
                                      std::size_t o2, std::size_t i1, std::size_t i2);

/// Lowest index holding the same point as points[i].
std::size_t representative(std::span<const Point2> points, std::size_t i);

/// The points as a C++ initializer list with exact hexadecimal literals, for reproducers.
std::string cpp_literal(std::span<const Point2> points);

}  // namespace vcmm::test
