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
  EXPECT_NE(missing.err.find("ring.csv: cannot read the points file: no such file"), std::string::npos)
      << missing.err;
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

namespace {

std::string arc_csv(double span_deg, int n) {
  std::ostringstream csv;
  csv.precision(17);
  for (int i = 0; i < n; ++i) {
    const double t = span_deg * i / (n - 1) * 3.141592653589793 / 180.0;
    const double r = 10.0 + 0.001 * std::cos(3 * t);
    csv << r * std::cos(t) << "," << r * std::sin(t) << "\n";
  }
  return csv.str();
}

// Issue 11: one undefined circle (MI of an arc) no longer takes the whole answer down.
TEST(CliRoundness, PerCircleOutcomesOnAPartialArc) {
  const fs::path p = write_scratch("arc100.csv", arc_csv(100.0, 200));
  const CliRun r = run("roundness '" + p.string() + "' --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("schema"), "vcmm.roundness_result");
  EXPECT_EQ(j.at("unit"), "mm");
  EXPECT_FALSE(j["coverage"]["closed"].get<bool>());
  EXPECT_NEAR(j["coverage"]["covered_deg"].get<double>(), 100.0, 0.1);
  EXPECT_TRUE(j["LS"]["defined"].get<bool>());
  EXPECT_TRUE(j["MZ"]["certified"].get<bool>());
  EXPECT_FALSE(j["MI"]["defined"].get<bool>());
  EXPECT_NE(j["MI"]["reason"].get<std::string>().find("not defined"), std::string::npos);
  EXPECT_EQ(j["MC"]["caution"], "not a roundness reference on an arc < 180°");
  // The table says the same, one line per circle.
  const CliRun t = run("roundness '" + p.string() + "'");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_NE(t.out.find("MI  undefined: "), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("partial arc"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("caution: not a roundness reference"), std::string::npos) << t.out;
  // Only MI asked (any case): nothing defined, exit 4, the reason in the output.
  const CliRun mi = run("roundness '" + p.string() + "' --reference mi --json");
  EXPECT_EQ(mi.exit_code, 4) << mi.err;
  EXPECT_FALSE(nlohmann::json::parse(mi.out)["MI"]["defined"].get<bool>());
}

TEST(CliRoundness, HarmonicsAndInputUnits) {
  const CliRun r = run("roundness '" + kScan + "' --json --reference LS --harmonics 4");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["harmonics"]["orders"].size(), 4u);
  // The bundled ring's form: 45 nm at 2 UPR, 30 nm at 3 (docs/errormodel.md), within noise.
  EXPECT_NEAR(j["harmonics"]["orders"][1]["amplitude"].get<double>(), 45e-6, 3e-6);
  EXPECT_NEAR(j["harmonics"]["orders"][2]["amplitude"].get<double>(), 30e-6, 3e-6);
  // The same file read as µm: every length 1000× smaller.
  const CliRun um = run("roundness '" + kScan + "' --json --reference LS --unit um");
  ASSERT_EQ(um.exit_code, 0) << um.err;
  EXPECT_NEAR(nlohmann::json::parse(um.out)["LS"]["radius"].get<double>(),
              j["LS"]["radius"].get<double>() * 1e-3, 1e-12);
  // --filter-upr none is accepted; nan and 0 are usage errors with a plain message.
  EXPECT_EQ(run("roundness '" + kScan + "' --filter-upr none --reference LS").exit_code, 0);
  const CliRun nan = run("roundness '" + kScan + "' --filter-upr nan");
  EXPECT_EQ(nan.exit_code, 2);
  EXPECT_NE(nan.err.find("positive number of UPR or 'none'"), std::string::npos) << nan.err;
}

TEST(CliRoundness, BatchGivesOneRowPerFileAndErrorRows) {
  const fs::path dir = scratch_dir() / "batch";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "a_arc.csv") << arc_csv(90.0, 100);
  std::ofstream(dir / "b_broken.csv") << "1,2\n3,4\n";
  std::ofstream(dir / "c_circle.csv") << arc_csv(360.0 * 99 / 100, 100);
  std::ofstream(dir / "notes.txt") << "not a profile";
  const CliRun csv = run("roundness '" + dir.string() + "' --threads 2");
  EXPECT_EQ(csv.exit_code, 3) << csv.err;  // one invalid file: the most severe outcome
  std::istringstream lines(csv.out);
  std::string header, line;
  std::getline(lines, header);
  EXPECT_EQ(header.rfind("file,status,n_points", 0), 0u) << header;
  std::vector<std::string> rows;
  while (std::getline(lines, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 3u) << csv.out;  // *.csv only, sorted by name
  EXPECT_NE(rows[0].find("a_arc.csv,ok,100"), std::string::npos) << rows[0];
  EXPECT_NE(rows[0].find("MI undefined"), std::string::npos) << rows[0];
  EXPECT_NE(rows[1].find("b_broken.csv,error"), std::string::npos) << rows[1];
  EXPECT_NE(rows[1].find("needs at least 3 points"), std::string::npos) << rows[1];
  EXPECT_NE(rows[2].find("c_circle.csv,ok"), std::string::npos) << rows[2];
  for (const auto& row : rows)
    EXPECT_EQ(std::count(row.begin(), row.end(), ','), std::count(header.begin(), header.end(), ','))
        << row;
  // JSON lines: the same, one object a line, in input order.
  const CliRun jl = run("roundness '" + (dir / "c_circle.csv").string() + "' '" +
                        (dir / "a_arc.csv").string() + "' --json -o '" +
                        (dir / "out.jsonl").string() + "'");
  EXPECT_EQ(jl.exit_code, 0) << jl.err;
  std::istringstream jlines(slurp(dir / "out.jsonl"));
  std::getline(jlines, line);
  EXPECT_EQ(nlohmann::json::parse(line)["file"], (dir / "c_circle.csv").string());
  std::getline(jlines, line);
  EXPECT_FALSE(nlohmann::json::parse(line)["MI"]["defined"].get<bool>());
}

TEST(CliRoundness, OutputIntoAMissingDirectoryOrOverADeviceIsAUserError) {
  const CliRun r = run("roundness '" + kTouch + "' -o /nonexistent/dir/out.txt");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("No such file or directory"), std::string::npos) << r.err;
  const CliRun d = run("roundness '" + kTouch + "' -o '" + scratch_dir().string() + "'");
  EXPECT_EQ(d.exit_code, 3) << d.err;
  EXPECT_NE(d.err.find("not a regular file"), std::string::npos) << d.err;
}

}  // namespace

namespace {

TEST(CliCheck, ExactClaimIsOptimalPerturbedIsNotAndBatchGivesRows) {
  // The exact MZ centre, as `vcmm roundness --json` prints it (17 significant digits).
  const CliRun mz = run("roundness '" + kScan + "' --json --reference MZ");
  ASSERT_EQ(mz.exit_code, 0) << mz.err;
  const auto j = nlohmann::json::parse(mz.out);
  char center[128];
  std::snprintf(center, sizeof center, "%.17g,%.17g", j["MZ"]["center"][0].get<double>(),
                j["MZ"]["center"][1].get<double>());
  const CliRun ok = run("check '" + kScan + "' --reference mz --center " + center + " --json");
  ASSERT_EQ(ok.exit_code, 0) << ok.err << ok.out;
  const auto k = nlohmann::json::parse(ok.out);
  EXPECT_EQ(k["verdict"], "optimal");
  EXPECT_TRUE(k["exact"]["certified"].get<bool>());
  EXPECT_EQ(k["exact"]["contacts"].size(), 4u);
  // 1 µm off in x: feasible (radii derived), not optimal, exit 5, the excess reported.
  std::snprintf(center, sizeof center, "%.17g,%.17g", j["MZ"]["center"][0].get<double>() + 1e-3,
                j["MZ"]["center"][1].get<double>());
  const CliRun off = run("check '" + kScan + "' --reference MZ --center " + center);
  EXPECT_EQ(off.exit_code, 5) << off.err;
  EXPECT_NE(off.out.find("verdict          not_optimal"), std::string::npos) << off.out;
  // Radii too tight: infeasible, the violating points named.
  const CliRun tight = run("check '" + kScan + "' --reference MZ --center " + center +
                           " --radii 85.49995,85.50005 --json");
  EXPECT_EQ(tight.exit_code, 5);
  const auto t = nlohmann::json::parse(tight.out);
  EXPECT_EQ(t["verdict"], "infeasible");
  EXPECT_GT(t["violations"].get<int>(), 0);
  // A claims file: one row per claim, relative paths, a broken line-up is an error row.
  const fs::path dir = scratch_dir() / "claims";
  fs::create_directories(dir);
  fs::copy_file(kScan, dir / "ring.csv", fs::copy_options::overwrite_existing);
  std::ofstream(dir / "claims.csv") << "file,reference,center_x,center_y,radius,outer_radius\n"
                                    << "ring.csv,MZ," << center << ",,\n"
                                    << "missing.csv,MI,0,0,,\n"
                                    << "ring.csv,MC,412.5,305.25,85.6,\n";
  const CliRun batch = run("check --claims '" + (dir / "claims.csv").string() + "'");
  EXPECT_EQ(batch.exit_code, 3) << batch.err;  // the missing file is the most severe
  std::istringstream lines(batch.out);
  std::string line;
  std::vector<std::string> rows;
  while (std::getline(lines, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 4u) << batch.out;
  EXPECT_NE(rows[1].find(",MZ,not_optimal,true,false,"), std::string::npos) << rows[1];
  EXPECT_NE(rows[2].find(",MI,error,"), std::string::npos) << rows[2];
  EXPECT_NE(rows[3].find(",MC,not_optimal,true,false,"), std::string::npos) << rows[3];
  // Usage errors.
  EXPECT_EQ(run("check '" + kScan + "' --reference XX --center 1,2").exit_code, 2);
  EXPECT_EQ(run("check '" + kScan + "' --reference MZ --center 1").exit_code, 2);
  EXPECT_EQ(run("check '" + kScan + "' --reference MZ --center 1,2 --radii 85").exit_code, 2);
  EXPECT_EQ(run("check '" + kScan + "' --reference MI --center nan,2").exit_code, 2);
}

}  // namespace
