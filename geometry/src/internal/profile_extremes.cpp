// internal/profile_extremes.cpp — the O(n) passes of the *_from_extremes functions
// (internal/profile_extremes.h). The two range passes are the only per-point work of those
// functions: written as fixed-width lane operations (a tree of max/min per block of 16) that
// the compiler vectorises, compiled for AVX-512, AVX2 and the baseline (runtime dispatch).
// Every lane computes exactly the scalar expression — the file is compiled with
// -ffp-contract=off (top-level CMakeLists.txt), else the AVX clones would fuse products into
// FMAs — so the values, and with them every decision, are the same on every machine.
#include "internal/profile_extremes.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "vcmm/internal/simd_clones.h"

namespace vcmm::geometry::internal {
namespace {

// Eight lanes as one GCC vector (lowered to two AVX2 or four SSE2 registers where AVX-512 is
// not available): the per-block reductions below are explicit shuffle trees, which the
// auto-vectoriser does not produce from scalar code. These helpers are inlined into the
// kernels; the warning that passing such vectors by value would change the ABI between
// instruction sets does not apply to them.
#pragma GCC diagnostic ignored "-Wpsabi"  // (GCC reports it at the end of the file)
using V8 = double __attribute__((vector_size(64)));
using M8 = long long __attribute__((vector_size(64)));
static_assert(kRangeBlock == 16, "the kernels below handle a block as two V8");

constexpr double kInf = std::numeric_limits<double>::infinity();

[[gnu::always_inline]] inline V8 load8(const double* p) {
  V8 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
[[gnu::always_inline]] inline V8 vmax(V8 a, V8 b) { return a > b ? a : b; }
[[gnu::always_inline]] inline V8 vmin(V8 a, V8 b) { return a < b ? a : b; }
[[gnu::always_inline]] inline double hmax(V8 v) {
  v = vmax(v, __builtin_shuffle(v, M8{4, 5, 6, 7, 0, 1, 2, 3}));
  v = vmax(v, __builtin_shuffle(v, M8{2, 3, 0, 1, 6, 7, 4, 5}));
  v = vmax(v, __builtin_shuffle(v, M8{1, 0, 3, 2, 5, 4, 7, 6}));
  return v[0];
}
[[gnu::always_inline]] inline double hmin(V8 v) {
  v = vmin(v, __builtin_shuffle(v, M8{4, 5, 6, 7, 0, 1, 2, 3}));
  v = vmin(v, __builtin_shuffle(v, M8{2, 3, 0, 1, 6, 7, 4, 5}));
  v = vmin(v, __builtin_shuffle(v, M8{1, 0, 3, 2, 5, 4, 7, 6}));
  return v[0];
}

/// For blocks b ∈ [first, last) (full, with both outer neighbours inside the array): the
/// highest local maximum and the lowest local minimum of d (x ≥ / ≤ both neighbours; −inf /
/// +inf where none). Returns Σ d over them (NaN or ±inf if any d is).
VCMM_SIMD_CLONES double deviation_blocks(const double* d, std::size_t first, std::size_t last,
                                         double* phi, double* vlo) {
  V8 sum = {};
  const V8 none_hi = V8{} - kInf, none_lo = V8{} + kInf;
  for (std::size_t b = first; b < last; ++b) {
    const double* v = d + b * kRangeBlock;
    const V8 x0 = load8(v), x1 = load8(v + 8);
    const V8 a0 = load8(v - 1), a1 = load8(v + 7), c0 = load8(v + 1), c1 = load8(v + 9);
    sum += x0 + x1;
    // A peak where min(x − a, x − c) ≥ 0, a valley where max(x − a, x − c) ≤ 0 (one compare
    // and select each: combining two compare masks is not vectorised for every target).
    const V8 p0 = vmin(x0 - a0, x0 - c0) >= 0.0 ? x0 : none_hi;
    const V8 p1 = vmin(x1 - a1, x1 - c1) >= 0.0 ? x1 : none_hi;
    const V8 q0 = vmax(x0 - a0, x0 - c0) <= 0.0 ? x0 : none_lo;
    const V8 q1 = vmax(x1 - a1, x1 - c1) <= 0.0 ? x1 : none_lo;
    phi[b] = hmax(vmax(p0, p1));
    vlo[b] = hmin(vmin(q0, q1));
  }
  double total = 0.0;
  for (int k = 0; k < 8; ++k) total += sum[k];
  return total;
}

/// D̃ of `count` consecutive points (polar_squared_distance, lane by lane).
VCMM_SIMD_CLONES void distances_of(const double* d, const double* cs, const double* sn,
                                   double base, double cx, double cy, std::size_t count,
                                   double* out) {
  for (std::size_t k = 0; k < count; ++k) {
    const double r = base + d[k];
    const double dx = r * cs[k] - cx, dy = r * sn[k] - cy;
    out[k] = dx * dx + dy * dy;
  }
}

/// D̃ of points [0, n) about c into out, and per block of kRangeBlock points their highest
/// and lowest (max and min are exact in any order; a non-finite coordinate gives a NaN that
/// they may not show). Eight points a step as GCC vectors (the compiler does not vectorise
/// the interleaved x, y nor the max/min of a plain loop); the tail with the same operations.
VCMM_SIMD_CLONES void squared_distances_of(const Point2* p, std::size_t n, Point2 c,
                                           double* __restrict out, double* __restrict block_hi,
                                           double* __restrict block_lo) {
  const double* xy = reinterpret_cast<const double*>(p);
  const V8 cx = V8{} + c.x, cy = V8{} + c.y;
  const std::size_t full = n / kRangeBlock;
  for (std::size_t b = 0; b < full; ++b) {
    const std::size_t j = b * kRangeBlock;
    V8 v[2];
    for (std::size_t h = 0; h < 2; ++h) {
      const V8 a0 = load8(xy + 2 * j + 16 * h), a1 = load8(xy + 2 * j + 16 * h + 8);
      const V8 x = __builtin_shuffle(a0, a1, M8{0, 2, 4, 6, 8, 10, 12, 14}) - cx;
      const V8 y = __builtin_shuffle(a0, a1, M8{1, 3, 5, 7, 9, 11, 13, 15}) - cy;
      v[h] = x * x + y * y;
      std::memcpy(out + j + 8 * h, &v[h], sizeof v[h]);
    }
    block_hi[b] = hmax(vmax(v[0], v[1]));
    block_lo[b] = hmin(vmin(v[0], v[1]));
  }
  if (full * kRangeBlock == n) return;
  double hi = -kInf, lo = kInf;
  for (std::size_t j = full * kRangeBlock; j < n; ++j) {
    const double dx = p[j].x - c.x, dy = p[j].y - c.y;
    const double v = dx * dx + dy * dy;
    out[j] = v;
    hi = std::max(hi, v);
    lo = std::min(lo, v);
  }
  block_hi[full] = hi;
  block_lo[full] = lo;
}

constexpr double kU = 0x1.0p-53;

}  // namespace

void squared_distances(std::span<const Point2> points, Point2 c, double* out,
                       ExtremesScratch& s) {
  const std::size_t blocks = (points.size() + kRangeBlock - 1) / kRangeBlock;
  s.peak_hi.resize(blocks);
  s.valley_lo.resize(blocks);
  squared_distances_of(points.data(), points.size(), c, out, s.peak_hi.data(),
                       s.valley_lo.data());
}

ValueRange deviation_ranges(const PolarProfile& p, ExtremesScratch& s, const char* caller) {
  const std::size_t n = p.size();
  if (p.directions == nullptr || p.directions->size() != n)
    throw InvalidInput(std::string(caller) + ": expected one direction per deviation; got " +
                       std::to_string(n) + " deviations and " +
                       std::to_string(p.directions ? p.directions->size() : 0) + " directions");
  const double sum = local_extremes(p.deviation, s);
  if (!std::isfinite(sum) || !std::isfinite(p.base_radius)) {
    const double* d = p.deviation.data();
    std::size_t j = 0;
    while (j < n && std::isfinite(d[j])) ++j;
    throw InvalidInput(std::string(caller) + ": " +
                       (j < n ? "deviation " + std::to_string(j) + " is not finite"
                              : std::string("the base radius is not finite")));
  }
  ValueRange r{s.valley_lo[0], s.peak_hi[0]};
  for (std::size_t b = 1; b < s.peak_hi.size(); ++b) {
    r.hi = std::max(r.hi, s.peak_hi[b]);
    r.lo = std::min(r.lo, s.valley_lo[b]);
  }
  return r;
}

double local_extremes(std::span<const double> values, ExtremesScratch& s) {
  const std::size_t n = values.size();
  const std::size_t blocks = (n + kRangeBlock - 1) / kRangeBlock;
  // Blocks 1 … last − 1 are full and have both outer neighbours inside the array: the
  // vectorised pass; the first and the last ones here (cyclic neighbours). n ≥ 8.
  const std::size_t full = n / kRangeBlock;
  const std::size_t last = n % kRangeBlock == 0 ? full - 1 : full;
  s.peak_hi.resize(blocks);
  s.valley_lo.resize(blocks);
  const double* d = values.data();
  double sum =
      last > 1 ? deviation_blocks(d, 1, last, s.peak_hi.data(), s.valley_lo.data()) : 0.0;
  const auto scalar_block = [&](std::size_t b) {
    double peak = -kInf, valley = kInf;
    for (std::size_t j = b * kRangeBlock; j < std::min(n, (b + 1) * kRangeBlock); ++j) {
      const double x = d[j], a = d[j == 0 ? n - 1 : j - 1], c = d[j + 1 == n ? 0 : j + 1];
      sum += x;
      if (x >= a && x >= c) peak = std::max(peak, x);
      if (x <= a && x <= c) valley = std::min(valley, x);
    }
    s.peak_hi[b] = peak;
    s.valley_lo[b] = valley;
  };
  scalar_block(0);
  for (std::size_t b = std::max<std::size_t>(last, 1); b < blocks; ++b) scalar_block(b);
  return sum;
}

void add_deviation_extremes(const PolarProfile& p, ExtremesScratch& s, double top, double bottom,
                            std::size_t neighbours) {
  add_value_extremes(p.deviation, s, top, bottom, neighbours);
}

void add_value_extremes(std::span<const double> values, ExtremesScratch& s, double top,
                        double bottom, std::size_t neighbours) {
  const std::size_t n = values.size();
  const double* d = values.data();
  // The block's highest peak and lowest valley (the first point holding that value; a
  // second qualifying extremum in the same 16 points is left to the check's rounds).
  const auto first_equal = [&](std::size_t b, double v) {
    std::size_t j = b * kRangeBlock;
    while (d[j] != v) ++j;
    return j;
  };
  for (std::size_t b = 0; b < s.peak_hi.size(); ++b) {
    if (s.peak_hi[b] > top) add_with_neighbours(first_equal(b, s.peak_hi[b]), neighbours, n, s);
    if (s.valley_lo[b] < bottom)
      add_with_neighbours(first_equal(b, s.valley_lo[b]), neighbours, n, s);
  }
}

std::size_t index_of_highest(const PolarProfile& p, const ExtremesScratch& s) {
  const auto best = std::max_element(s.peak_hi.begin(), s.peak_hi.end());
  std::size_t j = static_cast<std::size_t>(best - s.peak_hi.begin()) * kRangeBlock;
  while (p.deviation[j] != *best) ++j;
  return j;
}

// The window. For point j, r_j = fl(R₀ + d_j), p_j = (fl(r_j c_j), fl(r_j s_j)), D̃_j as in
// polar_squared_distance; |u_j|² ∈ [q_lo, q_hi] (PolarDirections, each within 2u). Then
//   √D̃_j ≤ (|p_j| + |c|)(1 + 3u),  |p_j| ≤ |R₀ + d_j| √q_hi (1 + 4u),
//   √D̃_j ≥ (|p_j| − |c|)(1 − 3u),  |p_j| ≥ |R₀ + d_j| √q_lo (1 − 4u),
// so |R₀ + d_j| ≤ ρ_hi = (√above (1 − 8u) − |c|)/(√q_hi (1 + 8u)) proves D̃_j ≤ above and
// |R₀ + d_j| ≥ ρ_lo = (√below (1 + 8u) + |c|)/(√q_lo (1 − 8u)) proves D̃_j ≥ below (the
// factors 8u cover every rounding above, including that of the square roots, of |c| and of
// ρ's own arithmetic, with room). So a block whose deviations all lie in
// [ρ_lo − R₀, ρ_hi − R₀] (then R₀ + d ≥ ρ_lo ≥ 0) holds no point beyond either threshold; the
// bounds are moved outwards by 16u of the magnitudes for the rounding of the subtraction.
DistanceWindow distance_window(const PolarProfile& p, Point2 c, double above, double below) {
  const double cn = std::hypot(c.x, c.y) * (1.0 + 8 * kU);
  const double rho_hi = (std::sqrt(std::max(above, 0.0)) * (1.0 - 8 * kU) - cn) /
                        (std::sqrt(p.directions->norm2_hi()) * (1.0 + 8 * kU));
  const double rho_lo = (std::sqrt(std::max(below, 0.0)) * (1.0 + 8 * kU) + cn) /
                        (std::sqrt(p.directions->norm2_lo()) * (1.0 - 8 * kU));
  const double slack =
      16 * kU * (std::fabs(p.base_radius) + std::fabs(rho_hi) + std::fabs(rho_lo));
  return {rho_hi - p.base_radius - slack, rho_lo - p.base_radius + slack};
}

std::size_t block_distances(const PolarProfile& p, std::size_t b, Point2 c, double* out) {
  const std::size_t first = b * kRangeBlock;
  const std::size_t count = std::min(p.size(), first + kRangeBlock) - first;
  distances_of(p.deviation.data() + first, p.directions->cos().data() + first,
               p.directions->sin().data() + first,
               p.base_radius, c.x, c.y, count, out);
  return count;
}

void clear_subset(std::size_t n, ExtremesScratch& s) {
  s.member.assign(n, 0);
  s.subset_index.clear();
  s.subset.clear();
}

std::size_t add_with_neighbours(std::size_t j, std::size_t neighbours, std::size_t n,
                                ExtremesScratch& s) {
  std::size_t added = 0;
  const std::size_t span = std::min(2 * neighbours + 1, n);
  std::size_t k = (j + n - std::min(neighbours, n - 1)) % n;
  for (std::size_t i = 0; i < span; ++i) {
    if (!s.member[k]) {
      s.member[k] = 1;
      s.subset_index.push_back(k);
      ++added;
    }
    k = k + 1 == n ? 0 : k + 1;
  }
  return added;
}

std::optional<ValueRange> origin_distance_extremes(std::span<const Point2> points, Point2 origin,
                                                   ExtremesScratch& s, const char* caller) {
  const std::size_t n = points.size();
  if (n < 8)
    throw InvalidInput(std::string(caller) + ": needs at least 8 points; got " +
                       std::to_string(n));
  s.distance2.resize(n);
  squared_distances(points, origin, s.distance2.data(), s);
  // The sum of the D_o is finite exactly when every one is.
  const bool finite = std::isfinite(local_extremes(s.distance2, s));
  clear_subset(n, s);
  if (!finite) {
    validate_profile(points, 8, caller);  // names a non-finite point
    return std::nullopt;
  }
  ValueRange r{s.valley_lo[0], s.peak_hi[0]};  // the global extremes are local ones
  for (std::size_t b = 1; b < s.peak_hi.size(); ++b) {
    r.hi = std::max(r.hi, s.peak_hi[b]);
    r.lo = std::min(r.lo, s.valley_lo[b]);
  }
  return r;
}

void collect_subset(std::span<const Point2> points, ExtremesScratch& s) {
  s.subset.resize(s.subset_index.size());
  for (std::size_t i = 0; i < s.subset_index.size(); ++i) s.subset[i] = points[s.subset_index[i]];
}

void collect_subset(const PolarProfile& p, ExtremesScratch& s) {
  s.subset.resize(s.subset_index.size());
  for (std::size_t i = 0; i < s.subset_index.size(); ++i)
    s.subset[i] = polar_point(p, s.subset_index[i]);
}

}  // namespace vcmm::geometry::internal
