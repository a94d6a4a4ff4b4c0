// cli/json_output.cpp — see json_output.h.
#include "json_output.h"

#include <cmath>
#include <numbers>

#include "run_control.h"
#include "vcmm/geometry/certificate.h"

namespace vcmm::cli {
namespace {

using json = nlohmann::ordered_json;
namespace g = vcmm::geometry;

void put_ron(json& j, const g::RoundnessParameters& r) {
  j["RONt"] = r.ront;
  j["RONp"] = r.ronp;
  j["RONv"] = r.ronv;
  j["RONq"] = r.ronq;
}

const char* optimality_name(g::Optimality o) {
  return o == g::Optimality::global ? "global" : "local";
}

template <class Circle>
void put_certificate(json& j, std::span<const g::Point2> profile, const Circle& c) {
  const g::Verification v = g::verify(profile, c);
  j["certified"] = v.valid;
  j["optimality"] = optimality_name(c.certificate.optimality);
  j["certificate"] = c.certificate.argument;
  if (!v.valid) j["verification_failure"] = v.reason;
}

/// MI and MC: one radius, a flat contact list and a certificate.
template <class Circle>
json single_radius_json(std::span<const g::Point2> profile, const Circle& c) {
  json j;
  j["defined"] = true;
  j["center"] = {c.center.x, c.center.y};
  j["radius"] = c.radius;
  put_ron(j, c.ron);
  j["contacts"] = c.contacts;
  put_certificate(j, profile, c);
  return j;
}

}  // namespace

nlohmann::ordered_json to_json(std::span<const g::Point2> profile, const g::RoundnessEvaluation& e) {
  constexpr double kDeg = 180.0 / std::numbers::pi;
  json out;
  out["n_points"] = e.n_points;
  out["filter"] = e.filter_cutoff_upr ? json(*e.filter_cutoff_upr) : json(nullptr);
  if (e.filter_path)
    out["filter_path"] = *e.filter_path == g::FilterPath::fft          ? "fft"
                         : *e.filter_path == g::FilterPath::nonuniform ? "nonuniform"
                                                                       : "open_profile";
  out["coverage"] = {{"covered_deg", e.coverage.covered_rad * kDeg},
                     {"largest_gap_deg", e.coverage.largest_gap_rad * kDeg},
                     {"gap_start_deg", e.coverage.gap_start_rad * kDeg},
                     {"gap_between_points", {e.coverage.gap_start_index,
                                             e.coverage.gap_end_index}},
                     {"closed", e.coverage.closed}};
  if (e.least_squares) {
    const auto& c = *e.least_squares;
    json j;
    j["defined"] = true;
    j["center"] = {c.center.x, c.center.y};
    j["radius"] = c.radius;
    put_ron(j, c.ron);
    j["contacts"] = c.contacts;
    j["certified"] = false;
    j["optimality"] = "numerical";
    j["certificate"] = "none: least squares is a numerical fit (Gauss-Newton converged in " +
                       std::to_string(c.iterations) +
                       (c.iterations == 1 ? " iteration)" : " iterations)");
    out["LS"] = j;
  }
  if (e.minimum_zone) {
    const auto& c = *e.minimum_zone;
    json j;
    j["defined"] = true;
    j["center"] = {c.center.x, c.center.y};
    j["inner_radius"] = c.inner_radius;
    j["outer_radius"] = c.outer_radius;
    put_ron(j, c.ron);
    j["contacts"] = {{"outer", c.outer_contacts}, {"inner", c.inner_contacts}};
    put_certificate(j, profile, c);
    out["MZ"] = j;
  }
  if (e.maximum_inscribed) out["MI"] = single_radius_json(profile, *e.maximum_inscribed);
  if (e.minimum_circumscribed)
    out["MC"] = single_radius_json(profile, *e.minimum_circumscribed);
  for (const auto& [circle, reason] : e.undefined)
    out[std::string(g::to_string(circle))] = {{"defined", false}, {"reason", user_message(reason)}};
  for (const auto& [circle, caution] : e.cautions)
    out[std::string(g::to_string(circle))]["caution"] = caution;
  return out;
}

nlohmann::ordered_json harmonics_json(const g::ProfileHarmonics& h) {
  constexpr double kDeg = 180.0 / std::numbers::pi;
  json orders = json::array();
  for (std::size_t k = 1; k <= h.max_order(); ++k) {
    const double a = h.cos_mm(k), b = h.sin_mm(k);
    orders.push_back({{"order", k},
                      {"amplitude", std::hypot(a, b)},
                      {"phase_deg", std::atan2(b, a) * kDeg}});
  }
  return {{"about", "LS circle of the evaluated profile"},
          {"path", h.path() == g::HarmonicsPath::fft ? "fft" : "quadrature"},
          {"orders", orders}};
}

}  // namespace vcmm::cli
