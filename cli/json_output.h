// cli/json_output.h — the JSON contract of `vcmm roundness --json` (docs/cli.md).
#pragma once

#include <nlohmann/json.hpp>
#include <span>

#include "vcmm/geometry/roundness.h"

namespace vcmm::cli {

/// {"n_points", "filter", "LS": {...}, "MZ": {...}, "MI": {...}, "MC": {...}} with, per
/// circle: "center": [x, y], "radius" (LS, MI, MC) or "inner_radius"/"outer_radius" (MZ),
/// "RONt", "RONp", "RONv", "RONq", "contacts" (MZ: {"outer": [..], "inner": [..]}),
/// "certified" (the independent exact verify() passed; false for LS, which has no
/// certificate), "optimality" ("global", "local" or "numerical" for LS) and "certificate"
/// (the proof's text). Lengths in the input's unit.
nlohmann::json to_json(std::span<const geometry::Point2> points,
                       const geometry::RoundnessEvaluation& evaluation);

}  // namespace vcmm::cli
