// roundness_parameters.cpp — RONt, RONp, RONv, RONq (ISO 12181-1:2011) of a profile about
// a given reference circle (centre c, radius R_ref).
//
// d_i = |p_i − c| − R_ref, with p_i − c formed first (coordinates relative to the centre), so a
// profile 900 mm from the origin loses nothing beyond the rounding of each distance
// (½ ulp of |p − c|). RONt is taken as max r_i − min r_i, which does not involve R_ref at
// all; RONq = sqrt(mean d_i²) sums small squares (no cancellation).
//
// Boundary checks (every build): at least one point, every coordinate finite, and a finite
// centre and radius — InvalidInput naming the function, the rule and the value.
#include "vcmm/geometry/roundness_parameters.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace vcmm::geometry {
namespace {

constexpr const char* kCaller = "roundness_parameters";

/// |(dx, dy)|: the plain square root, falling back to hypot only where dx² + dy² overflows
/// (coordinates beyond ~1e154) or loses precision to underflow (distances below 1e-150,
/// whose squares leave the normal range), so the common case stays fast.
double distance(double dx, double dy) {
  const double r = std::sqrt(dx * dx + dy * dy);
  return std::isfinite(r) && r > 1e-150 ? r : std::hypot(dx, dy);
}

}  // namespace

RoundnessParameters roundness_parameters(std::span<const Point2> points, Point2 center,
                                         double reference_radius) {
  validate_profile(points, 1, kCaller, /*require_non_collinear=*/false);
  if (!std::isfinite(center.x) || !std::isfinite(center.y)) {
    std::ostringstream os;
    os << kCaller << ": the centre must be finite; got (x = " << center.x
       << ", y = " << center.y << ")";
    throw InvalidInput(os.str());
  }
  if (!std::isfinite(reference_radius)) {
    std::ostringstream os;
    os << kCaller << ": the reference radius must be finite; got " << reference_radius;
    throw InvalidInput(os.str());
  }
  // d_i² is summed as (d_i·2^−e)² with 2^e the scale of the radius (an exact rescaling), so
  // RONq neither overflows for huge coordinates nor underflows for tiny ones.
  const double size = std::max(std::fabs(reference_radius),
                               distance(points[0].x - center.x, points[0].y - center.y));
  const int e = size > 0.0 && std::isfinite(size) ? std::ilogb(size) : 0;
  const double inv_scale = std::ldexp(1.0, -e);  // multiplying by it is exact
  double r_max = -1.0, r_min = 0.0, sum_dd = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double r = distance(points[i].x - center.x, points[i].y - center.y);
    if (i == 0) {
      r_max = r_min = r;
    } else {
      r_max = std::max(r_max, r);
      r_min = std::min(r_min, r);
    }
    const double d = (r - reference_radius) * inv_scale;
    sum_dd += d * d;
  }
  RoundnessParameters out;
  const double d_max = r_max - reference_radius, d_min = r_min - reference_radius;
  out.ront = r_max - r_min;
  out.ronp = std::max(0.0, d_max);
  out.ronv = std::max(0.0, -d_min);
  out.ronq = std::ldexp(std::sqrt(sum_dd / static_cast<double>(points.size())), e);
  return out;
}

}  // namespace vcmm::geometry
