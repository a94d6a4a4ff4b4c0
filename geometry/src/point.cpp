#include "vcmm/geometry/point.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cmath>
#include <sstream>

namespace vcmm::geometry {

void validate_profile(std::span<const Point2> points, std::size_t min_points,
                      const char* caller, bool require_non_collinear) {
  if (points.size() < min_points) {
    std::ostringstream os;
    os << caller << ": needs at least " << min_points << " points; got " << points.size();
    throw InvalidInput(os.str());
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!std::isfinite(points[i].x) || !std::isfinite(points[i].y)) {
      std::ostringstream os;
      os << caller << ": point " << i << " has a non-finite coordinate (x = " << points[i].x
         << ", y = " << points[i].y << ")";
      throw InvalidInput(os.str());
    }
  }
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
