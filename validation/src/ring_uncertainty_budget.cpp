// validation/src/ring_uncertainty_budget.cpp — one-at-a-time runs on common random numbers
// (the method and its limits: the header and docs/validation.md, "Uncertainty budget").
#include "vcmm/validation/ring_uncertainty_budget.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <span>

#include "vcmm/uncertainty/errors.h"
#include "vcmm/uncertainty/statistics.h"
#include "vcmm/validation/ring_experiment.h"

namespace vcmm::validation {

std::uint64_t budget_trials(const BudgetOptions& budget, std::uint64_t full_trials) {
  return budget.trials == 0 ? full_trials : std::min(budget.trials, full_trials);
}

std::optional<UncertaintyBudget> ring_uncertainty_budget(
    const errormodel::DigitalModel& model, const errormodel::Measurement& best,
    const RingEvaluationOptions& evaluation, const errormodel::Stages& stages,
    const uncertainty::MonteCarloResult& full, const BudgetOptions& budget,
    const uncertainty::MonteCarloOptions& monte_carlo) {
  if (full.summaries.empty() || full.measurand_count != ring_measurand_count)
    throw uncertainty::InvalidInput(
        "ring_uncertainty_budget: the full run has no statistics of the ring's two measurands");
  const auto start = std::chrono::steady_clock::now();
  UncertaintyBudget out;
  out.trials = budget_trials(budget, full.trials);
  // The full run's u over the same trials (all of them unless budget.trials cuts them).
  const std::span<const double> same_trials(full.samples.data(),
                                            out.trials * ring_measurand_count);
  const double p = monte_carlo.coverage_probability;
  out.diameter_full_u_mm =
      uncertainty::summarize_measurand(same_trials, ring_measurand_count, diameter, p)
          .standard_uncertainty;
  out.roundness_full_u_mm =
      uncertainty::summarize_measurand(same_trials, ring_measurand_count, roundness, p)
          .standard_uncertainty;

  std::uint64_t runs = 0;
  for (const errormodel::ErrorSource s : errormodel::all_error_sources)
    runs += stages.is_enabled(s) ? 1 : 0;
  const std::uint64_t planned = runs * out.trials;
  std::uint64_t done = 0;
  uncertainty::MonteCarloOptions mc = monte_carlo;
  mc.trials = out.trials;  // seed unchanged: trial t draws from the full run's stream t
  double diameter_sum = 0.0, roundness_sum = 0.0;
  for (const errormodel::ErrorSource s : errormodel::all_error_sources) {
    SourceContribution c;
    c.source = s;
    c.evaluated = stages.is_enabled(s);
    if (c.evaluated) {
      if (monte_carlo.progress) {
        mc.progress = [&progress = monte_carlo.progress, done, planned](std::uint64_t d,
                                                                       std::uint64_t) {
          progress(done + d, planned);
        };
      }
      const auto run = uncertainty::run_monte_carlo(
          ring_experiment_factory(model, best, evaluation, stages, errormodel::Stages::only(s)),
          ring_measurand_count, mc);
      if (run.status == uncertainty::RunStatus::cancelled) return std::nullopt;
      done += out.trials;
      c.diameter_u_mm = run.summaries.at(diameter).standard_uncertainty;
      c.roundness_u_mm = run.summaries.at(roundness).standard_uncertainty;
    }
    diameter_sum += c.diameter_u_mm * c.diameter_u_mm;
    roundness_sum += c.roundness_u_mm * c.roundness_u_mm;
    out.sources.push_back(c);
  }
  for (SourceContribution& c : out.sources) {
    if (diameter_sum > 0.0) c.diameter_share = c.diameter_u_mm * c.diameter_u_mm / diameter_sum;
    if (roundness_sum > 0.0)
      c.roundness_share = c.roundness_u_mm * c.roundness_u_mm / roundness_sum;
  }
  out.diameter_quadrature_mm = std::sqrt(diameter_sum);
  out.roundness_quadrature_mm = std::sqrt(roundness_sum);
  out.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace vcmm::validation
