// `vcmm characterize noise --reference PROFILE.csv [--scan S.csv [--scan-repeat S2.csv]]
//                          [--touch T.csv] [--cutoff-upr 50] [--phase-deg P]
//                          [--no-scan-systematics] [--model MODEL.json]
//                          [--accept-inconsistent] -o noise.json`
// Noise σ by probing mode (and roughness from a repeated scan) from CMM profiles of a
// calibrated artefact and its reference profile: writes the model's "noise" (and "roughness")
// sections with a diagnostics block (characterization/noise.h, docs/characterization.md
// "Noise and roughness", docs/cli.md).
#include <cmath>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "atomic_file.h"
#include "commands.h"
#include "run_control.h"
#include "vcmm/characterization/cmm_points_file.h"
#include "vcmm/characterization/identical_inputs.h"
#include "vcmm/characterization/noise.h"
#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/errors.h"

namespace vcmm::cli {
namespace {

namespace ch = vcmm::characterization;
namespace em = vcmm::errormodel;

struct NoiseOptions {
  std::string reference;
  std::string scan;
  std::string scan_repeat;
  std::string touch;
  double cutoff_upr = 50.0;
  std::optional<double> phase_deg;
  bool no_scan_systematics = false;
  std::string model;
  bool accept_inconsistent = false;
  std::string output;
};

/// The XY profile of a CMM points file; a measurement CSV whose mode contradicts the option
/// it was given to is rejected.
std::vector<geometry::Point2> read_profile(const std::string& path, em::ProbingMode expected) {
  const ch::CmmPoints data = ch::read_cmm_points_file(path, false);
  if (data.mode && *data.mode != expected)
    throw em::InvalidInput(path + ": the file's mode is " + std::string(to_string(*data.mode)) +
                           " but it was given as " + std::string(to_string(expected)) + " data");
  std::vector<geometry::Point2> out(static_cast<std::size_t>(data.points_mm.cols()));
  for (Eigen::Index i = 0; i < data.points_mm.cols(); ++i)
    out[static_cast<std::size_t>(i)] = {data.points_mm(0, i), data.points_mm(1, i)};
  return out;
}

int run_noise(const NoiseOptions& o) {
  constexpr const char* kName = "vcmm characterize noise";
  try {
    // A scan given twice (as --scan and --scan-repeat, or as --touch) is no second measurement.
    std::vector<ch::InputFile> inputs{{"--reference", o.reference}};
    if (!o.scan.empty()) inputs.push_back({"--scan", o.scan});
    if (!o.scan_repeat.empty()) inputs.push_back({"--scan-repeat", o.scan_repeat});
    if (!o.touch.empty()) inputs.push_back({"--touch", o.touch});
    ch::refuse_identical_inputs(inputs);
    const ch::ReferenceProfile reference = ch::read_reference_profile_csv_file(o.reference);
    std::optional<double> fallback_scan, fallback_touch;
    if (!o.model.empty()) {
      const em::DigitalModel model = em::read_digital_model_file(o.model);
      fallback_scan = model.noise.scanning_sigma_mm;
      fallback_touch = model.noise.touch_trigger_sigma_mm;
    }
    ch::ScanNoiseOptions options;
    options.cutoff_upr = o.cutoff_upr;
    if (o.phase_deg) options.phase_rad = *o.phase_deg * std::numbers::pi / 180.0;

    ch::NoiseCharacterization c;
    c.reference_source = o.reference;
    c.scan_source = o.scan;
    c.repeat_source = o.scan_repeat;
    c.touch_source = o.touch;
    const ch::ScanNoiseResult* scan = nullptr;
    if (!o.scan.empty()) {
      const auto s = read_profile(o.scan, em::ProbingMode::scanning);
      if (!o.scan_repeat.empty()) {
        c.repeated = ch::repeated_scan_noise(
            s, read_profile(o.scan_repeat, em::ProbingMode::scanning), reference, options);
        scan = &c.repeated->first;
      } else {
        c.scan = ch::scanning_noise(s, reference, options);
        scan = &*c.scan;
      }
    }
    if (!o.touch.empty()) {
      // With a scan, its low-frequency systematic profile is subtracted from the touch points,
      // which also makes the scan's phase the right one (docs/characterization.md).
      const ch::SystematicProfile* systematics = nullptr;
      if (scan && !o.no_scan_systematics)
        systematics = c.repeated ? &c.repeated->systematic : &c.scan->systematic;
      double phase = 0.0;
      if (options.phase_rad) {
        phase = *options.phase_rad;
      } else if (scan && (systematics || scan->phase_determined)) {
        phase = scan->phase_rad;
      } else {
        std::cerr << kName << ": error: the touch-trigger evaluation needs the phase of the "
                  << "reference: "
                  << (scan ? "without the scan's systematic profile the scan's phase estimate "
                             "is not good enough (phase SNR below 8)"
                           : "there is no scan to estimate it from")
                  << "; give --phase-deg\n";
        return kUndefined;
      }
      c.touch = ch::touch_trigger_noise(read_profile(o.touch, em::ProbingMode::touch_trigger),
                                        reference, phase, systematics);
    }
    // Outliers in any data set refuse the calibration (or are recorded with
    // --accept-inconsistent), naming the file and the point.
    std::vector<std::pair<std::string, const ch::ConsistencyTest*>> tests;
    if (c.scan) tests.emplace_back("--scan " + o.scan, &c.scan->consistency);
    if (c.repeated) {
      tests.emplace_back("--scan " + o.scan, &c.repeated->first.consistency);
      tests.emplace_back("the difference of --scan " + o.scan + " and --scan-repeat " + o.scan_repeat,
                         &c.repeated->difference_consistency);
    }
    if (c.touch) tests.emplace_back("--touch " + o.touch, &c.touch->consistency);
    bool inconsistent = false;
    for (const auto& [what, t] : tests) {
      if (t->passed()) continue;
      inconsistent = true;
      std::cerr << kName << ": " << (o.accept_inconsistent ? "warning" : "error") << ": " << what
                << ": " << t->summary() << "\n";
    }
    if (inconsistent && !o.accept_inconsistent) {
      std::cerr << kName << ": error: a point far outside the noise of the others (dirt, a probe "
                   "bounce, a wrong file) would become noise in the model; check the named point; "
                   "--accept-inconsistent writes the result anyway and records this; nothing "
                   "written\n";
      return kInvalidInput;
    }
    write_file_atomically(o.output, ch::noise_characterization_json(c, fallback_scan, fallback_touch,
                                                                    o.accept_inconsistent));
    auto um = [](double mm) { return mm * 1e3; };
    std::cout << kName << ":";
    if (c.repeated)
      std::cout << " scanning sigma " << um(c.repeated->noise.sigma_mm) << " um (u "
                << um(c.repeated->noise.u_mm) << "), roughness "
                << um(c.repeated->roughness.sigma_mm) << " um ("
                << to_string(c.repeated->roughness_status) << ");";
    else if (c.scan)
      std::cout << " scanning sigma " << um(c.scan->sigma.sigma_mm) << " um (u "
                << um(c.scan->sigma.u_mm) << ", noise and roughness together);";
    if (c.touch)
      std::cout << " touch-trigger sigma " << um(c.touch->sigma.sigma_mm) << " um (u "
                << um(c.touch->sigma.u_mm) << ");";
    std::cout << " wrote " << o.output << "\n";
    return kOk;
  } catch (const std::exception&) {  // 3 for invalid input, 1 otherwise
    return report_current_exception("characterize noise");
  }
}

}  // namespace

void add_characterize_noise_command(CLI::App& characterize, int* exit_code) {
  auto opts = std::make_shared<NoiseOptions>();
  CLI::App* cmd = characterize.add_subcommand(
      "noise",
      "noise sigma per probing mode (and roughness from a repeated scan) from CMM profiles of "
      "a calibrated artefact and its reference profile; writes the model's \"noise\" "
      "(and \"roughness\") sections");
  cmd->add_option("--reference", opts->reference,
                  "reference profile of the artefact: roundness-instrument CSV "
                  "angle_deg,deviation_um, equiangular")
      ->required();
  CLI::Option* scan = cmd->add_option(
      "--scan", opts->scan,
      "dense equiangular scan of the artefact (x,y[,z] CSV, machine coordinates, or a vcmm "
      "measurement CSV)");
  cmd->add_option("--scan-repeat", opts->scan_repeat,
                  "a second scan of the same track (same points): separates roughness from "
                  "noise")
      ->needs(scan);
  CLI::Option* touch =
      cmd->add_option("--touch", opts->touch, "touch-trigger points on the same artefact");
  cmd->add_option("--cutoff-upr", opts->cutoff_upr,
                  "Gaussian low-pass cut-off separating systematic from random (UPR)")
      ->default_val(50.0);
  cmd->add_option("--phase-deg", opts->phase_deg,
                  "machine angle (about the profile centre, from +X) of the reference's 0 "
                  "degrees; default: estimated from the scan");
  cmd->add_flag("--no-scan-systematics", opts->no_scan_systematics,
                "do not subtract the scan's low-frequency systematic profile from the touch "
                "points (then the touch sigma includes the CMM's systematic errors)");
  cmd->add_option("--model", opts->model,
                  "current digital model: supplies the sigma of a mode without data");
  cmd->add_flag("--accept-inconsistent", opts->accept_inconsistent,
                "write the result even when a data set has an outlier (studentized, 1 % "
                "overall); the verdict is recorded in the output");
  cmd->add_option("-o,--output", opts->output, "output JSON (written atomically)")->required();
  cmd->callback([opts, exit_code, scan, touch] {
    if (scan->count() == 0 && touch->count() == 0) {
      std::cerr << "vcmm characterize noise: error: give --scan and/or --touch\n";
      *exit_code = kUsage;
      return;
    }
    // Physical ranges: roundness cut-offs are 15–1500 UPR (ISO 12181-2); below 1 UPR the
    // filter keeps nothing but the circle, above 1e5 no scan resolves it. An angle is given
    // within one turn either way.
    if (!(opts->cutoff_upr >= 1.0 && opts->cutoff_upr <= 1e5)) {
      std::cerr << "vcmm characterize noise: error: --cutoff-upr must be a cut-off in UPR in "
                   "[1, 100000] (and at most half the scan's points); got "
                << opts->cutoff_upr << " UPR\n";
      *exit_code = kUsage;
      return;
    }
    if (opts->phase_deg && !(std::abs(*opts->phase_deg) <= 360.0)) {
      std::cerr << "vcmm characterize noise: error: --phase-deg must be an angle in degrees in "
                   "[-360, 360]; got "
                << *opts->phase_deg << " deg\n";
      *exit_code = kUsage;
      return;
    }
    *exit_code = run_noise(*opts);
  });
}

}  // namespace vcmm::cli
