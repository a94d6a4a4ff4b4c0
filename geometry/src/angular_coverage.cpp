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
#include "internal/angular_walk.h"

#include <Eigen/Core>

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
constexpr double kQuarterTurn = 0.25 * std::numbers::pi;
/// Candidate margin on t = tan(step) (see the top): 2⁻⁴⁶ ≈ 1.4e-14.
constexpr double kTanMargin = 0x1.0p-46;

// Pass 1 runs on Eigen's SIMD packets (2 doubles with SSE2; as in least_squares.cpp): the
// compiler does not vectorise the division and the reductions by itself.
namespace simd = Eigen::internal;
using Packet = simd::packet_traits<double>::type;
constexpr std::size_t kLanes = simd::packet_traits<double>::size;

/// Per-thread scratch arrays, kept between calls (no allocation per call).
struct WalkScratch {
  std::vector<double> x, y, t;       // directions p_i − c (x, y: n + 1, closing copy) and t
  std::vector<std::size_t> candidate;  // steps that can be the largest gap, ascending
};

thread_local WalkScratch scratch;

/// A closed walk once round the centre (pass 1 of the fast path, described at the top).
struct Walk {
  bool ccw = true;         ///< counter-clockwise in input order
  double t_max = 0.0;      ///< tan of the longest step
  std::size_t wrap = 0;    ///< the step across θ = ±π (in input order: from wrap to wrap + 1)
};

/// Pass 1: the walk, its directions (ws.x, ws.y) and step tangents (ws.t); nullopt when
/// the input does not qualify.
std::optional<Walk> angular_walk(std::span<const Point2> points, Point2 center,
                                 WalkScratch& ws) {
  const std::size_t n = points.size();
  if (n < 3) return std::nullopt;
  ws.x.resize(n + 1);
  ws.y.resize(n + 1);
  ws.t.resize(n);
  double* x = ws.x.data();
  double* y = ws.y.data();
  double* t = ws.t.data();
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = points[i].x - center.x;
    y[i] = points[i].y - center.y;
  }
  x[n] = x[0];
  y[n] = y[0];
  // Pass 1, step i from direction a = d_i to b = d_{i+1}: every step certain (t in (1e-9, 1):
  // then |a × b| > 7e-10 |a||b|, far above its rounding, and the angle is in (7e-10, π/4)),
  // no underflow (a · b > 2⁻⁹⁰⁰), the same turn; t of each step; the crossings of θ = π
  // (upper half y ≥ 0 to lower y < 0, or back) and the last step where each happens.
  const Packet zero = simd::pset1<Packet>(0.0), one = simd::pset1<Packet>(1.0);
  const Packet t_min = simd::pset1<Packet>(1e-9), dot_min = simd::pset1<Packet>(0x1.0p-900);
  const Packet all = simd::ptrue(zero);
  Packet bad = zero, negative = zero, positive = zero, downs = zero, ups = zero;
  Packet last_down = simd::pset1<Packet>(-1.0), last_up = last_down, t_max = zero;
  Packet index = simd::plset<Packet>(0.0);
  const Packet lanes = simd::pset1<Packet>(static_cast<double>(kLanes));
  const std::size_t packed = n - n % kLanes;
  for (std::size_t i = 0; i < packed; i += kLanes) {
    const Packet ax = simd::ploadu<Packet>(x + i), ay = simd::ploadu<Packet>(y + i);
    const Packet bx = simd::ploadu<Packet>(x + i + 1), by = simd::ploadu<Packet>(y + i + 1);
    const Packet cross = simd::psub(simd::pmul(ax, by), simd::pmul(ay, bx));
    const Packet dot = simd::padd(simd::pmul(ax, bx), simd::pmul(ay, by));
    const Packet ti = simd::pdiv(simd::pabs(cross), dot);
    simd::pstoreu(t + i, ti);
    const Packet good = simd::pand(simd::pand(simd::pcmp_lt(t_min, ti), simd::pcmp_lt(ti, one)),
                                   simd::pcmp_lt(dot_min, dot));  // false on NaN
    bad = simd::por(bad, simd::pandnot(all, good));
    negative = simd::por(negative, simd::pcmp_lt(cross, zero));
    positive = simd::por(positive, simd::pcmp_lt(zero, cross));
    const Packet down = simd::pand(simd::pcmp_le(zero, ay), simd::pcmp_lt(by, zero));
    const Packet up = simd::pand(simd::pcmp_lt(ay, zero), simd::pcmp_le(zero, by));
    downs = simd::padd(downs, simd::pand(down, one));
    ups = simd::padd(ups, simd::pand(up, one));
    last_down = simd::pselect(down, index, last_down);
    last_up = simd::pselect(up, index, last_up);
    t_max = simd::pmax(t_max, ti);
    index = simd::padd(index, lanes);
  }
  bool ok = !simd::predux_any(bad);
  bool any_negative = simd::predux_any(negative), any_positive = simd::predux_any(positive);
  double down_count = simd::predux(downs), up_count = simd::predux(ups);
  double down_at = simd::predux_max(last_down), up_at = simd::predux_max(last_up);
  double tm = simd::predux_max(t_max);
  for (std::size_t i = packed; i < n; ++i) {
    const double cross = x[i] * y[i + 1] - y[i] * x[i + 1];
    const double dot = x[i] * x[i + 1] + y[i] * y[i + 1];
    const double ti = std::fabs(cross) / dot;
    t[i] = ti;
    ok = ok && ti > 1e-9 && ti < 1.0 && dot > 0x1.0p-900;
    any_negative = any_negative || cross < 0.0;
    any_positive = any_positive || cross > 0.0;
    if (y[i] >= 0.0 && y[i + 1] < 0.0) {
      down_count += 1.0;
      down_at = static_cast<double>(i);
    }
    if (y[i] < 0.0 && y[i + 1] >= 0.0) {
      up_count += 1.0;
      up_at = static_cast<double>(i);
    }
    tm = std::max(tm, ti);
  }
  // Once round: one crossing of θ = ±π in the sense of the walk (a counter-clockwise walk
  // goes from the upper half to the lower only there, a clockwise one the other way).
  const bool ccw = !any_negative;
  if (!ok || (any_negative && any_positive) || (ccw ? down_count : up_count) != 1.0)
    return std::nullopt;
  return Walk{ccw, tm, static_cast<std::size_t>(ccw ? down_at : up_at)};
}

/// The fast path described at the top; nullopt when the walk does not qualify.
std::optional<AngularCoverage> coverage_of_angular_walk(std::span<const Point2> points,
                                                       Point2 center) {
  WalkScratch& ws = scratch;
  const std::optional<Walk> walk = angular_walk(points, center, ws);
  if (!walk) return std::nullopt;
  const std::size_t n = points.size();
  const bool ccw = walk->ccw;
  const double tm = walk->t_max;
  const std::size_t wrap = walk->wrap;
  const double* x = ws.x.data();
  const double* y = ws.y.data();
  const double* t = ws.t.data();
  // Pass 2: the candidates; beyond n / 4 of them (many steps equal to the last few ulps, e.g.
  // an exact equiangular ring about its own centre) the general path's n atan2 cost less.
  const double threshold = tm - kTanMargin;
  ws.candidate.clear();
  for (std::size_t s = 0; s < n; ++s) {
    if (t[s] < threshold) continue;
    if (ws.candidate.size() == n / 4) return std::nullopt;
    ws.candidate.push_back(s);
  }
  // Step s joins points s and s + 1; in increasing angle it runs from `from(s)` to `to(s)`.
  // The wrap step (across θ = ±π, from the upper half into the lower in increasing angle) is
  // where the general path's order starts and ends.
  const auto next = [n](std::size_t i) { return i + 1 == n ? 0 : i + 1; };
  const auto from = [&](std::size_t s) { return ccw ? s : next(s); };
  const auto to = [&](std::size_t s) { return ccw ? next(s) : s; };
  const auto angle = [&](std::size_t i) { return std::atan2(y[i], x[i]); };
  // Pass 3, the general path's scan: the wrap gap first, then the candidate gaps in
  // increasing angle, strict ">". Increasing angle is input order from the wrap onwards,
  // backwards for a clockwise walk.
  AngularCoverage c;
  const double lo = angle(to(wrap)), hi = angle(from(wrap));
  c.largest_gap_rad = lo + kTwoPi - hi;
  c.gap_start_rad = hi;
  c.gap_start_index = from(wrap);
  c.gap_end_index = to(wrap);
  const auto consider = [&](std::size_t s) {
    if (s == wrap) return;
    const double a = angle(from(s)), b = angle(to(s));
    if (b - a > c.largest_gap_rad) {
      c.largest_gap_rad = b - a;
      c.gap_start_rad = a;
      c.gap_start_index = from(s);
      c.gap_end_index = to(s);
    }
  };
  const std::vector<std::size_t>& k = ws.candidate;
  const auto split = static_cast<std::size_t>(  // first candidate after the wrap
      std::upper_bound(k.begin(), k.end(), wrap) - k.begin());
  if (ccw) {
    for (std::size_t j = split; j < k.size(); ++j) consider(k[j]);
    for (std::size_t j = 0; j < split; ++j) consider(k[j]);
  } else {
    for (std::size_t j = split; j-- > 0;) consider(k[j]);
    for (std::size_t j = k.size(); j-- > split;) consider(k[j]);
  }
  c.covered_rad = kTwoPi - c.largest_gap_rad;
  c.closed = c.largest_gap_rad <= 3.0 * kTwoPi / static_cast<double>(n);
  return c;
}

}  // namespace

bool internal::has_angular_steps_below(std::span<const Point2> points, Point2 center,
                                       double limit_rad) {
  const std::optional<Walk> walk = angular_walk(points, center, scratch);
  // t_max < tan(limit) with both sides good to a few ulps: a margin of 1e-6 relative.
  return walk && walk->t_max < (1.0 - 1e-6) * std::tan(std::min(limit_rad, kQuarterTurn));
}

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
