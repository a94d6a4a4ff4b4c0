// Kinematic tip errors: cost of tip_errors() per ring (the Monte Carlo inner loop) and of one
// draw() of all 21 error functions' coefficients.
//
// Measured: a ring of n points (n swept 360 … 36 000; 3 600 is the scanning case of the seed
// study) at a general location with a stylus offset, moving-bridge chain, all 18 functions
// cubic (4 Legendre coefficients each) with non-zero uncertainty, plus the 3 squareness terms.
// Against: the budget of the whole simulate stage, < 100 µs per 3 600-point ring; the
// kinematic part should stay well under 30 µs. Fixed seed; preallocated output (the
// no-allocation overload). Results with machine and command in docs/performance.md.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>

#include "vcmm/errormodel/kinematic_errors.h"

namespace {

using namespace vcmm::errormodel;

KinematicModel cubic_model() {
  std::array<ErrorFunctionEstimate, axis_error_count> fns;
  for (int f = 0; f < axis_error_count; ++f) {
    const double scale = is_rotation(static_cast<AxisError>(f)) ? 0.3e-6 : 0.2e-3;
    fns[f].coefficients = {0.1 * scale, 0.5 * scale, 0.3 * scale, 0.1 * scale};
    fns[f].standard_uncertainties = {0.2 * scale, 0.2 * scale, 0.1 * scale, 0.1 * scale};
  }
  std::array<EstimatedValue, squareness_count> sq{{{0.5e-6, 0.3e-6}, {0.3e-6, 0.3e-6}, {0.2e-6, 0.3e-6}}};
  return KinematicModel(KinematicChain::moving_bridge(), {{{0, 800}, {0, 1000}, {-600, 0}}}, fns,
                        sq);
}

Eigen::Matrix3Xd ring(int n) {
  Eigen::Matrix3Xd p(3, n);
  for (int i = 0; i < n; ++i) {
    const double th = 2.0 * std::numbers::pi * i / n;
    p.col(i) << 400.0 + 85.5 * std::cos(th), 500.0 + 85.5 * std::sin(th), -350.0;
  }
  return p;
}

void run(benchmark::State& state, Formula formula) {
  const auto model = cubic_model();
  SeededRandomSource rng(1);
  const auto errors = model.draw(rng);
  const int n = static_cast<int>(state.range(0));
  const Eigen::Matrix3Xd p = ring(n);
  const Eigen::Vector3d t(0.0, 0.0, -100.0);
  Eigen::Matrix3Xd out(3, n);
  for (auto _ : state) {
    tip_errors(model, errors, p, t, formula, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * n);
}

void BM_TipErrorsFirstOrder(benchmark::State& state) { run(state, Formula::first_order); }
void BM_TipErrorsExact(benchmark::State& state) { run(state, Formula::exact); }
BENCHMARK(BM_TipErrorsFirstOrder)->Arg(360)->Arg(3600)->Arg(36000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TipErrorsExact)->Arg(360)->Arg(3600)->Unit(benchmark::kMicrosecond);

void BM_DrawKinematicErrors(benchmark::State& state) {
  const auto model = cubic_model();  // 18·4 + 3 = 75 uncertain parameters
  SeededRandomSource rng(2);
  KinematicErrors e;
  for (auto _ : state) {
    model.draw(rng, e);
    benchmark::DoNotOptimize(e.parameters().data());
  }
}
BENCHMARK(BM_DrawKinematicErrors)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
