#include "vcmm/validation/ring_uncertainty_report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "internal/number_text.h"
#include "vcmm/validation/provenance.h"

namespace vcmm::validation {
namespace {

constexpr double kUmPerMm = 1000.0;

struct MeasurandView {
  const char* name;
  const char* unit;
  const char* prose_unit;  // the unit in sentences ("µm" where the key says "um")
  double scale;  // mm → unit
  const uncertainty::MeasurandSummary* summary;
  const uncertainty::BiasCorrection* correction;  // the reported treatment's
  const uncertainty::BiasCorrection* paper;       // the study's
  std::string_view treatment;
  double estimate;
};

nlohmann::json correction_json(const uncertainty::BiasCorrection& c, double scale,
                               std::string_view prose_unit) {
  nlohmann::json j;
  j["bias"] = c.bias * scale;
  j["bias_standard_error"] = c.bias_standard_error * scale;
  j["bias_uncertainty"] = c.bias_uncertainty * scale;
  j["corrected"] = c.corrected * scale;
  j["corrected_standard_uncertainty"] = c.standard_uncertainty * scale;
  j["corrected_interval"] = {{"low", c.interval.low * scale}, {"high", c.interval.high * scale}};
  j["correction_applied"] = c.applied;
  j["correction_refused"] = c.refused;
  j["corrected_clamped_at_zero"] = c.clamped;
  j["note"] = uncertainty::describe(c, scale, prose_unit);
  return j;
}

nlohmann::json measurand_json(const MeasurandView& v) {
  const auto& s = *v.summary;
  const auto& c = *v.correction;
  nlohmann::json j;
  j["unit"] = v.unit;
  j["estimate"] = v.estimate * v.scale;
  j["mean"] = s.mean * v.scale;
  j["standard_uncertainty"] = s.standard_uncertainty * v.scale;
  j["coverage_interval"] = {
      {"probability", s.probabilistically_symmetric.probability},
      {"low", s.probabilistically_symmetric.low * v.scale},
      {"high", s.probabilistically_symmetric.high * v.scale},
      {"shortest_low", s.shortest.low * v.scale},
      {"shortest_high", s.shortest.high * v.scale}};
  j["bias_treatment"] = std::string(v.treatment);
  j.update(correction_json(c, v.scale, v.prose_unit));
  j["paper"] = correction_json(*v.paper, v.scale, v.prose_unit);
  return j;
}

std::array<MeasurandView, 2> views(const RingUncertaintyResult& r) {
  return {{{"diameter", "mm", "mm", 1.0, &r.monte_carlo.summaries.at(diameter), &r.diameter,
            &r.diameter, "paper", r.estimate.diameter_mm},
           {"roundness", "um", "µm", kUmPerMm, &r.monte_carlo.summaries.at(roundness), &r.roundness,
            &r.roundness_paper, to_string(r.roundness_treatment), r.estimate.roundness_mm}}};
}

/// Decimal places of a reported value in GUM style (JCGM 100 7.2.6): the standard
/// uncertainty with two significant digits, every value of the measurand to the same place.
/// 4 when u is 0 or not finite; at most 9.
int gum_decimals(double u) {
  if (!(u > 0.0) || !std::isfinite(u)) return 4;
  const int d = 1 - static_cast<int>(std::floor(std::log10(u)));
  return std::clamp(d, 0, 9);
}

}  // namespace

std::string ring_uncertainty_json(const RingUncertaintyResult& result,
                                  const RingUncertaintyOptions& options) {
  nlohmann::json j;
  j["schema"] = "vcmm.uncertainty_result";
  j["schema_version"] = 1;
  nlohmann::json prov = {{"vcmm_version", std::string(vcmm_version())},
                         {"git_revision", std::string(vcmm_revision())}};
  for (const auto& [k, v] : options.provenance) prov[k] = v;
  j["provenance"] = std::move(prov);
  const auto& mc = result.monte_carlo;
  j["evaluation"] = {
      {"reference_circle", std::string(to_string(options.evaluation.reference))},
      {"filter_cutoff_upr", options.evaluation.filter_cutoff_upr
                                ? nlohmann::json(*options.evaluation.filter_cutoff_upr)
                                : nlohmann::json(nullptr)}};
  j["monte_carlo"] = {{"trials", mc.trials},
                      {"seed", options.monte_carlo.seed},
                      {"threads", mc.threads_used},
                      {"status", std::string(uncertainty::to_string(mc.status))},
                      {"message", mc.message},
                      {"adaptive", options.adaptive.has_value()},
                      {"wall_seconds", mc.wall_seconds}};
  if (mc.summaries.empty()) {  // cancelled below the minimum sample count
    j["measurands"] = nullptr;
    return j.dump(2) + "\n";
  }
  for (const MeasurandView& v : views(result)) j["measurands"][v.name] = measurand_json(v);
  if (result.surrogate) {
    const SurrogateRun& s = *result.surrogate;
    const auto& y = s.monte_carlo.summaries.at(surrogate_roundness);
    const auto& z = s.monte_carlo.summaries.at(surrogate_shrunk);
    j["shrinkage"] = {
        {"unit", "um"},
        {"pilot_trials", s.shrinkage.pilot_trials},
        {"max_order", s.shrinkage.max_order},
        {"dominant_orders", s.shrinkage.dominant_orders},
        {"median_error_power_um2", s.shrinkage.median_error_power_mm2 * kUmPerMm * kUmPerMm},
        {"kept_harmonics", s.surrogate.kept_harmonics},
        {"surrogate_roundness", s.surrogate.measurands.roundness_mm * kUmPerMm},
        {"trials", s.monte_carlo.trials},
        {"mean_at_surrogate", y.mean * kUmPerMm},
        {"u_at_surrogate", y.standard_uncertainty * kUmPerMm},
        {"u_of_surrogate_estimate", z.standard_uncertainty * kUmPerMm}};
  }
  if (mc.correlation.size() == 4) j["correlation_diameter_roundness"] = mc.correlation[1];
  return j.dump(2) + "\n";
}

std::string ring_uncertainty_text(const RingUncertaintyResult& result,
                                  const RingUncertaintyOptions& options) {
  std::ostringstream os;
  const auto& mc = result.monte_carlo;
  char line[256];
  os << "Monte Carlo (JCGM 101): " << mc.trials << " trials, seed " << options.monte_carlo.seed
     << ", " << mc.threads_used << " thread(s), " << uncertainty::to_string(mc.status);
  if (!mc.message.empty() && mc.status != uncertainty::RunStatus::completed)
    os << " (" << mc.message << ")";
  std::snprintf(line, sizeof line, ", %.2f s\n", mc.wall_seconds);
  os << line;
  os << "roundness: RONt about the " << to_string(options.evaluation.reference) << " circle, ";
  if (options.evaluation.filter_cutoff_upr) {
    os << "Gaussian filter " << internal::shortest(*options.evaluation.filter_cutoff_upr)
       << " UPR\n";
  } else {
    os << "unfiltered\n";
  }
  os << "vcmm " << vcmm_version() << " (" << vcmm_revision() << ")";
  if (const auto m = options.provenance.find("model_sha256"); m != options.provenance.end())
    os << ", model sha256 " << m->second.substr(0, 16) << "…";
  os << "\n";
  if (mc.summaries.empty()) {
    os << "too few trials completed for statistics\n";
    return os.str();
  }
  const double p = mc.summaries.at(0).probabilistically_symmetric.probability;
  for (const MeasurandView& v : views(result)) {
    const auto& s = *v.summary;
    const auto& c = *v.correction;
    const int digits = gum_decimals(s.standard_uncertainty * v.scale);
    os << "\n" << v.name << " (" << v.unit << ")\n";
    auto row = [&](const char* label, double value) {
      std::snprintf(line, sizeof line, "  %-28s %.*f\n", label, digits, value * v.scale);
      os << line;
    };
    row("estimate from data", v.estimate);
    row("Monte Carlo mean", s.mean);
    row("standard uncertainty u", s.standard_uncertainty);
    row("expanded U (k = 2)", 2.0 * s.standard_uncertainty);
    const std::string percent = std::to_string(static_cast<int>(p * 100.0 + 0.5)) + " % interval";
    for (const auto& [kind, ci] : {std::pair{" (symmetric)", &s.probabilistically_symmetric},
                                   std::pair{" (shortest)", &s.shortest}}) {
      std::snprintf(line, sizeof line, "  %-28s [%.*f, %.*f]\n", (percent + kind).c_str(), digits,
                    ci->low * v.scale, digits, ci->high * v.scale);
      os << line;
    }
    const auto treatment_rows = [&](const uncertainty::BiasCorrection& t, bool surrogate) {
      // The bias to the place of its own Monte Carlo standard error (at least the
      // measurand's): −0.0000040 (MC standard error 0.0000066), never "-0.00000".
      const int bias_digits = std::max(digits, gum_decimals(t.bias_standard_error * v.scale));
      std::snprintf(line, sizeof line, "  %-28s %.*f (MC standard error %.*f)\n",
                    surrogate ? "bias (at the surrogate)" : "bias (mean - estimate)",
                    bias_digits, t.bias * v.scale, bias_digits, t.bias_standard_error * v.scale);
      os << line;
      if (surrogate) row("u of the bias estimate", t.bias_uncertainty);
      row(t.applied ? "corrected estimate" : "reported (uncorrected)", t.corrected);
      row("its standard uncertainty", t.standard_uncertainty);
      std::snprintf(line, sizeof line, "  %-28s [%.*f, %.*f]\n", "its interval", digits,
                    t.interval.low * v.scale, digits, t.interval.high * v.scale);
      os << line;
    };
    const bool shrinkage = v.correction != v.paper && v.treatment == "shrinkage";
    if (shrinkage) {
      os << "  -- bias treatment: shrinkage (default; docs/validation.md)\n";
      treatment_rows(c, true);
      if (c.clamped) os << "  correction: the corrected value fell below 0 and is reported as 0\n";
      os << "  -- the seed study's treatment (bias of the Monte Carlo on the measured data)\n";
    }
    treatment_rows(*v.paper, false);
    os << "  correction: "
       << (v.paper->applied
               ? "applied (the interval is the Monte Carlo interval reflected about the "
                 "estimate)"
               : "refused: it would make the value negative; the uncorrected estimate is "
                 "reported with u enlarged by |bias| and the interval widened by |bias|")
       << "\n";
  }
  return os.str();
}

std::string ring_samples_csv(const uncertainty::MonteCarloResult& mc) {
  std::string out = "diameter_mm,roundness_um\n";
  out.reserve(out.size() + static_cast<std::size_t>(mc.trials) * 40);
  const std::size_t q = mc.measurand_count;
  for (std::uint64_t t = 0; t < mc.trials; ++t) {
    out += internal::shortest(mc.samples[t * q + diameter]);
    out += ',';
    out += internal::shortest(mc.samples[t * q + roundness] * kUmPerMm);
    out += '\n';
  }
  return out;
}

}  // namespace vcmm::validation
