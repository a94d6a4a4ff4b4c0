// Benchmarks of the ISO 12181-2 reference circles and the ISO 16610-21 filter.
//
// What: wall time of one evaluation on a nearly round profile — the 171 mm ring-gauge
// case: R = 85.5 mm, lobing of a few hundred nm (orders 2, 3, 5, 7, 15) and 50 nm white
// noise (tests/support/test_profiles.h, lobed_noisy_ring) — at n = 360, 3600, 36000.
// Against: the target of all four circles plus the filter in < 100 µs at n = 3600 on
// one core, cost growing about linearly with n. Fixed seeds; the profile is built once per
// size outside the timed loop. Results and machine: docs/performance.md.
//
// Degenerate but valid inputs (issue 11, item 3), registered in main(): MZ, MI, MC and the
// three verify() calls on a perfect circle (co-circular to the last ulp), an ulp-level form
// (1e-13 mm), a smooth few-harmonic form (0.2, 0.15, 0.1 µm at orders 2, 3, 4), a polygon with
// exact square symmetry (exact co-circular 8-tuples), integer points exactly on a circle,
// and the noisy ring above as the yardstick — at n = 360, 3600, 10⁴. Against: the noisy
// ring of the same size (within ~10×, no worse than O(n log n) growth).
#include <benchmark/benchmark.h>

#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "../../geometry/src/internal/isa.h"
#include "../../geometry/src/internal/least_squares_on_rays.h"
#include "support/test_profiles.h"
#include "vcmm/geometry/angular_coverage.h"
#include "vcmm/geometry/certificate.h"
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

// The same with the widest instruction-set variant its passes may take (0: baseline, 1: AVX2,
// 2: AVX-512; internal/isa.h — a variant the CPU lacks falls back to the next narrower one).
void BM_LeastSquaresIsa(benchmark::State& state) {
  const auto& p = profile(static_cast<std::size_t>(state.range(0)));
  const g::internal::LimitIsa limit(static_cast<g::internal::IsaLevel>(state.range(1)));
  for (auto _ : state) benchmark::DoNotOptimize(g::least_squares_circle(p));
}
BENCHMARK(BM_LeastSquaresIsa)->ArgsProduct({{3600}, {0, 1, 2}})->Unit(benchmark::kMicrosecond);

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

// The LS circle of the filtered profile as the Monte Carlo trial takes it (filter, then one
// step on the rays: gaussian_filtered_least_squares_circle), with the widest instruction-set
// variant allowed as in BM_LeastSquaresIsa.
void BM_FilteredLeastSquaresIsa(benchmark::State& state) {
  const auto& p = profile(static_cast<std::size_t>(state.range(0)));
  const g::LeastSquaresCircle ls = g::least_squares_circle(p);
  const g::internal::LimitIsa limit(static_cast<g::internal::IsaLevel>(state.range(1)));
  for (auto _ : state)
    benchmark::DoNotOptimize(g::gaussian_filtered_least_squares_circle(p, 50.0, ls, true));
}
BENCHMARK(BM_FilteredLeastSquaresIsa)
    ->ArgsProduct({{3600}, {0, 1, 2}})
    ->Unit(benchmark::kMicrosecond);

// Its last step alone (internal/least_squares_on_rays.h): the profile's own rays from its LS
// centre, w the deviations from the LS radius.
void BM_LeastSquaresOnRaysIsa(benchmark::State& state) {
  const auto& p = profile(static_cast<std::size_t>(state.range(0)));
  const g::LeastSquaresCircle ls = g::least_squares_circle(p);
  std::vector<double> w, x, y, inv;
  for (const g::Point2& q : p) {
    x.push_back(q.x - ls.center.x);
    y.push_back(q.y - ls.center.y);
    inv.push_back(1.0 / std::hypot(x.back(), y.back()));
    w.push_back(std::hypot(x.back(), y.back()) - ls.radius);
  }
  const g::internal::LimitIsa limit(static_cast<g::internal::IsaLevel>(state.range(1)));
  for (auto _ : state)
    benchmark::DoNotOptimize(g::internal::least_squares_circle_on_rays(
        ls.center, ls.radius, w.data(), x.data(), y.data(), inv.data(), p.size()));
}
BENCHMARK(BM_LeastSquaresOnRaysIsa)
    ->ArgsProduct({{3600}, {0, 1, 2}})
    ->Unit(benchmark::kMicrosecond);

// The whole evaluation of the target: filter (50 UPR) + LS + MZ + MI + MC.
/// The coverage evaluate_roundness reports: a scan in angular order about its LS centre (the
/// fast path: atan2 only for the steps that can be the largest gap).
void BM_AngularCoverage(benchmark::State& state) {
  const auto& p = profile(static_cast<std::size_t>(state.range(0)));
  const g::Point2 c = g::least_squares_circle(p).center;
  for (auto _ : state) benchmark::DoNotOptimize(g::angular_coverage(p, c));
}
BENCHMARK(BM_AngularCoverage)->Apply(sizes);

void BM_AllFourCirclesFiltered(benchmark::State& state) {
  const auto& p = profile(static_cast<std::size_t>(state.range(0)));
  g::RoundnessRequest r;
  r.filter_cutoff_upr = 50.0;
  for (auto _ : state) benchmark::DoNotOptimize(g::evaluate_roundness(p, r));
}
BENCHMARK(BM_AllFourCirclesFiltered)->Apply(sizes);

// The stages of BM_AllFourCirclesFiltered after the filter, one at a time, on the filtered
// profile (50 UPR) it fits them to: MZ, MI, MC and the coverage about the filtered LS centre.
const std::vector<g::Point2>& filtered_profile(std::size_t n) {
  static std::map<std::size_t, std::vector<g::Point2>> cache;
  auto& f = cache[n];
  if (f.empty()) f = g::gaussian_filtered_profile(profile(n), 50.0).points;
  return f;
}

void BM_FilteredMinimumZone(benchmark::State& state) {
  const auto& p = filtered_profile(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(g::minimum_zone_circle(p));
}
BENCHMARK(BM_FilteredMinimumZone)->Apply(sizes);

void BM_FilteredMaximumInscribed(benchmark::State& state) {
  const auto& p = filtered_profile(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(g::maximum_inscribed_circle(p));
}
BENCHMARK(BM_FilteredMaximumInscribed)->Apply(sizes);

void BM_FilteredMinimumCircumscribed(benchmark::State& state) {
  const auto& p = filtered_profile(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(g::minimum_circumscribed_circle(p));
}
BENCHMARK(BM_FilteredMinimumCircumscribed)->Apply(sizes);

void BM_FilteredAngularCoverage(benchmark::State& state) {
  const auto& p = filtered_profile(static_cast<std::size_t>(state.range(0)));
  const g::Point2 c = g::least_squares_circle(p).center;
  for (auto _ : state) benchmark::DoNotOptimize(g::angular_coverage(p, c));
}
BENCHMARK(BM_FilteredAngularCoverage)->Apply(sizes);

// ---- degenerate families ----------------------------------------------------------------

using Family = std::function<std::vector<g::Point2>(std::size_t)>;

/// A ring of radius 85.5 mm about (600, 500) with r(θ) = R + s·(2 cos(2θ + 1) +
/// 1.5 cos(3θ + 0.5) + cos 4θ)·1e-4 mm: s = 0 a perfect circle, s = 1 the smooth profile of
/// the issue with phases whose MI contacts are nearly antipodal at all three sizes (the
/// case that sent the MI fast path to the full Delaunay exhaustion).
std::vector<g::Point2> smooth_ring(std::size_t n, double s) {
  vcmm::test::RingSpec spec;
  spec.center = {600.0, 500.0};
  spec.n = n;
  if (s > 0.0) spec.harmonics = {{2, 2e-4 * s, 1.0}, {3, 1.5e-4 * s, 0.5}, {4, 1e-4 * s, 0.0}};
  return vcmm::test::ring_profile(spec);
}

const std::vector<std::pair<std::string, Family>>& families() {
  static const std::vector<std::pair<std::string, Family>> f = {
      {"perfect", [](std::size_t n) { return smooth_ring(n, 0.0); }},
      {"ulp_form", [](std::size_t n) { return smooth_ring(n, 5e-10); }},  // 1e-13 mm
      {"smooth", [](std::size_t n) { return smooth_ring(n, 1.0); }},
      {"symmetric_polygon", [](std::size_t n) { return vcmm::test::symmetric_polygon(n); }},
      {"lattice_circle", [](std::size_t n) { return vcmm::test::lattice_circle(n); }},
      {"noisy", [](std::size_t n) { return vcmm::test::lobed_noisy_ring(n, 20261122, 5e-5); }},
  };
  return f;
}

/// Registers name/n for n = 360, 3600 and 10⁴; `run(points, state)` holds the timed loop
/// (the profile is built outside it).
template <class Run>
void register_sizes(const std::string& name, const Family& make, Run run) {
  for (const std::size_t n : {std::size_t{360}, std::size_t{3600}, std::size_t{10000}}) {
    benchmark::RegisterBenchmark((name + "/" + std::to_string(n)).c_str(),
                                 [make, run, n](benchmark::State& state) { run(make(n), state); })
        ->Unit(benchmark::kMicrosecond);
  }
}

template <class Fit>
void register_fit(const std::string& name, const Family& make, Fit fit) {
  register_sizes(name, make, [fit](const std::vector<g::Point2>& p, benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(fit(p));
  });
}

/// verify() of a result computed once outside the timed loop.
template <class Fit>
void register_verify(const std::string& name, const Family& make, Fit fit) {
  register_sizes(name, make, [fit](const std::vector<g::Point2>& p, benchmark::State& state) {
    const auto result = fit(p);
    if (!g::verify(p, result)) state.SkipWithError("rejected");
    for (auto _ : state) benchmark::DoNotOptimize(g::verify(p, result).valid);
  });
}

void register_degenerate() {
  auto mz = [](const std::vector<g::Point2>& p) { return g::minimum_zone_circle(p); };
  auto mi = [](const std::vector<g::Point2>& p) { return g::maximum_inscribed_circle(p); };
  auto mc = [](const std::vector<g::Point2>& p) { return g::minimum_circumscribed_circle(p); };
  for (const auto& [family, make] : families()) {
    register_fit("Degenerate_MZ/" + family, make, mz);
    register_fit("Degenerate_MI/" + family, make, mi);
    register_fit("Degenerate_MC/" + family, make, mc);
    register_verify("Degenerate_VerifyMZ/" + family, make, mz);
    register_verify("Degenerate_VerifyMI/" + family, make, mi);
    register_verify("Degenerate_VerifyMC/" + family, make, mc);
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_degenerate();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
