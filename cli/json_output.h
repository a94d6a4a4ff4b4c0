// cli/json_output.h — the JSON contract of `vcmm roundness --json` (docs/cli.md).
#pragma once

#include <nlohmann/json.hpp>
#include <span>

#include "vcmm/geometry/profile_harmonics.h"
#include "vcmm/geometry/roundness.h"

namespace vcmm::cli {

/// Schema name and version of one file's roundness result.
inline constexpr const char* kRoundnessSchema = "vcmm.roundness_result";
inline constexpr int kRoundnessSchemaVersion = 2;

/// {"n_points", "filter", "coverage": {...}, "LS": {...}, "MZ": {...}, "MI": {...},
/// "MC": {...}} with, per requested circle, either {"defined": true, "center": [x, y],
/// "radius" (LS, MI, MC) or "inner_radius"/"outer_radius" (MZ), "RONt", "RONp", "RONv",
/// "RONq", "contacts" (MZ: {"outer": [..], "inner": [..]}), "certified" (the independent
/// exact verify() passed; false for LS, which has no certificate), "optimality" ("global",
/// "local" or "numerical" for LS), "certificate" (the proof's text) and "caution" where one
/// applies} or {"defined": false, "reason": "..."}. Lengths in mm.
nlohmann::ordered_json to_json(std::span<const geometry::Point2> points,
                       const geometry::RoundnessEvaluation& evaluation);

/// {"about": "LS circle of the evaluated profile", "path": "fft"|"quadrature", "orders":
/// [{"order": k, "amplitude": A_k, "phase_deg": φ_k}, ...]} for k = 1 … N, with the profile's
/// radial deviation Σ A_k cos(kθ − φ_k) (θ counter-clockwise from +x about the LS centre;
/// A_k in mm, the peak of harmonic k: its peak-to-valley is 2A_k).
nlohmann::ordered_json harmonics_json(const geometry::ProfileHarmonics& harmonics);

}  // namespace vcmm::cli
