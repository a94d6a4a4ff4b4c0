// The "kinematics" section of the digital-model file → KinematicModel (schema: docs/kinematics.md).
// Every rule is checked here with the full key path in the message, so that a user editing the
// file is pointed to the exact value; the KinematicModel constructor re-checks the same rules.
#include "internal/kinematics_json.h"

#include "vcmm/errormodel/physical_ranges.h"

#include <Eigen/Cholesky>

#include <array>
#include <cmath>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace vcmm::errormodel {
namespace {

constexpr double kUm = 1e-3;     // µm → mm
constexpr double kUrad = 1e-6;   // µrad → rad

[[noreturn]] void fail(const std::string& path, const std::string& rule) {
  throw std::invalid_argument(path + ": " + rule);
}

std::string shown(const nlohmann::json& v) {
  std::string s = v.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

std::string child(const std::string& path, std::string_view key) {
  return path + "." + std::string(key);
}
std::string element(const std::string& path, std::size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

bool is_free_key(const std::string& key) {
  return key == "comment" || key == "description" || key == "source";
}

void require_object(const nlohmann::json& v, const std::string& path) {
  if (!v.is_object()) fail(path, "must be a JSON object; got " + shown(v));
}

// Rejects keys not in `allowed` (free keys must hold strings).
void check_keys(const nlohmann::json& obj, const std::string& path,
                std::initializer_list<std::string_view> allowed, const std::string& hint = "") {
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    const std::string& key = it.key();
    if (is_free_key(key)) {
      if (!it.value().is_string()) fail(child(path, key), "must be a string; got " + shown(it.value()));
      continue;
    }
    bool ok = false;
    for (std::string_view a : allowed) ok = ok || key == a;
    if (!ok) {
      std::string list;
      for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      fail(child(path, key), "unknown key (allowed: " + list + ", comment, description, source)" +
                                 hint);
    }
  }
}

const nlohmann::json& required(const nlohmann::json& obj, std::string_view key,
                               const std::string& path) {
  const auto it = obj.find(std::string(key));
  if (it == obj.end()) fail(child(path, key), "required key is missing");
  return *it;
}

double number(const nlohmann::json& v, const std::string& path) {
  if (!v.is_number()) fail(path, "must be a number; got " + shown(v));
  const double d = v.get<double>();
  if (!std::isfinite(d)) fail(path, "must be finite; got " + shown(v));
  return d;
}

std::vector<double> numbers(const nlohmann::json& v, const std::string& path,
                            std::size_t min_size, std::size_t max_size) {
  if (!v.is_array()) fail(path, "must be an array of numbers; got " + shown(v));
  if (v.size() < min_size || v.size() > max_size) {
    fail(path, "must have " +
                   (min_size == max_size ? std::to_string(min_size)
                                         : std::to_string(min_size) + " to " +
                                               std::to_string(max_size)) +
                   " elements; got " + std::to_string(v.size()));
  }
  std::vector<double> out;
  out.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out.push_back(number(v[i], element(path, i)));
  return out;
}

Axis axis_from_name(const nlohmann::json& v, const std::string& path) {
  if (!v.is_string()) fail(path, "must be an axis name \"X\", \"Y\" or \"Z\"; got " + shown(v));
  const auto s = v.get<std::string>();
  if (s == "X") return Axis::x;
  if (s == "Y") return Axis::y;
  if (s == "Z") return Axis::z;
  fail(path, "unknown axis name (allowed: \"X\", \"Y\", \"Z\"); got " + shown(v));
}

KinematicChain parse_chain(const nlohmann::json& v, const std::string& path) {
  if (v.is_string()) {
    const auto s = v.get<std::string>();
    if (s == "moving_bridge" || s == "gantry") return KinematicChain::moving_bridge();
    if (s == "fixed_bridge" || s == "moving_table") return KinematicChain::fixed_bridge();
    fail(path, "unknown chain preset (allowed: \"moving_bridge\", \"gantry\", \"fixed_bridge\", "
               "\"moving_table\", or an object with tool_side and workpiece_side); got " +
                   shown(v));
  }
  require_object(v, path);
  check_keys(v, path, {"tool_side", "workpiece_side"});
  KinematicChain chain;
  for (const auto* side : {"tool_side", "workpiece_side"}) {
    const std::string p = child(path, side);
    const nlohmann::json& list = required(v, side, path);
    if (!list.is_array()) fail(p, "must be an array of axis names; got " + shown(list));
    auto& dst = std::string_view(side) == "tool_side" ? chain.tool_side : chain.workpiece_side;
    for (std::size_t i = 0; i < list.size(); ++i) dst.push_back(axis_from_name(list[i], element(p, i)));
  }
  int seen[3] = {0, 0, 0};
  for (Axis a : chain.tool_side) ++seen[static_cast<int>(a)];
  for (Axis a : chain.workpiece_side) ++seen[static_cast<int>(a)];
  for (int k = 0; k < 3; ++k) {
    if (seen[k] != 1) {
      fail(path, "every axis must appear exactly once in tool_side + workpiece_side; axis " +
                     std::string(name(static_cast<Axis>(k))) + " appears " +
                     std::to_string(seen[k]) + " times");
    }
  }
  return chain;
}

ErrorFunctionEstimate parse_function(const nlohmann::json& v, const std::string& path,
                                     AxisError e) {
  require_object(v, path);
  const bool rot = is_rotation(e);
  const std::string unit = rot ? "urad" : "um";
  const double to_internal = rot ? kUrad : kUm;
  const std::string kc = "legendre_" + unit, ku = "uncertainty_" + unit;
  check_keys(v, path, {kc, ku, "correlation"},
             rot ? " (a rotation error takes µrad: legendre_urad, uncertainty_urad)"
                 : " (a translation error takes µm: legendre_um, uncertainty_um)");
  ErrorFunctionEstimate fn;
  const auto c = numbers(required(v, kc, path), child(path, kc), 1,
                         static_cast<std::size_t>(max_legendre_degree + 1));
  const auto u = numbers(required(v, ku, path), child(path, ku), c.size(), c.size());
  // Each coefficient and uncertainty in its physical range (physical_ranges.h).
  const PhysicalRange& value_range =
      rot ? physical_range::kinematic_rotation_urad : physical_range::kinematic_error_um;
  const PhysicalRange& u_range = rot ? physical_range::rotation_u_urad : physical_range::length_sigma_um;
  for (std::size_t i = 0; i < c.size(); ++i)
    if (const std::string problem = range_problem(value_range, c[i]); !problem.empty())
      fail(element(child(path, kc), i), problem);
  for (std::size_t i = 0; i < u.size(); ++i)
    if (const std::string problem = range_problem(u_range, u[i]); !problem.empty())
      fail(element(child(path, ku), i), problem);
  for (double x : c) fn.coefficients.push_back(x * to_internal);
  for (double x : u) fn.standard_uncertainties.push_back(x * to_internal);
  if (const auto it = v.find("correlation"); it != v.end()) {
    const std::string p = child(path, "correlation");
    const auto n = c.size();
    if (!it->is_array() || it->size() != n) {
      fail(p, "must be an array of " + std::to_string(n) + " rows of " + std::to_string(n) +
                  " numbers; got " + shown(*it));
    }
    const auto ni = static_cast<Eigen::Index>(n);
    Eigen::MatrixXd r(ni, ni);
    for (std::size_t i = 0; i < n; ++i) {
      const auto row = numbers((*it)[i], element(p, i), n, n);
      for (std::size_t j = 0; j < n; ++j) {
        r(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = row[j];
      }
    }
    // 1e-12: hand-typed decimals round-trip to ~1e-16; a larger mismatch is a typing error.
    for (Eigen::Index i = 0; i < ni; ++i) {
      for (Eigen::Index j = 0; j < ni; ++j) {
        const std::string at = element(element(p, static_cast<std::size_t>(i)),
                                       static_cast<std::size_t>(j));
        if (i == j && std::abs(r(i, j) - 1.0) > 1e-12) {
          fail(at, "diagonal of a correlation matrix must be 1; got " + shown((*it)[i][j]));
        }
        if (std::abs(r(i, j)) > 1.0) fail(at, "must lie in [-1, 1]; got " + shown((*it)[i][j]));
        if (std::abs(r(i, j) - r(j, i)) > 1e-12) {
          fail(at, "correlation must be symmetric; got " + shown((*it)[i][j]) + " but [" +
                       std::to_string(j) + "][" + std::to_string(i) + "] is " +
                       shown((*it)[j][i]));
        }
      }
    }
    std::vector<Eigen::Index> idx;
    for (std::size_t i = 0; i < n; ++i) {
      if (u[i] > 0.0) idx.push_back(static_cast<Eigen::Index>(i));
    }
    const auto k = static_cast<Eigen::Index>(idx.size());
    Eigen::MatrixXd sub(k, k);
    for (Eigen::Index a = 0; a < k; ++a) {
      for (Eigen::Index b = 0; b < k; ++b) {
        sub(a, b) = r(idx[static_cast<std::size_t>(a)], idx[static_cast<std::size_t>(b)]);
      }
    }
    if (k > 0 && Eigen::LLT<Eigen::MatrixXd>(sub).info() != Eigen::Success) {
      fail(p, "must be positive definite (on the coefficients with non-zero uncertainty); got " +
                  shown(*it));
    }
    fn.correlation = std::move(r);
  }
  return fn;
}

}  // namespace

KinematicModel kinematic_model_from_json(const nlohmann::json& section,
                                         const std::string& key_path) {
  require_object(section, key_path);
  check_keys(section, key_path, {"chain", "axis_range_mm", "errors", "squareness"});

  const KinematicChain chain = parse_chain(required(section, "chain", key_path),
                                           child(key_path, "chain"));

  std::array<AxisRange, 3> ranges{};
  {
    const std::string p = child(key_path, "axis_range_mm");
    const nlohmann::json& obj = required(section, "axis_range_mm", key_path);
    require_object(obj, p);
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      if (is_free_key(it.key())) continue;
      (void)axis_from_name(it.key(), child(p, it.key()));  // rejects unknown axis names
    }
    for (int k = 0; k < 3; ++k) {
      const std::string an(name(static_cast<Axis>(k)));
      const auto r = numbers(required(obj, an, p), child(p, an), 2, 2);
      if (!(r[0] < r[1])) {
        fail(child(p, an), "must be [min, max] with min < max; got " + shown(obj[an]));
      }
      ranges[static_cast<std::size_t>(k)] = {r[0], r[1]};
    }
  }

  std::array<ErrorFunctionEstimate, axis_error_count> functions;
  {
    const std::string p = child(key_path, "errors");
    const nlohmann::json& obj = required(section, "errors", key_path);
    require_object(obj, p);
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      if (is_free_key(it.key())) continue;
      bool known = false;
      for (int f = 0; f < axis_error_count; ++f) known = known || it.key() == name(static_cast<AxisError>(f));
      if (!known) {
        fail(child(p, it.key()),
             "unknown error name (the 18 ISO 230-1 names E_XX, E_YX, E_ZX, E_AX, E_BX, E_CX, "
             "E_XY, …, E_CZ; squareness goes under \"squareness\")");
      }
    }
    for (int f = 0; f < axis_error_count; ++f) {
      const auto e = static_cast<AxisError>(f);
      const std::string en(name(e));
      functions[static_cast<std::size_t>(f)] =
          parse_function(required(obj, en, p), child(p, en), e);
    }
  }

  std::array<EstimatedValue, squareness_count> squareness{};
  {
    const std::string p = child(key_path, "squareness");
    const nlohmann::json& obj = required(section, "squareness", key_path);
    require_object(obj, p);
    check_keys(obj, p, {"E_C0Y", "E_B0Z", "E_A0Z"});
    for (int s = 0; s < squareness_count; ++s) {
      const std::string sn(name(static_cast<Squareness>(s)));
      const std::string ps = child(p, sn);
      const nlohmann::json& v = required(obj, sn, p);
      require_object(v, ps);
      check_keys(v, ps, {"value_urad", "uncertainty_urad"});
      const double value = number(required(v, "value_urad", ps), child(ps, "value_urad"));
      const double u = number(required(v, "uncertainty_urad", ps), child(ps, "uncertainty_urad"));
      if (const std::string problem = range_problem(physical_range::kinematic_rotation_urad, value);
          !problem.empty())
        fail(child(ps, "value_urad"), problem);
      if (const std::string problem = range_problem(physical_range::rotation_u_urad, u);
          !problem.empty())
        fail(child(ps, "uncertainty_urad"), problem);
      squareness[static_cast<std::size_t>(s)] = {value * kUrad, u * kUrad};
    }
  }

  try {
    return KinematicModel(chain, ranges, functions, squareness);
  } catch (const std::invalid_argument& ex) {  // all rules are checked above; defensive
    throw std::invalid_argument(key_path + ": " + ex.what());
  }
}

}  // namespace vcmm::errormodel
