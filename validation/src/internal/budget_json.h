// validation/src/internal/budget_json.h — the uncertainty budget's JSON object, the one shape
// every output uses: `vcmm uncertainty --budget --json` ("budget" of the uncertainty result)
// and each campaign measurement's file (measurements/<id>.json, results.json). Written and
// read in ring_uncertainty_report.cpp; docs/cli.md describes the keys.
#pragma once

#include <nlohmann/json.hpp>

#include "vcmm/validation/ring_uncertainty_budget.h"

namespace vcmm::validation::internal {

/// The "budget" object: method, trials, wall_seconds, per source (source, evaluated,
/// diameter_u_mm, roundness_u_um, share_of_variance {diameter, roundness}), quadrature_sum
/// (the sums, the full run's u and their ratios, null where the full u is 0) and a note.
nlohmann::json budget_json(const UncertaintyBudget& budget);

/// The budget back from budget_json's object (µm → mm); throws nlohmann::json exceptions for
/// a missing key or a wrong type and std::invalid_argument for an unknown source name.
UncertaintyBudget budget_from_json(const nlohmann::json& j);

/// Quadrature sum / full u; NaN when the full u is 0.
double budget_ratio(double quadrature, double full);

}  // namespace vcmm::validation::internal
