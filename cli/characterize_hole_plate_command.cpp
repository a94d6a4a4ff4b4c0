// `vcmm characterize hole-plate --plate PLATE.csv --placement P1.csv [--placement P2.csv ...]
//        --probing-sigma-um S (--axis-range X=MIN,MAX --axis-range Y=… --axis-range Z=… |
//        --model MODEL.json) [--chain moving_bridge] [--degree N] [--degree-of E_XX=N ...]
//        [--rank-tolerance T] [--prior-um U] [--prior-urad U] -o kinematics.json
//        [--json REPORT.json] [--accept-inconsistent]`
// Kinematic errors from a calibrated hole/ball plate measured in several placements: writes the
// digital model's "kinematics" section ({"kinematics": {...}}, atomically) and prints the report
// (characterization/hole_plate.h, docs/characterization.md "Hole plate: kinematic errors",
// docs/cli.md).
#include <nlohmann/json.hpp>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "atomic_file.h"
#include "commands.h"
#include "option_values.h"
#include "run_control.h"
#include "vcmm/characterization/hole_plate.h"
#include "vcmm/characterization/identical_inputs.h"
#include "vcmm/errormodel/digital_model.h"

namespace vcmm::cli {
namespace {

namespace ch = vcmm::characterization;
namespace em = vcmm::errormodel;

struct HolePlateOptions {
  std::string plate;
  std::vector<std::string> placements;
  std::string model;
  std::vector<std::string> axis_ranges;
  std::string chain;
  int degree = -1;  // -1: the model's degrees, else 2
  std::vector<std::string> degree_of;
  double probing_sigma_um = 0.0;
  double rank_tolerance = 1e-3;
  double prior_um = 1.0;
  double prior_urad = 1.0;
  bool accept_inconsistent = false;
  std::string output;
  std::string report;
};

// Physical ranges of the options (µm, µrad): a feature centre's repeatability on a CMM is
// 0.01–10 µm; an a-priori u of a kinematic error beyond 1 mm or 1 mrad is no CMM.
constexpr double kMaxProbingSigmaUm = 1000.0;
constexpr double kMaxPriorUm = 1000.0;
constexpr double kMaxPriorUrad = 1000.0;

double parse_double(const std::string& text, const std::string& what) {
  double v = 0.0;
  std::string t = text;
  while (!t.empty() && t.front() == ' ') t.erase(0, 1);
  while (!t.empty() && t.back() == ' ') t.pop_back();
  if (!t.empty() && t.front() == '+') t.erase(0, 1);
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size() || !std::isfinite(v))
    throw std::invalid_argument(what + ": '" + text + "' is not a finite number");
  return v;
}

/// "X=0,1200" → axis index and range; throws std::invalid_argument (usage error).
std::pair<int, em::AxisRange> parse_axis_range(const std::string& text) {
  const auto eq = text.find('=');
  const auto comma = text.find(',', eq == std::string::npos ? 0 : eq);
  if (eq == std::string::npos || comma == std::string::npos)
    throw std::invalid_argument("--axis-range needs AXIS=MIN,MAX (mm), e.g. X=0,1200; got '" +
                                text + "'");
  const std::string axis = text.substr(0, eq);
  const int k = axis == "X" ? 0 : axis == "Y" ? 1 : axis == "Z" ? 2 : -1;
  if (k < 0) throw std::invalid_argument("--axis-range: unknown axis '" + axis + "' (X, Y or Z)");
  em::AxisRange r{parse_double(text.substr(eq + 1, comma - eq - 1), "--axis-range " + axis + " min"),
                  parse_double(text.substr(comma + 1), "--axis-range " + axis + " max")};
  if (!(r.min < r.max))
    throw std::invalid_argument("--axis-range " + axis + ": needs MIN < MAX; got '" + text + "'");
  return {k, r};
}

std::string shown(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

em::KinematicChain chain_from_name(const std::string& name) {
  if (name == "moving_bridge" || name == "gantry") return em::KinematicChain::moving_bridge();
  return em::KinematicChain::fixed_bridge();  // "fixed_bridge", "moving_table" (IsMember-checked)
}

std::string um(double mm) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4f", mm * 1e3);
  return b;
}

std::string format_report(const ch::KinematicCharacterization& r, const std::string& plate) {
  std::ostringstream os;
  char buf[256];
  os << "vcmm characterize hole-plate: " << plate << ", " << r.placements.size()
     << " placements, " << r.setups.size() << " setups\n";
  os << r.message << "\n";
  os << "probing sigma: given " << um(r.probing_sigma_given_mm) << " um, from residuals "
     << um(r.probing_sigma_from_residuals_mm) << " um; variance factor " << r.variance_factor
     << (r.covariance_scaled ? " > 1: covariance scaled by it\n" : " <= 1: covariance from the given sigma\n");
  os << "observations " << r.observations << ", unknowns " << r.unknowns << ", dof "
     << r.degrees_of_freedom << ", weakest kept direction " << r.weakest_direction << "\n";
  os << "\nparameter          status              value    std.unc.  (um or urad)\n";
  for (const auto& p : r.parameters) {
    const double unit = p.rotation ? 1e-6 : 1e-3;
    std::snprintf(buf, sizeof buf, "%-12s %-16s %10.4f %10.4f\n", p.name.c_str(),
                  std::string(ch::to_string(p.status)).c_str(), p.value / unit,
                  p.standard_uncertainty / unit);
    os << buf;
  }
  if (!r.null_directions.empty()) {
    os << "\ninvisible directions (coefficients in um/urad; pivot fixed at 0):\n";
    for (const auto& nd : r.null_directions)
      os << "  " << (nd.intrinsic ? "by convention   " : "NOT IDENTIFIED  ") << nd.text << "\n";
  }
  os << "\nplacement residuals:\n";
  for (const auto& p : r.placements) {
    std::snprintf(buf, sizeof buf, "  %-40s %3ld features  RMS %8.4f um\n", p.name.c_str(),
                  static_cast<long>(p.residuals_mm.cols()), p.rms_mm * 1e3);
    os << buf;
  }
  return os.str();
}

int run_hole_plate(const HolePlateOptions& o) {
  constexpr const char* kName = "vcmm characterize hole-plate";
  // 1. Options → exit 2.
  ch::HolePlateFitOptions options;
  std::map<int, em::AxisRange> ranges;
  std::map<int, int> degree_of;
  try {
    for (const std::string& d : o.degree_of) {
      const auto eq = d.find('=');
      int f = -1;
      for (int i = 0; i < em::axis_error_count && eq != std::string::npos; ++i)
        if (d.substr(0, eq) == em::name(static_cast<em::AxisError>(i))) f = i;
      if (f < 0)
        throw std::invalid_argument("--degree-of needs NAME=N with an ISO 230-1 name (E_XX … E_CZ); got '" + d + "'");
      const double n = parse_double(d.substr(eq + 1), "--degree-of " + d.substr(0, eq));
      if (n != std::floor(n) || n < 0 || n > em::max_legendre_degree)
        throw std::invalid_argument("--degree-of " + d + ": degree must be an integer 0 to " +
                                    std::to_string(em::max_legendre_degree));
      degree_of[f] = static_cast<int>(n);
    }
    for (const std::string& a : o.axis_ranges) {
      const auto [k, r] = parse_axis_range(a);
      if (ranges.count(k)) throw std::invalid_argument("--axis-range: axis given twice ('" + a + "')");
      ranges[k] = r;
    }
    if (o.model.empty() && ranges.size() != 3)
      throw std::invalid_argument("give --axis-range for X, Y and Z (or --model MODEL.json)");
    if (!std::isfinite(o.probing_sigma_um) || !(o.probing_sigma_um > 0.0) ||
        o.probing_sigma_um > kMaxProbingSigmaUm)
      throw std::invalid_argument("--probing-sigma-um must be a number of um in (0, 1000] "
                                  "(the repeatability of a feature centre); got " +
                                  shown(o.probing_sigma_um) + " um");
    if (!(o.prior_um >= 0.0 && o.prior_um <= kMaxPriorUm))
      throw std::invalid_argument("--prior-um must be a number of um in [0, 1000]; got " +
                                  shown(o.prior_um) + " um");
    if (!(o.prior_urad >= 0.0 && o.prior_urad <= kMaxPriorUrad))
      throw std::invalid_argument("--prior-urad must be a number of urad in [0, 1000]; got " +
                                  shown(o.prior_urad) + " urad");
  } catch (const std::invalid_argument& ex) {
    std::cerr << kName << ": error: " << ex.what() << "\n";
    return kUsage;
  }
  // 2. Files and the estimate → exit 3 (invalid input) / 4 (no usable result).
  try {
    if (!o.model.empty()) {
      const em::DigitalModel m = em::read_digital_model_file(o.model);
      options.chain = m.kinematics.chain();
      for (int k = 0; k < 3; ++k)
        options.axis_ranges[static_cast<std::size_t>(k)] = m.kinematics.range(static_cast<em::Axis>(k));
      options.degrees = ch::degrees_of(m.kinematics);
    } else {
      options.degrees = ch::uniform_degrees(2);
    }
    for (const auto& [k, r] : ranges) options.axis_ranges[static_cast<std::size_t>(k)] = r;
    if (!o.chain.empty()) options.chain = chain_from_name(o.chain);
    if (o.degree >= 0) options.degrees = ch::uniform_degrees(o.degree);
    for (const auto& [f, n] : degree_of) options.degrees[static_cast<std::size_t>(f)] = n;
    options.probing_sigma_mm = o.probing_sigma_um * 1e-3;
    options.rank_tolerance = o.rank_tolerance;
    options.unidentified_translation_u_mm = o.prior_um * 1e-3;
    options.unidentified_rotation_u_rad = o.prior_urad * 1e-6;

    std::vector<ch::InputFile> inputs{{"--plate", o.plate}};
    for (const std::string& p : o.placements) inputs.push_back({"--placement", p});
    ch::refuse_identical_inputs(inputs);
    const ch::HolePlate plate = ch::read_hole_plate_csv_file(o.plate);
    std::vector<ch::HolePlatePlacement> placements;
    for (const std::string& p : o.placements)
      placements.push_back(ch::read_hole_plate_placement_csv_file(p));
    const ch::KinematicCharacterization r = ch::estimate_kinematic_errors(placements, plate, options);
    std::cout << format_report(r, o.plate) << std::flush;
    if (!r.usable) {
      std::cerr << kName << ": error: no usable result: " << r.message << "\n";
      return kUndefined;
    }
    std::string source = "hole plate " + o.plate + "; placements";
    for (const std::string& p : o.placements) source += " " + p;
    const bool inconsistent = !r.consistency.passed();
    if (inconsistent && !o.accept_inconsistent) {
      std::cerr << kName << ": error: the calibration data are inconsistent with "
                << "--probing-sigma-um " << o.probing_sigma_um << " um and the plate's u (" << o.plate
                << "): " << r.consistency.summary()
                << "; check the named file (a blunder, a wrong '# setup:' label, a wrong "
                   "stylus offset) or, if sigma is too small, state it; --accept-inconsistent "
                   "writes the model anyway and records this; nothing written\n";
      return kInvalidInput;
    }
    if (inconsistent) {
      std::cerr << kName << ": warning: accepted although inconsistent (--accept-inconsistent): "
                << r.consistency.summary() << "\n";
      source += "; ACCEPTED ALTHOUGH INCONSISTENT (--accept-inconsistent): " + r.consistency.summary();
    }
    nlohmann::ordered_json out = nlohmann::ordered_json::object();
    out["kinematics"] = nlohmann::ordered_json::parse(ch::kinematics_json_section(r, source));
    OutputTransaction outputs;  // the model section and the report together or not at all
    outputs.stage(o.output, out.dump(2) + "\n");
    if (!o.report.empty())
      outputs.stage(o.report, ch::hole_plate_report_json(r, o.accept_inconsistent) + "\n");
    outputs.commit();
    std::cout << kName << ": wrote " << o.output << (o.report.empty() ? "" : " and " + o.report)
              << "\n";
    return kOk;
  } catch (const std::exception&) {  // 3 for invalid input, 1 otherwise
    return report_current_exception("characterize hole-plate");
  }
}

}  // namespace

void add_characterize_hole_plate_command(CLI::App& characterize, int* exit_code) {
  auto opts = std::make_shared<HolePlateOptions>();
  CLI::App* cmd = characterize.add_subcommand(
      "hole-plate",
      "kinematic errors (21 functions) from a calibrated hole/ball plate measured in several "
      "placements: writes the digital model's kinematics section");
  cmd->add_option("--plate", opts->plate, "plate calibration CSV: id,x_mm,y_mm,z_mm,u_um")
      ->required();
  cmd->add_option("--placement", opts->placements,
                  "placement CSV (repeatable): '# stylus_offset_mm: x, y, z', optional "
                  "'# setup: NAME', then id,x_mm,y_mm,z_mm")
      ->required();
  cmd->add_option("--probing-sigma-um", opts->probing_sigma_um,
                  "standard deviation of one coordinate of a measured feature centre (um)")
      ->required()
      ->check(physical_value(em::physical_range::length_sigma_um, /*open_below=*/true));
  cmd->add_option("--axis-range", opts->axis_ranges,
                  "travel of an axis, AXIS=MIN,MAX in mm (give X, Y and Z), e.g. X=0,1200");
  cmd->add_option("--model", opts->model,
                  "take chain, axis ranges and degrees from this digital-model file's kinematics");
  cmd->add_option("--chain", opts->chain, "kinematic chain (default moving_bridge)")
      ->check(CLI::IsMember({"moving_bridge", "gantry", "fixed_bridge", "moving_table"}));
  cmd->add_option("--degree", opts->degree,
                  "Legendre degree of all 18 error functions (default 2, or the --model's)")
      ->check(CLI::Range(0, em::max_legendre_degree));
  cmd->add_option("--degree-of", opts->degree_of, "degree of one function, NAME=N (repeatable)");
  cmd->add_option("--rank-tolerance", opts->rank_tolerance,
                  "relative singular value below which a direction counts as invisible")
      ->check(CLI::Range(1e-15, 0.5))
      ->default_val(1e-3);
  cmd->add_option("--prior-um", opts->prior_um,
                  "a-priori u written for not-identifiable translation coefficients (um)")
      ->check(CLI::NonNegativeNumber)
      ->default_val(1.0);
  cmd->add_option("--prior-urad", opts->prior_urad,
                  "a-priori u written for not-identifiable rotation/squareness coefficients (urad)")
      ->check(CLI::NonNegativeNumber)
      ->default_val(1.0);
  cmd->add_option("-o,--output", opts->output,
                  "output JSON {\"kinematics\": {...}} (written atomically)")
      ->required();
  cmd->add_option("--json", opts->report, "also write the diagnostics report as JSON here");
  cmd->add_flag("--accept-inconsistent", opts->accept_inconsistent,
                "write the model even when the residuals fail the consistency test (chi2 or an "
                "outlier at the 1 % level); the verdict is recorded in the output");
  cmd->callback([opts, exit_code] { *exit_code = run_hole_plate(*opts); });
}

}  // namespace vcmm::cli
