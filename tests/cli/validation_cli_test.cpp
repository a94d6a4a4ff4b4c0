// The `vcmm uncertainty`, `vcmm validate` and `vcmm demo` contracts (docs/cli.md): the JSON
// report and samples file, the same numbers for any thread count, exit 2 for bad options,
// exit 3 for bad input files (named), no output file on error; a small demo end to end and
// its resume.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/cli_run.h"
#include "vcmm/validation/provenance.h"

namespace {

namespace fs = std::filesystem;
using vcmm::test::CliRun;
using vcmm::test::scratch_dir;
using vcmm::test::slurp;

CliRun run(const std::string& args) { return vcmm::test::run_command(VCMM_EXE, args); }

const std::string kModel = std::string(VCMM_SOURCE_DIR) + "/examples/cmm_model.json";

/// A 360-point scanning measurement of the ring, made once with `vcmm simulate`.
const fs::path& measurement() {
  static const fs::path p = [] {
    const fs::path out = scratch_dir() / "ring360.csv";
    const CliRun r = run("simulate --model '" + kModel +
                         "' --ring 171 --points 360 --location 600,500,250 "
                         "--stylus-offset 0,0,-100 --temperature 20.4 --seed 3 -o '" +
                         out.string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return out;
  }();
  return p;
}

std::string uncertainty_args(const std::string& extra) {
  return "uncertainty --model '" + kModel + "' --points '" + measurement().string() +
         "' --filter-upr 15 --progress never " + extra;
}

TEST(CliUncertainty, JsonReportHasEveryQuantityWithUnits) {
  const CliRun r = run(uncertainty_args("--trials 300 --seed 5 --json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["schema"], "vcmm.uncertainty_result");
  EXPECT_EQ(j["monte_carlo"]["trials"], 300);
  EXPECT_EQ(j["monte_carlo"]["status"], "completed");
  for (const char* m : {"diameter", "roundness"}) {
    const auto& q = j["measurands"][m];
    for (const char* k : {"estimate", "mean", "standard_uncertainty", "bias", "corrected",
                          "corrected_standard_uncertainty", "correction_applied", "note"})
      EXPECT_TRUE(q.contains(k)) << m << "." << k;
    EXPECT_GT(q["standard_uncertainty"].get<double>(), 0.0);
    EXPECT_LE(q["coverage_interval"]["low"].get<double>(), q["mean"].get<double>());
    EXPECT_GE(q["coverage_interval"]["high"].get<double>(), q["mean"].get<double>());
  }
  EXPECT_EQ(j["measurands"]["diameter"]["unit"], "mm");
  EXPECT_EQ(j["measurands"]["roundness"]["unit"], "um");
  EXPECT_NEAR(j["measurands"]["diameter"]["estimate"].get<double>(), 171.0, 0.01);
  // Provenance: the code and the exact inputs that made the result.
  const auto& p = j["provenance"];
  EXPECT_EQ(p["vcmm_version"], std::string(vcmm::validation::vcmm_version()));
  EXPECT_FALSE(p["git_revision"].get<std::string>().empty());
  EXPECT_EQ(p["model_file"], kModel);
  EXPECT_EQ(p["model_sha256"], vcmm::validation::sha256_hex(slurp(kModel)));
  EXPECT_EQ(p["points_sha256"], vcmm::validation::sha256_hex(slurp(measurement())));
}

TEST(CliUncertainty, SameSeedSameNumbersForOneAndTwoThreads) {
  const fs::path s1 = scratch_dir() / "s1.csv", s2 = scratch_dir() / "s2.csv";
  const CliRun a = run(uncertainty_args("--trials 200 --threads 1 --samples '" + s1.string() + "'"));
  const CliRun b = run(uncertainty_args("--trials 200 --threads 2 --samples '" + s2.string() + "'"));
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const std::string x = slurp(s1);
  EXPECT_EQ(x, slurp(s2));
  EXPECT_EQ(std::count(x.begin(), x.end(), '\n'), 201);  // header + one line a trial
  EXPECT_EQ(x.rfind("diameter_mm,roundness_um\n", 0), 0u);
}

// --budget: the "budget" object (docs/formats.md), five sources in stage order, the
// quadrature sum beside the full u; the table carries it too; the same numbers for one and two
// threads; --budget-trials needs --budget.
TEST(CliUncertainty, BudgetPerErrorSource) {
  const std::string args = "--trials 200 --pilot-trials 100 --budget --budget-trials 100 --json ";
  const CliRun a = run(uncertainty_args(args + "--threads 1"));
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto j = nlohmann::json::parse(a.out);
  const auto& b = j["budget"];
  EXPECT_EQ(b["trials"], 100);
  ASSERT_EQ(b["sources"].size(), 5u);
  const char* names[] = {"roughness", "temperature", "kinematic", "probe", "noise"};
  double shares = 0.0;
  for (std::size_t i = 0; i < 5; ++i) {
    const auto& s = b["sources"][i];
    EXPECT_EQ(s["source"], names[i]);
    EXPECT_GT(s["diameter_u_mm"].get<double>(), 0.0) << names[i];
    EXPECT_GE(s["roundness_u_um"].get<double>(), 0.0) << names[i];
    shares += s["share_of_variance"]["diameter"].get<double>();
  }
  EXPECT_NEAR(shares, 1.0, 1e-12);
  const auto& q = b["quadrature_sum"];
  for (const char* k : {"diameter_u_mm", "roundness_u_um", "full_diameter_u_mm",
                        "full_roundness_u_um", "diameter_ratio", "roundness_ratio"})
    EXPECT_TRUE(q[k].is_number()) << k;
  EXPECT_NE(b["note"].get<std::string>().find("common random numbers"), std::string::npos);
  const CliRun two = run(uncertainty_args(args + "--threads 2"));
  ASSERT_EQ(two.exit_code, 0) << two.err;
  auto j2 = nlohmann::json::parse(two.out);
  j2["budget"].erase("wall_seconds");
  auto j1 = j;
  j1["budget"].erase("wall_seconds");
  EXPECT_EQ(j1["budget"], j2["budget"]);
  EXPECT_FALSE(nlohmann::json::parse(run(uncertainty_args("--trials 200 --json")).out)
                   .contains("budget"));  // off by default
  const CliRun t = run(uncertainty_args("--trials 200 --pilot-trials 100 --budget"));
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_NE(t.out.find("uncertainty budget"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("sqrt(sum u_i^2)"), std::string::npos) << t.out;
  const CliRun bad = run(uncertainty_args("--trials 200 --budget-trials 100"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--budget"), std::string::npos) << bad.err;
}

TEST(CliUncertainty, BadOptionsAndInputs) {
  EXPECT_EQ(run(uncertainty_args("--trials 100 --adaptive 0.01")).exit_code, 2);
  EXPECT_EQ(run(uncertainty_args("--reference XY")).exit_code, 2);
  const CliRun f = run(uncertainty_args("--trials 100 --filter-upr abc"));
  EXPECT_EQ(f.exit_code, 2);
  EXPECT_NE(f.err.find("--filter-upr"), std::string::npos) << f.err;
  const fs::path out = scratch_dir() / "never.json";
  const CliRun m = run("uncertainty --model /nonexistent/model.json --points '" +
                       measurement().string() + "' --trials 100 -o '" + out.string() + "'");
  EXPECT_EQ(m.exit_code, 3);
  EXPECT_NE(m.err.find("/nonexistent/model.json"), std::string::npos) << m.err;
  EXPECT_FALSE(fs::exists(out));
  // A measurement too sparse for the filter: a clear error, exit 3.
  const fs::path sparse = scratch_dir() / "ring12.csv";
  ASSERT_EQ(run("simulate --model '" + kModel + "' --ring 171 --points 12 --mode touch "
                "--location 600,500,250 -o '" + sparse.string() + "'").exit_code, 0);
  const CliRun s = run("uncertainty --model '" + kModel + "' --points '" + sparse.string() +
                       "' --trials 100 --filter-upr 50 --progress never");
  EXPECT_EQ(s.exit_code, 3) << s.out;
  EXPECT_NE(s.err.find("cut-off"), std::string::npos) << s.err;
}

// --trial: the report names the trial that ran and why (auto: spectral where it applies);
// spectral is refused where it does not apply (exit 3, naming the reason) and with --budget
// (exit 2); demo and validate check the value.
TEST(CliUncertainty, TrialIsChosenRecordedAndRefusedWithAReason) {
  const auto trial_of = [](const CliRun& r) {
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out)["monte_carlo"]["trial"];
  };
  const auto a = trial_of(run(uncertainty_args("--trials 200 --bias-treatment paper --json")));
  EXPECT_EQ(a["requested"], "auto");
  EXPECT_EQ(a["kind"], "spectral");
  const auto e =
      trial_of(run(uncertainty_args("--trials 200 --bias-treatment paper --json --trial exact")));
  EXPECT_EQ(e["kind"], "exact");
  const std::string unfiltered = "uncertainty --model '" + kModel + "' --points '" +
                                 measurement().string() +
                                 "' --filter-upr none --trials 200 --bias-treatment paper "
                                 "--progress never --json";
  const auto u = trial_of(run(unfiltered));
  EXPECT_EQ(u["kind"], "exact");
  EXPECT_NE(u["reason"].get<std::string>().find("filter"), std::string::npos) << u;
  // Refused by the options alone: a command-line error.
  const CliRun refused = run(unfiltered + " --trial spectral");
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("--trial spectral needs the Gaussian filter"), std::string::npos)
      << refused.err;
  // Refused by the data: the same ring with every two neighbouring points swapped in the file
  // is no equiangular grid in file order (the exact trial sorts by angle and runs) — exit 3.
  {
    std::istringstream in(slurp(measurement()));
    std::string text, line;
    std::vector<std::string> rows;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#' || line.rfind("x_mm", 0) == 0)
        text += line + "\n";
      else
        rows.push_back(line);
    }
    for (std::size_t i = 0; i + 1 < rows.size(); i += 2) std::swap(rows[i], rows[i + 1]);
    for (const std::string& r : rows) text += r + "\n";
    const fs::path swapped = scratch_dir() / "ring360_swapped.csv";
    std::ofstream(swapped, std::ios::binary) << text;
    const std::string args = "uncertainty --model '" + kModel + "' --points '" +
                             swapped.string() +
                             "' --trials 200 --bias-treatment paper --progress never --json";
    const auto fallback = trial_of(run(args));
    EXPECT_EQ(fallback["kind"], "exact") << fallback;
    const CliRun data_refused = run(args + " --trial spectral");
    EXPECT_EQ(data_refused.exit_code, 3) << data_refused.err;
    EXPECT_NE(data_refused.err.find("spectral trial does not apply"), std::string::npos)
        << data_refused.err;
  }
  const CliRun budget = run(uncertainty_args("--trials 200 --budget --trial spectral"));
  EXPECT_EQ(budget.exit_code, 2);
  EXPECT_NE(budget.err.find("--budget"), std::string::npos) << budget.err;
  EXPECT_EQ(run(uncertainty_args("--trials 200 --trial fast")).exit_code, 2);
  EXPECT_EQ(run("demo -o '" + (scratch_dir() / "never").string() + "' --trial fast").exit_code, 2);
}

TEST(CliUncertainty, PlainCmmExportWithMetadataOptions) {
  // The bundled example export (x,y,z in the model's machine frame, no metadata header) runs
  // with the metadata given as options — the command docs/cli.md shows.
  const std::string scan = std::string(VCMM_SOURCE_DIR) + "/examples/profiles/ring_171mm_scan.csv";
  const std::string base = "uncertainty --model '" + kModel + "' --points '" + scan +
                           "' --progress never --trials 300 --pilot-trials 100 ";
  const CliRun r = run(base + "--mode scanning --temperature 20.3 --stylus-offset 0,0,-100 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["measurands"]["diameter"]["estimate"].get<double>(), 171.0, 0.002);
  EXPECT_EQ(j["provenance"]["points_sha256"], vcmm::validation::sha256_hex(slurp(scan)));
  for (const char* m : {"diameter", "roundness"}) {
    const auto& q = j["measurands"][m];
    const auto& ci = q["corrected_interval"];
    EXPECT_LT(ci["low"].get<double>(), ci["high"].get<double>()) << m;
    // The note's numbers are the JSON's, in its unit (issue 13: "bias 0.4378 um" beside a
    // note saying "Bias 0.0004378").
    char bias[32];
    std::snprintf(bias, sizeof bias, "%.4g %s", q["bias"].get<double>(),
                  q["unit"] == "um" ? "µm" : "mm");
    EXPECT_NE(q["note"].get<std::string>().find(bias), std::string::npos)
        << m << ": " << bias << " not in " << q["note"];
  }
  // The table: U (k = 2) and both intervals, the bias never printed as "-0.0…0".
  const CliRun t = run(base + "--mode scanning --temperature 20.3 --stylus-offset 0,0,-100");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_NE(t.out.find("expanded U (k = 2)"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("% interval (shortest)"), std::string::npos) << t.out;
  for (const char* zero : {" -0.00 ", " -0.0000 ", " -0.00000 "})
    EXPECT_EQ(t.out.find(zero), std::string::npos) << t.out;
  // Every missing item named at once with the file that lacks them, exit 3.
  const CliRun missing = run(base + "--json");
  EXPECT_EQ(missing.exit_code, 3) << missing.err;
  EXPECT_NE(missing.err.find("ring_171mm_scan.csv"), std::string::npos) << missing.err;
  for (const char* k : {"--mode", "--temperature", "--stylus-offset"})
    EXPECT_NE(missing.err.find(k), std::string::npos) << k << ": " << missing.err;
  // Points outside the model's travel with this stylus: refused naming the axis (exit 3).
  const CliRun travel =
      run(base + "--mode scanning --temperature 20.3 --stylus-offset 0,0,200 --json");
  EXPECT_EQ(travel.exit_code, 3) << travel.err;
  EXPECT_NE(travel.err.find("Z axis"), std::string::npos) << travel.err;
}

TEST(CliUncertainty, OutputsAppearTogetherOrNotAtAll) {
  // The report's directory exists, the samples' does not: exit 3 naming the path and the
  // reason, before any trial is run, and no report either.
  const fs::path report = scratch_dir() / "together_report.txt";
  fs::remove(report);
  const fs::path samples = scratch_dir() / "no_such_dir" / "s.csv";
  const CliRun r = run(uncertainty_args("--trials 100 -o '" + report.string() + "' --samples '" +
                                        samples.string() + "'"));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find(samples.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(report));
  // The same file for both outputs is refused, and nothing is written.
  const CliRun same = run(uncertainty_args("--trials 100 -o '" + report.string() +
                                           "' --samples '" + report.string() + "'"));
  EXPECT_EQ(same.exit_code, 3) << same.err;
  EXPECT_NE(same.err.find("two outputs"), std::string::npos) << same.err;
  EXPECT_FALSE(fs::exists(report));
}

TEST(CliDemo, SmallDemoRunsAndResumes) {
  const fs::path out = scratch_dir() / "demo";
  fs::remove_all(out);
  const std::string args = "demo --model '" + kModel + "' -o '" + out.string() +
                           "' --trials 100 --progress never";
  const CliRun a = run(args);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  EXPECT_NE(a.out.find("66 measurements (66 computed, 0 resumed)"), std::string::npos) << a.out;
  EXPECT_NE(a.out.find("roundness  corrected"), std::string::npos) << a.out;
  const std::string table = slurp(out / "results.csv");
  const CliRun b = run(args);
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_NE(b.out.find("(0 computed, 66 resumed)"), std::string::npos) << b.out;
  EXPECT_EQ(slurp(out / "results.csv"), table);
  // validate on the demo's own campaign file gives the same table (no truth columns).
  const CliRun v = run("validate '" + (out / "world" / "campaign.json").string() + "' -o '" +
                       (scratch_dir() / "validate").string() +
                       "' --progress never");
  ASSERT_EQ(v.exit_code, 0) << v.err;
  EXPECT_TRUE(fs::is_regular_file(scratch_dir() / "validate" / "summary.csv"));
  EXPECT_FALSE(fs::exists(scratch_dir() / "validate" / "treatments.csv"));
}

TEST(CliDemo, BundledModelIsTheExampleFileAndOptionsAreChecked) {
  // Without --model the demo uses the compiled-in examples/cmm_model.json: byte for byte the
  // file, so a run with the file resumes every measurement of a run without it.
  const fs::path out = scratch_dir() / "demo_bundled";
  fs::remove_all(out);
  const std::string common = " -o '" + out.string() + "' --trials 100 --progress never";
  const CliRun a = run("demo" + common);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  EXPECT_NE(a.err.find("bundled example model"), std::string::npos) << a.err;
  const CliRun b = run("demo --model '" + kModel + "'" + common);
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_NE(b.out.find("(0 computed, 66 resumed)"), std::string::npos) << b.out;
  // The seed study's reference circle is the default; the settings reach the campaign.
  const std::string campaign = slurp(out / "world" / "campaign.json");
  EXPECT_NE(campaign.find("\"reference_circle\": \"MI\""), std::string::npos);
  EXPECT_NE(campaign.find("\"bias_treatment\": \"shrinkage\""), std::string::npos);
  EXPECT_NE(campaign.find("\"kinematic_errors\": \"corrected\""), std::string::npos);
  // Bad values: usage errors naming the option.
  for (const char* bad : {" --form-scale -1", " --form-scale nan", " --reference XX",
                          " --kinematics partly", " --bias-treatment denoised"}) {
    const CliRun c = run(std::string("demo -o '") + (scratch_dir() / "demo_bad").string() +
                         "' --trials 100 --progress never" + bad);
    EXPECT_EQ(c.exit_code, 2) << bad << "\n" << c.err;
  }
}

TEST(CliDemo, KinematicsLeftUncorrectedAndFormScaled) {
  const fs::path out = scratch_dir() / "demo_uncorrected";
  fs::remove_all(out);
  const CliRun a = run("demo -o '" + out.string() +
                       "' --trials 100 --progress never --kinematics uncorrected "
                       "--form-scale 5 --reference MZ --world-seed 3");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const std::string campaign = slurp(out / "world" / "campaign.json");
  EXPECT_NE(campaign.find("\"kinematic_errors\": \"uncertainty_only\""), std::string::npos);
  EXPECT_NE(campaign.find("\"reference_circle\": \"MZ\""), std::string::npos);
  // Form ×5: the true roundness (truth.json) is about 5 × 0.14 µm.
  const std::string truth = slurp(out / "world" / "truth.json");
  EXPECT_NE(truth.find("\"roundness_um\": 0.6"), std::string::npos) << truth.substr(0, 400);
  const std::string info = slurp(out / "run_info.json");
  EXPECT_NE(info.find("\"kinematic_errors\": \"uncertainty_only\""), std::string::npos);
}

/// A campaign of two entries of the 360-point measurement, 200 trials; `evaluation_extra` is
/// added to the evaluation object (e.g. `, "budget": true`).
fs::path small_campaign(const std::string& name, const std::string& evaluation_extra = "") {
  const fs::path c = scratch_dir() / (name + ".json");
  std::string entries;
  for (const char* id : {"a", "b"}) {
    entries += std::string(entries.empty() ? "" : ",") + R"({"id": ")" + id +
               R"(", "points": ")" + measurement().string() +
               R"(", "setup": {"location": "L", "orientation_deg": 0, "height": "middle",
                 "mode": "scanning"},
                 "reference": {"roundness": {"value_um": 0.2, "u_um": 0.01}}})";
  }
  std::ofstream(c) << R"({"schema": "vcmm.campaign", "schema_version": 1, "model": ")" << kModel
                   << R"(", "evaluation": {"filter_cutoff_upr": 15, "trials": 200)"
                   << evaluation_extra << R"(}, "measurements": [)" << entries << "]}";
  return c;
}

TEST(CliValidate, UncertaintyBudgetPerMeasurementAndItsTable) {
  const fs::path campaign = small_campaign("budget_campaign");
  const fs::path out = scratch_dir() / "validate_budget";
  fs::remove_all(out);
  const std::string args =
      "validate '" + campaign.string() + "' -o '" + out.string() + "' --progress never";
  const CliRun plain = run(args);
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_FALSE(fs::exists(out / "budget.csv"));  // off by default
  const CliRun a = run(args + " --budget --budget-trials 100");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  EXPECT_NE(a.out.find("(2 computed, 0 resumed)"), std::string::npos) << a.out;
  const std::string table = slurp(out / "budget.csv");
  EXPECT_EQ(table.rfind("id,location,orientation_deg,height,mode,trials,source,evaluated,"
                        "u_diameter_um,share_diameter,u_roundness_um,share_roundness,"
                        "ratio_diameter,ratio_roundness\n", 0),
            0u)
      << table.substr(0, 200);
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 1 + 2 * 7);
  EXPECT_NE(table.find("a,L,0,middle,scanning,100,probe,true,"), std::string::npos) << table;
  const auto j = nlohmann::json::parse(slurp(out / "measurements" / "b.json"));
  EXPECT_EQ(j["budget"]["trials"], 100);
  EXPECT_EQ(j["budget"]["sources"].size(), 5u);
  const auto info = nlohmann::json::parse(slurp(out / "run_info.json"));
  EXPECT_NE(info["command"].get<std::string>().find("--budget --budget-trials 100"),
            std::string::npos);
  // The same options resume; without --budget-trials each budget run has all 200 trials.
  const CliRun b = run(args + " --budget --budget-trials 100");
  EXPECT_NE(b.out.find("(0 computed, 2 resumed)"), std::string::npos) << b.out;
  const CliRun c = run(args + " --budget");
  EXPECT_NE(c.out.find("(2 computed, 0 resumed)"), std::string::npos) << c.out;
  EXPECT_EQ(nlohmann::json::parse(slurp(out / "measurements" / "b.json"))["budget"]["trials"],
            200);

  // The campaign file can ask for it; --budget-trials then overrides its budget_trials.
  const fs::path in_file =
      small_campaign("budget_in_file", R"(, "budget": true, "budget_trials": 150)");
  const fs::path out2 = scratch_dir() / "validate_budget_file";
  fs::remove_all(out2);
  const CliRun d = run("validate '" + in_file.string() + "' -o '" + out2.string() +
                       "' --progress never");
  ASSERT_EQ(d.exit_code, 0) << d.err;
  EXPECT_NE(slurp(out2 / "budget.csv").find(",150,noise,"), std::string::npos);

  // Bad values: usage errors (exit 2) naming the option, before any computation.
  for (const char* bad : {" --budget --budget-trials 300", " --budget --budget-trials 50",
                          " --budget-trials 100", " --budget --budget-trials x"}) {
    const CliRun e = run(args + bad);
    EXPECT_EQ(e.exit_code, 2) << bad << "\n" << e.err;
    EXPECT_NE(e.err.find("--budget"), std::string::npos) << bad << "\n" << e.err;
  }
  const CliRun too_many = run(args + " --budget --budget-trials 300");
  EXPECT_NE(too_many.err.find("exceeds the 200 trials per measurement (evaluation.trials of"),
            std::string::npos)
      << too_many.err;
  // In the campaign file: input errors (exit 3) naming the key.
  const CliRun f = run("validate '" +
                       small_campaign("budget_bad", R"(, "budget_trials": 150)").string() +
                       "' -o '" + (scratch_dir() / "v_bad").string() + "' --progress never");
  EXPECT_EQ(f.exit_code, 3);
  EXPECT_NE(f.err.find("evaluation.budget_trials: needs \"budget\": true"), std::string::npos)
      << f.err;
  // The demo checks --budget-trials against --trials before it builds its world.
  const CliRun g = run("demo -o '" + (scratch_dir() / "demo_budget_bad").string() +
                       "' --trials 100 --budget --budget-trials 200 --progress never");
  EXPECT_EQ(g.exit_code, 2) << g.err;
  EXPECT_NE(g.err.find("--budget-trials 200 exceeds the 100 trials per measurement (--trials)"),
            std::string::npos)
      << g.err;
  EXPECT_FALSE(fs::exists(scratch_dir() / "demo_budget_bad" / "world"));
}

TEST(CliValidate, CampaignErrorsNameTheEntry) {
  const fs::path c = scratch_dir() / "bad_campaign.json";
  std::ofstream(c) << R"({"schema": "vcmm.campaign", "schema_version": 1, "model": ")" << kModel
                   << R"(", "measurements": [{"id": "m1", "points": "missing.csv",
                   "setup": {"location": "C", "orientation_deg": 0, "height": "middle",
                   "mode": "scanning"}, "reference": {"roundness": {"value_um": 0.2, "u_um": 0.01}}}]})";
  const CliRun r = run("validate '" + c.string() + "' -o '" + (scratch_dir() / "v2").string() + "'");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("m1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("missing.csv"), std::string::npos) << r.err;
}

}  // namespace
