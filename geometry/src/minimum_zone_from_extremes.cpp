// minimum_zone_from_extremes.cpp — RONt about the minimum-zone circle of a smooth closed
// profile computed exactly from a subset of its points (vcmm/geometry/minimum_zone_from_extremes.h:
// the argument, the subset, the rounds).
#include "vcmm/geometry/minimum_zone_from_extremes.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <string>

#include "vcmm/geometry/minimum_zone.h"

namespace vcmm::geometry {
namespace {

/// Neighbours taken on either side of a peak or valley: the reference's centre shift tilts the
/// profile by a harmonic 1, which moves an extremum of a profile sampled ≥ 8 points per
/// shortest wavelength (the filtered band) by less than a sample; two are a margin. (Only the
/// speed depends on it: the check below makes the result exact for any starting subset.)
constexpr std::size_t kNeighbours = 2;
/// Relative rounding of a squared distance and of a squared radius a few ulps from exact:
/// 1e-14 (~45 ulps) of r² is 4e-13 mm of radius at r = 85 mm, below what any RONt resolves.
constexpr double kRoundingOfSquares = 1e-14;

}  // namespace

double minimum_zone_ront_from_extremes(std::span<const Point2> points,
                                       std::span<const double> d, MinimumZoneScratch& scratch) {
  const std::size_t n = points.size();
  if (d.size() != n || n < 8)
    throw InvalidInput("minimum_zone_ront_from_extremes: expected at least 8 points and "
                                 "one deviation per point; got " + std::to_string(n) +
                                 " points and " + std::to_string(d.size()) + " deviations");
  std::vector<Point2>& subset = scratch.subset;
  std::vector<unsigned char>& member = scratch.member;
  std::vector<double>& flag = scratch.flag;
  std::vector<double>& r2 = scratch.squared_distance;
  member.assign(n, 0);
  flag.resize(n);
  subset.clear();
  // Peaks of v at or above `top` and valleys at or below `bottom` (cyclic), each joining S with
  // its neighbours; returns how many of them were not in S yet. The indicator
  // max(min(x − a, x − b, x − top), min(a − x, b − x, bottom − x)) ≥ 0 (a, b the neighbours'
  // values) is min/max arithmetic, which the compiler vectorises (comparisons into flags it
  // does not, and this pass is most of the function's own time).
  const auto take_extremes = [&](const double* v, double top, double bottom) {
    const auto indicator = [top, bottom](double x, double a, double b) {
      return std::max(std::min(std::min(x - a, x - b), x - top),
                      std::min(std::min(a - x, b - x), bottom - x));
    };
    double* __restrict f = flag.data();
    f[0] = indicator(v[0], v[n - 1], v[1]);
    for (std::size_t j = 1; j + 1 < n; ++j) f[j] = indicator(v[j], v[j - 1], v[j + 1]);
    f[n - 1] = indicator(v[n - 1], v[n - 2], v[0]);
    std::size_t taken = 0;
    constexpr std::size_t kBlock = 8;  // one well-predicted branch per block of 8 values
    for (std::size_t j = 0; j < n; ++j) {
      if (j % kBlock == 0 && j + kBlock <= n) {
        double m = f[j];
        for (std::size_t i = 1; i < kBlock; ++i) m = std::max(m, f[j + i]);
        if (m < 0.0) {
          j += kBlock - 1;
          continue;
        }
      }
      if (f[j] < 0.0) continue;
      taken += member[j] ? 0 : 1;
      for (std::size_t k = n + j - kNeighbours; k <= n + j + kNeighbours; ++k) {
        if (!member[k % n]) {
          member[k % n] = 1;
          subset.push_back(points[k % n]);
        }
      }
    }
    return taken;
  };
  {
    const auto [lo, hi] = std::minmax_element(d.begin(), d.end());
    const double band = 0.25 * (*hi - *lo);
    take_extremes(d.data(), *hi - band, *lo + band);
  }
  r2.resize(n);
  constexpr int kRounds = 6;
  for (int round = 0; round < kRounds && subset.size() >= 8; ++round) {
    const auto mz = minimum_zone_circle(subset);
    const double cx = mz.center.x, cy = mz.center.y;
    for (std::size_t j = 0; j < n; ++j) {
      const double dx = points[j].x - cx, dy = points[j].y - cy;
      r2[j] = dx * dx + dy * dy;
    }
    const Eigen::Map<const Eigen::ArrayXd> all(r2.data(), static_cast<Eigen::Index>(n));
    const double r2_hi = all.maxCoeff(), r2_lo = all.minCoeff();
    // Every point in the annulus, to the rounding of r² (its contacts, members of S, lie on
    // it to a few ulps): S's zone is the zone of all points.
    const double inner2 = mz.inner_radius * mz.inner_radius;
    const double outer2 = mz.outer_radius * mz.outer_radius;
    if (r2_hi <= outer2 * (1.0 + kRoundingOfSquares) &&
        r2_lo >= inner2 * (1.0 - kRoundingOfSquares))
      return std::sqrt(r2_hi) - std::sqrt(r2_lo);
    // Else the violated lobes' extremes join S.
    if (take_extremes(r2.data(), outer2, inner2) == 0)  // violations at rounding level only
      return std::sqrt(r2_hi) - std::sqrt(r2_lo);
  }
  return minimum_zone_circle(points).ron.ront;
}

}  // namespace vcmm::geometry
