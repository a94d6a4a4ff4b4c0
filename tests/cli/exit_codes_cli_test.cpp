// The exit-code table of docs/cli.md, one case per row and per subcommand, with the hostile
// inputs of issue 12 ("Silent garbage", "Unclear"): every bad option value exits 2 naming the
// option, every bad file or output path exits 3 naming the file (key, unit, entry) or the path
// and the OS reason, an undefined result exits 4 in every subcommand alike, and no message
// names an internal function.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>

#include "support/cli_run.h"

namespace {

namespace fs = std::filesystem;
using vcmm::test::CliRun;
using vcmm::test::scratch_dir;
using vcmm::test::slurp;

CliRun run(const std::string& args) { return vcmm::test::run_command(VCMM_EXE, args); }

const std::string kModel = std::string(VCMM_SOURCE_DIR) + "/examples/cmm_model.json";
const std::string kScan = std::string(VCMM_SOURCE_DIR) + "/examples/profiles/ring_171mm_scan.csv";

std::string quoted(const fs::path& p) {
  std::string q = "'";  // appended: GCC 12 warns (-Wrestrict) on "'" + string + "'"
  q.append(p.string()).append("'");
  return q;
}

fs::path write_scratch(const std::string& name, const std::string& content) {
  const fs::path p = scratch_dir() / name;
  std::ofstream(p, std::ios::binary) << content;
  return p;
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// A 360-point scanning measurement of the ring (vcmm simulate), made once.
const fs::path& measurement() {
  static const fs::path p = [] {
    const fs::path out = scratch_dir() / "ring360.csv";
    const CliRun r = run("simulate --model '" + kModel +
                         "' --ring 171 --points 360 --location 600,500,250 --seed 3 -o " +
                         quoted(out));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return out;
  }();
  return p;
}

/// The first half of the simulated ring (points 0..179 of 360), as measurement-file text.
std::string half_ring_text() {
  std::istringstream in(slurp(measurement()));
  std::string line, half;
  int data = 0;
  bool header = false;
  while (std::getline(in, line)) {
    if (header && data++ >= 180) break;
    if (line.rfind("x_mm", 0) == 0) header = true;
    half += line + "\n";
  }
  return half;
}

/// The example model with one key replaced by raw JSON text (e.g. "1e300").
fs::path model_with(const std::string& name, const std::string& section, const std::string& key,
                    const std::string& raw) {
  nlohmann::json m = nlohmann::json::parse(slurp(kModel));
  m[section][key] = "@@";
  std::string text = m.dump(1);
  text.replace(text.find("\"@@\""), 4, raw);
  return write_scratch(name, text);
}

std::string simulate_args(const std::string& model, const std::string& extra) {
  return "simulate --model '" + model + "' --ring 171 --points 360 --location 600,500,250 " +
         extra;
}

std::string uncertainty_args(const fs::path& points, const std::string& extra) {
  return "uncertainty --model '" + kModel + "' --points " + quoted(points) +
         " --progress never --trials 200 " + extra;
}

// ---- 2: bad option values, through the shared validators ------------------------------------

TEST(CliExitCodes, BadOptionValuesExit2NamingTheOption) {
  struct Case {
    std::string args, option;
  };
  const fs::path out = scratch_dir() / "never.csv";
  const Case cases[] = {
      {"roundness '" + kScan + "' --filter-upr nan", "--filter-upr"},
      {"roundness '" + kScan + "' --filter-upr NONE --threads 5000", "--threads"},
      {"roundness '" + kScan + "' --threads -1", "--threads"},
      {uncertainty_args(measurement(), "--threads 5000"), "--threads"},
      {"uncertainty --model '" + kModel + "' --points " + quoted(measurement()) +
           " --adaptive nan",
       "--adaptive"},
      {uncertainty_args(measurement(), "--coverage nan"), "--coverage"},
      {uncertainty_args(measurement(), "--coverage 1e-20"), "--coverage"},
      {uncertainty_args(measurement(), "--temperature 293.15"), "--temperature"},
      {uncertainty_args(measurement(), "--trial spectral --filter-upr none"), "--trial spectral"},
      {simulate_args(kModel, "--ring nan -o " + quoted(out)), "--ring"},
      {simulate_args(kModel, "--temperature -300 -o " + quoted(out)), "--temperature"},
      {simulate_args(kModel, "--temperature 293.15 -o " + quoted(out)), "--temperature"},
      {simulate_args(kModel, "--orientation inf -o " + quoted(out)), "--orientation"},
      {simulate_args(kModel, "--stylus-offset 0,0,1e300 -o " + quoted(out)), "--stylus-offset"},
      {"validate x.json -o " + quoted(scratch_dir() / "v") + " --threads 5000", "--threads"},
  };
  for (const Case& c : cases) {
    const CliRun r = run(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_TRUE(has(r.err, c.option)) << c.args << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(out));
}

TEST(CliExitCodes, TrialsBelowTheJcgm101MinimumExit2) {
  const CliRun r = run("uncertainty --model '" + kModel + "' --points " + quoted(measurement()) +
                       " --progress never --trials 10");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(has(r.err, "--trials must be >= ")) << r.err;
  EXPECT_TRUE(has(r.err, "JCGM 101")) << r.err;
  EXPECT_FALSE(has(r.err, "run_monte_carlo")) << r.err;
}

TEST(CliExitCodes, TemperatureMessagesSayKelvinAndAbsoluteZero) {
  const fs::path out = scratch_dir() / "never.csv";
  const CliRun k = run(simulate_args(kModel, "--temperature 293.15 -o " + quoted(out)));
  EXPECT_TRUE(has(k.err, "kelvin given? 293.15 K = 20 °C")) << k.err;
  const CliRun z = run(simulate_args(kModel, "--temperature -300 -o " + quoted(out)));
  EXPECT_TRUE(has(z.err, "below absolute zero")) << z.err;
}

// ---- 3: bad input files, named with key and unit ---------------------------------------------

TEST(CliExitCodes, ModelValuesOutsideTheirPhysicalRangeExit3WithKeyAndUnit) {
  struct Case {
    fs::path model;
    std::string key, unit;
  };
  const Case cases[] = {
      {model_with("noise_1e300.json", "noise", "scanning_sigma_um", "1e300"),
       "noise.scanning_sigma_um", "µm"},
      {model_with("rough_1e300.json", "roughness", "sigma_um", "1e300"), "roughness.sigma_um",
       "µm"},
  };
  for (const Case& c : cases) {
    const fs::path out = scratch_dir() / "garbage.csv";
    const CliRun r = run(simulate_args(c.model.string(), "-o " + quoted(out)));
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_TRUE(has(r.err, c.model.string() + ": " + c.key + ": must lie in")) << r.err;
    EXPECT_TRUE(has(r.err, c.unit)) << r.err;
    EXPECT_FALSE(fs::exists(out));  // on main: points at 1e296 mm, exit 0
  }
  // α of 1e300 is blamed on α, not on an axis range.
  nlohmann::json m = nlohmann::json::parse(slurp(kModel));
  m["temperature"]["expansion_coefficient"]["value_per_K"] = 1e300;
  const fs::path alpha = write_scratch("alpha_1e300.json", m.dump(1));
  const CliRun a = run(simulate_args(alpha.string(), "-o " + quoted(scratch_dir() / "a.csv")));
  EXPECT_EQ(a.exit_code, 3) << a.err;
  EXPECT_TRUE(has(a.err, "temperature.expansion_coefficient.value_per_K: must lie in")) << a.err;
  EXPECT_FALSE(has(a.err, "axis range")) << a.err;
  // A tip error of 1e300 µm likewise.
  m = nlohmann::json::parse(slurp(kModel));
  m["probe"]["tip_radius_error"]["uncertainty_um"] = 1e300;
  const fs::path tip = write_scratch("tip_1e300.json", m.dump(1));
  const CliRun t = run(simulate_args(tip.string(), "-o " + quoted(scratch_dir() / "t.csv")));
  EXPECT_EQ(t.exit_code, 3) << t.err;
  EXPECT_TRUE(has(t.err, "probe.tip_radius_error.uncertainty_um: must lie in [0, 1000] µm"))
      << t.err;
}

TEST(CliExitCodes, ModelNumberBeyondTheDoubleRangeExit3NamingTheFile) {
  const fs::path model = model_with("m_1e999.json", "noise", "touch_trigger_sigma_um", "1e999");
  const CliRun r = run(simulate_args(model.string(), "-o " + quoted(scratch_dir() / "x.csv")));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_TRUE(has(r.err, model.string())) << r.err;
  EXPECT_FALSE(has(r.err, "json.exception")) << r.err;
}

TEST(CliExitCodes, KelvinInAMeasurementCsvExit3NamingFileKeyAndUnit) {
  std::string text = slurp(measurement());
  const std::string key = "# temperature_C: ";
  const auto at = text.find(key);
  ASSERT_NE(at, std::string::npos);
  text.replace(at + key.size(), text.find('\n', at) - at - key.size(), "293.15");
  const fs::path kelvin = write_scratch("kelvin.csv", text);
  const CliRun r = run(uncertainty_args(kelvin, ""));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_TRUE(has(r.err, kelvin.string() + ":4: temperature_C must lie in [-50, 100] °C"))
      << r.err;
  EXPECT_TRUE(has(r.err, "kelvin given?")) << r.err;
}

TEST(CliExitCodes, NumberReadingMessagesSayWhatIsWrong) {
  // 1e-400 underflows: it is finite as written.
  const fs::path under = write_scratch("under.csv", "1,0\n0,1\n-1,1e-400\n0,-1\n");
  const CliRun u = run("roundness " + quoted(under));
  EXPECT_EQ(u.exit_code, 3) << u.err;
  EXPECT_TRUE(has(u.err, "under.csv:3: field 2 underflows")) << u.err;
  EXPECT_FALSE(has(u.err, "not finite")) << u.err;
  // A CR-only file (classic Mac line ends) is read, not called empty.
  std::ostringstream cr;
  for (int i = 0; i < 36; ++i)
    cr << 85.5 * std::cos(i * std::numbers::pi / 18) << "," << 85.5 * std::sin(i * std::numbers::pi / 18) << "\r";
  const fs::path crfile = write_scratch("cr_only.csv", cr.str());
  const CliRun c = run("roundness " + quoted(crfile) + " --json");
  EXPECT_EQ(c.exit_code, 0) << c.err;
  EXPECT_TRUE(has(c.out, "\"n_points\": 36")) << c.out;
  // A circle of radius 1e70 mm is outside what the LS fit handles, and says so.
  std::ostringstream big;
  big.precision(17);
  for (int i = 0; i < 100; ++i)
    big << 1e70 * std::cos(i * std::numbers::pi / 50) << "," << 1e70 * std::sin(i * std::numbers::pi / 50) << "\n";
  const fs::path bigfile = write_scratch("big.csv", big.str());
  const CliRun b = run("roundness " + quoted(bigfile));
  EXPECT_EQ(b.exit_code, 3) << b.err;
  EXPECT_TRUE(has(b.err, "the points span 2e+70 mm")) << b.err;
  EXPECT_FALSE(has(b.err, "straight line")) << b.err;
}

// ---- 3: output paths that cannot be written ----------------------------------------------------

TEST(CliExitCodes, UnwritableOutputsExit3WithPathAndReason) {
  const fs::path file = write_scratch("a_plain_file", "x");
  const fs::path missing = scratch_dir() / "no_such_dir" / "r.json";
  const CliRun r = run("roundness '" + kScan + "' --json -o " + quoted(missing));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_TRUE(has(r.err, missing.string())) << r.err;
  const fs::path under_file = file / "ring.csv";
  const CliRun s = run(simulate_args(kModel, "-o " + quoted(under_file)));
  EXPECT_EQ(s.exit_code, 3) << s.err;
  EXPECT_TRUE(has(s.err, under_file.string())) << s.err;
  // validate -o under a path that is a file.
  const fs::path campaign = write_scratch(
      "ok_campaign.json",
      R"({"schema": "vcmm.campaign", "schema_version": 1, "model": ")" + kModel +
          R"(", "measurements": [{"id": "m1", "points": ")" + measurement().string() +
          R"(", "setup": {"location": "C", "orientation_deg": 0, "height": "middle",
          "mode": "scanning"}, "reference": {"roundness": {"value_um": 0.2, "u_um": 0.01}}}]})");
  const fs::path outdir = file / "results";
  const CliRun v = run("validate " + quoted(campaign) + " --progress never -o " + quoted(outdir));
  EXPECT_EQ(v.exit_code, 3) << v.err;
  EXPECT_TRUE(has(v.err, outdir.string())) << v.err;
  EXPECT_TRUE(has(v.err, "Not a directory")) << v.err;  // the operating system's reason
  EXPECT_FALSE(has(v.err, "internal error")) << v.err;
}

// ---- 4: the result does not exist, in every subcommand alike -------------------------------------

// A directory or a missing path where a file is expected: exit 3 naming the path, what the
// file was meant to be and why. (A std::ifstream opens a directory on Linux: before, the
// reader said "basic_filebuf::underflow error reading the file" without a path, or called the
// directory "not valid JSON".) A directory of profiles without any *.csv: exit 3, not an empty
// table with exit 0.
TEST(CliExitCodes, DirectoriesAndMissingFilesAreNamedAsSuch) {
  const fs::path dir = scratch_dir() / "a_directory";
  fs::create_directories(dir / "sub");
  const std::string d = quoted(dir);
  struct Case {
    std::string args, what;
  };
  const Case cases[] = {
      {"uncertainty --model '" + kModel + "' --points " + d, "measurement file"},
      {"uncertainty --model " + d + " --points " + quoted(measurement()), "digital-model file"},
      {"validate " + d + " -o " + quoted(scratch_dir() / "dir_out"), "campaign file"},
      {"demo --model " + d + " -o " + quoted(scratch_dir() / "dir_out2"), "digital-model file"},
      {"simulate --model " + d + " --ring 171 --points 36 --location 600,500,250 -o " + quoted(scratch_dir() / "x.csv"),
       "digital-model file"},
      {"characterize sphere --points " + d + " --diameter-mm 25 --u-diameter-um 0.1 -o " +
           quoted(scratch_dir() / "p.json"),
       "points file"},
  };
  for (const Case& c : cases) {
    const CliRun r = run(c.args);
    EXPECT_EQ(r.exit_code, 3) << c.args << "\n" << r.err;
    EXPECT_TRUE(has(r.err, dir.string() + ": cannot read the " + c.what +
                               ": it is a directory, not a file"))
        << c.args << "\n" << r.err;
  }
  const CliRun missing = run("roundness " + quoted(scratch_dir() / "no_such_profile.csv"));
  EXPECT_EQ(missing.exit_code, 3);
  EXPECT_TRUE(has(missing.err, "no_such_profile.csv: cannot read the points file: no such file"))
      << missing.err;
  const CliRun empty = run("roundness " + d);
  EXPECT_EQ(empty.exit_code, 3) << empty.out;
  EXPECT_TRUE(has(empty.err, dir.string() + ": the directory holds no profile (*.csv) files"))
      << empty.err;
  EXPECT_TRUE(empty.out.empty()) << empty.out;
}

TEST(CliExitCodes, MiOfAHalfRingExits4InRoundnessAndUncertainty) {
  const std::string half = half_ring_text();
  const fs::path file = write_scratch("half_ring.csv", half);
  const CliRun u = run(uncertainty_args(file, "--reference MI --filter-upr none"));
  EXPECT_EQ(u.exit_code, 4) << u.err;  // main: 1 ("internal error")
  EXPECT_TRUE(has(u.err, "MI circle: ")) << u.err;
  EXPECT_FALSE(has(u.err, "maximum_inscribed_circle")) << u.err;
  // The same points as a plain profile: roundness says the same.
  std::ostringstream xy;
  std::istringstream again(half);
  std::string line;
  bool header = false;
  while (std::getline(again, line)) {
    if (header) xy << line.substr(0, line.find(',', line.find(',') + 1)) << "\n";
    if (line.rfind("x_mm", 0) == 0) header = true;
  }
  const fs::path plain = write_scratch("half_ring_xy.csv", xy.str());
  const CliRun r = run("roundness " + quoted(plain) + " --reference mi");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_FALSE(has(r.out, "maximum_inscribed_circle")) << r.out;
  EXPECT_TRUE(has(r.out, "partial arc")) << r.out;  // main: "coverage 0.00° … closed profile"
}

// ---- messages: no internal function names; campaign entries named ---------------------------

TEST(CliExitCodes, MessagesNameOperationsNotFunctions) {
  // A half ring under the default 50 UPR filter: the filter refuses an open profile.
  const fs::path file = write_scratch("half_ring_f.csv", half_ring_text());
  const CliRun r = run(uncertainty_args(file, "--filter-upr 50"));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_TRUE(has(r.err, "Gaussian filter (ISO 16610-21): ")) << r.err;
  EXPECT_FALSE(has(r.err, "gaussian_filtered_profile")) << r.err;
}

TEST(CliExitCodes, CampaignEntryTooSparseForTheFilterIsNamed) {
  const fs::path touch = scratch_dir() / "touch16.csv";
  ASSERT_EQ(run("simulate --model '" + kModel + "' --ring 171 --mode touch --location " +
                "600,500,250 -o " + quoted(touch))
                .exit_code,
            0);
  const fs::path campaign = write_scratch(
      "touch_campaign.json",
      R"({"schema": "vcmm.campaign", "schema_version": 1, "model": ")" + kModel +
          R"(", "evaluation": {"trials": 200, "filter_cutoff_upr": 50},
          "measurements": [{"id": "T16-touch", "points": ")" + touch.string() +
          R"(", "setup": {"location": "C", "orientation_deg": 0, "height": "middle",
          "mode": "touch_trigger"}, "reference": {"roundness": {"value_um": 0.2, "u_um": 0.01}}}]})");
  const CliRun v = run("validate " + quoted(campaign) + " --progress never -o " +
                       quoted(scratch_dir() / "touch_out"));
  EXPECT_EQ(v.exit_code, 3) << v.err;
  EXPECT_TRUE(has(v.err, campaign.string() + ": measurements[0] (\"T16-touch\"): ")) << v.err;
  EXPECT_TRUE(has(v.err, "Gaussian filter")) << v.err;
  EXPECT_FALSE(has(v.err, "gaussian_filtered_profile")) << v.err;
}

TEST(CliExitCodes, HelpStatesTheExitCodeTable) {
  const CliRun r = run("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* part : {"Exit codes", "2 bad", "3 invalid input", "4 result undefined",
                           "130 interrupted"})
    EXPECT_TRUE(has(r.out, part)) << part << "\n" << r.out;
}

}  // namespace
