#include "vcmm/geometry/point.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <Eigen/Core>

#include <cmath>
#include <sstream>

#include "internal/prevalidated.h"

namespace vcmm::geometry {

void validate_profile(std::span<const Point2> points, std::size_t min_points,
                      const char* caller, bool require_non_collinear) {
  if (points.size() < min_points) {
    std::ostringstream os;
    os << caller << ": needs at least " << min_points << " points; got " << points.size();
    throw InvalidInput(os.str());
  }
  // Fast path (the Monte Carlo loop validates ~10⁴ profiles a second): v·0 is 0 for finite
  // v and NaN for NaN or ±inf, so the sum of every coordinate times 0 is 0 exactly when all
  // are finite — one vectorised pass with no branch per point. Only a failure runs the
  // point-by-point search below, which names the first offending point.
  static_assert(sizeof(Point2) == 2 * sizeof(double), "Point2 must be two packed doubles");
  const Eigen::Map<const Eigen::ArrayXd> coordinates(
      reinterpret_cast<const double*>(points.data()), static_cast<Eigen::Index>(2 * points.size()));
  const bool all_finite = points.empty() || (coordinates * 0.0).sum() == 0.0;
  for (std::size_t i = 0; !all_finite && i < points.size(); ++i) {
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
