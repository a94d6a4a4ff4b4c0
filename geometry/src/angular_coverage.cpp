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
#include "internal/vec.h"

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
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
  std::size_t wrap = 0;    ///< the step across θ = ±π (from wrap to wrap + 1), if asked for
};

/// Pass 1: the walk, its directions (ws.x, ws.y) and step tangents (ws.t); nullopt when
/// the input does not qualify.
std::optional<Walk> angular_walk(std::span<const Point2> points, Point2 center,
                                 WalkScratch& ws, bool find_wrap = true) {
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
  // Pass 1, step i from direction a = d_i to b = d_{i+1}, t_i = |a × b| / (a · b): every
  // step certain (t in (1e-9, 1): then |a × b| > 7e-10 |a||b|, far above its rounding, and
  // the angle is in (7e-10, π/4)), no underflow (a · b > 2⁻⁹⁰⁰), one sign of a × b; kept as
  // extremes and a sum (NaN from non-finite input propagates into the sum).
  const Packet inf = simd::pset1<Packet>(std::numeric_limits<double>::infinity());
  Packet t_max = simd::pset1<Packet>(0.0), t_min = inf, dot_min = inf, t_sum = t_max;
  Packet cross_min = inf, cross_max = simd::pnegate(inf);
  const std::size_t packed = n - n % kLanes;
  for (std::size_t i = 0; i < packed; i += kLanes) {
    const Packet ax = simd::ploadu<Packet>(x + i), ay = simd::ploadu<Packet>(y + i);
    const Packet bx = simd::ploadu<Packet>(x + i + 1), by = simd::ploadu<Packet>(y + i + 1);
    const Packet cross = simd::psub(simd::pmul(ax, by), simd::pmul(ay, bx));
    const Packet dot = simd::padd(simd::pmul(ax, bx), simd::pmul(ay, by));
    const Packet ti = simd::pdiv(simd::pabs(cross), dot);
    simd::pstoreu(t + i, ti);
    t_max = simd::pmax(t_max, ti);
    t_min = simd::pmin(t_min, ti);
    t_sum = simd::padd(t_sum, ti);
    dot_min = simd::pmin(dot_min, dot);
    cross_min = simd::pmin(cross_min, cross);
    cross_max = simd::pmax(cross_max, cross);
  }
  double tm = simd::predux_max(t_max), tn = simd::predux_min(t_min), ts = simd::predux(t_sum);
  double dn = simd::predux_min(dot_min);
  double cn = simd::predux_min(cross_min), cm = simd::predux_max(cross_max);
  for (std::size_t i = packed; i < n; ++i) {
    const double cross = x[i] * y[i + 1] - y[i] * x[i + 1];
    const double dot = x[i] * x[i + 1] + y[i] * y[i + 1];
    const double ti = std::fabs(cross) / dot;
    t[i] = ti;
    tm = std::max(tm, ti);
    tn = std::min(tn, ti);
    ts += ti;
    dn = std::min(dn, dot);
    cn = std::min(cn, cross);
    cm = std::max(cm, cross);
  }
  // Once round: all steps turn one way, so the angles θ_i add up to 2πk, k ≥ 1; θ ≤ tan θ
  // makes Σ t < 4π (with a margin far above the sum's rounding) force k = 1.
  const bool ccw = cn > 0.0;
  if (!(tn > 1e-9 && tm < 1.0 && dn > 0x1.0p-900 && (ccw || cm < 0.0) &&
        ts < 2.0 * kTwoPi * (1.0 - 1e-6)))  // false on NaN
    return std::nullopt;
  if (!find_wrap) return Walk{ccw, tm, 0};
  // The wrap: in increasing angle, the one step from the upper half (atan2 in [+0, π]: sign
  // bit of y clear) into the lower one (sign bit set, −0 included: atan2(−0, x < 0) = −π).
  // Four steps a test on the sign bits (the first block holding it), then the step itself.
  std::size_t i = 0;
  {
    using M4 = internal::VecOf<4>::mask;  // internal/vec.h
    for (; i + 4 <= n; i += 4) {
      M4 a, b;  // the bits of y_i … y_{i+3} and y_{i+1} … y_{i+4}
      std::memcpy(&a, y + i, sizeof a);
      std::memcpy(&b, y + i + 1, sizeof b);
      const M4 hit = ccw ? (~a & b) : (a & ~b);  // sign bit: this step is the wrap
      if (((hit[0] | hit[1]) | (hit[2] | hit[3])) < 0) break;
    }
  }
  for (; i < n; ++i) {
    const bool a_upper = !std::signbit(y[i]), b_upper = !std::signbit(y[i + 1]);
    if (ccw ? (a_upper && !b_upper) : (!a_upper && b_upper)) return Walk{ccw, tm, i};
  }
  return std::nullopt;  // not reached: a walk once round crosses θ = ±π once
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
  const std::optional<Walk> walk = angular_walk(points, center, scratch, /*find_wrap=*/false);
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
