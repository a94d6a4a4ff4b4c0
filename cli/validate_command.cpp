// `vcmm validate CAMPAIGN.json -o OUTDIR [--threads T] [--denoised]
//                [--budget [--budget-trials N]] [--progress ...]`
//   runs the uncertainty evaluation of every measurement of a campaign, compares with the
//   reference values (E_n, zeta) under the bias treatments, and writes the tables; resumable.
// `vcmm demo -o OUTDIR [--model MODEL.json] [--trials M] [--seed S] [--world-seed W]
//            [--reference MI|MZ|LS|MC] [--form-scale F] [--kinematics corrected|uncorrected]
//            [--bias-treatment shrinkage|paper] [--budget [--budget-trials N]] ...`
//   builds the synthetic ground-truth world (docs/demo.md), writes it as a campaign into
//   OUTDIR/world and validates it, with the true values known.
// (docs/validation.md, docs/cli.md.)
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include "commands.h"
#include "option_values.h"
#include "processes.h"
#include "run_control.h"
#include "vcmm/geometry/text_file.h"
#include "vcmm/errormodel/digital_model.h"
#include "vcmm/validation/campaign.h"
#include "vcmm/validation/campaign_run.h"
#include "vcmm/validation/demo_world.h"

namespace vcmm::cli {
namespace {

namespace va = vcmm::validation;

/// Shortest round-trip decimal of a double (as in the library's files).
std::string internal_shortest(double v) {
  char buf[32];
  for (int p = 1; p <= 17; ++p) {
    std::snprintf(buf, sizeof buf, "%.*g", p, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

struct CampaignCliOptions {
  std::string campaign, output, model;
  unsigned threads = 0;
  bool denoised = false;
  bool budget = false;
  std::uint64_t budget_trials = 0;  // 0: the campaign's (else the measurement's trials)
  std::string progress = "auto";
  std::string trial;  // --trial: empty = the campaign's "trial" (validate) or auto (demo)
  // demo only
  std::uint64_t trials = 10000;
  std::uint64_t seed = 1;
  std::uint64_t world_seed = va::DemoWorldOptions{}.seed;
  std::string reference = "MI";
  double form_scale = 1.0;
  std::string kinematics = "corrected";
  std::string bias_treatment = "shrinkage";
};

void print_summary(const va::CampaignOutcome& o, const std::string& out_dir) {
  std::printf("\n%zu measurements (%zu computed, %zu resumed) in %.1f s; tables in %s\n",
              o.measurements.size(), o.computed, o.resumed, o.wall_seconds, out_dir.c_str());
  std::printf("\nE_n = (reference - measured) / (k sqrt(u_ref^2 + u^2)), k = 2 (the seed study's "
              "sign: E_n > 0 when the measured value is below the reference)\n");
  std::printf("E_n over all measurements (honest uncertainties: mean ~0, RMS ~0.5, "
              "95.4 %% within +-1)\n");
  std::printf("  %-10s %-12s %4s %10s %9s %8s\n", "measurand", "treatment", "n", "|En|<=1",
              "mean En", "RMS En");
  for (const auto& r : o.summary) {
    if (r.factor != "all") continue;
    std::printf("  %-10s %-12s %4zu %9.1f%% %9.3f %8.3f\n", r.measurand.c_str(),
                r.treatment.c_str(), r.n, 100.0 * r.share_within_1, r.mean_en, r.rms_en);
  }
  if (!o.treatments.empty()) {
    std::printf("\nAgainst the true values (demo): error = reported - true\n");
    std::printf("  %-10s %-12s %12s %12s\n", "measurand", "treatment", "mean error", "RMS error");
    for (const auto& r : o.treatments) {
      const double s = 1000.0;  // both shown in µm
      std::printf("  %-10s %-12s %9.4f um %9.4f um\n", r.measurand.c_str(),
                  r.treatment.c_str(), r.mean_error_mm * s, r.rms_error_mm * s);
    }
  }
}

int run_campaign_cli(const va::Campaign& campaign, const std::string& out_dir,
                     const CampaignCliOptions& o,
                     std::map<std::string, va::RingMeasurands> truth, const char* name,
                     std::map<std::string, std::string> provenance) {
  InterruptGuard interrupt;
  const bool output = is_output_process();  // only rank 0 writes and reports (docs/mpi.md)
  const ProgressMode mode = output ? progress_mode_from_string(o.progress) : ProgressMode::never;
  std::unique_ptr<ProgressBar> bar;
  va::CampaignRunOptions options;
  options.threads = threads_per_process(o.threads);
  options.process_group = process_group();
  options.denoised_treatment = o.denoised;
  options.truth = std::move(truth);
  options.cancel = interrupt.flag();
  options.provenance = std::move(provenance);
  options.on_measurement = [&](std::size_t i, std::size_t n, const std::string& id,
                               bool resumed) {
    bar.reset();
    if (!output) return;
    if (resumed) {
      std::fprintf(stderr, "[%zu/%zu] %s: done in an earlier run (loaded)\n", i + 1, n,
                   id.c_str());
    } else {
      std::fprintf(stderr, "[%zu/%zu] %s\n", i + 1, n, id.c_str());
      bar = std::make_unique<ProgressBar>(std::string("  ") + id, mode);
    }
  };
  options.progress = [&](std::uint64_t done, std::uint64_t planned) {
    if (bar) bar->update(done, planned);
  };
  const va::CampaignOutcome outcome = va::run_campaign(campaign, out_dir, options);
  bar.reset();
  if (!output) return outcome.cancelled ? kInterrupted : kOk;
  if (outcome.cancelled) {
    std::fprintf(stderr,
                 "vcmm %s: interrupted after %zu finished measurement(s); they are kept in %s/"
                 "measurements — run the same command again to resume\n",
                 name, outcome.measurements.size(), out_dir.c_str());
    return kInterrupted;
  }
  print_summary(outcome, out_dir);
  return kOk;
}

template <class Body>
int guarded(const char* name, Body body) {
  try {
    return body();
  } catch (const std::exception&) {
    return report_current_exception(name);
  }
}

/// `--budget [--budget-trials N]` onto the evaluation settings `ev` (whose trials come from
/// `trials_source`); returns the usage error, "" when the options fit. Without --budget the
/// settings stay as they are (a campaign file may ask for the budget itself).
std::string apply_budget_options(const CampaignCliOptions& o, va::EvaluationSettings& ev,
                                 const std::string& trials_source) {
  if (!o.budget) return {};
  if (o.budget_trials > ev.trials)
    return "--budget-trials " + std::to_string(o.budget_trials) + " exceeds the " +
           std::to_string(ev.trials) + " trials per measurement (" + trials_source +
           "): each budget run is compared with the full run over the same trials";
  ev.budget = true;
  if (o.budget_trials != 0) ev.budget_trials = o.budget_trials;
  return {};
}

/// The budget options as given, for the command line recorded in run_info.json.
std::string budget_arguments(const CampaignCliOptions& o) {
  if (!o.budget) return {};
  return " --budget" +
         (o.budget_trials != 0 ? " --budget-trials " + std::to_string(o.budget_trials) : "");
}

int run_validate(const CampaignCliOptions& o) {
  return guarded("validate", [&] {
    va::Campaign campaign = va::read_campaign_file(o.campaign);
    if (!o.trial.empty()) campaign.evaluation.trial = *va::trial_kind_from_string(o.trial);
    const std::string usage =
        apply_budget_options(o, campaign.evaluation, "evaluation.trials of " + o.campaign);
    if (!usage.empty()) {
      std::fprintf(stderr, "vcmm validate: error: %s\n", usage.c_str());
      return static_cast<int>(kUsage);
    }
    return run_campaign_cli(campaign, o.output, o, {}, "validate",
                            {{"command", "vcmm validate " + o.campaign + " -o " + o.output +
                                             (o.trial.empty() ? std::string() : " --trial " + o.trial) +
                                             (o.denoised ? " --denoised" : "") +
                                             budget_arguments(o)}});
  });
}

int run_demo(const CampaignCliOptions& o) {
  {
    va::EvaluationSettings ev;
    ev.trials = o.trials;
    const std::string usage = apply_budget_options(o, ev, "--trials");
    if (!usage.empty()) {  // before the world is built
      std::fprintf(stderr, "vcmm demo: error: %s\n", usage.c_str());
      return kUsage;
    }
  }
  return guarded("demo", [&] {
    std::string text;
    std::string model_name = o.model;
    if (o.model.empty()) {
      text = std::string(va::bundled_example_model_json());
      model_name = "the bundled example model (examples/cmm_model.json)";
    } else {
      text = geometry::read_text_file(o.model, "digital-model file");
    }
    const errormodel::DigitalModel model =
        errormodel::parse_digital_model(text, o.model.empty() ? "examples/cmm_model.json" : o.model);
    va::EvaluationSettings ev;
    ev.trials = o.trials;
    ev.seed = o.seed;
    ev.reference_circle = *va::reference_circle_from_string(upper_case(o.reference));
    ev.kinematics_corrected = o.kinematics == "corrected";
    ev.bias_treatment = *va::roundness_bias_treatment_from_string(o.bias_treatment);
    if (!o.trial.empty()) ev.trial = *va::trial_kind_from_string(o.trial);
    apply_budget_options(o, ev, "--trials");  // checked above
    const std::filesystem::path world_dir = std::filesystem::path(o.output) / "world";
    std::map<std::string, va::RingMeasurands> truth;
    if (is_output_process()) {  // under mpirun the others read the world rank 0 wrote
      va::DemoWorldOptions wo;
      wo.seed = o.world_seed;
      wo.form_scale = o.form_scale;
      std::fprintf(stderr,
                   "vcmm demo: building the ground-truth world (seed %llu, form x%s, %s)\n",
                   static_cast<unsigned long long>(wo.seed), std::to_string(o.form_scale).c_str(),
                   model_name.c_str());
      const va::DemoWorld world = va::make_demo_world(model, wo);
      truth = va::write_demo_campaign(world, text, ev, world_dir);
    }
    uncertainty::any_process(process_group(), false);  // the world is on disk for every rank
    const va::Campaign campaign = va::read_campaign_file(world_dir / "campaign.json");
    if (is_output_process()) {
      std::fprintf(stderr, "vcmm demo: %zu measurements, %llu trials each, %s reference circle\n",
                   campaign.measurements.size(), static_cast<unsigned long long>(o.trials),
                   std::string(va::to_string(ev.reference_circle)).c_str());
    }
    return run_campaign_cli(
        campaign, o.output, o, std::move(truth), "demo",
        {{"command", "vcmm demo" + (o.model.empty() ? std::string() : " --model " + o.model) +
                         " -o " + o.output + " --trials " + std::to_string(o.trials) +
                         " --seed " + std::to_string(o.seed) + " --world-seed " +
                         std::to_string(o.world_seed) + " --reference " + upper_case(o.reference) +
                         " --form-scale " + internal_shortest(o.form_scale) + " --kinematics " +
                         o.kinematics + " --bias-treatment " + o.bias_treatment +
                         (o.trial.empty() ? std::string() : " --trial " + o.trial) +
                         (o.denoised ? " --denoised" : "") + budget_arguments(o)},
         {"world", (world_dir / "campaign.json").string()},
         {"form_scale", internal_shortest(o.form_scale)}});
  });
}

void add_common(CLI::App* cmd, CampaignCliOptions& o) {
  cmd->add_option("-o,--output", o.output, "output directory (created; reruns resume)")
      ->required();
  cmd->add_option("--threads", o.threads,
                  "Monte Carlo threads per process (default: all cores; under mpirun the "
                  "node's cores shared among its processes)")
      ->check(thread_count())
      ->default_val(0);
  cmd->add_flag("--denoised", o.denoised,
                "also run treatment (b) (one more Monte Carlo, on the denoised profile)");
  auto* budget = cmd->add_flag(
      "--budget", o.budget,
      "also the uncertainty budget of every measurement: each error source alone on the same "
      "random numbers (one more run per source; budget.csv; docs/validation.md)");
  cmd->add_option("--budget-trials", o.budget_trials,
                  "trials of each budget run (default and at most: the trials per measurement)")
      ->check(CLI::Range(std::uint64_t{100}, std::uint64_t{100'000'000}))
      ->needs(budget);
  cmd->add_option("--progress", o.progress,
                  "progress bar on stderr: auto (when a terminal), always, never")
      ->check(CLI::IsMember({"auto", "always", "never"}))
      ->default_val("auto");
  cmd->add_option("--trial", o.trial,
                  "Monte Carlo trial of the first run: auto (spectral where it applies), exact "
                  "or spectral (docs/validation.md); validate: overrides the campaign's "
                  "\"trial\"")
      ->check(CLI::IsMember({"auto", "exact", "spectral"}));
}

}  // namespace

void add_validate_command(CLI::App& app, int* exit_code) {
  auto o = std::make_shared<CampaignCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "validate", "validate the virtual CMM on a campaign: uncertainty, bias treatments, E_n");
  cmd->add_option("campaign", o->campaign, "campaign JSON (docs/validation.md)")->required();
  add_common(cmd, *o);
  cmd->callback([o, exit_code] { *exit_code = run_validate(*o); });
}

void add_demo_command(CLI::App& app, int* exit_code) {
  auto o = std::make_shared<CampaignCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "demo", "the validation demo: a synthetic ground-truth world of 66 measurements, validated");
  cmd->add_option("--model", o->model,
                  "digital-model JSON (default: the bundled examples/cmm_model.json)");
  cmd->add_option("--trials", o->trials, "Monte Carlo trials per measurement")
      ->check(CLI::Range(std::uint64_t{100}, std::uint64_t{100'000'000}))
      ->default_val(10000);
  cmd->add_option("--seed", o->seed, "seed of the Monte Carlo runs")
      ->check(unsigned_64())
      ->default_val(1);
  cmd->add_option("--world-seed", o->world_seed, "seed of the synthetic world")
      ->check(unsigned_64())
      ->default_val(va::DemoWorldOptions{}.seed);
  cmd->add_option("--reference", o->reference,
                  "reference circle of RONt: MI (the seed study's), MZ, LS or MC")
      ->check(CLI::IsMember({"MZ", "MI", "LS", "MC"}, CLI::ignore_case))
      ->default_val("MI");
  cmd->add_option("--form-scale", o->form_scale,
                  "multiply the world's true form (tests the method where form dominates)")
      ->check(finite_in_range(0.0, 1e6))
      ->default_val(1.0);
  cmd->add_option("--kinematics", o->kinematics,
                  "corrected: remove the model's kinematic errors; uncorrected: leave them and "
                  "only take them into account in the uncertainty (the seed study)")
      ->check(CLI::IsMember({"corrected", "uncorrected"}))
      ->default_val("corrected");
  cmd->add_option("--bias-treatment", o->bias_treatment,
                  "roundness bias treatment of the 'corrected' columns: shrinkage (default) or "
                  "paper (the seed study's); both are always reported")
      ->check(CLI::IsMember({"shrinkage", "paper"}))
      ->default_val("shrinkage");
  add_common(cmd, *o);
  cmd->callback([o, exit_code] { *exit_code = run_demo(*o); });
}

}  // namespace vcmm::cli
