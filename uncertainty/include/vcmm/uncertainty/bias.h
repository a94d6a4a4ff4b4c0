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
  std::string note;             ///< one sentence saying what was done and why
};

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

}  // namespace vcmm::uncertainty
