// The `vcmm simulate` contract (docs/cli.md, docs/errormodel.md): a readable measurement CSV,
// reproducible with a seed, --only keeps one source, exit 2 for bad options, exit 3 for a bad
// model file (message naming the key path), nothing written on error.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/cli_run.h"
#include "vcmm/errormodel/measurement.h"

namespace {

namespace fs = std::filesystem;
using vcmm::errormodel::Measurement;
using vcmm::errormodel::ProbingMode;

using vcmm::test::CliRun;
using vcmm::test::scratch_dir;
using vcmm::test::slurp;

CliRun run(const std::string& args) { return vcmm::test::run_command(VCMM_EXE, args); }

const std::string kModel = std::string(VCMM_SOURCE_DIR) + "/examples/cmm_model.json";

std::string base(const fs::path& out) {
  return "simulate --model '" + kModel + "' --ring 171 --location 600,500,250 -o '" +
         out.string() + "'";
}

TEST(CliSimulate, WritesAReadableMeasurementWithProvenance) {
  const fs::path out = scratch_dir() / "scan.csv";
  const CliRun r = run(base(out) + " --seed 7 --orientation 30 --height 5 --temperature 20.5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Measurement m = vcmm::errormodel::read_measurement_csv_file(out.string());
  EXPECT_EQ(m.size(), 3600);
  EXPECT_EQ(m.mode, ProbingMode::scanning);
  EXPECT_EQ(m.temperature_c, 20.5);
  EXPECT_EQ(m.placement.location_mm, Eigen::Vector3d(600, 500, 250));
  EXPECT_NEAR(m.placement.orientation_rad, 30.0 * 3.141592653589793 / 180.0, 1e-15);
  EXPECT_NEAR(m.points_mm(2, 0), 5.0, 1e-2);  // the height, plus µm-level errors
  const std::string text = slurp(out);
  EXPECT_NE(text.find("--seed 7"), std::string::npos);
  EXPECT_NE(text.find("sources roughness,temperature,kinematic,probe,noise"), std::string::npos);
  // Simulated radii: 85.5 mm within a few µm.
  const Eigen::ArrayXd r2 = m.points_mm.topRows<2>().colwise().norm().transpose().array();
  EXPECT_LT((r2 - 85.5).abs().maxCoeff(), 0.01);
}

// What `simulate` writes, `roundness` reads (its header names the x, y, z columns among the
// normals): the LS radius is the simulated ring's, within the µm-level errors.
TEST(CliSimulate, RoundnessReadsTheMeasurementItWrites) {
  const fs::path out = scratch_dir() / "scan_for_roundness.csv";
  ASSERT_EQ(run(base(out) + " --seed 5 --points 720").exit_code, 0);
  const CliRun r = run("roundness --reference LS --json '" + out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"n_points\": 720"), std::string::npos) << r.out;
  const std::size_t at = r.out.find("\"radius\": ");
  ASSERT_NE(at, std::string::npos) << r.out;
  EXPECT_NEAR(std::stod(r.out.substr(at + 10)), 85.5, 0.01);
}

TEST(CliSimulate, SameSeedSameFileDifferentSeedDifferent) {
  const fs::path a = scratch_dir() / "a.csv", b = scratch_dir() / "b.csv",
                 c = scratch_dir() / "c.csv";
  ASSERT_EQ(run(base(a) + " --seed 11 --mode touch").exit_code, 0);
  ASSERT_EQ(run(base(b) + " --seed 11 --mode touch").exit_code, 0);
  ASSERT_EQ(run(base(c) + " --seed 12 --mode touch").exit_code, 0);
  EXPECT_EQ(slurp(a), slurp(b));
  EXPECT_NE(slurp(a), slurp(c));
  EXPECT_EQ(vcmm::errormodel::read_measurement_csv_file(a.string()).size(), 16);
}

TEST(CliSimulate, OnlyOneSourceOnAPerfectRing) {
  // Temperature alone scales a perfect ring: every radius equal (no form, no noise).
  const fs::path out = scratch_dir() / "temp.csv";
  const CliRun r =
      run(base(out) + " --only temperature --no-form --temperature 25 --points 360 --seed 3");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Measurement m = vcmm::errormodel::read_measurement_csv_file(out.string());
  const Eigen::ArrayXd radius = m.points_mm.topRows<2>().colwise().norm().transpose().array();
  EXPECT_LT(radius.maxCoeff() - radius.minCoeff(), 1e-12);
  // α(T − 20)·R with α ~ N(11.5e-6, 1e-6²), T ~ N(25, 0.1²): σ = R·√((5e-6)² + (1.15e-6)²)
  // = 0.44 µm; 5σ (one fixed draw).
  EXPECT_NEAR(radius.mean() - 85.5, 11.5e-6 * 5.0 * 85.5, 5.0 * 0.44e-3);
  EXPECT_NE(slurp(out).find("sources temperature,"), std::string::npos);
  // Two sources.
  const fs::path two = scratch_dir() / "two.csv";
  ASSERT_EQ(run(base(two) + " --only noise --only probe").exit_code, 0);
  EXPECT_NE(slurp(two).find("sources probe,noise,"), std::string::npos);
}

TEST(CliSimulate, BadOptionsExitWithTwoAndWriteNothing) {
  const fs::path out = scratch_dir() / "never.csv";
  const std::string m = "simulate --model '" + kModel + "' ";
  const std::string o = " -o '" + out.string() + "'";
  EXPECT_EQ(run(m + "--ring 171" + o).exit_code, 2);  // --location missing
  EXPECT_EQ(run(m + "--ring 171 --location 1,2" + o).exit_code, 2);
  EXPECT_EQ(run(m + "--ring 171 --location 1,2,x" + o).exit_code, 2);
  EXPECT_EQ(run(m + "--ring -171 --location 600,500,250" + o).exit_code, 2);
  EXPECT_EQ(run(m + "--ring 171 --location 600,500,250 --mode sideways" + o).exit_code, 2);
  EXPECT_EQ(run(m + "--ring 171 --location 600,500,250 --only thermal" + o).exit_code, 2);
  EXPECT_EQ(run(m + "--ring 171 --location 600,500,250 --points 2" + o).exit_code, 2);
  EXPECT_EQ(run(m + "--ring 171 --location 600,500,250").exit_code, 2);  // no -o
  EXPECT_EQ(run(m + "--ring 171 --location 600,500,250 --temperature nan" + o).exit_code, 2);
  const CliRun r = run(m + "--ring 171 --location 600,500,250 --stylus-offset 0,0" + o);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--stylus-offset"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(CliSimulate, BadModelFileExitsWithThreeNamingTheKeyPath) {
  std::string model = slurp(kModel);
  model.replace(model.find("\"scanning_sigma_um\": 0.7"), 24, "\"scanning_sigma_um\": -0.7");
  const fs::path bad = scratch_dir() / "bad_model.json";
  std::ofstream(bad) << model;
  const fs::path out = scratch_dir() / "never2.csv";
  const std::string rest = " --ring 171 --location 600,500,250 -o '" + out.string() + "'";
  CliRun r = run("simulate --model '" + bad.string() + "'" + rest);
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("noise.scanning_sigma_um"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("-0.7"), std::string::npos) << r.err;
  r = run("simulate --model /nonexistent/model.json" + rest);
  EXPECT_EQ(r.exit_code, 3);
  // A ring that does not fit in the machine's travel is invalid input too.
  r = run("simulate --model '" + kModel + "' --ring 171 --location 20,500,250 -o '" +
          out.string() + "'");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("outside the axis range"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
