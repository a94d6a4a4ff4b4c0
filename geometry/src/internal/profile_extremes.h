// internal/profile_extremes.h — the O(n) passes shared by the *_from_extremes reference-circle
// functions (minimum_zone_from_extremes.cpp, maximum_inscribed_from_extremes.cpp) on a
// PolarProfile: per block of kRangeBlock points the highest peak and the lowest valley of the
// deviations (so that later scans skip the blocks that cannot hold what they look for), the
// subset S of points those functions fit, and the squared distances from a centre where they
// can matter. Not part of the public API.
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
#include <optional>
#include <span>

#include "vcmm/geometry/polar_profile.h"

namespace vcmm::geometry::internal {

/// Points per block of ExtremesScratch::peak_hi / valley_lo.
inline constexpr std::size_t kRangeBlock = 16;

/// The subset policy both *_from_extremes functions follow (their headers give the argument):
/// S starts with the extrema within this fraction of the deviations' peak-to-valley of the
/// top (MZ) or the bottom (MZ and MI),
inline constexpr double kFirstBand = 0.45;
/// takes this many neighbours either side of an extremum or a violator,
inline constexpr std::size_t kSubsetNeighbours = 1;
/// and is fitted at most this many times (typically once, rarely twice) before all points are.
inline constexpr int kSubsetRounds = 6;

struct ValueRange {
  double lo = 0.0, hi = 0.0;
};

/// Per block the highest local maximum (d_j ≥ both neighbours, cyclic; −inf: none) and the
/// lowest local minimum (+inf: none) of the deviations, and their overall range (the global
/// maximum is a local one). Throws InvalidInput naming `caller` when there are no directions,
/// their count differs from the deviations', or a deviation or the base radius is not finite.
ValueRange deviation_ranges(const PolarProfile& p, ExtremesScratch& s, const char* caller);

/// deviation_ranges' pass over any cyclic sequence (n ≥ 8): per block the highest local maximum
/// and the lowest local minimum into s.peak_hi, s.valley_lo; returns the sum of the values
/// (not finite when one of them is not).
double local_extremes(std::span<const double> values, ExtremesScratch& s);

/// The range of the deviations of block b: its extremum is a peak (valley) of the block or
/// one of the block's two end points.
inline ValueRange block_range(const PolarProfile& p, const ExtremesScratch& s, std::size_t b) {
  const std::size_t first = b * kRangeBlock;
  const std::size_t last = std::min(p.size(), first + kRangeBlock) - 1;
  const double a = p.deviation[first], c = p.deviation[last];
  return {std::min({s.valley_lo[b], a, c}), std::max({s.peak_hi[b], a, c})};
}

/// Per block, the highest local maximum of the deviations if strictly above `top` and the
/// lowest local minimum if strictly below `bottom` join S with `neighbours` either side
/// (deviation_ranges must have run). A block of 16 rarely holds two such extremes of a
/// band-limited profile; the *_from_extremes checks add what this misses.
void add_deviation_extremes(const PolarProfile& p, ExtremesScratch& s, double top, double bottom,
                            std::size_t neighbours);

/// add_deviation_extremes for any sequence whose local extremes local_extremes has found.
void add_value_extremes(std::span<const double> values, ExtremesScratch& s, double top,
                        double bottom, std::size_t neighbours);

/// D̃_j = fl(fl(x_j − c.x)² + fl(y_j − c.y)²) of every point into out[0 … n), vectorised,
/// and per block of kRangeBlock points their highest and lowest into s.peak_hi, s.valley_lo
/// (a non-finite coordinate gives a NaN in out that these may miss).
void squared_distances(std::span<const Point2> points, Point2 c, double* out,
                       ExtremesScratch& s);

/// The index of the highest deviation (the first one holding it; deviation_ranges must have
/// run).
std::size_t index_of_highest(const PolarProfile& p, const ExtremesScratch& s);

/// D̃_j = fl(dx² + dy²), (dx, dy) = fl(polar_point(p, j) − c): the squared distance every
/// pass below uses (bit for bit).
inline double polar_squared_distance(const PolarProfile& p, std::size_t j, Point2 c) {
  const Point2 q = polar_point(p, j);
  const double dx = q.x - c.x, dy = q.y - c.y;
  return dx * dx + dy * dy;
}

/// Deviation bounds outside which a point's D̃ about c can exceed `above` or fall below
/// `below`: every point with lo ≤ d_j ≤ hi has below ≤ D̃_j ≤ above (rigorous; derivation in
/// the .cpp).
struct DistanceWindow {
  double hi = 0.0, lo = 0.0;
};
DistanceWindow distance_window(const PolarProfile& p, Point2 c, double above, double below);

/// D̃ about c of the points of block b into out[0 … count) (vectorised); returns count.
std::size_t block_distances(const PolarProfile& p, std::size_t b, Point2 c, double* out);

/// Calls visit(j, x) for every point with x = D̃_j about c strictly above `above` or below
/// `below`, computing D̃ only in the blocks whose deviations leave distance_window, and
/// returns the range of D̃ over all points: from those blocks when they reach beyond both
/// thresholds (every other point lies between them), else from a pass over all points.
template <class Visit>
ValueRange distances_beyond(const PolarProfile& p, const ExtremesScratch& s, Point2 c,
                            double above, double below, Visit visit) {
  const DistanceWindow w = distance_window(p, c, above, below);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  ValueRange r{kInf, -kInf};
  double t[kRangeBlock];
  const std::size_t blocks = s.peak_hi.size();
  for (std::size_t b = 0; b < blocks; ++b) {
    const ValueRange d = block_range(p, s, b);
    if (!(d.hi > w.hi) && !(d.lo < w.lo)) continue;
    const std::size_t count = block_distances(p, b, c, t);
    double hi = t[0], lo = t[0];  // the block's range first (registers, no branches)
    for (std::size_t k = 1; k < count; ++k) {
      hi = std::max(hi, t[k]);
      lo = std::min(lo, t[k]);
    }
    r.hi = std::max(r.hi, hi);
    r.lo = std::min(r.lo, lo);
    if (!(hi > above) && !(lo < below)) continue;
    for (std::size_t k = 0; k < count; ++k)
      if (t[k] > above || t[k] < below) visit(b * kRangeBlock + k, t[k]);
  }
  if (r.hi > above && r.lo < below) return r;
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t count = block_distances(p, b, c, t);
    for (std::size_t k = 0; k < count; ++k) {
      r.hi = std::max(r.hi, t[k]);
      r.lo = std::min(r.lo, t[k]);
    }
  }
  return r;
}

/// The first pass of the points overloads of the *_from_extremes functions: at least 8
/// points (else InvalidInput naming `caller`), D_o = D̃ about `origin` into s.distance2 and its
/// local extremes per block (s.peak_hi, s.valley_lo), S := ∅. Returns the range of D_o, or
/// nullopt when some D_o is not finite though every coordinate is (squares beyond the double
/// range: the caller fits all points); a non-finite coordinate throws InvalidInput naming
/// `caller` and the point.
std::optional<ValueRange> origin_distance_extremes(std::span<const Point2> points, Point2 origin,
                                                   ExtremesScratch& s, const char* caller);

/// s.subset := the points of S (in the order they joined), for a profile given as points.
void collect_subset(std::span<const Point2> points, ExtremesScratch& s);

/// S := ∅ for a profile of n points.
void clear_subset(std::size_t n, ExtremesScratch& s);

/// j and its `neighbours` on either side (cyclic) join S; returns how many were new.
std::size_t add_with_neighbours(std::size_t j, std::size_t neighbours, std::size_t n,
                                ExtremesScratch& s);

/// s.subset := the points of S (in the order they joined).
void collect_subset(const PolarProfile& p, ExtremesScratch& s);

}  // namespace vcmm::geometry::internal
