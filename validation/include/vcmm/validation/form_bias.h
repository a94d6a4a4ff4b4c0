// vcmm/validation/form_bias.h — the shrinkage bias treatment of a form measurand (roundness),
// vcmm's default (docs/validation.md, "Bias treatments"; docs/uncertainty.md, "Bias at a
// surrogate truth").
//
// Why. RONt is a peak-to-valley: errors inflate it. The seed study estimates the bias by
// re-simulating the measured profile x̂, which already carries one realisation of the errors,
// so its Monte Carlo sees the errors twice and evaluates the bias at the wrong profile (for a
// seminorm the bias shrinks as the profile grows): it under-corrects, least where the error is
// largest (docs/demo.md). The shrinkage treatment evaluates the bias at a surrogate p̂ of the
// true profile instead, and carries the uncertainty of that surrogate.
//
// Notation. Harmonics of the corrected profile's radial deviations about its LS circle,
// X_k = (a_k, b_k), power P_k = a_k² + b_k² (geometry/profile_harmonics.h); e the errors of one
// virtual-experiment trial; F the ISO 16610-21 filter (gain H(k) = 2^−(k/f_c)²), R the RONt
// about the chosen reference circle.
//   1. Error power per harmonic: V_k = E[|X_k(x̂ + e) − X_k(x̂)|²], estimated by a pilot Monte
//      Carlo of `pilot_trials` trials (unfiltered power: filtering scales P_k and V_k alike).
//   2. K = the highest order with H(k) ≥ min_filter_gain (⌊n/2⌋ unfiltered, and ≤ ⌊n/2⌋).
//      Thresholds: c_k = 1 where V_k > dominance_ratio × median(V_2 … V_K) (the few low orders
//      where systematic errors such as probe lobing dominate: plain power subtraction), and
//      c_k = ln K elsewhere (a harmonic of pure noise has P_k/V_k ~ Exp(1), so it survives the
//      threshold with probability 1/K: on average one noise harmonic of K is kept — the
//      "universal threshold" of wavelet shrinkage, Donoho & Johnstone 1994, in power form).
//   3. Shrinkage gains: s_k = 1 (k ≤ 1: size and position are not form), s_k = √max(0, 1 −
//      c_k V_k / P_k) (2 ≤ k ≤ K), harmonics above K dropped. The surrogate p̂ = S(x̂) is x̂
//      with every point moved along its ray to the shrunk deviation.
//   4. The virtual experiment on p̂, per trial t: y*_t = R(F(p̂ + e_t)) (the measurement as
//      the study simulates it, but about the surrogate) and z*_t = R(F(S(p̂ + e_t))) (the
//      surrogate estimator re-applied, with the same V and c). Then, with y = R(F(x̂)):
//        b = mean(y*) − R(F(p̂)),   corrected = max(0, y − b),
//        u_c² = s(y*)² + s(z*)² + s(y*)²/M   (uncertainty::correct_bias_at_surrogate),
//      where s(z*) — the spread of the surrogate's roundness — is the uncertainty of the bias
//      estimate itself, reported as its own component.
// The diameter (LS, unbiased by zero-mean errors) keeps the study's treatment.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/measurement.h"
#include "vcmm/errormodel/virtual_cmm.h"
#include "vcmm/geometry/profile_harmonics.h"
#include "vcmm/uncertainty/monte_carlo.h"
#include "vcmm/validation/ring_evaluation.h"

namespace vcmm::validation {

/// How the roundness's bias is treated (docs/validation.md, "Bias treatments").
enum class RoundnessBiasTreatment {
  shrinkage,  ///< default: bias at a shrunk surrogate of the true profile (form_bias.h)
  paper,      ///< the seed study: b = mean of the Monte Carlo on x̂ − y (correct_bias)
};

/// "shrinkage", "paper".
std::string_view to_string(RoundnessBiasTreatment treatment);
std::optional<RoundnessBiasTreatment> roundness_bias_treatment_from_string(std::string_view text);

/// The tunables of the shrinkage (file comment, with why each has its value).
struct ShrinkageOptions {
  /// Trials of the pilot run that estimates V_k: each V_k is then known to ~1/√M (5 % at
  /// 400), far below what changes a threshold decision.
  std::uint64_t pilot_trials = 400;
  /// V_k above this multiple of the median error power marks a systematic-dominated order.
  double dominance_ratio = 10.0;
  /// Harmonics with a filter gain below this are dropped from the surrogate (they contribute
  /// < 1 % of their amplitude to the filtered profile).
  double min_filter_gain = 0.01;
  /// Trials of the second run at the surrogate: min(this, the first run's trials); 0 = as
  /// many as the first run. The run estimates a mean (the bias; its Monte Carlo standard
  /// error s/√M is a component of u_c) and two standard deviations; at 4 000 trials these are
  /// known to 1.6 % of u and 1.1 % relative — far below the treatment's own model error —
  /// while each trial costs about twice a first-run trial (two reference-circle fits).
  std::uint64_t surrogate_trials = 4000;
};

/// The error power per harmonic and the thresholds built from it (file comment, steps 1–3).
struct HarmonicShrinkage {
  std::size_t max_order = 0;            ///< K
  std::vector<double> error_power_mm2;  ///< V_k, k = 0 … K (V_0, V_1 estimated, not used)
  std::vector<double> threshold;        ///< c_k, k = 0 … K (c_0 = c_1 = 0: never shrunk)
  std::uint64_t pilot_trials = 0;
  double median_error_power_mm2 = 0.0;  ///< median of V_2 … V_K
  std::size_t dominant_orders = 0;      ///< how many k ≥ 2 have c_k = 1

  /// Shrinkage gains s_0 … s_K of a profile analysed up to K (h.max_order() must be K:
  /// std::invalid_argument otherwise); `out` must hold K + 1 values. When `transmission` is
  /// not empty (K + 1 values) each gain is multiplied by it (the filter applied in the same
  /// synthesis). O(K).
  void gains(const geometry::ProfileHarmonics& h, std::span<const double> transmission,
             std::span<double> out) const;
};

/// K for an evaluation and a point count (file comment, step 2). O(1).
std::size_t shrinkage_max_order(const RingEvaluationOptions& evaluation, std::size_t points,
                                double min_filter_gain);

/// The filter's transmission H(0 … K) (all 1 unfiltered). O(K).
std::vector<double> filter_transmission(const RingEvaluationOptions& evaluation, std::size_t K);

/// Estimates V_k by a pilot Monte Carlo of options.pilot_trials trials of the ring experiment on
/// `best` (the corrected data) and derives the thresholds (steps 1–2). `run` gives the seed
/// (trial t uses RandomStream(seed, t): the same numbers for any thread count), the threads and
/// the cancel flag; its trials and progress are not used. Returns std::nullopt when cancelled.
/// Throws as the ring experiment and the Monte Carlo engine, and std::invalid_argument for a
/// dominance_ratio that is not a finite number > 0 or fewer than 2 pilot trials.
/// O(pilot_trials · n log n).
std::optional<HarmonicShrinkage> estimate_harmonic_shrinkage(
    const errormodel::DigitalModel& model, const errormodel::Measurement& best,
    const RingEvaluationOptions& evaluation, const errormodel::Stages& stages,
    const ShrinkageOptions& options, const uncertainty::MonteCarloOptions& run);

/// The surrogate truth p̂ = S(best) and its measurands f(p̂).
struct Surrogate {
  errormodel::Measurement surface;  ///< best with its XY profile shrunk; z, normals, metadata kept
  RingMeasurands measurands;        ///< f(p̂) under the evaluation
  std::size_t kept_harmonics = 0;   ///< orders k ≥ 2 with a non-zero gain
};

/// The surrogate truth p̂ = S(best) (step 3) and f(p̂). When no harmonic of order ≥ 2
/// survives, p̂ is a circle to < 1e-10 mm and its RONt is reported as 0 without calling the
/// reference-circle fitters (form_bias.cpp, has_form); the same rule gives z* = 0 in a trial.
/// Throws as geometry::ProfileHarmonics and evaluate_ring. O(n log n).
Surrogate shrunk_ring(const errormodel::Measurement& best, const HarmonicShrinkage& shrinkage,
                      const RingEvaluationOptions& evaluation);

/// Index of each measurand of the run at the surrogate.
enum SurrogateMeasurand : std::size_t {
  surrogate_diameter = 0,   ///< LS diameter of p̂ + e
  surrogate_roundness = 1,  ///< y* = R(F(p̂ + e))
  surrogate_shrunk = 2,     ///< z* = R(F(S(p̂ + e)))
};
inline constexpr std::size_t surrogate_measurand_count = 3;

/// A factory of the trials of step 4 (one per worker thread) for uncertainty::run_monte_carlo.
/// `model` and `shrinkage` must outlive the run.
uncertainty::ExperimentFactory surrogate_experiment_factory(
    const errormodel::DigitalModel& model, const errormodel::Measurement& surrogate,
    const RingEvaluationOptions& evaluation, const errormodel::Stages& stages,
    const HarmonicShrinkage& shrinkage);

}  // namespace vcmm::validation
