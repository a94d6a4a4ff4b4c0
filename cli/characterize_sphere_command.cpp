// `vcmm characterize sphere --points SPHERE.csv --diameter-mm D --u-diameter-um U
//                           [--form-um F] [--orders 2,3,4] [--probing-sigma-um S]
//                           [--accept-inconsistent] -o probe.json`
// Probe errors from points measured on a calibrated sphere: writes the digital model's "probe"
// section with a diagnostics block (characterization/probe_sphere.h,
// docs/characterization.md "Sphere: probe errors", docs/cli.md).
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <memory>
#include <string>
#include <vector>

#include "atomic_file.h"
#include "commands.h"
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
  std::optional<double> probing_sigma_um;
  bool accept_inconsistent = false;
  std::string output;
};

// The largest calibration sphere diameter accepted (mm): reference spheres are 5–100 mm.
constexpr double kMaxSphereDiameterMm = 1000.0;

std::string shown(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

/// The option values in their physical ranges (with the option and unit named), else "".
std::string option_problem(const SphereOptions& o) {
  if (!std::isfinite(o.diameter_mm) || !(o.diameter_mm > 0.0) || o.diameter_mm > kMaxSphereDiameterMm)
    return "--diameter-mm must be a diameter in mm in (0, 1000]; got " + shown(o.diameter_mm) + " mm";
  // 1 % of the diameter, in µm: a certificate's u and form are fractions of a µm.
  const double limit_um = 10.0 * o.diameter_mm;
  if (!std::isfinite(o.u_diameter_um) || !(o.u_diameter_um >= 0.0) || o.u_diameter_um > limit_um)
    return "--u-diameter-um must be a standard uncertainty in um in [0, " + shown(limit_um) +
           "] (1 % of the diameter); got " + shown(o.u_diameter_um) + " um";
  if (!std::isfinite(o.form_um) || !(o.form_um >= 0.0) || o.form_um > limit_um)
    return "--form-um must be a form deviation in um in [0, " + shown(limit_um) +
           "] (1 % of the diameter); got " + shown(o.form_um) + " um";
  if (o.probing_sigma_um && (!std::isfinite(*o.probing_sigma_um) || !(*o.probing_sigma_um > 0.0) ||
                             *o.probing_sigma_um > 0.5 * limit_um))
    return "--probing-sigma-um must be a standard deviation in um in (0, " + shown(0.5 * limit_um) +
           "] (1 % of the radius); got " + shown(*o.probing_sigma_um) + " um";
  return "";
}

int run_sphere(const SphereOptions& o) {
  constexpr const char* kName = "vcmm characterize sphere";
  try {
    const ch::CmmPoints data = ch::read_cmm_points_file(o.points, true);
    const ch::CalibratedSphere sphere{o.diameter_mm, o.u_diameter_um * 1e-3, o.form_um * 1e-3};
    ch::SphereProbeOptions options;
    options.orders = o.orders;
    if (o.probing_sigma_um) options.probing_sigma_mm = *o.probing_sigma_um * 1e-3;
    const ch::SphereProbeCharacterization r =
        ch::characterize_probe_sphere(data.points_mm, sphere, options);
    for (const ch::NotIdentifiable& ni : r.not_identifiable)
      std::cerr << kName << ": note: " << ni.what << ": " << ni.reason << "\n";
    if (!r.usable) {
      std::cerr << kName << ": error: " << r.message << "\n";
      return kUndefined;
    }
    std::string source = "points file " + o.points;
    if (!r.consistency.passed()) {
      if (!o.accept_inconsistent) {
        std::cerr << kName << ": error: the points of " << o.points << " are inconsistent with "
                  << (o.probing_sigma_um ? "--probing-sigma-um " + shown(*o.probing_sigma_um) +
                                               " um and --form-um " + shown(o.form_um) + " um"
                                         : std::string("each other"))
                  << ": " << r.consistency.summary()
                  << "; check the named point (a blunder, dirt on the sphere) or the stated "
                     "sigma; --accept-inconsistent writes the result anyway and records this; "
                     "nothing written\n";
        return kInvalidInput;
      }
      std::cerr << kName << ": warning: accepted although inconsistent (--accept-inconsistent): "
                << r.consistency.summary() << "\n";
      source += "; ACCEPTED ALTHOUGH INCONSISTENT (--accept-inconsistent): " + r.consistency.summary();
    }
    write_file_atomically(o.output,
                          ch::probe_characterization_json(r, source, o.accept_inconsistent));
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
      ->required();
  cmd->add_option("--u-diameter-um", opts->u_diameter_um,
                  "standard uncertainty of the calibrated diameter (um)")
      ->required();
  cmd->add_option("--form-um", opts->form_um,
                  "form deviation of the sphere, peak-to-valley (um); a rectangular "
                  "contribution")
      ->default_val(0.0);
  cmd->add_option("--orders", opts->orders,
                  "directional harmonic orders to estimate, comma-separated (1 is reported "
                  "as not identifiable)")
      ->delimiter(',')
      ->check(CLI::Range(1, errormodel::max_probe_harmonic_order))
      ->default_str("2,3,4");
  cmd->add_option("--probing-sigma-um", opts->probing_sigma_um,
                  "standard deviation of the CMM's probing noise of one point (um), e.g. from "
                  "`characterize noise`: the residuals are tested against it (chi2 and outliers); "
                  "without it only outliers are tested");
  cmd->add_flag("--accept-inconsistent", opts->accept_inconsistent,
                "write the result even when the residuals fail the consistency test (chi2 or an "
                "outlier at the 1 % level); the verdict is recorded in the output");
  cmd->add_option("-o,--output", opts->output, "output JSON (written atomically)")->required();
  cmd->callback([opts, exit_code] {
    if (const std::string problem = option_problem(*opts); !problem.empty()) {
      std::cerr << "vcmm characterize sphere: error: " << problem << "\n";
      *exit_code = kUsage;
      return;
    }
    *exit_code = run_sphere(*opts);
  });
}

}  // namespace vcmm::cli
