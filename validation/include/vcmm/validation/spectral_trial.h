// vcmm/validation/spectral_trial.h — the spectral Monte Carlo trial of a ring measurement: the
// trial of ring_experiment.h drawn as the in-band harmonics of the radial deviation instead of
// point by point (docs/validation.md, "The spectral trial": derivation, bound, validity).
//
// Notation. Best estimate x̂: points p_j (j < n, an equiangular closed profile in index order),
// LS circle (c₀, R₀), directions u_j = (p_j − c₀)/|p_j − c₀|, the filter's transmission
// H(k) = 2^−(k/f_c)². One exact trial (RingTrial) moves every point by
//   p'_j = κ p_j + δ_j/ŝ,   κ = s/ŝ (drawn over estimated expansion factor),
//   δ_j = Σ_i θ_i ∂p_j/∂θ_i (kinematic and probe parameters θ, linear in the first-order model)
//         + r_j n_j + z_j    (roughness along the normal, noise; white),
// then fits the LS circle (diameter), filters the radial deviations about it by index (FFT
// path) and evaluates RONt about the reference circle. To first order in |δ|/R the radial
// deviation about c₀ is ρ'_j = κ ρ̂_j + u_j·δ_j/ŝ, so with the series of equiangular_transform.h
//   diameter  = 2 (κ R₀ + a₀(u·δ)/ŝ) + the white tangential mean E|δ_t|²/R₀,
//   filtered  = κ f̂_j + Σ_{k=2}^{K} H(k) (a_k cos 2πkj/n + b_k sin 2πkj/n)/ŝ,
// f̂ the estimate's filtered deviations (exactly as the exact path filters it), a_k, b_k of
// u·δ: Σ_i θ_i (precomputed harmonics of the response u_j·∂p_j/∂θ_i) plus, for the white
// parts, independent N(0, 2v/n) coefficients (v/n at k = 0 and at the Nyquist order), v the
// radial variance of one point (σ_r² (n·u)² + σ_noise²) — the exact law of the DFT of
// independent Gaussian samples, for any n. Harmonic 1 is the LS (and filter) centre's and is
// dropped; harmonics above K are below the truncation tolerance. RONt: LS = max − min of the
// filtered deviations about the estimate's filtered LS circle; MZ, MI: the exact minimum zone
// or maximum-inscribed circle of a subset of extreme points, checked against all n filtered
// points (geometry::minimum_zone_ront_from_extremes, maximum_inscribed_ront_from_extremes);
// MC: the exact geometry fitter on the n filtered points at the estimate's directions.
// Neglected (SpectralBound, per trial at 5 standard deviations of every drawn quantity):
// second-order terms |δ|²/R₀, the kinematic errors evaluated at the estimate's machine
// positions instead of the expanded and roughened ones, the harmonics above K, and the
// harmonic 1 of the synthesised part about the true directions (real scans sit off the grid
// by ε rad). For the 171 mm ring all of these are below 1 nm (docs/validation.md).
// Random numbers: trial t draws from uncertainty::RandomStream(seed, t): the systematic
// parameters by errormodel::draw_errors with the roughness and noise stages off (the same
// distributions as the exact trial), then 1 + 2(K_w − 1) standard normals for the white
// harmonics — a fixed function of (seed, t) for any thread count (not the exact trial's
// numbers).
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/measurement.h"
#include "vcmm/errormodel/virtual_cmm.h"
#include "vcmm/geometry/equiangular_transform.h"
#include "vcmm/geometry/point.h"
#include "vcmm/geometry/polar_profile.h"
#include "vcmm/uncertainty/monte_carlo.h"
#include "vcmm/uncertainty/random_stream.h"
#include "vcmm/validation/ring_evaluation.h"
#include "vcmm/validation/trial_kind.h"

namespace vcmm::validation {

/// Whether the spectral trial applies to a best estimate, and if not why (a sentence naming
/// the measurement property or option, for the result file and error messages).
struct SpectralApplicability {
  bool applicable = false;
  std::string reason;
};

/// The spectral trial applies when: the roundness is filtered (a cut-off is set); the
/// estimate's points lie, in input order, on an equiangular grid of n directions about their
/// LS centre (within a quarter step, stricter than the filter's FFT path, and without a repeated
/// closing point); the filter takes its FFT path on them; and the radial variance of the white
/// sources is the same at every point (normals within 1e-3 of radial when roughness is drawn).
/// Never throws for a valid measurement; InvalidInput for an invalid one.
SpectralApplicability spectral_trial_applicability(const errormodel::DigitalModel& model,
                                                   const errormodel::Measurement& best,
                                                   const RingEvaluationOptions& options,
                                                   const errormodel::Stages& stages);

/// The trial an uncertainty evaluation runs for its first Monte Carlo run, and why.
struct TrialChoice {
  TrialKind kind = TrialKind::exact;  ///< exact or spectral (never automatic)
  std::string reason;                 ///< a sentence for the result file
};

/// Resolves `requested` for a best estimate: exact stays exact; spectral is checked
/// (spectral_trial_applicability) and refused with InvalidInput naming the reason where it does
/// not apply, and refused with an uncertainty budget (`budget`: its one-at-a-time runs share the
/// exact trial's random numbers, ring_uncertainty_budget.h); automatic takes spectral where it
/// applies and there is no budget, else exact, and says why.
TrialChoice choose_ring_trial(const errormodel::DigitalModel& model,
                              const errormodel::Measurement& best,
                              const RingEvaluationOptions& options,
                              const errormodel::Stages& stages, TrialKind requested, bool budget);

/// What the spectral trial neglects, per trial, at 5 standard deviations of every drawn
/// quantity (mm; file comment). Bounds on the difference from the exact trial's measurands.
struct SpectralBound {
  std::size_t systematic_order = 0;  ///< K_s: highest harmonic of the systematic responses
  std::size_t white_order = 0;       ///< K_w: highest harmonic of the white parts
  double truncation_mm = 0.0;        ///< harmonics above K_s and K_w, at any point
  double second_order_mm = 0.0;      ///< (|δ_sys| + 5σ_white)²/R₀, on RONt and diameter
  double kinematic_position_mm = 0.0;  ///< e evaluated at the estimate's machine positions
  double grid_offset_mm = 0.0;       ///< harmonic 1 of the synthesised part off the grid
  double diameter_mm = 0.0;          ///< total on the diameter
  double roundness_mm = 0.0;         ///< total on RONt
};

/// Everything a spectral trial needs, computed once per measurement (the responses of the
/// radial deviation to every drawn parameter, in band): immutable, shared by all workers.
class SpectralRingModel {
 public:
  /// Throws InvalidInput naming the reason when the spectral trial does not apply
  /// (spectral_trial_applicability) or the measurement is invalid. `model` must outlive the
  /// object. O(P · n log n) for P drawn systematic parameters (~10 ms at n = 3600, P = 80).
  SpectralRingModel(const errormodel::DigitalModel& model, const errormodel::Measurement& best,
                    const RingEvaluationOptions& options, const errormodel::Stages& stages);

  std::size_t point_count() const { return n_; }
  /// Systematic parameters with a response (drawn, non-zero uncertainty).
  std::size_t parameter_count() const { return parameters_.size(); }
  /// Standard normals a trial draws for the white harmonics (after the systematic ones).
  std::size_t white_normal_count() const { return white_ ? 1 + 2 * (white_order_ - 1) : 0; }
  const SpectralBound& bound() const { return bound_; }
  /// f(x̂) as the spectral trial sees it (no draw): equal to evaluate_ring(x̂) to rounding.
  const RingEvaluationOptions& options() const { return options_; }

 private:
  friend class SpectralRingTrial;
  /// One drawn systematic parameter: where its value sits in an ErrorDraw.
  struct Parameter {
    enum class Kind { tip_radius, probe_cos, probe_sin, kinematic } kind;
    Eigen::Index index = 0;  ///< probe order or kinematic parameter index
    double nominal = 0.0;    ///< the estimate (what correction removes)
  };
  double parameter_value(const Parameter& p, const errormodel::ErrorDraw& d) const;

  const errormodel::DigitalModel* model_;
  std::shared_ptr<const errormodel::PreparedMeasurement> prepared_;
  RingEvaluationOptions options_;
  errormodel::Stages systematic_stages_;
  bool temperature_ = false, white_ = false;
  std::size_t n_ = 0;
  double radius_ = 0.0;           ///< R₀
  double estimated_scale_ = 1.0;  ///< ŝ
  std::vector<double> cos_, sin_;        ///< estimate directions about c₀
  std::optional<geometry::PolarDirections> directions_;  ///< the same, checked (n ≥ 8)
  std::vector<double> filtered_;         ///< f̂_j about (c₀, R₀)
  std::vector<double> filtered_ls_;      ///< f̂ about the filtered estimate's LS circle
  std::vector<Parameter> parameters_;
  std::size_t systematic_order_ = 1, white_order_ = 1, order_ = 1;
  Eigen::MatrixXd response_;        ///< rows 2(k − 2) (a_k) and 2(k − 2) + 1 (b_k), H applied
  Eigen::VectorXd response_mean_;   ///< a₀ of each response (diameter)
  std::vector<double> white_sd_a_, white_sd_b_;  ///< index k (0 … K_w), H applied
  double white_mean_sd_ = 0.0;      ///< sd of a₀ of the white parts
  double white_tangential_mm_ = 0.0;  ///< E|δ_t|²/(2R₀) of the white parts
  SpectralBound bound_;
};

/// One worker's spectral trial (scratch buffers; not safe to share between threads).
class SpectralRingTrial {
 public:
  explicit SpectralRingTrial(std::shared_ptr<const SpectralRingModel> model);
  /// Draws (file comment) and writes measurands[diameter], measurands[roundness] (mm).
  void operator()(uncertainty::RandomStream& rng, std::span<double> measurands);
  /// The measurands for given values: the systematic parameters of `draw` (T, α, kinematic,
  /// probe; its roughness and noise arrays are ignored) and the white harmonics from
  /// `white_normals` (white_normal_count() standard normals, or empty: no white part).
  /// Deterministic; for tests against the exact trial with the same parameter values.
  RingMeasurands measurands(const errormodel::ErrorDraw& draw,
                            std::span<const double> white_normals);

 private:
  std::shared_ptr<const SpectralRingModel> model_;
  errormodel::ErrorDraw draw_;
  Eigen::VectorXd theta_, harmonics_;
  std::vector<double> white_, a_, b_, synthesized_;
  std::vector<geometry::Point2> points_;
  geometry::ExtremesScratch extremes_;
  geometry::EquiangularTransform transform_;
};

/// A factory of SpectralRingTrial experiments (one per worker) sharing one SpectralRingModel.
/// Throws as SpectralRingModel (before any trial runs).
uncertainty::ExperimentFactory spectral_ring_experiment_factory(
    const errormodel::DigitalModel& model, const errormodel::Measurement& best,
    const RingEvaluationOptions& options, const errormodel::Stages& stages);

}  // namespace vcmm::validation
