// `vcmm roundness FILE [--filter-upr N | --no-filter] [--reference LS|MZ|MI|MC|all]
//                      [--json] [-o OUT]`
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include "atomic_file.h"
#include "commands.h"
#include "json_output.h"
#include "vcmm/geometry/point_io.h"
#include "vcmm/geometry/roundness.h"

namespace vcmm::cli {
namespace {

namespace g = vcmm::geometry;

struct RoundnessOptions {
  std::string file;
  double filter_upr = 0.0;
  bool no_filter = false;
  std::string reference = "all";
  bool json = false;
  std::string output;
};

std::string format_table(const std::string& file, std::span<const g::Point2> profile,
                         const g::RoundnessEvaluation& e) {
  std::ostringstream os;
  char buf[512];
  os << "vcmm roundness: " << file << " — " << e.n_points << " points, ";
  if (e.filter_cutoff_upr)
    os << "Gaussian filter " << *e.filter_cutoff_upr << " UPR (ISO 16610-21)\n";
  else
    os << "unfiltered\n";
  os << "lengths in the input's unit (mm); RON in µm\n";
  std::snprintf(buf, sizeof buf, "%-3s %19s %19s %19s %10s %10s %10s %10s  %-20s %s\n", "ref",
                "centre x", "centre y", "radius", "RONt", "RONp", "RONv", "RONq", "contacts",
                "proof");
  os << buf;
  auto row = [&](const char* name, g::Point2 c, const std::string& radius,
                 const g::RoundnessParameters& r, const std::string& contacts,
                 const std::string& proof) {
    std::snprintf(buf, sizeof buf, "%-3s %19.12f %19.12f %19s %10.4f %10.4f %10.4f %10.4f  %-20s %s\n",
                  name, c.x, c.y, radius.c_str(), r.ront * 1e3, r.ronp * 1e3, r.ronv * 1e3,
                  r.ronq * 1e3, contacts.c_str(), proof.c_str());
    os << buf;
  };
  auto list = [](const std::vector<std::size_t>& v) {
    std::string s;
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + std::to_string(v[i]);
    return s;
  };
  auto fmt = [](double v) {
    char b[64];
    std::snprintf(b, sizeof b, "%.12f", v);
    return std::string(b);
  };
  auto proof = [&](const auto& circle) {
    const bool ok = g::verify(profile, circle).valid;
    std::string s = ok ? "certified, " : "NOT VERIFIED, ";
    s += circle.certificate.optimality == g::Optimality::global ? "global" : "local";
    return s;
  };
  if (e.least_squares)
    row("LS", e.least_squares->center, fmt(e.least_squares->radius), e.least_squares->ron,
        list(e.least_squares->contacts), "numerical fit");
  if (e.minimum_zone) {
    const auto& m = *e.minimum_zone;
    row("MZ", m.center, fmt(0.5 * (m.inner_radius + m.outer_radius)), m.ron,
        "o:" + list(m.outer_contacts) + " i:" + list(m.inner_contacts), proof(m));
  }
  if (e.maximum_inscribed)
    row("MI", e.maximum_inscribed->center, fmt(e.maximum_inscribed->radius),
        e.maximum_inscribed->ron, list(e.maximum_inscribed->contacts),
        proof(*e.maximum_inscribed));
  if (e.minimum_circumscribed)
    row("MC", e.minimum_circumscribed->center, fmt(e.minimum_circumscribed->radius),
        e.minimum_circumscribed->ron, list(e.minimum_circumscribed->contacts),
        proof(*e.minimum_circumscribed));
  if (e.minimum_zone)
    os << "MZ radius column: mean of inner " << fmt(e.minimum_zone->inner_radius)
       << " and outer " << fmt(e.minimum_zone->outer_radius) << "\n";
  return os.str();
}

int run_roundness(const RoundnessOptions& o) {
  try {
    g::RoundnessRequest request;
    const bool all = o.reference == "all";
    request.least_squares = all || o.reference == "LS";
    request.minimum_zone = all || o.reference == "MZ";
    request.maximum_inscribed = all || o.reference == "MI";
    request.minimum_circumscribed = all || o.reference == "MC";
    if (!o.no_filter && o.filter_upr > 0.0) request.filter_cutoff_upr = o.filter_upr;

    const g::PointTable table = g::read_points_csv_file(o.file);
    const g::RoundnessEvaluation e = g::evaluate_roundness(table.points, request);
    const std::span<const g::Point2> profile =
        e.filtered_points.empty() ? std::span<const g::Point2>(table.points)
                                  : std::span<const g::Point2>(e.filtered_points);
    std::string text;
    if (o.json) {
      nlohmann::json j = to_json(profile, e);
      j["file"] = o.file;
      text = j.dump(2) + "\n";
    } else {
      text = format_table(o.file, profile, e);
    }
    if (o.output.empty())
      std::cout << text << std::flush;
    else
      write_file_atomically(o.output, text);
    return kOk;
  } catch (const g::InvalidInput& ex) {
    std::cerr << "vcmm roundness: error: " << ex.what() << "\n";
    return kInvalidInput;
  } catch (const g::UndefinedResult& ex) {
    std::cerr << "vcmm roundness: error: " << ex.what() << "\n";
    return kUndefined;
  } catch (const std::exception& ex) {
    std::cerr << "vcmm roundness: internal error: " << ex.what() << "\n";
    return kFailure;
  }
}

}  // namespace

void add_roundness_command(CLI::App& app, int* exit_code) {
  auto opts = std::make_shared<RoundnessOptions>();
  CLI::App* cmd = app.add_subcommand(
      "roundness", "ISO 12181-2 reference circles (LS, MZ, MI, MC) and RONt/p/v/q of a profile");
  cmd->add_option("FILE", opts->file, "profile CSV: x,y or x,y,z (mm); '-' for stdin")
      ->required();
  auto* filter = cmd->add_option("--filter-upr", opts->filter_upr,
                                 "ISO 16610-21 Gaussian filter cut-off in undulations per "
                                 "revolution (15, 50, 150, 500, 1500); default: unfiltered")
                     ->check(CLI::PositiveNumber);
  auto* nofilter = cmd->add_flag("--no-filter", opts->no_filter, "evaluate unfiltered (default)");
  filter->excludes(nofilter);
  cmd->add_option("--reference", opts->reference, "reference circle(s): LS, MZ, MI, MC or all")
      ->check(CLI::IsMember({"LS", "MZ", "MI", "MC", "all"}))
      ->default_val("all");
  cmd->add_flag("--json", opts->json, "print one JSON object (docs/cli.md)");
  cmd->add_option("-o,--output", opts->output, "write the result to this file (atomically)");
  cmd->callback([opts, exit_code] { *exit_code = run_roundness(*opts); });
}

}  // namespace vcmm::cli
