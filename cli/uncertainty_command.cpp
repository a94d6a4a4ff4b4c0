// `vcmm uncertainty --model MODEL.json --points MEASURED.csv [--trials M | --adaptive TOL_UM]
//                   [--seed S] [--threads T] [--reference MZ|MI|LS|MC] [--filter-upr N|none]
//                   [--bias-treatment shrinkage|paper] [--pilot-trials N] [--surrogate-trials N]
//                   [--budget [--budget-trials N]] [--trial auto|exact|spectral]
//                   [--json] [-o OUT] [--samples OUT.csv] [--progress auto|always|never]`
// Monte Carlo uncertainty (JCGM 101) of the diameter and roundness of one ring measurement,
// with the bias and the bias-corrected estimates: the roundness by the shrinkage treatment
// (default) and by the seed study's (docs/uncertainty.md, docs/validation.md, docs/cli.md).
#include <cctype>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "atomic_file.h"
#include "commands.h"
#include "option_values.h"
#include "processes.h"
#include "run_control.h"
#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/measurement.h"
#include "vcmm/validation/measurement_input.h"
#include "vcmm/validation/provenance.h"
#include "vcmm/validation/ring_experiment.h"
#include "vcmm/validation/ring_uncertainty_report.h"

namespace vcmm::cli {
namespace {

namespace em = vcmm::errormodel;
namespace va = vcmm::validation;

struct UncertaintyOptions {
  std::string model, points;
  std::uint64_t trials = 0;  // 0: the default (unless adaptive)
  double adaptive_tolerance_um = 0.0;
  std::uint64_t seed = 1;
  unsigned threads = 0;
  std::string reference = "MZ";
  std::string filter = "50";
  double coverage = 0.95;
  bool json = false;
  std::string output, samples;
  std::string progress = "auto";
  std::string bias_treatment = "shrinkage";
  std::uint64_t pilot_trials = va::ShrinkageOptions{}.pilot_trials;
  std::uint64_t surrogate_trials = va::ShrinkageOptions{}.surrogate_trials;
  // Metadata of a plain point file or a roundness-meter profile (measurement_input.h).
  std::string mode, location, stylus_offset, frame = "machine", surface = "inner";
  std::optional<double> temperature_c, orientation_deg, radius_mm;
  double height_mm = 0.0;
  bool budget = false;            // per-source uncertainty budget (ring_uncertainty_budget.h)
  std::uint64_t budget_trials = 0;  // 0: the main run's trials
  std::string trial = "auto";       // the first run's trial (validation/trial_kind.h)
};

/// The metadata options as the library's MeasurementSetup; std::invalid_argument (exit 2)
/// for a malformed value.
va::MeasurementSetup measurement_setup(const UncertaintyOptions& o) {
  va::MeasurementSetup s;
  if (!o.mode.empty()) s.mode = em::probing_mode_from_string(o.mode);
  if (!o.mode.empty() && !s.mode)
    throw std::invalid_argument("--mode must be scanning or touch; got '" + o.mode + "'");
  s.temperature_c = o.temperature_c;
  s.orientation_deg = o.orientation_deg;
  s.radius_mm = o.radius_mm;
  s.height_mm = o.height_mm;
  if (!o.location.empty()) s.location_mm = parse_triple(o.location, "--location");
  if (!o.stylus_offset.empty()) s.stylus_offset_mm = parse_triple(o.stylus_offset, "--stylus-offset");
  s.frame = o.frame == "workpiece" ? va::PointFrame::workpiece : va::PointFrame::machine;
  s.side = o.surface == "outer" ? va::SurfaceSide::outer : va::SurfaceSide::inner;
  return s;
}

constexpr std::uint64_t kDefaultTrials = 100'000;

int run_uncertainty(const UncertaintyOptions& o) {
  va::RingUncertaintyOptions options;
  va::MeasurementSetup setup;
  ProgressMode progress_mode;
  try {
    // IsMember-checked: MZ, MI, LS, MC in any case.
    options.evaluation.reference = *va::reference_circle_from_string(upper_case(o.reference));
    options.evaluation.filter_cutoff_upr = parse_filter_upr(o.filter);
    if (o.trials > 0 && o.adaptive_tolerance_um > 0.0)
      throw std::invalid_argument("--trials and --adaptive exclude each other");
    options.monte_carlo.trials = o.trials > 0 ? o.trials : kDefaultTrials;
    check_trials_for_coverage(o.adaptive_tolerance_um > 0.0 ? 0 : options.monte_carlo.trials,
                              o.coverage);
    options.monte_carlo.seed = o.seed;
    options.monte_carlo.threads = threads_per_process(o.threads);
    options.monte_carlo.process_group = process_group();  // null unless under mpirun
    options.monte_carlo.coverage_probability = o.coverage;
    if (o.adaptive_tolerance_um > 0.0) {
      uncertainty::AdaptiveOptions adaptive;
      adaptive.numerical_tolerance = o.adaptive_tolerance_um / 1000.0;  // µm → mm
      options.adaptive = adaptive;
    }
    progress_mode = progress_mode_from_string(o.progress);
    if (!is_output_process()) progress_mode = ProgressMode::never;
    options.roundness_bias = *va::roundness_bias_treatment_from_string(o.bias_treatment);
    options.shrinkage.pilot_trials = o.pilot_trials;
    options.shrinkage.surrogate_trials = o.surrogate_trials;
    setup = measurement_setup(o);
    if (o.budget) options.budget = va::BudgetOptions{o.budget_trials};
    options.trial = *va::trial_kind_from_string(o.trial);  // IsMember-checked
    if (options.trial == va::TrialKind::spectral && o.budget)
      throw std::invalid_argument("--trial spectral and --budget exclude each other: the "
                                  "budget's one-at-a-time runs share the exact trial's random "
                                  "numbers");
    // Decided by the options alone, so a command-line error (exit 2); what depends on the
    // data (an equiangular grid, radial normals) is checked on the data (exit 3).
    if (options.trial == va::TrialKind::spectral && !options.evaluation.filter_cutoff_upr)
      throw std::invalid_argument("--trial spectral needs the Gaussian filter: with "
                                  "--filter-upr none the unfiltered RONt needs every harmonic, "
                                  "which is the exact trial");
  } catch (const std::invalid_argument& ex) {
    std::cerr << "vcmm uncertainty: error: " << ex.what() << "\n";
    return kUsage;
  }
  try {
    // Before minutes of Monte Carlo; only the output process writes (docs/mpi.md).
    if (!o.output.empty() && is_output_process()) check_output_path(o.output);
    if (!o.samples.empty() && is_output_process()) check_output_path(o.samples);
    const em::DigitalModel model = em::read_digital_model_file(o.model);
    const em::Measurement measured = va::read_measurement_file(o.points, setup);
    options.provenance = {{"model_file", o.model},
                          {"model_sha256", va::file_sha256(o.model)},
                          {"points_file", o.points},
                          {"points_sha256", va::file_sha256(o.points)}};
    InterruptGuard interrupt;
    ProgressBar bar("vcmm uncertainty", progress_mode);
    options.monte_carlo.cancel = interrupt.flag();
    options.monte_carlo.progress = [&bar](std::uint64_t done, std::uint64_t planned) {
      bar.update(done, planned);
    };
    const va::RingUncertaintyResult result =
        va::evaluate_ring_uncertainty(model, measured, options);
    bar.finish();
    const bool cancelled = result.monte_carlo.status == uncertainty::RunStatus::cancelled;
    if (!is_output_process()) return cancelled ? kInterrupted : kOk;  // rank 0 reports
    const std::string report = o.json ? va::ring_uncertainty_json(result, options)
                                      : va::ring_uncertainty_text(result, options);
    // An interrupted run reports what it did, but never writes files that look finished.
    // The report and the samples appear together or not at all.
    OutputTransaction outputs;
    if (!o.output.empty() && !cancelled) outputs.stage(o.output, report);
    if (!o.samples.empty() && !cancelled)
      outputs.stage(o.samples, va::ring_samples_csv(result.monte_carlo));
    outputs.commit();
    if (o.output.empty() || cancelled) std::cout << report;
    if (cancelled) {
      std::cerr << "vcmm uncertainty: interrupted: the statistics above cover only the "
                << result.monte_carlo.trials << " trials done; no output file written\n";
      return kInterrupted;
    }
    return kOk;
  } catch (const std::exception&) {
    return report_current_exception("uncertainty");
  }
}

}  // namespace

void add_uncertainty_command(CLI::App& app, int* exit_code) {
  auto opts = std::make_shared<UncertaintyOptions>();
  CLI::App* cmd = app.add_subcommand(
      "uncertainty",
      "Monte Carlo uncertainty (JCGM 101) of the diameter and roundness of one ring "
      "measurement, with bias and bias-corrected estimates");
  cmd->add_option("--model", opts->model, "digital-model JSON (docs/errormodel.md)")->required();
  cmd->add_option("--points", opts->points,
                  "the measurement: vcmm's measurement CSV (docs/errormodel.md), or plain points "
                  "x,y[,z] or a roundness-meter profile angle_deg,deviation_um with the "
                  "metadata options below (docs/formats.md)")
      ->required();
  const char* meta = "Metadata of plain points and profiles";
  cmd->add_option("--mode", opts->mode, "probing mode: scanning or touch")->group(meta);
  cmd->add_option("--temperature", opts->temperature_c, "workpiece temperature reading (°C)")
      ->check(physical_value(em::physical_range::temperature_c))
      ->group(meta);
  cmd->add_option("--location", opts->location,
                  "ring centre in machine coordinates X,Y,Z (mm); default for machine-frame "
                  "points with z: their LS centre and mean z")
      ->group(meta);
  cmd->add_option("--orientation", opts->orientation_deg,
                  "rotation of the ring about machine Z (degrees, default 0)")
      ->check(finite_number())
      ->group(meta);
  cmd->add_option("--stylus-offset", opts->stylus_offset,
                  "tip centre relative to the ram reference point X,Y,Z (mm)")
      ->group(meta);
  cmd->add_option("--frame", opts->frame,
                  "frame of plain points: machine (a CMM export, default) or workpiece")
      ->check(CLI::IsMember({"machine", "workpiece"}))
      ->group(meta);
  cmd->add_option("--surface", opts->surface,
                  "probed side: inner (a bore, the ring gauge; default) or outer")
      ->check(CLI::IsMember({"inner", "outer"}))
      ->group(meta);
  cmd->add_option("--radius", opts->radius_mm,
                  "profiles: nominal radius the deviations are about (mm)")
      ->check(finite_in_range(0.0, em::physical_range::diameter_mm.max / 2.0))
      ->group(meta);
  cmd->add_option("--height", opts->height_mm, "profiles: workpiece height of the profile (mm)")
      ->check(finite_number())
      ->group(meta);
  auto* trials = cmd->add_option("--trials", opts->trials,
                                 "number of Monte Carlo trials M (default 100000)")
                     ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{100'000'000}));
  auto* adaptive = cmd->add_option(
      "--adaptive", opts->adaptive_tolerance_um,
      "adaptive JCGM 101 7.9 run to this numerical tolerance (um) for u and interval ends")
      ->check(finite_in_range(0.0, 1e6, true));
  trials->excludes(adaptive);
  cmd->add_option("--seed", opts->seed, "seed: fixes every number, whatever the thread count")
      ->check(unsigned_64())
      ->default_val(1);
  cmd->add_option("--threads", opts->threads, "worker threads per process (default: all cores; under mpirun the node's cores "
                  "shared among its processes)")
      ->check(thread_count())
      ->default_val(0);
  cmd->add_option("--reference", opts->reference, "reference circle of RONt: MZ, MI, LS or MC")
      ->check(CLI::IsMember({"MZ", "MI", "LS", "MC"}, CLI::ignore_case))
      ->default_val("MZ");
  cmd->add_option("--filter-upr", opts->filter,
                  "ISO 16610-21 Gaussian cut-off (UPR) before the roundness, or 'none'")
      ->default_val("50");
  cmd->add_option("--coverage", opts->coverage, "coverage probability of the intervals")
      ->check(finite_in_range(0.0, 1.0, true))
      ->default_val(0.95);
  cmd->add_option("--bias-treatment", opts->bias_treatment,
                  "roundness bias treatment reported as 'corrected': shrinkage (default: bias at "
                  "a shrunk surrogate of the true profile, with its own uncertainty) or paper "
                  "(the seed study's); the study's is always shown too")
      ->check(CLI::IsMember({"shrinkage", "paper"}))
      ->default_val("shrinkage");
  cmd->add_option("--pilot-trials", opts->pilot_trials,
                  "trials of the shrinkage treatment's pilot run (error power per harmonic)")
      ->check(CLI::Range(std::uint64_t{20}, std::uint64_t{10'000'000}))
      ->default_val(va::ShrinkageOptions{}.pilot_trials);
  cmd->add_option("--surrogate-trials", opts->surrogate_trials,
                  "trials of the shrinkage treatment's second run: min(this, --trials); 0: as "
                  "many as --trials")
      ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{100'000'000}))
      ->default_val(va::ShrinkageOptions{}.surrogate_trials);
  auto* budget = cmd->add_flag("--budget", opts->budget,
                "also the uncertainty budget: each error source alone on the same random numbers "
                "(one more run per source; docs/validation.md)");
  cmd->add_option("--budget-trials", opts->budget_trials,
                  "trials of each budget run (default and at most: the main run's)")
      ->check(CLI::Range(std::uint64_t{100}, std::uint64_t{100'000'000}))
      ->needs(budget);
  cmd->add_option("--trial", opts->trial,
                  "Monte Carlo trial of the first run: auto (default: spectral where it "
                  "applies, else exact; the result says which and why), exact (point by point) "
                  "or spectral (in-band harmonics; refused where it does not apply; "
                  "docs/validation.md)")
      ->check(CLI::IsMember({"auto", "exact", "spectral"}))
      ->default_val("auto");
  cmd->add_flag("--json", opts->json, "print JSON instead of the table");
  cmd->add_option("-o,--output", opts->output, "write the report to this file (atomically)");
  cmd->add_option("--samples", opts->samples,
                  "write the samples (diameter_mm,roundness_um per trial) to this CSV");
  cmd->add_option("--progress", opts->progress,
                  "progress bar on stderr: auto (when a terminal), always, never")
      ->check(CLI::IsMember({"auto", "always", "never"}))
      ->default_val("auto");
  cmd->callback([opts, exit_code] { *exit_code = run_uncertainty(*opts); });
}

}  // namespace vcmm::cli
