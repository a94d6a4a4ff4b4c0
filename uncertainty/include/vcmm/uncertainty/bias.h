// vcmm/uncertainty/bias.h — estimate and correction of the bias a measurand's evaluation shows
// in the virtual experiment (docs/uncertainty.md, "Bias correction").
//
// Model: the virtual experiment re-measures the best estimate of the workpiece M times; its
// samples Y_mc scatter about ȳ while the estimate from the real data is x. The evaluation's
// bias is estimated as b = ȳ − x (e.g. roundness of noisy data is biased upwards). Assuming
// the law of (Y_mc − x) mirrors that of (x − Y_true) — the real measurement relates to the
// truth as the simulations relate to the estimate, the basic-bootstrap argument (Davison &
// Hinkley 1997, §5.2.1) — the corrected estimate is x − b = 2x − ȳ and the coverage interval is
// the reflection [2x − y_high, 2x − y_low] of the Monte Carlo probabilistically symmetric
// interval [y_low, y_high] (JCGM 101 7.7). The reported standard uncertainty adds the Monte
// Carlo standard error of b, u/√M, in quadrature: u_c = √(u² + u²/M).
//
// Guard: for a quantity that cannot be negative (roundness, a diameter) a correction that
// would give a negative value is refused — typically when the simulation adds noise on top of
// already noisy data and so over-estimates the bias (docs/uncertainty.md). The estimate is then
// reported uncorrected with the uncertainty enlarged by the bias, u_c = √(u² + b²), and the
// "wide interval" [max(0, y_low − |b|), y_high + |b|].
#pragma once

#include <string>
#include <string_view>

#include "vcmm/uncertainty/statistics.h"

namespace vcmm::uncertainty {

struct BiasCorrection {
  double estimate = 0;          ///< x, from the measured data
  double monte_carlo_mean = 0;  ///< ȳ
  double bias = 0;              ///< b = ȳ − x
  double bias_standard_error = 0;   ///< u/√M (Monte Carlo standard error of b)
  double corrected = 0;         ///< x − b when applied, else x
  double standard_uncertainty = 0;  ///< of the reported value: sqrt(u² + (u/√M)²) when
                                    ///< applied; when refused: sqrt(u² + b²)
  CoverageInterval interval;    ///< applied: reflection [2x − high, 2x − low] of the MC
                                ///< probabilistically symmetric interval (low end clamped at
                                ///< 0 for a non-negative quantity); refused: see below
  bool applied = false;
  bool refused = false;         ///< correction would make a non-negative quantity negative
  /// The standard uncertainty of the bias estimate itself as an estimate of the true bias
  /// (its own component of standard_uncertainty); 0 where the treatment does not assess it
  /// (correct_bias: the study's treatment takes b as exact up to its Monte Carlo error).
  double bias_uncertainty = 0;
  bool clamped = false;         ///< corrected value below 0 set to 0 (correct_bias_at_surrogate)
  /// How the bias was evaluated: at the data (correct_bias) or at a surrogate truth
  /// (correct_bias_at_surrogate, whose f(ŝ) is `surrogate_value`).
  bool at_surrogate = false;
  double surrogate_value = 0;
  double corrected_unclamped = 0;     ///< x − b before clamping at 0
  bool interval_low_clamped = false;  ///< the interval's lower end set to 0
  bool interval_high_truncated = false;  ///< its upper end from the truncated normal
  /// One sentence saying what was done and why, numbers in the quantity's own unit
  /// (describe(c) of the fields above).
  std::string note;
};

/// The note of a correction with its numbers multiplied by `scale` and followed by `unit`
/// (e.g. 1000, "µm" for a roundness computed in mm), so that a report's prose and its numbers
/// agree. 4 significant digits. describe(c) (scale 1, no unit) is c.note.
std::string describe(const BiasCorrection& c, double scale = 1.0, std::string_view unit = {});

/// bias = mean − estimate; corrected = estimate − bias. If `non_negative` and the corrected
/// value is < 0, the correction is refused: reported value = estimate (uncorrected),
/// interval = [max(0, low − |b|), high + |b|] around the uncorrected MC interval widened by |b|
/// (the "wide interval" of the seed study), u = sqrt(u² + b²).
/// When applied to a non-negative quantity, a reflected interval reaching below 0 is clamped
/// at 0 (the probability it covers is unchanged: the quantity has no mass below 0) and the
/// note says so. The interval's probability is the summary's.
/// Throws InvalidInput if estimate or a summary field is NaN/inf, summary.count is 0,
/// standard_uncertainty < 0, the interval has low > high, or `non_negative` and estimate < 0.
/// Exact arithmetic apart from rounding: O(1).
BiasCorrection correct_bias(double estimate, const MeasurandSummary& summary,
                            bool non_negative);

/// The bias evaluated at a surrogate of the truth (docs/uncertainty.md, "Bias at a surrogate
/// truth"). The virtual experiment is run on a surrogate ŝ of the true object (e.g. a profile
/// from which the estimated error power has been removed) instead of on the measured data,
/// whose errors it would otherwise add a second time. Inputs: y the estimate from the data;
/// f_s = f(ŝ) the measurand of the surrogate; `at_surrogate` the summary of the trials
/// y*_t = f(ŝ + e_t); `surrogate_spread` the summary of z*_t = f(S(ŝ + e_t)), the surrogate
/// estimator S applied to each trial, whose spread is the uncertainty of f(ŝ) as an estimate
/// of the true f and so of the bias evaluated there. Then
///   b = ȳ* − f_s,   corrected = y − b  (a non-negative quantity: max(0, y − b), `clamped`),
///   u_b = s(z*),    u_c² = s(y*)² + u_b² + s(y*)²/M   (M: at_surrogate.count),
/// bias_standard_error = s(y*)/√M, bias_uncertainty = u_b, and the interval
///   [c − √((y_high − ȳ*)² + (k_p u_b)²),  c + √((ȳ* − y_low)² + (k_p u_b)²)]
/// with [y_low, y_high] the probabilistically symmetric interval of the y*, k_p the normal
/// coverage factor of its probability (1.96 for 0.95): the Monte Carlo interval reflected
/// about the corrected value and widened by the bias uncertainty taken as normal; its lower
/// end clamped at 0 for a non-negative quantity, whose upper end is then at least the q of
/// N(y − b, u_c²) truncated to [0, ∞) with P(0 ≤ X ≤ q) = p·P(X ≥ 0) (so the interval never
/// ends below 0 when the uncorrected value lies far below the bias).
/// Throws InvalidInput for NaN/inf inputs, a count of 0, a negative standard uncertainty, an
/// interval with low > high, or `non_negative` with a negative estimate or f_s. O(1).
BiasCorrection correct_bias_at_surrogate(double estimate, double surrogate_value,
                                         const MeasurandSummary& at_surrogate,
                                         const MeasurandSummary& surrogate_spread,
                                         bool non_negative);

/// The standard normal quantile Φ⁻¹(p), p in (0, 1) (InvalidInput otherwise): Acklam's rational
/// approximation refined by one Halley step on erfc, relative error < 1e-15. O(1).
double standard_normal_quantile(double p);

}  // namespace vcmm::uncertainty
