// The digital-model file: the example parses with the documented unit conversions, and every
// broken rule is an InvalidParameter naming the full key path, the value and the rule.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/errors.h"

namespace {

using namespace vcmm::errormodel;
using nlohmann::json;

const std::string kExample = std::string(VCMM_SOURCE_DIR) + "/examples/cmm_model.json";

json example_json() {
  std::ifstream f(kExample);
  return json::parse(f);
}

struct Failure {
  std::string key_path;
  std::string message;
};

Failure failure_of(const std::string& text) {
  try {
    parse_digital_model(text, "model.json");
  } catch (const InvalidParameter& e) {
    return {e.key_path(), e.what()};
  }
  return {"(no exception)", "(no exception)"};
}

Failure failure_of(const json& j) { return failure_of(j.dump(2)); }

TEST(DigitalModel, ExampleFileParsesWithUnitsConverted) {
  const DigitalModel m = read_digital_model_file(kExample);
  EXPECT_FALSE(m.description.empty());
  EXPECT_DOUBLE_EQ(m.roughness.sigma_mm, 0.05e-3);
  EXPECT_DOUBLE_EQ(m.temperature.expansion_coefficient_per_k.value, 11.5e-6);
  EXPECT_DOUBLE_EQ(m.temperature.expansion_coefficient_per_k.u, 1.0e-6);
  EXPECT_DOUBLE_EQ(m.temperature.thermometer_u_k, 0.1);
  EXPECT_DOUBLE_EQ(m.probe.tip_radius_error_mm.value, 0.05e-3);
  EXPECT_DOUBLE_EQ(m.probe.tip_radius_error_mm.u, 0.10e-3);
  ASSERT_EQ(m.probe.directional.size(), 3u);
  EXPECT_EQ(m.probe.directional[1].order, 3);
  EXPECT_DOUBLE_EQ(m.probe.directional[1].cos_mm.value, 0.08e-3);
  EXPECT_DOUBLE_EQ(m.probe.directional[1].sin_mm.u, 0.15e-3);
  EXPECT_DOUBLE_EQ(m.noise.scanning_sigma_mm, 0.7e-3);
  EXPECT_DOUBLE_EQ(m.noise.touch_trigger_sigma_mm, 0.45e-3);
  EXPECT_EQ(m.kinematics.chain(), KinematicChain::moving_bridge());
  EXPECT_DOUBLE_EQ(m.kinematics.nominal().squareness(m.kinematics, Squareness::E_C0Y), 0.6e-6);
  EXPECT_NO_THROW(validate_digital_model(m));
}

TEST(DigitalModelBadFile, MissingKeyNamesItsPath) {
  json j = example_json();
  j["noise"].erase("touch_trigger_sigma_um");
  const Failure f = failure_of(j);
  EXPECT_EQ(f.key_path, "noise.touch_trigger_sigma_um");
  EXPECT_NE(f.message.find("model.json: noise.touch_trigger_sigma_um: required key missing"),
            std::string::npos)
      << f.message;
}

TEST(DigitalModelBadFile, NegativeSigmaNamesPathValueAndRule) {
  json j = example_json();
  j["noise"]["scanning_sigma_um"] = -0.2;
  const Failure f = failure_of(j);
  EXPECT_EQ(f.key_path, "noise.scanning_sigma_um");
  EXPECT_NE(f.message.find("must lie in [0, 1000] µm (a standard deviation); got -0.2 µm"),
            std::string::npos)
      << f.message;
}

// Issue 12: a noise σ or tip error of 1e300 made `simulate` write points at 1e296 mm, and an
// α of 1e300 was blamed on an axis range. Each value beyond its physical range is refused
// under its own key, with the unit (errormodel/physical_ranges.h).
TEST(DigitalModelBadFile, ValuesBeyondTheirPhysicalRangeNameKeyAndUnit) {
  struct Case {
    std::vector<std::string> path;
    double value;
    std::string key, rule;
  };
  const Case cases[] = {
      {{"noise", "scanning_sigma_um"}, 1e300, "noise.scanning_sigma_um",
       "must lie in [0, 1000] µm (a standard deviation); got 1e+300 µm"},
      {{"noise", "touch_trigger_sigma_um"}, 1001, "noise.touch_trigger_sigma_um",
       "must lie in [0, 1000] µm"},
      {{"roughness", "sigma_um"}, 1e300, "roughness.sigma_um", "must lie in [0, 1000] µm"},
      {{"temperature", "expansion_coefficient", "value_per_K"}, 1e300,
       "temperature.expansion_coefficient.value_per_K",
       "must lie in [-0.001, 0.001] /K (a linear expansion coefficient); got 1e+300 /K"},
      {{"temperature", "expansion_coefficient", "uncertainty_per_K"}, 0.5,
       "temperature.expansion_coefficient.uncertainty_per_K", "must lie in [0, 0.001] /K"},
      {{"temperature", "thermometer_uncertainty_K"}, 273.15,
       "temperature.thermometer_uncertainty_K", "must lie in [0, 10] K"},
      {{"probe", "tip_radius_error", "value_um"}, -1e300, "probe.tip_radius_error.value_um",
       "must lie in [-1000, 1000] µm (a probe error); got -1e+300 µm"},
      {{"probe", "tip_radius_error", "uncertainty_um"}, 1e300,
       "probe.tip_radius_error.uncertainty_um", "must lie in [0, 1000] µm"},
  };
  for (const Case& c : cases) {
    json j = example_json();
    json* at = &j;
    for (const std::string& k : c.path) at = &(*at)[k];
    *at = c.value;
    const Failure f = failure_of(j);
    EXPECT_EQ(f.key_path, c.key);
    EXPECT_NE(f.message.find("model.json: " + c.key + ": " + c.rule), std::string::npos)
        << f.message;
  }
  json j = example_json();
  j["probe"]["directional_error"][1]["sin"]["value_um"] = 2000;
  EXPECT_EQ(failure_of(j).key_path, "probe.directional_error[1].sin.value_um");
  // Just inside the limits: accepted.
  j = example_json();
  j["noise"]["scanning_sigma_um"] = 1000;
  j["temperature"]["expansion_coefficient"]["value_per_K"] = -1e-3;
  EXPECT_NO_THROW(parse_digital_model(j.dump(), "model.json"));
}

TEST(DigitalModelBadFile, NonNumericValue) {
  json j = example_json();
  j["temperature"]["expansion_coefficient"]["value_per_K"] = "11.5e-6";
  const Failure f = failure_of(j);
  EXPECT_EQ(f.key_path, "temperature.expansion_coefficient.value_per_K");
  EXPECT_NE(f.message.find("must be a number; got \"11.5e-6\""), std::string::npos) << f.message;
  j = example_json();
  j["roughness"]["sigma_um"] = true;  // a boolean is not a number
  EXPECT_EQ(failure_of(j).key_path, "roughness.sigma_um");
}

TEST(DigitalModelBadFile, UnknownKeyIsAnErrorNotIgnored) {
  json j = example_json();
  j["probe"]["tip_radius_eror"] = {{"value_um", 0.0}, {"uncertainty_um", 0.1}};
  Failure f = failure_of(j);
  EXPECT_EQ(f.key_path, "probe.tip_radius_eror");
  EXPECT_NE(f.message.find("unknown key"), std::string::npos) << f.message;
  j = example_json();
  j["thermal"] = json::object();
  EXPECT_EQ(failure_of(j).key_path, "thermal");
  j = example_json();
  j["probe"]["directional_error"][0]["cos"]["u"] = 0.1;
  EXPECT_EQ(failure_of(j).key_path, "probe.directional_error[0].cos.u");
}

TEST(DigitalModelBadFile, WrongSchemaOrVersion) {
  json j = example_json();
  j["schema_version"] = 2;
  Failure f = failure_of(j);
  EXPECT_EQ(f.key_path, "schema_version");
  EXPECT_NE(f.message.find("unsupported version (this reader: 1); got 2"), std::string::npos)
      << f.message;
  j = example_json();
  j["schema"] = "vcmm.campaign";
  EXPECT_EQ(failure_of(j).key_path, "schema");
  j = example_json();
  j.erase("schema_version");
  EXPECT_EQ(failure_of(j).key_path, "schema_version");
}

TEST(DigitalModelBadFile, NegativeUncertaintyAndBadHarmonics) {
  json j = example_json();
  j["probe"]["tip_radius_error"]["uncertainty_um"] = -0.1;
  EXPECT_EQ(failure_of(j).key_path, "probe.tip_radius_error.uncertainty_um");
  j = example_json();
  j["probe"]["directional_error"][2]["order"] = 3;
  Failure f = failure_of(j);
  EXPECT_EQ(f.key_path, "probe.directional_error[2].order");
  EXPECT_NE(f.message.find("repeats an order"), std::string::npos) << f.message;
  j = example_json();
  j["probe"]["directional_error"][0]["order"] = 0;
  EXPECT_EQ(failure_of(j).key_path, "probe.directional_error[0].order");
  j["probe"]["directional_error"][0]["order"] = 2.5;
  EXPECT_EQ(failure_of(j).key_path, "probe.directional_error[0].order");
  j = example_json();
  j["temperature"]["thermometer_uncertainty_K"] = -1;
  EXPECT_EQ(failure_of(j).key_path, "temperature.thermometer_uncertainty_K");
}

TEST(DigitalModelBadFile, KinematicsErrorsKeepTheirKeyPath) {
  json j = example_json();
  j["kinematics"]["errors"]["E_AX"]["uncertainty_urad"][1] = -0.2;
  const Failure f = failure_of(j);
  EXPECT_EQ(f.key_path, "kinematics.errors.E_AX.uncertainty_urad[1]");
  EXPECT_NE(f.message.find("model.json: kinematics.errors.E_AX.uncertainty_urad[1]"),
            std::string::npos)
      << f.message;
  j = example_json();
  j.erase("kinematics");
  EXPECT_EQ(failure_of(j).key_path, "kinematics");
}

TEST(DigitalModelBadFile, InvalidJsonNamesTheLine) {
  std::string text = example_json().dump(2);
  text.insert(text.find("\"noise\""), "oops ");
  const Failure f = failure_of(text);
  EXPECT_EQ(f.key_path, "");
  EXPECT_NE(f.message.find("not valid JSON"), std::string::npos) << f.message;
  EXPECT_NE(f.message.find("model.json:"), std::string::npos) << f.message;
  EXPECT_EQ(failure_of(std::string("[1, 2]"))
                .message.find("model.json: the file must hold one JSON object"),
            0u);
  EXPECT_THROW(read_digital_model_file("/nonexistent/model.json"), InvalidParameter);
}

TEST(DigitalModelValidation, ModelsBuiltInCodeAreCheckedLikeFiles) {
  DigitalModel m = read_digital_model_file(kExample);
  m.noise.touch_trigger_sigma_mm = -1e-3;
  try {
    validate_digital_model(m);
    FAIL() << "no exception";
  } catch (const InvalidParameter& e) {
    EXPECT_EQ(e.key_path(), "noise.touch_trigger_sigma_um");
  }
  m = read_digital_model_file(kExample);
  m.noise.scanning_sigma_mm = 1.5;  // 1500 µm: the file's limit, in the model's mm
  try {
    validate_digital_model(m);
    FAIL() << "no exception";
  } catch (const InvalidParameter& e) {
    EXPECT_EQ(e.key_path(), "noise.scanning_sigma_um");
    EXPECT_NE(std::string(e.what()).find("got 1500 µm"), std::string::npos) << e.what();
  }
  m = read_digital_model_file(kExample);
  m.probe.directional.push_back({2, {0.0, 0.0}, {0.0, 0.0}});
  EXPECT_THROW(validate_digital_model(m), InvalidParameter);
}

}  // namespace
