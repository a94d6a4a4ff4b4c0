// validation/src/campaign_run.cpp — the campaign runner (see the header for the treatments and
// the resume rule; docs/validation.md for the method).
#include "vcmm/validation/campaign_run.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <functional>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "internal/budget_json.h"
#include "internal/number_text.h"
#include "vcmm/errormodel/atomic_file.h"
#include "vcmm/errormodel/digital_model.h"
#include "vcmm/uncertainty/errors.h"
#include "vcmm/uncertainty/process_group.h"
#include "vcmm/validation/comparison.h"
#include "vcmm/validation/provenance.h"
#include "vcmm/validation/ring_uncertainty_report.h"
#include "vcmm/geometry/text_file.h"

namespace vcmm::validation {
namespace {

namespace em = vcmm::errormodel;
namespace fs = std::filesystem;
using nlohmann::json;
using internal::shortest;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kUmPerMm = 1000.0;
/// Setup values must equal the points file's metadata to this (both are written as shortest
/// round-trip decimals, so an honest match is exact; the slack only forgives hand-written
/// rounding far below any physical meaning).
constexpr double kSetupToleranceMm = 1e-9;
constexpr double kSetupToleranceDeg = 1e-9;
constexpr double kSetupToleranceC = 1e-9;
/// Version of the per-measurement file; part of the fingerprint (a format change recomputes).
/// v3: the optional "budget" object.
constexpr const char* kOutcomeFormat = "vcmm.campaign_measurement.v3";

std::string read_bytes(const fs::path& p) {
  return geometry::read_text_file(p.string(), "file");
}

/// FNV-1a 64 over a sequence of byte strings (with their lengths, so boundaries count).
class Fingerprint {
 public:
  void add(const std::string& bytes) {
    add_raw(std::to_string(bytes.size()) + ":");
    add_raw(bytes);
  }
  std::string hex() const {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h_));
    return buf;
  }

 private:
  void add_raw(const std::string& s) {
    for (unsigned char c : s) {
      h_ ^= c;
      h_ *= 0x100000001b3ULL;
    }
  }
  std::uint64_t h_ = 0xcbf29ce484222325ULL;
};

[[noreturn]] void setup_error(const Campaign& c, std::size_t i, const std::string& path,
                              const std::string& message) {
  const std::string index = "measurements[" + std::to_string(i) + "]";
  throw CampaignError(c.source, i, c.measurements[i].id, index + "." + path,
                      c.source + ": " + index + " (\"" + c.measurements[i].id + "\")." + path +
                          ": " + message);
}

/// The points file's metadata must agree with the campaign's setup where both give it.
void check_setup(const Campaign& c, std::size_t i, const em::Measurement& m) {
  const Setup& s = c.measurements[i].setup;
  const std::string file = c.measurements[i].points_path.string();
  if (s.mode != m.mode)
    setup_error(c, i, "setup.mode",
                "mode \"" + std::string(em::to_string(s.mode)) + "\" but the points file " + file +
                    " says \"" + std::string(em::to_string(m.mode)) + "\"");
  if (s.location_mm) {
    for (int k = 0; k < 3; ++k) {
      if (std::abs((*s.location_mm)[static_cast<std::size_t>(k)] - m.placement.location_mm[k]) >
          kSetupToleranceMm)
        setup_error(c, i, "setup.location_mm",
                    "component " + std::to_string(k) + " is " +
                        shortest((*s.location_mm)[static_cast<std::size_t>(k)]) +
                        " mm but the points file " + file + " says " +
                        shortest(m.placement.location_mm[k]) + " mm");
    }
  }
  const double file_deg = m.placement.orientation_rad * 180.0 / std::numbers::pi;
  if (std::abs(std::remainder(s.orientation_deg - file_deg, 360.0)) > kSetupToleranceDeg)
    setup_error(c, i, "setup.orientation_deg",
                shortest(s.orientation_deg) + " deg but the points file " + file + " says " +
                    shortest(file_deg) + " deg");
  if (s.temperature_c && std::abs(*s.temperature_c - m.temperature_c) > kSetupToleranceC)
    setup_error(c, i, "setup.temperature_c",
                shortest(*s.temperature_c) + " C but the points file " + file + " says " +
                    shortest(m.temperature_c) + " C");
}

/// The entry's points file as a Measurement: vcmm's measurement CSV with its own metadata, or
/// a plain point file / roundness-meter profile with the metadata from the entry's setup
/// (measurement_input.h). Errors name the entry and the setup key.
em::Measurement read_entry_points(const Campaign& c, std::size_t i) {
  const CampaignMeasurement& entry = c.measurements[i];
  const Setup& s = entry.setup;
  const std::string file = entry.points_path.string();
  const MeasurementFileKind kind = detect_measurement_file_kind(read_bytes(entry.points_path));
  if (kind == MeasurementFileKind::vcmm_measurement) {
    if (s.has_plain_file_keys())
      setup_error(c, i, "setup",
                  "stylus_offset_mm, frame, surface, radius_mm and profile_height_mm are for "
                  "plain point files and profiles; " + file +
                      " is vcmm's measurement CSV and carries its own metadata");
    return em::read_measurement_csv_file(file);
  }
  const bool profile = kind == MeasurementFileKind::roundness_profile;
  if (!s.temperature_c)
    setup_error(c, i, "setup.temperature_c",
                "required: " + file + " is a plain " + (profile ? "profile" : "point file") +
                    " with no metadata (the workpiece temperature reading, °C)");
  if (!s.stylus_offset_mm)
    setup_error(c, i, "setup.stylus_offset_mm",
                "required: " + file + " has no metadata (the tip relative to the ram, [x, y, z] mm)");
  if (!s.location_mm && (profile || s.frame == PointFrame::workpiece))
    setup_error(c, i, "setup.location_mm",
                "required for " + std::string(profile ? "a roundness-meter profile"
                                                      : "points in the workpiece frame") +
                    " (the ring centre in machine coordinates, [x, y, z] mm)");
  if (profile && !s.radius_mm)
    setup_error(c, i, "setup.radius_mm",
                "required for a roundness-meter profile (the nominal radius of its deviations, mm)");
  MeasurementSetup ms;
  ms.mode = s.mode;
  ms.temperature_c = s.temperature_c;
  ms.orientation_deg = s.orientation_deg;
  const auto vec = [](const std::array<double, 3>& a) { return Eigen::Vector3d(a[0], a[1], a[2]); };
  if (s.location_mm) ms.location_mm = vec(*s.location_mm);
  ms.stylus_offset_mm = vec(*s.stylus_offset_mm);
  ms.frame = s.frame.value_or(PointFrame::machine);
  ms.side = s.surface.value_or(SurfaceSide::inner);
  ms.radius_mm = s.radius_mm;
  ms.height_mm = s.profile_height_mm.value_or(0.0);
  try {
    return read_measurement_file(file, ms);
  } catch (const geometry::InvalidInput& e) {
    setup_error(c, i, "points", e.what());
  }
}

/// The Monte Carlo summary of run (b) re-expressed about the estimate y: its bias b_dn
/// = ȳ_dn − f(denoised) applied to y (so correct_bias(y, ·) gives y − b_dn).
uncertainty::MeasurandSummary shifted(const uncertainty::MeasurandSummary& s, double by) {
  uncertainty::MeasurandSummary out = s;
  out.mean += by;
  out.probabilistically_symmetric.low += by;
  out.probabilistically_symmetric.high += by;
  out.shortest.low += by;
  out.shortest.high += by;
  return out;
}

void score(MeasurandOutcome& o, double k) {
  if (!o.has_reference) {
    o.en = o.en_corrected = o.en_paper = o.en_denoised = o.en_inflated = o.zeta =
        o.zeta_corrected = kNaN;
    return;
  }
  const double xr = o.reference_mm, ur = o.u_reference_mm;
  o.en = en_score(xr, ur, o.estimate_mm, o.u_mm, k);
  o.zeta = zeta_score(xr, ur, o.estimate_mm, o.u_mm);
  o.en_corrected = en_score(xr, ur, o.corrected_mm, o.u_corrected_mm, k);
  o.zeta_corrected = zeta_score(xr, ur, o.corrected_mm, o.u_corrected_mm);
  o.en_paper = en_score(xr, ur, o.corrected_paper_mm, o.u_corrected_paper_mm, k);
  o.en_denoised = std::isnan(o.corrected_denoised_mm)
                      ? kNaN
                      : en_score(xr, ur, o.corrected_denoised_mm, o.u_denoised_mm, k);
  o.en_inflated =
      en_score_expanded(xr, k * ur, o.estimate_mm, k * o.u_mm + std::abs(o.bias_paper_mm));
}

/// The outcome of one measurand from the uncertainty evaluation: the study's run on x̂, the
/// campaign's treatment (`chosen`) and the study's (`paper`). The note's numbers are given in
/// the measurand's reporting unit (`scale` per mm, `unit`).
void fill_outcome(MeasurandOutcome& o, double estimate, const uncertainty::MeasurandSummary& s,
                  const uncertainty::BiasCorrection& chosen, std::string_view treatment,
                  const uncertainty::BiasCorrection& paper, double scale, std::string_view unit) {
  o.estimate_mm = estimate;
  o.u_mm = s.standard_uncertainty;
  o.mc_mean_mm = s.mean;
  o.interval_low_mm = s.probabilistically_symmetric.low;
  o.interval_high_mm = s.probabilistically_symmetric.high;
  o.treatment = std::string(treatment);
  o.bias_mm = chosen.bias;
  o.bias_standard_error_mm = chosen.bias_standard_error;
  o.bias_uncertainty_mm = chosen.bias_uncertainty;
  o.corrected_mm = chosen.corrected;
  o.u_corrected_mm = chosen.standard_uncertainty;
  o.correction_applied = chosen.applied;
  o.note = uncertainty::describe(chosen, scale, unit);
  o.bias_paper_mm = paper.bias;
  o.corrected_paper_mm = paper.corrected;
  o.u_corrected_paper_mm = paper.standard_uncertainty;
  o.paper_applied = paper.applied;
}

// ---- per-measurement JSON (the resume file) --------------------------------------------------

json num(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
double to_num(const json& j) { return j.is_null() ? kNaN : j.get<double>(); }

json measurand_to_json(const MeasurandOutcome& o) {
  return {{"has_reference", o.has_reference},
          {"reference_mm", num(o.reference_mm)},
          {"u_reference_mm", num(o.u_reference_mm)},
          {"reference_method", o.reference_method},
          {"estimate_mm", num(o.estimate_mm)},
          {"u_mm", num(o.u_mm)},
          {"mc_mean_mm", num(o.mc_mean_mm)},
          {"interval_low_mm", num(o.interval_low_mm)},
          {"interval_high_mm", num(o.interval_high_mm)},
          {"treatment", o.treatment},
          {"bias_mm", num(o.bias_mm)},
          {"bias_standard_error_mm", num(o.bias_standard_error_mm)},
          {"bias_uncertainty_mm", num(o.bias_uncertainty_mm)},
          {"corrected_mm", num(o.corrected_mm)},
          {"u_corrected_mm", num(o.u_corrected_mm)},
          {"correction_applied", o.correction_applied},
          {"note", o.note},
          {"bias_paper_mm", num(o.bias_paper_mm)},
          {"corrected_paper_mm", num(o.corrected_paper_mm)},
          {"u_corrected_paper_mm", num(o.u_corrected_paper_mm)},
          {"paper_applied", o.paper_applied},
          {"corrected_denoised_mm", num(o.corrected_denoised_mm)},
          {"u_denoised_mm", num(o.u_denoised_mm)},
          {"denoised_applied", o.denoised_applied},
          {"En", num(o.en)},
          {"En_corrected", num(o.en_corrected)},
          {"En_paper", num(o.en_paper)},
          {"En_denoised", num(o.en_denoised)},
          {"En_inflated", num(o.en_inflated)},
          {"zeta", num(o.zeta)},
          {"zeta_corrected", num(o.zeta_corrected)},
          {"true_mm", num(o.true_mm)}};
}

MeasurandOutcome measurand_from_json(const json& j) {
  MeasurandOutcome o;
  o.has_reference = j.at("has_reference").get<bool>();
  o.reference_mm = to_num(j.at("reference_mm"));
  o.u_reference_mm = to_num(j.at("u_reference_mm"));
  o.reference_method = j.at("reference_method").get<std::string>();
  o.estimate_mm = to_num(j.at("estimate_mm"));
  o.u_mm = to_num(j.at("u_mm"));
  o.mc_mean_mm = to_num(j.at("mc_mean_mm"));
  o.interval_low_mm = to_num(j.at("interval_low_mm"));
  o.interval_high_mm = to_num(j.at("interval_high_mm"));
  o.treatment = j.at("treatment").get<std::string>();
  o.bias_mm = to_num(j.at("bias_mm"));
  o.bias_standard_error_mm = to_num(j.at("bias_standard_error_mm"));
  o.bias_uncertainty_mm = to_num(j.at("bias_uncertainty_mm"));
  o.corrected_mm = to_num(j.at("corrected_mm"));
  o.u_corrected_mm = to_num(j.at("u_corrected_mm"));
  o.correction_applied = j.at("correction_applied").get<bool>();
  o.note = j.at("note").get<std::string>();
  o.bias_paper_mm = to_num(j.at("bias_paper_mm"));
  o.corrected_paper_mm = to_num(j.at("corrected_paper_mm"));
  o.u_corrected_paper_mm = to_num(j.at("u_corrected_paper_mm"));
  o.paper_applied = j.at("paper_applied").get<bool>();
  o.corrected_denoised_mm = to_num(j.at("corrected_denoised_mm"));
  o.u_denoised_mm = to_num(j.at("u_denoised_mm"));
  o.denoised_applied = j.at("denoised_applied").get<bool>();
  o.en = to_num(j.at("En"));
  o.en_corrected = to_num(j.at("En_corrected"));
  o.en_paper = to_num(j.at("En_paper"));
  o.en_denoised = to_num(j.at("En_denoised"));
  o.en_inflated = to_num(j.at("En_inflated"));
  o.zeta = to_num(j.at("zeta"));
  o.zeta_corrected = to_num(j.at("zeta_corrected"));
  o.true_mm = to_num(j.at("true_mm"));
  return o;
}

json outcome_to_json(const MeasurementOutcome& o) {
  json j = {{"format", kOutcomeFormat},
            {"fingerprint", o.fingerprint},
            {"id", o.id},
            {"location", o.location},
            {"orientation_deg", o.orientation_deg},
            {"height", std::string(to_string(o.height))},
            {"mode", std::string(em::to_string(o.mode))},
            {"points", o.points},
            {"seed", o.seed},
            {"trials", o.trials},
            {"trial", o.trial},
            {"wall_seconds", o.wall_seconds},
            {"diameter", measurand_to_json(o.diameter)},
            {"roundness", measurand_to_json(o.roundness)}};
  if (o.budget) j["budget"] = internal::budget_json(*o.budget);
  return j;
}

MeasurementOutcome outcome_from_json(const json& j) {
  MeasurementOutcome o;
  o.fingerprint = j.at("fingerprint").get<std::string>();
  o.id = j.at("id").get<std::string>();
  o.location = j.at("location").get<std::string>();
  o.orientation_deg = j.at("orientation_deg").get<double>();
  o.height = height_from_string(j.at("height").get<std::string>()).value();
  o.mode = em::probing_mode_from_string(j.at("mode").get<std::string>()).value();
  o.points = j.at("points").get<std::size_t>();
  o.seed = j.at("seed").get<std::uint64_t>();
  o.trials = j.at("trials").get<std::uint64_t>();
  o.trial = j.value("trial", std::string("exact"));  // files before the spectral trial
  o.wall_seconds = j.at("wall_seconds").get<double>();
  o.diameter = measurand_from_json(j.at("diameter"));
  o.roundness = measurand_from_json(j.at("roundness"));
  if (const auto b = j.find("budget"); b != j.end()) o.budget = internal::budget_from_json(*b);
  return o;
}

/// A previous run's outcome for this fingerprint, if its file is intact and matches.
std::optional<MeasurementOutcome> load_previous(const fs::path& file,
                                                const std::string& fingerprint) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return std::nullopt;
  try {
    const json j = json::parse(read_bytes(file));
    if (j.at("format").get<std::string>() != kOutcomeFormat) return std::nullopt;
    if (j.at("fingerprint").get<std::string>() != fingerprint) return std::nullopt;
    MeasurementOutcome o = outcome_from_json(j);
    o.resumed = true;
    return o;
  } catch (const std::exception&) {
    return std::nullopt;  // unreadable or foreign: recompute and overwrite
  }
}

std::string residuals_csv(const RingProfileEvaluation& e) {
  // In angular order about the reference centre.
  std::vector<std::size_t> order(e.angle_rad.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return e.angle_rad[a] < e.angle_rad[b]; });
  std::string out = "angle_deg,deviation_um,filtered_deviation_um\n";
  for (std::size_t i : order) {
    out += shortest(e.angle_rad[i] * 180.0 / std::numbers::pi) + "," +
           shortest(e.deviation_mm[i] * kUmPerMm) + "," +
           shortest(e.filtered_deviation_mm[i] * kUmPerMm) + "\n";
  }
  return out;
}

// ---- tables -------------------------------------------------------------------------------

std::string cell(double v) { return std::isfinite(v) ? shortest(v) : std::string(); }

std::string results_csv(const std::vector<MeasurementOutcome>& outcomes) {
  std::string out =
      "id,location,orientation_deg,height,mode,measurand,unit,reference,u_reference,estimate,u,"
      "mc_mean,interval_low,interval_high,treatment,bias,u_bias,corrected,u_corrected,"
      "correction_applied,bias_paper,corrected_paper,u_corrected_paper,paper_applied,"
      "En,En_corrected,En_paper,zeta,zeta_corrected,corrected_denoised,En_denoised,En_inflated,"
      "true_value\n";
  for (const auto& m : outcomes) {
    for (int which = 0; which < 2; ++which) {
      const MeasurandOutcome& o = which == 0 ? m.diameter : m.roundness;
      const double s = which == 0 ? 1.0 : kUmPerMm;
      const double nan = kNaN;
      const auto v = [&](double x) { return cell(x * s) + ","; };
      const auto e = [&](double x) { return cell(x) + ","; };
      out += m.id + "," + m.location + "," + shortest(m.orientation_deg) + "," +
             std::string(to_string(m.height)) + "," + std::string(em::to_string(m.mode)) + "," +
             (which == 0 ? "diameter,mm," : "roundness,um,") +
             v(o.has_reference ? o.reference_mm : nan) +
             v(o.has_reference ? o.u_reference_mm : nan) + v(o.estimate_mm) + v(o.u_mm) +
             v(o.mc_mean_mm) + v(o.interval_low_mm) + v(o.interval_high_mm) + o.treatment + "," +
             v(o.bias_mm) + v(o.bias_uncertainty_mm) + v(o.corrected_mm) + v(o.u_corrected_mm) +
             (o.correction_applied ? "true," : "false,") + v(o.bias_paper_mm) +
             v(o.corrected_paper_mm) + v(o.u_corrected_paper_mm) +
             (o.paper_applied ? "true," : "false,") + e(o.en) + e(o.en_corrected) +
             e(o.en_paper) + e(o.zeta) + e(o.zeta_corrected) + v(o.corrected_denoised_mm) +
             e(o.en_denoised) + e(o.en_inflated) + cell(o.true_mm * s) + "\n";
    }
  }
  return out;
}

std::string summary_csv(const std::vector<SummaryRow>& rows) {
  std::string out = "factor,level,measurand,treatment,n,share_abs_En_le_1,mean_En,rms_En\n";
  for (const auto& r : rows)
    out += r.factor + "," + r.level + "," + r.measurand + "," + r.treatment + "," +
           std::to_string(r.n) + "," + shortest(r.share_within_1) + "," + shortest(r.mean_en) +
           "," + shortest(r.rms_en) + "\n";
  return out;
}

json summary_json(const std::vector<SummaryRow>& rows) {
  json a = json::array();
  for (const auto& r : rows)
    a.push_back({{"factor", r.factor},
                 {"level", r.level},
                 {"measurand", r.measurand},
                 {"treatment", r.treatment},
                 {"n", r.n},
                 {"share_abs_En_le_1", r.share_within_1},
                 {"mean_En", r.mean_en},
                 {"rms_En", r.rms_en}});
  return a;
}

/// budget.csv (docs/validation.md, "Output directory"): per measurement one row per error source, then the
/// quadrature sum √Σu_i² (with its ratio to the full u) and the full run's u over the same
/// trials. u in µm for both measurands; shares u_i²/Σu_j² as fractions.
std::string budget_csv(const std::vector<MeasurementOutcome>& outcomes) {
  std::string out =
      "id,location,orientation_deg,height,mode,trials,source,evaluated,u_diameter_um,"
      "share_diameter,u_roundness_um,share_roundness,ratio_diameter,ratio_roundness\n";
  for (const auto& m : outcomes) {
    if (!m.budget) continue;
    const UncertaintyBudget& b = *m.budget;
    const std::string head = m.id + "," + m.location + "," + shortest(m.orientation_deg) + "," +
                             std::string(to_string(m.height)) + "," +
                             std::string(em::to_string(m.mode)) + "," +
                             std::to_string(b.trials) + ",";
    const auto um = [](double mm) { return cell(mm * kUmPerMm); };
    for (const SourceContribution& c : b.sources) {
      out += head + std::string(em::to_string(c.source)) + "," +
             (c.evaluated ? "true," : "false,") + um(c.diameter_u_mm) + "," +
             cell(c.diameter_share) + "," + um(c.roundness_u_mm) + "," +
             cell(c.roundness_share) + ",,\n";
    }
    out += head + "quadrature_sum,," + um(b.diameter_quadrature_mm) + ",," +
           um(b.roundness_quadrature_mm) + ",," +
           cell(internal::budget_ratio(b.diameter_quadrature_mm, b.diameter_full_u_mm)) + "," +
           cell(internal::budget_ratio(b.roundness_quadrature_mm, b.roundness_full_u_mm)) +
           "\n";
    out += head + "full_run,," + um(b.diameter_full_u_mm) + ",," + um(b.roundness_full_u_mm) +
           ",,,\n";
  }
  return out;
}

constexpr std::array<const char*, 5> kTreatments = {"uncorrected", "corrected", "paper",
                                                    "denoised", "inflated"};

double en_of(const MeasurandOutcome& o, std::size_t treatment) {
  switch (treatment) {
    case 0: return o.en;
    case 1: return o.en_corrected;
    case 2: return o.en_paper;
    case 3: return o.en_denoised;
    default: return o.en_inflated;
  }
}
double reported_of(const MeasurandOutcome& o, std::size_t treatment) {
  switch (treatment) {
    case 1: return o.corrected_mm;
    case 2: return o.corrected_paper_mm;
    case 3: return o.corrected_denoised_mm;
    default: return o.estimate_mm;  // uncorrected and inflated report y
  }
}

struct EnStats {
  std::size_t n = 0, within = 0;
  double sum = 0.0, sum_sq = 0.0;
  void add(double e) {
    if (!std::isfinite(e)) return;
    ++n;
    within += std::abs(e) <= 1.0 ? 1 : 0;
    sum += e;
    sum_sq += e * e;
  }
};

std::vector<TreatmentRow> treatment_rows(const std::vector<MeasurementOutcome>& outcomes) {
  std::vector<TreatmentRow> rows;
  for (int which = 0; which < 2; ++which) {
    for (std::size_t t = 0; t < kTreatments.size(); ++t) {
      EnStats st;
      std::size_t ne = 0;
      double se = 0.0, se2 = 0.0;
      for (const auto& m : outcomes) {
        const MeasurandOutcome& o = which == 0 ? m.diameter : m.roundness;
        st.add(en_of(o, t));
        const double err = reported_of(o, t) - o.true_mm;
        if (std::isfinite(err)) {
          ++ne;
          se += err;
          se2 += err * err;
        }
      }
      if (ne == 0) continue;
      TreatmentRow r;
      r.measurand = which == 0 ? "diameter" : "roundness";
      r.treatment = kTreatments[t];
      r.n = st.n;
      r.mean_en = st.n ? st.sum / static_cast<double>(st.n) : kNaN;
      r.rms_en = st.n ? std::sqrt(st.sum_sq / static_cast<double>(st.n)) : kNaN;
      r.share_within_1 = st.n ? static_cast<double>(st.within) / static_cast<double>(st.n) : kNaN;
      r.mean_error_mm = se / static_cast<double>(ne);
      r.rms_error_mm = std::sqrt(se2 / static_cast<double>(ne));
      rows.push_back(r);
    }
  }
  return rows;
}

std::string treatments_csv(const std::vector<TreatmentRow>& rows) {
  std::string out =
      "measurand,treatment,n,mean_En,rms_En,share_abs_En_le_1,mean_error,rms_error,unit\n";
  for (const auto& r : rows) {
    const bool d = r.measurand == "diameter";
    const double s = d ? 1.0 : kUmPerMm;
    out += r.measurand + "," + r.treatment + "," + std::to_string(r.n) + "," + cell(r.mean_en) +
           "," + cell(r.rms_en) + "," + cell(r.share_within_1) + "," +
           cell(r.mean_error_mm * s) + "," + cell(r.rms_error_mm * s) + "," + (d ? "mm" : "um") +
           "\n";
  }
  return out;
}

void ensure_dir(const fs::path& p) {
  std::error_code ec;
  fs::create_directories(p, ec);
  if (ec)
    throw em::OutputError(p.string() + ": cannot create the output directory: " + ec.message());
}

/// Rethrows the exception in flight with measurement i of the campaign named in front, of the
/// same kind (so the `vcmm` exit code stays that of the problem): every per-entry error says
/// which entry it is about. Errors that name the entry already, and output paths, pass as
/// they are.
[[noreturn]] void rethrow_for_entry(const Campaign& c, std::size_t i) {
  const std::string index = "measurements[" + std::to_string(i) + "]";
  const std::string where = c.source + ": " + index + " (\"" + c.measurements[i].id + "\"): ";
  const auto invalid = [&](const std::string& what) {
    return CampaignError(c.source, i, c.measurements[i].id, index, where + what);
  };
  try {
    throw;
  } catch (const CampaignError&) {
    throw;
  } catch (const em::OutputError&) {
    throw;
  } catch (const uncertainty::ExperimentError& e) {  // a Monte Carlo trial: keep its kind
    try {
      std::rethrow_if_nested(e);
    } catch (const geometry::UndefinedResult&) {
      throw geometry::UndefinedResult(where + e.what());
    } catch (const std::invalid_argument&) {
      throw invalid(e.what());
    } catch (...) {
    }
    throw std::runtime_error(where + e.what());
  } catch (const geometry::UndefinedResult& e) {
    throw geometry::UndefinedResult(where + e.what());
  } catch (const std::invalid_argument& e) {
    throw invalid(e.what());
  } catch (const std::exception& e) {
    throw std::runtime_error(where + e.what());
  }
}

}  // namespace

std::vector<SummaryRow> summarize_campaign(const std::vector<MeasurementOutcome>& outcomes) {
  using Level = std::function<std::string(const MeasurementOutcome&)>;
  const std::vector<std::pair<std::string, Level>> factors = {
      {"all", [](const MeasurementOutcome&) { return std::string("all"); }},
      {"location", [](const MeasurementOutcome& m) { return m.location; }},
      {"orientation_deg", [](const MeasurementOutcome& m) { return shortest(m.orientation_deg); }},
      {"height", [](const MeasurementOutcome& m) { return std::string(to_string(m.height)); }},
      {"mode", [](const MeasurementOutcome& m) { return std::string(em::to_string(m.mode)); }},
  };
  std::vector<SummaryRow> rows;
  for (const auto& [factor, level_of] : factors) {
    std::vector<std::string> levels;
    for (const auto& m : outcomes) {
      const std::string l = level_of(m);
      if (std::find(levels.begin(), levels.end(), l) == levels.end()) levels.push_back(l);
    }
    for (const std::string& level : levels) {
      for (int which = 0; which < 2; ++which) {
        for (std::size_t t = 0; t < kTreatments.size(); ++t) {
          EnStats st;
          for (const auto& m : outcomes)
            if (level_of(m) == level) st.add(en_of(which == 0 ? m.diameter : m.roundness, t));
          if (st.n == 0) continue;
          SummaryRow r;
          r.factor = factor;
          r.level = level;
          r.measurand = which == 0 ? "diameter" : "roundness";
          r.treatment = kTreatments[t];
          r.n = st.n;
          r.share_within_1 = static_cast<double>(st.within) / static_cast<double>(st.n);
          r.mean_en = st.sum / static_cast<double>(st.n);
          r.rms_en = std::sqrt(st.sum_sq / static_cast<double>(st.n));
          rows.push_back(r);
        }
      }
    }
  }
  return rows;
}

CampaignOutcome run_campaign(const Campaign& campaign, const fs::path& out_dir,
                             const CampaignRunOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  CampaignOutcome outcome;
  uncertainty::ProcessGroup* const group = options.process_group;
  const bool writer = group == nullptr || group->rank() == 0;  // the others never touch out_dir
  if (writer) {
    ensure_dir(out_dir);
    ensure_dir(out_dir / "measurements");
    ensure_dir(out_dir / "samples");
    ensure_dir(out_dir / "residuals");
  }
  unsigned threads_used = options.threads;

  const std::string model_bytes = read_bytes(campaign.model_path);
  const em::DigitalModel parsed = em::parse_digital_model(model_bytes, campaign.model_path.string());
  const em::DigitalModel model = campaign.evaluation.kinematics_corrected
                                     ? parsed
                                     : em::with_kinematics_uncorrected(parsed);
  const EvaluationSettings& ev = campaign.evaluation;
  RingEvaluationOptions evaluation;
  evaluation.reference = ev.reference_circle;
  evaluation.filter_cutoff_upr = ev.filter_cutoff_upr;
  const bool run_denoised = options.denoised_treatment && ev.filter_cutoff_upr.has_value();
  // The budget's settings reach the fingerprint through the evaluation settings
  // (campaign_json below), so a run with other budget settings recomputes.
  const std::optional<BudgetOptions> budget =
      ev.budget ? std::optional<BudgetOptions>(BudgetOptions{ev.budget_trials}) : std::nullopt;

  for (std::size_t i = 0; i < campaign.measurements.size(); ++i) try {
    const CampaignMeasurement& entry = campaign.measurements[i];
    // Fingerprint: everything this measurement's numbers depend on.
    Fingerprint fp;
    fp.add(kOutcomeFormat);
    fp.add(model_bytes);
    fp.add(read_bytes(entry.points_path));
    Campaign single = campaign;
    single.measurements = {entry};
    fp.add(campaign_json(single));
    for (const fs::path* p : {entry.reference.roundness && std::holds_alternative<ProfileRoundness>(
                                                              *entry.reference.roundness)
                                  ? &std::get<ProfileRoundness>(*entry.reference.roundness).profile_path
                                  : nullptr,
                              entry.reference.diameter &&
                                      std::holds_alternative<InterferometerDiameter>(
                                          *entry.reference.diameter)
                                  ? &std::get<InterferometerDiameter>(*entry.reference.diameter)
                                         .profile_path
                                  : nullptr}) {
      fp.add(p ? read_bytes(*p) : std::string("-"));
    }
    fp.add(run_denoised ? "denoised" : "no-denoised");
    const auto truth = options.truth.find(entry.id);
    fp.add(truth == options.truth.end()
               ? std::string("no-truth")
               : shortest(truth->second.diameter_mm) + "," + shortest(truth->second.roundness_mm));
    const std::string fingerprint = fp.hex();
    const fs::path result_file = out_dir / "measurements" / (entry.id + ".json");

    // Resumed where process 0 finds a finished file (the others need not see out_dir).
    auto previous = writer ? load_previous(result_file, fingerprint) : std::nullopt;
    if (uncertainty::decision_of_first(group, previous.has_value())) {
      if (options.on_measurement)
        options.on_measurement(i, campaign.measurements.size(), entry.id, true);
      if (previous) outcome.measurements.push_back(std::move(*previous));
      ++outcome.resumed;
      continue;
    }
    if (options.on_measurement)
      options.on_measurement(i, campaign.measurements.size(), entry.id, false);
    const auto m_start = std::chrono::steady_clock::now();

    const em::Measurement measured = read_entry_points(campaign, i);
    check_setup(campaign, i, measured);

    MeasurementOutcome m;
    m.id = entry.id;
    m.location = entry.setup.location;
    m.orientation_deg = entry.setup.orientation_deg;
    m.height = entry.setup.height;
    m.mode = entry.setup.mode;
    m.points = static_cast<std::size_t>(measured.size());
    m.seed = measurement_seed(ev.seed, entry.id);
    m.trials = ev.trials;
    m.fingerprint = fingerprint;

    RingUncertaintyOptions uo;
    uo.evaluation = evaluation;
    uo.monte_carlo.trials = ev.trials;
    uo.monte_carlo.seed = m.seed;
    uo.monte_carlo.threads = options.threads;
    uo.monte_carlo.coverage_probability = ev.coverage_probability;
    uo.monte_carlo.progress = options.progress;
    uo.monte_carlo.cancel = options.cancel;
    uo.monte_carlo.process_group = group;
    uo.roundness_bias = ev.bias_treatment;
    uo.trial = ev.trial;
    uo.budget = budget;
    const RingUncertaintyResult a = evaluate_ring_uncertainty(model, measured, uo);
    threads_used = a.monte_carlo.threads_used;
    m.trial = std::string(to_string(a.trial.kind));
    if (a.monte_carlo.status == uncertainty::RunStatus::cancelled) {
      outcome.cancelled = true;
      break;
    }
    fill_outcome(m.diameter, a.estimate.diameter_mm, a.monte_carlo.summaries[diameter],
                 a.diameter, "paper", a.diameter, 1.0, "mm");
    fill_outcome(m.roundness, a.estimate.roundness_mm, a.monte_carlo.summaries[roundness],
                 a.roundness, to_string(a.roundness_treatment), a.roundness_paper, 1000.0, "µm");
    m.budget = a.budget;

    // Treatment (b): the same virtual experiment on the denoised virtual truth.
    m.diameter.corrected_denoised_mm = m.diameter.u_denoised_mm = kNaN;
    m.roundness.corrected_denoised_mm = m.roundness.u_denoised_mm = kNaN;
    if (run_denoised) {
      const em::Measurement den = denoised_ring(a.best_estimate, *ev.filter_cutoff_upr);
      uo.monte_carlo.seed = measurement_seed(ev.seed, entry.id + "#denoised");
      uo.roundness_bias = RoundnessBiasTreatment::paper;
      uo.budget.reset();  // the budget decomposes the study's run only
      const RingUncertaintyResult b = evaluate_ring_uncertainty_on_surface(model, den, uo);
      if (b.monte_carlo.status == uncertainty::RunStatus::cancelled) {
        outcome.cancelled = true;
        break;
      }
      const auto apply = [](MeasurandOutcome& o, double y, double f_den,
                            const uncertainty::MeasurandSummary& s) {
        const auto c = uncertainty::correct_bias(y, shifted(s, y - f_den), true);
        o.corrected_denoised_mm = c.corrected;
        o.u_denoised_mm = c.standard_uncertainty;
        o.denoised_applied = c.applied;
      };
      apply(m.diameter, a.estimate.diameter_mm, b.estimate.diameter_mm,
            b.monte_carlo.summaries[diameter]);
      apply(m.roundness, a.estimate.roundness_mm, b.estimate.roundness_mm,
            b.monte_carlo.summaries[roundness]);
    }

    // References (nominal radius for the profile: the measured LS radius).
    if (auto r = evaluate_roundness_reference(campaign, i, 0.5 * a.estimate.diameter_mm)) {
      m.roundness.has_reference = true;
      m.roundness.reference_mm = r->value_mm;
      m.roundness.u_reference_mm = r->u_mm;
      m.roundness.reference_method = r->method;
    }
    if (auto d = evaluate_diameter_reference(campaign, i)) {
      m.diameter.has_reference = true;
      m.diameter.reference_mm = d->value_mm;
      m.diameter.u_reference_mm = d->u_mm;
      m.diameter.reference_method = d->method;
    }
    m.diameter.true_mm = truth == options.truth.end() ? kNaN : truth->second.diameter_mm;
    m.roundness.true_mm = truth == options.truth.end() ? kNaN : truth->second.roundness_mm;
    score(m.diameter, ev.k);
    score(m.roundness, ev.k);

    // Files of one measurement (process 0's): one transaction, the outcome (the completion
    // marker that resume looks for) renamed into place last.
    errormodel::OutputTransaction files;
    if (writer) {
      files.stage((out_dir / "samples" / (entry.id + ".csv")).string(),
                  ring_samples_csv(a.monte_carlo));
      files.stage((out_dir / "residuals" / (entry.id + ".csv")).string(),
                  residuals_csv(evaluate_ring_profile(ring_profile(a.best_estimate), evaluation)));
    }
    m.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    // Round-trip through the file's text so computed and resumed outcomes are identical.
    const std::string text = outcome_to_json(m).dump(1) + "\n";
    if (writer) {
      files.stage(result_file.string(), text);
      files.commit();
    }
    MeasurementOutcome stored = outcome_from_json(json::parse(text));
    outcome.measurements.push_back(std::move(stored));
    ++outcome.computed;
  } catch (...) {
    rethrow_for_entry(campaign, i);
  }
  outcome.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (outcome.cancelled || !writer) return outcome;

  outcome.summary = summarize_campaign(outcome.measurements);
  if (!options.truth.empty()) outcome.treatments = treatment_rows(outcome.measurements);

  json results = json::array();
  for (const auto& m : outcome.measurements) {
    json j = outcome_to_json(m);
    j.erase("wall_seconds");  // the tables are the same whether computed or resumed
    if (j.contains("budget")) j["budget"].erase("wall_seconds");
    results.push_back(std::move(j));
  }
  errormodel::OutputTransaction tables;  // the campaign's tables appear together
  tables.stage((out_dir / "results.csv").string(),
                                    results_csv(outcome.measurements));
  tables.stage(
      (out_dir / "results.json").string(),
      json({{"schema", "vcmm.campaign_results"}, {"schema_version", 1}, {"measurements", results}})
              .dump(1) +
          "\n");
  tables.stage((out_dir / "summary.csv").string(),
                                    summary_csv(outcome.summary));
  tables.stage(
      (out_dir / "summary.json").string(),
      json({{"schema", "vcmm.campaign_summary"}, {"schema_version", 1},
            {"summary", summary_json(outcome.summary)}})
              .dump(1) +
          "\n");
  if (!outcome.treatments.empty())
    tables.stage((out_dir / "treatments.csv").string(),
                                      treatments_csv(outcome.treatments));
  if (budget) tables.stage((out_dir / "budget.csv").string(), budget_csv(outcome.measurements));
  json info = {{"campaign", campaign.source},
               {"description", campaign.description},
               {"measurements", outcome.measurements.size()},
               {"computed", outcome.computed},
               {"resumed", outcome.resumed},
               {"trials_per_measurement", ev.trials},
               {"seed", ev.seed},
               {"k", ev.k},
               {"coverage_probability", ev.coverage_probability},
               {"residual_angles", "about the reference-circle centre, workpiece (ring) frame"},
               {"en_sign", "E_n = (reference - measured) / (k sqrt(u_ref^2 + u^2))"},
               {"reference_circle", std::string(to_string(ev.reference_circle))},
               {"filter_cutoff_upr", ev.filter_cutoff_upr ? json(*ev.filter_cutoff_upr) : json()},
               {"denoised_treatment", run_denoised},
               {"bias_treatment", std::string(to_string(ev.bias_treatment))},
               {"kinematic_errors", ev.kinematics_corrected ? "corrected" : "uncertainty_only"},
               {"budget", ev.budget},
               {"budget_trials", budget ? json(budget_trials(*budget, ev.trials)) : json()},
               {"trial", std::string(to_string(ev.trial))},
               {"wall_seconds_this_run", outcome.wall_seconds},
               // How this run was spread (the numbers do not depend on it; docs/mpi.md).
               {"monte_carlo", {{"ranks", group != nullptr ? group->size() : 1u},
                                {"threads", threads_used}}}};
  info["vcmm_version"] = std::string(vcmm_version());
  info["git_revision"] = std::string(vcmm_revision());
  if (!campaign.model_path.empty())  // empty for campaigns built in code, not read from a file
    info["model_sha256"] = file_sha256(campaign.model_path.string());
  for (const auto& [k, v] : options.provenance) info[k] = v;
  tables.stage((out_dir / "run_info.json").string(), info.dump(1) + "\n");
  tables.commit();
  // An optional table this run does not write, left by an earlier run in the same directory
  // (a demo's treatments.csv under a later `validate`, a budget run's budget.csv), would
  // describe other results beside these.
  const auto remove_stale = [&out_dir](const char* name, const char* what) {
    std::error_code ec;
    fs::remove(out_dir / name, ec);
    if (ec)
      throw em::OutputError((out_dir / name).string() + ": cannot remove the " + what +
                            " of an earlier run: " + ec.message());
  };
  if (!budget) remove_stale("budget.csv", "budget table");
  if (outcome.treatments.empty()) remove_stale("treatments.csv", "treatments table (with truth)");
  return outcome;
}

}  // namespace vcmm::validation
