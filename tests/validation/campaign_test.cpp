// The campaign file (vcmm/validation/campaign.h): a valid campaign parses with its defaults
// and resolved paths; campaign_json round-trips exactly; every class of error — missing file,
// unknown key, wrong unit, wrong type, duplicate id or key, bad id characters, empty
// measurements, bad enumeration, non-finite number, trials out of range — is a CampaignError
// naming the file, the measurement and the JSON path; references evaluate to the hand-known
// values of their profiles.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "vcmm/geometry/point.h"
#include "vcmm/validation/campaign.h"

namespace {

namespace fs = std::filesystem;
using namespace vcmm::validation;
using nlohmann::json;

void write_text(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream f(path);
  f << text;
}

/// n samples every 360/n degrees of d = a cos(kθ) (µm), as a roundness-meter CSV.
std::string lobed_profile_csv(int n, int order, double amplitude_um) {
  std::string s = "angle_deg,deviation_um\n";
  for (int j = 0; j < n; ++j) {
    const double deg = 360.0 * j / n;
    json v = amplitude_um * std::cos(order * deg / 180.0 * std::numbers::pi);
    s += json(deg).dump() + "," + v.dump() + "\n";
  }
  return s;
}

struct Failure {
  std::string message;
  std::string json_path;
  std::optional<std::size_t> index;
  std::string id;
};

class CampaignTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("vcmm_campaign_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    write_text(dir_ / "cmm_model.json", "{}\n");
    write_text(dir_ / "measurements/L1-O000-mid-scan.csv", "# points\n");
    write_text(dir_ / "measurements/C-O090-top-touch.csv", "# points\n");
    write_text(dir_ / "reference/L1-mid.csv", lobed_profile_csv(360, 3, 0.4));
    write_text(dir_ / "reference/two-lobe.csv", lobed_profile_csv(360, 2, 0.25));
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// The agreed example of the format, with both reference forms.
  static json example() {
    return json::parse(R"({
      "schema": "vcmm.campaign",
      "schema_version": 1,
      "description": "two measurements",
      "model": "cmm_model.json",
      "evaluation": {"reference_circle": "MZ", "filter_cutoff_upr": 50, "trials": 10000,
                     "seed": 1, "coverage_probability": 0.95, "k": 2},
      "measurements": [
        {"id": "L1-O000-mid-scan",
         "points": "measurements/L1-O000-mid-scan.csv",
         "setup": {"location": "L1", "location_mm": [600, 500, 400], "orientation_deg": 0,
                   "height": "middle", "mode": "scanning", "temperature_c": 20.3},
         "reference": {"roundness": {"value_um": 0.205, "u_um": 0.010},
                       "diameter": {"value_mm": 171.00012, "u_um": 0.05}}},
        {"id": "C-O090-top-touch",
         "points": "measurements/C-O090-top-touch.csv",
         "setup": {"location": "C", "orientation_deg": 90, "height": "top",
                   "mode": "touch_trigger"},
         "reference": {"roundness": {"profile": "reference/L1-mid.csv", "u_um": 0.010},
                       "diameter": {"interferometer_distance_mm": 171.0001,
                                    "u_interferometer_um": 0.04,
                                    "profile": "reference/two-lobe.csv",
                                    "u_profile_point_um": 0.01}}}
      ]
    })");
  }

  Campaign parse(const json& doc) const { return parse_text(doc.dump(2)); }
  Campaign parse_text(const std::string& text) const {
    write_text(dir_ / "campaign.json", text);
    return read_campaign_file(dir_ / "campaign.json");
  }

  Failure failure_of_text(const std::string& text) const {
    try {
      parse_text(text);
    } catch (const CampaignError& e) {
      return {e.what(), e.json_path(), e.measurement_index(), e.measurement_id()};
    }
    return {"(no exception)", "", std::nullopt, ""};
  }
  Failure failure_of(const json& doc) const { return failure_of_text(doc.dump(2)); }

  /// The message without the leading "<dir>/campaign.json: ".
  std::string rule_of(const json& doc) const {
    const std::string m = failure_of(doc).message;
    const std::string prefix = (dir_ / "campaign.json").string() + ": ";
    return m.rfind(prefix, 0) == 0 ? m.substr(prefix.size()) : "(unexpected prefix) " + m;
  }

  fs::path dir_;
};

TEST_F(CampaignTest, ExampleParsesWithResolvedPathsAndFileUnits) {
  const Campaign c = parse(example());
  EXPECT_EQ(c.source, (dir_ / "campaign.json").string());
  EXPECT_EQ(c.description, "two measurements");
  EXPECT_EQ(c.model, "cmm_model.json");
  EXPECT_EQ(c.model_path, dir_ / "cmm_model.json");
  EXPECT_EQ(c.evaluation, EvaluationSettings{});  // the example states the defaults
  ASSERT_EQ(c.measurements.size(), 2u);
  const CampaignMeasurement& a = c.measurements[0];
  EXPECT_EQ(a.id, "L1-O000-mid-scan");
  EXPECT_EQ(a.points_path, dir_ / "measurements/L1-O000-mid-scan.csv");
  EXPECT_EQ(a.setup.location, "L1");
  EXPECT_EQ(a.setup.location_mm, (std::array<double, 3>{600, 500, 400}));
  EXPECT_EQ(a.setup.orientation_deg, 0.0);
  EXPECT_EQ(a.setup.height, Height::middle);
  EXPECT_EQ(a.setup.mode, vcmm::errormodel::ProbingMode::scanning);
  EXPECT_EQ(a.setup.temperature_c, 20.3);
  ASSERT_TRUE(a.reference.roundness && a.reference.diameter);
  EXPECT_EQ(std::get<GivenRoundness>(*a.reference.roundness), (GivenRoundness{0.205, 0.010}));
  EXPECT_EQ(std::get<GivenDiameter>(*a.reference.diameter), (GivenDiameter{171.00012, 0.05}));
  const CampaignMeasurement& b = c.measurements[1];
  EXPECT_FALSE(b.setup.location_mm.has_value());
  EXPECT_FALSE(b.setup.temperature_c.has_value());
  EXPECT_EQ(b.setup.orientation_deg, 90.0);
  EXPECT_DOUBLE_EQ(b.setup.orientation_rad(), std::numbers::pi / 2);
  EXPECT_EQ(b.setup.height, Height::top);
  EXPECT_EQ(b.setup.mode, vcmm::errormodel::ProbingMode::touch_trigger);
  const auto& pr = std::get<ProfileRoundness>(*b.reference.roundness);
  EXPECT_EQ(pr.profile, "reference/L1-mid.csv");
  EXPECT_EQ(pr.profile_path, dir_ / "reference/L1-mid.csv");
  const auto& id = std::get<InterferometerDiameter>(*b.reference.diameter);
  EXPECT_EQ(id.interferometer_distance_mm, 171.0001);
  EXPECT_EQ(id.u_interferometer_um, 0.04);
  EXPECT_EQ(id.u_profile_point_um, 0.01);
  EXPECT_EQ(id.profile_path, dir_ / "reference/two-lobe.csv");
}

TEST_F(CampaignTest, EvaluationDefaultsAndExplicitSettings) {
  json doc = example();
  doc.erase("evaluation");
  EXPECT_EQ(parse(doc).evaluation, EvaluationSettings{});
  doc["evaluation"] = json::parse(R"({"reference_circle": "MI", "filter_cutoff_upr": null,
      "trials": 100, "seed": 18446744073709551615, "coverage_probability": 0.99, "k": 2.576})");
  const EvaluationSettings e = parse(doc).evaluation;
  EXPECT_EQ(e.reference_circle, ReferenceCircle::maximum_inscribed);
  EXPECT_FALSE(e.filter_cutoff_upr.has_value());
  EXPECT_EQ(e.trials, 100u);
  EXPECT_EQ(e.seed, std::numeric_limits<std::uint64_t>::max());
  EXPECT_EQ(e.coverage_probability, 0.99);
  EXPECT_EQ(e.k, 2.576);
  // Only a roundness (or only a diameter) reference is fine; absolute paths are kept.
  doc["measurements"][0]["reference"].erase("diameter");
  doc["measurements"][1]["reference"].erase("roundness");
  doc["model"] = (dir_ / "cmm_model.json").string();
  const Campaign c = parse(doc);
  EXPECT_FALSE(c.measurements[0].reference.diameter.has_value());
  EXPECT_FALSE(c.measurements[1].reference.roundness.has_value());
  EXPECT_EQ(c.model_path, dir_ / "cmm_model.json");
  // u_profile_point_um is optional (0: the profile's contribution omitted).
  doc["measurements"][1]["reference"]["diameter"].erase("u_profile_point_um");
  EXPECT_EQ(std::get<InterferometerDiameter>(*parse(doc).measurements[1].reference.diameter)
                .u_profile_point_um,
            0.0);
}

TEST_F(CampaignTest, WriterRoundTripsExactly) {
  const Campaign c = parse(example());
  const std::string text = campaign_json(c);
  EXPECT_EQ(parse_text(text), c);
  EXPECT_EQ(text.find("null"), std::string::npos);
  EXPECT_NE(text.find("\"schema\": \"vcmm.campaign\""), std::string::npos);
  EXPECT_LT(text.find("\"schema\""), text.find("\"measurements\""));  // the format's order

  // A campaign built in code (as the demo does), with numbers that have no short decimal.
  Campaign built;
  built.description = "generated";
  built.model = "cmm_model.json";
  built.model_path = dir_ / "cmm_model.json";
  built.evaluation.filter_cutoff_upr.reset();
  built.evaluation.reference_circle = ReferenceCircle::least_squares;
  built.evaluation.seed = 0xDEADBEEFCAFEF00Dull;
  built.evaluation.trials = 2000;
  built.evaluation.bias_treatment = RoundnessBiasTreatment::paper;
  built.evaluation.trial = TrialKind::exact;
  built.evaluation.kinematics_corrected = false;
  CampaignMeasurement m;
  m.id = "C-O045-bottom-scan";
  m.points = "measurements/L1-O000-mid-scan.csv";
  m.points_path = dir_ / m.points;
  m.setup.location = "C";
  m.setup.location_mm = std::array<double, 3>{0.1 + 0.2, 1.0 / 3.0, -400.0};
  m.setup.orientation_deg = 45.0 + 1e-12;
  m.setup.height = Height::bottom;
  m.setup.temperature_c = 20.0 + 1.0 / 7.0;
  m.reference.roundness = GivenRoundness{0.1 + 0.2, 1.0 / 3.0};
  m.reference.diameter = InterferometerDiameter{171.0 + 1e-9, 0.04, "reference/two-lobe.csv",
                                                dir_ / "reference/two-lobe.csv", 0.0};
  built.measurements.push_back(m);
  m.id = "C-O045-bottom-touch";
  m.setup.mode = vcmm::errormodel::ProbingMode::touch_trigger;
  m.setup.location_mm.reset();
  m.setup.temperature_c.reset();
  m.reference.roundness = ProfileRoundness{"reference/L1-mid.csv", dir_ / "reference/L1-mid.csv",
                                           std::numeric_limits<double>::denorm_min()};
  m.reference.diameter = GivenDiameter{171.0 + 2e-9, 0.05};
  built.measurements.push_back(m);
  const Campaign back = parse_text(campaign_json(built));
  EXPECT_EQ(back, built);
  EXPECT_EQ(campaign_json(back), campaign_json(built));
}

TEST_F(CampaignTest, WriterRefusesWhatTheReaderWouldRefuse) {
  Campaign c = parse(example());
  c.measurements[0].setup.orientation_deg = std::numeric_limits<double>::quiet_NaN();
  try {
    campaign_json(c);
    ADD_FAILURE() << "no exception";
  } catch (const CampaignError& e) {
    EXPECT_EQ(std::string(e.what()),
              "campaign_json: measurements[0].setup.orientation_deg: must be finite; got nan");
    EXPECT_EQ(e.source(), "campaign_json");
    EXPECT_EQ(e.measurement_index(), 0u);
  }
  c = parse(example());
  c.measurements[1].id = "bad id";
  EXPECT_THROW(campaign_json(c), CampaignError);
  c = parse(example());
  c.evaluation.trials = 99;
  EXPECT_THROW(campaign_json(c), CampaignError);
  c = parse(example());
  c.measurements.clear();
  EXPECT_THROW(campaign_json(c), CampaignError);
}

TEST_F(CampaignTest, MissingFilesNameTheEntryAndTheResolvedPath) {
  json doc = example();
  doc["measurements"][1]["points"] = "measurements/../measurements/missing.csv";
  Failure f = failure_of(doc);
  EXPECT_EQ(f.message, (dir_ / "campaign.json").string() +
                           ": measurements[1] (\"C-O090-top-touch\").points: file not found: " +
                           (dir_ / "measurements/missing.csv").string());
  EXPECT_EQ(f.json_path, "measurements[1].points");
  EXPECT_EQ(f.index, 1u);
  EXPECT_EQ(f.id, "C-O090-top-touch");

  doc = example();
  doc["model"] = "no_model.json";
  EXPECT_EQ(rule_of(doc), "model: file not found: " + (dir_ / "no_model.json").string());
  doc = example();
  doc["measurements"][1]["reference"]["roundness"]["profile"] = "reference/none.csv";
  EXPECT_EQ(rule_of(doc),
            "measurements[1] (\"C-O090-top-touch\").reference.roundness.profile: file not "
            "found: " + (dir_ / "reference/none.csv").string());
  doc = example();
  doc["measurements"][1]["reference"]["diameter"]["profile"] = "reference";  // a directory
  EXPECT_EQ(rule_of(doc),
            "measurements[1] (\"C-O090-top-touch\").reference.diameter.profile: not a regular "
            "file: " + (dir_ / "reference").string());
  doc = example();
  doc["measurements"][0]["points"] = "";
  EXPECT_EQ(rule_of(doc),
            "measurements[0] (\"L1-O000-mid-scan\").points: must be a non-empty file path");
  // The campaign file itself.
  try {
    read_campaign_file(dir_ / "nothing.json");
    ADD_FAILURE() << "no exception";
  } catch (const CampaignError& e) {
    EXPECT_EQ(std::string(e.what()), (dir_ / "nothing.json").string() +
                                         ": cannot read the campaign file: no such file");
  }
}

TEST_F(CampaignTest, UnknownKeysAreErrorsAnywhere) {
  json doc = example();
  doc["trails"] = 10;
  EXPECT_EQ(rule_of(doc),
            "unknown key \"trails\" (allowed here: schema, schema_version, description, model, "
            "evaluation, measurements)");
  doc = example();
  {
    nlohmann::json bad = doc;
    bad["evaluation"]["bias_treatment"] = "denoise";
    EXPECT_EQ(rule_of(bad), "evaluation.bias_treatment: must be \"shrinkage\" or \"paper\"; got \"denoise\"");
    bad = doc;
    bad["evaluation"]["kinematic_errors"] = true;
    EXPECT_EQ(rule_of(bad),
              "evaluation.kinematic_errors: must be \"corrected\" or \"uncertainty_only\"; got true");
    bad = doc;
    bad["evaluation"]["trial"] = "fast";
    EXPECT_EQ(rule_of(bad),
              "evaluation.trial: must be \"auto\", \"exact\" or \"spectral\"; got \"fast\"");
  }
  doc["evaluation"]["trails"] = 10;
  EXPECT_EQ(rule_of(doc),
            "evaluation: unknown key \"trails\" (allowed here: reference_circle, "
            "filter_cutoff_upr, trials, seed, coverage_probability, k, bias_treatment, "
            "kinematic_errors, budget, budget_trials, trial)");
  doc = example();
  doc["measurements"][1]["setup"]["colour"] = "red";
  EXPECT_EQ(rule_of(doc),
            "measurements[1] (\"C-O090-top-touch\").setup: unknown key \"colour\" (allowed "
            "here: location, location_mm, orientation_deg, height, mode, temperature_c, "
            "stylus_offset_mm, frame, surface, radius_mm, profile_height_mm)");
  doc = example();
  doc["measurements"][0]["comment"] = "x";
  const Failure f = failure_of(doc);
  EXPECT_EQ(f.json_path, "measurements[0]");
  EXPECT_NE(f.message.find("unknown key \"comment\""), std::string::npos);
}

TEST_F(CampaignTest, WrongUnitsNameTheExpectedKey) {
  json doc = example();
  auto& ron = doc["measurements"][0]["reference"]["roundness"];
  ron.erase("value_um");
  ron["value_mm"] = 0.000205;
  // The format's own example message.
  EXPECT_EQ(rule_of(doc), "measurements[0] (\"L1-O000-mid-scan\").reference.roundness: unknown "
                          "key \"value_mm\" (roundness is given in µm: \"value_um\")");
  doc = example();
  auto& dia = doc["measurements"][0]["reference"]["diameter"];
  dia.erase("u_um");
  dia["u_mm"] = 0.00005;
  EXPECT_EQ(rule_of(doc), "measurements[0] (\"L1-O000-mid-scan\").reference.diameter: unknown "
                          "key \"u_mm\" (the standard uncertainty is given in µm: \"u_um\")");
  doc = example();
  doc["measurements"][0]["reference"]["diameter"].erase("value_mm");
  doc["measurements"][0]["reference"]["diameter"]["value_um"] = 171000.12;
  EXPECT_EQ(rule_of(doc), "measurements[0] (\"L1-O000-mid-scan\").reference.diameter: unknown "
                          "key \"value_um\" (the diameter is given in mm: \"value_mm\")");
  doc = example();
  doc["measurements"][1]["setup"].erase("orientation_deg");
  doc["measurements"][1]["setup"]["orientation_rad"] = 1.5708;
  EXPECT_EQ(rule_of(doc), "measurements[1] (\"C-O090-top-touch\").setup: unknown key "
                          "\"orientation_rad\" (the orientation is given in degrees: "
                          "\"orientation_deg\")");
  doc = example();
  doc["measurements"][0]["setup"].erase("temperature_c");
  doc["measurements"][0]["setup"]["temperature_K"] = 293.45;
  EXPECT_EQ(rule_of(doc), "measurements[0] (\"L1-O000-mid-scan\").setup: unknown key "
                          "\"temperature_K\" (the temperature is given in °C: \"temperature_c\")");
  doc = example();
  doc["measurements"][0]["setup"].erase("location_mm");
  doc["measurements"][0]["setup"]["location_m"] = {0.6, 0.5, 0.4};
  EXPECT_EQ(rule_of(doc), "measurements[0] (\"L1-O000-mid-scan\").setup: unknown key "
                          "\"location_m\" (the location is given in mm: \"location_mm\")");
  doc = example();
  doc["evaluation"].erase("filter_cutoff_upr");
  doc["evaluation"]["filter_cutoff"] = 50;  // no unit at all
  EXPECT_EQ(rule_of(doc), "evaluation: unknown key \"filter_cutoff\" (the filter cut-off is "
                          "given in UPR: \"filter_cutoff_upr\")");
  // A kelvin value under the right key is caught by its range.
  doc = example();
  doc["measurements"][0]["setup"]["temperature_c"] = 293.45;
  EXPECT_EQ(rule_of(doc), "measurements[0] (\"L1-O000-mid-scan\").setup.temperature_c: must lie "
                          "in [-50, 100] °C (a workpiece temperature in °C; kelvin given? 293.45 "
                          "K = 20.3 °C); got 293.45 °C");
  doc["measurements"][0]["setup"]["temperature_c"] = 1e300;
  EXPECT_EQ(rule_of(doc), "measurements[0] (\"L1-O000-mid-scan\").setup.temperature_c: must lie "
                          "in [-50, 100] °C (a workpiece temperature in °C; kelvin or °F given?); "
                          "got 1e+300 °C");
  doc["measurements"][0]["setup"]["temperature_c"] = 20;
  doc["measurements"][0]["setup"]["location_mm"] = {600, 1e300, 250};
  EXPECT_EQ(rule_of(doc), "measurements[0] (\"L1-O000-mid-scan\").setup.location_mm[1]: must lie "
                          "in [-1e+05, 1e+05] mm (a position in a CMM volume); got 1e+300 mm");
  doc = example();
  doc["measurements"][0]["setup"]["temperature_c"] = -300;
  EXPECT_EQ(rule_of(doc), "measurements[0] (\"L1-O000-mid-scan\").setup.temperature_c: is below "
                          "absolute zero (-273.15 °C): not a temperature in °C; got -300 °C");
}

TEST_F(CampaignTest, WrongTypesAreNamed) {
  json doc = example();
  doc["evaluation"]["trials"] = "many";
  EXPECT_EQ(rule_of(doc),
            "evaluation.trials: must be an integer from 100 to 100000000; got \"many\"");
  doc = example();
  doc["measurements"][1]["setup"]["orientation_deg"] = "90";
  EXPECT_EQ(rule_of(doc),
            "measurements[1] (\"C-O090-top-touch\").setup.orientation_deg: must be a number; "
            "got \"90\"");
  doc = example();
  doc["measurements"][0]["setup"] = json::array();
  EXPECT_EQ(rule_of(doc),
            "measurements[0] (\"L1-O000-mid-scan\").setup: must be an object {\"location\": ..., "
            "\"orientation_deg\": ..., \"height\": ..., \"mode\": ...}; got []");
  doc = example();
  doc["measurements"] = json::object();
  EXPECT_EQ(rule_of(doc), "measurements: must be an array of measurements; got {}");
  doc = example();
  doc["measurements"][0]["setup"]["location_mm"] = {600, 500};
  EXPECT_EQ(rule_of(doc),
            "measurements[0] (\"L1-O000-mid-scan\").setup.location_mm: must be an array of 3 "
            "numbers [x, y, z] (mm); got [600,500]");
  doc = example();
  doc["measurements"][0]["setup"]["location_mm"] = {600, "500", 400};
  EXPECT_EQ(rule_of(doc),
            "measurements[0] (\"L1-O000-mid-scan\").setup.location_mm[1]: must be a number; got "
            "\"500\"");
  doc = example();
  doc["measurements"][0]["id"] = 7;
  const Failure f = failure_of(doc);
  EXPECT_EQ(f.message, (dir_ / "campaign.json").string() +
                           ": measurements[0].id: must be a string; got 7");
  EXPECT_EQ(f.id, "");
  EXPECT_EQ(f.index, 0u);
  doc = example();
  doc["measurements"][1]["reference"]["roundness"]["u_um"] = true;
  EXPECT_EQ(rule_of(doc), "measurements[1] (\"C-O090-top-touch\").reference.roundness.u_um: must "
                          "be a number; got true");
  EXPECT_EQ(rule_of(json::array()), "a campaign must be a JSON object; got []");
}

TEST_F(CampaignTest, IdsMustBeUniqueAndFileNameSafe) {
  json doc = example();
  doc["measurements"][1]["id"] = "L1-O000-mid-scan";
  Failure f = failure_of(doc);
  EXPECT_EQ(f.message, (dir_ / "campaign.json").string() +
                           ": measurements[1] (\"L1-O000-mid-scan\").id: duplicate id "
                           "\"L1-O000-mid-scan\" (already used by measurements[0])");
  EXPECT_EQ(f.index, 1u);
  for (const char* bad : {"L1 O000", "../x", "a/b", "", "é"}) {
    doc = example();
    doc["measurements"][1]["id"] = bad;
    EXPECT_EQ(rule_of(doc), "measurements[1].id: must be a non-empty string of letters, digits, "
                            "'_', '.' and '-' (it names result files); got " + json(bad).dump())
        << bad;
  }
  doc = example();
  doc["measurements"][1]["id"] = "..";
  EXPECT_EQ(rule_of(doc),
            "measurements[1].id: must not be \".\" or \"..\" (it names result files); got \"..\"");
  doc = example();
  doc["measurements"][1]["id"] = std::string(201, 'x');
  EXPECT_EQ(rule_of(doc), "measurements[1].id: must be at most 200 characters (it names result "
                          "files); got 201");
  doc = example();
  doc["measurements"][1].erase("id");
  EXPECT_EQ(rule_of(doc), "measurements[1]: required key \"id\" missing");
  doc = example();
  doc["measurements"][1]["setup"]["location"] = "centre, left";
  EXPECT_EQ(rule_of(doc),
            "measurements[1] (\"C-O090-top-touch\").setup.location: must be a non-empty label of "
            "letters, digits, '_', '.' and '-' (it goes into CSV tables unquoted); got \"centre, "
            "left\"");
}

TEST_F(CampaignTest, EmptyMeasurementsAndMissingPieces) {
  json doc = example();
  doc["measurements"] = json::array();
  EXPECT_EQ(rule_of(doc), "measurements: a campaign needs at least one measurement");
  doc = example();
  doc.erase("measurements");
  EXPECT_EQ(rule_of(doc), "required key \"measurements\" missing");
  doc = example();
  doc["measurements"][0]["setup"].erase("mode");
  EXPECT_EQ(rule_of(doc),
            "measurements[0] (\"L1-O000-mid-scan\").setup: required key \"mode\" missing");
  doc = example();
  doc["measurements"][0]["reference"] = json::object();
  EXPECT_EQ(rule_of(doc), "measurements[0] (\"L1-O000-mid-scan\").reference: needs \"roundness\" "
                          "or \"diameter\" (or both)");
  doc = example();
  doc["measurements"][0]["reference"]["roundness"]["profile"] = "reference/L1-mid.csv";
  EXPECT_EQ(rule_of(doc), "measurements[0] (\"L1-O000-mid-scan\").reference.roundness: give "
                          "either \"value_um\" or \"profile\", not both");
  doc = example();
  doc["measurements"][0]["reference"]["roundness"].erase("value_um");
  EXPECT_EQ(rule_of(doc), "measurements[0] (\"L1-O000-mid-scan\").reference.roundness: needs "
                          "\"value_um\" (a given RONt) or \"profile\" (a roundness-meter profile)");
  doc = example();
  doc["measurements"][0]["reference"]["diameter"]["profile"] = "reference/two-lobe.csv";
  EXPECT_EQ(rule_of(doc), "measurements[0] (\"L1-O000-mid-scan\").reference.diameter: "
                          "\"profile\" belongs to the interferometer form; a given diameter takes "
                          "\"value_mm\" and \"u_um\"");
  doc = example();
  doc["measurements"][1]["reference"]["diameter"]["u_um"] = 0.05;
  EXPECT_EQ(rule_of(doc), "measurements[1] (\"C-O090-top-touch\").reference.diameter: \"u_um\" "
                          "belongs to a given diameter; the interferometer form takes "
                          "\"u_interferometer_um\" (and \"u_profile_point_um\")");
  doc = example();
  doc["schema"] = "vcmm.digital_model";
  EXPECT_EQ(rule_of(doc), "schema: must be \"vcmm.campaign\"; got \"vcmm.digital_model\"");
  doc = example();
  doc["schema_version"] = 2;
  EXPECT_EQ(rule_of(doc), "schema_version: unsupported version (this reader knows 1); got 2");
}

TEST_F(CampaignTest, BadEnumerationsListTheChoices) {
  json doc = example();
  doc["evaluation"]["reference_circle"] = "mz";
  EXPECT_EQ(
      rule_of(doc),
      "evaluation.reference_circle: must be one of \"MZ\", \"MI\", \"LS\", \"MC\"; got \"mz\"");
  doc = example();
  doc["measurements"][1]["setup"]["height"] = "centre";
  EXPECT_EQ(rule_of(doc), "measurements[1] (\"C-O090-top-touch\").setup.height: must be one of "
                          "\"top\", \"middle\", \"bottom\"; got \"centre\"");
  doc = example();
  doc["measurements"][1]["setup"]["mode"] = "touch";
  EXPECT_EQ(rule_of(doc), "measurements[1] (\"C-O090-top-touch\").setup.mode: must be one of "
                          "\"scanning\", \"touch_trigger\"; got \"touch\"");
}

TEST_F(CampaignTest, NumbersMustBeFiniteAndInRange) {
  // JSON cannot spell NaN or infinity; a number beyond double range is the way to get one.
  std::string text = example().dump(2);
  const std::string key = "\"value_um\": 0.205";
  text.replace(text.find(key), key.size(), "\"value_um\": 1e999");
  const Failure f = failure_of_text(text);
  EXPECT_EQ(f.json_path, "measurements[0].reference.roundness.value_um");
  EXPECT_EQ(f.index, 0u);
  EXPECT_EQ(f.id, "L1-O000-mid-scan");
  EXPECT_NE(f.message.find("measurements[0] (\"L1-O000-mid-scan\").reference.roundness.value_um: "
                           "invalid JSON: number overflow parsing '1e999'"),
            std::string::npos)
      << f.message;
  // An element of an array.
  text = example().dump();
  text.replace(text.find("[600,500,400]"), 13, "[600,-1e400,400]");
  EXPECT_EQ(failure_of_text(text).json_path, "measurements[0].setup.location_mm[1]");
  // NaN is not JSON at all: a syntax error, with the line.
  text = example().dump(2);
  text.replace(text.find(key), key.size(), "\"value_um\": NaN");
  const Failure g = failure_of_text(text);
  const auto line = 1 + std::count(text.begin(), text.begin() + text.find("NaN"), '\n');
  EXPECT_NE(g.message.find((dir_ / "campaign.json").string() + ":" + std::to_string(line) +
                           ": measurements[0] "
                           "(\"L1-O000-mid-scan\").reference.roundness.value_um: invalid JSON:"),
            std::string::npos)
      << g.message;

  json doc = example();
  for (const auto& [trials, shown] : {std::pair<json, std::string>{99, "99"},
                                      {100000001, "100000001"}, {-5, "-5"}, {1000.5, "1000.5"}}) {
    doc["evaluation"]["trials"] = trials;
    EXPECT_EQ(rule_of(doc), "evaluation.trials: must be an integer from 100 to 100000000; got " +
                                shown);
  }
  doc = example();
  doc["evaluation"]["seed"] = -1;
  EXPECT_EQ(rule_of(doc), "evaluation.seed: must be an unsigned 64-bit integer (0 to "
                          "18446744073709551615); got -1");
  doc = example();
  doc["evaluation"]["coverage_probability"] = 95;
  EXPECT_EQ(rule_of(doc), "evaluation.coverage_probability: must lie in (0, 1); got 95");
  doc = example();
  doc["evaluation"]["k"] = 0;
  EXPECT_EQ(rule_of(doc), "evaluation.k: must be > 0; got 0");
  doc = example();
  doc["evaluation"]["filter_cutoff_upr"] = -50;
  EXPECT_EQ(rule_of(doc), "evaluation.filter_cutoff_upr: must be > 0; got -50");
  doc = example();
  doc["measurements"][0]["reference"]["roundness"]["u_um"] = -0.01;
  EXPECT_EQ(rule_of(doc), "measurements[0] (\"L1-O000-mid-scan\").reference.roundness.u_um: must "
                          "be >= 0 (a standard uncertainty); got -0.01");
  doc = example();
  doc["measurements"][0]["reference"]["diameter"]["value_mm"] = 0;
  EXPECT_EQ(rule_of(doc), "measurements[0] (\"L1-O000-mid-scan\").reference.diameter.value_mm: "
                          "must be > 0; got 0");
}

TEST_F(CampaignTest, BudgetSettingsAreReadCheckedAndWritten) {
  json doc = example();
  EXPECT_FALSE(parse(doc).evaluation.budget);  // off by default
  doc["evaluation"]["trials"] = 2000;
  doc["evaluation"]["budget"] = true;
  EvaluationSettings e = parse(doc).evaluation;
  EXPECT_TRUE(e.budget);
  EXPECT_EQ(e.budget_trials, 0u);  // as many as the measurement's run
  doc["evaluation"]["budget_trials"] = 500;
  const Campaign c = parse(doc);
  EXPECT_EQ(c.evaluation.budget_trials, 500u);
  // Written explicitly and read back to the same settings.
  const std::string text = campaign_json(c);
  EXPECT_NE(text.find("\"budget\": true"), std::string::npos) << text;
  EXPECT_NE(text.find("\"budget_trials\": 500"), std::string::npos) << text;
  EXPECT_EQ(parse_text(text), c);
  doc["evaluation"]["budget_trials"] = 2000;  // the upper end: the measurement's trials
  EXPECT_EQ(parse(doc).evaluation.budget_trials, 2000u);
  Campaign off = parse(example());
  EXPECT_NE(campaign_json(off).find("\"budget\": false"), std::string::npos);
  EXPECT_EQ(campaign_json(off).find("budget_trials"), std::string::npos);

  for (const auto& [trials, shown] : {std::pair<json, std::string>{99, "99"}, {2001, "2001"},
                                      {-100, "-100"}, {500.5, "500.5"}, {"500", "\"500\""}}) {
    doc["evaluation"]["budget_trials"] = trials;
    EXPECT_EQ(rule_of(doc), "evaluation.budget_trials: must be an integer from 100 to 2000 "
                            "(evaluation.trials); got " + shown);
  }
  doc["evaluation"]["budget"] = false;
  doc["evaluation"]["budget_trials"] = 500;
  EXPECT_EQ(rule_of(doc), "evaluation.budget_trials: needs \"budget\": true (the trials of "
                          "each uncertainty-budget run)");
  doc["evaluation"].erase("budget");
  EXPECT_EQ(rule_of(doc), "evaluation.budget_trials: needs \"budget\": true (the trials of "
                          "each uncertainty-budget run)");
  doc["evaluation"].erase("budget_trials");
  doc["evaluation"]["budget"] = "yes";
  EXPECT_EQ(rule_of(doc), "evaluation.budget: must be true or false; got \"yes\"");
}

TEST_F(CampaignTest, SyntaxErrorsAndRepeatedKeysGiveLineAndPath) {
  const Failure f = failure_of_text("{\n  \"schema\": \"vcmm.campaign\",\n  \"model\": ,\n}\n");
  EXPECT_NE(f.message.find((dir_ / "campaign.json").string() + ":3: model: invalid JSON: "),
            std::string::npos)
      << f.message;
  // A key given twice: JSON parsers keep one silently; the campaign reader refuses.
  std::string text = example().dump(2);
  const std::string key = "\"mode\": \"touch_trigger\"";
  text.replace(text.find(key), key.size(), key + ", \"mode\": \"scanning\"");
  const Failure g = failure_of_text(text);
  EXPECT_EQ(g.message, (dir_ / "campaign.json").string() +
                           ": measurements[1] (\"C-O090-top-touch\").setup: key \"mode\" appears "
                           "twice in one object (JSON would keep only one)");
  EXPECT_EQ(g.json_path, "measurements[1].setup");
  // Comments are not JSON.
  EXPECT_NE(failure_of_text("// campaign\n" + example().dump()).message.find(":1: invalid JSON"),
            std::string::npos);
  // A nesting bomb is refused by the shared guard before any recursive walk (issue 12).
  const Failure bomb = failure_of_text("{\"measurements\": " + std::string(100000, '[') + "}");
  EXPECT_NE(bomb.message.find("nesting deeper than 64 levels"), std::string::npos)
      << bomb.message;
}

TEST_F(CampaignTest, ErrorsAreTheLibrarysInvalidInput) {
  json doc = example();
  doc["evaluation"]["trials"] = 5;
  write_text(dir_ / "campaign.json", doc.dump());
  EXPECT_THROW(read_campaign_file(dir_ / "campaign.json"), vcmm::geometry::InvalidInput);
  // parse_campaign resolves against the given path's directory, whether or not it exists.
  EXPECT_NO_THROW(parse_campaign(example().dump(), dir_ / "not-written.json"));
  EXPECT_THROW(parse_campaign(example().dump(), dir_ / "sub" / "c.json"), CampaignError);
}

TEST(MeasurementSeed, StableAndDependsOnSeedAndIdOnly) {
  // Pinned: the rule is part of campaign format v1 (changing it changes every result). The
  // values were computed by an independent Python transcription of splitmix64 and FNV-1a.
  EXPECT_EQ(measurement_seed(1, "L1-O000-mid-scan"), 0x85850300ed36f48dull);
  EXPECT_EQ(measurement_seed(1, ""), 0x36178ff42bee28e5ull);
  EXPECT_EQ(measurement_seed(42, "C-O090-top-touch"), 0xd3ca9b4bbb6baaa2ull);
  EXPECT_NE(measurement_seed(1, "a"), measurement_seed(1, "b"));
  EXPECT_NE(measurement_seed(1, "a"), measurement_seed(2, "a"));
  EXPECT_NE(measurement_seed(1, "ab"), measurement_seed(1, "ba"));
}

TEST_F(CampaignTest, ReferencesEvaluateToTheHandKnownValues) {
  json doc = example();
  doc["evaluation"]["filter_cutoff_upr"] = nullptr;
  Campaign c = parse(doc);
  // Given values, converted to mm.
  const auto ron0 = evaluate_roundness_reference(c, 0, 85.5);
  ASSERT_TRUE(ron0);
  EXPECT_DOUBLE_EQ(ron0->value_mm, 0.205e-3);
  EXPECT_DOUBLE_EQ(ron0->u_mm, 0.010e-3);
  EXPECT_EQ(ron0->method, "given in the campaign file");
  const auto dia0 = evaluate_diameter_reference(c, 0);
  EXPECT_EQ(dia0->value_mm, 171.00012);
  EXPECT_DOUBLE_EQ(dia0->u_mm, 0.05e-6 * 1e3);
  // Profile: 0.4 µm cos 3θ every 1°, unfiltered MZ → RONt = 0.8 µm (exact up to rounding).
  const auto ron1 = evaluate_roundness_reference(c, 1, 85.5);
  ASSERT_TRUE(ron1);
  EXPECT_NEAR(ron1->value_mm, 0.8e-3, 1e-12);
  EXPECT_DOUBLE_EQ(ron1->u_mm, 0.010e-3);
  EXPECT_TRUE(ron1->verified);
  EXPECT_NE(ron1->method.find("MZ, unfiltered, certificate verified"), std::string::npos)
      << ron1->method;
  // Filtered at 50 UPR: harmonic 3 passes with H = 2^−(3/50)².
  c.evaluation.filter_cutoff_upr = 50.0;
  EXPECT_NEAR(evaluate_roundness_reference(c, 1, 85.5)->value_mm, 0.8e-3 * std::exp2(-0.0036),
              1e-12);
  // Interferometer: 0.25 µm cos 2θ → D = L − 2a; u = sqrt(u_L² + u_p²(2 − 4/360)).
  const auto dia1 = evaluate_diameter_reference(c, 1);
  ASSERT_TRUE(dia1);
  EXPECT_NEAR(dia1->value_mm, 171.0001 - 0.5e-3, 1e-12);
  EXPECT_NEAR(dia1->u_mm, 1e-3 * std::hypot(0.04, 0.01 * std::sqrt(2.0 - 4.0 / 360)), 1e-15);
  // No such reference.
  c.measurements[1].reference.roundness.reset();
  EXPECT_FALSE(evaluate_roundness_reference(c, 1, 85.5).has_value());
}

TEST_F(CampaignTest, ReferenceEvaluationErrorsNameTheEntry) {
  const Campaign c = parse(example());
  write_text(dir_ / "reference/L1-mid.csv", "angle_deg,deviation_um\n0,0.1\n10,abc\n");
  try {
    evaluate_roundness_reference(c, 1, 85.5);
    ADD_FAILURE() << "no exception";
  } catch (const CampaignError& e) {
    EXPECT_EQ(std::string(e.what()),
              (dir_ / "campaign.json").string() +
                  ": measurements[1] (\"C-O090-top-touch\").reference.roundness.profile: " +
                  (dir_ / "reference/L1-mid.csv").string() +
                  ":3: field 2 (deviation_um) is not a number ('abc')");
    EXPECT_EQ(e.json_path(), "measurements[1].reference.roundness.profile");
  }
  fs::remove(dir_ / "reference/two-lobe.csv");
  try {
    evaluate_diameter_reference(c, 1);
    ADD_FAILURE() << "no exception";
  } catch (const CampaignError& e) {
    EXPECT_EQ(e.json_path(), "measurements[1].reference.diameter.profile");
    EXPECT_NE(std::string(e.what()).find("cannot read the roundness profile file: no such file"), std::string::npos);
  }
  EXPECT_THROW(evaluate_diameter_reference(c, 2), vcmm::geometry::InvalidInput);
  EXPECT_THROW(evaluate_roundness_reference(c, 0, 0.0), vcmm::geometry::InvalidInput);
}

}  // namespace
