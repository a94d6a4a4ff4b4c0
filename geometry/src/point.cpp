#include "vcmm/geometry/point.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cmath>
#include <sstream>

#include "internal/isa.h"
#include "internal/prevalidated.h"
#include "internal/vec.h"

namespace vcmm::geometry {
namespace {

// Whether all n doubles at c are finite: v·0 is +0 or −0 for finite v and NaN for NaN or ±inf,
// so a sum of such products is ±0 exactly when all are finite, in any order of summation. W
// lanes, four accumulators (independent chains); the tail one at a time.
template <int W>
[[gnu::always_inline]] inline bool finite_body(const double* c, std::size_t n) {
  using V = typename internal::VecOf<W>::type;
  V a0{}, a1{}, a2{}, a3{};
  std::size_t i = 0;
  for (; i + 4 * W <= n; i += 4 * W) {
    a0 += internal::load<V>(c + i) * 0.0;
    a1 += internal::load<V>(c + i + W) * 0.0;
    a2 += internal::load<V>(c + i + 2 * W) * 0.0;
    a3 += internal::load<V>(c + i + 3 * W) * 0.0;
  }
  const V a = (a0 + a1) + (a2 + a3);
  double s = 0.0;
  for (int l = 0; l < W; ++l) s += a[l];
  for (; i < n; ++i) s += c[i] * 0.0;
  return s == 0.0;
}

bool all_finite_baseline(const double* c, std::size_t n) { return finite_body<2>(c, n); }
#if VCMM_GEOMETRY_X86
__attribute__((target("avx512f"))) bool all_finite_avx512(const double* c, std::size_t n) {
  return finite_body<8>(c, n);
}
#endif

bool all_finite(const double* c, std::size_t n) {
#if VCMM_GEOMETRY_X86
  if (internal::use_avx512()) return all_finite_avx512(c, n);
#endif
  return all_finite_baseline(c, n);
}

}  // namespace

void validate_profile(std::span<const Point2> points, std::size_t min_points,
                      const char* caller, bool require_non_collinear) {
  if (points.size() < min_points) {
    std::ostringstream os;
    os << caller << ": needs at least " << min_points << " points; got " << points.size();
    throw InvalidInput(os.str());
  }
  // Fast path (the Monte Carlo loop validates ~10⁴ profiles a second): one vectorised pass
  // with no branch per point (all_finite; AVX-512 where the CPU has it — the decision does not
  // depend on the order of summation). Only a failure runs the point-by-point search below,
  // which names the first offending point.
  static_assert(sizeof(Point2) == 2 * sizeof(double), "Point2 must be two packed doubles");
  const bool finite =
      all_finite(reinterpret_cast<const double*>(points.data()), 2 * points.size());
  for (std::size_t i = 0; !finite && i < points.size(); ++i) {
    if (!std::isfinite(points[i].x) || !std::isfinite(points[i].y)) {
      std::ostringstream os;
      os << caller << ": point " << i << " has a non-finite coordinate (x = " << points[i].x
         << ", y = " << points[i].y << ")";
      throw InvalidInput(os.str());
    }
  }
  internal::validate_profile_shape(points, min_points, caller, require_non_collinear);
}

void internal::validate_profile_shape(std::span<const Point2> points, std::size_t min_points,
                                      const char* caller, bool require_non_collinear) {
  if (points.empty()) return;
  // A second distinct point, then (optionally) a point off their line — exact predicates.
  std::size_t j = 1;
  while (j < points.size() && points[j] == points[0]) ++j;
  if (j == points.size()) {
    if (min_points <= 1) return;
    std::ostringstream os;
    os << caller << ": all " << points.size() << " points are identical (x = "
       << points[0].x << ", y = " << points[0].y << ")";
    throw InvalidInput(os.str());
  }
  if (!require_non_collinear) return;
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  const K::Point_2 a(points[0].x, points[0].y), b(points[j].x, points[j].y);
  for (std::size_t k = j + 1; k < points.size(); ++k) {
    if (CGAL::orientation(a, b, K::Point_2(points[k].x, points[k].y)) != CGAL::COLLINEAR)
      return;
  }
  std::ostringstream os;
  os << caller << ": all " << points.size()
     << " points are collinear (exact test): no circle can be fitted";
  throw InvalidInput(os.str());
}

}  // namespace vcmm::geometry
