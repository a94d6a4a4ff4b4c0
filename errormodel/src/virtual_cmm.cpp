// The virtual CMM: stages 1-5 (simulate), their systematic inverse (correct) and the draw.
// Notation and formulas: vcmm/errormodel/virtual_cmm.h and docs/errormodel.md.
#include "vcmm/errormodel/virtual_cmm.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>

#include "vcmm/errormodel/errors.h"

namespace vcmm::errormodel {
namespace {

// Cheap checks for the Monte Carlo loop (three calls per trial); the exact, message-building
// checks of validate_measurement() run only when a cheap check fails. A sum of finite values
// is finite unless it overflows, and a NaN or ±inf anywhere makes it non-finite, so a finite
// sum proves every coordinate finite (an overflow merely falls back to the full check). The
// normal test is the same tolerance as validate_measurement, on |n|² (≈ 2(|n| − 1)).
void check_measurement(const Measurement& m, const char* caller) {
  bool ok = m.points_mm.cols() > 0 && m.normals.cols() == m.points_mm.cols() &&
            std::isfinite(m.points_mm.sum()) && m.placement.location_mm.allFinite() &&
            m.stylus_offset_mm.allFinite() && std::isfinite(m.placement.orientation_rad) &&
            std::isfinite(m.temperature_c);
  if (ok) {
    const double* n = m.normals.data();
    bool bad = false;  // accumulated without branches; NaN fails the comparison
    for (Eigen::Index i = 0; i < m.normals.cols(); ++i, n += 3)
      bad |= !(std::abs(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1.0) <= 1.9e-9);
    ok = !bad;
  }
  if (!ok) validate_measurement(m, caller);  // throws with the offending index and value
}

double noise_sigma_mm(const DigitalModel& model, ProbingMode mode) {
  return mode == ProbingMode::scanning ? model.noise.scanning_sigma_mm
                                       : model.noise.touch_trigger_sigma_mm;
}

ProbeErrors nominal_probe(const ProbeModel& p) {
  ProbeErrors out;
  out.tip_radius_error_mm = p.tip_radius_error_mm.value;
  for (const ProbeHarmonic& h : p.directional) {
    out.cos_mm[static_cast<std::size_t>(h.order)] = h.cos_mm.value;
    out.sin_mm[static_cast<std::size_t>(h.order)] = h.sin_mm.value;
    out.max_order = std::max(out.max_order, h.order);
  }
  return out;
}

/// δr + D(d) for a probing direction with XY components (dx, dy) (virtual_cmm.h):
/// Re/Im of (dx + i·dy)^k by complex multiplication.
inline double probe_shift(const ProbeErrors& probe, double dx, double dy) {
  double e = probe.tip_radius_error_mm;
  double re = 1.0, im = 0.0;
  for (int k = 1; k <= probe.max_order; ++k) {
    const double next_re = re * dx - im * dy;
    im = re * dy + im * dx;
    re = next_re;
    e += probe.cos_mm[static_cast<std::size_t>(k)] * re +
         probe.sin_mm[static_cast<std::size_t>(k)] * im;
  }
  return e;
}

/// Per-thread work arrays for the kinematic stage (machine positions and tip errors): the
/// Monte Carlo loop calls simulate/correct millions of times on same-sized rings, and fresh
/// 3×N allocations there cost page faults (measured: ~7 % of simulate at N = 3600).
struct Scratch {
  Eigen::Matrix3Xd w, e;
  Eigen::ArrayXd shift;
};
Scratch& thread_scratch(Eigen::Index n) {
  thread_local Scratch scratch;
  if (scratch.w.cols() != n) {
    scratch.w.resize(3, n);
    scratch.e.resize(3, n);
    scratch.shift.resize(n);
  }
  return scratch;
}

/// out[i] = sign·(δr + D(d_i)) for every point, d = −R n (virtual_cmm.h). The order loop is
/// unrolled at compile time (K = max_order) so that the out-of-order core overlaps the
/// latency-bound complex recurrence of neighbouring points (a runtime loop cost ~15 ns a point).
template <int K>
void probe_shifts_k(const ProbeErrors& probe, const Measurement& m, double sign, double* out) {
  const Eigen::Matrix3d r = m.placement.rotation();
  const double c = r(0, 0), s = r(1, 0);
  std::array<double, K + 1> ck{}, sk{};
  for (int k = 1; k <= K; ++k) {
    ck[static_cast<std::size_t>(k)] = sign * probe.cos_mm[static_cast<std::size_t>(k)];
    sk[static_cast<std::size_t>(k)] = sign * probe.sin_mm[static_cast<std::size_t>(k)];
  }
  const double base = sign * probe.tip_radius_error_mm;
  const double* n = m.normals.data();
  for (Eigen::Index i = 0; i < m.normals.cols(); ++i, n += 3) {
    const double dx = -(c * n[0] - s * n[1]), dy = -(s * n[0] + c * n[1]);
    double e = base, re = 1.0, im = 0.0;
    for (int k = 1; k <= K; ++k) {
      const double next_re = re * dx - im * dy;
      im = re * dy + im * dx;
      re = next_re;
      e += ck[static_cast<std::size_t>(k)] * re + sk[static_cast<std::size_t>(k)] * im;
    }
    out[i] = e;
  }
}

template <int... K>
void probe_shifts_dispatch(std::integer_sequence<int, K...>, const ProbeErrors& probe,
                           const Measurement& m, double sign, double* out) {
  ((probe.max_order == K ? probe_shifts_k<K>(probe, m, sign, out) : void()), ...);
}

void probe_shifts(const ProbeErrors& probe, const Measurement& m, double sign,
                  Eigen::ArrayXd& out) {
  probe_shifts_dispatch(std::make_integer_sequence<int, max_probe_harmonic_order + 1>{}, probe,
                        m, sign, out.data());
}

void copy_metadata(const Measurement& from, Measurement& to) {
  to.normals = from.normals;
  to.placement = from.placement;
  to.mode = from.mode;
  to.temperature_c = from.temperature_c;
  to.stylus_offset_mm = from.stylus_offset_mm;
}

double expansion_factor(double alpha_per_k, double temperature_c) {
  return 1.0 + alpha_per_k * (temperature_c - reference_temperature_c);
}

void check_probe(const ProbeErrors& probe, const char* caller) {
  if (probe.max_order < 0 || probe.max_order > max_probe_harmonic_order)
    throw InvalidInput(std::string(caller) + ": ProbeErrors::max_order must be 0 to " +
                       std::to_string(max_probe_harmonic_order) + "; got " +
                       std::to_string(probe.max_order));
}

void check_draw_size(Eigen::Index got, Eigen::Index want, const char* what) {
  if (got != want)
    throw InvalidInput(std::string("simulate: the draw's ") + what + " has " +
                       std::to_string(got) + " columns but the measurement has " +
                       std::to_string(want) + " points (draw it for this measurement with the "
                       "stage switched on)");
}

}  // namespace

std::string_view to_string(ErrorSource source) {
  switch (source) {
    case ErrorSource::roughness: return "roughness";
    case ErrorSource::temperature: return "temperature";
    case ErrorSource::kinematic: return "kinematic";
    case ErrorSource::probe: return "probe";
    case ErrorSource::noise: return "noise";
  }
  return "?";
}

std::optional<ErrorSource> error_source_from_string(std::string_view text) {
  for (ErrorSource s : all_error_sources)
    if (to_string(s) == text) return s;
  return std::nullopt;
}

double probe_error_mm(const ProbeErrors& probe, const Eigen::Vector3d& d) {
  check_probe(probe, "probe_error_mm");
  return probe_shift(probe, d.x(), d.y());
}

ErrorDraw nominal_errors(const DigitalModel& model, const Measurement& m) {
  check_measurement(m, "nominal_errors");
  ErrorDraw d;
  d.temperature_c = m.temperature_c;
  d.expansion_coefficient_per_k = model.temperature.expansion_coefficient_per_k.value;
  d.kinematic = model.kinematics.nominal();
  d.probe = nominal_probe(model.probe);
  d.roughness_mm = Eigen::VectorXd::Zero(m.size());
  d.noise_mm = Eigen::Matrix3Xd::Zero(3, m.size());
  return d;
}

void draw_errors(const DigitalModel& model, const Measurement& m, RandomSource& rng,
                 const Stages& stages, ErrorDraw& out) {
  check_measurement(m, "draw_errors");
  const bool temperature = stages.is_enabled(ErrorSource::temperature);
  const bool probe = stages.is_enabled(ErrorSource::probe);
  const ProbeModel& pm = model.probe;

  // Scalars of stages 2 and 4 in one bulk call: T, α, δr, then (c_k, s_k) per harmonic.
  std::array<double, 3 + 2 * max_probe_harmonic_order> z{};
  const std::size_t n_scalars =
      (temperature ? 2 : 0) + (probe ? 1 + 2 * pm.directional.size() : 0);
  rng.fill_standard_normal(std::span<double>(z.data(), n_scalars));
  std::size_t next = 0;

  const auto& alpha = model.temperature.expansion_coefficient_per_k;
  out.temperature_c = m.temperature_c;
  out.expansion_coefficient_per_k = alpha.value;
  if (temperature) {
    out.temperature_c += model.temperature.thermometer_u_k * z[next++];
    out.expansion_coefficient_per_k += alpha.u * z[next++];
  }
  out.probe = nominal_probe(pm);
  if (probe) {
    out.probe.tip_radius_error_mm += pm.tip_radius_error_mm.u * z[next++];
    for (const ProbeHarmonic& h : pm.directional) {
      out.probe.cos_mm[static_cast<std::size_t>(h.order)] += h.cos_mm.u * z[next++];
      out.probe.sin_mm[static_cast<std::size_t>(h.order)] += h.sin_mm.u * z[next++];
    }
  }
  if (stages.is_enabled(ErrorSource::kinematic))
    model.kinematics.draw(rng, out.kinematic);
  else
    out.kinematic = model.kinematics.nominal();

  const Eigen::Index n = m.size();
  if (stages.is_enabled(ErrorSource::roughness)) {
    out.roughness_mm.resize(n);
    rng.fill_standard_normal(
        std::span<double>(out.roughness_mm.data(), static_cast<std::size_t>(n)));
    out.roughness_mm *= model.roughness.sigma_mm;
  } else {
    out.roughness_mm.resize(0);
  }
  if (stages.is_enabled(ErrorSource::noise)) {
    out.noise_mm.resize(3, n);
    rng.fill_standard_normal(
        std::span<double>(out.noise_mm.data(), static_cast<std::size_t>(3 * n)));
    out.noise_mm *= noise_sigma_mm(model, m.mode);
  } else {
    out.noise_mm.resize(3, 0);
  }
}

ErrorDraw draw_errors(const DigitalModel& model, const Measurement& m, RandomSource& rng,
                      const Stages& stages) {
  ErrorDraw d;
  draw_errors(model, m, rng, stages, d);
  return d;
}

void simulate(const Measurement& m, const DigitalModel& model, const ErrorDraw& draw,
              const Stages& stages, Formula formula, Measurement& out) {
  check_measurement(m, "simulate");
  if (&out == &m) throw InvalidInput("simulate: the output may not be the input measurement");
  const Eigen::Index n = m.size();
  const bool roughness = stages.is_enabled(ErrorSource::roughness);
  const bool temperature = stages.is_enabled(ErrorSource::temperature);
  const bool kinematic = stages.is_enabled(ErrorSource::kinematic);
  const bool probe = stages.is_enabled(ErrorSource::probe);
  const bool noise = stages.is_enabled(ErrorSource::noise);
  if (roughness) check_draw_size(draw.roughness_mm.size(), n, "roughness");
  if (noise) check_draw_size(draw.noise_mm.cols(), n, "noise");
  if (probe) check_probe(draw.probe, "simulate");
  copy_metadata(m, out);
  out.points_mm.resize(3, n);

  const Eigen::Matrix3d r = m.placement.rotation();
  const Eigen::Vector3d& location = m.placement.location_mm;
  const double scale =
      temperature ? expansion_factor(draw.expansion_coefficient_per_k, draw.temperature_c) : 1.0;
  Scratch& scratch = thread_scratch(n);

  // Stages 1 and 2, and the machine position w of each point for stage 3.
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::Vector3d q = m.points_mm.col(i);
    if (roughness) q += draw.roughness_mm[i] * m.normals.col(i);
    q *= scale;
    out.points_mm.col(i) = q;
    if (kinematic) scratch.w.col(i) = r * q + location;
  }
  if (kinematic) {
    // Reported position m solves m = w + e(m) (e evaluated at the reported, i.e. measured,
    // position, as tip_errors defines it). Fixed point from m = w: two evaluations leave
    // |∇e|²·|e| ≈ 1e-15 mm (the iteration of measured_tip_positions, kept here on the error
    // vector itself so that no 500 mm coordinates are subtracted).
    tip_errors(model.kinematics, draw.kinematic, scratch.w, m.stylus_offset_mm, formula,
               scratch.e);
    scratch.w += scratch.e;
    tip_errors(model.kinematics, draw.kinematic, scratch.w, m.stylus_offset_mm, formula,
               scratch.e);
  }
  // Stages 3 (in workpiece axes), 4 and 5.
  if (probe) probe_shifts(draw.probe, m, 1.0, scratch.shift);
  const Eigen::Matrix3d rt = r.transpose();
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::Vector3d q = out.points_mm.col(i);
    if (kinematic) q += rt * scratch.e.col(i);
    if (probe) q += scratch.shift[i] * m.normals.col(i);
    if (noise) q += draw.noise_mm.col(i);
    out.points_mm.col(i) = q;
  }
}

Measurement simulate(const Measurement& m, const DigitalModel& model, const ErrorDraw& draw,
                     const Stages& stages, Formula formula) {
  Measurement out;
  simulate(m, model, draw, stages, formula, out);
  return out;
}

void correct(const Measurement& measured, const DigitalModel& model, const Stages& stages,
             Formula formula, Measurement& out) {
  check_measurement(measured, "correct");
  if (&out == &measured)
    throw InvalidInput("correct: the output may not be the input measurement");
  const Eigen::Index n = measured.size();
  const bool temperature = stages.is_enabled(ErrorSource::temperature);
  const bool kinematic = stages.is_enabled(ErrorSource::kinematic);
  const bool probe = stages.is_enabled(ErrorSource::probe);
  copy_metadata(measured, out);
  out.points_mm.resize(3, n);

  const Eigen::Matrix3d r = measured.placement.rotation();
  Scratch& scratch = thread_scratch(n);
  if (probe) probe_shifts(nominal_probe(model.probe), measured, -1.0, scratch.shift);
  // Undo 4, and the measured machine positions for undoing 3.
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::Vector3d q = measured.points_mm.col(i);
    if (probe) q += scratch.shift[i] * measured.normals.col(i);
    out.points_mm.col(i) = q;
    if (kinematic) scratch.w.col(i) = r * q + measured.placement.location_mm;
  }
  // Undo 3 (true = measured − e(measured), exact for the model) and 2.
  if (kinematic)
    tip_errors(model.kinematics, model.kinematics.nominal(), scratch.w, measured.stylus_offset_mm,
               formula, scratch.e);
  const double inverse_scale =
      temperature ? 1.0 / expansion_factor(model.temperature.expansion_coefficient_per_k.value,
                                           measured.temperature_c)
                  : 1.0;
  const Eigen::Matrix3d rt = r.transpose();
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::Vector3d q = out.points_mm.col(i);
    if (kinematic) q -= rt * scratch.e.col(i);
    out.points_mm.col(i) = q * inverse_scale;
  }
}

Measurement correct(const Measurement& measured, const DigitalModel& model, const Stages& stages,
                    Formula formula) {
  Measurement out;
  correct(measured, model, stages, formula, out);
  return out;
}

}  // namespace vcmm::errormodel
