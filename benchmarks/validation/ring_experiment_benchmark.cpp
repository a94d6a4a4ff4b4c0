// Trials per second of the ring-gauge virtual experiment (issue 4's target: ≥ 10 000 trials/s
// on this 2-core machine): a 3600-point scanning measurement (and a 360-point touch-trigger
// one) of the 171 mm ring at the centre of the volume, all five error sources of
// examples/cmm_model.json, LS diameter and RONt about the MZ circle after the 50 UPR Gaussian
// filter (the second argument picks the reference: 0 MZ, 1 MI, 2 LS; label). BM_RingMonteCarlo
// runs the whole engine (threads 1 and 2; items/s = trials/s) with the study's bias treatment
// only (one run); BM_RingTrial one trial on one thread (no engine), for the cost split. BM_SurrogateTrial is one trial of the shrinkage treatment's second run
// (simulate, LS, filter + RONt, harmonics, shrink + RONt; MZ and MI), and BM_RingShrinkage the
// whole default evaluation (first run, pilot of 400, second run) of M = 10⁴ trials, as one
// measurement of the demo costs. BM_SpectralTrial is one spectral trial (spectral_trial.h; LS,
// MZ, MI) on one thread, BM_SpectralMonteCarlo the whole first run with the spectral trial
// (threads 1 and 2; issue 14's targets: ≥ 100 000 trials/s with LS, ≥ 40 000 with MZ, 2 cores).
#include <benchmark/benchmark.h>

#include <memory>
#include <string>

#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/ring_gauge.h"
#include "vcmm/errormodel/virtual_cmm.h"
#include "vcmm/validation/ring_experiment.h"
#include "vcmm/validation/spectral_trial.h"

namespace {

namespace em = vcmm::errormodel;
namespace va = vcmm::validation;

const em::DigitalModel& example_model() {
  static const em::DigitalModel model =
      em::read_digital_model_file(std::string(VCMM_SOURCE_DIR) + "/examples/cmm_model.json");
  return model;
}

em::Measurement measured_ring(Eigen::Index n) {
  em::RingGauge ring;
  ring.form = em::seed_study_ring_form();
  em::RingSampling s;
  s.points = n;
  s.mode = n >= 1000 ? em::ProbingMode::scanning : em::ProbingMode::touch_trigger;
  s.placement.location_mm = {600.0, 500.0, 250.0};
  s.stylus_offset_mm = {0.0, 0.0, -100.0};
  s.temperature_c = 20.3;
  const em::Measurement truth = em::ring_gauge_measurement(ring, s);
  em::SeededRandomSource rng(11);
  return em::simulate(truth, example_model(), em::draw_errors(example_model(), truth, rng));
}

va::ReferenceCircle circle_of(std::int64_t code) {
  switch (code) {
    case 0: return va::ReferenceCircle::minimum_zone;
    case 1: return va::ReferenceCircle::maximum_inscribed;
    default: return va::ReferenceCircle::least_squares;
  }
}

const char* label_of(va::ReferenceCircle c) {
  switch (c) {
    case va::ReferenceCircle::minimum_zone: return "MZ";
    case va::ReferenceCircle::maximum_inscribed: return "MI";
    case va::ReferenceCircle::least_squares: return "LS";
    case va::ReferenceCircle::minimum_circumscribed: return "MC";
  }
  return "?";
}

/// Times one trial a benchmark iteration (trial t on RandomStream(1, t)); items = trials.
template <class Trial>
void time_trials(benchmark::State& state, Trial& trial) {
  double out[2];
  std::uint64_t t = 0;
  for (auto _ : state) {
    vcmm::uncertainty::RandomStream rng(1, t++);
    trial(rng, out);
    benchmark::DoNotOptimize(out);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_RingTrial(benchmark::State& state) {
  const em::Measurement best =
      em::correct(measured_ring(state.range(0)), example_model());
  va::RingEvaluationOptions e;
  e.reference = circle_of(state.range(1));
  va::RingTrial trial(example_model(),
                      std::make_shared<const em::PreparedMeasurement>(best, example_model()), e,
                      em::Stages::all());
  time_trials(state, trial);
  state.SetLabel(label_of(e.reference));
}
BENCHMARK(BM_RingTrial)
    ->Args({3600, 0})
    ->Args({3600, 1})
    ->Args({3600, 2})
    ->Args({360, 0})
    ->Unit(benchmark::kMicrosecond);

void BM_RingMonteCarlo(benchmark::State& state) {
  const em::Measurement measured = measured_ring(state.range(0));
  va::RingUncertaintyOptions o;
  o.roundness_bias = va::RoundnessBiasTreatment::paper;  // one run: trials/s of the engine
  o.trial = va::TrialKind::exact;  // the point-wise trial (BM_SpectralMonteCarlo: the other)
  o.evaluation.reference = circle_of(state.range(2));
  o.monte_carlo.trials = 2000;
  o.monte_carlo.threads = static_cast<unsigned>(state.range(1));
  for (auto _ : state) {
    const auto r = va::evaluate_ring_uncertainty(example_model(), measured, o);
    benchmark::DoNotOptimize(r.monte_carlo.samples.data());
  }
  state.SetItemsProcessed(state.iterations() * 2000);
  state.SetLabel(label_of(o.evaluation.reference));
}
BENCHMARK(BM_RingMonteCarlo)
    ->Args({3600, 1, 0})
    ->Args({3600, 2, 0})
    ->Args({3600, 1, 2})
    ->Args({3600, 2, 2})
    ->Args({3600, 2, 1})
    ->Args({360, 2, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_SurrogateTrial(benchmark::State& state) {
  const em::Measurement best = em::correct(measured_ring(state.range(0)), example_model());
  va::RingEvaluationOptions e;
  e.reference = circle_of(state.range(1));
  const auto shrinkage = va::estimate_harmonic_shrinkage(example_model(), best, e,
                                                         em::Stages::all(), {}, {});
  const va::Surrogate surrogate = va::shrunk_ring(best, *shrinkage, e);
  const auto experiment = va::surrogate_experiment_factory(
      example_model(), surrogate.surface, e, em::Stages::all(), *shrinkage)();
  double out[va::surrogate_measurand_count];
  std::uint64_t t = 0;
  for (auto _ : state) {
    vcmm::uncertainty::RandomStream rng(2, t++);
    experiment(rng, out);
    benchmark::DoNotOptimize(out);
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(label_of(e.reference));
}
BENCHMARK(BM_SurrogateTrial)
    ->Args({3600, 0})
    ->Args({3600, 1})
    ->Args({360, 1})
    ->Unit(benchmark::kMicrosecond);

void BM_RingShrinkage(benchmark::State& state) {
  const em::Measurement measured = measured_ring(state.range(0));
  va::RingUncertaintyOptions o;
  o.evaluation.reference = circle_of(state.range(1));
  o.monte_carlo.trials = 10000;
  o.monte_carlo.threads = 2;
  for (auto _ : state) {
    const auto r = va::evaluate_ring_uncertainty(example_model(), measured, o);
    benchmark::DoNotOptimize(r.roundness.corrected);
  }
  state.SetLabel(label_of(o.evaluation.reference));
}
BENCHMARK(BM_RingShrinkage)
    ->Args({3600, 1})
    ->Args({360, 1})
    ->Args({3600, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);

va::ReferenceCircle spectral_circle(std::int64_t code) {
  return code == 0   ? va::ReferenceCircle::least_squares
         : code == 1 ? va::ReferenceCircle::minimum_zone
                     : va::ReferenceCircle::maximum_inscribed;
}

void BM_SpectralTrial(benchmark::State& state) {
  const em::Measurement best = em::correct(measured_ring(state.range(0)), example_model());
  va::RingEvaluationOptions e;
  e.reference = spectral_circle(state.range(1));
  va::SpectralRingTrial trial(
      std::make_shared<const va::SpectralRingModel>(example_model(), best, e, em::Stages::all()));
  time_trials(state, trial);
  state.SetLabel(std::string(va::to_string(e.reference)));
}
BENCHMARK(BM_SpectralTrial)
    ->Args({3600, 0})
    ->Args({3600, 1})
    ->Args({3600, 2})
    ->Args({360, 1})
    ->Unit(benchmark::kMicrosecond);

void BM_SpectralMonteCarlo(benchmark::State& state) {
  const em::Measurement best = em::correct(measured_ring(state.range(0)), example_model());
  va::RingEvaluationOptions e;
  e.reference = spectral_circle(state.range(1));
  const auto factory = va::spectral_ring_experiment_factory(example_model(), best, e,
                                                            em::Stages::all());
  vcmm::uncertainty::MonteCarloOptions o;
  o.trials = 20000;
  o.threads = static_cast<unsigned>(state.range(2));
  for (auto _ : state) {
    const auto r = vcmm::uncertainty::run_monte_carlo(factory, va::ring_measurand_count, o);
    benchmark::DoNotOptimize(r.samples.data());
  }
  state.SetItemsProcessed(state.iterations() * 20000);
  state.SetLabel(std::string(va::to_string(e.reference)));
}
BENCHMARK(BM_SpectralMonteCarlo)
    ->Args({3600, 0, 1})
    ->Args({3600, 0, 2})
    ->Args({3600, 1, 1})
    ->Args({3600, 1, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
