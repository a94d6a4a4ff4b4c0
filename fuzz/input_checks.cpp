// fuzz/input_checks.cpp — the checks of input_checks.h. Each check parses through the
// reader's istream/string entry point (no file system), then re-checks the result with the
// library's own validators and, where a writer exists, by a write → read round trip.
#include "input_checks.h"

#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <unordered_set>

#include "vcmm/characterization/hole_plate.h"
#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/measurement.h"
#include "vcmm/geometry/point.h"
#include "vcmm/geometry/point_io.h"
#include "vcmm/geometry/roundness_profile.h"
#include "vcmm/validation/campaign.h"

namespace vcmm::fuzz {
namespace {

/// The source name every check passes to its reader (messages only).
constexpr const char* kSource = "fuzz-input";

[[noreturn]] void violated(const char* reader, const std::string& rule) {
  throw PropertyViolation(std::string(reader) + ": " + rule);
}

/// Parses with `parse`; the documented input error is Outcome::rejected. Then `check` the
/// result: an InvalidInput from there (a validator or writer refusing what the reader
/// accepted) is a PropertyViolation, as is any violation `check` reports itself.
template <class Parse, class Check>
Outcome parse_then_check(const char* reader, Parse parse, Check check) {
  std::optional<decltype(parse())> result;
  try {
    result.emplace(parse());
  } catch (const geometry::InvalidInput&) {
    return Outcome::rejected;
  }
  try {
    check(*result);
  } catch (const geometry::InvalidInput& e) {
    violated(reader, std::string("a parsed result is refused by the library: ") + e.what());
  }
  return Outcome::parsed;
}

/// The same double, or its neighbour (a value stored in other units round-trips to 1 ulp).
bool within_one_ulp(double a, double b) {
  return a == b || std::nextafter(a, b) == b;
}

void check_ids(const char* reader, const std::vector<std::string>& ids) {
  std::unordered_set<std::string> seen;
  for (const std::string& id : ids) {
    if (id.empty()) violated(reader, "an empty id");
    if (!seen.insert(id).second) violated(reader, "id '" + id + "' repeated");
  }
}

}  // namespace

Outcome check_points_csv(std::string_view bytes) {
  constexpr const char* reader = "read_points_csv";
  return parse_then_check(
      reader,
      [&] {
        std::istringstream in{std::string(bytes)};
        return geometry::read_points_csv(in, kSource);
      },
      [&](const geometry::PointTable& t) {
        if (t.points.empty()) violated(reader, "no points but no error");
        if (!t.z.empty() && t.z.size() != t.points.size())
          violated(reader, "z and points differ in count");
        if (t.line.size() != t.points.size()) violated(reader, "line and points differ in count");
        for (std::size_t i = 0; i < t.points.size(); ++i) {
          if (!std::isfinite(t.points[i].x) || !std::isfinite(t.points[i].y) ||
              (!t.z.empty() && !std::isfinite(t.z[i])))
            violated(reader, "a non-finite coordinate at point " + std::to_string(i));
          if (t.line[i] == 0 || (i > 0 && t.line[i] <= t.line[i - 1]))
            violated(reader, "line numbers not 1-based and increasing at point " +
                                 std::to_string(i));
        }
      });
}

Outcome check_measurement_csv(std::string_view bytes) {
  constexpr const char* reader = "read_measurement_csv";
  return parse_then_check(
      reader,
      [&] {
        std::istringstream in{std::string(bytes)};
        return errormodel::read_measurement_csv(in, kSource);
      },
      [&](const errormodel::Measurement& m) {
        errormodel::validate_measurement(m, reader);
        // docs/errormodel.md: the file round-trips bit-exactly, the orientation to 1 ulp.
        std::istringstream again{errormodel::measurement_csv(m)};
        const errormodel::Measurement r = errormodel::read_measurement_csv(again, kSource);
        if (r.points_mm != m.points_mm || r.normals != m.normals)
          violated(reader, "points or normals differ after a write/read round trip");
        if (r.placement.location_mm != m.placement.location_mm ||
            !within_one_ulp(r.placement.orientation_rad, m.placement.orientation_rad))
          violated(reader, "the placement differs after a write/read round trip");
        if (r.mode != m.mode || r.temperature_c != m.temperature_c ||
            r.stylus_offset_mm != m.stylus_offset_mm)
          violated(reader, "mode, temperature or stylus offset differ after a round trip");
      });
}

Outcome check_roundness_profile_csv(std::string_view bytes) {
  constexpr const char* reader = "read_roundness_profile_csv";
  return parse_then_check(
      reader,
      [&] {
        std::istringstream in{std::string(bytes)};
        return geometry::read_roundness_profile_csv(in, kSource);
      },
      [&](const geometry::RoundnessProfile& p) {
        if (p.line.size() != p.angle_rad.size()) violated(reader, "line and samples differ");
        geometry::validate_roundness_profile(p, reader);
      });
}

Outcome check_digital_model_json(std::string_view bytes) {
  constexpr const char* reader = "parse_digital_model";
  return parse_then_check(
      reader, [&] { return errormodel::parse_digital_model(bytes, kSource); },
      [](const errormodel::DigitalModel& model) { errormodel::validate_digital_model(model); });
}

Outcome check_campaign_json(std::string_view bytes) {
  constexpr const char* reader = "parse_campaign";
  const std::filesystem::path& path = campaign_sandbox();
  return parse_then_check(
      reader, [&] { return validation::parse_campaign(bytes, path); },
      [&](const validation::Campaign& c) {
        if (c.measurements.empty()) violated(reader, "no measurements but no error");
        // campaign.h: parse_campaign(campaign_json(c), p) == c.
        if (!(validation::parse_campaign(validation::campaign_json(c), path) == c))
          violated(reader, "the campaign differs after a write/read round trip");
      });
}

Outcome check_hole_plate_csv(std::string_view bytes) {
  constexpr const char* reader = "read_hole_plate_csv";
  return parse_then_check(
      reader,
      [&] {
        std::istringstream in{std::string(bytes)};
        return characterization::read_hole_plate_csv(in, kSource);
      },
      [&](const characterization::HolePlate& p) {
        const auto n = static_cast<std::size_t>(p.calibrated_mm.cols());
        if (n < 3 || p.ids.size() != n || p.calibration_u_mm.size() != n)
          violated(reader, "fewer than 3 features or sizes that differ");
        check_ids(reader, p.ids);
        if (!p.calibrated_mm.allFinite()) violated(reader, "a non-finite coordinate");
        for (double u : p.calibration_u_mm)
          if (!std::isfinite(u) || u < 0) violated(reader, "an uncertainty not finite and >= 0");
        std::istringstream again{characterization::hole_plate_csv(p)};
        const characterization::HolePlate r = characterization::read_hole_plate_csv(again, kSource);
        if (r.ids != p.ids || r.calibrated_mm != p.calibrated_mm ||
            r.calibration_u_mm != p.calibration_u_mm)
          violated(reader, "the plate differs after a write/read round trip");
      });
}

Outcome check_hole_plate_placement_csv(std::string_view bytes) {
  constexpr const char* reader = "read_hole_plate_placement_csv";
  return parse_then_check(
      reader,
      [&] {
        std::istringstream in{std::string(bytes)};
        return characterization::read_hole_plate_placement_csv(in, kSource);
      },
      [&](const characterization::HolePlatePlacement& p) {
        if (p.measured_mm.cols() < 1 || p.ids.size() != static_cast<std::size_t>(p.measured_mm.cols()))
          violated(reader, "no features or sizes that differ");
        check_ids(reader, p.ids);
        if (!p.measured_mm.allFinite() || !p.stylus_offset_mm.allFinite())
          violated(reader, "a non-finite coordinate");
        std::istringstream again{characterization::hole_plate_placement_csv(p)};
        const characterization::HolePlatePlacement r =
            characterization::read_hole_plate_placement_csv(again, kSource);
        if (r.name != p.name || r.setup != p.setup || r.ids != p.ids ||
            r.measured_mm != p.measured_mm || r.stylus_offset_mm != p.stylus_offset_mm)
          violated(reader, "the placement differs after a write/read round trip");
      });
}

std::span<const Target> targets() {
  static const Target all[] = {
      {"points_csv", check_points_csv},
      {"measurement_csv", check_measurement_csv},
      {"roundness_profile_csv", check_roundness_profile_csv},
      {"digital_model_json", check_digital_model_json},
      {"campaign_json", check_campaign_json},
      {"hole_plate_csv", check_hole_plate_csv},
      {"hole_plate_placement_csv", check_hole_plate_placement_csv},
  };
  return all;
}

const std::filesystem::path& campaign_sandbox() {
  static const std::filesystem::path campaign = [] {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / "vcmm_fuzz_campaign_sandbox";
    // The files named by fuzz/corpus/campaign_json/docs_example.json (the example of
    // docs/validation.md). Written only when absent, so concurrent runs can share them.
    for (const char* name : {"cmm_model.json", "measurements/L1-O000-mid-scan.csv",
                             "measurements/C-O090-top-touch.csv", "reference/C-top.csv"}) {
      const fs::path file = dir / name;
      fs::create_directories(file.parent_path());
      if (!fs::exists(file)) std::ofstream(file).put('\n');
      if (!fs::is_regular_file(file))
        throw std::runtime_error("campaign_sandbox: cannot create " + file.string());
    }
    return dir / "campaign.json";
  }();
  return campaign;
}

}  // namespace vcmm::fuzz
