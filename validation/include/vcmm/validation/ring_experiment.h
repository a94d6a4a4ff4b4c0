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
// f: the points are projected on the workpiece XY plane (the ring axis is workpiece Z);
//   diameter = 2 · r_LS of the unfiltered profile (ISO 12181-2 LSCI, the seed study's diameter);
//   roundness = RONt of the ISO 16610-21 Gaussian-filtered profile about the chosen reference
//   circle (MZ by default; MI in the seed study).
// Random numbers: trial t draws everything from uncertainty::RandomStream(seed, t), so a seed
// fixes every number whatever the thread count.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/measurement.h"
#include "vcmm/errormodel/virtual_cmm.h"
#include "vcmm/geometry/point.h"
#include "vcmm/uncertainty/bias.h"
#include "vcmm/uncertainty/monte_carlo.h"
#include "vcmm/uncertainty/random_stream.h"
#include "vcmm/validation/reference_values.h"  // ReferenceCircle

namespace vcmm::validation {

/// How the measurands are evaluated from a profile.
struct RingEvaluationOptions {
  ReferenceCircle reference = ReferenceCircle::minimum_zone;
  /// ISO 16610-21 cut-off (UPR) applied before the roundness evaluation; none: unfiltered.
  /// The diameter is always the LS diameter of the unfiltered points.
  std::optional<double> filter_cutoff_upr = 50.0;
};

/// Index of each measurand in the Monte Carlo sample vector.
enum RingMeasurand : std::size_t { diameter = 0, roundness = 1 };
inline constexpr std::size_t ring_measurand_count = 2;

/// The measurands of one ring measurement (mm).
struct RingMeasurands {
  double diameter_mm = 0.0;   ///< 2 · r_LS, unfiltered profile
  double roundness_mm = 0.0;  ///< RONt of the (filtered) profile about the reference circle
};

/// A profile evaluated in detail (for reports): the measurands and the deviations about the
/// reference circle.
struct RingProfileEvaluation {
  RingMeasurands measurands;
  geometry::Point2 reference_center;   ///< centre of the reference circle (filtered profile)
  double reference_radius_mm = 0.0;    ///< MZ: (R + r)/2; MI, MC, LS: the circle's radius
  /// Per input point, in input order: the angle about reference_center (rad, [0, 2π)), the
  /// radial deviation of the unfiltered point and of the filtered point from the reference
  /// radius (mm).
  std::vector<double> angle_rad, deviation_mm, filtered_deviation_mm;
};

/// Projects the measurement's points on the workpiece XY plane.
std::vector<geometry::Point2> ring_profile(const errormodel::Measurement& m);

/// The measurands of a ring profile (file comment). Preconditions as the geometry functions:
/// ≥ 8 finite points forming a closed profile when filtered (geometry::InvalidInput);
/// geometry::UndefinedResult where a reference circle does not exist. O(n log n).
RingMeasurands evaluate_ring(std::span<const geometry::Point2> profile,
                             const RingEvaluationOptions& options);
RingMeasurands evaluate_ring(const errormodel::Measurement& m, const RingEvaluationOptions& options);

/// As evaluate_ring, with the deviations about the reference circle. O(n log n).
RingProfileEvaluation evaluate_ring_profile(std::span<const geometry::Point2> profile,
                                            const RingEvaluationOptions& options);

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
  /// Draws all error sources from `rng`, computes correct(simulate(x̂, e)) in one fused pass
  /// (errormodel::simulate_corrected, first-order kinematics), evaluates; writes
  /// measurands[diameter] (mm) and measurands[roundness] (mm).
  void operator()(uncertainty::RandomStream& rng, std::span<double> measurands);

 private:
  const errormodel::DigitalModel* model_;
  std::shared_ptr<const errormodel::PreparedMeasurement> prepared_;
  RingEvaluationOptions options_;
  errormodel::Stages stages_;
  errormodel::ErrorDraw draw_;
  std::vector<geometry::Point2> profile_;
};

/// A factory of RingTrial experiments for uncertainty::run_monte_carlo (one per worker).
uncertainty::ExperimentFactory ring_experiment_factory(const errormodel::DigitalModel& model,
                                                       const errormodel::Measurement& best,
                                                       const RingEvaluationOptions& options,
                                                       const errormodel::Stages& stages);

/// Options of one uncertainty evaluation.
struct RingUncertaintyOptions {
  RingEvaluationOptions evaluation;
  errormodel::Stages stages = errormodel::Stages::all();
  uncertainty::MonteCarloOptions monte_carlo;           ///< trials, seed, threads, progress, cancel
  std::optional<uncertainty::AdaptiveOptions> adaptive; ///< set: JCGM 101 7.9 instead of fixed M
};

/// The result for one measurement.
struct RingUncertaintyResult {
  errormodel::Measurement best_estimate;  ///< the corrected data x̂
  RingMeasurands estimate;                ///< y = f(x̂)
  uncertainty::MonteCarloResult monte_carlo;
  uncertainty::BiasCorrection diameter;   ///< never refused (a diameter cannot go negative here)
  uncertainty::BiasCorrection roundness;  ///< refused when the correction would go negative
};

/// Uncertainty of the diameter and roundness of one ring measurement (file comment).
/// `measured` is what the CMM reported (validated: InvalidInput); the model is applied with
/// the given stages. Throws as the pieces; the Monte Carlo result's status says whether it
/// completed, converged or was cancelled. O(M · n log n).
RingUncertaintyResult evaluate_ring_uncertainty(const errormodel::DigitalModel& model,
                                                const errormodel::Measurement& measured,
                                                const RingUncertaintyOptions& options);

/// The same Monte Carlo on a given surface `truth_estimate` (already corrected, e.g. the
/// denoised ring): the estimate is f(truth_estimate) and the bias is ȳ − f(truth_estimate).
RingUncertaintyResult evaluate_ring_uncertainty_on_surface(
    const errormodel::DigitalModel& model, const errormodel::Measurement& truth_estimate,
    const RingUncertaintyOptions& options);

}  // namespace vcmm::validation
