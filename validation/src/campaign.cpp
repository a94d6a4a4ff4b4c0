// campaign.cpp — the campaign file, schema "vcmm.campaign" version 1 (vcmm/validation/
// campaign.h, docs/validation.md "The campaign file").
//
// Reading is two passes over the text. A SAX pass (errormodel::check_json_input) follows the
// JSON path of every token: it finds keys repeated within an object (nlohmann's DOM would keep
// the last one silently), nesting deeper than any campaign needs, and, on a syntax error or a
// number too large for a double, says where it happened (line and path). Then the DOM is walked by Reader, which checks every entry where it is read
// and throws CampaignError at the first broken rule, with the source, the measurement (index
// and, once read, id) and the JSON path. Unknown keys are errors; when an unknown key differs
// from an expected one only in its unit suffix ("value_mm" for "value_um") the message names
// the expected key and unit.
//
// Writing builds the document in the format's key order (nlohmann::ordered_json, whose number
// output is the shortest text that reads back to the same double), then reads it back with
// the same Reader (files not checked), so the writer can never emit a file the reader refuses.
#include "vcmm/validation/campaign.h"

#include "vcmm/errormodel/json_input.h"
#include "vcmm/errormodel/physical_ranges.h"
#include "vcmm/geometry/text_file.h"

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <system_error>
#include <utility>

namespace vcmm::validation {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using nlohmann::ordered_json;

constexpr double kMmPerUm = 1e-3;
constexpr const char* kWriterSource = "campaign_json";

std::string number_text(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

/// "measurements[3] ("id").setup.mode": the JSON path with the measurement's id after its
/// index (when known).
std::string display_path(const std::string& path, std::optional<std::size_t> index,
                         const std::string& id) {
  if (!index || id.empty()) return path;
  const std::string prefix = "measurements[" + std::to_string(*index) + "]";
  if (path.rfind(prefix, 0) != 0) return path;
  return prefix + " (\"" + id + "\")" + path.substr(prefix.size());
}

[[noreturn]] void throw_error(const std::string& source, std::optional<std::size_t> index,
                              const std::string& id, const std::string& path,
                              const std::string& rule, std::optional<std::size_t> line = {}) {
  std::string msg = source;
  if (line) msg += ":" + std::to_string(*line);
  const std::string shown = display_path(path, index, id);
  msg += ": " + (shown.empty() ? std::string() : shown + ": ") + rule;
  throw CampaignError(source, index, id, path, msg);
}

std::optional<std::size_t> measurement_index_of(const std::string& path) {
  const std::string prefix = "measurements[";
  if (path.rfind(prefix, 0) != 0) return std::nullopt;
  std::size_t i = prefix.size(), value = 0;
  if (i >= path.size() || path[i] < '0' || path[i] > '9') return std::nullopt;
  while (i < path.size() && path[i] >= '0' && path[i] <= '9')
    value = value * 10 + static_cast<std::size_t>(path[i++] - '0');
  if (i >= path.size() || path[i] != ']') return std::nullopt;
  return value;
}

// ---- pass 2: the schema --------------------------------------------------------------------

/// A key allowed in an object, and how to name its quantity in a wrong-unit message.
struct KeySpec {
  const char* name;
  const char* quantity;  // "" for keys without a unit
};

/// The unit suffix of a key ("um" of "u_um"), or "" when it has none we know.
std::string unit_suffix(const std::string& key) {
  static const std::set<std::string> kUnits = {"mm", "um", "nm", "m",  "cm", "in", "deg",
                                               "rad", "c", "k", "f", "upr", "µm"};
  const auto us = key.rfind('_');
  if (us == std::string::npos || us == 0) return {};
  std::string suffix = key.substr(us + 1);
  for (char& ch : suffix)
    if (ch >= 'A' && ch <= 'Z') ch = static_cast<char>(ch - 'A' + 'a');
  return kUnits.count(suffix) ? suffix : std::string();
}

std::string stem(const std::string& key) {
  const std::string unit = unit_suffix(key);
  return unit.empty() ? key : key.substr(0, key.size() - unit.size() - 1);
}

std::string unit_name(const std::string& unit) {
  if (unit == "um") return "µm";
  if (unit == "deg") return "degrees";
  if (unit == "c") return "°C";
  if (unit == "upr") return "UPR";
  return unit;
}

class Reader {
 public:
  Reader(std::string source, fs::path base_dir, bool check_files)
      : source_(std::move(source)), base_(std::move(base_dir)), check_files_(check_files) {}

  [[noreturn]] void fail(const std::string& path, const std::string& rule) const {
    throw_error(source_, index_, id_, path, rule);
  }
  [[noreturn]] void fail(const std::string& path, const std::string& rule, const json& got) const {
    fail(path, rule + "; got " + shown(got));
  }

  static std::string shown(const json& v) {
    std::string s = v.dump();
    if (s.size() > 60) s = s.substr(0, 57) + "...";
    return s;
  }
  static std::string join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }

  void enter_measurement(std::size_t i) {
    index_ = i;
    id_.clear();
  }
  void name_measurement(const std::string& id) { id_ = id; }
  void leave_measurement() {
    index_.reset();
    id_.clear();
  }

  Campaign document(const json& root) {
    if (!root.is_object()) fail("", "a campaign must be a JSON object", root);
    Campaign c;
    c.source = source_;
    // The schema first: a file that is not a campaign gets that message, not "unknown key".
    const json& schema = member(root, "schema", "");
    if (!schema.is_string() || schema.get<std::string>() != campaign_schema)
      fail("schema", "must be \"" + std::string(campaign_schema) + "\"", schema);
    const json& version = member(root, "schema_version", "");
    if (!version.is_number_integer() || version.get<long long>() != campaign_schema_version)
      fail("schema_version",
           "unsupported version (this reader knows " + std::to_string(campaign_schema_version) +
               ")",
           version);
    only_keys(root,
              {{"schema", ""}, {"schema_version", ""}, {"description", ""}, {"model", ""},
               {"evaluation", ""}, {"measurements", ""}},
              "");
    if (const json* d = find(root, "description")) c.description = text(*d, "description");
    c.model = text(member(root, "model", ""), "model");
    c.model_path = file(c.model, "model");
    if (const json* e = find(root, "evaluation")) c.evaluation = evaluation(*e);
    const json& list = member(root, "measurements", "");
    if (!list.is_array()) fail("measurements", "must be an array of measurements", list);
    if (list.empty()) fail("measurements", "a campaign needs at least one measurement");
    std::map<std::string, std::size_t> seen;
    for (std::size_t i = 0; i < list.size(); ++i) {
      enter_measurement(i);
      c.measurements.push_back(measurement(list[i], i, seen));
      leave_measurement();
    }
    return c;
  }

 private:
  static const json* find(const json& obj, const char* key) {
    const auto it = obj.find(key);
    return it == obj.end() ? nullptr : &*it;
  }

  const json& member(const json& obj, const char* key, const std::string& path) const {
    const json* v = find(obj, key);
    if (!v) fail(path, "required key \"" + std::string(key) + "\" missing");
    return *v;
  }

  const json& object(const json& v, const std::string& path, const char* shape) const {
    if (!v.is_object()) fail(path, std::string("must be an object ") + shape, v);
    return v;
  }

  void only_keys(const json& obj, std::initializer_list<KeySpec> allowed,
                 const std::string& path) const {
    for (const auto& item : obj.items()) {
      const std::string& key = item.key();
      bool ok = false;
      for (const KeySpec& a : allowed) ok = ok || key == a.name;
      if (ok) continue;
      // Another unit than the expected one, or none: name the expected key.
      for (const KeySpec& a : allowed) {
        const std::string expected_unit = unit_suffix(a.name);
        if (expected_unit.empty() || stem(key) != stem(a.name)) continue;
        fail(path, "unknown key \"" + key + "\" (" + a.quantity + " is given in " +
                       unit_name(expected_unit) + ": \"" + a.name + "\")");
      }
      std::string list;
      for (const KeySpec& a : allowed) list += (list.empty() ? "" : ", ") + std::string(a.name);
      fail(path, "unknown key \"" + key + "\" (allowed here: " + list + ")");
    }
  }

  std::string text(const json& v, const std::string& path) const {
    if (!v.is_string()) fail(path, "must be a string", v);
    return v.get<std::string>();
  }

  double number(const json& v, const std::string& path) const {
    if (!v.is_number()) fail(path, "must be a number", v);
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(path, "must be finite", v);
    return d;
  }

  double non_negative(const json& v, const std::string& path) const {
    const double d = number(v, path);
    if (d < 0.0) fail(path, "must be >= 0 (a standard uncertainty)", v);
    return d;
  }

  double positive(const json& v, const std::string& path) const {
    const double d = number(v, path);
    if (!(d > 0.0)) fail(path, "must be > 0", v);
    return d;
  }

  /// A referenced file: non-empty, resolved against the campaign's directory, existing.
  fs::path file(const std::string& given, const std::string& path) const {
    if (given.empty()) fail(path, "must be a non-empty file path");
    fs::path p(given);
    if (p.is_relative()) p = base_ / p;
    p = p.lexically_normal();
    if (check_files_) {
      std::error_code ec;
      const fs::file_status st = fs::status(p, ec);
      if (!fs::exists(st)) fail(path, "file not found: " + p.string());
      if (!fs::is_regular_file(st)) fail(path, "not a regular file: " + p.string());
    }
    return p;
  }

  static bool is_label(const std::string& s) {
    if (s.empty()) return false;
    for (const char ch : s) {
      const bool ok = (ch >= 'A' && ch <= 'Z') || (ch >= 'a' && ch <= 'z') ||
                      (ch >= '0' && ch <= '9') || ch == '_' || ch == '.' || ch == '-';
      if (!ok) return false;
    }
    return true;
  }

  EvaluationSettings evaluation(const json& v) const {
    const std::string path = "evaluation";
    object(v, path, "of evaluation settings");
    only_keys(v,
              {{"reference_circle", ""}, {"filter_cutoff_upr", "the filter cut-off"},
               {"trials", ""}, {"seed", ""}, {"coverage_probability", ""}, {"k", ""},
               {"bias_treatment", ""}, {"kinematic_errors", ""}, {"budget", ""},
               {"budget_trials", ""}, {"trial", ""}},
              path);
    EvaluationSettings e;
    if (const json* rc = find(v, "reference_circle")) {
      const std::string p = join(path, "reference_circle");
      const auto circle = rc->is_string() ? reference_circle_from_string(rc->get<std::string>())
                                          : std::nullopt;
      if (!circle) fail(p, "must be one of \"MZ\", \"MI\", \"LS\", \"MC\"", *rc);
      e.reference_circle = *circle;
    }
    if (const json* fc = find(v, "filter_cutoff_upr")) {
      const std::string p = join(path, "filter_cutoff_upr");
      if (fc->is_null()) {
        e.filter_cutoff_upr.reset();
      } else {
        if (!fc->is_number()) fail(p, "must be a number (UPR) or null for unfiltered", *fc);
        e.filter_cutoff_upr = positive(*fc, p);
      }
    }
    if (const json* t = find(v, "trials")) {
      e.trials = count(*t, join(path, "trials"), min_campaign_trials, max_campaign_trials);
    }
    if (const json* s = find(v, "seed")) {
      e.seed = unsigned_integer(*s, join(path, "seed"),
                                "must be an unsigned 64-bit integer (0 to 18446744073709551615)");
    }
    if (const json* cp = find(v, "coverage_probability")) {
      const std::string p = join(path, "coverage_probability");
      const double prob = number(*cp, p);
      if (!(prob > 0.0 && prob < 1.0)) fail(p, "must lie in (0, 1)", *cp);
      e.coverage_probability = prob;
    }
    if (const json* k = find(v, "k")) e.k = positive(*k, join(path, "k"));
    if (const json* b = find(v, "bias_treatment")) {
      const auto t = b->is_string() ? roundness_bias_treatment_from_string(b->get<std::string>())
                                    : std::nullopt;
      if (!t) fail(join(path, "bias_treatment"), "must be \"shrinkage\" or \"paper\"", *b);
      e.bias_treatment = *t;
    }
    if (const json* ke = find(v, "kinematic_errors")) {
      const std::string text = ke->is_string() ? ke->get<std::string>() : std::string();
      if (text != "corrected" && text != "uncertainty_only")
        fail(join(path, "kinematic_errors"), "must be \"corrected\" or \"uncertainty_only\"",
             *ke);
      e.kinematics_corrected = text == "corrected";
    }
    if (const json* b = find(v, "budget")) {
      if (!b->is_boolean()) fail(join(path, "budget"), "must be true or false", *b);
      e.budget = b->get<bool>();
    }
    if (const json* bt = find(v, "budget_trials")) {
      const std::string p = join(path, "budget_trials");
      if (!e.budget)
        fail(p, "needs \"budget\": true (the trials of each uncertainty-budget run)");
      // At most the measurement's trials: each budget run is compared with the full run's u
      // over the same trials, where the random numbers coincide (ring_uncertainty_budget.h).
      e.budget_trials = count(*bt, p, min_campaign_trials, e.trials, " (evaluation.trials)");
    }
    if (const json* t = find(v, "trial")) {
      const auto kind = t->is_string() ? trial_kind_from_string(t->get<std::string>())
                                       : std::nullopt;
      if (!kind) fail(join(path, "trial"), "must be \"auto\", \"exact\" or \"spectral\"", *t);
      e.trial = *kind;
    }
    return e;
  }

  /// An integer in [0, 2⁶⁴ − 1] (JSON keeps non-negative integers unsigned, negative ones
  /// signed); anything else fails with `rule`.
  std::uint64_t unsigned_integer(const json& v, const std::string& path,
                                 const std::string& rule) const {
    if (!v.is_number_integer()) fail(path, rule, v);
    if (v.is_number_unsigned()) return v.get<std::uint64_t>();
    if (v.get<long long>() < 0) fail(path, rule, v);
    return static_cast<std::uint64_t>(v.get<long long>());
  }

  /// A trial count: an integer in [min, max] (`max_source` says where max comes from).
  std::uint64_t count(const json& v, const std::string& path, std::uint64_t min,
                      std::uint64_t max, const std::string& max_source = "") const {
    const std::string rule = "must be an integer from " + std::to_string(min) + " to " +
                             std::to_string(max) + max_source;
    const std::uint64_t n = unsigned_integer(v, path, rule);
    if (n < min || n > max) fail(path, rule, v);
    return n;
  }

  CampaignMeasurement measurement(const json& v, std::size_t i,
                                  std::map<std::string, std::size_t>& seen) {
    const std::string path = "measurements[" + std::to_string(i) + "]";
    object(v, path, "{\"id\": ..., \"points\": ..., \"setup\": {...}, \"reference\": {...}}");
    CampaignMeasurement m;
    // The id first, so that every later message can name the entry.
    const std::string id_path = join(path, "id");
    m.id = text(member(v, "id", path), id_path);
    if (!is_label(m.id))
      fail(id_path, "must be a non-empty string of letters, digits, '_', '.' and '-' (it names "
                    "result files)", member(v, "id", path));
    if (m.id == "." || m.id == "..")
      fail(id_path, "must not be \".\" or \"..\" (it names result files)", member(v, "id", path));
    if (m.id.size() > max_measurement_id_length)
      fail(id_path, "must be at most " + std::to_string(max_measurement_id_length) +
                        " characters (it names result files); got " +
                        std::to_string(m.id.size()));
    name_measurement(m.id);
    if (const auto [it, fresh] = seen.emplace(m.id, i); !fresh)
      fail(id_path, "duplicate id \"" + m.id + "\" (already used by measurements[" +
                        std::to_string(it->second) + "])");
    only_keys(v, {{"id", ""}, {"points", ""}, {"setup", ""}, {"reference", ""}}, path);
    const std::string points_path = join(path, "points");
    m.points = text(member(v, "points", path), points_path);
    m.points_path = file(m.points, points_path);
    m.setup = setup(member(v, "setup", path), join(path, "setup"));
    m.reference = references(member(v, "reference", path), join(path, "reference"));
    return m;
  }

  /// An optional [x, y, z] (mm) member.
  std::optional<std::array<double, 3>> triple(const json& v, const char* key,
                                              const std::string& path) const {
    const json* t = find(v, key);
    if (!t) return std::nullopt;
    const std::string p = join(path, key);
    if (!t->is_array() || t->size() != 3) fail(p, "must be an array of 3 numbers [x, y, z] (mm)", *t);
    std::array<double, 3> xyz{};
    for (std::size_t k = 0; k < 3; ++k) {  // each a coordinate in a CMM (physical_ranges.h)
      const std::string pk = p + "[" + std::to_string(k) + "]";
      xyz[k] = number((*t)[k], pk);
      if (const std::string problem =
              errormodel::range_problem(errormodel::physical_range::coordinate_mm, xyz[k]);
          !problem.empty())
        fail(pk, problem);
    }
    return xyz;
  }

  Setup setup(const json& v, const std::string& path) const {
    object(v, path,
           "{\"location\": ..., \"orientation_deg\": ..., \"height\": ..., \"mode\": ...}");
    only_keys(v,
              {{"location", ""}, {"location_mm", "the location"},
               {"orientation_deg", "the orientation"}, {"height", ""}, {"mode", ""},
               {"temperature_c", "the temperature"}, {"stylus_offset_mm", "the stylus offset"},
               {"frame", ""}, {"surface", ""}, {"radius_mm", "the radius"},
               {"profile_height_mm", "the profile height"}},
              path);
    Setup s;
    const std::string lp = join(path, "location");
    s.location = text(member(v, "location", path), lp);
    if (!is_label(s.location))
      fail(lp, "must be a non-empty label of letters, digits, '_', '.' and '-' (it goes "
               "into CSV tables unquoted)", member(v, "location", path));
    s.location_mm = triple(v, "location_mm", path);
    s.stylus_offset_mm = triple(v, "stylus_offset_mm", path);
    if (const json* f = find(v, "frame")) {
      if (!f->is_string() || (*f != "machine" && *f != "workpiece"))
        fail(join(path, "frame"), "must be one of \"machine\", \"workpiece\"", *f);
      s.frame = *f == "machine" ? PointFrame::machine : PointFrame::workpiece;
    }
    if (const json* f = find(v, "surface")) {
      if (!f->is_string() || (*f != "inner" && *f != "outer"))
        fail(join(path, "surface"), "must be one of \"inner\", \"outer\"", *f);
      s.surface = *f == "inner" ? SurfaceSide::inner : SurfaceSide::outer;
    }
    if (const json* r = find(v, "radius_mm")) {
      const double radius = number(*r, join(path, "radius_mm"));
      if (!(radius > 0.0)) fail(join(path, "radius_mm"), "must be > 0 (mm)", *r);
      s.radius_mm = radius;
    }
    if (const json* h = find(v, "profile_height_mm"))
      s.profile_height_mm = number(*h, join(path, "profile_height_mm"));
    s.orientation_deg =
        number(member(v, "orientation_deg", path), join(path, "orientation_deg"));
    const std::string hp = join(path, "height");
    const json& h = member(v, "height", path);
    const auto height = h.is_string() ? height_from_string(h.get<std::string>()) : std::nullopt;
    if (!height) fail(hp, "must be one of \"top\", \"middle\", \"bottom\"", h);
    s.height = *height;
    const std::string mp = join(path, "mode");
    const json& mode = member(v, "mode", path);
    if (!mode.is_string() ||
        (mode.get<std::string>() != "scanning" && mode.get<std::string>() != "touch_trigger"))
      fail(mp, "must be one of \"scanning\", \"touch_trigger\"", mode);
    s.mode = mode.get<std::string>() == "scanning" ? errormodel::ProbingMode::scanning
                                                   : errormodel::ProbingMode::touch_trigger;
    if (const json* t = find(v, "temperature_c")) {
      const std::string p = join(path, "temperature_c");
      const double tc = number(*t, p);
      // A workpiece in a CMM room (physical_ranges.h): outside, kelvin or °F was given.
      if (const std::string problem =
              errormodel::range_problem(errormodel::physical_range::temperature_c, tc);
          !problem.empty())
        fail(p, problem);
      s.temperature_c = tc;
    }
    return s;
  }

  References references(const json& v, const std::string& path) const {
    object(v, path, "{\"roundness\": {...}, \"diameter\": {...}}");
    only_keys(v, {{"roundness", ""}, {"diameter", ""}}, path);
    References r;
    if (const json* ron = find(v, "roundness"))
      r.roundness = roundness(*ron, join(path, "roundness"));
    if (const json* d = find(v, "diameter")) r.diameter = diameter(*d, join(path, "diameter"));
    if (!r.roundness && !r.diameter)
      fail(path, "needs \"roundness\" or \"diameter\" (or both)");
    return r;
  }

  RoundnessReference roundness(const json& v, const std::string& path) const {
    object(v, path, "{\"value_um\": ..., \"u_um\": ...} or {\"profile\": ..., \"u_um\": ...}");
    only_keys(v, {{"value_um", "roundness"}, {"u_um", "the standard uncertainty"}, {"profile", ""}},
              path);
    const json* value = find(v, "value_um");
    const json* profile = find(v, "profile");
    if (value && profile)
      fail(path, "give either \"value_um\" or \"profile\", not both");
    if (!value && !profile)
      fail(path, "needs \"value_um\" (a given RONt) or \"profile\" (a roundness-meter profile)");
    const double u = non_negative(member(v, "u_um", path), join(path, "u_um"));
    if (value) {
      const double ron = number(*value, join(path, "value_um"));
      if (ron < 0.0) fail(join(path, "value_um"), "must be >= 0 (a roundness)", *value);
      return GivenRoundness{ron, u};
    }
    ProfileRoundness p;
    p.profile = text(*profile, join(path, "profile"));
    p.profile_path = file(p.profile, join(path, "profile"));
    p.u_um = u;
    return p;
  }

  DiameterReference diameter(const json& v, const std::string& path) const {
    object(v, path,
           "{\"value_mm\": ..., \"u_um\": ...} or {\"interferometer_distance_mm\": ..., "
           "\"u_interferometer_um\": ..., \"profile\": ...}");
    only_keys(v,
              {{"value_mm", "the diameter"},
               {"u_um", "the standard uncertainty"},
               {"interferometer_distance_mm", "the interferometer distance"},
               {"u_interferometer_um", "the interferometer's standard uncertainty"},
               {"profile", ""},
               {"u_profile_point_um", "the standard uncertainty of a profile reading"}},
              path);
    const json* value = find(v, "value_mm");
    const json* distance = find(v, "interferometer_distance_mm");
    if (value && distance)
      fail(path, "give either \"value_mm\" or \"interferometer_distance_mm\", not both");
    if (!value && !distance)
      fail(path, "needs \"value_mm\" (a given diameter) or \"interferometer_distance_mm\" with "
                 "\"u_interferometer_um\" and \"profile\"");
    if (value) {
      for (const char* k : {"u_interferometer_um", "profile", "u_profile_point_um"})
        if (find(v, k))
          fail(path, "\"" + std::string(k) +
                         "\" belongs to the interferometer form; a given diameter takes "
                         "\"value_mm\" and \"u_um\"");
      GivenDiameter g;
      g.value_mm = positive(*value, join(path, "value_mm"));
      g.u_um = non_negative(member(v, "u_um", path), join(path, "u_um"));
      return g;
    }
    if (find(v, "u_um"))
      fail(path, "\"u_um\" belongs to a given diameter; the interferometer form takes "
                 "\"u_interferometer_um\" (and \"u_profile_point_um\")");
    InterferometerDiameter d;
    d.interferometer_distance_mm = positive(*distance, join(path, "interferometer_distance_mm"));
    d.u_interferometer_um = non_negative(member(v, "u_interferometer_um", path),
                                         join(path, "u_interferometer_um"));
    d.profile = text(member(v, "profile", path), join(path, "profile"));
    d.profile_path = file(d.profile, join(path, "profile"));
    if (const json* up = find(v, "u_profile_point_um"))
      d.u_profile_point_um = non_negative(*up, join(path, "u_profile_point_um"));
    return d;
  }

  std::string source_;
  fs::path base_;
  bool check_files_ = true;
  std::optional<std::size_t> index_;
  std::string id_;
};

Campaign parse_document(std::string_view text, const std::string& source, const fs::path& base,
                        bool check_files) {
  const errormodel::JsonInputCheck check = errormodel::check_json_input(text);
  if (!check.ok()) {
    const auto index = measurement_index_of(check.path);
    std::string id;
    if (index)
      if (const auto it = check.ids.find("measurements[" + std::to_string(*index) + "]");
          it != check.ids.end())
        id = it->second;
    using Problem = errormodel::JsonInputCheck::Problem;
    switch (check.problem) {
      case Problem::syntax:
        throw_error(source, index, id, check.path, "invalid JSON: " + check.message, check.line);
      case Problem::duplicate_key:
        throw_error(source, index, id, check.path,
                    "key \"" + check.message +
                        "\" appears twice in one object (JSON would keep only one)");
      case Problem::too_deep:
      case Problem::none:
        throw_error(source, index, id, check.path, "invalid JSON: " + check.message, check.line);
    }
  }
  const json root = json::parse(text);
  Reader reader(source, base, check_files);
  return reader.document(root);
}

/// Finds a non-finite number in a document built in code (ordered_json would write null).
void reject_non_finite(const ordered_json& v, const std::string& path) {
  if (v.is_number_float() && !std::isfinite(v.get<double>()))
    throw_error(kWriterSource, measurement_index_of(path), {}, path,
                "must be finite; got " + number_text(v.get<double>()));
  if (v.is_object())
    for (const auto& item : v.items())
      reject_non_finite(item.value(), path.empty() ? item.key() : path + "." + item.key());
  if (v.is_array())
    for (std::size_t i = 0; i < v.size(); ++i)
      reject_non_finite(v[i], path + "[" + std::to_string(i) + "]");
}

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

const CampaignMeasurement& entry(const Campaign& c, std::size_t index, const char* caller) {
  if (index >= c.measurements.size())
    throw geometry::InvalidInput(std::string(caller) + ": measurement index " +
                                 std::to_string(index) + " out of range (the campaign has " +
                                 std::to_string(c.measurements.size()) + ")");
  return c.measurements[index];
}

std::string entry_path(std::size_t index, const char* suffix) {
  return "measurements[" + std::to_string(index) + "]" + suffix;
}

}  // namespace

CampaignError::CampaignError(std::string source, std::optional<std::size_t> measurement_index,
                             std::string measurement_id, std::string json_path,
                             const std::string& message)
    : geometry::InvalidInput(message),
      source_(std::move(source)),
      index_(measurement_index),
      id_(std::move(measurement_id)),
      json_path_(std::move(json_path)) {}

std::string_view to_string(Height height) {
  switch (height) {
    case Height::top: return "top";
    case Height::middle: return "middle";
    case Height::bottom: return "bottom";
  }
  return "?";
}

std::optional<Height> height_from_string(std::string_view text) {
  if (text == "top") return Height::top;
  if (text == "middle") return Height::middle;
  if (text == "bottom") return Height::bottom;
  return std::nullopt;
}

Campaign parse_campaign(std::string_view json_text, const fs::path& campaign_path) {
  std::error_code ec;
  fs::path base = fs::absolute(campaign_path, ec);
  if (ec) base = campaign_path;
  return parse_document(json_text, campaign_path.string(), base.parent_path(), true);
}

Campaign read_campaign_file(const fs::path& path) {
  std::string text, why;
  if (!geometry::try_read_text_file(path.string(), text, why))
    throw_error(path.string(), std::nullopt, {}, "", "cannot read the campaign file: " + why);
  return parse_campaign(text, path);
}

std::string campaign_json(const Campaign& c) {
  ordered_json j;
  j["schema"] = std::string(campaign_schema);
  j["schema_version"] = campaign_schema_version;
  j["description"] = c.description;
  j["model"] = c.model;
  ordered_json& e = j["evaluation"];
  e["reference_circle"] = std::string(to_string(c.evaluation.reference_circle));
  e["filter_cutoff_upr"] =
      c.evaluation.filter_cutoff_upr ? ordered_json(*c.evaluation.filter_cutoff_upr)
                                     : ordered_json(nullptr);
  e["trials"] = c.evaluation.trials;
  e["seed"] = c.evaluation.seed;
  e["coverage_probability"] = c.evaluation.coverage_probability;
  e["k"] = c.evaluation.k;
  e["bias_treatment"] = std::string(to_string(c.evaluation.bias_treatment));
  e["kinematic_errors"] = c.evaluation.kinematics_corrected ? "corrected" : "uncertainty_only";
  e["budget"] = c.evaluation.budget;
  if (c.evaluation.budget_trials != 0) e["budget_trials"] = c.evaluation.budget_trials;
  e["trial"] = std::string(to_string(c.evaluation.trial));
  ordered_json list = ordered_json::array();
  for (const CampaignMeasurement& m : c.measurements) {
    ordered_json mj;
    mj["id"] = m.id;
    mj["points"] = m.points;
    ordered_json& s = mj["setup"];
    s["location"] = m.setup.location;
    if (m.setup.location_mm) s["location_mm"] = *m.setup.location_mm;
    s["orientation_deg"] = m.setup.orientation_deg;
    s["height"] = std::string(to_string(m.setup.height));
    s["mode"] = std::string(errormodel::to_string(m.setup.mode));
    if (m.setup.temperature_c) s["temperature_c"] = *m.setup.temperature_c;
    if (m.setup.stylus_offset_mm) s["stylus_offset_mm"] = *m.setup.stylus_offset_mm;
    if (m.setup.frame)
      s["frame"] = *m.setup.frame == PointFrame::machine ? "machine" : "workpiece";
    if (m.setup.surface) s["surface"] = *m.setup.surface == SurfaceSide::inner ? "inner" : "outer";
    if (m.setup.radius_mm) s["radius_mm"] = *m.setup.radius_mm;
    if (m.setup.profile_height_mm) s["profile_height_mm"] = *m.setup.profile_height_mm;
    ordered_json& r = mj["reference"];
    r = ordered_json::object();
    if (m.reference.roundness) {
      if (const auto* g = std::get_if<GivenRoundness>(&*m.reference.roundness))
        r["roundness"] = {{"value_um", g->value_um}, {"u_um", g->u_um}};
      else if (const auto* p = std::get_if<ProfileRoundness>(&*m.reference.roundness))
        r["roundness"] = {{"profile", p->profile}, {"u_um", p->u_um}};
    }
    if (m.reference.diameter) {
      if (const auto* g = std::get_if<GivenDiameter>(&*m.reference.diameter))
        r["diameter"] = {{"value_mm", g->value_mm}, {"u_um", g->u_um}};
      else if (const auto* d = std::get_if<InterferometerDiameter>(&*m.reference.diameter))
        r["diameter"] = {{"interferometer_distance_mm", d->interferometer_distance_mm},
                         {"u_interferometer_um", d->u_interferometer_um},
                         {"profile", d->profile},
                         {"u_profile_point_um", d->u_profile_point_um}};
    }
    list.push_back(std::move(mj));
  }
  j["measurements"] = std::move(list);
  reject_non_finite(j, "");
  std::string text;
  try {
    text = j.dump(2) + "\n";
  } catch (const nlohmann::json::exception& ex) {  // e.g. a string that is not UTF-8
    throw_error(kWriterSource, std::nullopt, {}, "", std::string("cannot write: ") + ex.what());
  }
  // Read it back (files not checked): the writer never emits what the reader refuses.
  std::error_code ec;
  parse_document(text, kWriterSource, fs::current_path(ec), false);
  return text;
}

std::uint64_t measurement_seed(std::uint64_t campaign_seed, std::string_view id) {
  std::uint64_t h = 0xCBF29CE484222325ull;  // FNV-1a 64 offset basis
  for (const char ch : id) {
    h ^= static_cast<unsigned char>(ch);
    h *= 0x100000001B3ull;  // FNV-1a 64 prime
  }
  return splitmix64(splitmix64(campaign_seed) ^ h);
}

std::optional<EvaluatedReference> evaluate_roundness_reference(const Campaign& campaign,
                                                               std::size_t index,
                                                               double nominal_radius_mm) {
  constexpr const char* kCaller = "evaluate_roundness_reference";
  const CampaignMeasurement& m = entry(campaign, index, kCaller);
  if (!std::isfinite(nominal_radius_mm) || !(nominal_radius_mm > 0.0))
    throw geometry::InvalidInput(std::string(kCaller) +
                                 ": nominal_radius_mm must be finite and > 0; got " +
                                 number_text(nominal_radius_mm));
  if (!m.reference.roundness) return std::nullopt;
  if (const auto* g = std::get_if<GivenRoundness>(&*m.reference.roundness))
    return EvaluatedReference{g->value_um * kMmPerUm, g->u_um * kMmPerUm,
                              "given in the campaign file", true};
  const auto& p = std::get<ProfileRoundness>(*m.reference.roundness);
  try {
    const RoundnessProfile profile = read_roundness_profile_csv_file(p.profile_path.string());
    ReferenceRoundnessOptions options;
    options.reference_circle = campaign.evaluation.reference_circle;
    options.filter_cutoff_upr = campaign.evaluation.filter_cutoff_upr;
    options.u_instrument_mm = p.u_um * kMmPerUm;
    options.nominal_radius_mm = nominal_radius_mm;
    const ReferenceRoundness r = reference_roundness(profile, options);
    EvaluatedReference out{r.value_mm, r.u_mm, {}, r.verification.valid};
    out.method = "roundness-meter profile " + p.profile_path.string() + " (" +
                 std::to_string(profile.angle_rad.size()) + " samples), " +
                 std::string(to_string(r.reference_circle)) + ", " +
                 (r.filter_cutoff_upr ? number_text(*r.filter_cutoff_upr) + " UPR" : "unfiltered");
    if (r.certificate)
      out.method += r.verification.valid
                        ? std::string(", certificate verified (") +
                              (r.certificate->optimality == geometry::Optimality::global
                                   ? "global"
                                   : "local") +
                              " optimum)"
                        : ", certificate NOT verified: " + r.verification.reason;
    return out;
  } catch (const std::exception& ex) {
    throw_error(campaign.source, index, m.id, entry_path(index, ".reference.roundness.profile"),
                ex.what());
  }
}

std::optional<EvaluatedReference> evaluate_diameter_reference(const Campaign& campaign,
                                                              std::size_t index) {
  constexpr const char* kCaller = "evaluate_diameter_reference";
  const CampaignMeasurement& m = entry(campaign, index, kCaller);
  if (!m.reference.diameter) return std::nullopt;
  if (const auto* g = std::get_if<GivenDiameter>(&*m.reference.diameter))
    return EvaluatedReference{g->value_mm, g->u_um * kMmPerUm, "given in the campaign file",
                              true};
  const auto& d = std::get<InterferometerDiameter>(*m.reference.diameter);
  try {
    const RoundnessProfile profile = read_roundness_profile_csv_file(d.profile_path.string());
    const ReferenceDiameter r =
        reference_diameter(d.interferometer_distance_mm, d.u_interferometer_um * kMmPerUm,
                           profile, d.u_profile_point_um * kMmPerUm);
    EvaluatedReference out{r.value_mm, r.u_mm, {}, true};
    out.method = "interferometer distance " + number_text(r.interferometer_distance_mm) +
                 " mm + 2 x mean deviation of profile " + d.profile_path.string() + " (" +
                 std::to_string(profile.angle_rad.size()) + " samples) relative to its 0/180 deg "
                 "points: " + number_text(r.correction_mm / kMmPerUm) + " um";
    return out;
  } catch (const std::exception& ex) {
    throw_error(campaign.source, index, m.id, entry_path(index, ".reference.diameter.profile"),
                ex.what());
  }
}

}  // namespace vcmm::validation
