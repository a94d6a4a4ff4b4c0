// `vcmm characterize sphere` and `vcmm characterize noise`: round trips through the command
// (calibration data simulated with a known model → command → JSON merged into a model file →
// errormodel::parse_digital_model → the known values within their uncertainties), the bundled
// examples, exit codes and messages (docs/cli.md).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "support/cli_run.h"
#include "vcmm/characterization/probe_sphere.h"
#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/random_source.h"
#include "vcmm/errormodel/virtual_cmm.h"

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
const std::string kNoise = kSource + "/examples/characterization/noise/";
const std::string kSphere = kSource + "/examples/characterization/sphere/";
constexpr double kUm = 1e-3;

CliRun run(const std::string& args) { return vcmm::test::run_command(kExe, args); }

/// The example model with `sections` replaced: what a user does with the command's output.
em::DigitalModel merged_model(const nlohmann::json& sections) {
  std::ifstream f(kModel);
  nlohmann::json model = nlohmann::json::parse(f);
  for (const auto& [key, value] : sections.items())
    if (key != "characterization") model[key] = value;
  return em::parse_digital_model(model.dump(), "merged model");
}

TEST(CliCharacterizeSphere, RoundTripThroughTheModelFile) {
  // Truth: the example model's probe section, the lobing tripled; 73-point plan, touch noise
  // 0.15 µm; the sphere's true diameter 20 nm above the certificate (u 0.05 µm). Written as
  // x,y,z with 17 digits, characterised by the command, merged, loaded, compared (3 u).
  em::DigitalModel truth = em::read_digital_model_file(kModel);
  for (em::ProbeHarmonic& h : truth.probe.directional) {
    h.cos_mm = {3.0 * h.cos_mm.value, 0.0};
    h.sin_mm = {3.0 * h.sin_mm.value, 0.0};
  }
  truth.probe.tip_radius_error_mm.u = 0.0;
  truth.noise.touch_trigger_sigma_mm = 0.15 * kUm;
  em::Placement placement;
  placement.location_mm = Eigen::Vector3d(400.0, 300.0, 200.0);
  const double d_cal = 30.0, d_true = d_cal + 0.02 * kUm;
  const em::Measurement nominal = ch::sphere_measurement(d_true, ch::dense_hemisphere_directions(),
                                                         placement, em::ProbingMode::touch_trigger);
  em::Stages stages = em::Stages::none();
  stages.set(em::ErrorSource::probe, true).set(em::ErrorSource::noise, true);
  em::SeededRandomSource rng(2024);
  const Eigen::Matrix3Xd pts = em::machine_coordinates(
      em::simulate(nominal, truth, em::draw_errors(truth, nominal, rng, stages), stages));
  const fs::path csv = scratch_dir() / "sphere_points.csv";
  {
    std::ofstream out(csv);
    out.precision(17);
    out << "x,y,z\n";
    for (Eigen::Index i = 0; i < pts.cols(); ++i)
      out << pts(0, i) << "," << pts(1, i) << "," << pts(2, i) << "\n";
  }
  const fs::path json = scratch_dir() / "probe.json";
  const CliRun r =
      run("characterize sphere --points '" + csv.string() +
          "' --diameter-mm 30 --u-diameter-um 0.05 --orders 1,2,3,4 -o '" + json.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("order 1"), std::string::npos) << r.err;  // reported, not estimated
  const nlohmann::json out = nlohmann::json::parse(slurp(json));
  const em::DigitalModel loaded = merged_model(out);
  const em::ProbeModel& p = loaded.probe;
  const double expected_dr = truth.probe.tip_radius_error_mm.value + 0.5 * (d_true - d_cal);
  EXPECT_NEAR(p.tip_radius_error_mm.value, expected_dr, 3.0 * p.tip_radius_error_mm.u);
  ASSERT_EQ(p.directional.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(p.directional[i].order, truth.probe.directional[i].order);
    EXPECT_NEAR(p.directional[i].cos_mm.value, truth.probe.directional[i].cos_mm.value,
                3.0 * p.directional[i].cos_mm.u);
    EXPECT_NEAR(p.directional[i].sin_mm.value, truth.probe.directional[i].sin_mm.value,
                3.0 * p.directional[i].sin_mm.u);
  }
  EXPECT_EQ(out["characterization"]["not_identifiable"][0]["what"], "order 1");
}

TEST(CliCharacterizeSphere, BundledExamples) {
  // examples/characterization/sphere/truth.json: δr to expect 0.365 µm (0.35 + (D_true −
  // D_cal)/2), lobing cos_3 0.24 µm.
  for (const char* file : {"sphere_iso25.csv", "sphere_dense.csv"}) {
    const fs::path json = scratch_dir() / "probe_example.json";
    const CliRun r = run("characterize sphere --points '" + kSphere + file +
                         "' --diameter-mm 25.0004 --u-diameter-um 0.05 --form-um 0.03 -o '" +
                         json.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json probe = nlohmann::json::parse(slurp(json))["probe"];
    EXPECT_NEAR(probe["tip_radius_error"]["value_um"].get<double>(), 0.365,
                3.0 * probe["tip_radius_error"]["uncertainty_um"].get<double>())
        << file;
    EXPECT_NEAR(probe["directional_error"][1]["cos"]["value_um"].get<double>(), 0.24,
                3.0 * probe["directional_error"][1]["cos"]["uncertainty_um"].get<double>())
        << file;
  }
}

TEST(CliCharacterizeSphere, ExitCodes) {
  const fs::path out = scratch_dir() / "never_probe.json";
  fs::remove(out);
  const std::string iso = "--points '" + kSphere + "sphere_iso25.csv' --diameter-mm 25.0004 ";
  // Rank-deficient design: exit 4, the combination named, no file.
  CliRun r = run("characterize sphere " + iso + "--u-diameter-um 0.05 --orders 2,8 -o '" +
                 out.string() + "'");
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_NE(r.err.find("sin_8"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  // Invalid input: a NaN in the file, a wrong diameter.
  const fs::path bad = scratch_dir() / "nan_sphere.csv";
  std::ofstream(bad) << "1,2,3\nnan,2,3\n";
  r = run("characterize sphere --points '" + bad.string() +
          "' --diameter-mm 25 --u-diameter-um 0.05 -o '" + out.string() + "'");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("nan_sphere.csv:2"), std::string::npos) << r.err;
  r = run("characterize sphere " + iso + "--u-diameter-um 0.05 --diameter-mm 50 -o '" +
          out.string() + "'");
  EXPECT_EQ(r.exit_code, 2);  // --diameter-mm given twice
  r = run("characterize sphere --points '" + kSphere +
          "sphere_iso25.csv' --diameter-mm 50 --u-diameter-um 0.05 -o '" + out.string() + "'");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("differs from the calibrated"), std::string::npos) << r.err;
  // Usage.
  EXPECT_EQ(run("characterize sphere " + iso + "-o x.json").exit_code, 2);  // no u
  EXPECT_EQ(run("characterize sphere " + iso + "--u-diameter-um -1 -o x.json").exit_code, 2);
  // Issue 12: 1e300 wrote "uncertainty_um": null with exit 0; it is refused as the value.
  const CliRun huge = run("characterize sphere " + iso + "--u-diameter-um 1e300 -o x.json");
  EXPECT_EQ(huge.exit_code, 2) << huge.err;
  EXPECT_NE(huge.err.find("--u-diameter-um must be a standard uncertainty"), std::string::npos)
      << huge.err;
  EXPECT_EQ(
      run("characterize sphere " + iso + "--u-diameter-um 0.1 --orders 0 -o x.json").exit_code, 2);
  EXPECT_FALSE(fs::exists(out));
}

TEST(CliCharacterizeNoise, BundledExampleRoundTrip) {
  // examples/characterization/noise: the example model (scanning 0.7 µm, touch 0.45 µm,
  // roughness 0.05 µm), ring turned 30°. The repeat pair gives the roughness-free scanning σ;
  // the example's roughness (0.05 µm) is far below what 1440 points resolve
  // (u(σ_r²) ≈ 0.013 µm²): not significant. Touch σ from 16 points (ν = 13, u ≈ 0.1 µm), with
  // the scans' systematic profile and phase (no --phase-deg needed).
  const fs::path json = scratch_dir() / "noise.json";
  const std::string common = "characterize noise --reference '" + kNoise +
                             "reference_171mm.csv' --scan '" + kNoise + "scan_a.csv' ";
  const CliRun r = run(common + "--scan-repeat '" + kNoise + "scan_b.csv' --touch '" + kNoise +
                       "touch16.csv' -o '" + json.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json out = nlohmann::json::parse(slurp(json));
  const em::DigitalModel loaded = merged_model(out);
  const auto& c = out["characterization"];
  EXPECT_NEAR(loaded.noise.scanning_sigma_mm, 0.7 * kUm,
              3.0 * c["repeat"]["noise_from_difference"]["uncertainty_um"].get<double>() * kUm);
  EXPECT_NEAR(loaded.noise.touch_trigger_sigma_mm, 0.45 * kUm,
              3.0 * c["touch"]["estimate"]["uncertainty_um"].get<double>() * kUm);
  EXPECT_TRUE(c["touch"]["scan_systematics_removed"].get<bool>());
  EXPECT_EQ(c["repeat"]["roughness_status"], "not_significant");
  EXPECT_GE(c["repeat"]["roughness_upper_bound_um"].get<double>(), 0.05);
  EXPECT_LE(loaded.roughness.sigma_mm, c["repeat"]["roughness_upper_bound_um"].get<double>() * kUm);

  // One scan only: no roughness section, and the reason in the diagnostics; with --model the
  // touch σ is taken from the model and the section is complete.
  const CliRun single = run(common + "--model '" + kModel + "' -o '" + json.string() + "'");
  ASSERT_EQ(single.exit_code, 0) << single.err;
  const nlohmann::json s = nlohmann::json::parse(slurp(json));
  EXPECT_FALSE(s.contains("roughness"));
  EXPECT_NE(s["characterization"]["roughness"].get<std::string>().find("single scan"),
            std::string::npos);
  EXPECT_NEAR(merged_model(s).noise.touch_trigger_sigma_mm, 0.45 * kUm, 1e-15);
}

TEST(CliCharacterizeNoise, ExitCodes) {
  const fs::path out = scratch_dir() / "never_noise.json";
  fs::remove(out);
  const std::string ref = "--reference '" + kNoise + "reference_171mm.csv' ";
  // Touch data without a phase: alone, or with a scan that cannot determine it when its
  // systematic profile is not used: exit 4.
  CliRun r = run("characterize noise " + ref + "--touch '" + kNoise + "touch16.csv' -o '" +
                 out.string() + "'");
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_NE(r.err.find("--phase-deg"), std::string::npos) << r.err;
  r = run("characterize noise " + ref + "--scan '" + kNoise + "scan_a.csv' --touch '" + kNoise +
          "touch16.csv' --no-scan-systematics -o '" + out.string() + "'");
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_NE(r.err.find("phase SNR"), std::string::npos) << r.err;
  // Invalid input: a points file (x_mm,y_mm,z_mm) given as the reference, a repeat of another
  // track.
  r = run("characterize noise --reference '" + kNoise + "touch16.csv' --scan '" + kNoise +
          "scan_a.csv' -o '" + out.string() + "'");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("touch16.csv:3: header must be 'angle_deg,deviation_um'"),
            std::string::npos)
      << r.err;
  r = run("characterize noise " + ref + "--scan '" + kNoise + "scan_a.csv' --scan-repeat '" +
          kNoise + "touch16.csv' -o '" + out.string() + "'");
  EXPECT_EQ(r.exit_code, 3);
  // Usage: no data, a repeat without a scan, a bad cut-off.
  EXPECT_EQ(run("characterize noise " + ref + "-o x.json").exit_code, 2);
  EXPECT_EQ(run("characterize noise " + ref + "--scan-repeat a.csv -o x.json").exit_code, 2);
  EXPECT_EQ(run("characterize noise " + ref + "--scan a.csv --cutoff-upr -5 -o x.json").exit_code,
            2);
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
