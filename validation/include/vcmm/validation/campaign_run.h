// vcmm/validation/campaign_run.h — running a validation campaign: the uncertainty evaluation
// of every measurement, its comparison with the reference values (E_n, zeta) under the bias
// treatments, and the tables (docs/validation.md, "Running a campaign"; output files:
// docs/formats.md, "Validation output directory").
//
// Bias treatments compared per measurement and measurand (docs/validation.md, "Bias
// treatments"):
//   uncorrected  y with u                               E_n = (x_ref − y) / (k·√(u_ref² + u²))
//   corrected    the campaign's treatment (evaluation.bias_treatment): by default, for the
//                roundness, the shrinkage treatment (form_bias.h: bias at a surrogate of the true
//                profile, u_c including the uncertainty of the bias estimate); the diameter
//                always takes the study's correction (its bias is ~0)
//   paper        (a) the seed study: bias b from the virtual experiment run on the measured
//                (corrected-for-systematics) points; y − b with u_c (uncertainty::correct_bias);
//                refused (y reported, u = √(u² + b²)) where it would make the roundness negative
//   denoised     (b) optional: bias from the virtual experiment run on the denoised virtual
//                truth (the measured profile after the Gaussian filter, denoised_ring)
//   inflated     (c) no correction; U = k·u + |b| (b of the study's treatment):
//                E_n = (x_ref − y) / √((k u_ref)² + (k u + |b|)²)
// Resumable: each finished measurement is written as OUT/measurements/<id>.json (atomically,
// after its samples and residuals) with a fingerprint of everything its numbers depend on
// (model, points and reference files' bytes, the entry, the evaluation settings — the budget's
// among them —, the treatments, the true values); a rerun loads every measurement whose fingerprint matches
// instead of recomputing it, so an interrupted and restarted run gives the same tables, bit
// for bit, as an uninterrupted one.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "vcmm/errormodel/measurement.h"
#include "vcmm/uncertainty/process_group.h"
#include "vcmm/validation/campaign.h"
#include "vcmm/validation/ring_experiment.h"
#include "vcmm/validation/ring_uncertainty_budget.h"

namespace vcmm::validation {

/// One measurand of one measurement: values in mm (roundness too), scores dimensionless;
/// NaN where there is nothing (no reference → no scores; treatment (b) not run).
struct MeasurandOutcome {
  bool has_reference = false;
  double reference_mm = 0.0, u_reference_mm = 0.0;
  std::string reference_method;
  double estimate_mm = 0.0;       ///< y, from the (systematics-corrected) data
  double u_mm = 0.0;              ///< Monte Carlo standard uncertainty (the study's run, on x̂)
  double mc_mean_mm = 0.0;
  double interval_low_mm = 0.0, interval_high_mm = 0.0;  ///< MC probabilistically symmetric
  // The campaign's treatment ("corrected").
  std::string treatment;          ///< "shrinkage" or "paper"
  double bias_mm = 0.0, bias_standard_error_mm = 0.0;
  double bias_uncertainty_mm = 0.0;  ///< u of the bias estimate itself (0: not assessed)
  double corrected_mm = 0.0, u_corrected_mm = 0.0;
  bool correction_applied = false;
  std::string note;
  // The seed study's treatment (a).
  double bias_paper_mm = 0.0, corrected_paper_mm = 0.0, u_corrected_paper_mm = 0.0;
  bool paper_applied = false;
  double corrected_denoised_mm = 0.0, u_denoised_mm = 0.0;  ///< treatment (b), NaN if not run
  bool denoised_applied = false;
  double en = 0.0, en_corrected = 0.0, en_paper = 0.0, en_denoised = 0.0, en_inflated = 0.0;
  double zeta = 0.0, zeta_corrected = 0.0;
  double true_mm = 0.0;  ///< the true value (demo), NaN otherwise
};

/// One measurement's outcome.
struct MeasurementOutcome {
  std::string id;
  std::string location;
  double orientation_deg = 0.0;
  Height height = Height::middle;
  errormodel::ProbingMode mode = errormodel::ProbingMode::scanning;
  std::size_t points = 0;
  std::uint64_t seed = 0;
  std::uint64_t trials = 0;
  std::string trial = "exact";  ///< the first run's trial: "exact" or "spectral" (trial_kind.h)
  MeasurandOutcome diameter, roundness;
  /// The uncertainty budget of the study's run (evaluation.budget; ring_uncertainty_budget.h).
  std::optional<UncertaintyBudget> budget;
  std::string fingerprint;
  double wall_seconds = 0.0;  ///< time spent computing it (0 when loaded)
  bool resumed = false;       ///< loaded from a previous run's file
};

/// One line of the summary: E_n statistics of one treatment over the measurements that share
/// a factor level.
struct SummaryRow {
  std::string factor;     ///< all, location, orientation_deg, height, mode
  std::string level;      ///< "all" or the level
  std::string measurand;  ///< diameter, roundness
  std::string treatment;  ///< uncorrected, corrected, paper, denoised, inflated
  std::size_t n = 0;
  double share_within_1 = 0.0;  ///< share of |E_n| ≤ 1
  double mean_en = 0.0, rms_en = 0.0;
};

/// With known true values (demo): per measurand and treatment, E_n statistics and the error
/// of the reported value against the truth.
struct TreatmentRow {
  std::string measurand, treatment;
  std::size_t n = 0;
  double mean_en = 0.0, rms_en = 0.0, share_within_1 = 0.0;
  double mean_error_mm = 0.0, rms_error_mm = 0.0;
};

struct CampaignRunOptions {
  unsigned threads = 0;  ///< Monte Carlo threads of this process (0: all cores)
  /// The processes every Monte Carlo run is spread over (uncertainty/process_group.h; e.g. an
  /// MPI job, docs/mpi.md), or null for this process alone. Every process calls run_campaign
  /// with the same campaign and reads the same input files; only process 0 touches
  /// `output_dir` (creates it, resumes from it, writes every file) and its decision to resume a
  /// measurement is taken by all. The files are bit-identical for any number of processes and
  /// threads (run_info.json records both). On the other processes the outcome lists only the
  /// measurements computed in this run.
  uncertainty::ProcessGroup* process_group = nullptr;
  /// Run treatment (b) as well (one more Monte Carlo per measurement, on the denoised truth;
  /// needs a filter cut-off in the campaign). Off by default: the demo shows it biased.
  bool denoised_treatment = false;
  /// Known true values by measurement id (demo); missing ids have none.
  std::map<std::string, RingMeasurands> truth;
  /// Called before each measurement (index, count, id, resumed?) and during its Monte Carlo.
  std::function<void(std::size_t index, std::size_t count, const std::string& id, bool resumed)>
      on_measurement;
  std::function<void(std::uint64_t done, std::uint64_t planned)> progress;
  const std::atomic<bool>* cancel = nullptr;
  /// Extra provenance written into run_info.json (e.g. the command line).
  std::map<std::string, std::string> provenance;
};

struct CampaignOutcome {
  std::vector<MeasurementOutcome> measurements;  ///< in campaign order (finished ones)
  std::vector<SummaryRow> summary;
  std::vector<TreatmentRow> treatments;          ///< empty without truth
  std::size_t computed = 0, resumed = 0;
  bool cancelled = false;  ///< stopped early: tables not written; rerun to resume
  double wall_seconds = 0.0;
};

/// Runs the campaign into `output_dir` (created if needed): per measurement the files
/// samples/<id>.csv, residuals/<id>.csv and measurements/<id>.json (with its uncertainty
/// budget when evaluation.budget asks for it); then results.csv, results.json, summary.csv,
/// summary.json, treatments.csv (with truth), budget.csv (with evaluation.budget; a stale one
/// of an earlier run is removed otherwise) and run_info.json, all written atomically. Throws CampaignError (naming the entry) when a points file's
/// metadata contradicts its setup or a reference cannot be evaluated, geometry::InvalidInput /
/// errormodel::InvalidParameter for bad model or points files, std::runtime_error when a file
/// cannot be written. When options.cancel becomes true the current measurement is abandoned,
/// the finished ones stay on disk, and the outcome says cancelled.
CampaignOutcome run_campaign(const Campaign& campaign, const std::filesystem::path& output_dir,
                             const CampaignRunOptions& options);

/// The summary rows of a set of outcomes (factor "all" first, then location, orientation_deg,
/// height, mode; levels in order of first appearance; treatments uncorrected, corrected,
/// paper, denoised, inflated; rows with no finite E_n are left out).
std::vector<SummaryRow> summarize_campaign(const std::vector<MeasurementOutcome>& outcomes);

}  // namespace vcmm::validation
