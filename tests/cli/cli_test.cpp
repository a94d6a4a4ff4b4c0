// The `vcmm roundness` contract (docs/cli.md): JSON keys, exit codes, messages, atomic output.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "support/cli_run.h"

namespace {

namespace fs = std::filesystem;

using vcmm::test::CliRun;
using vcmm::test::scratch_dir;
using vcmm::test::slurp;

fs::path write_scratch(const std::string& name, const std::string& content) {
  const fs::path p = scratch_dir() / name;
  std::ofstream(p) << content;
  return p;
}

CliRun run(const std::string& args, const std::string& stdin_file = "") {
  return vcmm::test::run_command(VCMM_EXE, args, stdin_file);
}

const std::string kScan = std::string(VCMM_SOURCE_DIR) + "/examples/profiles/ring_171mm_scan.csv";
const std::string kTouch =
    std::string(VCMM_SOURCE_DIR) + "/examples/profiles/ring_171mm_touch16.csv";

TEST(CliRoundness, JsonHasTheContractKeysAndCertifiedCircles) {
  const CliRun r = run("roundness '" + kScan + "' --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("n_points"), 3600);
  EXPECT_TRUE(j.at("filter").is_null());
  for (const char* k : {"LS", "MZ", "MI", "MC"}) {
    ASSERT_TRUE(j.contains(k)) << k;
    const auto& c = j.at(k);
    EXPECT_EQ(c.at("center").size(), 2u);
    for (const char* p : {"RONt", "RONp", "RONv", "RONq"}) EXPECT_TRUE(c.at(p).is_number()) << k << p;
    EXPECT_TRUE(c.contains("contacts"));
    EXPECT_TRUE(c.at("certified").is_boolean());
  }
  EXPECT_TRUE(j["MZ"].contains("inner_radius"));
  EXPECT_TRUE(j["MZ"].contains("outer_radius"));
  EXPECT_EQ(j["MZ"]["contacts"]["outer"].size(), 2u);
  EXPECT_EQ(j["MZ"]["contacts"]["inner"].size(), 2u);
  for (const char* k : {"MZ", "MI", "MC"}) EXPECT_TRUE(j[k]["certified"].get<bool>()) << k;
  const double mz = j["MZ"]["RONt"];
  for (const char* k : {"LS", "MI", "MC"}) EXPECT_LE(mz, j[k]["RONt"].get<double>()) << k;
  // The bundled ring has ~200 nm of form: RONt between 0.1 and 0.4 µm.
  EXPECT_GT(mz, 1e-4);
  EXPECT_LT(mz, 4e-4);
  EXPECT_LE(j["MI"]["radius"].get<double>(), j["LS"]["radius"].get<double>());
  EXPECT_LE(j["LS"]["radius"].get<double>(), j["MC"]["radius"].get<double>());
}

TEST(CliRoundness, ReferenceSelectsOneCircleAndFilterIsReported) {
  const CliRun r = run("roundness '" + kScan + "' --json --reference MZ --filter-upr 50");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j.contains("MZ"));
  EXPECT_FALSE(j.contains("LS"));
  EXPECT_FALSE(j.contains("MI"));
  EXPECT_EQ(j.at("filter").get<double>(), 50.0);
}

TEST(CliRoundness, HumanTableAndSparseTouchProfile) {
  const CliRun r = run("roundness '" + kTouch + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("16 points"), std::string::npos);
  EXPECT_NE(r.out.find("MZ"), std::string::npos);
}

TEST(CliRoundness, ReadsStandardInput) {
  const CliRun r = run("roundness - --json --reference LS", kScan);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out).at("n_points"), 3600);
}

TEST(CliRoundness, BadInputsExitNonZeroWithAClearMessage) {
  struct Case {
    std::string content;
    std::string expected;
  };
  const Case cases[] = {
      {"", "no points (empty input)"},
      {"1,0\n0,1\n-1,nan\n0,-1\n", ":3: field 2 is not finite"},
      {"1,0\n0,1\n-1,zero\n", ":3: field 2 is not a number"},
      {"1,0\n0,1\n", "needs at least 3 points; got 2"},
      {"0,0\n1,1\n2,2\n3,3\n", "collinear"},
      {"5,5\n5,5\n5,5\n", "identical"},
  };
  int k = 0;
  for (const auto& c : cases) {
    const fs::path p = write_scratch("bad" + std::to_string(k++) + ".csv", c.content);
    const CliRun r = run("roundness '" + p.string() + "' --json");
    EXPECT_EQ(r.exit_code, 3) << c.expected << "\n" << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << "no partial output on error";
  }
  const CliRun missing = run("roundness /nonexistent/ring.csv");
  EXPECT_EQ(missing.exit_code, 3);
  EXPECT_NE(missing.err.find("cannot open"), std::string::npos);
}

TEST(CliRoundness, ExtremeCoordinatesNeverCrash) {
  // Regression: 1e180-scale coordinates made `verify` trap (SIGFPE) inside the CLI.
  std::ostringstream csv;
  csv.precision(17);
  for (int i = 0; i < 12; ++i) {
    const double t = 2 * 3.141592653589793 * i / 12, r = 1e180 * (1 + 0.01 * std::cos(3 * t));
    csv << r * std::cos(t) << "," << r * std::sin(t) << "\n";
  }
  const fs::path p = write_scratch("huge.csv", csv.str());
  const CliRun circles = run("roundness '" + p.string() + "' --json --reference MZ");
  ASSERT_EQ(circles.exit_code, 0) << circles.err;
  EXPECT_TRUE(nlohmann::json::parse(circles.out)["MZ"]["certified"].get<bool>());
  const CliRun ls = run("roundness '" + p.string() + "' --json --reference LS");
  EXPECT_EQ(ls.exit_code, 3);
  EXPECT_NE(ls.err.find("overflow"), std::string::npos) << ls.err;
}

TEST(CliRoundness, FilterOnASparseProfileIsRefused) {
  const CliRun r = run("roundness '" + kTouch + "' --filter-upr 50");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_FALSE(r.err.empty());
}

TEST(CliRoundness, UsageErrorsExitTwo) {
  EXPECT_EQ(run("roundness '" + kScan + "' --reference XX").exit_code, 2);
  EXPECT_EQ(run("roundness '" + kScan + "' --filter-upr 50 --no-filter").exit_code, 2);
  EXPECT_EQ(run("roundness '" + kScan + "' --filter-upr -3").exit_code, 2);
  EXPECT_EQ(run("roundness").exit_code, 2);
  EXPECT_EQ(run("frobnicate").exit_code, 2);
}

TEST(CliRoundness, OutputFileIsWrittenAtomically) {
  const fs::path out = scratch_dir() / "result.json";
  fs::remove(out);
  const CliRun ok = run("roundness '" + kScan + "' --json -o '" + out.string() + "'");
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(nlohmann::json::parse(slurp(out)).at("n_points"), 3600);
  // A failing run leaves no file (and no temporary) behind.
  const fs::path bad_out = scratch_dir() / "never.json";
  const fs::path bad = write_scratch("empty.csv", "");
  EXPECT_EQ(run("roundness '" + bad.string() + "' --json -o '" + bad_out.string() + "'").exit_code, 3);
  EXPECT_FALSE(fs::exists(bad_out));
  const CliRun no_dir = run("roundness '" + kScan + "' --json -o /nonexistent/dir/r.json");
  EXPECT_NE(no_dir.exit_code, 0);
  for (const auto& e : fs::directory_iterator(scratch_dir()))
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
}

}  // namespace
