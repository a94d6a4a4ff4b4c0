// The virtual CMM in the Monte Carlo inner loop: one 171 mm ring with the example digital
// model (examples/cmm_model.json), all five stages, first-order kinematics unless named.
//
//   BM_Simulate            simulate() with a precomputed draw (the model's own cost)
//   BM_DrawErrors          draw_errors() with SeededRandomSource (4N + ~100 normals)
//   BM_DrawAndSimulate     the two together: the figure ("well under 100 µs at 3600")
//   BM_MonteCarloTrial     draw + simulate + correct: one trial before the geometry evaluation
//   BM_SimulateExact       simulate() with the exact kinematic chain
//   BM_StandardNormals     the random numbers alone (4N normals), for comparison
// Sizes: 16 (touch-trigger), 360, 3600 (the seed study's scan), 36000. Fixed seeds; outputs
// reused across iterations (no allocation in draw_errors once sized). Results and machine in
// docs/performance.md.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/random_source.h"
#include "vcmm/errormodel/ring_gauge.h"
#include "vcmm/errormodel/virtual_cmm.h"

namespace {

using namespace vcmm::errormodel;

const DigitalModel& example_model() {
  static const DigitalModel model =
      read_digital_model_file(std::string(VCMM_SOURCE_DIR) + "/examples/cmm_model.json");
  return model;
}

Measurement ring(benchmark::State& state) {
  RingGauge g;
  g.form = seed_study_ring_form();
  RingSampling s;
  s.points = state.range(0);
  s.mode = s.points < 100 ? ProbingMode::touch_trigger : ProbingMode::scanning;
  s.placement.location_mm = {600.0, 500.0, 250.0};
  s.placement.orientation_rad = 0.3;
  s.temperature_c = 20.4;
  return ring_gauge_measurement(g, s);
}

void BM_Simulate(benchmark::State& state) {
  const DigitalModel& model = example_model();
  const Measurement m = ring(state);
  SeededRandomSource rng(1);
  const ErrorDraw d = draw_errors(model, m, rng);
  Measurement out;
  for (auto _ : state) {
    simulate(m, model, d, Stages::all(), Formula::first_order, out);
    benchmark::DoNotOptimize(out.points_mm.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

void BM_DrawErrors(benchmark::State& state) {
  const DigitalModel& model = example_model();
  const Measurement m = ring(state);
  SeededRandomSource rng(2);
  ErrorDraw d;
  for (auto _ : state) {
    draw_errors(model, m, rng, Stages::all(), d);
    benchmark::DoNotOptimize(d.noise_mm.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

void BM_DrawAndSimulate(benchmark::State& state) {
  const DigitalModel& model = example_model();
  const Measurement m = ring(state);
  SeededRandomSource rng(3);
  ErrorDraw d;
  Measurement out;
  for (auto _ : state) {
    draw_errors(model, m, rng, Stages::all(), d);
    simulate(m, model, d, Stages::all(), Formula::first_order, out);
    benchmark::DoNotOptimize(out.points_mm.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

void BM_MonteCarloTrial(benchmark::State& state) {
  const DigitalModel& model = example_model();
  const Measurement m = ring(state);
  SeededRandomSource rng(4);
  ErrorDraw d;
  Measurement simulated, corrected;
  for (auto _ : state) {
    draw_errors(model, m, rng, Stages::all(), d);
    simulate(m, model, d, Stages::all(), Formula::first_order, simulated);
    correct(simulated, model, Stages::all(), Formula::first_order, corrected);
    benchmark::DoNotOptimize(corrected.points_mm.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

void BM_SimulateExact(benchmark::State& state) {
  const DigitalModel& model = example_model();
  const Measurement m = ring(state);
  SeededRandomSource rng(5);
  const ErrorDraw d = draw_errors(model, m, rng);
  Measurement out;
  for (auto _ : state) {
    simulate(m, model, d, Stages::all(), Formula::exact, out);
    benchmark::DoNotOptimize(out.points_mm.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

void BM_StandardNormals(benchmark::State& state) {
  SeededRandomSource rng(6);
  std::vector<double> z(static_cast<std::size_t>(4 * state.range(0)));
  for (auto _ : state) {
    rng.fill_standard_normal(z);
    benchmark::DoNotOptimize(z.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

#define VCMM_RING_SIZES ->Arg(16)->Arg(360)->Arg(3600)->Arg(36000)->Unit(benchmark::kMicrosecond)
BENCHMARK(BM_Simulate) VCMM_RING_SIZES;
BENCHMARK(BM_DrawErrors) VCMM_RING_SIZES;
BENCHMARK(BM_DrawAndSimulate) VCMM_RING_SIZES;
BENCHMARK(BM_MonteCarloTrial) VCMM_RING_SIZES;
BENCHMARK(BM_SimulateExact) VCMM_RING_SIZES;
BENCHMARK(BM_StandardNormals) VCMM_RING_SIZES;

}  // namespace
// main(): BENCHMARK_MAIN in kinematic_errors_benchmark.cpp (one per executable).
