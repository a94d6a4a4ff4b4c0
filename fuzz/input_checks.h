// fuzz/input_checks.h — one check per file reader of vcmm: feed bytes to the reader's
// in-memory entry point, accept its documented input error, and check properties of what it
// parsed. Shared by the libFuzzer targets (fuzz/fuzz_<target>.cpp, docs/fuzzing.md) and the
// regression test that replays every input that ever failed (tests/fuzz_regressions/).
//
// The contract each check enforces, for any byte string:
//  - the reader returns, or throws vcmm::geometry::InvalidInput (every reader's documented
//    input error; errormodel::InvalidParameter and validation::CampaignError derive from it):
//    the check returns Outcome::parsed or Outcome::rejected;
//  - a parsed result satisfies the reader's documented post-conditions (every number finite,
//    sizes consistent, the module's own validate_* accepts it) and, where the module has a
//    writer, writing it and reading the text back gives the same result. A broken property
//    throws PropertyViolation naming the reader and the rule;
//  - anything else — another exception type, a crash, undefined behaviour, a hang — escapes
//    the check, and libFuzzer (or the test) reports it.
#pragma once

#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace vcmm::fuzz {

enum class Outcome {
  parsed,    ///< the reader returned and every property held
  rejected,  ///< the reader threw its documented input error (geometry::InvalidInput)
};

/// A parsed result that breaks a documented property of its reader: a bug, never bad input.
class PropertyViolation : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

/// geometry::read_points_csv (docs/formats.md "Profile points").
Outcome check_points_csv(std::string_view bytes);
/// errormodel::read_measurement_csv (docs/errormodel.md "Measurement CSV").
Outcome check_measurement_csv(std::string_view bytes);
/// geometry::read_roundness_profile_csv (docs/formats.md "Roundness-meter profile").
Outcome check_roundness_profile_csv(std::string_view bytes);
/// errormodel::parse_digital_model (docs/errormodel.md, docs/kinematics.md).
Outcome check_digital_model_json(std::string_view bytes);
/// validation::parse_campaign (docs/validation.md "The campaign file"), the campaign placed in
/// campaign_sandbox() so that the files of the seed campaign exist.
Outcome check_campaign_json(std::string_view bytes);
/// characterization::read_hole_plate_csv (docs/characterization.md, "File formats").
Outcome check_hole_plate_csv(std::string_view bytes);
/// characterization::read_hole_plate_placement_csv (docs/characterization.md, "File formats").
Outcome check_hole_plate_placement_csv(std::string_view bytes);

/// A fuzz target: its name (fuzz/fuzz_<name>.cpp, fuzz/corpus/<name>/,
/// tests/data/fuzz_regressions/<name>/) and its check.
struct Target {
  const char* name;
  Outcome (*check)(std::string_view bytes);
};
/// Every target, in the order of docs/fuzzing.md.
std::span<const Target> targets();

/// The campaign file the campaign check parses as (it is never written): "campaign.json" in a
/// directory under the system temporary directory that holds the files the seed campaign
/// (fuzz/corpus/campaign_json/) refers to — the model, two points files and a profile — so
/// that inputs get past the reader's file-existence rule to the checks behind it. Created on
/// first use (idempotent; the files are empty: parse_campaign does not read them).
const std::filesystem::path& campaign_sandbox();

}  // namespace vcmm::fuzz
