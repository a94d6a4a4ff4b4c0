// characterization/src/output_checks.h (internal) — what every characterisation output passes
// before it is written: every number finite (nlohmann writes NaN and infinity as null, which the
// model loader then refuses far from the cause), and the consistency verdict as JSON.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>

#include "vcmm/characterization/consistency.h"
#include "vcmm/errormodel/errors.h"

namespace vcmm::characterization::internal {

/// Throws errormodel::InvalidInput naming the output key (e.g. "noise.scanning_sigma_um"), the
/// value and `inputs` (the files and options it was computed from) if any number in `j` is not
/// finite. O(size of j).
template <class Json>
void require_finite_numbers(const Json& j, std::string_view inputs, const std::string& key = "") {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it)
      require_finite_numbers(it.value(), inputs, key.empty() ? it.key() : key + "." + it.key());
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i)
      require_finite_numbers(j[i], inputs, key + "[" + std::to_string(i) + "]");
  } else if (j.is_number_float()) {
    const double v = j.template get<double>();
    if (!std::isfinite(v)) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%g", v);
      throw errormodel::InvalidInput("the result '" + key + "' is not finite (" + buf +
                                     "): computed from " + std::string(inputs) +
                                     " — a value out of any physical range there; nothing written");
    }
  }
}

/// The consistency verdict for a diagnostics block; `accepted` marks a refusal overridden by
/// the user (--accept-inconsistent).
template <class Json>
Json consistency_json(const ConsistencyTest& t, bool accepted) {
  Json o = Json::object();
  o["passed"] = t.passed();
  if (!t.passed()) o["accepted_although_inconsistent"] = accepted;
  o["sigma_stated"] = t.sigma_stated;
  o["chi_squared"] = t.chi_squared;
  o["degrees_of_freedom"] = t.degrees_of_freedom;
  o["chi_squared_per_dof"] = t.degrees_of_freedom > 0.0 ? t.chi_squared / t.degrees_of_freedom : 0.0;
  o["birge_ratio"] = t.birge_ratio;
  o["p_value"] = t.p_value;
  o["chi_squared_level"] = t.levels.chi_squared;
  o["chi_squared_passed"] = t.chi_squared_passed;
  o["outlier_level"] = t.levels.outlier;
  o["outlier_threshold"] = t.outlier_threshold;
  o["residuals_tested"] = t.tested;
  if (t.largest) {
    o["largest_normalized_residual"] = t.largest->normalized;
    o["largest_at"] = t.largest->group + ": " + t.largest->where;
  }
  Json out = Json::array();
  for (const ResidualOutlier& r : t.outliers)
    out.push_back({{"at", r.group + ": " + r.where},
                   {"residual_um", r.value * 1e3},
                   {"uncertainty_um", r.uncertainty * 1e3},
                   {"normalized", r.normalized}});
  o["outliers"] = out;
  o["summary"] = t.summary();
  return o;
}

}  // namespace vcmm::characterization::internal
