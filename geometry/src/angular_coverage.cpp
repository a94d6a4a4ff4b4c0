// angular_coverage.cpp — the largest gap between the directions of a profile's points.
//
// General path: θ_i = atan2(y_i − c_y, x_i − c_x) for every point, then the largest gap
// between neighbours in angular order by pigeonhole buckets (O(n), no sort).
//
// Fast path (coverage_of_angular_walk): most profiles are scans given in angular order. When
// the input, walked as a closed polygon, turns about the centre the same way at every step by
// a certain angle in (1e-9, π/4) rad and winds round it exactly once, the angular order is the
// input order (cyclically; reversed for a clockwise walk), so the gaps are the steps. The
// result must equal the general path's bit for bit, and that path's gaps are differences of
// rounded atan2 values, so the step angles are not used as gaps; they only select the steps
// that can be the largest gap. With t = |a × b| / (a · b) = tan of the step angle (monotone
// on [0, π/4], where dθ/dt = cos²θ ≥ 1/2; t itself is good to a few ulps of the angle), a
// step with t < t_max − Δ is at least Δ/2 = 2⁻⁴⁷ ≈ 7e-15 rad shorter than the longest one:
// more than the error of a difference of two atan2 values (glibc: < 1 ulp each, ≤ 4.4e-16
// rad for |θ| ≤ π; with 2 ulp assumed, ≤ 1.8e-15 rad for the difference), so its rounded gap
// cannot be the largest. Only the candidates (t ≥ t_max − Δ) and the wrap step (across
// θ = ±π, where the general path's order starts) get their atan2; the general path's tie
// rule (the wrap first, then the first gap in increasing angle; strict ">") is applied to them
// in angular order. Every step angle ≥ 1e-9 rad also makes the atan2 values strictly
// increasing along the walk (no equal angles, so no index ties). A real scan has a few
// candidates (the gaps differ by the coordinates' rounding and the centre's offset); when
// more than n/4 steps tie (an exactly equiangular ring about its own centre) or a step fails
// the tests, the general path runs.
#include "vcmm/geometry/angular_coverage.h"

#include <algorithm>
#include <cstddef>
#include <cmath>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace vcmm::geometry {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
/// Candidate margin on t = tan(step) (see the top): 2⁻⁴⁶ ≈ 1.4e-14.
constexpr double kTanMargin = 0x1.0p-46;

/// The fast path described at the top; nullopt when the walk does not qualify.
std::optional<AngularCoverage> coverage_of_angular_walk(std::span<const Point2> points,
                                                       Point2 center) {
  const std::size_t n = points.size();
  if (n < 3) return std::nullopt;
  const auto dir = [&](std::size_t i) {
    return Point2{points[i].x - center.x, points[i].y - center.y};
  };
  // Pass 1: every step certain, the same turn, t < 1; t of each step (kept for pass 2); the
  // crossings of θ = π (the upper half y ≥ 0 to the lower y < 0, or back).
  thread_local std::vector<double> tan_step;  // reused: no allocation per call
  tan_step.resize(n);
  bool ok = true;
  std::size_t positive = 0, up_to_down = 0, down_to_up = 0, last_down = 0, last_up = 0;
  double t_max = 0.0;
  const auto step = [&](std::size_t i, Point2 a, Point2 b) {
    const double cross = a.x * b.y - a.y * b.x, dot = a.x * b.x + a.y * b.y;
    const double norms = (a.x * a.x + a.y * a.y) * (b.x * b.x + b.y * b.y);
    const double t = std::fabs(cross) / dot;
    ok &= (cross * cross > 1e-18 * norms) & (t < 1.0) & (dot > 0.0);  // false on NaN
    positive += cross > 0.0;
    const bool down = (a.y >= 0.0) & (b.y < 0.0), up = (a.y < 0.0) & (b.y >= 0.0);
    up_to_down += down;
    down_to_up += up;
    last_down = down ? i : last_down;
    last_up = up ? i : last_up;
    tan_step[i] = t;
    t_max = std::max(t_max, t);
  };
  for (std::size_t i = 0; i + 1 < n; ++i) step(i, dir(i), dir(i + 1));
  step(n - 1, dir(n - 1), dir(0));
  const bool ccw = positive == n;
  // Once round: one crossing of θ = ±π in the sense of the walk (a counter-clockwise walk
  // goes from the upper half to the lower only there, a clockwise one the other way).
  if (!ok || !(ccw || positive == 0) || (ccw ? up_to_down : down_to_up) != 1)
    return std::nullopt;
  // Pass 2: how many candidates; beyond n / 4 (many steps equal to the last few ulps, e.g. an
  // exact equiangular ring about its own centre) the general path's n atan2 cost less.
  const double threshold = t_max - kTanMargin;
  std::size_t count = 0;
  for (std::size_t s = 0; s < n; ++s) count += tan_step[s] >= threshold;
  if (count > n / 4) return std::nullopt;
  // Step s joins points s and s + 1; in increasing angle it runs from `from(s)` to `to(s)`.
  // The wrap step (across θ = ±π, from the upper half into the lower in increasing angle) is
  // where the general path's order starts and ends.
  const auto next = [n](std::size_t i) { return i + 1 == n ? 0 : i + 1; };
  const auto from = [&](std::size_t s) { return ccw ? s : next(s); };
  const auto to = [&](std::size_t s) { return ccw ? next(s) : s; };
  const std::size_t wrap = ccw ? last_down : last_up;
  const auto angle = [&](std::size_t i) {
    const Point2 d = dir(i);
    return std::atan2(d.y, d.x);
  };
  // Pass 3, the general path's scan: the wrap gap first, then the candidate gaps in
  // increasing angle (input order from the wrap, backwards for a clockwise walk), strict ">".
  AngularCoverage c;
  const double lo = angle(to(wrap)), hi = angle(from(wrap));
  c.largest_gap_rad = lo + kTwoPi - hi;
  c.gap_start_rad = hi;
  c.gap_start_index = from(wrap);
  c.gap_end_index = to(wrap);
  for (std::size_t r = 1, s = wrap; r < n; ++r) {
    s = ccw ? next(s) : (s == 0 ? n - 1 : s - 1);
    if (tan_step[s] < threshold) continue;
    const double a = angle(from(s)), b = angle(to(s));
    if (b - a > c.largest_gap_rad) {
      c.largest_gap_rad = b - a;
      c.gap_start_rad = a;
      c.gap_start_index = from(s);
      c.gap_end_index = to(s);
    }
  }
  c.covered_rad = kTwoPi - c.largest_gap_rad;
  c.closed = c.largest_gap_rad <= 3.0 * kTwoPi / static_cast<double>(n);
  return c;
}

}  // namespace

AngularCoverage angular_coverage(std::span<const Point2> points, Point2 center) {
  const std::size_t n = points.size();
  if (n < 2) {
    std::ostringstream os;
    os << "angular_coverage: needs at least 2 points; got " << n;
    throw InvalidInput(os.str());
  }
  if (!(std::isfinite(center.x) && std::isfinite(center.y)))
    throw InvalidInput("angular_coverage: the centre must be finite");
  if (const auto c = coverage_of_angular_walk(points, center)) return *c;
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
