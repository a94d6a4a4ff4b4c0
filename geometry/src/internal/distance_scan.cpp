// internal/distance_scan.cpp — the passes of internal/distance_scan.h.
//
// Eight points a step in GCC vector types of four doubles (one AVX2 register, or two SSE2
// ones in the baseline variant), or sixteen in vectors of eight (one AVX-512 register), as
// two groups with their own per-lane extremes (two independent compare-and-select chains:
// one chain bounds a loop to its ~6-cycle latency per group). Per group, two loads of
// interleaved (x, y) pairs are unpacked into x and y of the group's points — with four lanes
// in the order (0, 2, 1, 3) of the unpack instructions, with eight in order (one permute),
// kept throughout (the lane indices say which point a lane holds). The squared distance per
// lane is the scalar expression (no FMA: -ffp-contract=off), each lane keeps its extreme and
// the index of its first occurrence by strict comparisons, the lanes are merged with ties to
// the lowest index, then the remaining points run scalar: the plain loop's result, whichever
// variant runs. Flags: one mask test per step, the rare set bits pushed in point order.
#include "internal/distance_scan.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "internal/isa.h"
#include "internal/near_circle.h"
#include "internal/vec.h"

namespace vcmm::geometry::internal {
namespace {

// Four lanes (AVX2, or two SSE2 registers) or eight (AVX-512): internal/vec.h's vectors
// with the lane order of each width.
template <int W>
struct Lanes;
template <>
struct Lanes<4> {
  using V = VecOf<4>::type;
  using M = VecOf<4>::mask;
  /// x (or y, with 1) of the four points in a = (x0 y0 x1 y1), b = (x2 y2 x3 y3), in the lane
  /// order of the unpack instructions: points 0, 2, 1, 3.
  static constexpr M kX = {0, 4, 2, 6}, kY = {1, 5, 3, 7};
  static constexpr M kPoint = {0, 2, 1, 3};
  static constexpr int kOrder[4] = {0, 2, 1, 3};  // lanes in point order
};
template <>
struct Lanes<8> {
  using V = VecOf<8>::type;
  using M = VecOf<8>::mask;
  /// Points 0 … 7 of a = (x0 y0 … x3 y3), b = (x4 y4 … x7 y7) in order (one permute each).
  static constexpr M kX = {0, 2, 4, 6, 8, 10, 12, 14}, kY = {1, 3, 5, 7, 9, 11, 13, 15};
  static constexpr M kPoint = {0, 1, 2, 3, 4, 5, 6, 7};
  static constexpr int kOrder[8] = {0, 1, 2, 3, 4, 5, 6, 7};
};

/// Whether any lane of a comparison mask is set: the lanes OR-ed by shuffles, one
/// extraction (one extraction per lane costs more in the loop).
template <int W>
[[gnu::always_inline]] inline bool any_lane(typename Lanes<W>::M m) {
  using M = typename Lanes<W>::M;
  if constexpr (W == 8) m |= __builtin_shuffle(m, M{4, 5, 6, 7, 0, 1, 2, 3});
  M h;
  if constexpr (W == 8) {
    h = m | __builtin_shuffle(m, M{2, 3, 0, 1, 6, 7, 4, 5});
    return (h | __builtin_shuffle(h, M{1, 0, 3, 2, 5, 4, 7, 6}))[0] != 0;
  } else {
    h = m | __builtin_shuffle(m, M{2, 3, 0, 1});
    return (h | __builtin_shuffle(h, M{1, 0, 3, 2}))[0] != 0;
  }
}

/// RONq's near-circle sums in a pass (RonqSums): the series' constants and the reference.
struct RonqIn {
  NearCircle k;
  double radius = 0.0, inv_scale = 1.0;
};
struct RonqOut {
  double sum_dd = 0.0, s_max = 0.0;
};

/// The 2W lanes' extremes (two groups) merged: the extreme value, then the lowest index among
/// the lanes holding it (each lane holds its first occurrence, so that is the first point of
/// the extreme value) — two reduction trees of one compare-and-select a level, no branch.
/// `best`, `index` are left alone when no lane holds a value (still at its initial kNo…).
template <int W, bool kIsMin>
[[gnu::always_inline]] inline void merge_lanes(const typename Lanes<W>::V (&v)[2],
                                               const typename Lanes<W>::M (&a)[2],
                                               double& best, std::size_t& index) {
  using V = typename Lanes<W>::V;
  using M = typename Lanes<W>::M;
  const auto pick = [](const V& x, const V& y) {
    if constexpr (kIsMin) return x < y ? x : y;
    else return x > y ? x : y;
  };
  V m = pick(v[0], v[1]);
  if constexpr (W == 8) m = pick(m, __builtin_shuffle(m, M{4, 5, 6, 7, 0, 1, 2, 3}));
  if constexpr (W == 8) {
    m = pick(m, __builtin_shuffle(m, M{2, 3, 0, 1, 6, 7, 4, 5}));
    m = pick(m, __builtin_shuffle(m, M{1, 0, 3, 2, 5, 4, 7, 6}));
  } else {
    m = pick(m, __builtin_shuffle(m, M{2, 3, 0, 1}));
    m = pick(m, __builtin_shuffle(m, M{1, 0, 3, 2}));
  }
  if (!(kIsMin ? m[0] < best : m[0] > best)) return;  // every lane still at its start value
  const M none = M{} + std::numeric_limits<long long>::max();
  const M k0 = v[0] == m ? a[0] : none, k1 = v[1] == m ? a[1] : none;
  M k = k0 < k1 ? k0 : k1;
  if constexpr (W == 8) {
    k = k < __builtin_shuffle(k, M{4, 5, 6, 7, 0, 1, 2, 3})
            ? k
            : __builtin_shuffle(k, M{4, 5, 6, 7, 0, 1, 2, 3});
    const M k2 = __builtin_shuffle(k, M{2, 3, 0, 1, 6, 7, 4, 5});
    k = k < k2 ? k : k2;
    const M k1s = __builtin_shuffle(k, M{1, 0, 3, 2, 5, 4, 7, 6});
    k = k < k1s ? k : k1s;
  } else {
    const M k2 = __builtin_shuffle(k, M{2, 3, 0, 1});
    k = k < k2 ? k : k2;
    const M k1s = __builtin_shuffle(k, M{1, 0, 3, 2});
    k = k < k1s ? k : k1s;
  }
  best = m[0];
  index = static_cast<std::size_t>(k[0]);
}

/// What a pass tracks: the smallest and/or the largest value; flags: none, D̃ ≥ threshold
/// (+1) or D̃ ≤ threshold (−1); kScaled: the differences are multiplied by `scale` (else the
/// scale is 1 and the products, exact, are skipped); kRonq: RONq's sums too (RonqSums).
template <bool kMin, bool kMax, int kFlag, bool kScaled, bool kRonq = false>
struct Pass {
  static constexpr double kNoMin = std::numeric_limits<double>::infinity();
  static constexpr double kNoMax = -1.0;
  struct Out {
    double smin = kNoMin, smax = kNoMax;
    std::size_t imin = 0, imax = 0;
  };

  /// Two groups of W lanes a step (2W points), each group with its own per-lane extremes.
  template <int W>
  [[gnu::always_inline]] static inline Out run(const Point2* p, std::size_t lo, std::size_t hi,
                                               Point2 c, double scale, double threshold,
                                               std::vector<std::size_t>* flagged,
                                               const RonqIn* rq = nullptr,
                                               RonqOut* ro = nullptr) {
    static_assert(sizeof(Point2) == 2 * sizeof(double), "Point2: two packed doubles");
    using L = Lanes<W>;
    using V = typename L::V;
    using M = typename L::M;
    const double* xy = reinterpret_cast<const double*>(p);
    const V cx = V{} + c.x, cy = V{} + c.y;
    const V s = V{} + scale;
    const V t = V{} + threshold;
    const auto l = static_cast<std::int64_t>(lo);
    const M step = M{} + 2 * W;
    M at[2] = {L::kPoint + l, L::kPoint + (l + W)};  // the point of each lane
    V bmin[2] = {V{} + kNoMin, V{} + kNoMin}, bmax[2] = {V{} + kNoMax, V{} + kNoMax};
    M amin[2] = {at[0], at[1]}, amax[2] = {at[0], at[1]};
    // RONq: as roundness_parameters.cpp's near_sums (degree 3): Σ d² in four partial sums by
    // point residue mod 4 (lo is 0 for these passes), the extremes of s per lane.
    using Sum4 = VecOf<4>::type;
    Sum4 ronq_sum = {};
    V s_hi = {}, s_lo = {};
    std::size_t i = lo;
    for (; i + 2 * W <= hi; i += 2 * W) {
      M flag[2];
      for (int h = 0; h < 2; ++h) {
        V a, b;
        __builtin_memcpy(&a, xy + 2 * i + 2 * W * h, sizeof a);
        __builtin_memcpy(&b, xy + 2 * i + 2 * W * h + W, sizeof b);
        const V x = __builtin_shuffle(a, b, L::kX);
        const V y = __builtin_shuffle(a, b, L::kY);
        V dx = x - cx, dy = y - cy;
        if constexpr (kRonq) {
          const V sv = near_circle_s(dx * dx + dy * dy, rq->k);
          s_hi = sv > s_hi ? sv : s_hi;
          s_lo = sv < s_lo ? sv : s_lo;
          const V d = ((rq->k.r0 + near_circle_offset<3>(sv, rq->k)) - rq->radius) * rq->inv_scale;
          const V dd = d * d;
          if constexpr (W == 4) {
            ronq_sum += dd;  // lanes: residues 0, 2, 1, 3
          } else {
            ronq_sum += low_half(dd);  // the points in order: internal/vec.h
            ronq_sum += high_half(dd);
          }
        }
        if constexpr (kScaled) {
          dx *= s;
          dy *= s;
        }
        const V d2 = dx * dx + dy * dy;
        if constexpr (kMin) {
          const M better = d2 < bmin[h];
          bmin[h] = better ? d2 : bmin[h];
          amin[h] = better ? at[h] : amin[h];
        }
        if constexpr (kMax) {
          const M better = d2 > bmax[h];
          bmax[h] = better ? d2 : bmax[h];
          amax[h] = better ? at[h] : amax[h];
        }
        if constexpr (kFlag > 0) flag[h] = d2 >= t;
        if constexpr (kFlag < 0) flag[h] = d2 <= t;
      }
      if constexpr (kFlag != 0) {
        if (any_lane<W>(flag[0] | flag[1])) [[unlikely]] {
          for (int h = 0; h < 2; ++h)
            for (int k : L::kOrder)  // lanes in point order
              if (flag[h][k] != 0) flagged->push_back(static_cast<std::size_t>(at[h][k]));
        }
      }
      at[0] += step;
      at[1] += step;
    }
    Out out;
    if (i > lo) {
      if constexpr (kMin) merge_lanes<W, true>(bmin, amin, out.smin, out.imin);
      if constexpr (kMax) merge_lanes<W, false>(bmax, amax, out.smax, out.imax);
    }
    if (i == lo) out.imin = out.imax = lo;  // no whole step: the plain loop's start
    // RONq: the partial sums by residue, then the rest point by point in near_sums' order.
    double by_residue[4] = {}, s_max = 0.0;
    if constexpr (kRonq) {
      for (int r = 0; r < 4; ++r) by_residue[r] = ronq_sum[W == 4 ? (r == 1 ? 2 : r == 2 ? 1 : r) : r];
      for (int k = 0; k < W; ++k) s_max = std::max({s_max, s_hi[k], -s_lo[k]});
    }
    const std::size_t whole4 = hi - hi % 4;
    double sum_dd = 0.0;
    bool combined = false;
    for (; i < hi; ++i) {
      if constexpr (kRonq) {
        if (i >= whole4 && !combined) {
          sum_dd = (by_residue[0] + by_residue[1]) + (by_residue[2] + by_residue[3]);
          combined = true;
        }
        const double ux = p[i].x - c.x, uy = p[i].y - c.y;
        const double sv = near_circle_s(ux * ux + uy * uy, rq->k);
        s_max = std::max(s_max, std::fabs(sv));
        const double d = ((rq->k.r0 + near_circle_offset<3>(sv, rq->k)) - rq->radius) * rq->inv_scale;
        if (combined) sum_dd += d * d;
        else by_residue[i % 4] += d * d;
      }
      const double dx = (p[i].x - c.x) * scale, dy = (p[i].y - c.y) * scale;
      const double d2 = dx * dx + dy * dy;
      if (kMin && d2 < out.smin) {
        out.smin = d2;
        out.imin = i;
      }
      if (kMax && d2 > out.smax) {
        out.smax = d2;
        out.imax = i;
      }
      if (kFlag > 0 && d2 >= threshold) flagged->push_back(i);
      if (kFlag < 0 && d2 <= threshold) flagged->push_back(i);
    }
    if constexpr (kRonq) {
      if (!combined) sum_dd = (by_residue[0] + by_residue[1]) + (by_residue[2] + by_residue[3]);
      *ro = {sum_dd, s_max};
    }
    return out;
  }
};

using NearestPass = Pass<true, false, +1, true>;
using FarthestPass = Pass<false, true, -1, true>;
using NearestRonqPass = Pass<true, false, +1, true, true>;
using FarthestRonqPass = Pass<false, true, -1, true, true>;
using ExtremesPass = Pass<true, true, 0, false>;

// Each pass compiled for the baseline ISA, for AVX2 and for AVX-512 (chosen per call,
// internal/isa.h): the same element-wise operations in the same order, so the same values;
// the extremes (first index on ties) and the flags (in point order) do not depend on the
// lanes.
template <class P>
typename P::Out run_baseline(const Point2* p, std::size_t lo, std::size_t hi, Point2 c,
                             double scale, double threshold, std::vector<std::size_t>* flagged,
                             const RonqIn* rq, RonqOut* ro) {
  return P::template run<4>(p, lo, hi, c, scale, threshold, flagged, rq, ro);
}
#if VCMM_GEOMETRY_X86
template <class P>
__attribute__((target("avx2"))) typename P::Out run_avx2(const Point2* p, std::size_t lo,
                                                         std::size_t hi, Point2 c,
                                                         double scale, double threshold,
                                                         std::vector<std::size_t>* flagged,
                                                         const RonqIn* rq, RonqOut* ro) {
  return P::template run<4>(p, lo, hi, c, scale, threshold, flagged, rq, ro);
}
template <class P>
__attribute__((target("avx512f"))) typename P::Out run_avx512(
    const Point2* p, std::size_t lo, std::size_t hi, Point2 c, double scale, double threshold,
    std::vector<std::size_t>* flagged, const RonqIn* rq, RonqOut* ro) {
  return P::template run<8>(p, lo, hi, c, scale, threshold, flagged, rq, ro);
}
#endif
template <class P>
typename P::Out run(const Point2* p, std::size_t lo, std::size_t hi, Point2 c, double scale,
                    double threshold, std::vector<std::size_t>* flagged,
                    const RonqIn* rq = nullptr, RonqOut* ro = nullptr) {
#if VCMM_GEOMETRY_X86
  if (use_avx512()) return run_avx512<P>(p, lo, hi, c, scale, threshold, flagged, rq, ro);
  if (use_avx2()) return run_avx2<P>(p, lo, hi, c, scale, threshold, flagged, rq, ro);
#endif
  return run_baseline<P>(p, lo, hi, c, scale, threshold, flagged, rq, ro);
}

}  // namespace

template <Track kTrack>
DistanceScan scan_distances(std::span<const Point2> points, Point2 c, double scale,
                            double threshold, std::vector<std::size_t>& flagged,
                            RonqSums* ronq) {
  constexpr bool kNear = kTrack == Track::kNearest;
  using Plain = std::conditional_t<kNear, NearestPass, FarthestPass>;
  using WithRonq = std::conditional_t<kNear, NearestRonqPass, FarthestRonqPass>;
  const auto extreme = [](const auto& o) {
    return kNear ? DistanceScan{o.smin, o.imin} : DistanceScan{o.smax, o.imax};
  };
  if (ronq && near_circle_radius_ok(ronq->radius)) {
    const RonqIn in{near_circle_about(ronq->radius), ronq->radius, ronq->inv_scale};
    RonqOut sums;
    const auto o = run<WithRonq>(points.data(), 0, points.size(), c, scale, threshold,
                                 &flagged, &in, &sums);
    ronq->sum_dd = sums.sum_dd;
    ronq->s_max = sums.s_max;
    return extreme(o);
  }
  if (ronq) ronq->s_max = std::numeric_limits<double>::infinity();  // nothing summed
  return extreme(run<Plain>(points.data(), 0, points.size(), c, scale, threshold, &flagged));
}

template DistanceScan scan_distances<Track::kNearest>(std::span<const Point2>, Point2, double,
                                                      double, std::vector<std::size_t>&,
                                                      RonqSums*);
template DistanceScan scan_distances<Track::kFarthest>(std::span<const Point2>, Point2, double,
                                                       double, std::vector<std::size_t>&,
                                                       RonqSums*);

DistanceExtremes distance_extremes(std::span<const Point2> points, std::size_t lo,
                                   std::size_t hi, Point2 c) {
  const auto o = run<ExtremesPass>(points.data(), lo, hi, c, 1.0, 0.0, nullptr);
  return {o.imax, o.imin, o.smax, o.smin};
}

}  // namespace vcmm::geometry::internal
