// `vcmm characterize hole-plate|sphere|noise` refuse calibration blunders before anything is
// written (docs/characterization.md, "Consistency of a calibration"; docs/cli.md): a wrong
// '# setup:' label, a blunder in one hole centre (named), one file given twice (also through
// another path), one scan given as --scan and --scan-repeat, values of 1e300 in options (exit 2,
// option and unit named) and files (exit 3, file and line named); the bundled examples pass and
// report χ²/ν, the Birge ratio and p; --accept-inconsistent writes and records the verdict.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/cli_run.h"

namespace {

namespace fs = std::filesystem;
using vcmm::test::CliRun;
using vcmm::test::scratch_dir;
using vcmm::test::slurp;

const std::string kExe = VCMM_EXE;
const std::string kSource = VCMM_SOURCE_DIR;
const std::string kModel = kSource + "/examples/cmm_model.json";
const std::string kPlateDir = kSource + "/examples/characterization/hole_plate/";
const std::string kSphere = kSource + "/examples/characterization/sphere/";
const std::string kNoise = kSource + "/examples/characterization/noise/";
const std::vector<std::string> kPlacements = {
    "xy_low_t1.csv", "xy_low_t2.csv", "xy_low_t3.csv", "xy_high_t1.csv", "xz_t1.csv",
    "xz_t2.csv",     "xz_t3.csv",     "yz_t1.csv",     "yz_t2.csv",      "yz_t3.csv"};

CliRun run(const std::string& args) { return vcmm::test::run_command(kExe, args); }
std::string q(const fs::path& p) {
  std::string s = "'";  // appends: GCC 12 warns falsely (-Wrestrict) on "literal" + string
  s += p.string();
  s += '\'';
  return s;
}

fs::path fresh(const char* name) {
  const fs::path p = scratch_dir() / name;
  fs::remove(p);
  return p;
}

fs::path write(const char* name, const std::string& text) {
  const fs::path p = scratch_dir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

/// The example's placements with `replace[i]` in place of placement i, + the model and σ.
std::string hole_plate_args(const std::vector<std::pair<std::size_t, fs::path>>& replace = {}) {
  std::string a = "characterize hole-plate --plate " + q(kPlateDir + "plate.csv");
  for (std::size_t i = 0; i < kPlacements.size(); ++i) {
    fs::path p = kPlateDir + kPlacements[i];
    for (const auto& [j, r] : replace)
      if (j == i) p = r;
    a += " --placement " + q(p);
  }
  return a + " --model " + q(kModel) + " --probing-sigma-um 0.2";
}

/// `text` with field `field` (0-based) of the data line starting "id," changed by `delta`.
std::string shifted(std::string text, const std::string& id, int field, double delta) {
  std::string key = "\n";  // appends: GCC 12 warns falsely (-Wrestrict) on "literal" + string
  key += id;
  key += ',';
  const auto at = text.find(key);
  EXPECT_NE(at, std::string::npos);
  std::size_t start = at + 1;
  for (int f = 0; f < field; ++f) start = text.find(',', start) + 1;
  const auto end = text.find_first_of(",\n", start);
  const double v = std::stod(text.substr(start, end - start)) + delta;
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  text.replace(start, end - start, buf);
  return text;
}

// ---- hole plate --------------------------------------------------------------------------

TEST(CliCharacterizeConsistency, HolePlateExamplePassesAndReportsChiSquared) {
  const fs::path out = fresh("cc_kin.json"), rep = fresh("cc_rep.json");
  const CliRun r = run(hole_plate_args() + " -o " + q(out) + " --json " + q(rep));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto c = nlohmann::json::parse(slurp(rep))["consistency"];
  std::printf("[ info ] hole-plate example: chi2/nu %.4f, Birge ratio %.4f, p %.3f, nu %g, "
              "largest normalized residual %.2f (limit %.2f)\n",
              c["chi_squared_per_dof"].get<double>(), c["birge_ratio"].get<double>(),
              c["p_value"].get<double>(), c["degrees_of_freedom"].get<double>(),
              c["largest_normalized_residual"].get<double>(), c["outlier_threshold"].get<double>());
  EXPECT_TRUE(c["passed"].get<bool>());
  EXPECT_GE(c["p_value"].get<double>(), 0.005);
  EXPECT_NE(r.out.find("Birge ratio"), std::string::npos) << r.out;
}

TEST(CliCharacterizeConsistency, HolePlateWrongSetupLabelIsRefused) {
  const fs::path out = fresh("cc_never.json");
  std::string text = slurp(kPlateDir + "xz_t2.csv");
  const auto at = text.find("# setup: xz");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 11, "# setup: yz");
  const fs::path bad = write("cc_xz_t2_labelled_yz.csv", text);
  const CliRun r = run(hole_plate_args({{5, bad}}) + " -o " + q(out));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find(bad.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("setup"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(CliCharacterizeConsistency, HolePlateBlunderInOneHoleIsNamed) {
  const fs::path out = fresh("cc_never.json"), rep = fresh("cc_never_rep.json");
  const std::string text = slurp(kPlateDir + "xy_low_t2.csv");
  // 10 mm in x of hole R2C3: refused before the fit, the file, line and hole named.
  const fs::path ten = write("cc_blunder_10mm.csv", shifted(text, "R2C3", 1, 10.0));
  CliRun r = run(hole_plate_args({{1, ten}}) + " -o " + q(out) + " --json " + q(rep));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find(ten.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("hole R2C3"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(rep));
  // 20 µm (100 σ) in y: refused by the outlier test, the culprit named first.
  const fs::path small = write("cc_blunder_20um.csv", shifted(text, "R2C3", 2, 0.02));
  r = run(hole_plate_args({{1, small}}) + " -o " + q(out) + " --json " + q(rep));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("OUTLIER"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(small.string() + ": line "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("hole R2C3, y"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(rep));
  // --accept-inconsistent writes both, with the verdict recorded in each.
  r = run(hole_plate_args({{1, small}}) + " -o " + q(out) + " --json " + q(rep) +
          " --accept-inconsistent");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: accepted although inconsistent"), std::string::npos) << r.err;
  EXPECT_NE(slurp(out).find("ACCEPTED ALTHOUGH INCONSISTENT"), std::string::npos);
  const auto c = nlohmann::json::parse(slurp(rep))["consistency"];
  EXPECT_FALSE(c["passed"].get<bool>());
  EXPECT_TRUE(c["accepted_although_inconsistent"].get<bool>());
  EXPECT_EQ(c["outliers"][0]["at"].get<std::string>().find(small.string()), 0u);
}

TEST(CliCharacterizeConsistency, HolePlateSameFileTwiceIsRefusedNamingBoth) {
  const fs::path out = fresh("cc_never.json");
  const std::string t1 = kPlateDir + "xy_low_t1.csv";
  // The same path twice.
  CliRun r = run(hole_plate_args({{1, t1}}) + " -o " + q(out));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("--placement " + t1 + " and --placement " + t1), std::string::npos) << r.err;
  // A byte-identical copy under another name.
  const fs::path copy = write("cc_copy_of_t1.csv", slurp(t1));
  r = run(hole_plate_args({{1, copy}}) + " -o " + q(out));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find(t1), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(copy.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("identical"), std::string::npos) << r.err;
  // The same path through "dir/../dir".
  const std::string dotted = kPlateDir + "../hole_plate/xy_low_t1.csv";
  r = run(hole_plate_args({{1, dotted}}) + " -o " + q(out));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find(dotted), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(CliCharacterizeConsistency, HolePlateOptionsOutOfRangeExit2) {
  const fs::path out = fresh("cc_never.json");
  for (const char* opt : {"--probing-sigma-um 1e300", "--prior-um 1e300", "--prior-urad 1e300"}) {
    const CliRun r = run(hole_plate_args() + " " + opt + " -o " + q(out));
    EXPECT_EQ(r.exit_code, 2) << opt << ": " << r.err;
    const std::string name = std::string(opt).substr(0, std::string(opt).find(' '));
    EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(out));
}

// ---- sphere ------------------------------------------------------------------------------

std::string sphere_args(const std::string& points) {
  return "characterize sphere --points " + q(points) +
         " --diameter-mm 25.0004 --u-diameter-um 0.05 --form-um 0.03";
}

TEST(CliCharacterizeConsistency, SphereExamplesPassWithTheStatedNoise) {
  for (const char* file : {"sphere_dense.csv", "sphere_iso25.csv"}) {
    const fs::path out = fresh("cc_probe.json");
    const CliRun r = run(sphere_args(kSphere + file) + " --probing-sigma-um 0.1 -o " + q(out));
    ASSERT_EQ(r.exit_code, 0) << file << ": " << r.err;
    const auto c = nlohmann::json::parse(slurp(out))["characterization"]["consistency"];
    std::printf("[ info ] sphere example %s: chi2/nu %.4f, Birge ratio %.4f, p %.3f, nu %g, "
                "largest normalized residual %.2f (limit %.2f)\n",
                file, c["chi_squared_per_dof"].get<double>(), c["birge_ratio"].get<double>(),
                c["p_value"].get<double>(), c["degrees_of_freedom"].get<double>(),
                c["largest_normalized_residual"].get<double>(), c["outlier_threshold"].get<double>());
    EXPECT_TRUE(c["passed"].get<bool>());
  }
}

TEST(CliCharacterizeConsistency, SphereOutlierAndHugeValuesAreRefused) {
  const fs::path out = fresh("cc_never.json");
  // 1e300 in an option: exit 2 naming the option and its unit.
  for (const char* opt : {"--u-diameter-um 1e300", "--form-um 1e300", "--probing-sigma-um 1e300"}) {
    std::string args = "characterize sphere --points " + q(kSphere + "sphere_dense.csv") +
                       " --diameter-mm 25.0004 " + opt;
    if (!std::string(opt).starts_with("--u-diameter")) args += " --u-diameter-um 0.05";
    const CliRun r = run(args + " -o " + q(out));
    EXPECT_EQ(r.exit_code, 2) << opt << ": " << r.err;
    const std::string name = std::string(opt).substr(0, std::string(opt).find(' '));
    EXPECT_NE(r.err.find(name + " must be"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(" um"), std::string::npos) << r.err;
  }
  CliRun r = run("characterize sphere --points " + q(kSphere + "sphere_dense.csv") +
                 " --diameter-mm 1e300 --u-diameter-um 0.05 -o " + q(out));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--diameter-mm"), std::string::npos) << r.err;
  // 3 µm of dirt under one point: exit 3 naming it, with or without a stated σ.
  std::string text = slurp(kSphere + "sphere_dense.csv");
  std::size_t line_start = 0;
  int data_line = 0;
  for (std::size_t i = 0; i < text.size() && data_line < 40; ++i)
    if (text[i] == '\n' && i + 1 < text.size() && text[i + 1] != '#' && text[i + 1] != 'x') {
      ++data_line;
      line_start = i + 1;
    }
  const auto end = text.find('\n', line_start);
  std::string row = text.substr(line_start, end - line_start);
  // Move the point 3 µm outward along z (the points of the 40th line are near the 60° circle).
  const auto c2 = row.rfind(',');
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.10f", std::stod(row.substr(c2 + 1)) + 0.003);
  row = row.substr(0, c2 + 1) + buf;
  text.replace(line_start, end - line_start, row);
  const fs::path dirty = write("cc_sphere_dirty.csv", text);
  for (const char* sigma : {" --probing-sigma-um 0.1", ""}) {
    r = run(sphere_args(dirty.string()) + sigma + " -o " + q(out));
    EXPECT_EQ(r.exit_code, 3) << sigma << ": " << r.err;
    EXPECT_NE(r.err.find("OUTLIER"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(dirty.string()), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
}

// ---- noise -------------------------------------------------------------------------------

TEST(CliCharacterizeConsistency, NoiseSameScanTwiceIsRefusedNamingBoth) {
  const fs::path out = fresh("cc_never.json");
  const std::string ref = kNoise + "reference_171mm.csv", scan = kNoise + "scan_a.csv";
  CliRun r = run("characterize noise --reference " + q(ref) + " --scan " + q(scan) +
                 " --scan-repeat " + q(scan) + " -o " + q(out));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("--scan " + scan + " and --scan-repeat " + scan), std::string::npos) << r.err;
  const fs::path copy = write("cc_scan_copy.csv", slurp(scan));
  r = run("characterize noise --reference " + q(ref) + " --scan " + q(scan) + " --scan-repeat " +
          q(copy) + " -o " + q(out));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find(copy.string()), std::string::npos) << r.err;
  // The same points with another header comment: refused by the library (point for point).
  std::string edited_text = "# copied\n";
  edited_text += slurp(scan);
  const fs::path edited = write("cc_scan_edited.csv", edited_text);
  r = run("characterize noise --reference " + q(ref) + " --scan " + q(scan) + " --scan-repeat " +
          q(edited) + " -o " + q(out));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("identical"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(CliCharacterizeConsistency, NoiseHugeReferenceDeviationIsRefusedNamingTheLine) {
  const fs::path out = fresh("cc_never.json");
  std::string ref = slurp(kNoise + "reference_171mm.csv");
  const auto at = ref.find("\n1.0,");
  ASSERT_NE(at, std::string::npos);
  const auto end = ref.find('\n', at + 1);
  ref.replace(at + 1, end - at - 1, "1.0,1e300");
  const fs::path bad = write("cc_ref_1e300.csv", ref);
  const CliRun r = run("characterize noise --reference " + q(bad) + " --scan " +
                       q(kNoise + "scan_a.csv") + " -o " + q(out));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find(bad.string() + ":6"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("um"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(CliCharacterizeConsistency, NoiseSpikeInAScanIsNamed) {
  const fs::path out = fresh("cc_noise.json");
  // Point 101 of scan_a.csv moved 10 µm outward (about 14 σ) from the ring's centre.
  std::string text = slurp(kNoise + "scan_a.csv");
  std::vector<std::string> lines;
  for (std::size_t a = 0, b; a < text.size(); a = b + 1) {
    b = text.find('\n', a);
    if (b == std::string::npos) b = text.size();
    lines.push_back(text.substr(a, b - a));
  }
  std::size_t first = 0;
  while (lines[first].empty() || lines[first][0] == '#' || lines[first][0] == 'x') ++first;
  double cx = 0.0, cy = 0.0;
  std::size_t n = 0;
  for (std::size_t i = first; i < lines.size(); ++i) {
    if (lines[i].empty()) continue;
    cx += std::stod(lines[i]);
    cy += std::stod(lines[i].substr(lines[i].find(',') + 1));
    ++n;
  }
  cx /= static_cast<double>(n);
  cy /= static_cast<double>(n);
  std::string& row = lines[first + 100];
  const auto c1 = row.find(','), c2 = row.find(',', c1 + 1);
  const double x = std::stod(row), y = std::stod(row.substr(c1 + 1));
  const double r = std::hypot(x - cx, y - cy), k = (r + 0.01) / r;
  char buf[80];
  std::snprintf(buf, sizeof buf, "%.7f,%.7f", cx + (x - cx) * k, cy + (y - cy) * k);
  row = buf + row.substr(c2);
  std::string joined;
  for (const std::string& l : lines) {
    joined += l;
    joined += '\n';
  }
  const fs::path dirty = write("cc_scan_dirty.csv", joined);
  const std::string args = "characterize noise --reference " + q(kNoise + "reference_171mm.csv") +
                           " --scan " + q(dirty) + " --scan-repeat " + q(kNoise + "scan_b.csv");
  CliRun run1 = run(args + " -o " + q(out));
  EXPECT_EQ(run1.exit_code, 3) << run1.err;
  EXPECT_NE(run1.err.find("--scan " + dirty.string() + ": "), std::string::npos) << run1.err;
  EXPECT_NE(run1.err.find("point 101 ("), std::string::npos) << run1.err;
  EXPECT_FALSE(fs::exists(out));
  run1 = run(args + " --accept-inconsistent -o " + q(out));
  ASSERT_EQ(run1.exit_code, 0) << run1.err;
  const auto d = nlohmann::json::parse(slurp(out))["characterization"];
  EXPECT_FALSE(d["scan"]["consistency"]["passed"].get<bool>());
  EXPECT_TRUE(d["scan"]["consistency"]["accepted_although_inconsistent"].get<bool>());
}

TEST(CliCharacterizeConsistency, NoiseOptionsOutOfRangeExit2) {
  const fs::path out = fresh("cc_never.json");
  const std::string base = "characterize noise --reference " + q(kNoise + "reference_171mm.csv") +
                           " --scan " + q(kNoise + "scan_a.csv");
  for (const char* opt : {"--cutoff-upr 1e300", "--cutoff-upr 1e-300", "--phase-deg 1e300"}) {
    const CliRun r = run(base + " " + opt + " -o " + q(out));
    EXPECT_EQ(r.exit_code, 2) << opt << ": " << r.err;
    const std::string name = std::string(opt).substr(0, std::string(opt).find(' '));
    EXPECT_NE(r.err.find(name + " must be"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
