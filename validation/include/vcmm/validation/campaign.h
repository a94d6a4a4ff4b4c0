// vcmm/validation/campaign.h — the campaign file: which measurements to evaluate, with which
// settings, against which reference values (docs/validation.md, "The campaign file";
// schema "vcmm.campaign", version 1).
//
// The reader parses and checks every entry of the file — keys, types, units, enumerations,
// ids, that every referenced file exists — and returns plain data. It does not read the
// points CSVs or the profiles and runs nothing: the campaign runner reads the points and
// checks their metadata against `setup`, and evaluate_roundness_reference /
// evaluate_diameter_reference below turn a reference entry into a value.
//
// Units. As in the file, lengths carry their unit in the field name where it is not mm
// (`value_um`, `u_um`): the struct holds exactly the file's numbers, so
// parse(campaign_json(c)) == c holds bit for bit (a µm → mm → µm conversion would not
// round-trip every double). Angles are degrees here (`orientation_deg`, a label of the
// summary as much as a value); convert with orientation_rad().
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "vcmm/errormodel/measurement.h"
#include "vcmm/geometry/point.h"
#include "vcmm/validation/form_bias.h"
#include "vcmm/validation/measurement_input.h"
#include "vcmm/validation/reference_values.h"
#include "vcmm/validation/trial_kind.h"

namespace vcmm::validation {

/// A campaign file that breaks its schema, or a referenced file that is missing or bad. The
/// message names the source file, the measurement (index, and id when known) and the JSON
/// path: `campaign.json: measurements[3] ("L1-O090-top-touch").reference.roundness: unknown
/// key "value_mm" (roundness is given in µm: "value_um")`. Derives from
/// geometry::InvalidInput, so the CLI maps it to exit code 3 with the other input errors.
class CampaignError : public geometry::InvalidInput {
 public:
  CampaignError(std::string source, std::optional<std::size_t> measurement_index,
                std::string measurement_id, std::string json_path, const std::string& message);
  /// The campaign file as named by the caller ("campaign_json" for the writer).
  const std::string& source() const noexcept { return source_; }
  /// Index into "measurements" of the offending entry; none for top-level entries.
  std::optional<std::size_t> measurement_index() const noexcept { return index_; }
  /// Its "id" when it was read (empty otherwise).
  const std::string& measurement_id() const noexcept { return id_; }
  /// Full JSON path ("measurements[3].reference.roundness.value_mm"; "" for the document).
  const std::string& json_path() const noexcept { return json_path_; }

 private:
  std::string source_;
  std::optional<std::size_t> index_;
  std::string id_;
  std::string json_path_;
};

inline constexpr std::string_view campaign_schema = "vcmm.campaign";
inline constexpr int campaign_schema_version = 1;
/// Fewest Monte Carlo trials accepted: below 100 the standard uncertainty is not known to one
/// significant digit (relative standard error of u ≈ 1/sqrt(2M) = 7 % at M = 100) and each
/// end of a 95 % interval rests on 2-3 samples (JCGM 101:2008, 7.2.2 asks for far more).
inline constexpr std::uint64_t min_campaign_trials = 100;
/// Most trials accepted: 10⁸ trials × 2 measurands × 8 bytes = 1.6 GB of samples for one
/// measurement; a larger number is far likelier a misplaced exponent than intent.
inline constexpr std::uint64_t max_campaign_trials = 100'000'000;
/// Longest id: ids become file names ("<id>.csv"); file systems allow 255 bytes.
inline constexpr std::size_t max_measurement_id_length = 200;

/// Where the gauge was measured along its axis.
enum class Height { top, middle, bottom };
/// "top", "middle", "bottom".
std::string_view to_string(Height height);
std::optional<Height> height_from_string(std::string_view text);

/// "evaluation": how every measurement of the campaign is evaluated (defaults as the file's).
struct EvaluationSettings {
  ReferenceCircle reference_circle = ReferenceCircle::minimum_zone;
  std::optional<double> filter_cutoff_upr = 50.0;  ///< none: unfiltered (JSON null)
  std::uint64_t trials = 10000;   ///< Monte Carlo trials per measurement, in [100, 1e8]
  std::uint64_t seed = 1;         ///< see measurement_seed()
  double coverage_probability = 0.95;  ///< in (0, 1)
  double k = 2.0;                 ///< coverage factor of E_n, > 0
  /// The roundness's bias treatment whose values are the campaign's "corrected" ones
  /// ("bias_treatment": "shrinkage" (default) or "paper"); the study's is always reported too.
  RoundnessBiasTreatment bias_treatment = RoundnessBiasTreatment::shrinkage;
  /// "kinematic_errors": "corrected" (default: the model's estimated kinematic errors are
  /// removed from the data) or "uncertainty_only" (not corrected, only in the uncertainty:
  /// errormodel::with_kinematics_uncorrected).
  bool kinematics_corrected = true;
  /// "budget": also the uncertainty budget of every measurement (ring_uncertainty_budget.h:
  /// each error source alone on the same random numbers; one more run per source). Off by
  /// default.
  bool budget = false;
  /// "budget_trials": trials of each budget run, in [min_campaign_trials, trials]; 0 (key
  /// absent): as many as the measurement's run. Only with budget.
  std::uint64_t budget_trials = 0;
  /// "trial": "auto" (default: the spectral trial where it applies), "exact" or "spectral"
  /// (trial_kind.h; the first Monte Carlo run of every measurement).
  TrialKind trial = TrialKind::automatic;
  friend bool operator==(const EvaluationSettings&, const EvaluationSettings&) = default;
};

/// "setup": the factors of one measurement (summary labels), checked by the runner against
/// the points CSV's metadata where both give them.
struct Setup {
  std::string location;  ///< location label ("L1", "C"), [A-Za-z0-9_.-]+
  std::optional<std::array<double, 3>> location_mm;  ///< placement location, machine (mm)
  double orientation_deg = 0.0;  ///< rotation of the gauge about machine Z (degrees)
  Height height = Height::middle;
  errormodel::ProbingMode mode = errormodel::ProbingMode::scanning;
  std::optional<double> temperature_c;  ///< the workpiece temperature reading (°C)
  /// Plain point files and roundness-meter profiles only (docs/validation.md, "Plain point
  /// files"): what vcmm's measurement CSV carries in its header. temperature_c and
  /// stylus_offset_mm are then required; location_mm for workpiece frames and profiles.
  std::optional<std::array<double, 3>> stylus_offset_mm;  ///< tip relative to the ram (mm)
  std::optional<PointFrame> frame;      ///< default machine
  std::optional<SurfaceSide> surface;   ///< default inner
  std::optional<double> radius_mm;      ///< profiles: nominal radius of the deviations
  std::optional<double> profile_height_mm;  ///< profiles: workpiece z of the profile (mm)

  /// True when a plain-file-only key is set.
  bool has_plain_file_keys() const {
    return stylus_offset_mm || frame || surface || radius_mm || profile_height_mm;
  }
  double orientation_rad() const { return orientation_deg / 180.0 * std::numbers::pi; }
  friend bool operator==(const Setup&, const Setup&) = default;
};

/// {"value_um": v, "u_um": u}: a roundness reference given as a number.
struct GivenRoundness {
  double value_um = 0.0;  ///< RONt, ≥ 0
  double u_um = 0.0;      ///< standard uncertainty, ≥ 0
  friend bool operator==(const GivenRoundness&, const GivenRoundness&) = default;
};
/// {"profile": path, "u_um": u}: evaluated from a roundness-meter profile with the
/// campaign's filter and reference circle (reference_roundness).
struct ProfileRoundness {
  std::string profile;                 ///< as written in the file
  std::filesystem::path profile_path;  ///< resolved against the campaign file's directory
  double u_um = 0.0;                   ///< the instrument's standard uncertainty of RONt, ≥ 0
  friend bool operator==(const ProfileRoundness&, const ProfileRoundness&) = default;
};
using RoundnessReference = std::variant<GivenRoundness, ProfileRoundness>;

/// {"value_mm": D, "u_um": u}: a diameter reference given as a number.
struct GivenDiameter {
  double value_mm = 0.0;  ///< > 0
  double u_um = 0.0;      ///< ≥ 0
  friend bool operator==(const GivenDiameter&, const GivenDiameter&) = default;
};
/// {"interferometer_distance_mm": L, "u_interferometer_um": u_L, "profile": path,
///  "u_profile_point_um": u_p (optional, default 0)}: the seed study's reference diameter
/// (reference_diameter). u_p is the standard uncertainty of one profile reading; it enters
/// with sqrt(Σ c_j²) ≈ √2 (docs/validation.md). Left out, the profile's contribution is 0.
struct InterferometerDiameter {
  double interferometer_distance_mm = 0.0;  ///< > 0
  double u_interferometer_um = 0.0;         ///< ≥ 0
  std::string profile;                      ///< as written in the file
  std::filesystem::path profile_path;       ///< resolved
  double u_profile_point_um = 0.0;          ///< ≥ 0
  friend bool operator==(const InterferometerDiameter&, const InterferometerDiameter&) = default;
};
using DiameterReference = std::variant<GivenDiameter, InterferometerDiameter>;

/// "reference": at least one of the two.
struct References {
  std::optional<RoundnessReference> roundness;
  std::optional<DiameterReference> diameter;
  friend bool operator==(const References&, const References&) = default;
};

/// One entry of "measurements".
struct CampaignMeasurement {
  std::string id;                     ///< unique, [A-Za-z0-9_.-]+, not "." or ".."
  std::string points;                 ///< measurement CSV, as written in the file
  std::filesystem::path points_path;  ///< resolved
  Setup setup;
  References reference;
  friend bool operator==(const CampaignMeasurement&, const CampaignMeasurement&) = default;
};

struct Campaign {
  /// The file it was read from, as named by the caller (for messages; "" when built in code).
  /// Not part of the content: operator== ignores it.
  std::string source;
  std::string description;
  std::string model;                 ///< digital-model file, as written
  std::filesystem::path model_path;  ///< resolved
  EvaluationSettings evaluation;
  std::vector<CampaignMeasurement> measurements;  ///< at least one

  /// Equal content: every field but `source`.
  friend bool operator==(const Campaign& a, const Campaign& b) {
    return a.description == b.description && a.model == b.model &&
           a.model_path == b.model_path && a.evaluation == b.evaluation &&
           a.measurements == b.measurements;
  }
};

/// Parses a campaign document. `campaign_path` names the file in messages, and its directory
/// resolves relative paths (lexically normalised; absolute paths are kept); it need not exist
/// when the text comes from elsewhere. Checks, in every build, throwing CampaignError at the
/// first broken rule: valid JSON (with the line) and no key repeated within an object; schema
/// "vcmm.campaign", version 1; only the keys of the format anywhere (a key with another unit
/// than the one expected — "value_mm" for "value_um", "u_mm" for "u_um" — says which key and
/// unit are expected); types; finite numbers; enumerations (reference_circle MZ|MI|LS|MC,
/// height top|middle|bottom, mode scanning|touch_trigger); filter_cutoff_upr > 0 or null;
/// trials an integer in [min_campaign_trials, max_campaign_trials]; seed an unsigned 64-bit
/// integer; coverage_probability in (0, 1); k > 0; budget a boolean; budget_trials only with
/// "budget": true, an integer in [min_campaign_trials, trials]; at least one measurement; ids
/// matching [A-Za-z0-9_.-]+, not "." or "..", at most max_measurement_id_length characters,
/// unique;
/// location labels matching [A-Za-z0-9_.-]+ (they go into CSV tables unquoted); location_mm
/// three numbers; temperature_c in [−50, 100] °C (errormodel/physical_ranges.h: a kelvin value is caught); a reference
/// with roundness and/or diameter, each in exactly one of its two forms (value_um ≥ 0,
/// value_mm > 0, interferometer_distance_mm > 0, every u ≥ 0); every referenced file (model,
/// points, profiles) an existing regular file — the message names the entry and the resolved
/// path. O(size of the document) plus one file-system query per referenced file.
Campaign parse_campaign(std::string_view json_text, const std::filesystem::path& campaign_path);
/// Reads and parses `path`; an unreadable file is a CampaignError naming it.
Campaign read_campaign_file(const std::filesystem::path& path);

/// Writes `campaign` as a version-1 campaign document (2-space indented JSON, keys in the
/// format's order, every evaluation setting explicit, numbers as the shortest decimal that
/// reads back to the same double), so that parse_campaign(campaign_json(c), p) == c when
/// the resolved paths of c are those p implies. Checks the campaign by parsing the text it
/// produced (every rule of parse_campaign except the existence of files, which a generator
/// may write afterwards) and throws CampaignError (source "campaign_json") for a campaign
/// that could not be read back — e.g. a NaN, an empty path or a bad id. O(size).
std::string campaign_json(const Campaign& campaign);

/// The seed of measurement `id` in a campaign with seed `campaign_seed` (part of format v1,
/// stable across platforms and runs): splitmix64(splitmix64(campaign_seed) ⊕ FNV-1a-64(id)).
/// Depends on the id, not on the position in the file, so reordering or removing entries
/// leaves every other measurement's random numbers unchanged. O(length of id).
std::uint64_t measurement_seed(std::uint64_t campaign_seed, std::string_view id);

/// A reference value in mm, ready for comparison.
struct EvaluatedReference {
  double value_mm = 0.0;
  double u_mm = 0.0;
  /// Where it came from, for reports: "given in the campaign file", or e.g. "roundness-meter
  /// profile /abs/ref.csv (3600 samples), MZ, 50 UPR, certificate verified".
  std::string method;
  /// False only for a profile-evaluated roundness whose reference-circle certificate failed
  /// its exact verification (method then says why); the value is still the fitter's.
  bool verified = true;
};

/// The roundness reference of measurement `index` in mm: a given value converted from µm, or
/// reference_roundness() of its profile with the campaign's reference circle and filter,
/// u = u_um, and base radius `nominal_radius_mm` (the gauge's nominal radius; second-order,
/// see reference_values.h). nullopt when the entry has no roundness reference. Throws
/// CampaignError naming the entry for a bad profile file or a failed evaluation (the
/// underlying message kept), geometry::InvalidInput for an index out of range or a bad
/// nominal radius. Cost: reading the profile + reference_roundness.
std::optional<EvaluatedReference> evaluate_roundness_reference(const Campaign& campaign,
                                                               std::size_t index,
                                                               double nominal_radius_mm);
/// The diameter reference of measurement `index` in mm: a given value, or reference_diameter()
/// of its interferometer distance and profile (u from u_interferometer_um and
/// u_profile_point_um). nullopt when the entry has none. Throws as above. O(profile size).
std::optional<EvaluatedReference> evaluate_diameter_reference(const Campaign& campaign,
                                                              std::size_t index);

}  // namespace vcmm::validation
