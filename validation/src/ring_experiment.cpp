// validation/src/ring_experiment.cpp — the ring-gauge virtual experiment (see the header for
// the flow and docs/validation.md for the method).
#include "vcmm/validation/ring_experiment.h"

#include <algorithm>
#include <functional>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "internal/stream_random_source.h"
#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/point.h"

namespace vcmm::validation {

using internal::StreamRandomSource;

errormodel::Measurement denoised_ring(const errormodel::Measurement& m, double cutoff_upr) {
  errormodel::validate_measurement(m, "denoised_ring");
  const auto profile = ring_profile(m);
  const auto filtered = geometry::gaussian_filtered_profile(profile, cutoff_upr);
  errormodel::Measurement out = m;
  for (Eigen::Index i = 0; i < m.size(); ++i) {
    out.points_mm(0, i) = filtered.points[static_cast<std::size_t>(i)].x;
    out.points_mm(1, i) = filtered.points[static_cast<std::size_t>(i)].y;
  }
  return out;
}

RingTrial::RingTrial(const errormodel::DigitalModel& model,
                     std::shared_ptr<const errormodel::PreparedMeasurement> prepared,
                     const RingEvaluationOptions& options, const errormodel::Stages& stages)
    : RingTrial(model, std::move(prepared), options, stages, stages) {}

RingTrial::RingTrial(const errormodel::DigitalModel& model,
                     std::shared_ptr<const errormodel::PreparedMeasurement> prepared,
                     const RingEvaluationOptions& options, const errormodel::Stages& drawn,
                     const errormodel::Stages& applied)
    : model_(&model), prepared_(std::move(prepared)), options_(options), drawn_(drawn),
      applied_(applied) {
  if (!prepared_) throw geometry::InvalidInput("RingTrial: no prepared measurement");
  for (const errormodel::ErrorSource s : errormodel::all_error_sources) {
    if (applied_.is_enabled(s) && !drawn_.is_enabled(s))
      throw geometry::InvalidInput(std::string("RingTrial: the applied stage '") +
                                   std::string(errormodel::to_string(s)) + "' is not drawn");
  }
}

void RingTrial::operator()(uncertainty::RandomStream& rng, std::span<double> measurands) {
  StreamRandomSource source(rng);
  errormodel::draw_errors(*model_, *prepared_, source, drawn_, draw_,
                         errormodel::NoiseComponents::xy);
  errormodel::simulate_corrected(*prepared_, *model_, draw_, applied_,
                                 errormodel::Formula::first_order, profile_);
  const RingMeasurands y = evaluate_ring(profile_, options_);
  measurands[diameter] = y.diameter_mm;
  measurands[roundness] = y.roundness_mm;
}

uncertainty::ExperimentFactory ring_experiment_factory(const errormodel::DigitalModel& model,
                                                       const errormodel::Measurement& best,
                                                       const RingEvaluationOptions& options,
                                                       const errormodel::Stages& stages) {
  return ring_experiment_factory(model, best, options, stages, stages);
}

uncertainty::ExperimentFactory ring_experiment_factory(const errormodel::DigitalModel& model,
                                                       const errormodel::Measurement& best,
                                                       const RingEvaluationOptions& options,
                                                       const errormodel::Stages& drawn,
                                                       const errormodel::Stages& applied) {
  auto prepared = std::make_shared<const errormodel::PreparedMeasurement>(best, model);
  return [&model, prepared, options, drawn, applied]() -> uncertainty::Experiment {
    auto trial = std::make_shared<RingTrial>(model, prepared, options, drawn, applied);
    return [trial](uncertainty::RandomStream& rng, std::span<double> out) { (*trial)(rng, out); };
  };
}

namespace {

/// Seed purposes of the shrinkage treatment's runs (uncertainty::derived_seed).
constexpr std::uint64_t kPilotPurpose = 1;
constexpr std::uint64_t kSurrogatePurpose = 2;

/// Progress of a later run reported as part of the whole evaluation: (offset + done, total).
std::function<void(std::uint64_t, std::uint64_t)> offset_progress(
    const std::function<void(std::uint64_t, std::uint64_t)>& progress, std::uint64_t offset,
    std::uint64_t total) {
  if (!progress) return {};
  return [progress, offset, total](std::uint64_t done, std::uint64_t planned) {
    progress(offset + done, std::max(total, offset + planned));
  };
}

/// The shrinkage treatment (form_bias.h) after the first run: pilot, surrogate, second run.
/// `later`: trials planned after this treatment (the budget's), for the progress total.
void run_shrinkage(const errormodel::DigitalModel& model, const RingUncertaintyOptions& options,
                   std::uint64_t later, RingUncertaintyResult& result) {
  const std::uint64_t m1 = result.monte_carlo.trials;
  const std::uint64_t m2 = options.shrinkage.surrogate_trials == 0
                               ? m1
                               : std::min(m1, options.shrinkage.surrogate_trials);
  const std::uint64_t pilot = options.shrinkage.pilot_trials;
  const std::uint64_t total = m1 + pilot + m2 + later;
  SurrogateRun run;
  uncertainty::MonteCarloOptions pilot_run = options.monte_carlo;
  pilot_run.seed = uncertainty::derived_seed(options.monte_carlo.seed, kPilotPurpose);
  auto shrinkage = estimate_harmonic_shrinkage(model, result.best_estimate, options.evaluation,
                                               options.stages, options.shrinkage, pilot_run);
  const auto cancelled = [&result](const char* when) {
    result.monte_carlo.status = uncertainty::RunStatus::cancelled;
    result.monte_carlo.message = std::string("cancelled during the shrinkage treatment's ") + when;
  };
  if (!shrinkage) return cancelled("pilot run");
  run.shrinkage = std::move(*shrinkage);
  if (options.monte_carlo.progress) options.monte_carlo.progress(m1 + pilot, total);
  run.surrogate = shrunk_ring(result.best_estimate, run.shrinkage, options.evaluation);
  uncertainty::MonteCarloOptions mc = options.monte_carlo;
  mc.trials = m2;
  mc.seed = uncertainty::derived_seed(options.monte_carlo.seed, kSurrogatePurpose);
  mc.progress = offset_progress(options.monte_carlo.progress, m1 + pilot, total);
  run.monte_carlo = uncertainty::run_monte_carlo(
      surrogate_experiment_factory(model, run.surrogate.surface, options.evaluation, options.stages,
                                   run.shrinkage),
      surrogate_measurand_count, mc);
  if (run.monte_carlo.status == uncertainty::RunStatus::cancelled) return cancelled("second run");
  result.roundness = uncertainty::correct_bias_at_surrogate(
      result.estimate.roundness_mm, run.surrogate.measurands.roundness_mm,
      run.monte_carlo.summaries[surrogate_roundness], run.monte_carlo.summaries[surrogate_shrunk],
      true);
  result.roundness_treatment = RoundnessBiasTreatment::shrinkage;
  result.surrogate = std::move(run);
}

RingUncertaintyResult run_on_surface(const errormodel::DigitalModel& model,
                                     errormodel::Measurement surface,
                                     const RingUncertaintyOptions& options) {
  RingUncertaintyResult result;
  result.best_estimate = std::move(surface);
  result.estimate = evaluate_ring(result.best_estimate, options.evaluation);
  result.trial = choose_ring_trial(model, result.best_estimate, options.evaluation,
                                   options.stages, options.trial, options.budget.has_value());
  const auto factory =
      result.trial.kind == TrialKind::spectral
          ? spectral_ring_experiment_factory(model, result.best_estimate, options.evaluation,
                                             options.stages)
          : ring_experiment_factory(model, result.best_estimate, options.evaluation,
                                    options.stages);
  const bool shrinkage = options.roundness_bias == RoundnessBiasTreatment::shrinkage;
  uncertainty::MonteCarloOptions first = options.monte_carlo;
  // Trials planned after the first run of m trials: the shrinkage's, the budget's.
  const auto budget_planned = [&options](std::uint64_t m) -> std::uint64_t {
    if (!options.budget) return 0;
    std::uint64_t runs = 0;
    for (const errormodel::ErrorSource s : errormodel::all_error_sources)
      runs += options.stages.is_enabled(s) ? 1 : 0;
    return runs * budget_trials(*options.budget, m);
  };
  if (!options.adaptive) {
    const std::uint64_t m = options.monte_carlo.trials;
    const std::uint64_t m2 = options.shrinkage.surrogate_trials == 0
                                 ? m
                                 : std::min(m, options.shrinkage.surrogate_trials);
    const std::uint64_t later =
        (shrinkage ? m2 + options.shrinkage.pilot_trials : 0) + budget_planned(m);
    if (later > 0) first.progress = offset_progress(options.monte_carlo.progress, 0, m + later);
  }
  result.monte_carlo =
      options.adaptive
          ? uncertainty::run_adaptive_monte_carlo(factory, ring_measurand_count,
                                                  *options.adaptive, first)
          : uncertainty::run_monte_carlo(factory, ring_measurand_count, first);
  result.roundness_treatment = RoundnessBiasTreatment::paper;
  if (result.monte_carlo.summaries.empty()) return result;  // below the minimum sample count
  result.diameter = uncertainty::correct_bias(
      result.estimate.diameter_mm, result.monte_carlo.summaries[diameter], true);
  result.roundness_paper = uncertainty::correct_bias(
      result.estimate.roundness_mm, result.monte_carlo.summaries[roundness], true);
  result.roundness = result.roundness_paper;
  const std::uint64_t later = budget_planned(result.monte_carlo.trials);
  if (shrinkage && result.monte_carlo.status != uncertainty::RunStatus::cancelled)
    run_shrinkage(model, options, later, result);
  if (options.budget && result.monte_carlo.status != uncertainty::RunStatus::cancelled) {
    // Progress: the budget's runs come last, after every trial run so far.
    const std::uint64_t before =
        result.monte_carlo.trials + (result.surrogate ? result.surrogate->shrinkage.pilot_trials +
                                                            result.surrogate->monte_carlo.trials
                                                      : 0);
    uncertainty::MonteCarloOptions mc = options.monte_carlo;
    mc.progress = offset_progress(options.monte_carlo.progress, before, before + later);
    result.budget = ring_uncertainty_budget(model, result.best_estimate, options.evaluation,
                                            options.stages, result.monte_carlo, *options.budget,
                                            mc);
    if (!result.budget) {
      result.monte_carlo.status = uncertainty::RunStatus::cancelled;
      result.monte_carlo.message = "cancelled during the uncertainty budget's runs";
    }
  }
  return result;
}

}  // namespace

RingUncertaintyResult evaluate_ring_uncertainty(const errormodel::DigitalModel& model,
                                                const errormodel::Measurement& measured,
                                                const RingUncertaintyOptions& options) {
  errormodel::validate_measurement(measured, "evaluate_ring_uncertainty");
  return run_on_surface(model,
                        errormodel::correct(measured, model, options.stages,
                                            errormodel::Formula::first_order),
                        options);
}

RingUncertaintyResult evaluate_ring_uncertainty_on_surface(
    const errormodel::DigitalModel& model, const errormodel::Measurement& truth_estimate,
    const RingUncertaintyOptions& options) {
  errormodel::validate_measurement(truth_estimate, "evaluate_ring_uncertainty_on_surface");
  RingUncertaintyOptions o = options;
  o.roundness_bias = RoundnessBiasTreatment::paper;  // the surface is the surrogate already
  return run_on_surface(model, truth_estimate, o);
}

}  // namespace vcmm::validation
