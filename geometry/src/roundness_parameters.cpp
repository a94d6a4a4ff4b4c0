// roundness_parameters.cpp — RONt, RONp, RONv, RONq (ISO 12181-1:2011) of a profile about
// a given reference circle (centre c, radius R_ref).
//
// d_i = |p_i − c| − R_ref, with p_i − c formed first (coordinates relative to the centre), so a
// profile 900 mm from the origin loses nothing beyond the rounding of each distance
// (½ ulp of |p − c|). RONt is taken as max r_i − min r_i, which does not involve R_ref at
// all; RONq = sqrt(mean d_i²) sums small squares (no cancellation).
//
// Boundary checks (every build): at least one point, every coordinate finite, and a finite
// centre and radius — InvalidInput naming the function, the rule and the value. The fitters
// call the unchecked twin (internal/prevalidated.h) on points they have validated.
//
// Speed. Points near the reference circle (|s| ≤ 2⁻⁹, s = (|p − c|² − R₀²)/R₀², deviations up
// to ~1e-3 R: every roundness profile about its own reference circles) take their distances
// from internal/near_circle.h — r = R₀ + R₀·P₆(s), within ½ ulp + 2⁻⁵⁹ r of √q (std::sqrt's
// value except within 2⁻⁵⁹ r of a rounding midpoint, then 1 ulp off), no square root — and
// d = r − R_ref as below; four points a step (AVX2 where the CPU has it: the same bits,
// internal/isa.h) with Σ d² in four partial sums (point i into sum i mod 4, added as
// (s₀ + s₁) + (s₂ + s₃), then the rest): one sequential sum was bound by the addition's
// latency (~4 cycles a point) and the square root by its throughput. Against the square-root
// evaluation below: RONt, RONp, RONv identical but for such a midpoint (≤ 1 ulp of r), RONq
// in its last bits (the summation order; roundness_parameters_test). Otherwise
// (a point beyond 2⁻⁹, a radius out of the kernel's range) the square-root evaluation (SSE2:
// distances two at a time — the packet square root is the scalar one — extremes by packet
// min/max; Σ d² in sequential order: bit for bit the scalar loop).
#include "vcmm/geometry/roundness_parameters.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "internal/distance_scan.h"
#include "internal/isa.h"
#include "internal/near_circle.h"
#include "internal/prevalidated.h"
#include "internal/vec.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace vcmm::geometry {
namespace {

constexpr const char* kCaller = "roundness_parameters";

/// |(dx, dy)|: the plain square root, falling back to hypot only where dx² + dy² overflows
/// (coordinates beyond ~1e154) or loses precision to underflow (distances below 1e-150,
/// whose squares leave the normal range), so the common case stays fast.
double distance(double dx, double dy) {
  const double r = std::sqrt(dx * dx + dy * dy);
  return std::isfinite(r) && r > 1e-150 ? r : std::hypot(dx, dy);
}

/// The near-circle evaluation (file comment) of r_max, r_min and Σ (d·inv_scale)², or false
/// when some point has |s| > 2⁻⁹ (the caller then takes square roots).
struct NearSums {
  double r_max, r_min, sum_dd;
};
using V4 = internal::VecOf<4>::type;  // internal/vec.h
using M4 = internal::VecOf<4>::mask;

/// The near-circle evaluation over points [0, n) with W = 4 lanes (points 0, 2, 1, 3 of a
/// step: the unpack order) or W = 8 (points in order); either way Σ d² in the four partial
/// sums by point residue mod 4, then (s₀ + s₁) + (s₂ + s₃) and the last n mod 4 points in
/// order — the same operations on every value whatever W.
template <int kDegree, int W>
[[gnu::always_inline]] inline bool near_sums_body(const Point2* p, std::size_t n, Point2 c,
                                                   double reference_radius, double inv_scale,
                                                   const internal::NearCircle& k,
                                                   NearSums& out) {
  using V = typename internal::VecOf<W>::type;  // internal/vec.h
  using M = typename internal::VecOf<W>::mask;
  const double* xy = reinterpret_cast<const double*>(p);
  const V cx = V{} + c.x, cy = V{} + c.y, r0 = V{} + k.r0, inv = V{} + inv_scale;
  const V ref = V{} + reference_radius;
  V smax = V{}, smin = V{}, rmax = V{} - std::numeric_limits<double>::infinity();
  V rmin = V{} + std::numeric_limits<double>::infinity();
  V4 sum = V4{};  // lanes: residues 0, 2, 1, 3 (W = 4) or 0, 1, 2, 3 (W = 8)
  std::size_t i = 0;
  for (; i + W <= n; i += W) {
    V a, b;
    __builtin_memcpy(&a, xy + 2 * i, sizeof a);      // x0 y0 x1 y1 …
    __builtin_memcpy(&b, xy + 2 * i + W, sizeof b);  // … the second half
    V dx, dy;
    if constexpr (W == 4) {
      dx = __builtin_shuffle(a, b, M{0, 4, 2, 6}) - cx;  // points 0, 2, 1, 3
      dy = __builtin_shuffle(a, b, M{1, 5, 3, 7}) - cy;
    } else {
      dx = __builtin_shuffle(a, b, M{0, 2, 4, 6, 8, 10, 12, 14}) - cx;  // points 0 … 7
      dy = __builtin_shuffle(a, b, M{1, 3, 5, 7, 9, 11, 13, 15}) - cy;
    }
    const V s = internal::near_circle_s(dx * dx + dy * dy, k);
    const V off = internal::near_circle_offset<kDegree>(s, k);
    smax = s > smax ? s : smax;  // q = +∞ (overflow) gives s = +∞: refused below
    smin = s < smin ? s : smin;
    const V r = r0 + off;
    rmax = r > rmax ? r : rmax;
    rmin = r < rmin ? r : rmin;
    const V d = (r - ref) * inv;
    const V dd = d * d;
    internal::add_in_point_order(sum, dd);
  }
  double s_max = 0.0, r_max = -std::numeric_limits<double>::infinity();
  double r_min = std::numeric_limits<double>::infinity();
  for (int j = 0; j < W; ++j) {
    s_max = std::max({s_max, smax[j], -smin[j]});
    r_max = std::max(r_max, rmax[j]);
    r_min = std::min(r_min, rmin[j]);
  }
  const auto point = [&](std::size_t j) {  // one point: s, r and d²
    const double dx = p[j].x - c.x, dy = p[j].y - c.y;
    const double s = internal::near_circle_s(dx * dx + dy * dy, k);
    const double off = internal::near_circle_offset<kDegree>(s, k);
    s_max = std::max(s_max, std::fabs(s));
    const double r = k.r0 + off;
    r_max = std::max(r_max, r);
    r_min = std::min(r_min, r);
    const double d = (r - reference_radius) * inv_scale;
    return d * d;
  };
  // W = 8: a last whole four into the partial sums, lane by lane as the vector step adds.
  if (W == 8 && i + 4 <= n) {
    for (int j = 0; j < 4; ++j) sum[j] += point(i + j);
    i += 4;
  }
  // (s₀ + s₁) + (s₂ + s₃) by point residue: W = 4 lanes 0, 2 hold residues 0, 1 and lanes
  // 1, 3 hold 2, 3; W = 8 lanes are residues.
  double sum_dd = W == 4 ? (sum[0] + sum[2]) + (sum[1] + sum[3])
                         : (sum[0] + sum[1]) + (sum[2] + sum[3]);
  for (; i < n; ++i) sum_dd += point(i);
  if (!(s_max <= internal::near_circle_s_max(kDegree))) return false;  // also NaN
  out = {r_max, r_min, sum_dd};
  return true;
}
template <int kDegree>
bool near_sums_baseline(const Point2* p, std::size_t n, Point2 c, double reference_radius,
                        double inv_scale, const internal::NearCircle& k, NearSums& out) {
  return near_sums_body<kDegree, 4>(p, n, c, reference_radius, inv_scale, k, out);
}
#if VCMM_GEOMETRY_X86
template <int kDegree>
__attribute__((target("avx2"))) bool near_sums_avx2(const Point2* p, std::size_t n, Point2 c,
                                                    double reference_radius, double inv_scale,
                                                    const internal::NearCircle& k,
                                                    NearSums& out) {
  return near_sums_body<kDegree, 4>(p, n, c, reference_radius, inv_scale, k, out);
}
template <int kDegree>
__attribute__((target("avx512f"))) bool near_sums_avx512(
    const Point2* p, std::size_t n, Point2 c, double reference_radius, double inv_scale,
    const internal::NearCircle& k, NearSums& out) {
  return near_sums_body<kDegree, 8>(p, n, c, reference_radius, inv_scale, k, out);
}
#endif
template <int kDegree>
bool near_sums_of_degree(std::span<const Point2> points, Point2 c, double reference_radius,
                         double inv_scale, const internal::NearCircle& k, NearSums& out) {
#if VCMM_GEOMETRY_X86
  if (internal::use_avx512())
    return near_sums_avx512<kDegree>(points.data(), points.size(), c, reference_radius,
                                     inv_scale, k, out);
  if (internal::use_avx2())
    return near_sums_avx2<kDegree>(points.data(), points.size(), c, reference_radius, inv_scale,
                                   k, out);
#endif
  return near_sums_baseline<kDegree>(points.data(), points.size(), c, reference_radius,
                                     inv_scale, k, out);
}

/// The near-circle sums about (c, reference_radius) when the kernel applies (the radius in
/// its range, every |s| within the degree's range): the degree from the expected deviation
/// bound (near_circle_degree_for), redone with degree 6 when a point leaves that range.
bool near_sums(std::span<const Point2> points, Point2 c, double reference_radius,
               double deviation_bound, double inv_scale, NearSums& out) {
  const int degree = internal::near_circle_degree_for(reference_radius, deviation_bound);
  if (degree == 0) return false;
  const internal::NearCircle k = internal::near_circle_about(reference_radius);
  if (degree == 3 && near_sums_of_degree<3>(points, c, reference_radius, inv_scale, k, out))
    return true;
  if (degree == 4 && near_sums_of_degree<4>(points, c, reference_radius, inv_scale, k, out))
    return true;
  return near_sums_of_degree<6>(points, c, reference_radius, inv_scale, k, out);
}

}  // namespace

RoundnessParameters roundness_parameters(std::span<const Point2> points, Point2 center,
                                         double reference_radius) {
  validate_profile(points, 1, kCaller, /*require_non_collinear=*/false);
  if (!std::isfinite(center.x) || !std::isfinite(center.y)) {
    std::ostringstream os;
    os << kCaller << ": the centre must be finite; got (x = " << center.x
       << ", y = " << center.y << ")";
    throw InvalidInput(os.str());
  }
  if (!std::isfinite(reference_radius)) {
    std::ostringstream os;
    os << kCaller << ": the reference radius must be finite; got " << reference_radius;
    throw InvalidInput(os.str());
  }
  return internal::roundness_parameters_of_valid(points, center, reference_radius);
}

namespace {
/// d_i² is summed as (d_i·2^−e)² with 2^e the scale of the radius (an exact rescaling), so
/// RONq neither overflows for huge coordinates nor underflows for tiny ones: e.
int ronq_exponent(std::span<const Point2> points, Point2 center, double reference_radius) {
  const double size = std::max(std::fabs(reference_radius),
                               distance(points[0].x - center.x, points[0].y - center.y));
  return size > 0.0 && std::isfinite(size) ? std::ilogb(size) : 0;
}
}  // namespace

double internal::ronq_inv_scale(std::span<const Point2> points, Point2 center,
                                double reference_radius) {
  return std::ldexp(1.0, -ronq_exponent(points, center, reference_radius));
}

double internal::ronq_of_valid(std::span<const Point2> points, Point2 center,
                               double reference_radius, double deviation_bound,
                               const RonqSums& sums) {
  // The sums of a scan's pass are near_sums' of degree 3 (internal/distance_scan.h): RONq's
  // when that is the degree taken here and it held for every point.
  const int e = ronq_exponent(points, center, reference_radius);
  if (internal::near_circle_degree_for(reference_radius, deviation_bound) == 3 &&
      sums.radius == reference_radius && sums.inv_scale == std::ldexp(1.0, -e) &&
      sums.s_max <= internal::near_circle_s_max(3))
    return std::ldexp(std::sqrt(sums.sum_dd / static_cast<double>(points.size())), e);
  return roundness_parameters_of_valid(points, center, reference_radius, deviation_bound).ronq;
}

RoundnessParameters internal::roundness_parameters_of_valid(std::span<const Point2> points,
                                                            Point2 center,
                                                            double reference_radius,
                                                            double deviation_bound) {
  const int e = ronq_exponent(points, center, reference_radius);
  const double inv_scale = std::ldexp(1.0, -e);  // multiplying by it is exact
  const std::size_t n = points.size();
  NearSums near{};
  if (near_sums(points, center, reference_radius, deviation_bound, inv_scale, near)) {
    RoundnessParameters out;
    out.ront = near.r_max - near.r_min;
    out.ronp = std::max(0.0, near.r_max - reference_radius);
    out.ronv = std::max(0.0, -(near.r_min - reference_radius));
    out.ronq = std::ldexp(std::sqrt(near.sum_dd / static_cast<double>(n)), e);
    return out;
  }
  double r_max = distance(points[0].x - center.x, points[0].y - center.y), r_min = r_max;
  double sum_dd = 0.0;
  const auto add = [&](double r) {
    const double d = (r - reference_radius) * inv_scale;
    sum_dd += d * d;
  };
  std::size_t i = 0;
#if defined(__SSE2__)
  {
    // Two points a packet: (x0, y0), (x1, y1) unpacked into (x0, x1), (y0, y1).
    const __m128d cx = _mm_set1_pd(center.x), cy = _mm_set1_pd(center.y);
    const __m128d lo = _mm_set1_pd(1e-150), hi = _mm_set1_pd(std::numeric_limits<double>::max());
    __m128d pmax = _mm_set1_pd(r_max), pmin = pmax;
    alignas(16) double r[2];
    const double* xy = reinterpret_cast<const double*>(points.data());
    static_assert(sizeof(Point2) == 2 * sizeof(double), "Point2: two packed doubles");
    for (; i + 2 <= n; i += 2) {
      const __m128d a = _mm_loadu_pd(xy + 2 * i), b = _mm_loadu_pd(xy + 2 * i + 2);
      const __m128d dx = _mm_sub_pd(_mm_unpacklo_pd(a, b), cx);
      const __m128d dy = _mm_sub_pd(_mm_unpackhi_pd(a, b), cy);
      __m128d pr = _mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)));
      // distance()'s fallback where a lane is outside (1e-150, max]: rare, per point.
      if (_mm_movemask_pd(_mm_and_pd(_mm_cmplt_pd(lo, pr), _mm_cmple_pd(pr, hi))) != 3)
        pr = _mm_setr_pd(distance(points[i].x - center.x, points[i].y - center.y),
                         distance(points[i + 1].x - center.x, points[i + 1].y - center.y));
      _mm_store_pd(r, pr);
      add(r[0]);
      add(r[1]);
      pmax = _mm_max_pd(pmax, pr);
      pmin = _mm_min_pd(pmin, pr);
    }
    alignas(16) double m[2];
    _mm_store_pd(m, pmax);
    r_max = std::max(m[0], m[1]);
    _mm_store_pd(m, pmin);
    r_min = std::min(m[0], m[1]);
  }
#endif
  for (; i < n; ++i) {
    const double r = distance(points[i].x - center.x, points[i].y - center.y);
    r_max = std::max(r_max, r);
    r_min = std::min(r_min, r);
    add(r);
  }
  RoundnessParameters out;
  const double d_max = r_max - reference_radius, d_min = r_min - reference_radius;
  out.ront = r_max - r_min;
  out.ronp = std::max(0.0, d_max);
  out.ronv = std::max(0.0, -d_min);
  out.ronq = std::ldexp(std::sqrt(sum_dd / static_cast<double>(n)), e);
  return out;
}

}  // namespace vcmm::geometry
