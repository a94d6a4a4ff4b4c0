// `vcmm check FILE --reference MZ|MI|MC|LS --center X,Y [--radii R1[,R2]] [--filter-upr N|none]
//            [--unit mm|um|in] [--json] [-o OUT]`
// `vcmm check --claims CLAIMS.csv [--filter-upr N|none] [--unit ...] [--json] [-o OUT]`
// Checks a reference circle another program reported against the exact one: feasible?
// optimal? by how much does its RONt exceed the exact RONt? (geometry/claim_check.h,
// docs/cli.md).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "atomic_file.h"
#include "commands.h"
#include "option_values.h"
#include "run_control.h"
#include "vcmm/geometry/text_file.h"
#include "vcmm/geometry/claim_check.h"
#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/point_io.h"

namespace vcmm::cli {
namespace {

namespace g = vcmm::geometry;
namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

struct CheckOptions {
  std::string file, claims, reference, center, radii, filter = "none", unit = "mm", output;
  bool json = false;
};

struct Settings {
  std::optional<double> filter_upr;
  double to_mm = 1.0;
};

std::vector<double> numbers(const std::string& text, const std::string& option) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || item.empty() || !std::isfinite(v))
      throw std::invalid_argument(option + ": '" + item + "' is not a finite number");
    out.push_back(v);
  }
  return out;
}

/// Half a unit in the last decimal written of a number's text ("412.500019249398" → 5e-13;
/// "1.25e2" → 0.5): the resolution of a value another program printed.
double half_unit_in_last_place(const std::string& text) {
  const std::size_t e = text.find_first_of("eE");
  const std::string mantissa = text.substr(0, e);
  const int exponent = e == std::string::npos ? 0 : std::stoi(text.substr(e + 1));
  const std::size_t dot = mantissa.find('.');
  const int decimals = dot == std::string::npos ? 0 : static_cast<int>(mantissa.size() - dot - 1);
  return 0.5 * std::pow(10.0, exponent - decimals);
}

/// The resolution of a claimed centre "X,Y": the coarser of the two coordinates'.
double resolution_of(const std::string& x, const std::string& y) {
  return std::max(half_unit_in_last_place(x), half_unit_in_last_place(y));
}

g::ReferenceCircle circle_of(std::string name, const std::string& where) {
  name = upper_case(name);
  const auto c = g::reference_circle_from_string(name);
  if (!c) throw std::invalid_argument(where + ": reference must be MZ, MI, MC or LS; got '" +
                                      name + "'");
  return *c;
}

/// Builds the claim from centre and radius texts (mm after scaling).
g::ClaimedCircle make_claim(g::ReferenceCircle reference, const std::vector<double>& center,
                            const std::vector<double>& radii, double to_mm,
                            const std::string& where) {
  if (center.size() != 2)
    throw std::invalid_argument(where + ": the centre needs 2 numbers X,Y; got " +
                                std::to_string(center.size()));
  g::ClaimedCircle claim;
  claim.reference = reference;
  claim.center = {center[0] * to_mm, center[1] * to_mm};
  if (radii.size() == 1) {
    if (reference == g::ReferenceCircle::minimum_zone)
      throw std::invalid_argument(where + ": MZ needs two radii (inner,outer)");
    claim.radii = std::pair{radii[0] * to_mm, radii[0] * to_mm};
  } else if (radii.size() == 2) {
    if (reference != g::ReferenceCircle::minimum_zone)
      throw std::invalid_argument(where + ": " + std::string(g::to_string(reference)) +
                                  " takes one radius");
    claim.radii = std::pair{radii[0] * to_mm, radii[1] * to_mm};
  } else if (!radii.empty()) {
    throw std::invalid_argument(where + ": at most two radii");
  }
  return claim;
}

struct Outcome {
  std::string file;
  g::ClaimedCircle claim;
  int exit_code = kOk;
  std::string error;
  g::ClaimCheck check;
};

Outcome run_check(const std::string& file, const g::ClaimedCircle& claim, const Settings& s) {
  Outcome o;
  o.file = file;
  o.claim = claim;
  try {
    g::PointTable table = g::read_points_csv_file(file);
    std::vector<g::Point2> pts = table.points;
    if (s.to_mm != 1.0)
      for (g::Point2& p : pts) p = {p.x * s.to_mm, p.y * s.to_mm};
    if (s.filter_upr) pts = g::gaussian_filtered_profile(pts, *s.filter_upr).points;
    o.check = g::check_claimed_circle(pts, claim);
    o.exit_code = o.check.optimal ? kOk : kClaimFails;
  } catch (const std::exception& e) {
    o.exit_code = exit_code_of(e);
    o.error = error_text(e);
  }
  return o;
}

std::string verdict(const Outcome& o) {
  if (!o.error.empty()) return "error";
  if (!o.check.feasible) return "infeasible";
  return o.check.optimal ? "optimal" : "not_optimal";
}

json outcome_json(const Outcome& o) {
  json j;
  j["schema"] = "vcmm.check_result";
  j["schema_version"] = 1;
  j["file"] = o.file;
  j["unit"] = "mm";
  j["reference"] = std::string(g::to_string(o.claim.reference));
  j["verdict"] = verdict(o);
  if (!o.error.empty()) {
    j["error"] = o.error;
    return j;
  }
  const g::ClaimCheck& c = o.check;
  j["claim"] = {{"center", {o.claim.center.x, o.claim.center.y}},
                {"center_resolution", o.claim.center_resolution_mm},
                {"inner_radius", c.claimed_inner_radius},
                {"outer_radius", c.claimed_outer_radius},
                {"radii_given", c.radii_given}};
  j["feasible"] = c.feasible;
  j["violations"] = c.violations;
  j["violating_points"] = c.violating;
  j["optimal"] = c.optimal;
  j["claimed_RONt"] = c.claimed_ront;
  j["exact_RONt"] = c.exact_ront;
  j["excess_RONt"] = c.excess_ront;
  j["radius_excess"] = c.radius_excess;
  j["center_distance"] = c.center_distance;
  j["tolerance"] = c.tolerance;
  j["radius_tolerance"] = c.radius_tolerance;
  j["exact"] = {{"center", {c.exact_center.x, c.exact_center.y}},
                {"inner_radius", c.exact_inner_radius},
                {"outer_radius", c.exact_outer_radius},
                {"contacts", c.exact_contacts},
                {"certified", c.exact_certified},
                {"certificate", c.exact_certificate}};
  return j;
}

std::string outcome_text(const Outcome& o) {
  std::ostringstream os;
  char b[512];
  std::snprintf(b, sizeof b, " claimed at (%.17g, %.17g), resolution %.1e mm\n",
                o.claim.center.x, o.claim.center.y, o.claim.center_resolution_mm);
  os << "vcmm check: " << o.file << " — " << g::to_string(o.claim.reference) << b;
  if (!o.error.empty()) {
    os << "  error: " << o.error << "\n";
    return os.str();
  }
  const g::ClaimCheck& c = o.check;
  std::snprintf(b, sizeof b, "  claimed radii    %.12f, %.12f mm (%s)\n", c.claimed_inner_radius,
                c.claimed_outer_radius, c.radii_given ? "given" : "the tightest for the centre");
  os << b;
  os << "  feasible         " << (c.feasible ? "yes" : "NO") << " (" << c.violations
     << " point(s) break the containment rule";
  for (std::size_t k = 0; k < c.violating.size(); ++k) os << (k ? ", " : ": ") << c.violating[k];
  os << ")\n";
  std::snprintf(b, sizeof b,
                "  RONt             claimed %.6f µm, exact %.6f µm, excess %.6f µm "
                "(tolerance %.2e µm)\n",
                c.claimed_ront * 1e3, c.exact_ront * 1e3, c.excess_ront * 1e3,
                c.tolerance * 1e3);
  os << b;
  if (o.claim.reference == g::ReferenceCircle::maximum_inscribed ||
      o.claim.reference == g::ReferenceCircle::minimum_circumscribed) {
    std::snprintf(b, sizeof b, "  radius           %s by %.6f µm\n",
                  o.claim.reference == g::ReferenceCircle::maximum_inscribed
                      ? "short of the exact MI"
                      : "above the exact MC",
                  c.radius_excess * 1e3);
    os << b;
  }
  std::snprintf(b, sizeof b, "  exact circle     centre (%.12f, %.12f), radii %.12f, %.12f mm, "
                             "%s\n",
                c.exact_center.x, c.exact_center.y, c.exact_inner_radius, c.exact_outer_radius,
                c.exact_certified ? "certified" : "not certified");
  os << b;
  std::string contacts;
  for (std::size_t k = 0; k < c.exact_contacts.size(); ++k)
    contacts += (k ? "," : "") + std::to_string(c.exact_contacts[k]);
  std::snprintf(b, sizeof b, "  exact contacts   %s; centre %.3e mm from the claim\n",
                contacts.c_str(), c.center_distance);
  os << b;
  os << "  verdict          " << verdict(o) << "\n";
  return os.str();
}

constexpr const char* kCsvHeader =
    "file,reference,verdict,feasible,optimal,violations,claimed_RONt_mm,exact_RONt_mm,"
    "excess_RONt_mm,radius_excess_mm,center_distance_mm,tolerance_mm,exact_x_mm,exact_y_mm,"
    "exact_inner_radius_mm,exact_outer_radius_mm,exact_contacts,message\n";

std::string outcome_csv(const Outcome& o) {
  auto n = [](double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return std::string(b);
  };
  std::string row = csv_cell(o.file) + "," + std::string(g::to_string(o.claim.reference)) + "," +
                    verdict(o) + ",";
  if (!o.error.empty()) return row + std::string(14, ',') + csv_cell(o.error) + "\n";
  const g::ClaimCheck& c = o.check;
  std::string contacts;
  for (std::size_t k = 0; k < c.exact_contacts.size(); ++k)
    contacts += (k ? " " : "") + std::to_string(c.exact_contacts[k]);
  return row + (c.feasible ? "true," : "false,") + (c.optimal ? "true," : "false,") +
         std::to_string(c.violations) + "," + n(c.claimed_ront) + "," + n(c.exact_ront) + "," +
         n(c.excess_ront) + "," + n(c.radius_excess) + "," + n(c.center_distance) + "," +
         n(c.tolerance) + "," + n(c.exact_center.x) + "," + n(c.exact_center.y) + "," +
         n(c.exact_inner_radius) + "," + n(c.exact_outer_radius) + "," + contacts + ",\n";
}

/// The claims file: CSV `file,reference,center_x,center_y[,radius_1[,radius_2]]` with a header
/// line, `#` comments; paths relative to the claims file's directory.
std::vector<std::pair<std::string, g::ClaimedCircle>> read_claims(const std::string& path,
                                                                  double to_mm) {
  std::istringstream in(g::read_text_file(path, "claims file"));
  const fs::path base = fs::path(path).parent_path();
  std::vector<std::pair<std::string, g::ClaimedCircle>> out;
  std::string line;
  std::size_t number = 0;
  bool header = true;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      header = false;
      if (line.rfind("file,", 0) == 0) continue;
    }
    std::vector<std::string> f;
    std::stringstream ss(line);
    std::string item;
    while (std::getline(ss, item, ',')) f.push_back(item);
    const std::string where = path + ":" + std::to_string(number);
    if (f.size() < 4 || f.size() > 6)
      throw std::invalid_argument(where + ": expected file,reference,center_x,center_y"
                                  "[,radius[,outer_radius]]; got " + std::to_string(f.size()) +
                                  " fields");
    std::vector<double> radii;
    for (std::size_t k = 4; k < f.size(); ++k)
      if (!f[k].empty()) radii.push_back(numbers(f[k], where).at(0));
    const fs::path file = fs::path(f[0]).is_absolute() ? fs::path(f[0]) : base / f[0];
    out.emplace_back(file.string(),
                     make_claim(circle_of(f[1], where),
                                {numbers(f[2], where).at(0), numbers(f[3], where).at(0)}, radii,
                                to_mm, where));
    out.back().second.center_resolution_mm = to_mm * resolution_of(f[2], f[3]);
  }
  return out;
}

int run(const CheckOptions& o) {
  Settings s;
  std::vector<std::pair<std::string, g::ClaimedCircle>> claims;
  try {
    s.to_mm = millimetres_per_unit(o.unit);
    s.filter_upr = parse_filter_upr(o.filter);
    if (o.claims.empty()) {
      if (o.file.empty() || o.reference.empty() || o.center.empty())
        throw std::invalid_argument("give FILE with --reference and --center, or --claims CSV");
      claims.emplace_back(o.file, make_claim(circle_of(o.reference, "--reference"),
                                             numbers(o.center, "--center"),
                                             o.radii.empty() ? std::vector<double>{}
                                                             : numbers(o.radii, "--radii"),
                                             s.to_mm, "the claim"));
      const std::size_t comma = o.center.find(',');
      claims.back().second.center_resolution_mm =
          s.to_mm * resolution_of(o.center.substr(0, comma), o.center.substr(comma + 1));
    } else if (!o.file.empty() || !o.center.empty()) {
      throw std::invalid_argument("--claims excludes FILE and --center");
    }
  } catch (const std::invalid_argument& e) {
    std::cerr << "vcmm check: error: " << e.what() << "\n";
    return kUsage;
  }
  try {
    if (!o.claims.empty()) claims = read_claims(o.claims, s.to_mm);
    std::string text = o.json || o.claims.empty() ? std::string() : std::string(kCsvHeader);
    int worst = kOk;
    for (const auto& [file, claim] : claims) {
      const Outcome r = run_check(file, claim, s);
      if (o.claims.empty() && (r.exit_code == kInvalidInput || r.exit_code == kFailure ||
                               r.exit_code == kUndefined)) {
        std::cerr << "vcmm check: error: " << r.error << "\n";
        return r.exit_code;
      }
      if (o.json)
        text += o.claims.empty() ? outcome_json(r).dump(2) + "\n" : outcome_json(r).dump() + "\n";
      else
        text += o.claims.empty() ? outcome_text(r) : outcome_csv(r);
      const auto rank = [](int c) {
        return c == kFailure ? 5 : c == kInvalidInput ? 4 : c == kUndefined ? 3
                                   : c == kClaimFails ? 2 : 0;
      };
      if (rank(r.exit_code) > rank(worst)) worst = r.exit_code;
    }
    if (o.output.empty())
      std::cout << text << std::flush;
    else
      write_file_atomically(o.output, text);
    return worst;
  } catch (const std::exception&) {
    return report_current_exception("check");
  }
}

}  // namespace

void add_check_command(CLI::App& app, int* exit_code) {
  auto o = std::make_shared<CheckOptions>();
  CLI::App* cmd = app.add_subcommand(
      "check", "check another program's reference circle against the exact one: feasible, "
               "optimal, excess RONt");
  cmd->add_option("FILE", o->file, "profile CSV (x,y or x,y,z)");
  cmd->add_option("--reference", o->reference, "the claimed circle: MZ, MI, MC or LS");
  cmd->add_option("--center", o->center, "the claimed centre X,Y");
  cmd->add_option("--radii", o->radii,
                  "the claimed radii: MZ inner,outer; MI, MC, LS one radius (default: the "
                  "tightest for the centre)");
  cmd->add_option("--claims", o->claims,
                  "CSV of claims: file,reference,center_x,center_y[,radius[,outer_radius]] "
                  "(one output row or JSON line per claim)");
  cmd->add_option("--filter-upr", o->filter,
                  "ISO 16610-21 Gaussian filter (UPR) applied before the check, or 'none'")
      ->default_val("none");
  cmd->add_option("--unit", o->unit, "unit of the coordinates and claims: mm (default), um, in")
      ->check(CLI::IsMember({"mm", "um", "in"}))
      ->default_val("mm");
  cmd->add_flag("--json", o->json, "JSON (one object, or one line per claim)");
  cmd->add_option("-o,--output", o->output, "write the result to this file (atomically)");
  cmd->callback([o, exit_code] { *exit_code = run(*o); });
}

}  // namespace vcmm::cli
