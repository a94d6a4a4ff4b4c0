// vcmm/validation/ring_uncertainty_report.h — the result of one ring uncertainty evaluation
// for people (text table) and machines (JSON, samples CSV); docs/formats.md, "Uncertainty
// result". Diameter in mm, roundness in µm in every output.
#pragma once

#include <string>

#include "vcmm/validation/ring_experiment.h"

namespace vcmm::validation {

/// A fixed-width table: per measurand the estimate from the data, the Monte Carlo mean, u,
/// the coverage interval, the bias with its Monte Carlo standard error, the corrected value and
/// whether the correction was applied (with the reason when refused); then the run's trials,
/// seed, threads, status and wall time.
std::string ring_uncertainty_text(const RingUncertaintyResult& result,
                                  const RingUncertaintyOptions& options);

/// The same as a JSON document (`"schema": "vcmm.uncertainty_result"`, version 1), including
/// the shortest interval and the correlation between the measurands.
std::string ring_uncertainty_json(const RingUncertaintyResult& result,
                                  const RingUncertaintyOptions& options);

/// The samples, one trial a line: `diameter_mm,roundness_um` (shortest round-trip decimals).
std::string ring_samples_csv(const uncertainty::MonteCarloResult& monte_carlo);

}  // namespace vcmm::validation
