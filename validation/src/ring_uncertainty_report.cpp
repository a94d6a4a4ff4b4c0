#include "vcmm/validation/ring_uncertainty_report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "internal/budget_json.h"
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

/// Whether the quadrature sum agrees with the full u to Monte Carlo precision: the sample
/// covariances of independent sources make the ratio differ from 1 by at most ~1/√(2M) (one
/// standard error of u, relative); four of them (ring_uncertainty_budget.h, docs).
bool adds_in_quadrature(double ratio, std::uint64_t trials) {
  return std::abs(ratio - 1.0) <= 4.0 / std::sqrt(2.0 * static_cast<double>(trials - 1));
}

std::string budget_note(const UncertaintyBudget& b) {
  std::string note =
      "Each source alone (the others at their estimates), on the very random numbers it has in "
      "the full run (common random numbers), " + std::to_string(b.trials) +
      " trials a source. share_of_variance = u_i^2 / sum of u_j^2.";
  const auto sentence = [&](const char* name, double ratio) {
    std::string out = std::string(" ") + name + ": quadrature sum / full u = ";
    if (!std::isfinite(ratio)) return out + "undefined (full u = 0).";
    char text[32];
    std::snprintf(text, sizeof text, "%.3f", ratio);
    out += text;
    if (adds_in_quadrature(ratio, b.trials))
      return out + ", the u_i add in quadrature to Monte Carlo precision.";
    return out + ", the u_i do NOT add in quadrature.";
  };
  note += sentence("Diameter",
                   internal::budget_ratio(b.diameter_quadrature_mm, b.diameter_full_u_mm));
  note += sentence("Roundness",
                   internal::budget_ratio(b.roundness_quadrature_mm, b.roundness_full_u_mm));
  note +=
      " RONt is not linear in the errors (a peak-to-valley of summed deviations is not a sum; "
      "each source alone biases it upward on its own): its u_i need not add in quadrature, and "
      "its shares rank the sources rather than split u^2.";
  return note;
}

nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

}  // namespace

namespace internal {

double budget_ratio(double quadrature, double full) {
  return full > 0.0 ? quadrature / full : std::numeric_limits<double>::quiet_NaN();
}

nlohmann::json budget_json(const UncertaintyBudget& b) {
  nlohmann::json sources = nlohmann::json::array();
  for (const SourceContribution& c : b.sources) {
    sources.push_back({{"source", std::string(errormodel::to_string(c.source))},
                       {"evaluated", c.evaluated},
                       {"diameter_u_mm", c.diameter_u_mm},
                       {"roundness_u_um", c.roundness_u_mm * kUmPerMm},
                       {"share_of_variance",
                        {{"diameter", c.diameter_share}, {"roundness", c.roundness_share}}}});
  }
  return {{"method", "one source at a time, common random numbers"},
          {"trials", b.trials},
          {"wall_seconds", b.wall_seconds},
          {"sources", std::move(sources)},
          {"quadrature_sum",
           {{"diameter_u_mm", b.diameter_quadrature_mm},
            {"roundness_u_um", b.roundness_quadrature_mm * kUmPerMm},
            {"full_diameter_u_mm", b.diameter_full_u_mm},
            {"full_roundness_u_um", b.roundness_full_u_mm * kUmPerMm},
            {"diameter_ratio",
             number_or_null(budget_ratio(b.diameter_quadrature_mm, b.diameter_full_u_mm))},
            {"roundness_ratio",
             number_or_null(budget_ratio(b.roundness_quadrature_mm, b.roundness_full_u_mm))}}},
          {"note", budget_note(b)}};
}

UncertaintyBudget budget_from_json(const nlohmann::json& j) {
  UncertaintyBudget b;
  b.trials = j.at("trials").get<std::uint64_t>();
  b.wall_seconds = j.at("wall_seconds").get<double>();
  for (const nlohmann::json& s : j.at("sources")) {
    SourceContribution c;
    const std::string name = s.at("source").get<std::string>();
    const auto source = errormodel::error_source_from_string(name);
    if (!source) throw std::invalid_argument("budget: unknown error source \"" + name + "\"");
    c.source = *source;
    c.evaluated = s.at("evaluated").get<bool>();
    c.diameter_u_mm = s.at("diameter_u_mm").get<double>();
    c.roundness_u_mm = s.at("roundness_u_um").get<double>() / kUmPerMm;
    c.diameter_share = s.at("share_of_variance").at("diameter").get<double>();
    c.roundness_share = s.at("share_of_variance").at("roundness").get<double>();
    b.sources.push_back(c);
  }
  const nlohmann::json& q = j.at("quadrature_sum");
  b.diameter_quadrature_mm = q.at("diameter_u_mm").get<double>();
  b.roundness_quadrature_mm = q.at("roundness_u_um").get<double>() / kUmPerMm;
  b.diameter_full_u_mm = q.at("full_diameter_u_mm").get<double>();
  b.roundness_full_u_mm = q.at("full_roundness_u_um").get<double>() / kUmPerMm;
  return b;
}

}  // namespace internal

namespace {

/// A share as a bar of `width` characters and a percentage: "######     54 %".
std::string share_bar(double share) {
  constexpr int width = 10;
  const int n = static_cast<int>(std::lround(share * width));
  char pct[16];
  std::snprintf(pct, sizeof pct, " %3.0f %%", share * 100.0);
  return std::string(static_cast<std::size_t>(n), '#') +
         std::string(static_cast<std::size_t>(width - n), ' ') + pct;
}

/// `text` broken into lines of at most `width` characters at spaces, each indented by two.
std::string wrapped(const std::string& text, std::size_t width) {
  std::string out, line;
  std::istringstream words(text);
  std::string word;
  while (words >> word) {
    if (!line.empty() && line.size() + 1 + word.size() > width) {
      out += "  " + line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
  }
  if (!line.empty()) out += "  " + line + "\n";
  return out;
}

void budget_text(const UncertaintyBudget& b, std::ostringstream& os) {
  char line[256];
  os << "\nuncertainty budget: each source alone, common random numbers, " << b.trials
     << " trials a source\n";
  std::snprintf(line, sizeof line, "  %-16s %12s  %-16s %12s  %s\n", "source",
                "u diam. (mm)", "share", "u RONt (um)", "share");
  os << line;
  // Every u to two significant digits of its own: the budget compares sizes.
  const auto u_text = [](double u) {
    char t[32];
    std::snprintf(t, sizeof t, "%.*f", gum_decimals(u), u);
    return std::string(t);
  };
  for (const SourceContribution& c : b.sources) {
    const std::string name(to_string(c.source));
    if (!c.evaluated) {
      std::snprintf(line, sizeof line, "  %-16s %12s\n", name.c_str(), "(switched off)");
    } else {
      std::snprintf(line, sizeof line, "  %-16s %12s  %-16s %12s  %s\n", name.c_str(),
                    u_text(c.diameter_u_mm).c_str(), share_bar(c.diameter_share).c_str(),
                    u_text(c.roundness_u_mm * kUmPerMm).c_str(),
                    share_bar(c.roundness_share).c_str());
    }
    os << line;
  }
  const auto row = [&](const char* label, const std::string& d, const std::string& r) {
    std::snprintf(line, sizeof line, "  %-16s %12s  %16s %12s\n", label, d.c_str(), "",
                  r.c_str());
    os << line;
  };
  row("sqrt(sum u_i^2)", u_text(b.diameter_quadrature_mm),
      u_text(b.roundness_quadrature_mm * kUmPerMm));
  row("full run u", u_text(b.diameter_full_u_mm), u_text(b.roundness_full_u_mm * kUmPerMm));
  const auto ratio_text = [](double r) {
    char t[32];
    std::snprintf(t, sizeof t, "%.3f", r);
    return std::isfinite(r) ? std::string(t) : std::string("-");
  };
  row("ratio", ratio_text(internal::budget_ratio(b.diameter_quadrature_mm, b.diameter_full_u_mm)),
      ratio_text(internal::budget_ratio(b.roundness_quadrature_mm, b.roundness_full_u_mm)));
  os << wrapped(budget_note(b), 94);
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
                      {"ranks", mc.ranks},
                      {"status", std::string(uncertainty::to_string(mc.status))},
                      {"message", mc.message},
                      {"adaptive", options.adaptive.has_value()},
                      {"wall_seconds", mc.wall_seconds},
                      {"trial", {{"requested", std::string(to_string(options.trial))},
                                 {"kind", std::string(to_string(result.trial.kind))},
                                 {"reason", result.trial.reason}}}};
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
  if (result.budget) j["budget"] = internal::budget_json(*result.budget);
  return j.dump(2) + "\n";
}

std::string ring_uncertainty_text(const RingUncertaintyResult& result,
                                  const RingUncertaintyOptions& options) {
  std::ostringstream os;
  const auto& mc = result.monte_carlo;
  char line[256];
  os << "Monte Carlo (JCGM 101): " << mc.trials << " trials, seed " << options.monte_carlo.seed
     << ", " << (mc.ranks > 1 ? std::to_string(mc.ranks) + " processes x " : std::string())
     << mc.threads_used << " thread(s), " << uncertainty::to_string(mc.status);
  if (!mc.message.empty() && mc.status != uncertainty::RunStatus::completed)
    os << " (" << mc.message << ")";
  std::snprintf(line, sizeof line, ", %.2f s\n", mc.wall_seconds);
  os << line;
  os << "trial: " << to_string(result.trial.kind) << " (" << result.trial.reason << ")\n";
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
  if (result.budget) budget_text(*result.budget, os);
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
