// `vcmm roundness FILE... [--filter-upr N|none] [--reference LS|MZ|MI|MC|all] [--harmonics N]
//                         [--unit mm|um|in] [--json] [--threads T] [-o OUT]`
// One file: a table (or one JSON object) with every requested reference circle, or the reason
// it is undefined. Several files or a directory (its *.csv files): one CSV row (or one JSON
// line) per file, evaluated in parallel, a failing file an error row (docs/cli.md).
#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "atomic_file.h"
#include "commands.h"
#include "json_output.h"
#include "option_values.h"
#include "run_control.h"
#include "vcmm/geometry/certificate.h"
#include "vcmm/geometry/point_io.h"
#include "vcmm/geometry/profile_harmonics.h"
#include "vcmm/geometry/roundness.h"

namespace vcmm::cli {
namespace {

namespace g = vcmm::geometry;
namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

struct RoundnessOptions {
  std::vector<std::string> files;
  std::string filter = "none";
  bool no_filter = false;
  std::string reference = "all";
  std::size_t harmonics = 0;
  std::string unit = "mm";
  bool json = false;
  unsigned threads = 0;
  std::string output;
};

/// What the command needs to know, parsed once from the options.
struct Plan {
  g::RoundnessRequest request;
  std::size_t harmonics = 0;
  double to_mm = 1.0;
};

/// One file's outcome: its exit code (0, 3 invalid input, 4 no requested circle defined, 1 a
/// bug) and either the evaluation or the error message.
struct FileResult {
  std::string file;
  int exit_code = kOk;
  std::string error;
  std::vector<g::Point2> points;  // the input in mm
  g::RoundnessEvaluation evaluation;
  std::optional<g::ProfileHarmonics> harmonics;

  std::span<const g::Point2> profile() const {
    return evaluation.filtered_points.empty() ? std::span<const g::Point2>(points)
                                              : std::span<const g::Point2>(
                                                    evaluation.filtered_points);
  }
};

constexpr double kDeg = 180.0 / std::numbers::pi;

FileResult evaluate_file(const std::string& file, const Plan& plan) {
  FileResult r;
  r.file = file;
  try {
    const g::PointTable table = g::read_points_csv_file(file);
    r.points = table.points;
    if (plan.to_mm != 1.0)
      for (g::Point2& p : r.points) p = {p.x * plan.to_mm, p.y * plan.to_mm};
    r.evaluation = g::evaluate_roundness(r.points, plan.request);
    if (plan.harmonics > 0) {
      const auto profile = r.profile();
      const g::LeastSquaresCircle ls = g::least_squares_circle(profile);
      const std::size_t order = std::min(plan.harmonics, profile.size() / 2);
      r.harmonics.emplace(profile, ls.center, ls.radius, order);
    }
    r.exit_code = r.evaluation.defined_count() > 0 ? kOk : kUndefined;
  } catch (const std::exception& e) {
    r.exit_code = exit_code_of(e);
    r.error = error_text(e);
  }
  return r;
}

std::string list(const std::vector<std::size_t>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + std::to_string(v[i]);
  return s;
}

std::string fixed(double v, int digits = 12) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}

template <class Circle>
std::string proof_of(std::span<const g::Point2> profile, const Circle& circle) {
  const bool ok = g::verify(profile, circle).valid;
  std::string s = ok ? "certified, " : "NOT VERIFIED, ";
  s += circle.certificate.optimality == g::Optimality::global ? "global" : "local";
  return s;
}

std::string format_table(const FileResult& r) {
  const g::RoundnessEvaluation& e = r.evaluation;
  const auto profile = r.profile();
  std::ostringstream os;
  char buf[512];
  os << "vcmm roundness: " << r.file << " — " << e.n_points << " points, ";
  if (e.filter_cutoff_upr)
    os << "Gaussian filter " << *e.filter_cutoff_upr << " UPR (ISO 16610-21"
       << (e.filter_path == g::FilterPath::open_profile ? ", open profile: a partial arc" : "")
       << ")\n";
  else
    os << "unfiltered\n";
  std::snprintf(buf, sizeof buf, "coverage %.2f° (largest gap %.2f°)%s\n",
                e.coverage.covered_rad * kDeg, e.coverage.largest_gap_rad * kDeg,
                e.coverage.closed ? ", closed profile" : ", partial arc");
  os << buf;
  os << "lengths in mm; RON in µm\n";
  std::snprintf(buf, sizeof buf, "%-3s %19s %19s %19s %10s %10s %10s %10s  %-20s %s\n", "ref",
                "centre x", "centre y", "radius", "RONt", "RONp", "RONv", "RONq", "contacts",
                "proof");
  os << buf;
  auto row = [&](g::ReferenceCircle which, g::Point2 c, const std::string& radius,
                 const g::RoundnessParameters& ron, const std::string& contacts,
                 const std::string& proof) {
    std::snprintf(buf, sizeof buf,
                  "%-3s %19.12f %19.12f %19s %10.4f %10.4f %10.4f %10.4f  %-20s %s\n",
                  std::string(g::to_string(which)).c_str(), c.x, c.y, radius.c_str(),
                  ron.ront * 1e3, ron.ronp * 1e3, ron.ronv * 1e3, ron.ronq * 1e3,
                  contacts.c_str(), proof.c_str());
    os << buf;
    if (const auto c2 = e.cautions.find(which); c2 != e.cautions.end())
      os << "    caution: " << c2->second << "\n";
  };
  for (const g::ReferenceCircle which :
       {g::ReferenceCircle::least_squares, g::ReferenceCircle::minimum_zone,
        g::ReferenceCircle::maximum_inscribed, g::ReferenceCircle::minimum_circumscribed}) {
    if (const auto u = e.undefined.find(which); u != e.undefined.end()) {
      os << std::string(g::to_string(which)) << "  undefined: " << user_message(u->second) << "\n";
      continue;
    }
    switch (which) {
      case g::ReferenceCircle::least_squares:
        if (e.least_squares)
          row(which, e.least_squares->center, fixed(e.least_squares->radius),
              e.least_squares->ron, list(e.least_squares->contacts), "numerical fit");
        break;
      case g::ReferenceCircle::minimum_zone:
        if (e.minimum_zone) {
          const auto& m = *e.minimum_zone;
          row(which, m.center, fixed(0.5 * (m.inner_radius + m.outer_radius)), m.ron,
              "o:" + list(m.outer_contacts) + " i:" + list(m.inner_contacts),
              proof_of(profile, m));
        }
        break;
      case g::ReferenceCircle::maximum_inscribed:
        if (e.maximum_inscribed)
          row(which, e.maximum_inscribed->center, fixed(e.maximum_inscribed->radius),
              e.maximum_inscribed->ron, list(e.maximum_inscribed->contacts),
              proof_of(profile, *e.maximum_inscribed));
        break;
      case g::ReferenceCircle::minimum_circumscribed:
        if (e.minimum_circumscribed)
          row(which, e.minimum_circumscribed->center, fixed(e.minimum_circumscribed->radius),
              e.minimum_circumscribed->ron, list(e.minimum_circumscribed->contacts),
              proof_of(profile, *e.minimum_circumscribed));
        break;
    }
  }
  if (e.minimum_zone)
    os << "MZ radius column: mean of inner " << fixed(e.minimum_zone->inner_radius)
       << " and outer " << fixed(e.minimum_zone->outer_radius) << "\n";
  if (r.harmonics) {
    os << "harmonics of the radial deviation about the LS circle (amplitude A_k in µm, phase in "
          "degrees: A_k cos(kθ − φ_k))\n";
    for (std::size_t k = 1; k <= r.harmonics->max_order(); ++k) {
      const double a = r.harmonics->cos_mm(k), b = r.harmonics->sin_mm(k);
      std::snprintf(buf, sizeof buf, "  %4zu %12.5f %9.2f\n", k, std::hypot(a, b) * 1e3,
                    std::atan2(b, a) * kDeg);
      os << buf;
    }
  }
  return os.str();
}

json result_json(const FileResult& r) {
  json j;
  j["schema"] = kRoundnessSchema;
  j["schema_version"] = kRoundnessSchemaVersion;
  j["file"] = r.file;
  j["unit"] = "mm";
  if (!r.error.empty()) {
    j["status"] = "error";
    j["error"] = r.error;
    return j;
  }
  j["status"] = r.exit_code == kOk ? "ok" : "undefined";
  j.update(to_json(r.profile(), r.evaluation));
  if (r.harmonics) j["harmonics"] = harmonics_json(*r.harmonics);
  return j;
}

// ---- batch CSV: one row per file -----------------------------------------------------------

std::string number(double v) { return fixed(v, 12); }

constexpr const char* kCsvHeader =
    "file,status,n_points,filter_upr,covered_deg,closed,"
    "LS_x_mm,LS_y_mm,LS_radius_mm,LS_RONt_mm,"
    "MZ_x_mm,MZ_y_mm,MZ_inner_radius_mm,MZ_outer_radius_mm,MZ_RONt_mm,MZ_certified,"
    "MI_x_mm,MI_y_mm,MI_radius_mm,MI_RONt_mm,MI_certified,"
    "MC_x_mm,MC_y_mm,MC_radius_mm,MC_RONt_mm,MC_certified,message\n";

std::string csv_row(const FileResult& r) {
  std::string row = csv_cell(r.file) + ",";
  if (!r.error.empty())
    return row + "error" + std::string(25, ',') + csv_cell(r.error) + "\n";
  const g::RoundnessEvaluation& e = r.evaluation;
  const auto profile = r.profile();
  row += std::string(r.exit_code == kOk ? "ok" : "undefined") + "," +
         std::to_string(e.n_points) + "," +
         (e.filter_cutoff_upr ? number(*e.filter_cutoff_upr) : std::string("none")) + "," +
         fixed(e.coverage.covered_rad * kDeg, 6) + "," + (e.coverage.closed ? "true" : "false");
  const auto blank = [&row](int cells) { row += std::string(static_cast<std::size_t>(cells), ','); };
  if (e.least_squares)
    row += "," + number(e.least_squares->center.x) + "," + number(e.least_squares->center.y) +
           "," + number(e.least_squares->radius) + "," + number(e.least_squares->ron.ront);
  else
    blank(4);
  if (e.minimum_zone) {
    const auto& m = *e.minimum_zone;
    row += "," + number(m.center.x) + "," + number(m.center.y) + "," + number(m.inner_radius) +
           "," + number(m.outer_radius) + "," + number(m.ron.ront) + "," +
           (g::verify(profile, m).valid ? "true" : "false");
  } else {
    blank(6);
  }
  const auto single = [&](const auto& c) {
    if (c)
      row += "," + number(c->center.x) + "," + number(c->center.y) + "," + number(c->radius) +
             "," + number(c->ron.ront) + "," + (g::verify(profile, *c).valid ? "true" : "false");
    else
      blank(5);
  };
  single(e.maximum_inscribed);
  single(e.minimum_circumscribed);
  std::string message;
  for (const auto& [circle, reason] : e.undefined)
    message += (message.empty() ? "" : "; ") + std::string(g::to_string(circle)) +
               " undefined: " + user_message(reason);
  for (const auto& [circle, caution] : e.cautions)
    message += (message.empty() ? "" : "; ") + std::string(g::to_string(circle)) + ": " + caution;
  return row + "," + csv_cell(message) + "\n";
}

// ---- the command -----------------------------------------------------------------------------

/// FILE arguments, a directory replaced by its *.csv files (sorted by name).
std::vector<std::string> expand_inputs(const std::vector<std::string>& args, bool& batch) {
  std::vector<std::string> files;
  batch = args.size() > 1;
  for (const std::string& a : args) {
    std::error_code ec;
    if (a != "-" && fs::is_directory(a, ec)) {
      batch = true;
      std::vector<std::string> found;
      for (const auto& entry : fs::directory_iterator(a, ec))
        if (entry.is_regular_file() && entry.path().extension() == ".csv")
          found.push_back(entry.path().string());
      if (ec) throw errormodel::OutputError(a + ": cannot list the directory: " + ec.message());
      // An empty table with exit 0 would read as "all profiles passed".
      if (found.empty())
        throw g::InvalidInput(a + ": the directory holds no profile (*.csv) files");
      std::sort(found.begin(), found.end());
      files.insert(files.end(), found.begin(), found.end());
    } else {
      files.push_back(a);
    }
  }
  return files;
}

int run_roundness(const RoundnessOptions& o) {
  Plan plan;
  try {
    const std::string circle = upper_case(o.reference);
    const bool all = circle == "ALL";
    plan.request.least_squares = all || circle == "LS";
    plan.request.minimum_zone = all || circle == "MZ";
    plan.request.maximum_inscribed = all || circle == "MI";
    plan.request.minimum_circumscribed = all || circle == "MC";
    if (!all && !g::reference_circle_from_string(circle))
      throw std::invalid_argument("--reference must be LS, MZ, MI, MC or all; got '" +
                                  o.reference + "'");
    if (!o.no_filter) plan.request.filter_cutoff_upr = parse_filter_upr(o.filter);
    plan.harmonics = o.harmonics;
    plan.to_mm = millimetres_per_unit(o.unit);
  } catch (const std::invalid_argument& ex) {
    std::cerr << "vcmm roundness: error: " << ex.what() << "\n";
    return kUsage;
  }
  try {
    bool batch = false;
    const std::vector<std::string> files = expand_inputs(o.files, batch);
    if (!batch) {
      const FileResult r = evaluate_file(files.at(0), plan);
      if (!r.error.empty()) {
        std::cerr << "vcmm roundness: error: " << r.error << "\n";
        return r.exit_code;
      }
      const std::string text = o.json ? result_json(r).dump(2) + "\n" : format_table(r);
      if (o.output.empty())
        std::cout << text << std::flush;
      else
        write_file_atomically(o.output, text);
      if (r.exit_code == kUndefined)
        std::cerr << "vcmm roundness: no requested reference circle is defined for "
                  << r.file << "\n";
      return r.exit_code;
    }
    // Batch: files in parallel (each evaluation is independent), output in input order.
    std::vector<std::string> out(files.size());
    std::vector<int> codes(files.size(), kOk);
    std::atomic<std::size_t> next{0};
    const unsigned threads = std::max(
        1u, std::min<unsigned>(o.threads ? o.threads : std::thread::hardware_concurrency(),
                               static_cast<unsigned>(files.size())));
    auto worker = [&] {
      for (std::size_t i = next++; i < files.size(); i = next++) {
        const FileResult r = evaluate_file(files[i], plan);
        codes[i] = r.exit_code;
        out[i] = o.json ? result_json(r).dump() + "\n" : csv_row(r);
      }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
    std::string text = o.json ? std::string() : std::string(kCsvHeader);
    for (const std::string& line : out) text += line;
    if (o.output.empty())
      std::cout << text << std::flush;
    else
      write_file_atomically(o.output, text);
    // The most severe outcome: a bug, then invalid input, then no circle defined.
    int worst = kOk;
    for (int c : codes) {
      if (c == kFailure) worst = kFailure;
      else if (c == kInvalidInput && worst != kFailure) worst = kInvalidInput;
      else if (c == kUndefined && worst == kOk) worst = kUndefined;
    }
    const std::size_t failed =
        static_cast<std::size_t>(std::count_if(codes.begin(), codes.end(),
                                               [](int c) { return c != kOk; }));
    if (failed > 0)
      std::cerr << "vcmm roundness: " << failed << " of " << files.size()
                << " files gave no result (error rows in the output)\n";
    return worst;
  } catch (const std::exception&) {
    return report_current_exception("roundness");
  }
}

}  // namespace

void add_roundness_command(CLI::App& app, int* exit_code) {
  auto opts = std::make_shared<RoundnessOptions>();
  CLI::App* cmd = app.add_subcommand(
      "roundness", "ISO 12181-2 reference circles (LS, MZ, MI, MC) and RONt/p/v/q of profiles");
  cmd->add_option("FILE", opts->files,
                  "profile CSV(s): x,y or x,y,z; '-' for stdin; a directory: its *.csv files "
                  "(several files or a directory: one CSV row or JSON line per file)")
      ->required();
  auto* filter = cmd->add_option("--filter-upr", opts->filter,
                                 "ISO 16610-21 Gaussian filter cut-off in undulations per "
                                 "revolution (15, 50, 150, 500, 1500), or 'none' (default)")
                     ->default_val("none");
  auto* nofilter = cmd->add_flag("--no-filter", opts->no_filter, "evaluate unfiltered (default)");
  filter->excludes(nofilter);
  cmd->add_option("--reference", opts->reference,
                  "reference circle(s): LS, MZ, MI, MC or all (any case)")
      ->check(CLI::IsMember({"LS", "MZ", "MI", "MC", "all"}, CLI::ignore_case))
      ->default_val("all");
  cmd->add_option("--harmonics", opts->harmonics,
                  "also report the amplitude and phase of harmonics 1..N about the LS circle")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100000}));
  cmd->add_option("--unit", opts->unit, "unit of the input coordinates: mm (default), um, in")
      ->check(CLI::IsMember({"mm", "um", "in"}))
      ->default_val("mm");
  cmd->add_flag("--json", opts->json, "JSON: one object (one file) or one line per file");
  cmd->add_option("--threads", opts->threads, "batch: files evaluated at once (default: cores)")
      ->check(thread_count())
      ->default_val(0);
  cmd->add_option("-o,--output", opts->output, "write the result to this file (atomically)");
  cmd->callback([opts, exit_code] { *exit_code = run_roundness(*opts); });
}

}  // namespace vcmm::cli
