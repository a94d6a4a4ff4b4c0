// Hole-plate files (plate calibration CSV, placement CSV) and the JSON outputs of the
// kinematic characterisation: the digital model's "kinematics" section and the report
// (formats: docs/characterization.md, "File formats"; schema of the section: docs/kinematics.md).
#include <nlohmann/json.hpp>

#include <array>
#include <algorithm>
#include <charconv>
#include <initializer_list>
#include <cmath>
#include <fstream>
#include <istream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "output_checks.h"
#include "vcmm/geometry/text_file.h"
#include "vcmm/characterization/hole_plate.h"
#include "vcmm/errormodel/errors.h"
#include "vcmm/errormodel/physical_ranges.h"
#include "vcmm/geometry/text_lines.h"

namespace vcmm::characterization {
namespace {

namespace em = vcmm::errormodel;
using em::InvalidInput;
using Eigen::Index;
using ojson = nlohmann::ordered_json;

constexpr std::string_view kPlateFormat = "vcmm.hole_plate 1";
constexpr std::string_view kPlacementFormat = "vcmm.hole_plate_placement 1";
constexpr std::string_view kPlateHeader = "id,x_mm,y_mm,z_mm,u_um";
constexpr std::string_view kPlacementHeader = "id,x_mm,y_mm,z_mm";

std::string shortest(double v) {
  std::array<char, 32> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), r.ptr);
}

/// The µm text of a length stored in mm, such that the plate reader (µm · 1e-3) gives `mm`
/// back exactly. shortest(mm · 1e3) alone does not: the two products round twice, so e.g.
/// 13 µm → 0.013 mm → "13.000000000000002" µm → a different mm value (found by the fuzz target
/// hole_plate_csv, docs/fuzzing.md). The µm value the mm came from lies within a few ulps of
/// mm · 1e3 (three roundings of relative size ≤ 2⁻⁵³ each), so the neighbours up to 8 ulps away
/// are tried and the shortest text that reads back is kept; a value no µm text reproduces
/// (one built in code) falls back to the nearest, shortest(mm · 1e3).
std::string um_text_reading_back_to(double mm) {
  const double guess = mm * 1e3;
  std::string best;
  for (int side : {+1, -1}) {
    double um = guess;
    for (int step = 0; step <= 8 && std::isfinite(um); ++step) {
      if (um * 1e-3 == mm) {
        std::string text = shortest(um);
        if (best.empty() || text.size() < best.size()) best = std::move(text);
      }
      um = std::nextafter(um, side * std::numeric_limits<double>::infinity());
    }
  }
  return best.empty() ? shortest(guess) : best;
}

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

std::vector<std::string_view> split_commas(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  while (true) {
    const auto comma = s.find(',', start);
    out.push_back(trim(s.substr(start, comma == std::string_view::npos ? s.npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

[[noreturn]] void fail(const std::string& source, std::size_t line, const std::string& what) {
  throw InvalidInput(source + ":" + std::to_string(line) + ": " + what);
}

double parse_number(std::string_view field, const std::string& source, std::size_t line,
                    const std::string& what) {
  double v = 0.0;
  const char* first = field.data();
  const char* last = field.data() + field.size();
  if (!field.empty() && *first == '+') ++first;  // from_chars refuses a leading '+'
  const auto r = std::from_chars(first, last, v);
  if (field.empty() || r.ec == std::errc::invalid_argument || r.ptr != last)
    fail(source, line, what + " is not a number ('" + std::string(field) + "')");
  if (r.ec == std::errc::result_out_of_range || !std::isfinite(v))
    fail(source, line, what + " is not finite ('" + std::string(field) + "')");
  return v;
}

std::string compact(std::string_view text) {
  std::string s;
  for (char ch : text)
    if (ch != ' ' && ch != '\t') s += ch;
  return s;
}

// Splits the stream into trimmed non-empty lines (BOM skipped).
std::vector<std::pair<std::size_t, std::string>> read_lines(std::istream& in) {
  std::vector<std::pair<std::size_t, std::string>> lines;
  std::string raw;
  std::size_t n = 0;
  while (geometry::read_text_line(in, raw)) {
    ++n;
    std::string_view t(raw);
    if (n == 1 && t.starts_with("\xEF\xBB\xBF")) t.remove_prefix(3);
    t = trim(t);
    if (!t.empty()) lines.emplace_back(n, std::string(t));
  }
  return lines;
}

// "# key: value" → (key, value) if key is one of `keys`.
bool metadata(std::string_view text, std::initializer_list<std::string_view> keys,
              std::string& key, std::string_view& value) {
  const std::string_view body = trim(text.substr(1));
  const auto colon = body.find(':');
  if (colon == std::string_view::npos) return false;
  const std::string_view k = trim(body.substr(0, colon));
  for (std::string_view allowed : keys) {
    if (k == allowed) {
      key = std::string(k);
      value = trim(body.substr(colon + 1));
      return true;
    }
  }
  return false;
}

void check_id(std::string_view id, const std::string& source, std::size_t line,
              std::map<std::string, std::size_t>& seen, const std::string& what) {
  if (id.empty()) fail(source, line, "field 1 (id) is empty");
  if (id.find('#') != std::string_view::npos)
    fail(source, line, "field 1 (id) contains '#' ('" + std::string(id) + "')");
  const std::string s(id);
  if (const auto it = seen.find(s); it != seen.end())
    fail(source, line, what + " '" + s + "' repeated (first on line " + std::to_string(it->second) + ")");
  seen[s] = line;
}

std::string comments_block(std::span<const std::string> comments, const char* caller) {
  std::string s;
  for (std::size_t i = 0; i < comments.size(); ++i) {
    if (comments[i].find_first_of("\r\n") != std::string::npos)
      throw InvalidInput(std::string(caller) + ": comment " + std::to_string(i) +
                         " contains a line break");
    s += "# " + comments[i] + "\n";
  }
  return s;
}

// ---- JSON helpers --------------------------------------------------------------------------

double unit_of(bool rotation) { return rotation ? 1e-6 : 1e-3; }

ojson chain_json(const em::KinematicChain& chain) {
  if (chain == em::KinematicChain::moving_bridge()) return "moving_bridge";
  if (chain == em::KinematicChain::fixed_bridge()) return "fixed_bridge";
  ojson c = ojson::object();
  c["tool_side"] = ojson::array();
  c["workpiece_side"] = ojson::array();
  for (em::Axis a : chain.tool_side) c["tool_side"].push_back(std::string(em::name(a)));
  for (em::Axis a : chain.workpiece_side) c["workpiece_side"].push_back(std::string(em::name(a)));
  return c;
}

// The section; `function_comment(f)` / `squareness_comment(s)` may add a "comment".
template <class FunctionComment, class SquarenessComment>
ojson section_json(const em::KinematicModel& model, FunctionComment function_comment,
                   SquarenessComment squareness_comment) {
  ojson sec = ojson::object();
  sec["chain"] = chain_json(model.chain());
  ojson ranges = ojson::object();
  for (int k = 0; k < 3; ++k) {
    const auto a = static_cast<em::Axis>(k);
    ranges[std::string(em::name(a))] = {model.range(a).min, model.range(a).max};
  }
  sec["axis_range_mm"] = ranges;
  const Eigen::VectorXd& mean = model.mean();
  const Eigen::MatrixXd& cov = model.covariance();
  ojson errors = ojson::object();
  for (int f = 0; f < em::axis_error_count; ++f) {
    const auto e = static_cast<em::AxisError>(f);
    const bool rot = em::is_rotation(e);
    const double unit = unit_of(rot);
    const Index off = model.parameter_offset(e);
    const Index n = model.coefficient_count(e);
    ojson fn = ojson::object();
    const std::string comment = function_comment(f);
    if (!comment.empty()) fn["comment"] = comment;
    ojson c = ojson::array(), u = ojson::array();
    std::vector<double> sd(static_cast<std::size_t>(n));
    for (Index i = 0; i < n; ++i) {
      sd[static_cast<std::size_t>(i)] = std::sqrt(std::max(0.0, cov(off + i, off + i)));
      c.push_back(mean[off + i] / unit);
      u.push_back(sd[static_cast<std::size_t>(i)] / unit);
    }
    fn[rot ? "legendre_urad" : "legendre_um"] = c;
    fn[rot ? "uncertainty_urad" : "uncertainty_um"] = u;
    bool correlated = false;
    ojson corr = ojson::array();
    for (Index i = 0; i < n; ++i) {
      ojson rowj = ojson::array();
      for (Index j = 0; j < n; ++j) {
        double r = i == j ? 1.0 : 0.0;
        const double si = sd[static_cast<std::size_t>(i)], sj = sd[static_cast<std::size_t>(j)];
        if (i != j && si > 0.0 && sj > 0.0) {
          // Computed once per pair (from the lower triangle) so the matrix is exactly symmetric.
          const Index a = std::max(i, j), b = std::min(i, j);
          r = std::clamp(cov(off + a, off + b) / (sd[static_cast<std::size_t>(a)] * sd[static_cast<std::size_t>(b)]), -1.0, 1.0);
          correlated = correlated || r != 0.0;
        }
        rowj.push_back(r);
      }
      corr.push_back(rowj);
    }
    if (correlated) fn["correlation"] = corr;
    errors[std::string(em::name(e))] = fn;
  }
  sec["errors"] = errors;
  ojson sq = ojson::object();
  for (int s = 0; s < em::squareness_count; ++s) {
    const auto q = static_cast<em::Squareness>(s);
    const Index p = model.parameter_offset(q);
    ojson v = ojson::object();
    const std::string comment = squareness_comment(s);
    if (!comment.empty()) v["comment"] = comment;
    v["value_urad"] = mean[p] / 1e-6;
    v["uncertainty_urad"] = std::sqrt(std::max(0.0, cov(p, p))) / 1e-6;
    sq[std::string(em::name(q))] = v;
  }
  sec["squareness"] = sq;
  return sec;
}

// "c0 by convention; c2 not identifiable (a-priori u)" for the coefficients of one function.
std::string status_comment(const KinematicCharacterization& r, Index first, Index count,
                           bool squareness) {
  std::map<ParameterStatus, std::string> groups;
  for (Index i = 0; i < count; ++i) {
    const auto& p = r.parameters[static_cast<std::size_t>(first + i)];
    if (p.status == ParameterStatus::identifiable) continue;
    std::string& g = groups[p.status];
    // Built by appends: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
    if (!g.empty()) g += ", ";
    if (squareness) {
      g += "value";
    } else {
      g += 'c';
      g += std::to_string(i);
    }
  }
  std::string s;
  auto add = [&](ParameterStatus st, const char* text) {
    if (const auto it = groups.find(st); it != groups.end()) {
      if (!s.empty()) s += "; ";
      s += it->second;
      s += ' ';
      s += text;
    }
  };
  add(ParameterStatus::by_convention, "fixed at 0 by convention (invisible to any measurement)");
  add(ParameterStatus::not_identifiable,
      "not identifiable from the hole-plate plan: 0 with the a-priori uncertainty, not an estimate");
  add(ParameterStatus::in_combination,
      "estimated in combination with fixed coefficients (see the section comment)");
  return s;
}

}  // namespace

// ---- plate CSV -------------------------------------------------------------------------------

HolePlate read_hole_plate_csv(std::istream& in, const std::string& source) {
  HolePlate plate;
  plate.source = source;
  bool header = false, format_seen = false;
  std::size_t last_line = 0;
  std::map<std::string, std::size_t> seen;
  std::vector<Eigen::Vector3d> xs;
  for (const auto& [line, str] : read_lines(in)) {
    last_line = line;
    const std::string_view text(str);
    if (text.front() == '#') {
      std::string key;
      std::string_view value;
      if (!header && metadata(text, {"format"}, key, value)) {
        if (format_seen) fail(source, line, "metadata key 'format' repeated");
        format_seen = true;
        if (value != kPlateFormat)
          fail(source, line, "unsupported format '" + std::string(value) + "' (this reader: '" +
                                 std::string(kPlateFormat) + "')");
      }
      continue;
    }
    if (!header) {
      if (compact(text) != kPlateHeader)
        fail(source, line, "expected the header '" + std::string(kPlateHeader) + "'; got '" +
                               std::string(text) + "'");
      header = true;
      continue;
    }
    const auto fields = split_commas(text);
    if (fields.size() != 5)
      fail(source, line, "expected 5 fields (id,x_mm,y_mm,z_mm,u_um); got " +
                             std::to_string(fields.size()));
    check_id(fields[0], source, line, seen, "feature id");
    static const char* const names[5] = {"id", "x_mm", "y_mm", "z_mm", "u_um"};
    double v[4];
    for (int k = 0; k < 4; ++k)
      v[k] = parse_number(fields[static_cast<std::size_t>(k + 1)], source, line,
                          "field " + std::to_string(k + 2) + " (" + names[k + 1] + ")");
    // A calibration uncertainty in its physical range (errormodel/physical_ranges.h): a plate
    // is calibrated to ~0.1–5 µm; 1 mm is no calibration (1e300 would make every weight 0).
    if (const std::string problem =
            em::range_problem(em::physical_range::length_sigma_um, v[3]);
        !problem.empty())
      fail(source, line, "field 5 (u_um) " + problem);
    plate.ids.emplace_back(fields[0]);
    plate.lines.push_back(line);
    xs.emplace_back(v[0], v[1], v[2]);
    plate.calibration_u_mm.push_back(v[3] * 1e-3);
  }
  if (!header) fail(source, last_line + 1, "no header '" + std::string(kPlateHeader) + "' found");
  if (xs.size() < 3)
    fail(source, last_line + 1, "a plate needs at least 3 features; got " + std::to_string(xs.size()));
  plate.calibrated_mm.resize(3, static_cast<Index>(xs.size()));
  for (std::size_t i = 0; i < xs.size(); ++i) plate.calibrated_mm.col(static_cast<Index>(i)) = xs[i];
  return plate;
}

HolePlate read_hole_plate_csv_file(const std::string& path) {
  std::istringstream f(geometry::read_text_file(path, "hole-plate calibration file"));
  return read_hole_plate_csv(f, path);
}

std::string hole_plate_csv(const HolePlate& plate, std::span<const std::string> comments) {
  if (plate.ids.size() != static_cast<std::size_t>(plate.calibrated_mm.cols()) ||
      plate.ids.size() != plate.calibration_u_mm.size())
    throw InvalidInput("hole_plate_csv: ids, centres and uncertainties differ in count");
  std::string s = "# vcmm hole-plate calibration (docs/characterization.md): plate frame, mm; "
                  "u_um = standard uncertainty of each coordinate\n";
  s += "# format: " + std::string(kPlateFormat) + "\n";
  s += comments_block(comments, "hole_plate_csv");
  s += std::string(kPlateHeader) + "\n";
  for (std::size_t i = 0; i < plate.ids.size(); ++i) {
    const auto c = plate.calibrated_mm.col(static_cast<Index>(i));
    if (!c.allFinite() || !std::isfinite(plate.calibration_u_mm[i]))
      throw InvalidInput("hole_plate_csv: feature '" + plate.ids[i] + "' is not finite");
    s += plate.ids[i] + "," + shortest(c.x()) + "," + shortest(c.y()) + "," + shortest(c.z()) +
         "," + um_text_reading_back_to(plate.calibration_u_mm[i]) + "\n";
  }
  return s;
}

// ---- placement CSV ---------------------------------------------------------------------------

HolePlatePlacement read_hole_plate_placement_csv(std::istream& in, const std::string& source) {
  HolePlatePlacement pl;
  pl.name = source;
  pl.source = source;
  bool header = false, stylus = false;
  std::map<std::string, std::size_t> meta_seen, seen;
  std::vector<Eigen::Vector3d> xs;
  std::size_t last_line = 0;
  for (const auto& [line, str] : read_lines(in)) {
    last_line = line;
    const std::string_view text(str);
    if (text.front() == '#') {
      std::string key;
      std::string_view value;
      if (header || !metadata(text, {"format", "stylus_offset_mm", "setup", "name"}, key, value))
        continue;
      if (const auto it = meta_seen.find(key); it != meta_seen.end())
        fail(source, line, "metadata key '" + key + "' repeated (first on line " +
                               std::to_string(it->second) + ")");
      meta_seen[key] = line;
      if (key == "format") {
        if (value != kPlacementFormat)
          fail(source, line, "unsupported format '" + std::string(value) + "' (this reader: '" +
                                 std::string(kPlacementFormat) + "')");
      } else if (key == "stylus_offset_mm") {
        const auto f = split_commas(value);
        if (f.size() != 3)
          fail(source, line, "stylus_offset_mm needs 3 comma-separated values; got '" +
                                 std::string(value) + "'");
        for (int k = 0; k < 3; ++k)
          pl.stylus_offset_mm[k] = parse_number(f[static_cast<std::size_t>(k)], source, line,
                                                "stylus_offset_mm component " + std::to_string(k + 1));
        stylus = true;
      } else {  // setup or name
        // No carriage return can be inside the value: a lone CR ends the line
        // (geometry/text_lines.h; fuzz target hole_plate_placement_csv, docs/fuzzing.md).
        if (key == "setup") {
          pl.setup = std::string(value);
        } else {
          if (value.empty()) fail(source, line, "metadata 'name' is empty");
          pl.name = std::string(value);
        }
      }
      continue;
    }
    if (!header) {
      if (!stylus)
        fail(source, line, "metadata line '# stylus_offset_mm: x, y, z' missing before the header");
      if (compact(text) != kPlacementHeader)
        fail(source, line, "expected the header '" + std::string(kPlacementHeader) + "'; got '" +
                               std::string(text) + "'");
      header = true;
      continue;
    }
    const auto fields = split_commas(text);
    if (fields.size() != 4)
      fail(source, line, "expected 4 fields (id,x_mm,y_mm,z_mm); got " + std::to_string(fields.size()));
    check_id(fields[0], source, line, seen, "feature id");
    static const char* const names[3] = {"x_mm", "y_mm", "z_mm"};
    Eigen::Vector3d x;
    for (int k = 0; k < 3; ++k)
      x[k] = parse_number(fields[static_cast<std::size_t>(k + 1)], source, line,
                          "field " + std::to_string(k + 2) + " (" + names[k] + ")");
    pl.ids.emplace_back(fields[0]);
    pl.lines.push_back(line);
    xs.push_back(x);
  }
  if (!header)
    fail(source, last_line + 1, "no header '" + std::string(kPlacementHeader) + "' found");
  if (xs.empty()) fail(source, last_line + 1, "no measured features");
  pl.measured_mm.resize(3, static_cast<Index>(xs.size()));
  for (std::size_t i = 0; i < xs.size(); ++i) pl.measured_mm.col(static_cast<Index>(i)) = xs[i];
  return pl;
}

HolePlatePlacement read_hole_plate_placement_csv_file(const std::string& path) {
  std::istringstream f(geometry::read_text_file(path, "hole-plate placement file"));
  return read_hole_plate_placement_csv(f, path);
}

std::string hole_plate_placement_csv(const HolePlatePlacement& pl,
                                     std::span<const std::string> comments) {
  const char* c = "hole_plate_placement_csv";
  if (pl.ids.size() != static_cast<std::size_t>(pl.measured_mm.cols()))
    throw InvalidInput(std::string(c) + ": ids and measured centres differ in count");
  if (!pl.stylus_offset_mm.allFinite() || !pl.measured_mm.allFinite())
    throw InvalidInput(std::string(c) + ": stylus offset and centres must be finite");
  for (const std::string* s : {&pl.name, &pl.setup})
    if (s->find_first_of("\r\n") != std::string::npos)
      throw InvalidInput(std::string(c) + ": name and setup must not contain line breaks");
  std::string s = "# vcmm hole-plate placement (docs/characterization.md): measured feature "
                  "centres (tip centre), machine coordinates, mm\n";
  s += "# format: " + std::string(kPlacementFormat) + "\n";
  if (!pl.name.empty()) s += "# name: " + pl.name + "\n";
  if (!pl.setup.empty()) s += "# setup: " + pl.setup + "\n";
  s += "# stylus_offset_mm: " + shortest(pl.stylus_offset_mm.x()) + ", " +
       shortest(pl.stylus_offset_mm.y()) + ", " + shortest(pl.stylus_offset_mm.z()) + "\n";
  s += comments_block(comments, c);
  s += std::string(kPlacementHeader) + "\n";
  for (std::size_t i = 0; i < pl.ids.size(); ++i) {
    const auto x = pl.measured_mm.col(static_cast<Index>(i));
    s += pl.ids[i] + "," + shortest(x.x()) + "," + shortest(x.y()) + "," + shortest(x.z()) + "\n";
  }
  return s;
}

// ---- JSON ------------------------------------------------------------------------------------

std::string kinematics_json(const em::KinematicModel& model, std::string_view comment) {
  ojson sec = ojson::object();
  if (!comment.empty()) sec["comment"] = std::string(comment);
  const ojson body = section_json(model, [](int) { return std::string(); },
                                  [](int) { return std::string(); });
  for (auto it = body.begin(); it != body.end(); ++it) sec[it.key()] = it.value();
  internal::require_finite_numbers(sec, "the kinematic model", "kinematics");
  return sec.dump(2);
}

std::string kinematics_json_section(const KinematicCharacterization& r, std::string_view source) {
  if (!r.usable)
    throw InvalidInput("kinematics_json_section: the characterisation is not usable (" +
                       r.message + ")");
  // Physical range of a CMM's kinematic errors: a coefficient or its uncertainty beyond 1 mm
  // (translations) or 1 mrad (rotations, squareness) is no machine error but a blunder in the
  // data (µm and µrad are the scale; docs/characterization.md, "Consistency").
  for (const KinematicParameter& p : r.parameters) {
    const double limit = p.rotation ? 1e-3 : 1.0;
    const double unit = unit_of(p.rotation);
    for (const double v : {p.value, p.standard_uncertainty})
      if (!(std::abs(v) <= limit))
        throw InvalidInput("the estimated " + p.name + " (value " + shortest(p.value / unit) +
                           ", uncertainty " + shortest(p.standard_uncertainty / unit) +
                           (p.rotation ? " urad" : " um") + ") is outside the physical range of a "
                           "CMM's kinematic error (|value| and u at most " +
                           (p.rotation ? std::string("1000 urad") : std::string("1000 um")) +
                           "): computed from " + std::string(source) +
                           " — a blunder in these files or wrong units; nothing written");
  }
  const em::KinematicModel& m = r.model;
  std::string summary =
      "Estimated from a calibrated hole plate (vcmm characterize hole-plate, "
      "docs/characterization.md): " + r.message + ".";
  std::string conv, notid, comb;
  for (const NullDirection& nd : r.null_directions) {
    const std::string& pname = r.parameters[static_cast<std::size_t>(nd.pivot)].name;
    if (nd.intrinsic) {
      conv += (conv.empty() ? "" : ", ") + pname;
    } else {
      notid += (notid.empty() ? "" : ", ") + pname;
    }
    if (nd.terms.size() > 1) comb += (comb.empty() ? "" : "; ") + nd.text;
  }
  if (!conv.empty())
    summary += " Fixed at 0 by convention (no measurement of a rigid artefact can see them): " +
               conv + ".";
  if (!notid.empty())
    summary += " NOT identifiable from this plan (0 with the a-priori uncertainty, not "
               "estimates): " + notid + ".";
  if (!comb.empty())
    summary += " Invisible combinations (coefficients in um/urad; adding any multiple changes no "
               "measured centre): " + comb + ".";
  summary += " Correlations between different functions are not representable here and are "
             "dropped.";
  ojson sec = ojson::object();
  sec["source"] = std::string(source);
  sec["comment"] = summary;
  const ojson body = section_json(
      m,
      [&](int f) {
        const auto e = static_cast<em::AxisError>(f);
        return status_comment(r, m.parameter_offset(e), m.coefficient_count(e), false);
      },
      [&](int s) {
        return status_comment(r, m.parameter_offset(static_cast<em::Squareness>(s)), 1, true);
      });
  for (auto it = body.begin(); it != body.end(); ++it) sec[it.key()] = it.value();
  internal::require_finite_numbers(sec, source, "kinematics");
  return sec.dump(2);
}

std::string hole_plate_report_json(const KinematicCharacterization& r, bool accepted_inconsistent) {
  ojson j = ojson::object();
  j["status"] = std::string(to_string(r.status));
  j["usable"] = r.usable;
  j["message"] = r.message;
  j["iterations"] = r.iterations;
  j["observations"] = r.observations;
  j["unknowns"] = r.unknowns;
  j["degrees_of_freedom"] = r.degrees_of_freedom;
  j["residual_rms_um"] = r.residual_rms_mm * 1e3;
  j["variance_factor"] = r.variance_factor;
  j["covariance_scaled"] = r.covariance_scaled;
  j["probing_sigma_given_um"] = r.probing_sigma_given_mm * 1e3;
  j["probing_sigma_from_residuals_um"] = r.probing_sigma_from_residuals_mm * 1e3;
  j["weakest_direction"] = r.weakest_direction;
  ojson params = ojson::array();
  for (const KinematicParameter& p : r.parameters) {
    ojson o = ojson::object();
    const double unit = unit_of(p.rotation);
    o["name"] = p.name;
    o["status"] = std::string(to_string(p.status));
    o[p.rotation ? "value_urad" : "value_um"] = p.value / unit;
    o[p.rotation ? "uncertainty_urad" : "uncertainty_um"] = p.standard_uncertainty / unit;
    params.push_back(o);
  }
  j["parameters"] = params;
  ojson nulls = ojson::array();
  for (const NullDirection& nd : r.null_directions) {
    ojson o = ojson::object();
    o["pivot"] = r.parameters[static_cast<std::size_t>(nd.pivot)].name;
    o["intrinsic"] = nd.intrinsic;
    o["combination"] = nd.text;
    ojson terms = ojson::array();
    for (const auto& [q, coef] : nd.terms)
      terms.push_back({{"parameter", r.parameters[static_cast<std::size_t>(q)].name},
                       {"coefficient", coef}});
    o["terms"] = terms;
    nulls.push_back(o);
  }
  j["null_directions"] = nulls;
  ojson setups = ojson::array();
  for (const SetupPose& s : r.setups) {
    ojson o = ojson::object();
    o["setup"] = s.setup;
    ojson rot = ojson::array();
    for (int i = 0; i < 3; ++i)
      rot.push_back({s.pose.rotation(i, 0), s.pose.rotation(i, 1), s.pose.rotation(i, 2)});
    o["rotation"] = rot;
    o["translation_mm"] = {s.pose.translation_mm.x(), s.pose.translation_mm.y(),
                           s.pose.translation_mm.z()};
    setups.push_back(o);
  }
  j["setups"] = setups;
  ojson pls = ojson::array();
  for (const PlacementResiduals& p : r.placements) {
    pls.push_back({{"name", p.name},
                   {"features", p.residuals_mm.cols()},
                   {"residual_rms_um", p.rms_mm * 1e3},
                   {"max_abs_residual_um", p.residuals_mm.size() > 0 ? p.residuals_mm.cwiseAbs().maxCoeff() * 1e3 : 0.0}});
  }
  j["placements"] = pls;
  j["consistency"] = internal::consistency_json<ojson>(r.consistency, accepted_inconsistent);
  internal::require_finite_numbers(j, "the hole-plate report");
  return j.dump(2);
}

}  // namespace vcmm::characterization
