// roundness_parameters.cpp — RONt, RONp, RONv, RONq (ISO 12181-1:2011) of a profile about
// a given reference circle (centre c, radius R_ref).
//
// d_i = |p_i − c| − R_ref, with p_i − c formed first (coordinates relative to the centre), so a
// profile 900 mm from the origin loses nothing beyond the rounding of each distance
// (½ ulp of |p − c|). RONt is taken as max r_i − min r_i, which does not involve R_ref at
// all; RONq = sqrt(mean d_i²) sums small squares (no cancellation).
//
// Boundary checks (every build): at least one point, every coordinate finite, and a finite
// centre and radius — InvalidInput naming the function, the rule and the value. The fitters
// call the unchecked twin (internal/prevalidated.h) on points they have validated.
//
// Speed (SSE2): the distances are taken two at a time — the packet square root is the scalar
// one, correctly rounded — and the extremes by packet min/max (exact, in any order); Σ d²
// keeps its sequential order, so every result is bit for bit that of the scalar loop.
#include "vcmm/geometry/roundness_parameters.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "internal/prevalidated.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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
  return internal::roundness_parameters_of_valid(points, center, reference_radius);
}

RoundnessParameters internal::roundness_parameters_of_valid(std::span<const Point2> points,
                                                            Point2 center,
                                                            double reference_radius) {
  // d_i² is summed as (d_i·2^−e)² with 2^e the scale of the radius (an exact rescaling), so
  // RONq neither overflows for huge coordinates nor underflows for tiny ones.
  const double size = std::max(std::fabs(reference_radius),
                               distance(points[0].x - center.x, points[0].y - center.y));
  const int e = size > 0.0 && std::isfinite(size) ? std::ilogb(size) : 0;
  const double inv_scale = std::ldexp(1.0, -e);  // multiplying by it is exact
  const std::size_t n = points.size();
  double r_max = distance(points[0].x - center.x, points[0].y - center.y), r_min = r_max;
  double sum_dd = 0.0;
  const auto add = [&](double r) {
    const double d = (r - reference_radius) * inv_scale;
    sum_dd += d * d;
  };
  std::size_t i = 0;
#if defined(__SSE2__)
  {
    // Two points a packet: (x0, y0), (x1, y1) unpacked into (x0, x1), (y0, y1).
    const __m128d cx = _mm_set1_pd(center.x), cy = _mm_set1_pd(center.y);
    const __m128d lo = _mm_set1_pd(1e-150), hi = _mm_set1_pd(std::numeric_limits<double>::max());
    __m128d pmax = _mm_set1_pd(r_max), pmin = pmax;
    alignas(16) double r[2];
    const double* xy = reinterpret_cast<const double*>(points.data());
    static_assert(sizeof(Point2) == 2 * sizeof(double), "Point2: two packed doubles");
    for (; i + 2 <= n; i += 2) {
      const __m128d a = _mm_loadu_pd(xy + 2 * i), b = _mm_loadu_pd(xy + 2 * i + 2);
      const __m128d dx = _mm_sub_pd(_mm_unpacklo_pd(a, b), cx);
      const __m128d dy = _mm_sub_pd(_mm_unpackhi_pd(a, b), cy);
      __m128d pr = _mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)));
      // distance()'s fallback where a lane is outside (1e-150, max]: rare, per point.
      if (_mm_movemask_pd(_mm_and_pd(_mm_cmplt_pd(lo, pr), _mm_cmple_pd(pr, hi))) != 3)
        pr = _mm_setr_pd(distance(points[i].x - center.x, points[i].y - center.y),
                         distance(points[i + 1].x - center.x, points[i + 1].y - center.y));
      _mm_store_pd(r, pr);
      add(r[0]);
      add(r[1]);
      pmax = _mm_max_pd(pmax, pr);
      pmin = _mm_min_pd(pmin, pr);
    }
    alignas(16) double m[2];
    _mm_store_pd(m, pmax);
    r_max = std::max(m[0], m[1]);
    _mm_store_pd(m, pmin);
    r_min = std::min(m[0], m[1]);
  }
#endif
  for (; i < n; ++i) {
    const double r = distance(points[i].x - center.x, points[i].y - center.y);
    r_max = std::max(r_max, r);
    r_min = std::min(r_min, r);
    add(r);
  }
  RoundnessParameters out;
  const double d_max = r_max - reference_radius, d_min = r_min - reference_radius;
  out.ront = r_max - r_min;
  out.ronp = std::max(0.0, d_max);
  out.ronv = std::max(0.0, -d_min);
  out.ronq = std::ldexp(std::sqrt(sum_dd / static_cast<double>(n)), e);
  return out;
}

}  // namespace vcmm::geometry
