// vcmm/geometry/point.h — the 2D point of a roundness profile and the checks every
// public entry point of vcmm::geometry applies to its input.
//
// Units: coordinates in millimetres (any consistent length unit works; outputs carry the
// input's unit).
#pragma once

#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>

namespace vcmm::geometry {

/// A point of a measured profile, in the plane of the profile (mm).
struct Point2 {
  double x = 0.0;
  double y = 0.0;
  friend bool operator==(const Point2&, const Point2&) = default;
};

/// Thrown when a caller passes input that cannot be evaluated: empty, NaN/inf, too few
/// points, all points identical or collinear. The message names the function, the rule
/// broken and the offending value or index ("least_squares_circle: point 17 has a
/// non-finite coordinate (x = nan)").
class InvalidInput : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Thrown when the input is valid but the requested quantity does not exist for it (e.g. a
/// maximum-inscribed circle for a partial arc, whose largest empty circle is not enclosed
/// by the profile). The message says why.
class UndefinedResult : public std::domain_error {
 public:
  using std::domain_error::domain_error;
};

/// Checks a profile at a public boundary, in every build:
///  - at least `min_points` points;
///  - every coordinate finite;
///  - at least two distinct points, and (if `require_non_collinear`) not all on one line,
///    decided with an exact orientation predicate.
/// Throws InvalidInput naming `caller`, the rule and the offending index/value.
/// Duplicated points are accepted (a closed scan repeats its first point).
/// Complexity O(n).
void validate_profile(std::span<const Point2> points, std::size_t min_points,
                      const char* caller, bool require_non_collinear = true);

}  // namespace vcmm::geometry
