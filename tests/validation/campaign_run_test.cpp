// End-to-end tests of the campaign runner on a small synthetic world (the demo's plan with
// few points and few trials, so it runs in about a second): the tables, resume after an
// interruption giving the same final table, setup/metadata mismatches named by entry, and
// the treatments against the known truth.
#include "vcmm/validation/campaign_run.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "support/fake_process_group.h"
#include "vcmm/errormodel/digital_model.h"
#include "vcmm/validation/demo_world.h"

namespace vcmm::validation {
namespace {

namespace fs = std::filesystem;
namespace em = vcmm::errormodel;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

class CampaignRun : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("vcmm_campaign_run_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
             "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    const std::string model_path = std::string(VCMM_SOURCE_DIR) + "/examples/cmm_model.json";
    model_text_ = slurp(model_path);
    const em::DigitalModel model = em::parse_digital_model(model_text_, model_path);
    DemoWorldOptions wo;
    wo.scanning_points = 360;
    wo.touch_trigger_points = 120;
    wo.roundness_meter_points = 720;
    world_ = std::make_unique<DemoWorld>(make_demo_world(model, wo));
    settings_.trials = 100;
    settings_.filter_cutoff_upr = 15.0;
    truth_ = write_demo_campaign(*world_, model_text_, settings_, root_ / "world");
    campaign_ = read_campaign_file(root_ / "world" / "campaign.json");
  }
  void TearDown() override { fs::remove_all(root_); }

  fs::path root_;
  std::string model_text_;
  std::unique_ptr<DemoWorld> world_;
  EvaluationSettings settings_;
  std::map<std::string, RingMeasurands> truth_;
  Campaign campaign_;
};

TEST_F(CampaignRun, TheDemoPlanHas66MeasurementsOverAllFactors) {
  ASSERT_EQ(campaign_.measurements.size(), 66u);
  std::set<std::string> locations, heights, modes, orientations;
  for (const auto& m : campaign_.measurements) {
    locations.insert(m.setup.location);
    heights.insert(std::string(to_string(m.setup.height)));
    modes.insert(std::string(em::to_string(m.setup.mode)));
    orientations.insert(std::to_string(m.setup.orientation_deg));
  }
  EXPECT_EQ(locations.size(), 7u);
  EXPECT_EQ(heights.size(), 3u);
  EXPECT_EQ(modes.size(), 2u);
  EXPECT_EQ(orientations.size(), 4u);
}

TEST_F(CampaignRun, WritesEveryTableAndScoresEveryMeasurement) {
  CampaignRunOptions o;
  o.truth = truth_;
  o.denoised_treatment = true;
  const CampaignOutcome out = run_campaign(campaign_, root_ / "out", o);
  ASSERT_FALSE(out.cancelled);
  ASSERT_EQ(out.measurements.size(), 66u);
  for (const char* f : {"results.csv", "results.json", "summary.csv", "summary.json",
                        "treatments.csv", "run_info.json"})
    EXPECT_TRUE(fs::is_regular_file(root_ / "out" / f)) << f;
  for (const auto& m : out.measurements) {
    EXPECT_TRUE(fs::is_regular_file(root_ / "out" / "samples" / (m.id + ".csv")));
    EXPECT_TRUE(fs::is_regular_file(root_ / "out" / "residuals" / (m.id + ".csv")));
    for (const MeasurandOutcome* o2 : {&m.diameter, &m.roundness}) {
      EXPECT_TRUE(o2->has_reference);
      EXPECT_TRUE(std::isfinite(o2->en)) << m.id;
      EXPECT_TRUE(std::isfinite(o2->en_denoised)) << m.id;
      EXPECT_TRUE(std::isfinite(o2->en_paper)) << m.id;
      EXPECT_TRUE(std::isfinite(o2->en_corrected)) << m.id;
      EXPECT_GT(o2->u_mm, 0.0);
      // E_n = (ref − y) / (2 √(u_ref² + u²)) by hand.
      EXPECT_NEAR(o2->en,
                  (o2->reference_mm - o2->estimate_mm) /
                      (2.0 * std::hypot(o2->u_reference_mm, o2->u_mm)),
                  1e-12);
      EXPECT_TRUE(std::isfinite(o2->true_mm));
    }
    // The reference roundness sees the true form (filtered) within the meter's noise.
    EXPECT_NEAR(m.roundness.reference_mm, m.roundness.true_mm, 0.03e-3) << m.id;
    // The default treatment: the diameter keeps the study's correction; the roundness is the
    // shrinkage treatment, whose u includes the bias estimate's own uncertainty.
    EXPECT_EQ(m.diameter.treatment, "paper");
    EXPECT_EQ(m.diameter.corrected_mm, m.diameter.corrected_paper_mm);
    EXPECT_EQ(m.roundness.treatment, "shrinkage");
    EXPECT_GT(m.roundness.bias_uncertainty_mm, 0.0) << m.id;
    EXPECT_GE(m.roundness.u_corrected_mm, m.roundness.bias_uncertainty_mm) << m.id;
    EXPECT_GE(m.roundness.corrected_mm, 0.0) << m.id;
  }
  // One line per measurement and measurand, plus the header.
  const std::string csv = slurp(root_ / "out" / "results.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 2 * 66);
  // "all" rows exist for all five treatments of both measurands.
  std::size_t all_rows = 0;
  for (const auto& r : out.summary) all_rows += r.factor == "all" ? 1 : 0;
  EXPECT_EQ(all_rows, 10u);
  EXPECT_EQ(out.treatments.size(), 10u);
}

TEST_F(CampaignRun, AnInterruptedRunResumesToTheSameTable) {
  CampaignRunOptions o;
  o.truth = truth_;
  o.threads = 2;
  const auto full = run_campaign(campaign_, root_ / "full", o);
  ASSERT_FALSE(full.cancelled);

  std::atomic<bool> stop{false};
  CampaignRunOptions interrupted = o;
  interrupted.threads = 1;  // a different thread count must not change any number either
  interrupted.cancel = &stop;
  interrupted.on_measurement = [&](std::size_t i, std::size_t, const std::string&, bool) {
    if (i == 20) stop = true;  // abandons measurement 20 in its Monte Carlo
  };
  const auto first = run_campaign(campaign_, root_ / "resumed", interrupted);
  EXPECT_TRUE(first.cancelled);
  EXPECT_EQ(first.measurements.size(), 20u);
  EXPECT_FALSE(fs::exists(root_ / "resumed" / "results.csv"));

  const auto second = run_campaign(campaign_, root_ / "resumed", o);
  ASSERT_FALSE(second.cancelled);
  EXPECT_EQ(second.resumed, 20u);
  EXPECT_EQ(second.computed, 46u);
  for (const char* f : {"results.csv", "summary.csv", "treatments.csv", "results.json"})
    EXPECT_EQ(slurp(root_ / "full" / f), slurp(root_ / "resumed" / f)) << f;
}

TEST_F(CampaignRun, SpreadOverProcessesOnlyRankZeroWritesTheSameFilesAndDecidesResume) {
  // Two simulated processes (threads, tests/support/fake_process_group.h), each given its own
  // output directory: rank 0's must hold the files of a single-process run, byte for byte
  // (but for the run's own facts), rank 1's must never be created.
  Campaign small = campaign_;
  small.measurements.clear();  // the first two scanning and the first two touch measurements
  std::map<em::ProbingMode, int> taken;
  for (const auto& m : campaign_.measurements)
    if (taken[m.setup.mode]++ < 2) small.measurements.push_back(m);
  ASSERT_EQ(small.measurements.size(), 4u);
  const std::string touch_id = small.measurements.back().id;
  CampaignRunOptions o;
  o.truth = truth_;
  o.threads = 2;
  run_campaign(small, root_ / "single", o);
  const auto spread = [&](std::size_t expect_resumed) {
    std::string violations;
    const auto outcomes = test::run_as_processes<CampaignOutcome>(
        2,
        [&](uncertainty::ProcessGroup& group) {
          CampaignRunOptions p = o;
          p.threads = 1;
          p.process_group = &group;
          return run_campaign(small, root_ / ("rank" + std::to_string(group.rank())), p);
        },
        &violations);
    EXPECT_EQ(violations, "");
    for (const auto& outcome : outcomes) {
      ASSERT_FALSE(outcome.error);
      EXPECT_EQ(outcome.value.resumed, expect_resumed);
    }
    EXPECT_FALSE(fs::exists(root_ / "rank1"));
    const std::vector<std::string> files{
        "results.csv", "summary.csv", "treatments.csv", "results.json", "summary.json",
        "samples/" + small.measurements[0].id + ".csv", "samples/" + touch_id + ".csv",
        "residuals/" + touch_id + ".csv"};
    for (const std::string& f : files)
      EXPECT_EQ(slurp(root_ / "single" / f), slurp(root_ / "rank0" / f)) << f;
    const auto info = nlohmann::json::parse(slurp(root_ / "rank0" / "run_info.json"));
    EXPECT_EQ(info.at("monte_carlo").at("ranks"), 2);
    EXPECT_EQ(info.at("monte_carlo").at("threads"), 1);
  };
  spread(0);
  spread(4);  // rank 0 finds every measurement done; rank 1, seeing no files, follows it
}

TEST_F(CampaignRun, AChangedInputIsRecomputedNotResumed) {
  CampaignRunOptions o;
  Campaign small = campaign_;
  small.measurements.resize(2);
  run_campaign(small, root_ / "out", o);
  // Same campaign, other trial count: fingerprints differ, so nothing is reused.
  small.evaluation.trials = 120;
  const auto again = run_campaign(small, root_ / "out", o);
  EXPECT_EQ(again.resumed, 0u);
  EXPECT_EQ(again.computed, 2u);
  EXPECT_EQ(again.measurements[0].trials, 120u);
}

TEST_F(CampaignRun, ASetupContradictingThePointsFileNamesTheEntry) {
  Campaign bad = campaign_;
  bad.measurements.resize(3);
  bad.measurements[2].setup.orientation_deg += 90.0;
  try {
    run_campaign(bad, root_ / "out", {});
    FAIL() << "expected CampaignError";
  } catch (const CampaignError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("measurements[2]"), std::string::npos) << msg;
    EXPECT_NE(msg.find(bad.measurements[2].id), std::string::npos) << msg;
    EXPECT_NE(msg.find("orientation_deg"), std::string::npos) << msg;
  }
  bad = campaign_;
  bad.measurements.resize(1);
  bad.measurements[0].setup.mode = em::ProbingMode::touch_trigger;
  bad.measurements[0].points_path = campaign_.measurements[0].points_path;
  if (campaign_.measurements[0].setup.mode == em::ProbingMode::scanning) {
    EXPECT_THROW(run_campaign(bad, root_ / "out", {}), CampaignError);
  }
}

TEST_F(CampaignRun, APlainCmmExportWithItsSetupGivesTheSameEstimates) {
  // A demo measurement written again as a CMM would export it: x,y,z in machine coordinates,
  // no metadata. With the metadata in the entry's setup it is evaluated like the original.
  Campaign c = campaign_;
  c.measurements.resize(1);
  c.evaluation.trials = 1000;
  const em::Measurement m = em::read_measurement_csv_file(c.measurements[0].points_path.string());
  const Eigen::Matrix3Xd machine = em::machine_coordinates(m);
  const fs::path plain = root_ / "plain_export.csv";
  {
    std::ofstream out(plain);
    out.precision(17);
    out << "x_mm,y_mm,z_mm\n";
    for (Eigen::Index j = 0; j < machine.cols(); ++j)
      out << machine(0, j) << "," << machine(1, j) << "," << machine(2, j) << "\n";
  }
  CampaignMeasurement e = c.measurements[0];
  e.id = "plain";
  e.points = plain.string();
  e.points_path = plain;
  e.setup.temperature_c = m.temperature_c;
  e.setup.location_mm = {m.placement.location_mm.x(), m.placement.location_mm.y(),
                         m.placement.location_mm.z()};
  e.setup.stylus_offset_mm = {m.stylus_offset_mm.x(), m.stylus_offset_mm.y(),
                              m.stylus_offset_mm.z()};
  c.measurements.push_back(e);
  const CampaignOutcome out = run_campaign(c, root_ / "out", {});
  ASSERT_EQ(out.measurements.size(), 2u);
  const MeasurementOutcome& a = out.measurements[0];
  const MeasurementOutcome& b = out.measurements[1];
  EXPECT_NEAR(a.diameter.estimate_mm, b.diameter.estimate_mm, 1e-9);
  EXPECT_NEAR(a.roundness.estimate_mm, b.roundness.estimate_mm, 1e-9);
  // Other random numbers (the seed follows the id) and normals from the LS circle instead of
  // the file: the u agree within their Monte Carlo spread, 1/√(2(M−1)) = 2.2 % each at
  // M = 1000, so 4 standard errors of the ratio = 13 %.
  EXPECT_NEAR(b.diameter.u_mm / a.diameter.u_mm, 1.0, 0.13);
  EXPECT_NEAR(b.roundness.u_mm / a.roundness.u_mm, 1.0, 0.13);

  // Missing metadata is named by entry and key; plain-file keys on vcmm's CSV are refused.
  Campaign bad = c;
  bad.measurements[1].setup.stylus_offset_mm.reset();
  try {
    run_campaign(bad, root_ / "out_bad", {});
    FAIL() << "expected CampaignError";
  } catch (const CampaignError& err) {
    const std::string msg = err.what();
    EXPECT_NE(msg.find("(\"plain\").setup.stylus_offset_mm"), std::string::npos) << msg;
  }
  bad = c;
  bad.measurements[0].setup.stylus_offset_mm = std::array<double, 3>{0, 0, -100};
  try {
    run_campaign(bad, root_ / "out_bad2", {});
    FAIL() << "expected CampaignError";
  } catch (const CampaignError& err) {
    EXPECT_NE(std::string(err.what()).find("carries its own metadata"), std::string::npos)
        << err.what();
  }
  // The setup keys survive the campaign file's round trip.
  EXPECT_EQ(parse_campaign(campaign_json(c), root_ / "world" / "c.json").measurements[1].setup,
            c.measurements[1].setup);
}

/// The first two scanning and the first two touch-trigger measurements of the campaign.
Campaign two_of_each_mode(const Campaign& c) {
  Campaign out = c;
  out.measurements.clear();
  for (const em::ProbingMode mode : {em::ProbingMode::scanning, em::ProbingMode::touch_trigger}) {
    std::size_t taken = 0;
    for (const auto& m : c.measurements)
      if (m.setup.mode == mode && taken < 2) {
        out.measurements.push_back(m);
        ++taken;
      }
  }
  return out;
}

std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::vector<std::string> fields;
    std::size_t start = 0;
    for (std::size_t comma; (comma = line.find(',', start)) != std::string::npos;
         start = comma + 1)
      fields.push_back(line.substr(start, comma - start));
    fields.push_back(line.substr(start));
    rows.push_back(std::move(fields));
  }
  return rows;
}

TEST_F(CampaignRun, TheUncertaintyBudgetIsOffByDefaultAndPerMeasurementWhenAsked) {
  Campaign c = two_of_each_mode(campaign_);
  ASSERT_EQ(c.measurements.size(), 4u);
  c.evaluation.trials = 200;
  // The budget's runs share the exact trial's random numbers, so with a budget the first run is
  // always exact (trial_kind.h); pinned here so that the numbers compared below are the same
  // trial's with and without the budget.
  c.evaluation.trial = TrialKind::exact;
  const fs::path out = root_ / "out";
  const CampaignOutcome plain = run_campaign(c, out, {});
  for (const auto& m : plain.measurements) EXPECT_FALSE(m.budget.has_value()) << m.id;
  EXPECT_FALSE(fs::exists(out / "budget.csv"));
  EXPECT_EQ(nlohmann::json::parse(slurp(out / "run_info.json"))["budget"], false);
  EXPECT_FALSE(nlohmann::json::parse(slurp(out / "measurements" / (c.measurements[0].id + ".json")))
                   .contains("budget"));

  // Asked for: the budget settings are part of the fingerprint, so nothing is resumed.
  c.evaluation.budget = true;
  c.evaluation.budget_trials = 100;
  const CampaignOutcome with = run_campaign(c, out, {});
  EXPECT_EQ(with.resumed, 0u);
  EXPECT_EQ(with.computed, 4u);
  const auto rows = csv_rows(slurp(out / "budget.csv"));
  ASSERT_EQ(rows.size(), 1u + 4u * 7u);  // header; per measurement 5 sources + 2 summary rows
  const std::vector<std::string> header = {
      "id", "location", "orientation_deg", "height", "mode", "trials", "source", "evaluated",
      "u_diameter_um", "share_diameter", "u_roundness_um", "share_roundness", "ratio_diameter",
      "ratio_roundness"};
  EXPECT_EQ(rows[0], header);
  const std::vector<std::string> sources = {"roughness", "temperature", "kinematic", "probe",
                                            "noise", "quadrature_sum", "full_run"};
  for (std::size_t i = 0; i < 4; ++i) {
    const MeasurementOutcome& m = with.measurements[i];
    ASSERT_TRUE(m.budget.has_value()) << m.id;
    const UncertaintyBudget& b = *m.budget;
    EXPECT_EQ(b.trials, 100u);
    ASSERT_EQ(b.sources.size(), 5u);
    // The budget changes none of the measurement's other numbers.
    EXPECT_EQ(m.diameter.u_mm, plain.measurements[i].diameter.u_mm);
    EXPECT_EQ(m.roundness.corrected_mm, plain.measurements[i].roundness.corrected_mm);
    // The measurement's file carries the budget in the shape of `vcmm uncertainty --budget`.
    const auto j = nlohmann::json::parse(slurp(out / "measurements" / (m.id + ".json")));
    ASSERT_TRUE(j.contains("budget")) << m.id;
    for (const char* key : {"method", "trials", "wall_seconds", "sources", "quadrature_sum",
                            "note"})
      EXPECT_TRUE(j["budget"].contains(key)) << key;
    EXPECT_EQ(j["budget"]["sources"][3]["source"], "probe");
    EXPECT_DOUBLE_EQ(j["budget"]["sources"][3]["roundness_u_um"].get<double>(),
                     b.sources[3].roundness_u_mm * 1000.0);
    // Its rows in budget.csv: µm, shares that add up to 1, the ratio on the sum's row.
    double share_d = 0.0, share_r = 0.0;
    for (std::size_t k = 0; k < 7; ++k) {
      const auto& r = rows[1 + 7 * i + k];
      ASSERT_EQ(r.size(), header.size());
      EXPECT_EQ(r[0], m.id);
      EXPECT_EQ(r[4], std::string(em::to_string(m.mode)));
      EXPECT_EQ(r[5], "100");
      EXPECT_EQ(r[6], sources[k]);
      if (k < 5) {
        const SourceContribution& s = b.sources[k];
        EXPECT_EQ(r[7], s.evaluated ? "true" : "false");
        EXPECT_DOUBLE_EQ(std::stod(r[8]), s.diameter_u_mm * 1000.0) << sources[k];
        EXPECT_DOUBLE_EQ(std::stod(r[10]), s.roundness_u_mm * 1000.0) << sources[k];
        share_d += std::stod(r[9]);
        share_r += std::stod(r[11]);
        EXPECT_EQ(r[12], "");
      } else if (k == 5) {
        EXPECT_DOUBLE_EQ(std::stod(r[8]), b.diameter_quadrature_mm * 1000.0);
        EXPECT_DOUBLE_EQ(std::stod(r[12]), b.diameter_quadrature_mm / b.diameter_full_u_mm);
        EXPECT_DOUBLE_EQ(std::stod(r[13]), b.roundness_quadrature_mm / b.roundness_full_u_mm);
        EXPECT_EQ(r[9], "");
      } else {
        EXPECT_DOUBLE_EQ(std::stod(r[10]), b.roundness_full_u_mm * 1000.0);
        EXPECT_EQ(r[13], "");
      }
    }
    EXPECT_NEAR(share_d, 1.0, 1e-12) << m.id;
    EXPECT_NEAR(share_r, 1.0, 1e-12) << m.id;
    // The LS diameter is linear in the errors: its u_i add in quadrature (ratio 1 within
    // 4/√(2(M−1)) = 0.28 at M = 100).
    EXPECT_NEAR(b.diameter_quadrature_mm / b.diameter_full_u_mm, 1.0, 0.28) << m.id;
  }
  const auto info = nlohmann::json::parse(slurp(out / "run_info.json"));
  EXPECT_EQ(info["budget"], true);
  EXPECT_EQ(info["budget_trials"], 100);

  // Same settings: every measurement resumed, the same table byte for byte.
  const std::string table = slurp(out / "budget.csv");
  const CampaignOutcome again = run_campaign(c, out, {});
  EXPECT_EQ(again.resumed, 4u);
  EXPECT_EQ(slurp(out / "budget.csv"), table);
  // Other budget trials: recomputed, not resumed.
  c.evaluation.budget_trials = 0;  // as many as the run: 200
  const CampaignOutcome longer = run_campaign(c, out, {});
  EXPECT_EQ(longer.resumed, 0u);
  EXPECT_EQ(longer.measurements[0].budget->trials, 200u);
  // Off again: recomputed, and the earlier budget table is gone.
  c.evaluation.budget = false;
  const CampaignOutcome off = run_campaign(c, out, {});
  EXPECT_EQ(off.resumed, 0u);
  EXPECT_FALSE(fs::exists(out / "budget.csv"));
  // A table with truth left by an earlier run (a demo's treatments.csv) goes as well: this
  // campaign has no truth, so the table would describe other results.
  std::ofstream(out / "treatments.csv") << "measurand,treatment,n\n";
  const CampaignOutcome no_truth = run_campaign(c, out, {});
  ASSERT_TRUE(no_truth.treatments.empty());
  EXPECT_FALSE(fs::exists(out / "treatments.csv"));
}

TEST(CampaignSummary, StatisticsByHand) {
  std::vector<MeasurementOutcome> v(3);
  const double en[3] = {0.5, -1.5, 1.0};
  for (int i = 0; i < 3; ++i) {
    v[i].id = "m" + std::to_string(i);
    v[i].location = i < 2 ? "A" : "B";
    for (MeasurandOutcome* o : {&v[i].diameter, &v[i].roundness}) {
      o->has_reference = true;
      o->en = en[i];
      o->en_corrected = 0.0;
      o->en_denoised = std::nan("");
      o->en_inflated = 0.0;
    }
  }
  const auto rows = summarize_campaign(v);
  const SummaryRow* all = nullptr;
  const SummaryRow* loc_a = nullptr;
  for (const auto& r : rows) {
    if (r.factor == "all" && r.measurand == "roundness" && r.treatment == "uncorrected") all = &r;
    if (r.factor == "location" && r.level == "A" && r.measurand == "diameter" &&
        r.treatment == "uncorrected")
      loc_a = &r;
    EXPECT_NE(r.treatment, "denoised");  // no finite E_n: no row
  }
  ASSERT_TRUE(all && loc_a);
  EXPECT_EQ(all->n, 3u);
  EXPECT_DOUBLE_EQ(all->share_within_1, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(all->mean_en, 0.0);
  EXPECT_DOUBLE_EQ(all->rms_en, std::sqrt((0.25 + 2.25 + 1.0) / 3.0));
  EXPECT_EQ(loc_a->n, 2u);
  EXPECT_DOUBLE_EQ(loc_a->mean_en, -0.5);
}

}  // namespace
}  // namespace vcmm::validation
