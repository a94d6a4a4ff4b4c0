// internal/minimum_zone_overlay_detail.h — knobs and counters of the Voronoi-overlay
// minimum-zone method, for its tests and benchmarks (not part of the public API).
#pragma once

#include <cstddef>
#include <span>

#include "minimum_zone_overlay.h"  // same directory: also found from the tests
#include "vcmm/geometry/minimum_zone.h"

namespace vcmm::geometry::internal {

struct OverlayOptions {
  /// Restrict the overlay to the provable region around a seed centre (see
  /// minimum_zone_overlay.cpp, §4). false: exhaust every FVD edge × NVD edge pair
  /// (O(n·h), for cross-checks of the pruning).
  bool prune = true;
};

/// What one run did (filled when a pointer is passed).
struct OverlayStatistics {
  std::size_t distinct_points = 0;
  std::size_t hull_vertices = 0;       ///< of all distinct points
  /// Sites whose diagrams were built: all distinct points, or with a region only those
  /// that can be farthest (far) / nearest (near) from a centre in it.
  std::size_t far_sites = 0, near_sites = 0;
  std::size_t fvd_edges = 0;           ///< edges of the farthest-point Voronoi diagram built
  std::size_t nvd_edges = 0;           ///< edges of the nearest-point Voronoi diagram built
  std::size_t fvd_edges_in_region = 0;
  std::size_t nvd_edges_in_region = 0;
  std::size_t edge_pairs = 0;          ///< FVD × NVD pairs tested
  std::size_t exact_pair_tests = 0;    ///< pairs the interval filter could not decide
  std::size_t candidates = 0;          ///< overlay vertices found (all exact)
  std::size_t exact_width_evaluations = 0;
  std::size_t seed_rounds = 0;         ///< rounds of the subset seed search
  bool region_used = false;
  double region_radius = 0.0;          ///< radius of the exhausted disk about the seed (mm)
  bool cocircular = false;
  /// Wall time (ms) of the phases: distinct points + co-circularity + hull, seed search,
  /// region bound + local sites, diagrams (DT, FDT), overlay exhaustion, attainment +
  /// contacts + result.
  double ms_prepare = 0, ms_seed = 0, ms_region = 0, ms_diagrams = 0, ms_exhaustion = 0,
         ms_finish = 0;
};

/// minimum_zone_overlay with options and counters.
MinimumZoneCircle minimum_zone_overlay(std::span<const Point2> points,
                                       const OverlayOptions& options,
                                       OverlayStatistics* statistics = nullptr);

}  // namespace vcmm::geometry::internal
