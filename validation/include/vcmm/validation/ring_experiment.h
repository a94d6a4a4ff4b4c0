// vcmm/validation/ring_experiment.h — the ring-gauge virtual experiment: the error model
// (errormodel/) and the roundness evaluation (geometry/) composed under the Monte Carlo engine
// (uncertainty/), for one measurement (docs/validation.md, "The ring-gauge experiment").
//
// The flow (ARCHITECTURE.md, "The flow of one uncertainty evaluation"):
//   x̂ = correct(measured)                    best estimate of the surface (known systematics
//                                              removed: probe, kinematic, temperature to 20 °C)
//   y  = f(x̂)                                 measurands from the data: LS diameter, RONt
//   trial t:  e_t ~ model (draw_errors),  x_t = correct(simulate(x̂, e_t)),  y_t = f(x_t)
//   samples y_1 … y_M  →  mean, u, coverage intervals;  bias b = ȳ − y;  corrected y − b
// f: ring_evaluation.h (LS diameter; RONt after the Gaussian filter about the reference circle).
// Bias: the diameter keeps the study's correction (above); the roundness is corrected by the
// treatment chosen in the options — by default the shrinkage treatment (form_bias.h), which runs
// a pilot and a second Monte Carlo at a surrogate of the true profile; the study's correction is
// always reported beside it (roundness_paper).
// Random numbers: trial t draws everything from uncertainty::RandomStream(seed, t), so a seed
// fixes every number whatever the thread count.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/measurement.h"
#include "vcmm/errormodel/virtual_cmm.h"
#include "vcmm/geometry/point.h"
#include "vcmm/uncertainty/bias.h"
#include "vcmm/uncertainty/monte_carlo.h"
#include "vcmm/uncertainty/random_stream.h"
#include "vcmm/validation/form_bias.h"
#include "vcmm/validation/reference_values.h"  // ReferenceCircle
#include "vcmm/validation/ring_evaluation.h"
#include "vcmm/validation/ring_uncertainty_budget.h"
#include "vcmm/validation/spectral_trial.h"  // TrialKind

namespace vcmm::validation {

/// The denoised virtual truth of a ring measurement (treatment (b) of the bias study): every
/// point moved along its ray from the LS centre of the XY profile to the ISO 16610-21 filtered
/// radius at `cutoff_upr`; z, normals and metadata kept. Preconditions as the filter.
errormodel::Measurement denoised_ring(const errormodel::Measurement& m, double cutoff_upr);

/// The Monte Carlo trial of one ring measurement, with its own scratch buffers (one instance
/// per worker thread; not safe to share between threads). Holds references to the model and
/// the best estimate: they must outlive it.
class RingTrial {
 public:
  /// `prepared`: the best estimate, validated and laid out once for the loop (shared by all
  /// workers; it must outlive the trial, as must `model`).
  RingTrial(const errormodel::DigitalModel& model,
            std::shared_ptr<const errormodel::PreparedMeasurement> prepared,
            const RingEvaluationOptions& options, const errormodel::Stages& stages);
  /// Draws the errors of the `drawn` stages but simulates and corrects only the `applied` ones
  /// (a subset): each applied source then gets the very numbers it gets in the run of all
  /// `drawn` stages with the same seed (common random numbers: ring_uncertainty_budget.h).
  RingTrial(const errormodel::DigitalModel& model,
            std::shared_ptr<const errormodel::PreparedMeasurement> prepared,
            const RingEvaluationOptions& options, const errormodel::Stages& drawn,
            const errormodel::Stages& applied);
  /// Draws all error sources from `rng` (the noise as x, y only, errormodel::NoiseComponents::xy:
  /// the 2-D evaluation reads no z), computes correct(simulate(x̂, e)) in one fused pass
  /// (errormodel::simulate_corrected, first-order kinematics), evaluates; writes
  /// measurands[diameter] (mm) and measurands[roundness] (mm).
  void operator()(uncertainty::RandomStream& rng, std::span<double> measurands);

 private:
  const errormodel::DigitalModel* model_;
  std::shared_ptr<const errormodel::PreparedMeasurement> prepared_;
  RingEvaluationOptions options_;
  errormodel::Stages drawn_;
  errormodel::Stages applied_;
  errormodel::ErrorDraw draw_;
  std::vector<geometry::Point2> profile_;
};

/// A factory of RingTrial experiments for uncertainty::run_monte_carlo (one per worker).
uncertainty::ExperimentFactory ring_experiment_factory(const errormodel::DigitalModel& model,
                                                       const errormodel::Measurement& best,
                                                       const RingEvaluationOptions& options,
                                                       const errormodel::Stages& stages);
/// The same, drawing the `drawn` stages and applying only `applied` (RingTrial above).
uncertainty::ExperimentFactory ring_experiment_factory(const errormodel::DigitalModel& model,
                                                       const errormodel::Measurement& best,
                                                       const RingEvaluationOptions& options,
                                                       const errormodel::Stages& drawn,
                                                       const errormodel::Stages& applied);

/// Options of one uncertainty evaluation.
struct RingUncertaintyOptions {
  RingEvaluationOptions evaluation;
  errormodel::Stages stages = errormodel::Stages::all();
  uncertainty::MonteCarloOptions monte_carlo;           ///< trials, seed, threads, progress, cancel
  std::optional<uncertainty::AdaptiveOptions> adaptive; ///< set: JCGM 101 7.9 instead of fixed M
  RoundnessBiasTreatment roundness_bias = RoundnessBiasTreatment::shrinkage;
  ShrinkageOptions shrinkage;  ///< the shrinkage treatment's tunables
  /// Set: also the uncertainty budget (ring_uncertainty_budget.h), one more run per source.
  std::optional<BudgetOptions> budget;
  /// The first run's trial (spectral_trial.h, choose_ring_trial): by default the spectral one
  /// where it applies. The shrinkage treatment's pilot and second run and the budget's runs
  /// are always exact.
  TrialKind trial = TrialKind::automatic;
  /// Written into the report's "provenance" object beside the vcmm version and revision
  /// (e.g. model_file, model_sha256, points_file, points_sha256: provenance.h).
  std::map<std::string, std::string> provenance;
};

/// The shrinkage treatment's run (form_bias.h): what it estimated and its Monte Carlo.
struct SurrogateRun {
  HarmonicShrinkage shrinkage;                ///< V_k, c_k, K (pilot run)
  Surrogate surrogate;                        ///< p̂ and f(p̂)
  uncertainty::MonteCarloResult monte_carlo;  ///< measurands: SurrogateMeasurand
};

/// The result for one measurement.
struct RingUncertaintyResult {
  errormodel::Measurement best_estimate;  ///< the corrected data x̂
  RingMeasurands estimate;                ///< y = f(x̂)
  uncertainty::MonteCarloResult monte_carlo;  ///< the study's virtual experiment, on x̂
  TrialChoice trial;  ///< which trial `monte_carlo` ran (exact or spectral) and why
  uncertainty::BiasCorrection diameter;   ///< the study's correction (never refused)
  /// The roundness as the chosen treatment reports it (options.roundness_bias).
  uncertainty::BiasCorrection roundness;
  /// The study's treatment of the roundness, always (refused when it would go negative).
  uncertainty::BiasCorrection roundness_paper;
  RoundnessBiasTreatment roundness_treatment = RoundnessBiasTreatment::shrinkage;
  std::optional<SurrogateRun> surrogate;  ///< set by the shrinkage treatment
  /// Set when options.budget asks for it (per source, of the first run `monte_carlo`).
  std::optional<UncertaintyBudget> budget;
};

/// Uncertainty of the diameter and roundness of one ring measurement (file comment).
/// `measured` is what the CMM reported (validated: InvalidInput); the model is applied with
/// the given stages. The shrinkage treatment adds a pilot run (options.shrinkage.pilot_trials)
/// and a second run of min(trials completed, options.shrinkage.surrogate_trials) trials, seeded by
/// uncertainty::derived_seed(seed, 1) and (seed, 2). options.budget adds one run per enabled
/// source with the first run's seed (ring_uncertainty_budget.h), after the others. Throws as
/// the pieces; the Monte Carlo result's status says whether it completed, converged or was
/// cancelled (a cancelled first run skips the second: surrogate empty, roundness = the
/// study's; a cancelled budget leaves `budget` empty). O(M · n log n).
RingUncertaintyResult evaluate_ring_uncertainty(const errormodel::DigitalModel& model,
                                                const errormodel::Measurement& measured,
                                                const RingUncertaintyOptions& options);

/// The same Monte Carlo on a given surface `truth_estimate` (already corrected, e.g. the
/// denoised ring): the estimate is f(truth_estimate) and the bias is ȳ − f(truth_estimate).
RingUncertaintyResult evaluate_ring_uncertainty_on_surface(
    const errormodel::DigitalModel& model, const errormodel::Measurement& truth_estimate,
    const RingUncertaintyOptions& options);

}  // namespace vcmm::validation
