// vcmm/geometry/roundness_profile.h — the roundness-meter profile: radial deviations sampled
// at angles about the instrument's axis, its CSV file `angle_deg,deviation_um`
// (docs/formats.md, "Roundness-meter profile") and the rules every closed profile obeys.
//
// Notation. The profile is the radial deviation d(θ) of a surface from a base circle about the
// instrument's spindle axis, sampled at angles θ_j ∈ [0, 2π), j = 0 … n−1, strictly
// increasing (file: degrees and µm; here radians and mm). What d is measured against (a base
// circle of the meter, or the mean radius of the part) is the user's: the file format and its
// checks do not depend on it.
//
// Used by vcmm::validation (reference roundness and diameter) and vcmm::characterization
// (noise against a reference profile, which additionally requires equiangular samples).
#pragma once

#include <cstddef>
#include <istream>
#include <string>
#include <vector>

namespace vcmm::geometry {

/// A closed roundness-meter profile: radial deviations d_j (mm) at angles θ_j (rad), strictly
/// increasing in [0, 2π). `line` holds the 1-based source line of each sample (for messages;
/// empty for profiles built in code), `source` the file name ("" in code).
struct RoundnessProfile {
  std::vector<double> angle_rad;
  std::vector<double> deviation_mm;
  std::vector<std::size_t> line;
  std::string source;
};

/// The smallest profile accepted: the Gaussian filter (gaussian_filter.h) needs 8 points, and
/// fewer cannot describe a closed profile.
inline constexpr std::size_t min_roundness_profile_points = 8;

/// Checks a profile at a public boundary (every build): angle_rad and deviation_mm of equal
/// size ≥ min_roundness_profile_points (line empty or of that size too); every value finite;
/// angles strictly increasing within [0, 2π); closed: the largest angular gap between
/// neighbours, the wrap from the last to the first sample included, is below π (a profile with
/// a wider gap does not go round the axis — it is an arc, whose reference circles and mean
/// diameter are not those of the feature). Throws InvalidInput (point.h) naming `caller` (may
/// be null: no prefix), the sample (profile_sample_location), the rule and the offending
/// value, e.g. "caller: sample 4: angles must increase strictly; got 67.5 deg after 90 deg".
/// Exact comparisons, no tolerance. O(n).
void validate_roundness_profile(const RoundnessProfile& profile, const char* caller);

/// Where sample j of `profile` came from, for messages: "ref.csv:12" (source and line known),
/// "ref.csv: sample 12" (source only), "line 12" (line only) or "sample 12" (built in code).
/// j beyond the line table names the sample index. O(1).
std::string profile_sample_location(const RoundnessProfile& profile, std::size_t j);

/// Reads a roundness-meter profile, CSV `angle_deg,deviation_um` (docs/formats.md): one
/// sample a line, fields separated by ',' (or ';', tab or blanks, as points CSV), `#` starts a
/// comment, blank lines and a UTF-8 BOM skipped; an optional header, which must name the
/// units: `angle_deg,deviation_um` (case-insensitive, blanks around fields allowed) — any
/// other header is an error, so a file in mm or radians is never read as µm and degrees.
/// Exactly two fields a line; angles in [0, 360), strictly increasing; a closing sample at
/// exactly 360° is dropped when the profile starts at 0° with the same deviation (a meter's
/// repeated first point) and is an error otherwise. Then validate_roundness_profile.
/// Converts θ = angle_deg / 180 · π (exact for 0°, 90°, 180°, 270°), d = deviation_um · 1e-3
/// (correctly rounded products: relative error ≤ 2⁻⁵³ each). The result's `source` is
/// `source_name`, `line` the line of each sample. Throws InvalidInput naming source, line and
/// field, e.g. "ref.csv:3: field 2 (deviation_um) is not a number ('abc')" ("source: ..."
/// for whole-file rules such as too few samples or no samples). O(n).
RoundnessProfile read_roundness_profile_csv(std::istream& in, const std::string& source_name);

/// Opens `path` and reads it as read_roundness_profile_csv (source = path); an unreadable file
/// is InvalidInput "PATH: cannot open file for reading".
RoundnessProfile read_roundness_profile_csv_file(const std::string& path);

}  // namespace vcmm::geometry
