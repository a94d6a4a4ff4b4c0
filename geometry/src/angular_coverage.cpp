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

#include "vcmm/internal/simd_clones.h"

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

// Pass 1 is one kernel over the points themselves (no copy of the directions): eight steps
// a lane-wise GCC vector, compiled for AVX-512, AVX2 and the baseline (runtime dispatch,
// vcmm/internal/simd_clones.h). Every lane computes the scalar expressions (the project is
// compiled with -ffp-contract=off), so the tangents t_i — the only values that reach the
// result, through the choice of candidates — are the same bits on every machine; max and min
// are exact in any order, and the sum (a qualification test with a 1e-6 margin) is taken in a
// fixed order of eight partial sums whatever the variant.
#pragma GCC diagnostic ignored "-Wpsabi"  // 64-byte vectors inside the always-inlined kernel
using V8 = double __attribute__((vector_size(64)));
using M8 = long long __attribute__((vector_size(64)));

/// Per-thread scratch arrays, kept between calls (no allocation per call).
struct WalkScratch {
  std::vector<double> t;               // step tangents
  std::vector<std::size_t> candidate;  // steps that can be the largest gap, ascending
};

thread_local WalkScratch scratch;

/// What pass 1 keeps besides the tangents: their extremes and sum, the smallest a · b, the
/// turn of the first step (`ccw`: a × b > 0; every tangent is taken with the sign that makes
/// it positive for that turn, so a step turning the other way, or not at all, has t ≤ 0),
/// and the sum of the indices of the steps crossing θ = ±π in increasing angle for that
/// turn (from the upper half-plane into the lower one for `ccw` — the sign bit of y clear at
/// the step's start, set at its end — the other way round otherwise): the wrap step's index
/// when there is exactly one.
struct StepSummary {
  double t_max, t_min, t_sum, dot_min;
  bool ccw;
  std::size_t wrap_sum;
};

[[gnu::always_inline]] inline V8 vmax(V8 a, V8 b) { return a > b ? a : b; }
[[gnu::always_inline]] inline V8 vmin(V8 a, V8 b) { return a < b ? a : b; }

/// Pass 1 over the steps of the closed walk (step i from d_i = p_i − c to d_{i+1}, d_n = d_0):
/// t_i = |a × b| / (a · b) into t[0, n) and the summary. n ≥ 3.
VCMM_SIMD_CLONES void walk_steps(const Point2* p, std::size_t n, Point2 c, double* t,
                                 StepSummary& out) {
  static_assert(sizeof(Point2) == 2 * sizeof(double), "Point2: two packed doubles");
  const double* xy = reinterpret_cast<const double*>(p);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const V8 cx = V8{} + c.x, cy = V8{} + c.y;
  V8 t_max = V8{}, t_min = V8{} + kInf, t_sum = V8{}, dot_min = V8{} + kInf;
  // The first step's turn (the loop's expressions): flip = the sign bit when clockwise.
  const double cross0 =
      (p[0].x - c.x) * (p[1].y - c.y) - (p[0].y - c.y) * (p[1].x - c.x);
  const bool ccw = cross0 > 0.0;
  const long long flip = ccw ? 0 : std::numeric_limits<long long>::min();
  const M8 vflip = M8{} + flip;
  M8 wraps = M8{};
  M8 at = M8{0, 1, 2, 3, 4, 5, 6, 7};
  const M8 even = {0, 2, 4, 6, 8, 10, 12, 14}, odd = {1, 3, 5, 7, 9, 11, 13, 15};
  std::size_t i = 0;
  // Steps i … i + 7 read points i … i + 8: whole blocks while i + 8 < n.
  for (; i + 8 < n; i += 8) {
    V8 a0, a1, b0, b1;
    std::memcpy(&a0, xy + 2 * i, sizeof a0);
    std::memcpy(&a1, xy + 2 * i + 8, sizeof a1);
    std::memcpy(&b0, xy + 2 * i + 2, sizeof b0);
    std::memcpy(&b1, xy + 2 * i + 10, sizeof b1);
    const V8 ax = __builtin_shuffle(a0, a1, even) - cx, ay = __builtin_shuffle(a0, a1, odd) - cy;
    const V8 bx = __builtin_shuffle(b0, b1, even) - cx, by = __builtin_shuffle(b0, b1, odd) - cy;
    const V8 cross = ax * by - ay * bx;
    const V8 dot = ax * bx + ay * by;
    M8 bits;  // a × b with the sign that is positive for the first step's turn
    std::memcpy(&bits, &cross, sizeof bits);
    bits ^= vflip;
    V8 turn;
    std::memcpy(&turn, &bits, sizeof turn);
    const V8 ti = turn / dot;
    std::memcpy(t + i, &ti, sizeof ti);
    t_max = vmax(t_max, ti);
    t_min = vmin(t_min, ti);
    t_sum += ti;
    dot_min = vmin(dot_min, dot);
    M8 sa, sb;  // sign bits of the y components (−0 has it set, as atan2 sees it)
    std::memcpy(&sa, &ay, sizeof sa);
    std::memcpy(&sb, &by, sizeof sb);
    // Crossing θ = ±π in increasing angle: down for ccw, up otherwise (all ones or zero).
    const M8 is_wrap = (~(sa ^ vflip) & (sb ^ vflip)) >> 63;
    wraps += is_wrap & at;
    at += 8;
  }
  double tm = 0.0, tn = kInf, ts = 0.0, dn = kInf;
  std::size_t wrap_sum = 0;
  for (int k = 0; k < 8; ++k) {
    tm = std::max(tm, t_max[k]);
    tn = std::min(tn, t_min[k]);
    ts += t_sum[k];
    dn = std::min(dn, dot_min[k]);
    wrap_sum += static_cast<std::size_t>(wraps[k]);
  }
  for (; i < n; ++i) {
    const std::size_t j = i + 1 == n ? 0 : i + 1;
    const double ax = p[i].x - c.x, ay = p[i].y - c.y, bx = p[j].x - c.x, by = p[j].y - c.y;
    const double cross = ax * by - ay * bx;
    const double dot = ax * bx + ay * by;
    const double ti = (ccw ? cross : -cross) / dot;
    t[i] = ti;
    tm = std::max(tm, ti);
    tn = std::min(tn, ti);
    ts += ti;
    dn = std::min(dn, dot);
    const bool a_upper = !std::signbit(ay), b_upper = !std::signbit(by);
    if (ccw ? a_upper && !b_upper : !a_upper && b_upper) wrap_sum += i;
  }
  // A NaN anywhere propagates into the sum (max and min may drop it).
  out = {tm, tn, ts, dn, ccw, wrap_sum};
}

/// The steps s with t[s] ≥ threshold, ascending, into `out`; false (out incomplete) when
/// there are more than `limit`. One compare per 32 steps (of their lane-wise maximum), the
/// rare blocks with a hit scanned step by step.
VCMM_SIMD_CLONES bool steps_at_least(const double* t, std::size_t n, double threshold,
                                     std::size_t limit, std::vector<std::size_t>& out) {
  out.clear();
  const V8 thr = V8{} + threshold;
  std::size_t s = 0;
  for (; s < n; s += 32) {
    if (s + 32 <= n) {
      V8 v[4];
      std::memcpy(v, t + s, sizeof v);
      const V8 m = vmax(vmax(v[0], v[1]), vmax(v[2], v[3]));
      const M8 hit = m >= thr;
      const M8 h4 = __builtin_shuffle(hit, M8{4, 5, 6, 7, 0, 1, 2, 3}) | hit;
      const M8 h2 = __builtin_shuffle(h4, M8{2, 3, 0, 1, 6, 7, 4, 5}) | h4;
      if (((__builtin_shuffle(h2, M8{1, 0, 3, 2, 5, 4, 7, 6}) | h2)[0]) == 0) continue;
    }
    for (std::size_t k = s; k < std::min(s + 32, n); ++k) {
      if (t[k] < threshold) continue;
      if (out.size() == limit) return false;
      out.push_back(k);
    }
  }
  return true;
}

/// A closed walk once round the centre (pass 1 of the fast path, described at the top).
struct Walk {
  bool ccw = true;         ///< counter-clockwise in input order
  double t_max = 0.0;      ///< tan of the longest step
  std::size_t wrap = 0;    ///< the step across θ = ±π (from wrap to wrap + 1)
};

/// Pass 1: the walk and its step tangents (ws.t); nullopt when the input does not qualify.
std::optional<Walk> angular_walk(std::span<const Point2> points, Point2 center,
                                 WalkScratch& ws) {
  const std::size_t n = points.size();
  if (n < 3) return std::nullopt;
  ws.t.resize(n);
  // Step i from direction a = d_i to b = d_{i+1}, t_i = |a × b| / (a · b): every step
  // certain (t in (1e-9, 1): then |a × b| > 7e-10 |a||b|, far above its rounding, and the
  // angle is in (7e-10, π/4)), no underflow (a · b > 2⁻⁹⁰⁰), one sign of a × b; kept as
  // extremes and a sum (NaN from non-finite input propagates into the sum).
  StepSummary s;
  walk_steps(points.data(), n, center, ws.t.data(), s);
  // One turn: every t (signed for the first step's turn) > 1e-9, so every step turns that
  // way. Once round: the angles θ_i add up to 2πk, k ≥ 1; θ ≤ tan θ makes Σ t < 4π (with a
  // margin far above the sum's rounding) force k = 1.
  if (!(s.t_min > 1e-9 && s.t_max < 1.0 && s.dot_min > 0x1.0p-900 &&
        s.t_sum < 2.0 * kTwoPi * (1.0 - 1e-6)))  // false on NaN
    return std::nullopt;
  // The wrap: in increasing angle, the one step from the upper half (atan2 in [+0, π]: sign
  // bit of y clear) into the lower one (sign bit set, −0 included: atan2(−0, x < 0) = −π) —
  // once round, exactly one step crosses, so the sum of their indices is its index (checked).
  const std::size_t wrap = s.wrap_sum;
  const auto upper = [&](std::size_t i) { return !std::signbit(points[i].y - center.y); };
  const std::size_t after = wrap + 1 == n ? 0 : wrap + 1;
  if (wrap >= n || (upper(wrap) != s.ccw) || (upper(after) == s.ccw))
    return std::nullopt;  // not reached: a walk once round crosses θ = ±π once
  return Walk{s.ccw, s.t_max, wrap};
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
  // Pass 2: the candidates; beyond n / 4 of them (many steps equal to the last few ulps, e.g.
  // an exact equiangular ring about its own centre) the general path's n atan2 cost less.
  if (!steps_at_least(ws.t.data(), n, tm - kTanMargin, n / 4, ws.candidate))
    return std::nullopt;
  // Step s joins points s and s + 1; in increasing angle it runs from `from(s)` to `to(s)`.
  // The wrap step (across θ = ±π, from the upper half into the lower in increasing angle) is
  // where the general path's order starts and ends.
  const auto next = [n](std::size_t i) { return i + 1 == n ? 0 : i + 1; };
  const auto from = [&](std::size_t s) { return ccw ? s : next(s); };
  const auto to = [&](std::size_t s) { return ccw ? next(s) : s; };
  // The directions d_i = p_i − c as pass 1 formed them (the same roundings).
  const auto angle = [&](std::size_t i) {
    return std::atan2(points[i].y - center.y, points[i].x - center.x);
  };
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
