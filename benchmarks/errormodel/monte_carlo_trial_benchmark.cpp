// One Monte Carlo trial of the ring-gauge experiment without the cost of the random numbers:
// the sequence validation/ runs per trial (docs/performance.md, "the ring-gauge trial"),
//
//   once:  best = correct(measured, model)
//   trial: draw_errors(model, best, rng, all stages, draw)
//          simulate(best, model, draw, …, first_order, sim); correct(sim, …, corr)
//          pts = xy of corr;  LS circle (diameter);  Gaussian filter 50 UPR;  MZ (RONt)
//
// What is measured (wall time per trial) and against what: the budget of ≤ ~150 µs
// per trial on one core for everything but the random numbers (≥ 10 000 trials/s on 2 cores
// with a ~30 µs normal generator). The random source here is TableRandomSource: it copies
// standard normals from a table made once (65 536 values from SeededRandomSource, so the
// draw and the geometry see realistic data), cycling through it, so that the generator's
// own cost is reduced to a memory copy (measured alone in BM_TableNormals: subtract it to
// get the non-RNG figure). Measured data: the seed study's 171 mm ring (3600 points, orders
// 2-17 form), placed at (600, 500, 250) mm, rotated 0.3 rad, read at 20.4 °C, simulated once
// with all five sources (seed 11) and corrected to the best estimate.
//
//   BM_TrialComposed        the sequence above with the general entry points
//   BM_TrialFused           the same on a PreparedMeasurement (validated once), with
//                           simulate_corrected (x, y out) and the LS-sharing filter
//   BM_Trial{Draw, DrawPrepared, SimulateCorrect, SimulateCorrectFused (Measurement in),
//            SimulateCorrectPrepared, LeastSquares, Filter, FilterSharedLs, MinimumZone,
//            MinimumZoneLocal}   its pieces, on one trial's data
// Sizes 360, 3600 (the case), 36 000. Results and machine: docs/performance.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/random_source.h"
#include "vcmm/errormodel/ring_gauge.h"
#include "vcmm/errormodel/virtual_cmm.h"
#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/minimum_zone.h"

namespace {

using namespace vcmm::errormodel;
namespace geo = vcmm::geometry;

/// Standard normals copied from a fixed table (made once by SeededRandomSource), cycling:
/// realistic values at the cost of a memory copy. Uniforms likewise from a uniform table.
class TableRandomSource final : public RandomSource {
 public:
  TableRandomSource() {
    static const std::vector<double> normals = make(true), uniforms = make(false);
    normals_ = &normals;
    uniforms_ = &uniforms;
  }
  void fill_standard_normal(std::span<double> out) override { copy(*normals_, out); }
  void fill_uniform(std::span<double> out) override { copy(*uniforms_, out); }

 private:
  static constexpr std::size_t kSize = std::size_t{1} << 16;
  static std::vector<double> make(bool normal) {
    SeededRandomSource rng(20260101);
    std::vector<double> v(kSize);
    if (normal)
      rng.fill_standard_normal(v);
    else
      rng.fill_uniform(v);
    return v;
  }
  void copy(const std::vector<double>& table, std::span<double> out) {
    std::size_t done = 0;
    while (done < out.size()) {
      const std::size_t k = std::min(out.size() - done, kSize - cursor_);
      std::copy_n(table.begin() + static_cast<std::ptrdiff_t>(cursor_), k, out.begin() +
                  static_cast<std::ptrdiff_t>(done));
      done += k;
      cursor_ = (cursor_ + k) % kSize;
    }
  }
  const std::vector<double>* normals_ = nullptr;
  const std::vector<double>* uniforms_ = nullptr;
  std::size_t cursor_ = 0;
};

const DigitalModel& example_model() {
  static const DigitalModel model =
      read_digital_model_file(std::string(VCMM_SOURCE_DIR) + "/examples/cmm_model.json");
  return model;
}

/// The best estimate of a simulated measurement of the seed-study ring (see file comment).
Measurement best_estimate(Eigen::Index n) {
  RingGauge g;
  g.form = seed_study_ring_form();
  RingSampling s;
  s.points = n;
  s.placement.location_mm = {600.0, 500.0, 250.0};
  s.placement.orientation_rad = 0.3;
  s.temperature_c = 20.4;
  const Measurement truth = ring_gauge_measurement(g, s);
  SeededRandomSource rng(11);
  const Measurement measured =
      simulate(truth, example_model(), draw_errors(example_model(), truth, rng));
  return correct(measured, example_model());
}

void xy_of(const Measurement& m, std::vector<geo::Point2>& out) {
  out.resize(static_cast<std::size_t>(m.size()));
  for (Eigen::Index i = 0; i < m.size(); ++i)
    out[static_cast<std::size_t>(i)] = {m.points_mm(0, i), m.points_mm(1, i)};
}

constexpr double kCutoffUpr = 50.0;

void BM_TrialComposed(benchmark::State& state) {
  const DigitalModel& model = example_model();
  const Measurement best = best_estimate(state.range(0));
  TableRandomSource rng;
  ErrorDraw draw;
  Measurement sim, corr;
  std::vector<geo::Point2> pts;
  const geo::MinimumZoneOptions options;
  for (auto _ : state) {
    draw_errors(model, best, rng, Stages::all(), draw);
    simulate(best, model, draw, Stages::all(), Formula::first_order, sim);
    correct(sim, model, Stages::all(), Formula::first_order, corr);
    xy_of(corr, pts);
    const geo::LeastSquaresCircle ls = geo::least_squares_circle(pts);
    const geo::FilteredProfile f = geo::gaussian_filtered_profile(pts, kCutoffUpr);
    const geo::MinimumZoneCircle mz = geo::minimum_zone_circle(f.points, options);
    benchmark::DoNotOptimize(2.0 * ls.radius);
    benchmark::DoNotOptimize(mz.outer_radius - mz.inner_radius);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_TrialFused(benchmark::State& state) {
  const DigitalModel& model = example_model();
  const PreparedMeasurement best(best_estimate(state.range(0)), model);
  TableRandomSource rng;
  ErrorDraw draw;
  std::vector<geo::Point2> pts;
  const geo::MinimumZoneOptions options;
  for (auto _ : state) {
    draw_errors(model, best, rng, Stages::all(), draw);
    simulate_corrected(best, model, draw, Stages::all(), Formula::first_order, pts);
    const geo::LeastSquaresCircle ls = geo::least_squares_circle(pts);
    const geo::FilteredProfile f = geo::gaussian_filtered_profile(pts, kCutoffUpr, ls);
    const geo::MinimumZoneCircle mz = geo::minimum_zone_circle(f.points, options);
    benchmark::DoNotOptimize(2.0 * ls.radius);
    benchmark::DoNotOptimize(mz.outer_radius - mz.inner_radius);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_TableNormals(benchmark::State& state) {
  TableRandomSource rng;
  std::vector<double> z(static_cast<std::size_t>(4 * state.range(0)));
  for (auto _ : state) {
    rng.fill_standard_normal(z);
    benchmark::DoNotOptimize(z.data());
  }
}

/// One trial's corrected points (for the per-piece benchmarks of the geometry).
std::vector<geo::Point2> trial_points(Eigen::Index n) {
  const Measurement best = best_estimate(n);
  TableRandomSource rng;
  const ErrorDraw draw = draw_errors(example_model(), best, rng);
  std::vector<geo::Point2> pts;
  xy_of(correct(simulate(best, example_model(), draw), example_model()), pts);
  return pts;
}

void BM_TrialDraw(benchmark::State& state) {
  const Measurement best = best_estimate(state.range(0));
  TableRandomSource rng;
  ErrorDraw draw;
  for (auto _ : state) {
    draw_errors(example_model(), best, rng, Stages::all(), draw);
    benchmark::DoNotOptimize(draw.noise_mm.data());
  }
}

void BM_TrialSimulateCorrect(benchmark::State& state) {
  const Measurement best = best_estimate(state.range(0));
  TableRandomSource rng;
  const ErrorDraw draw = draw_errors(example_model(), best, rng);
  Measurement sim, corr;
  for (auto _ : state) {
    simulate(best, example_model(), draw, Stages::all(), Formula::first_order, sim);
    correct(sim, example_model(), Stages::all(), Formula::first_order, corr);
    benchmark::DoNotOptimize(corr.points_mm.data());
  }
}

void BM_TrialSimulateCorrectFused(benchmark::State& state) {
  const Measurement best = best_estimate(state.range(0));
  TableRandomSource rng;
  const ErrorDraw draw = draw_errors(example_model(), best, rng);
  std::vector<geo::Point2> pts;
  for (auto _ : state) {
    simulate_corrected(best, example_model(), draw, Stages::all(), Formula::first_order, pts);
    benchmark::DoNotOptimize(pts.data());
  }
}

void BM_TrialSimulateCorrectPrepared(benchmark::State& state) {
  const PreparedMeasurement best(best_estimate(state.range(0)), example_model());
  TableRandomSource rng;
  const ErrorDraw draw = draw_errors(example_model(), best.measurement(), rng);
  std::vector<geo::Point2> pts;
  for (auto _ : state) {
    simulate_corrected(best, example_model(), draw, Stages::all(), Formula::first_order, pts);
    benchmark::DoNotOptimize(pts.data());
  }
}

void BM_TrialDrawPrepared(benchmark::State& state) {
  const PreparedMeasurement best(best_estimate(state.range(0)), example_model());
  TableRandomSource rng;
  ErrorDraw draw;
  for (auto _ : state) {
    draw_errors(example_model(), best, rng, Stages::all(), draw);
    benchmark::DoNotOptimize(draw.noise_mm.data());
  }
}

void BM_TrialLeastSquares(benchmark::State& state) {
  const std::vector<geo::Point2> pts = trial_points(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(geo::least_squares_circle(pts));
}

void BM_TrialFilter(benchmark::State& state) {
  const std::vector<geo::Point2> pts = trial_points(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(geo::gaussian_filtered_profile(pts, kCutoffUpr));
}

void BM_TrialFilterSharedLs(benchmark::State& state) {
  const std::vector<geo::Point2> pts = trial_points(state.range(0));
  const geo::LeastSquaresCircle ls = geo::least_squares_circle(pts);
  for (auto _ : state)
    benchmark::DoNotOptimize(geo::gaussian_filtered_profile(pts, kCutoffUpr, ls));
}

void BM_TrialMinimumZone(benchmark::State& state) {
  const std::vector<geo::Point2> pts = trial_points(state.range(0));
  const geo::FilteredProfile f = geo::gaussian_filtered_profile(pts, kCutoffUpr);
  for (auto _ : state) benchmark::DoNotOptimize(geo::minimum_zone_circle(f.points));
}

void BM_TrialMinimumZoneLocal(benchmark::State& state) {
  const std::vector<geo::Point2> pts = trial_points(state.range(0));
  const geo::FilteredProfile f = geo::gaussian_filtered_profile(pts, kCutoffUpr);
  geo::MinimumZoneOptions o;
  o.prove_global = false;
  for (auto _ : state) benchmark::DoNotOptimize(geo::minimum_zone_circle(f.points, o));
}

#define VCMM_TRIAL_SIZES ->Arg(360)->Arg(3600)->Arg(36000)->Unit(benchmark::kMicrosecond)
BENCHMARK(BM_TrialComposed) VCMM_TRIAL_SIZES;
BENCHMARK(BM_TrialFused) VCMM_TRIAL_SIZES;
BENCHMARK(BM_TableNormals) VCMM_TRIAL_SIZES;
BENCHMARK(BM_TrialDraw) VCMM_TRIAL_SIZES;
BENCHMARK(BM_TrialDrawPrepared) VCMM_TRIAL_SIZES;
BENCHMARK(BM_TrialSimulateCorrect) VCMM_TRIAL_SIZES;
BENCHMARK(BM_TrialSimulateCorrectFused) VCMM_TRIAL_SIZES;
BENCHMARK(BM_TrialSimulateCorrectPrepared) VCMM_TRIAL_SIZES;
BENCHMARK(BM_TrialLeastSquares) VCMM_TRIAL_SIZES;
BENCHMARK(BM_TrialFilter) VCMM_TRIAL_SIZES;
BENCHMARK(BM_TrialFilterSharedLs) VCMM_TRIAL_SIZES;
BENCHMARK(BM_TrialMinimumZone) VCMM_TRIAL_SIZES;
BENCHMARK(BM_TrialMinimumZoneLocal) VCMM_TRIAL_SIZES;

}  // namespace
// main(): BENCHMARK_MAIN in kinematic_errors_benchmark.cpp (one per executable).
