// errormodel/src/internal/kinematics_json.h — the "kinematics" section of the digital-model
// parameter file (schema and an example in docs/kinematics.md). Internal: only errormodel
// sources (the model-file loader) and tests include it.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "vcmm/errormodel/kinematic_errors.h"

namespace vcmm::errormodel {

/// Builds the KinematicModel from the JSON object `section` found at `key_path` in the file
/// (e.g. "kinematics"; used only in messages). Input units: ranges in mm, translation
/// coefficients and uncertainties in µm (`legendre_um`, `uncertainty_um`), rotation and
/// squareness ones in µrad (`legendre_urad`, `uncertainty_urad`, `value_urad`); converted to
/// mm and rad.
///
/// Throws std::invalid_argument whose message names the full key path, the offending value
/// and the rule broken, e.g.
///   "kinematics.errors.E_AX.uncertainty_urad[1]: must be >= 0; got -0.2"
/// Rules: required key missing; value not a number / not finite / wrong type; negative
/// uncertainty; array of the wrong length; range with min >= max; correlation not symmetric,
/// not unit-diagonal, |r| > 1 or not positive definite; unknown axis, error or squareness name;
/// unknown key (only "comment", "description" and "source" strings are free); a chain that does
/// not list every axis exactly once; an unknown chain preset.
KinematicModel kinematic_model_from_json(const nlohmann::json& section,
                                         const std::string& key_path);

}  // namespace vcmm::errormodel
