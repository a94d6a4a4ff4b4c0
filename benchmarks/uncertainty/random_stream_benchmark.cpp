// Random numbers and the Monte Carlo engine (vcmm::uncertainty). What is measured:
//
//   BM_FillStandardNormal/n  fill_standard_normal of n values from a fresh RandomStream (one
//                            per iteration, as one trial does): ns per normal. n = 14 400 is
//                            one 3 600-point ring's roughness + noise draws. Target ≤ ~2 ns.
//   BM_FillNormalScaled/k    14 400 normals times σ: k = 0 fill_standard_normal then a
//                            second pass multiplying by σ (as the error draw did), k = 1
//                            fill_normal(out, σ) (the same bits in one pass).
//   BM_FillUniform/n         the same for fill_uniform.
//   BM_StandardNormalSingle  standard_normal() one call at a time (same values as the bulk
//                            call; shows the cost of the per-call buffer check).
//   BM_PhiloxWords/k         the word generator alone, 128 blocks (256 words) per call, for
//                            every kernel this CPU runs (k: 0 scalar, 1 AVX2, 2 AVX-512F).
//   BM_EngineTrivial/threads run_monte_carlo with a trivial experiment (one uniform) and
//                            M = 100 000, q = 1: per-trial cost of the engine including its
//                            summary (sort) — the floor under any experiment. Wall time and
//                            process CPU time (all threads).
//   BM_Summarize/M           summarize() of M normal samples (the sort dominates).
// Fixed seeds. Machine, command and medians: docs/performance.md.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "internal/philox.h"
#include "vcmm/uncertainty/monte_carlo.h"
#include "vcmm/uncertainty/random_stream.h"
#include "vcmm/uncertainty/statistics.h"

namespace {

using namespace vcmm::uncertainty;

void BM_FillStandardNormal(benchmark::State& state) {
  std::vector<double> out(static_cast<std::size_t>(state.range(0)));
  std::uint64_t trial = 0;
  for (auto _ : state) {
    RandomStream rng(1, trial++);
    rng.fill_standard_normal(out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_FillStandardNormal)->Arg(16)->Arg(1'440)->Arg(14'400)->Arg(144'000);

void BM_FillNormalScaled(benchmark::State& state) {
  std::vector<double> out(14'400);
  const double sigma = 7e-4;
  std::uint64_t trial = 0;
  for (auto _ : state) {
    RandomStream rng(1, trial++);
    if (state.range(0) == 0) {
      rng.fill_standard_normal(out);
      for (double& v : out) v *= sigma;
    } else {
      rng.fill_normal(out, sigma);
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * 14'400);
}
BENCHMARK(BM_FillNormalScaled)->Arg(0)->Arg(1);

void BM_FillUniform(benchmark::State& state) {
  std::vector<double> out(static_cast<std::size_t>(state.range(0)));
  std::uint64_t trial = 0;
  for (auto _ : state) {
    RandomStream rng(1, trial++);
    rng.fill_uniform(out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_FillUniform)->Arg(14'400);

void BM_StandardNormalSingle(benchmark::State& state) {
  RandomStream rng(1, 0);
  for (auto _ : state) benchmark::DoNotOptimize(rng.standard_normal());
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_StandardNormalSingle);

void BM_PhiloxWords(benchmark::State& state) {
  const auto kernels = internal::available_philox_kernels();
  const auto k = static_cast<std::size_t>(state.range(0));
  if (k >= kernels.size()) {
    state.SkipWithError("kernel not available on this CPU");
    return;
  }
  state.SetLabel(kernels[k].name);
  std::vector<std::uint64_t> words(256);
  std::uint64_t block = 0;
  for (auto _ : state) {
    kernels[k].kernel(1, 0, block, 128, words.data());
    block += 128;
    benchmark::DoNotOptimize(words.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * 256);
}
BENCHMARK(BM_PhiloxWords)->DenseRange(0, 2);

void BM_EngineTrivial(benchmark::State& state) {
  constexpr std::uint64_t trials = 100'000;
  const Experiment trivial = [](RandomStream& rng, std::span<double> y) { y[0] = rng.uniform(); };
  MonteCarloOptions options;
  options.trials = trials;
  options.threads = static_cast<unsigned>(state.range(0));
  for (auto _ : state) {
    const MonteCarloResult r = run_monte_carlo(trivial, 1, options);
    benchmark::DoNotOptimize(r.summaries.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(trials));
}
BENCHMARK(BM_EngineTrivial)
    ->Arg(1)
    ->Arg(2)
    ->MeasureProcessCPUTime()  // CPU of all worker threads
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

void BM_Summarize(benchmark::State& state) {
  std::vector<double> samples(static_cast<std::size_t>(state.range(0)));
  RandomStream(3, 0).fill_standard_normal(samples);
  for (auto _ : state) benchmark::DoNotOptimize(summarize(samples, 0.95));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_Summarize)->Arg(100'000)->Arg(1'000'000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
