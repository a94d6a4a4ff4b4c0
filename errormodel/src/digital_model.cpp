// The digital-model file: schema "vcmm.digital_model", version 1 (docs/errormodel.md).
//
// Every entry is checked where it is read; the first broken rule throws InvalidParameter with
// the full dotted key path ("probe.directional_error[1].cos.uncertainty_um"), the offending
// value and the rule. Unknown keys are errors too: a misspelt key must not silently fall back to zero.
#include "vcmm/errormodel/digital_model.h"

#include "vcmm/errormodel/json_input.h"

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <istream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "internal/kinematics_json.h"
#include "vcmm/errormodel/errors.h"
#include "vcmm/errormodel/physical_ranges.h"
#include "vcmm/geometry/text_file.h"

namespace vcmm::errormodel {
namespace {

using nlohmann::json;

constexpr const char* kSchema = "vcmm.digital_model";
constexpr int kSchemaVersion = 1;
constexpr double kMmPerUm = 1e-3;

class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& path, const std::string& rule) const {
    throw InvalidParameter(path, source_ + ": " + (path.empty() ? "" : path + ": ") + rule);
  }
  [[noreturn]] void fail(const std::string& path, const std::string& rule, const json& got) const {
    fail(path, rule + "; got " + shown(got));
  }

  static std::string shown(const json& v) {
    std::string s = v.dump();
    if (s.size() > 60) s = s.substr(0, 57) + "...";
    return s;
  }

  const json& object(const json& parent, const std::string& key, const std::string& path) const {
    const json& v = member(parent, key, path);
    if (!v.is_object()) fail(path, "must be a JSON object", v);
    return v;
  }

  const json& member(const json& parent, const std::string& key, const std::string& path) const {
    const auto it = parent.find(key);
    if (it == parent.end()) fail(path, "required key missing");
    return *it;
  }

  /// Rejects keys other than `allowed` and the free documentation keys "comment",
  /// "description" and "source" (strings; the same rule as the kinematics section).
  void only_keys(const json& obj, std::initializer_list<const char*> allowed,
                 const std::string& path) const {
    for (const auto& [key, value] : obj.items()) {
      if (key == "comment" || key == "description" || key == "source") {
        if (!value.is_string()) fail(join(path, key), "must be a string", value);
        continue;
      }
      bool ok = false;
      for (const char* a : allowed) ok = ok || key == a;
      if (!ok) {
        std::string list;
        for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        fail(join(path, key),
             "unknown key (allowed here: " + list + ", comment, description, source)");
      }
    }
  }

  double number(const json& v, const std::string& path) const {
    if (!v.is_number()) fail(path, "must be a number", v);
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(path, "must be finite", v);
    return d;
  }

  /// A number in its physical range (physical_ranges.h): the message names the key and unit.
  double in_range(const json& v, const std::string& path, const PhysicalRange& range) const {
    const double d = number(v, path);
    if (const std::string problem = range_problem(range, d); !problem.empty()) fail(path, problem);
    return d;
  }

  /// {"value_<unit>": v, "uncertainty_<unit>": u}, each in its range, both multiplied by
  /// `scale`.
  UncertainValue uncertain(const json& parent, const std::string& key, const std::string& path,
                           const std::string& unit, double scale, const PhysicalRange& value_range,
                           const PhysicalRange& u_range) const {
    const std::string kv = "value_" + unit, ku = "uncertainty_" + unit;
    const json& v = member(parent, key, path);
    if (!v.is_object())
      fail(path, "must be an object {\"" + kv + "\": ..., \"" + ku + "\": ...}", v);
    only_keys(v, {kv.c_str(), ku.c_str()}, path);
    UncertainValue out;
    out.value = in_range(member(v, kv, join(path, kv)), join(path, kv), value_range) * scale;
    out.u = in_range(member(v, ku, join(path, ku)), join(path, ku), u_range) * scale;
    return out;
  }

  static std::string join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }

  const std::string& source() const { return source_; }

 private:
  std::string source_;
};

RoughnessModel read_roughness(const Reader& r, const json& root) {
  const json& s = r.object(root, "roughness", "roughness");
  r.only_keys(s, {"sigma_um"}, "roughness");
  return {r.in_range(r.member(s, "sigma_um", "roughness.sigma_um"), "roughness.sigma_um",
                     physical_range::length_sigma_um) *
          kMmPerUm};
}

TemperatureModel read_temperature(const Reader& r, const json& root) {
  const json& s = r.object(root, "temperature", "temperature");
  r.only_keys(s, {"expansion_coefficient", "thermometer_uncertainty_K"}, "temperature");
  TemperatureModel t;
  t.expansion_coefficient_per_k =
      r.uncertain(s, "expansion_coefficient", "temperature.expansion_coefficient", "per_K", 1.0,
                  physical_range::expansion_coefficient_per_k,
                  physical_range::expansion_coefficient_u_per_k);
  const std::string tpath = "temperature.thermometer_uncertainty_K";
  t.thermometer_u_k = r.in_range(r.member(s, "thermometer_uncertainty_K", tpath), tpath,
                                 physical_range::thermometer_u_k);
  return t;
}

ProbeModel read_probe(const Reader& r, const json& root) {
  const json& s = r.object(root, "probe", "probe");
  r.only_keys(s, {"tip_radius_error", "directional_error"}, "probe");
  ProbeModel p;
  p.tip_radius_error_mm =
      r.uncertain(s, "tip_radius_error", "probe.tip_radius_error", "um", kMmPerUm,
                  physical_range::length_error_um, physical_range::length_sigma_um);
  const std::string dpath = "probe.directional_error";
  const json& list = r.member(s, "directional_error", dpath);
  if (!list.is_array()) r.fail(dpath, "must be an array of harmonics (may be empty)", list);
  std::set<int> orders;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string hpath = dpath + "[" + std::to_string(i) + "]";
    const json& h = list[i];
    if (!h.is_object())
      r.fail(hpath, "must be an object {\"order\": k, \"cos\": {...}, \"sin\": {...}}", h);
    r.only_keys(h, {"order", "cos", "sin"}, hpath);
    const json& order = r.member(h, "order", hpath + ".order");
    if (!order.is_number_integer() || order.get<long long>() < 1 ||
        order.get<long long>() > max_probe_harmonic_order)
      r.fail(hpath + ".order",
             "must be an integer from 1 to " + std::to_string(max_probe_harmonic_order), order);
    ProbeHarmonic ph;
    ph.order = static_cast<int>(order.get<long long>());
    if (!orders.insert(ph.order).second)
      r.fail(hpath + ".order", "repeats an order already given", order);
    ph.cos_mm = r.uncertain(h, "cos", hpath + ".cos", "um", kMmPerUm,
                            physical_range::length_error_um, physical_range::length_sigma_um);
    ph.sin_mm = r.uncertain(h, "sin", hpath + ".sin", "um", kMmPerUm,
                            physical_range::length_error_um, physical_range::length_sigma_um);
    p.directional.push_back(ph);
  }
  return p;
}

NoiseModel read_noise(const Reader& r, const json& root) {
  const json& s = r.object(root, "noise", "noise");
  r.only_keys(s, {"scanning_sigma_um", "touch_trigger_sigma_um"}, "noise");
  NoiseModel n;
  n.scanning_sigma_mm = r.in_range(r.member(s, "scanning_sigma_um", "noise.scanning_sigma_um"),
                                   "noise.scanning_sigma_um", physical_range::length_sigma_um) *
                        kMmPerUm;
  n.touch_trigger_sigma_mm =
      r.in_range(r.member(s, "touch_trigger_sigma_um", "noise.touch_trigger_sigma_um"),
                 "noise.touch_trigger_sigma_um", physical_range::length_sigma_um) *
      kMmPerUm;
  return n;
}

KinematicModel read_kinematics(const Reader& r, const json& root) {
  const json& s = r.object(root, "kinematics", "kinematics");
  try {
    return kinematic_model_from_json(s, "kinematics");
  } catch (const InvalidParameter&) {
    throw;
  } catch (const std::invalid_argument& e) {
    // The kinematics parser names the key path first: "kinematics.errors.E_AX...: rule".
    const std::string what = e.what();
    const auto colon = what.find(": ");
    std::string path = "kinematics";
    if (what.starts_with("kinematics") && colon != std::string::npos) path = what.substr(0, colon);
    throw InvalidParameter(path, r.source() + ": " + what);
  }
}

}  // namespace

void validate_digital_model(const DigitalModel& m) {
  const Reader r("validate_digital_model");
  // The same ranges as the file (physical_ranges.h), on the file's units (µm for lengths).
  auto check = [&](double v, const std::string& path, const PhysicalRange& range, double scale) {
    if (const std::string problem = range_problem(range, v * scale); !problem.empty())
      r.fail(path, problem);
  };
  namespace pr = physical_range;
  constexpr double um = 1.0 / kMmPerUm;
  check(m.roughness.sigma_mm, "roughness.sigma_um", pr::length_sigma_um, um);
  check(m.temperature.expansion_coefficient_per_k.value,
        "temperature.expansion_coefficient.value_per_K", pr::expansion_coefficient_per_k, 1.0);
  check(m.temperature.expansion_coefficient_per_k.u,
        "temperature.expansion_coefficient.uncertainty_per_K",
        pr::expansion_coefficient_u_per_k, 1.0);
  check(m.temperature.thermometer_u_k, "temperature.thermometer_uncertainty_K",
        pr::thermometer_u_k, 1.0);
  check(m.probe.tip_radius_error_mm.value, "probe.tip_radius_error.value_um",
        pr::length_error_um, um);
  check(m.probe.tip_radius_error_mm.u, "probe.tip_radius_error.uncertainty_um",
        pr::length_sigma_um, um);
  std::set<int> orders;
  for (std::size_t i = 0; i < m.probe.directional.size(); ++i) {
    const ProbeHarmonic& h = m.probe.directional[i];
    const std::string p = "probe.directional_error[" + std::to_string(i) + "]";
    if (h.order < 1 || h.order > max_probe_harmonic_order)
      r.fail(p + ".order",
             "must be an integer from 1 to " + std::to_string(max_probe_harmonic_order),
             json(h.order));
    if (!orders.insert(h.order).second)
      r.fail(p + ".order", "repeats an order already given", json(h.order));
    check(h.cos_mm.value, p + ".cos.value_um", pr::length_error_um, um);
    check(h.sin_mm.value, p + ".sin.value_um", pr::length_error_um, um);
    check(h.cos_mm.u, p + ".cos.uncertainty_um", pr::length_sigma_um, um);
    check(h.sin_mm.u, p + ".sin.uncertainty_um", pr::length_sigma_um, um);
  }
  check(m.noise.scanning_sigma_mm, "noise.scanning_sigma_um", pr::length_sigma_um, um);
  check(m.noise.touch_trigger_sigma_mm, "noise.touch_trigger_sigma_um", pr::length_sigma_um, um);
}

DigitalModel parse_digital_model(std::string_view text, const std::string& source) {
  const Reader r(source);
  // The SAX guard first (json_input.h): syntax, numbers beyond the double range, repeated
  // keys and excessive nesting are reported with the line and the key path.
  const JsonInputCheck check = check_json_input(text);
  switch (check.problem) {
    case JsonInputCheck::Problem::none:
      break;
    case JsonInputCheck::Problem::duplicate_key:
      throw InvalidParameter(check.path, source + ": " +
                                             (check.path.empty() ? "" : check.path + ": ") +
                                             "key \"" + check.message +
                                             "\" appears twice in one object (JSON would keep "
                                             "only one)");
    case JsonInputCheck::Problem::syntax:  // the line says where; the key path would not
      throw InvalidParameter("", source + ":" + std::to_string(check.line) +
                                     ": not valid JSON: " + check.message);
    case JsonInputCheck::Problem::too_deep:
      throw InvalidParameter(check.path, source + ":" + std::to_string(check.line) +
                                             ": not valid JSON here: " + check.message +
                                             (check.path.empty() ? "" : " (at " + check.path + ")"));
  }
  const json root = json::parse(text.begin(), text.end());
  if (!root.is_object()) r.fail("", "the file must hold one JSON object", root);
  r.only_keys(root,
              {"schema", "schema_version", "description", "roughness", "temperature", "kinematics",
               "probe", "noise"},
              "");
  const json& schema = r.member(root, "schema", "schema");
  if (!schema.is_string() || schema.get<std::string>() != kSchema)
    r.fail("schema", std::string("must be \"") + kSchema + "\"", schema);
  const json& version = r.member(root, "schema_version", "schema_version");
  if (!version.is_number_integer() || version.get<long long>() != kSchemaVersion)
    r.fail("schema_version",
           "unsupported version (this reader: " + std::to_string(kSchemaVersion) + ")", version);
  std::string description;
  if (const auto it = root.find("description"); it != root.end()) {
    if (!it->is_string()) r.fail("description", "must be a string", *it);
    description = it->get<std::string>();
  }
  // Sections in stage order, so the first error reported is the first in the model.
  const RoughnessModel roughness = read_roughness(r, root);
  const TemperatureModel temperature = read_temperature(r, root);
  DigitalModel model(read_kinematics(r, root));
  model.description = std::move(description);
  model.roughness = roughness;
  model.temperature = temperature;
  model.probe = read_probe(r, root);
  model.noise = read_noise(r, root);
  return model;
}

DigitalModel read_digital_model(std::istream& in, const std::string& source) {
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_digital_model(buffer.str(), source);
}

DigitalModel read_digital_model_file(const std::string& path) {
  std::string text, why;
  if (!geometry::try_read_text_file(path, text, why))
    throw InvalidParameter("", path + ": cannot read the digital-model file: " + why);
  return parse_digital_model(text, path);
}

DigitalModel with_kinematics_uncorrected(const DigitalModel& model) {
  DigitalModel out = model;
  out.kinematics = model.kinematics.uncorrected();
  return out;
}

}  // namespace vcmm::errormodel
