// `vcmm characterize hole-plate` (cli/characterize_hole_plate_command.cpp, docs/cli.md): the
// bundled example (examples/characterization/hole_plate/README.md) runs, and the kinematics
// section it writes loads with errormodel::parse_digital_model in place of the example model's
// "kinematics" — with the library's estimate (the command adds no logic); the explicit
// --axis-range/--degree-of form the README gives says the same as --model; invalid files exit
// 3 naming the file and write nothing; bad options exit 2 and write nothing.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/cli_run.h"
#include "vcmm/characterization/hole_plate.h"
#include "vcmm/errormodel/digital_model.h"

namespace {

namespace fs = std::filesystem;
namespace ch = vcmm::characterization;
namespace em = vcmm::errormodel;
using vcmm::test::CliRun;
using vcmm::test::scratch_dir;
using vcmm::test::slurp;

const std::string kExe = VCMM_EXE;
const std::string kSource = VCMM_SOURCE_DIR;
const std::string kModel = kSource + "/examples/cmm_model.json";
const std::string kPlateDir = kSource + "/examples/characterization/hole_plate/";
const std::vector<std::string> kPlacements = {
    "xy_low_t1.csv", "xy_low_t2.csv", "xy_low_t3.csv", "xy_high_t1.csv", "xz_t1.csv",
    "xz_t2.csv",     "xz_t3.csv",     "yz_t1.csv",     "yz_t2.csv",      "yz_t3.csv"};

CliRun run(const std::string& args) { return vcmm::test::run_command(kExe, args); }

std::string quoted(const std::string& path) { return "'" + path + "'"; }

/// The README's command line without -o/--json: plate, the ten placements, σ = 0.2 µm.
std::string example_inputs(const std::string& plate = kPlateDir + "plate.csv") {
  std::string args = "characterize hole-plate --plate " + quoted(plate);
  for (const std::string& p : kPlacements) args += " --placement " + quoted(kPlateDir + p);
  return args + " --probing-sigma-um 0.2";
}

/// The example model with its "kinematics" replaced by `kinematics`: what a user does with the
/// command's output.
em::DigitalModel merged_model(const nlohmann::json& kinematics) {
  std::ifstream f(kModel);
  nlohmann::json model = nlohmann::json::parse(f);
  model["kinematics"] = kinematics;
  return em::parse_digital_model(model.dump(), "merged model");
}

/// Removes `paths` and returns them (so that "writes nothing" is checked against a clean slate).
std::vector<fs::path> fresh(std::initializer_list<const char*> names) {
  std::vector<fs::path> out;
  for (const char* n : names) {
    out.push_back(scratch_dir() / n);
    fs::remove(out.back());
  }
  return out;
}

TEST(CliCharacterizeHolePlate, BundledExampleWritesALoadableKinematicsSection) {
  const auto files = fresh({"hp_kinematics.json", "hp_report.json"});
  const fs::path &json = files[0], &report = files[1];
  const CliRun r = run(example_inputs() + " --model " + quoted(kModel) + " -o " +
                       quoted(json.string()) + " --json " + quoted(report.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("vcmm characterize hole-plate: " + kPlateDir + "plate.csv, 10 placements, "
                       "4 setups"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("wrote " + json.string() + " and " + report.string()), std::string::npos)
      << r.out;

  const nlohmann::json out = nlohmann::json::parse(slurp(json));
  ASSERT_TRUE(out.is_object());
  ASSERT_EQ(out.size(), 1u) << out.dump();  // {"kinematics": {...}} and nothing else
  ASSERT_TRUE(out.contains("kinematics"));
  EXPECT_NE(out["kinematics"]["source"].get<std::string>().find("xy_low_t1.csv"),
            std::string::npos);
  const em::DigitalModel loaded = merged_model(out["kinematics"]);  // throws if not accepted

  // The library's estimate with the options --model implies: the section carries it.
  const em::DigitalModel example = em::read_digital_model_file(kModel);
  ch::HolePlateFitOptions options;
  options.chain = example.kinematics.chain();
  for (int k = 0; k < 3; ++k)
    options.axis_ranges[static_cast<std::size_t>(k)] =
        example.kinematics.range(static_cast<em::Axis>(k));
  options.degrees = ch::degrees_of(example.kinematics);
  options.probing_sigma_mm = 0.2e-3;
  std::vector<ch::HolePlatePlacement> placements;
  for (const std::string& p : kPlacements)
    placements.push_back(ch::read_hole_plate_placement_csv_file(kPlateDir + p));
  const ch::KinematicCharacterization expected = ch::estimate_kinematic_errors(
      placements, ch::read_hole_plate_csv_file(kPlateDir + "plate.csv"), options);
  ASSERT_TRUE(expected.usable) << expected.message;
  const em::KinematicModel& k = loaded.kinematics;
  EXPECT_TRUE(k.chain() == example.kinematics.chain());
  for (int a = 0; a < 3; ++a) {
    const auto axis = static_cast<em::Axis>(a);
    EXPECT_EQ(k.range(axis).min, example.kinematics.range(axis).min);
    EXPECT_EQ(k.range(axis).max, example.kinematics.range(axis).max);
  }
  ASSERT_EQ(k.parameter_count(), expected.model.parameter_count());
  // Values and standard uncertainties go through µm/µrad text with shortest round-trip
  // doubles: one rounding each way, relative ≤ 2⁻⁵² ≈ 2.2e-16. Coefficients are below 1e-2 mm
  // (1e-5 rad) and u below 1e-2 mm: 1e-15 absolute is a margin of ~500 over that.
  for (Eigen::Index i = 0; i < k.parameter_count(); ++i) {
    EXPECT_NEAR(k.mean()(i), expected.model.mean()(i), 1e-15) << "parameter " << i;
    EXPECT_NEAR(std::sqrt(k.covariance()(i, i)), std::sqrt(expected.model.covariance()(i, i)),
                1e-15)
        << "parameter " << i;
  }
  // Not a zero model: the example machine has errors of tenths of a µm.
  EXPECT_GT(k.mean().cwiseAbs().maxCoeff(), 1e-5);

  const nlohmann::json rep = nlohmann::json::parse(slurp(report));
  EXPECT_TRUE(rep["usable"].get<bool>());
  EXPECT_EQ(rep["observations"].get<long>(), static_cast<long>(expected.observations));
}

TEST(CliCharacterizeHolePlate, ExplicitRangesAndDegreesSayWhatTheModelSays) {
  // README: "--axis-range X=0,1200 --axis-range Y=0,1000 --axis-range Z=0,800 --degree-of …
  // says the same explicitly" — degree 3 for the nine translation functions, 2 for rotations.
  const auto files = fresh({"hp_from_model.json", "hp_explicit.json"});
  CliRun r = run(example_inputs() + " --model " + quoted(kModel) + " -o " +
                 quoted(files[0].string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string explicit_args = example_inputs() +
                              " --axis-range X=0,1200 --axis-range Y=0,1000 --axis-range Z=0,800"
                              " --degree 2";
  for (const char* f : {"E_XX", "E_YX", "E_ZX", "E_XY", "E_YY", "E_ZY", "E_XZ", "E_YZ", "E_ZZ"})
    explicit_args += std::string(" --degree-of ") + f + "=3";
  r = run(explicit_args + " -o " + quoted(files[1].string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(slurp(files[0])), nlohmann::json::parse(slurp(files[1])));
}

TEST(CliCharacterizeHolePlate, InvalidFilesExit3NamingTheFileAndWriteNothing) {
  const auto files = fresh({"hp_never.json", "hp_never_report.json"});
  const std::string outputs =
      " --model " + quoted(kModel) + " -o " + quoted(files[0].string()) + " --json " +
      quoted(files[1].string());
  const auto expect_nothing_written = [&] {
    EXPECT_FALSE(fs::exists(files[0]));
    EXPECT_FALSE(fs::exists(files[1]));
  };
  // A plate file that does not exist.
  const fs::path missing = scratch_dir() / "no_such_plate.csv";
  fs::remove(missing);
  CliRun r = run(example_inputs(missing.string()) + outputs);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find(missing.string()), std::string::npos) << r.err;
  expect_nothing_written();
  // A placement file that does not exist.
  const fs::path missing_placement = scratch_dir() / "no_such_placement.csv";
  fs::remove(missing_placement);
  r = run(example_inputs() + " --placement " + quoted(missing_placement.string()) + outputs);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find(missing_placement.string()), std::string::npos) << r.err;
  expect_nothing_written();
  // NaN in the plate file: the example plate with R1C2's x replaced (line 6: four header
  // lines, then R1C1).
  std::string plate = slurp(kPlateDir + "plate.csv");
  const auto at = plate.find("R1C2,");
  ASSERT_NE(at, std::string::npos);
  const auto comma = plate.find(',', at + 5);
  plate.replace(at + 5, comma - (at + 5), "nan");
  const fs::path nan_plate = scratch_dir() / "nan_plate.csv";
  std::ofstream(nan_plate) << plate;
  r = run(example_inputs(nan_plate.string()) + outputs);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find(nan_plate.string() + ":6:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not finite"), std::string::npos) << r.err;
  expect_nothing_written();
  // A model file that is not one.
  r = run(example_inputs() + " --model " + quoted(nan_plate.string()) + " -o " +
          quoted(files[0].string()));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find(nan_plate.string()), std::string::npos) << r.err;
  expect_nothing_written();
}

TEST(CliCharacterizeHolePlate, BadOptionsExit2AndWriteNothing) {
  const auto files = fresh({"hp_usage.json"});
  const std::string o = " -o " + quoted(files[0].string());
  const std::string model = " --model " + quoted(kModel);
  // An option the command does not know.
  CliRun r = run(example_inputs() + model + " --bogus 1" + o);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  // σ must be > 0.
  r = run("characterize hole-plate --plate " + quoted(kPlateDir + "plate.csv") + " --placement " +
          quoted(kPlateDir + "xy_low_t1.csv") + " --probing-sigma-um -0.2" + model + o);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--probing-sigma-um"), std::string::npos) << r.err;
  // Issue 12: 1e300 was blamed on "collinear features"; it is the value (a σ ≤ 1 mm).
  r = run("characterize hole-plate --plate " + quoted(kPlateDir + "plate.csv") + " --placement " +
          quoted(kPlateDir + "xy_low_t1.csv") + " --probing-sigma-um 1e300" + model + o);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--probing-sigma-um: must lie in (0, 1000] µm"), std::string::npos)
      << r.err;
  // No axis ranges and no model; an axis that does not exist; an unknown function name.
  r = run(example_inputs() + o);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--axis-range"), std::string::npos) << r.err;
  r = run(example_inputs() + " --axis-range X=0,1200 --axis-range Y=0,1000 --axis-range W=0,800" +
          o);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("'W'"), std::string::npos) << r.err;
  r = run(example_inputs() + model + " --degree-of E_QQ=2" + o);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("E_QQ"), std::string::npos) << r.err;
  // Required options missing: no -o, no --plate.
  EXPECT_EQ(run(example_inputs() + model).exit_code, 2);
  EXPECT_EQ(run("characterize hole-plate --placement " + quoted(kPlateDir + "xy_low_t1.csv") +
                " --probing-sigma-um 0.2" + model + o)
                .exit_code,
            2);
  EXPECT_FALSE(fs::exists(files[0]));
}

}  // namespace
