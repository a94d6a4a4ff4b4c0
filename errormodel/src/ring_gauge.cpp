// Nominal ring-gauge measurements (formulas in vcmm/errormodel/ring_gauge.h).
#include "vcmm/errormodel/ring_gauge.h"

#include <cmath>
#include <numbers>
#include <string>

#include "vcmm/errormodel/errors.h"

namespace vcmm::errormodel {

std::vector<FormHarmonic> seed_study_ring_form() {
  return {{2, 45e-6, 0.4}, {3, 30e-6, 1.9}, {4, 12e-6, 2.7}, {5, 10e-6, 0.1},
          {7, 6e-6, 4.0},  {11, 4e-6, 5.2}, {17, 3e-6, 1.3}};
}

Measurement ring_gauge_measurement(const RingGauge& ring, const RingSampling& s) {
  const std::string c = "ring_gauge_measurement: ";
  if (!std::isfinite(ring.diameter_mm) || ring.diameter_mm <= 0.0)
    throw InvalidInput(c + "diameter_mm must be finite and > 0; got " +
                       std::to_string(ring.diameter_mm));
  if (s.points < 3)
    throw InvalidInput(c + "at least 3 points are needed; got " + std::to_string(s.points));
  double slope_bound = 0.0;
  for (std::size_t j = 0; j < ring.form.size(); ++j) {
    const FormHarmonic& h = ring.form[j];
    if (h.order < 1)
      throw InvalidInput(c + "form harmonic " + std::to_string(j) + ": order must be >= 1; got " +
                         std::to_string(h.order));
    if (!std::isfinite(h.amplitude_mm) || !std::isfinite(h.phase_rad))
      throw InvalidInput(c + "form harmonic " + std::to_string(j) +
                         ": amplitude and phase must be finite");
    slope_bound += h.order * std::abs(h.amplitude_mm);
  }
  if (slope_bound >= 0.25 * ring.diameter_mm)
    throw InvalidInput(c + "form deviation too large: sum of k*|a_k| = " +
                       std::to_string(slope_bound) + " mm must stay below D/4 = " +
                       std::to_string(0.25 * ring.diameter_mm) + " mm");
  if (!std::isfinite(s.height_mm) || !std::isfinite(s.start_angle_rad))
    throw InvalidInput(c + "height_mm and start_angle_rad must be finite");

  Measurement m;
  m.mode = s.mode;
  m.placement = s.placement;
  m.temperature_c = s.temperature_c;
  m.stylus_offset_mm = s.stylus_offset_mm;
  m.points_mm.resize(3, s.points);
  m.normals.resize(3, s.points);
  const double r0 = 0.5 * ring.diameter_mm;
  for (Eigen::Index i = 0; i < s.points; ++i) {
    const double theta = s.start_angle_rad + 2.0 * std::numbers::pi * static_cast<double>(i) /
                                                 static_cast<double>(s.points);
    double r = r0, dr = 0.0;
    for (const FormHarmonic& h : ring.form) {
      const double a = h.order * theta + h.phase_rad;
      r += h.amplitude_mm * std::cos(a);
      dr -= h.order * h.amplitude_mm * std::sin(a);
    }
    const double ct = std::cos(theta), st = std::sin(theta);
    m.points_mm.col(i) = Eigen::Vector3d(r * ct, r * st, s.height_mm);
    // n ∝ −r u + r′ u⊥ (towards the axis), u = (cos, sin), u⊥ = (−sin, cos).
    const double inv = 1.0 / std::hypot(r, dr);
    m.normals.col(i) = Eigen::Vector3d((-r * ct - dr * st) * inv, (-r * st + dr * ct) * inv, 0.0);
  }
  validate_measurement(m, "ring_gauge_measurement");
  return m;
}

}  // namespace vcmm::errormodel
