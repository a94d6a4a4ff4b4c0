// internal/verify_inscribed_cover.cpp — see verify_inscribed_cover.h for the derivation.
#include "internal/verify_inscribed_cover.h"

#include <CGAL/Interval_nt.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <vector>

namespace vcmm::geometry::internal {
namespace {

using IA = CGAL::Interval_nt<true>;

/// The largest squared step (an upper bound) of the closed walk through points[order[k]],
/// when every step turns the same way about c, certainly; none otherwise. Repeated points
/// are skipped.
template <class At>
std::optional<double> max_step2(std::size_t n, At at, const ApproxCentre& c) {
  std::size_t kept = 0;
  int turn = 0;
  double longest = 0.0;
  Point2 first{}, prev{};
  auto step = [&](Point2 p, Point2 q) {
    const int o = certain_orientation(c, p, q);
    if (o == 0 || (turn != 0 && o != turn)) return false;
    turn = o;
    const double dx = q.x - p.x, dy = q.y - p.y;
    longest = std::max(longest, dx * dx + dy * dy);
    return true;
  };
  for (std::size_t k = 0; k < n; ++k) {
    const Point2 q = at(k);
    if (kept > 0 && q == prev) continue;
    if (kept > 0 && !step(prev, q)) return std::nullopt;
    if (kept == 0) first = q;
    prev = q;
    ++kept;
  }
  if (kept < 3 || prev == first || !step(prev, first)) return std::nullopt;
  // fl(dx² + dy²) of exactly computed... dx, dy carry one rounding each: relative error of
  // the square sum ≤ 5u (1 + u)ⁿ; 8u and an absolute term for subnormals cover it.
  return longest * (1.0 + 8.0 * 0x1p-53) + 4.0 * DBL_MIN;
}

IA enclose(std::pair<double, double> v) { return IA(v.first, v.second); }

}  // namespace

bool disks_cover_inscribed(std::span<const Point2> points, const ApproxCentre& c,
                           const InscribedCoverInput& in) {
  if (!verify_filter_enabled() || !std::isfinite(c.delta)) return false;
  std::optional<double> l2 =
      max_step2(points.size(), [&](std::size_t k) { return points[k]; }, c);
  if (!l2) {
    // Not a polygon winding about c in input order: try the order of angles about c̃.
    std::vector<double> angle(points.size());
    for (std::size_t k = 0; k < points.size(); ++k)
      angle[k] = std::atan2(points[k].y - c.y, points[k].x - c.x);
    std::vector<std::size_t> order(points.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return angle[a] < angle[b]; });
    l2 = max_step2(points.size(), [&](std::size_t k) { return points[order[k]]; }, c);
    if (!l2) return false;
  }
  const IA r2 = enclose(in.inner2);
  const IA gamma2 = enclose(in.gamma2);
  if (r2.inf() <= 0.0 || gamma2.inf() < 0.0) return false;
  const IA r = CGAL::sqrt(r2);
  const IA big_r = CGAL::sqrt(enclose(in.outer2));
  const IA spread2 = enclose(in.outer_minus_inner2);  // R² − r²
  // cos(α/2) ≥ √(1 − L²/(4r²)) for every wedge.
  const IA cos2 = IA(1) - IA(*l2) / (IA(4) * r2);
  if (!(cos2.inf() > 0.0)) return false;
  const IA half_cos = IA(CGAL::sqrt(IA(cos2.inf())).inf());  // a lower bound, as a point
  // The corners: t = 2γ (a lower bound) and t = R (an upper bound); ρ = r and ρ = R.
  const IA t_low = IA((IA(2) * CGAL::sqrt(gamma2)).inf());
  const IA t_high = IA(big_r.sup());
  for (const IA& t : {t_low, t_high}) {
    // f(t, r) − r² = t² − 2 t r cos;  f(t, R) − r² = t² + (R² − r²) − 2 t R cos.
    const IA at_inner = t * t - IA(2) * t * r * half_cos;
    const IA at_outer = t * t + spread2 - IA(2) * t * big_r * half_cos;
    if (!(at_inner.sup() <= 0.0) || !(at_outer.sup() <= 0.0)) return false;
  }
  return true;
}

}  // namespace vcmm::geometry::internal
