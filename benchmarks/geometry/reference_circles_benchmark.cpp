// Benchmarks of the ISO 12181-2 reference circles and the ISO 16610-21 filter.
//
// What: wall time of one evaluation on a nearly round profile — the 171 mm ring-gauge
// case: R = 85.5 mm, lobing of a few hundred nm (orders 2, 3, 5, 7, 15) and 50 nm white
// noise (tests/support/test_profiles.h, lobed_noisy_ring) — at n = 360, 3600, 36000.
// Against: the target of all four circles plus the filter in < 100 µs at n = 3600 on
// one core, cost growing about linearly with n. Fixed seeds; the profile is built once per
// size outside the timed loop. Results and machine: docs/performance.md.
#include <benchmark/benchmark.h>

#include <vector>

#include "support/test_profiles.h"
#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/minimum_circumscribed.h"
#include "vcmm/geometry/minimum_zone.h"
#include "vcmm/geometry/roundness.h"

namespace {

namespace g = vcmm::geometry;

const std::vector<g::Point2>& profile(std::size_t n) {
  static std::vector<g::Point2> cache[3];
  const int k = n == 360 ? 0 : n == 3600 ? 1 : 2;
  if (cache[k].size() != n) cache[k] = vcmm::test::lobed_noisy_ring(n, 20261122, 5e-5);
  return cache[k];
}

void sizes(benchmark::internal::Benchmark* b) {
  b->Arg(360)->Arg(3600)->Arg(36000)->Unit(benchmark::kMicrosecond);
}

void BM_LeastSquares(benchmark::State& state) {
  const auto& p = profile(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(g::least_squares_circle(p));
  state.SetComplexityN(state.range(0));
}
BENCHMARK(BM_LeastSquares)->Apply(sizes);

void BM_MinimumZone(benchmark::State& state) {
  const auto& p = profile(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(g::minimum_zone_circle(p));
}
BENCHMARK(BM_MinimumZone)->Apply(sizes);

void BM_MinimumZoneLocalOnly(benchmark::State& state) {
  const auto& p = profile(static_cast<std::size_t>(state.range(0)));
  g::MinimumZoneOptions o;
  o.prove_global = false;
  for (auto _ : state) benchmark::DoNotOptimize(g::minimum_zone_circle(p, o));
}
BENCHMARK(BM_MinimumZoneLocalOnly)->Apply(sizes);

void BM_MinimumZoneOverlay(benchmark::State& state) {
  const auto& p = profile(static_cast<std::size_t>(state.range(0)));
  g::MinimumZoneOptions o;
  o.method = g::MinimumZoneMethod::overlay;
  for (auto _ : state) benchmark::DoNotOptimize(g::minimum_zone_circle(p, o));
}
BENCHMARK(BM_MinimumZoneOverlay)->Apply(sizes);

void BM_MaximumInscribed(benchmark::State& state) {
  const auto& p = profile(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(g::maximum_inscribed_circle(p));
}
BENCHMARK(BM_MaximumInscribed)->Apply(sizes);

void BM_MinimumCircumscribed(benchmark::State& state) {
  const auto& p = profile(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(g::minimum_circumscribed_circle(p));
}
BENCHMARK(BM_MinimumCircumscribed)->Apply(sizes);

void BM_GaussianFilter(benchmark::State& state) {
  const auto& p = profile(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(g::gaussian_filtered_profile(p, 50.0));
}
BENCHMARK(BM_GaussianFilter)->Apply(sizes);

// The filter about an LS circle the caller already has (the Monte Carlo trial fits it for
// the diameter anyway): BM_GaussianFilter without its LS fit.
void BM_GaussianFilterSharedLs(benchmark::State& state) {
  const auto& p = profile(static_cast<std::size_t>(state.range(0)));
  const g::LeastSquaresCircle ls = g::least_squares_circle(p);
  for (auto _ : state) benchmark::DoNotOptimize(g::gaussian_filtered_profile(p, 50.0, ls));
}
BENCHMARK(BM_GaussianFilterSharedLs)->Apply(sizes);

// The whole evaluation of the target: filter (50 UPR) + LS + MZ + MI + MC.
void BM_AllFourCirclesFiltered(benchmark::State& state) {
  const auto& p = profile(static_cast<std::size_t>(state.range(0)));
  g::RoundnessRequest r;
  r.filter_cutoff_upr = 50.0;
  for (auto _ : state) benchmark::DoNotOptimize(g::evaluate_roundness(p, r));
}
BENCHMARK(BM_AllFourCirclesFiltered)->Apply(sizes);

}  // namespace

BENCHMARK_MAIN();
