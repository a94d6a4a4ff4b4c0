// vcmm/validation/ring_uncertainty_budget.h — the uncertainty budget of one ring measurement:
// per error source, the standard uncertainty of the diameter and of the roundness that source
// produces alone (docs/validation.md, "Uncertainty budget").
//
// Method (one at a time, common random numbers). The full virtual experiment of
// ring_experiment.h draws every source from the trial's stream RandomStream(seed, t) in a
// fixed order; a stage that is off would consume no numbers and shift every later source onto
// other numbers. So the budget run of source i draws ALL the stages of the full run, exactly as
// the full run does, and simulates and corrects only stage i (RingTrial with drawn = the full
// run's stages, applied = Stages::only(i)): trial t of run i sees the very realisation of
// source i that trial t of the full run saw, the others held at their estimates. Then
//   u_i = s(y_i,1 … y_i,M)               that source alone (sample sd, M − 1),
//   u_Σ = √Σ_i u_i²                      the quadrature sum, beside the full run's u over the
//                                        same M trials, and their ratio u_Σ / u,
//   share_i = u_i² / Σ_j u_j²            the source's share of the one-at-a-time variance sum.
// For a measurand linear in the errors, y − y₀ = Σ_i c_i e_i, the run of source i gives
// exactly the term c_i e_i of the full run, and u² = Σ u_i² + 2 Σ_{i<j} cov_ij with sample
// covariances of independent sources, O(u_i u_j / √M): the ratio is 1 to Monte Carlo
// precision (the LS diameter). RONt is not linear: a peak-to-valley of the sum of the sources'
// deviations is not a sum of peak-to-valleys, each source alone is biased upward on its own,
// and the one-at-a-time u's do not add in quadrature (the ratio departs from 1): the shares
// then rank the sources, they do not split u².
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/measurement.h"
#include "vcmm/errormodel/virtual_cmm.h"
#include "vcmm/uncertainty/monte_carlo.h"
#include "vcmm/validation/ring_evaluation.h"

namespace vcmm::validation {

/// Options of the budget (RingUncertaintyOptions::budget).
struct BudgetOptions {
  /// Trials of each source's run; 0: as many as the full run completed. At most the full
  /// run's trials (more are cut to them): the ratio compares with the full run's u over the
  /// same trials, where the common random numbers hold.
  std::uint64_t trials = 0;
};

/// One source's contribution.
struct SourceContribution {
  errormodel::ErrorSource source = errormodel::ErrorSource::roughness;
  /// False when the evaluation's stages switch this source off: no run, u = 0.
  bool evaluated = false;
  double diameter_u_mm = 0.0;   ///< u_i of the LS diameter (mm)
  double roundness_u_mm = 0.0;  ///< u_i of RONt (mm)
  double diameter_share = 0.0;  ///< u_i² / Σ_j u_j² of the diameter (0 when the sum is 0)
  double roundness_share = 0.0;
};

/// The budget of one measurement.
struct UncertaintyBudget {
  std::uint64_t trials = 0;                ///< M of every source's run
  std::vector<SourceContribution> sources; ///< all five, in stage order
  double diameter_quadrature_mm = 0.0;     ///< √Σ u_i²
  double roundness_quadrature_mm = 0.0;
  double diameter_full_u_mm = 0.0;         ///< the full run's u over its first `trials` trials
  double roundness_full_u_mm = 0.0;
  double wall_seconds = 0.0;               ///< of the source runs together
};

/// The budget (file comment) of the full run `full` of the ring experiment on the best
/// estimate `best` (the run of `stages` with `monte_carlo`'s seed). `monte_carlo` supplies
/// seed, threads, coverage, cancel and progress (called with trials done and planned over
/// the budget's runs together); its `trials` is ignored for `budget.trials`. Returns nullopt
/// when cancelled. Throws InvalidInput if `full` has no summaries (too few trials) or its
/// samples are not the ring experiment's (2 measurands); otherwise as the Monte Carlo.
/// Numbers: a function of the seed only (any thread count). Cost: one run of M trials per
/// enabled source, each about as costly as the full run's.
std::optional<UncertaintyBudget> ring_uncertainty_budget(
    const errormodel::DigitalModel& model, const errormodel::Measurement& best,
    const RingEvaluationOptions& evaluation, const errormodel::Stages& stages,
    const uncertainty::MonteCarloResult& full, const BudgetOptions& budget,
    const uncertainty::MonteCarloOptions& monte_carlo);

/// The trials of each source's run: budget.trials (0: full_trials), at most full_trials.
std::uint64_t budget_trials(const BudgetOptions& budget, std::uint64_t full_trials);

}  // namespace vcmm::validation
