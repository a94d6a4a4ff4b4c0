// Benchmarks of the reference circles from a subset of extremes (minimum_zone_from_extremes.h,
// maximum_inscribed_from_extremes.h) against the fitters on all points.
//
// What: CPU time of one RONt on a band-limited polar profile like one spectral trial's — the
// 171 mm ring (R = 85.5 mm), 3600 equiangular directions, harmonics 2 … 150 with amplitudes
// 2 µm/k and random phases (a filtered form with µm peak-to-valley), 64 such profiles cycled
// (fixed seed). BM_*FromExtremes: the subset functions on the PolarProfile (deviations only);
// BM_*AllPoints: building the 3600 points and the fitter on all of them, the path they
// replace; BM_MinimumZonePointsFromExtremes: building them and the points overload (the exact
// trial's path). Results and machine: docs/performance.md ("The spectral trial's reference fits").
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "support/polar_profiles.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/maximum_inscribed_from_extremes.h"
#include "vcmm/geometry/minimum_zone.h"
#include "vcmm/geometry/minimum_zone_from_extremes.h"
#include "vcmm/geometry/polar_profile.h"

namespace {

namespace g = vcmm::geometry;

constexpr std::size_t kPoints = 3600, kProfiles = 64;
constexpr double kRadius = 85.5;

struct Profiles {
  g::PolarDirections directions;
  std::vector<std::vector<double>> deviations;
};


const Profiles& profiles() {
  static const Profiles p = [] {
    Profiles out{vcmm::test::equiangular_directions(kPoints), {}};
    std::mt19937_64 gen(20261127);
    std::normal_distribution<double> normal;
    std::uniform_real_distribution<double> phase(0.0, 2 * std::numbers::pi);
    for (std::size_t t = 0; t < kProfiles; ++t) {
      std::vector<double> d(kPoints, 0.0);
      for (std::size_t k = 2; k <= 150; ++k) {
        const double a = 2e-3 * normal(gen) / static_cast<double>(k), f = phase(gen);
        for (std::size_t j = 0; j < kPoints; ++j)
          d[j] += a * std::cos(2 * std::numbers::pi * static_cast<double>(k * j) /
                                   static_cast<double>(kPoints) + f);
      }
      out.deviations.push_back(std::move(d));
    }
    return out;
  }();
  return p;
}

template <class Fit>
void run(benchmark::State& state, Fit fit) {
  const Profiles& p = profiles();
  std::size_t t = 0;
  for (auto _ : state) {
    const g::PolarProfile profile{kRadius, p.deviations[t++ % kProfiles], &p.directions};
    benchmark::DoNotOptimize(fit(profile));
  }
  state.SetItemsProcessed(state.iterations());
}

std::vector<g::Point2>& points_of(const g::PolarProfile& p) {
  static std::vector<g::Point2> points;
  points.resize(p.size());
  for (std::size_t j = 0; j < p.size(); ++j) points[j] = g::polar_point(p, j);
  return points;
}

void BM_MinimumZoneFromExtremes(benchmark::State& state) {
  g::ExtremesScratch scratch;
  run(state, [&](const g::PolarProfile& p) { return g::minimum_zone_ront_from_extremes(p, scratch); });
}
BENCHMARK(BM_MinimumZoneFromExtremes)->Unit(benchmark::kMicrosecond);

void BM_MinimumZoneAllPoints(benchmark::State& state) {
  run(state, [](const g::PolarProfile& p) { return g::minimum_zone_circle(points_of(p)).ron.ront; });
}
BENCHMARK(BM_MinimumZoneAllPoints)->Unit(benchmark::kMicrosecond);

// The points overload (the exact trial's path: a filtered profile as points about the filter
// centre), with the points built as for BM_MinimumZoneAllPoints.
void BM_MinimumZonePointsFromExtremes(benchmark::State& state) {
  g::ExtremesScratch scratch;
  run(state, [&](const g::PolarProfile& p) {
    return g::minimum_zone_ront_from_extremes(points_of(p), {0.0, 0.0}, scratch);
  });
}
BENCHMARK(BM_MinimumZonePointsFromExtremes)->Unit(benchmark::kMicrosecond);

void BM_MaximumInscribedFromExtremes(benchmark::State& state) {
  g::ExtremesScratch scratch;
  run(state,
      [&](const g::PolarProfile& p) { return g::maximum_inscribed_ront_from_extremes(p, scratch); });
}
BENCHMARK(BM_MaximumInscribedFromExtremes)->Unit(benchmark::kMicrosecond);

void BM_MaximumInscribedAllPoints(benchmark::State& state) {
  run(state,
      [](const g::PolarProfile& p) { return g::maximum_inscribed_circle(points_of(p)).ron.ront; });
}
BENCHMARK(BM_MaximumInscribedAllPoints)->Unit(benchmark::kMicrosecond);

}  // namespace
