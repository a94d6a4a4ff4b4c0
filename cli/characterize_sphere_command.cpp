// `vcmm characterize sphere --points SPHERE.csv --diameter-mm D --u-diameter-um U
//                           [--form-um F] [--orders 2,3,4] -o probe.json`
// Probe errors from points measured on a calibrated sphere: writes the digital model's "probe"
// section with a diagnostics block (characterization/probe_sphere.h,
// docs/characterization.md "Sphere: probe errors", docs/cli.md).
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "atomic_file.h"
#include "commands.h"
#include "option_values.h"
#include "run_control.h"
#include "vcmm/characterization/cmm_points_file.h"
#include "vcmm/characterization/probe_sphere.h"
#include "vcmm/errormodel/digital_model.h"

namespace vcmm::cli {
namespace {

namespace ch = vcmm::characterization;

struct SphereOptions {
  std::string points;
  double diameter_mm = 0.0;
  double u_diameter_um = 0.0;
  double form_um = 0.0;
  std::vector<int> orders = {2, 3, 4};
  std::string output;
};

int run_sphere(const SphereOptions& o) {
  constexpr const char* kName = "vcmm characterize sphere";
  try {
    const ch::CmmPoints data = ch::read_cmm_points_file(o.points, true);
    const ch::CalibratedSphere sphere{o.diameter_mm, o.u_diameter_um * 1e-3, o.form_um * 1e-3};
    ch::SphereProbeOptions options;
    options.orders = o.orders;
    const ch::SphereProbeCharacterization r =
        ch::characterize_probe_sphere(data.points_mm, sphere, options);
    for (const ch::NotIdentifiable& ni : r.not_identifiable)
      std::cerr << kName << ": note: " << ni.what << ": " << ni.reason << "\n";
    if (!r.usable) {
      std::cerr << kName << ": error: " << r.message << "\n";
      return kUndefined;
    }
    write_file_atomically(o.output, ch::probe_characterization_json(r, "points file " + o.points));
    std::cout << kName << ": " << r.message << "; wrote " << o.output << "\n";
    return kOk;
  } catch (const std::exception&) {  // 3 for invalid input, 1 otherwise
    return report_current_exception("characterize sphere");
  }
}

}  // namespace

void add_characterize_sphere_command(CLI::App& characterize, int* exit_code) {
  auto opts = std::make_shared<SphereOptions>();
  CLI::App* cmd = characterize.add_subcommand(
      "sphere",
      "probe errors (tip radius error, directional coefficients) from points on a calibrated "
      "sphere; writes the model's \"probe\" section");
  cmd->add_option("--points", opts->points,
                  "points on the sphere: x,y,z CSV in machine coordinates (mm) or a vcmm "
                  "measurement CSV")
      ->required();
  cmd->add_option("--diameter-mm", opts->diameter_mm, "calibrated sphere diameter (mm)")
      ->required()
      ->check(physical_value(errormodel::physical_range::diameter_mm, /*open_below=*/true));
  cmd->add_option("--u-diameter-um", opts->u_diameter_um,
                  "standard uncertainty of the calibrated diameter (um)")
      ->required()
      ->check(physical_value(errormodel::physical_range::length_sigma_um));
  cmd->add_option("--form-um", opts->form_um,
                  "form deviation of the sphere, peak-to-valley (um); a rectangular "
                  "contribution")
      ->default_val(0.0)
      ->check(physical_value(errormodel::physical_range::length_sigma_um));
  cmd->add_option("--orders", opts->orders,
                  "directional harmonic orders to estimate, comma-separated (1 is reported "
                  "as not identifiable)")
      ->delimiter(',')
      ->check(CLI::Range(1, errormodel::max_probe_harmonic_order))
      ->default_str("2,3,4");
  cmd->add_option("-o,--output", opts->output, "output JSON (written atomically)")->required();
  cmd->callback([opts, exit_code] {
    if (!std::isfinite(opts->diameter_mm) || !std::isfinite(opts->u_diameter_um) ||
        !std::isfinite(opts->form_um)) {
      std::cerr << "vcmm characterize sphere: error: --diameter-mm, --u-diameter-um and "
                   "--form-um must be finite numbers\n";
      *exit_code = kUsage;
      return;
    }
    *exit_code = run_sphere(*opts);
  });
}

}  // namespace vcmm::cli
