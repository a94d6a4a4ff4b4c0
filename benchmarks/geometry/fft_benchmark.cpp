// Benchmarks of the geometry module's FFT and the real transforms built on it.
//
// What: CPU time of one forward complex FFT (geometry/src/internal/fft.h) of length n on
// fixed pseudo-random data — n = 360, 1800 (the half-length transform of a 3600-point real
// profile), 3600, 3607 (prime: Bluestein) — and of EquiangularTransform::values at n = 3600
// from K + 1 harmonics (K = 50, 150, 250: the band-limited spectra of the spectral Monte
// Carlo trial, validation/src/spectral_trial.cpp; K = 1800: the full spectrum).
// Against: the same benchmarks before the change (docs/performance.md, "FFT").
#include <benchmark/benchmark.h>

#include <cstddef>
#include <random>
#include <string>
#include <vector>

#include "../../geometry/src/internal/aligned.h"
#include "../../geometry/src/internal/fft.h"
#include "vcmm/geometry/equiangular_transform.h"

namespace {

namespace g = vcmm::geometry;

std::vector<double> random_values(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> v(n);
  for (double& x : v) x = u(rng);
  return v;
}

/// Runs transform(re, im) on n values per iteration. Transforming the previous output again
/// keeps the data live; the values stay finite (they grow by √n per call, reset every 64
/// calls). Storage: std::vector<double> or internal::AlignedDoubles.
template <class Storage, class Transform>
void transform_repeatedly(benchmark::State& state, std::size_t n, Transform transform) {
  const std::vector<double> re0 = random_values(n, 1), im0 = random_values(n, 2);
  Storage re(re0.begin(), re0.end()), im(im0.begin(), im0.end());
  std::size_t calls = 0;
  for (auto _ : state) {
    transform(re.data(), im.data());
    benchmark::DoNotOptimize(re.data());
    benchmark::ClobberMemory();
    if (++calls % 64 == 0) {
      re.assign(re0.begin(), re0.end());
      im.assign(im0.begin(), im0.end());
    }
  }
}

void BM_ComplexFft(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  g::internal::ComplexFft fft(n);
  transform_repeatedly<std::vector<double>>(
      state, n, [&](double* re, double* im) { fft.forward(re, im); });
}
BENCHMARK(BM_ComplexFft)->Arg(360)->Arg(1800)->Arg(3600)->Arg(3607)->Unit(benchmark::kMicrosecond);

// The same on 64-byte aligned arrays (as the Gaussian filter's plan passes them).
void BM_ComplexFftAligned(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  g::internal::ComplexFft fft(n);
  transform_repeatedly<g::internal::AlignedDoubles>(
      state, n, [&](double* re, double* im) { fft.forward(re, im); });
}
BENCHMARK(BM_ComplexFftAligned)->Arg(360)->Arg(1800)->Arg(3600)->Unit(benchmark::kMicrosecond);

// The same with a named instruction-set variant (0: baseline, 1: avx2, 2: avx512 where the
// CPU has them), on aligned arrays.
void BM_ComplexFftVariant(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const auto& variants = g::internal::fft_variants();
  const auto v = static_cast<std::size_t>(state.range(1));
  if (v >= variants.size()) {
    state.SkipWithError("variant not available on this CPU");
    return;
  }
  state.SetLabel(std::string(variants[v].name));
  g::internal::ComplexFft fft(n);
  transform_repeatedly<g::internal::AlignedDoubles>(state, n, [&](double* re, double* im) {
    fft.forward_with(variants[v].name, re, im);
  });
}
BENCHMARK(BM_ComplexFftVariant)
    ->ArgsProduct({{360, 1800, 3600}, {0, 1, 2}})
    ->Unit(benchmark::kMicrosecond);

void BM_EquiangularValues(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const auto k = static_cast<std::size_t>(state.range(1));
  g::EquiangularTransform transform(n);
  const std::vector<double> a = random_values(k + 1, 3), b = random_values(k + 1, 4);
  std::vector<double> out(n);
  for (auto _ : state) {
    transform.values(a, b, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_EquiangularValues)
    ->Args({3600, 0})
    ->Args({3600, 5})
    ->Args({3600, 20})
    ->Args({3600, 50})
    ->Args({3600, 150})
    ->Args({3600, 250})
    ->Args({3600, 1800})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
