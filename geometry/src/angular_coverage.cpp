// angular_coverage.cpp — the largest gap between the directions of a profile's points.
#include "vcmm/geometry/angular_coverage.h"

#include <algorithm>
#include <cstddef>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace vcmm::geometry {

AngularCoverage angular_coverage(std::span<const Point2> points, Point2 center) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  const std::size_t n = points.size();
  if (n < 2) {
    std::ostringstream os;
    os << "angular_coverage: needs at least 2 points; got " << n;
    throw InvalidInput(os.str());
  }
  if (!(std::isfinite(center.x) && std::isfinite(center.y)))
    throw InvalidInput("angular_coverage: the centre must be finite");
  // Directions of the points not at the centre; `index` maps back to the input.
  std::vector<double> angle;
  std::vector<std::size_t> index;
  angle.reserve(n);
  index.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = points[i].x - center.x, dy = points[i].y - center.y;
    if (!(std::isfinite(dx) && std::isfinite(dy))) {
      std::ostringstream os;
      os << "angular_coverage: point " << i << " has a non-finite coordinate";
      throw InvalidInput(os.str());
    }
    if (dx == 0.0 && dy == 0.0) continue;  // no direction
    angle.push_back(std::atan2(dy, dx));
    index.push_back(i);
  }
  if (angle.size() < 2)
    throw InvalidInput("angular_coverage: needs at least 2 points away from the centre; got " +
                       std::to_string(angle.size()));
  // The largest gap in O(n) (the maximum-gap problem, pigeonhole buckets): with n + 1
  // buckets over [θ_min, θ_max] one bucket stays empty, so the largest gap between
  // neighbours is at least a bucket wide and lies between the maximum of one non-empty bucket
  // and the minimum of the next one (never inside a bucket); plus the wrap-around gap.
  const std::size_t m = angle.size();
  const auto [lo_it, hi_it] = std::minmax_element(angle.begin(), angle.end());
  const double lo = *lo_it, hi = *hi_it;
  const std::size_t lo_index = static_cast<std::size_t>(lo_it - angle.begin());
  const std::size_t hi_index = static_cast<std::size_t>(hi_it - angle.begin());
  AngularCoverage c;
  c.largest_gap_rad = lo + kTwoPi - hi;  // the wrap: from the largest angle round to the smallest
  c.gap_start_rad = hi;
  c.gap_start_index = hi_index;
  c.gap_end_index = lo_index;
  if (hi > lo) {
    const std::size_t buckets = m + 1;
    const double width = (hi - lo) / static_cast<double>(buckets);
    constexpr std::size_t kNone = static_cast<std::size_t>(-1);
    std::vector<std::size_t> bmin(buckets, kNone), bmax(buckets, kNone);
    for (std::size_t i = 0; i < m; ++i) {
      auto b = static_cast<std::size_t>((angle[i] - lo) / width);
      if (b >= buckets) b = buckets - 1;
      // Ties: the lowest index, so the result does not depend on the input order of equal
      // directions beyond their indices.
      if (bmin[b] == kNone || angle[i] < angle[bmin[b]] ||
          (angle[i] == angle[bmin[b]] && i < bmin[b]))
        bmin[b] = i;
      if (bmax[b] == kNone || angle[i] > angle[bmax[b]] ||
          (angle[i] == angle[bmax[b]] && i < bmax[b]))
        bmax[b] = i;
    }
    std::size_t previous = kNone;  // the last non-empty bucket's maximum
    for (std::size_t b = 0; b < buckets; ++b) {
      if (bmin[b] == kNone) continue;
      if (previous != kNone) {
        const double gap = angle[bmin[b]] - angle[previous];
        if (gap > c.largest_gap_rad) {
          c.largest_gap_rad = gap;
          c.gap_start_rad = angle[previous];
          c.gap_start_index = previous;
          c.gap_end_index = bmin[b];
        }
      }
      previous = bmax[b];
    }
  }
  c.covered_rad = kTwoPi - c.largest_gap_rad;
  c.gap_start_index = index[c.gap_start_index];
  c.gap_end_index = index[c.gap_end_index];
  c.closed = c.largest_gap_rad <= 3.0 * kTwoPi / static_cast<double>(angle.size());
  return c;
}

}  // namespace vcmm::geometry
