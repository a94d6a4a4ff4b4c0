// The virtual CMM: stages 1-5 (simulate), their systematic inverse (correct) and the draw.
// Notation and formulas: vcmm/errormodel/virtual_cmm.h and docs/errormodel.md.
#include "vcmm/errormodel/virtual_cmm.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <new>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "internal/first_order_kernel.h"
#include "internal/fused_trial_kernel.h"
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
    // A 0/1 flag per normal (a branch-free, vectorised map: NaN fails the comparison), then
    // their sum — GCC vectorises neither a reduction nor an early exit over stride-3 data.
    thread_local Eigen::ArrayXd flags;
    const Eigen::Index n = m.normals.cols();
    flags.resize(n);
    const double* __restrict v = m.normals.data();
    double* __restrict f = flags.data();
    for (Eigen::Index i = 0; i < n; ++i) {
      const double x = v[3 * i], y = v[3 * i + 1], z = v[3 * i + 2];
      f[i] = std::abs(x * x + y * y + z * z - 1.0) <= 1.9e-9 ? 0.0 : 1.0;
    }
    ok = flags.sum() == 0.0;
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

/// Per-thread work arrays for the kinematic stage (machine positions w and tip errors e): the
/// Monte Carlo loop calls simulate/correct millions of times on same-sized rings, and fresh
/// 3×N allocations there cost page faults (measured: ~7 % of simulate at N = 3600).
/// w and e live in one buffer, each on a 64-byte boundary and e exactly half a page (2 KiB,
/// mod 4 KiB) after w: the kinematic kernel reads w[i] while the stores of e[i − k] are in
/// flight, and when the two addresses agree in their low 12 bits the load waits for the store
/// ("4K aliasing"). With two separate heap blocks the distance depended on the heap's state,
/// and the same simulate() ran 79 or 88 µs at N = 3600 from one build to the next.
struct Scratch {
  Eigen::VectorXd storage;
  Eigen::Map<Eigen::Matrix3Xd> w{nullptr, 3, 0}, e{nullptr, 3, 0};
  Eigen::ArrayXd shift;
};

Scratch& thread_scratch(Eigen::Index n) {
  thread_local Scratch scratch;
  if (scratch.w.cols() != n) {
    const Eigen::Index len = 3 * n;                  // doubles per array
    scratch.storage.resize(2 * len + 1024);  // + room for the offsets below (≤ 6 + 7 + 504)
    double* base = scratch.storage.data();
    while (reinterpret_cast<std::uintptr_t>(base) % 64 != 0) ++base;  // 16-byte aligned: ≤ 6
    double* e = base + (len + 7) / 8 * 8;  // the next 64-byte boundary after w
    while ((reinterpret_cast<std::uintptr_t>(e) - reinterpret_cast<std::uintptr_t>(base)) %
               4096 != 2048)
      e += 8;  // 64 bytes at a time: at most 63 steps (504 doubles)
    new (&scratch.w) Eigen::Map<Eigen::Matrix3Xd>(base, 3, n);
    new (&scratch.e) Eigen::Map<Eigen::Matrix3Xd>(e, 3, n);
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

void check_draw_size(Eigen::Index got, Eigen::Index want, const char* what,
                     const char* caller = "simulate") {
  if (got != want)
    throw InvalidInput(std::string(caller) + ": the draw's " + what + " has " +
                       std::to_string(got) + " columns but the measurement has " +
                       std::to_string(want) + " points (draw it for this measurement with the "
                       "stage switched on)");
}

/// The draw's noise has `rows` rows (3: x, y, z; 2: x, y only) and N columns, or the stage is
/// off. Every form needs N columns; all but the first-order x, y form need 3 rows.
void check_noise(const ErrorDraw& draw, Eigen::Index n, bool xy_only, const char* caller) {
  check_draw_size(draw.noise_mm.cols(), n, "noise", caller);
  const Eigen::Index rows = draw.noise_mm.rows();
  if (rows == 3 || (rows == 2 && xy_only)) return;
  if (rows == 2)
    throw InvalidInput(std::string(caller) +
                       ": the draw's noise holds x, y only (drawn for the x, y form); this "
                       "form needs x, y and z (draw it with all three components)");
  throw InvalidInput(std::string(caller) + ": the draw's noise has " + std::to_string(rows) +
                     " rows; it needs 3 (x, y, z) or, for the x, y form, 2");
}

/// The probe errors `a` − `b`, coefficient by coefficient: δr + D is linear in them.
ProbeErrors probe_difference(const ProbeErrors& a, const ProbeErrors& b) {
  ProbeErrors d;
  d.tip_radius_error_mm = a.tip_radius_error_mm - b.tip_radius_error_mm;
  for (std::size_t k = 0; k < d.cos_mm.size(); ++k) {
    d.cos_mm[k] = a.cos_mm[k] - b.cos_mm[k];
    d.sin_mm[k] = a.sin_mm[k] - b.sin_mm[k];
  }
  d.max_order = std::max(a.max_order, b.max_order);
  return d;
}

/// The kinematic parameters drawn − estimated (model.mean()), in a per-thread KinematicErrors
/// (no allocation once sized; every parameter is overwritten, so a previous model's layout
/// does not matter). Throws std::invalid_argument as tip_errors() when `drawn` does not
/// belong to the model.
const KinematicErrors& kinematic_difference(const KinematicModel& model,
                                            const KinematicErrors& drawn, const char* caller) {
  if (drawn.parameters().size() != model.parameter_count())
    throw std::invalid_argument(std::string(caller) + ": the draw's kinematic errors have " +
                                std::to_string(drawn.parameters().size()) +
                                " parameters but the model has " +
                                std::to_string(model.parameter_count()) +
                                " (a KinematicErrors from another model?)");
  thread_local KinematicErrors delta;
  if (delta.parameters().size() != model.parameter_count()) delta = model.nominal();
  const Eigen::VectorXd& a = drawn.parameters();
  const Eigen::VectorXd& b = model.mean();
  std::array<double, max_legendre_degree + 1> c{};
  for (int f = 0; f < axis_error_count; ++f) {
    const auto e = static_cast<AxisError>(f);
    const Eigen::Index offset = model.parameter_offset(e);
    const int count = model.coefficient_count(e);
    for (int j = 0; j < count; ++j)
      c[static_cast<std::size_t>(j)] = a[offset + j] - b[offset + j];
    delta.set_coefficients(model, e,
                           std::span<const double>(c.data(), static_cast<std::size_t>(count)));
  }
  for (int k = 0; k < squareness_count; ++k) {
    const auto sq = static_cast<Squareness>(k);
    const Eigen::Index offset = model.parameter_offset(sq);
    delta.set_squareness(model, sq, a[offset] - b[offset]);
  }
  return delta;
}

/// Per-thread zero arrays standing in for the terms of disabled stages in the fused trial, so
/// that its per-point loop is the same branch-free (vectorised) code for any set of stages;
/// adding zeros leaves every value unchanged.
struct Zeros {
  Eigen::Matrix3Xd xyz;
  Eigen::ArrayXd scalar;
};
const Zeros& thread_zeros(Eigen::Index n) {
  thread_local Zeros zeros;
  if (zeros.scalar.size() != n) {
    zeros.xyz = Eigen::Matrix3Xd::Zero(3, n);
    zeros.scalar = Eigen::ArrayXd::Zero(n);
  }
  return zeros;
}

/// The x, y noise of the x, y form, point i's (x, y) at [2i, 2i + 1]: the draw's own storage
/// when it holds x, y only, else its x and y rows copied into a per-thread array; zeros when
/// the stage is off.
const double* xy_noise(const ErrorDraw& draw, bool noise, Eigen::Index n) {
  if (!noise) return thread_zeros(n).xyz.data();
  if (draw.noise_mm.rows() == 2) return draw.noise_mm.data();
  thread_local Eigen::Matrix2Xd xy;
  xy = draw.noise_mm.topRows<2>();
  return xy.data();
}

/// The corrected coordinates of the fused trial (virtual_cmm.h) for points [0, n): the
/// machine-axis terms e (kinematic, machine axes), shift (probe, along the normal) and z
/// (noise), every one an array of zeros when its stage is off. kXyz: write x, y, z with
/// stride 3 (a Measurement) from x, y, z noise, else x, y with stride 2 (Point2) from x, y
/// noise (xy_noise). No branch in the loop.
template <bool kXyz>
void fused_points(Eigen::Index n, const double* __restrict p, const double* __restrict nv,
                  const double* __restrict rough, const double* __restrict e,
                  const double* __restrict shift, const double* __restrict z, double scale,
                  double inverse_scale, const Eigen::Matrix3d& r, double* __restrict out) {
  // Rᵀ of a rotation about z: (x, y) → (r00 x + r10 y, r01 x + r11 y), z unchanged.
  const double t00 = r(0, 0), t01 = r(1, 0), t10 = r(0, 1), t11 = r(1, 1), t22 = r(2, 2);
  constexpr int kStride = kXyz ? 3 : 2;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = rough[i], sh = shift[i];
    const double nx = nv[3 * i], ny = nv[3 * i + 1], nz = nv[3 * i + 2];
    const double ex = e[3 * i], ey = e[3 * i + 1];
    const double qx = (p[3 * i] + t * nx) * scale;
    const double qy = (p[3 * i + 1] + t * ny) * scale;
    const double cx = t00 * ex + t01 * ey + sh * nx + z[kStride * i];
    const double cy = t10 * ex + t11 * ey + sh * ny + z[kStride * i + 1];
    out[kStride * i] = (qx + cx) * inverse_scale;
    out[kStride * i + 1] = (qy + cy) * inverse_scale;
    if constexpr (kXyz) {
      const double qz = (p[3 * i + 2] + t * nz) * scale;
      const double cz = t22 * e[3 * i + 2] + sh * nz + z[3 * i + 2];
      out[kStride * i + 2] = (qz + cz) * inverse_scale;
    }
  }
}

/// The fused trial of virtual_cmm.h (first-order kinematics), writing x, y, z (kXyz) or x, y of
/// every point to `out` (stride 3 or 2). Two passes over the points — the machine positions
/// for the one kinematic evaluation, then every stage's difference — and the kinematic
/// kernel's own pass.
template <bool kXyz>
void fused_trial(const Measurement& m, const DigitalModel& model, const ErrorDraw& draw,
                 const Stages& stages, const char* caller, double* out) {
  check_measurement(m, caller);
  const Eigen::Index n = m.size();
  const bool roughness = stages.is_enabled(ErrorSource::roughness);
  const bool temperature = stages.is_enabled(ErrorSource::temperature);
  const bool kinematic = stages.is_enabled(ErrorSource::kinematic);
  const bool probe = stages.is_enabled(ErrorSource::probe);
  const bool noise = stages.is_enabled(ErrorSource::noise);
  if (roughness) check_draw_size(draw.roughness_mm.size(), n, "roughness", caller);
  if (noise) check_noise(draw, n, !kXyz, caller);
  if (probe) check_probe(draw.probe, caller);

  const Eigen::Matrix3d r = m.placement.rotation();
  const double scale =
      temperature ? expansion_factor(draw.expansion_coefficient_per_k, draw.temperature_c) : 1.0;
  const double inverse_scale =
      temperature ? 1.0 / expansion_factor(model.temperature.expansion_coefficient_per_k.value,
                                           m.temperature_c)
                  : 1.0;
  Scratch& scratch = thread_scratch(n);
  const Zeros& zeros = thread_zeros(n);
  const double* p = m.points_mm.data();
  const double* nv = m.normals.data();
  const double* rough = roughness ? draw.roughness_mm.data() : zeros.scalar.data();
  if (kinematic) {
    // Machine positions w = L + R (p + r n)·s, and e_Δ(w) for the parameter difference.
    const double r00 = r(0, 0), r01 = r(0, 1), r10 = r(1, 0), r11 = r(1, 1), r22 = r(2, 2);
    const Eigen::Vector3d& location = m.placement.location_mm;
    const double lx = location.x(), ly = location.y(), lz = location.z();
    double* __restrict w = scratch.w.data();
    for (Eigen::Index i = 0; i < n; ++i) {
      const double t = rough[i];
      const double qx = (p[3 * i] + t * nv[3 * i]) * scale;
      const double qy = (p[3 * i + 1] + t * nv[3 * i + 1]) * scale;
      const double qz = (p[3 * i + 2] + t * nv[3 * i + 2]) * scale;
      w[3 * i] = r00 * qx + r01 * qy + lx;
      w[3 * i + 1] = r10 * qx + r11 * qy + ly;
      w[3 * i + 2] = r22 * qz + lz;
    }
    tip_errors(model.kinematics, kinematic_difference(model.kinematics, draw.kinematic, caller),
               scratch.w, m.stylus_offset_mm, Formula::first_order, scratch.e);
  }
  if (probe)
    probe_shifts(probe_difference(draw.probe, nominal_probe(model.probe)), m, 1.0, scratch.shift);
  fused_points<kXyz>(n, p, nv, rough, kinematic ? scratch.e.data() : zeros.xyz.data(),
                     probe ? scratch.shift.data() : zeros.scalar.data(),
                     kXyz ? (noise ? draw.noise_mm.data() : zeros.xyz.data())
                          : xy_noise(draw, noise, n),
                     scale, inverse_scale, r, out);
}

}  // namespace

/// The prepared measurement's arrays, for the kernels below (a friend of the class).
struct PreparedAccess {
  static const double* column(const PreparedMeasurement& p, Eigen::Index c) {
    return p.soa_.col(c).data();
  }
  static const double* harmonic(const PreparedMeasurement& p, Eigen::Index c) {
    return p.harmonics_.col(c).data();
  }
  static bool planar(const PreparedMeasurement& p) { return p.planar_; }
};

namespace {

/// The corrected coordinates of the fused trial on a prepared measurement (K = its probe
/// order): fused_points with structure-of-arrays inputs and the probe shift
/// δr + Σ_k c_k Re_k + s_k Im_k from the stored harmonics — the same operations in the same
/// order as probe_shifts_k and fused_points, so the same values bit for bit.
template <bool kXyz, int K>
void prepared_points(const PreparedMeasurement& pm, const double* __restrict rough,
                     const double* __restrict e, const double* __restrict z,
                     const ProbeErrors& probe, double scale, double inverse_scale,
                     const Eigen::Matrix3d& r, double* __restrict out) {
  const Eigen::Index n = pm.size();
  const double* __restrict px = PreparedAccess::column(pm, 0);
  const double* __restrict py = PreparedAccess::column(pm, 1);
  const double* __restrict pz = PreparedAccess::column(pm, 2);
  const double* __restrict nx = PreparedAccess::column(pm, 3);
  const double* __restrict ny = PreparedAccess::column(pm, 4);
  const double* __restrict nz = PreparedAccess::column(pm, 5);
  std::array<const double*, K + 1> re{}, im{};
  std::array<double, K + 1> ck{}, sk{};
  for (int k = 1; k <= K; ++k) {
    const auto u = static_cast<std::size_t>(k);
    re[u] = PreparedAccess::harmonic(pm, 2 * (k - 1));
    im[u] = PreparedAccess::harmonic(pm, 2 * (k - 1) + 1);
    ck[u] = probe.cos_mm[u];
    sk[u] = probe.sin_mm[u];
  }
  const double base = probe.tip_radius_error_mm;
  const double t00 = r(0, 0), t01 = r(1, 0), t10 = r(0, 1), t11 = r(1, 1), t22 = r(2, 2);
  constexpr int kStride = kXyz ? 3 : 2;
  for (Eigen::Index i = 0; i < n; ++i) {
    double sh = base;
    for (int k = 1; k <= K; ++k) {
      const auto u = static_cast<std::size_t>(k);
      sh += ck[u] * re[u][i] + sk[u] * im[u][i];
    }
    const double t = rough[i];
    const double ex = e[3 * i], ey = e[3 * i + 1];
    const double qx = (px[i] + t * nx[i]) * scale;
    const double qy = (py[i] + t * ny[i]) * scale;
    const double cx = t00 * ex + t01 * ey + sh * nx[i] + z[kStride * i];
    const double cy = t10 * ex + t11 * ey + sh * ny[i] + z[kStride * i + 1];
    out[kStride * i] = (qx + cx) * inverse_scale;
    out[kStride * i + 1] = (qy + cy) * inverse_scale;
    if constexpr (kXyz) {
      const double qz = (pz[i] + t * nz[i]) * scale;
      const double cz = t22 * e[3 * i + 2] + sh * nz[i] + z[3 * i + 2];
      out[kStride * i + 2] = (qz + cz) * inverse_scale;
    }
  }
}

template <bool kXyz, int... K>
void prepared_points_dispatch(std::integer_sequence<int, K...>, int order,
                              const PreparedMeasurement& pm, const double* rough,
                              const double* e, const double* z, const ProbeErrors& probe,
                              double scale, double inverse_scale, const Eigen::Matrix3d& r,
                              double* out) {
  ((order == K ? prepared_points<kXyz, K>(pm, rough, e, z, probe, scale, inverse_scale, r, out)
               : void()),
   ...);
}

/// The fused trial on a prepared measurement; false (nothing written) when the draw's probe
/// order exceeds the stored harmonics (the caller then takes the Measurement path).
template <bool kXyz>
bool prepared_trial(const PreparedMeasurement& pm, const DigitalModel& model,
                    const ErrorDraw& draw, const Stages& stages, const char* caller,
                    double* out) {
  const Measurement& m = pm.measurement();
  const Eigen::Index n = m.size();
  const bool roughness = stages.is_enabled(ErrorSource::roughness);
  const bool temperature = stages.is_enabled(ErrorSource::temperature);
  const bool kinematic = stages.is_enabled(ErrorSource::kinematic);
  const bool probe = stages.is_enabled(ErrorSource::probe);
  const bool noise = stages.is_enabled(ErrorSource::noise);
  if (roughness) check_draw_size(draw.roughness_mm.size(), n, "roughness", caller);
  if (noise) check_noise(draw, n, !kXyz, caller);
  if (probe) check_probe(draw.probe, caller);
  const ProbeErrors shift =
      probe ? probe_difference(draw.probe, nominal_probe(model.probe)) : ProbeErrors{};
  if (shift.max_order > pm.probe_order()) return false;

  const Eigen::Matrix3d r = m.placement.rotation();
  const double scale =
      temperature ? expansion_factor(draw.expansion_coefficient_per_k, draw.temperature_c) : 1.0;
  const double inverse_scale =
      temperature ? 1.0 / expansion_factor(model.temperature.expansion_coefficient_per_k.value,
                                           m.temperature_c)
                  : 1.0;
  Scratch& scratch = thread_scratch(n);
  const Zeros& zeros = thread_zeros(n);
  const double* rough = roughness ? draw.roughness_mm.data() : zeros.scalar.data();
  const double* z = kXyz ? (noise ? draw.noise_mm.data() : zeros.xyz.data())
                         : xy_noise(draw, noise, n);
  if (kinematic) {
    // One pass over the points (internal/fused_trial_kernel.h), the probe shifts first.
    const internal::FirstOrderKernel kernel = internal::first_order_kernel(
        model.kinematics, kinematic_difference(model.kinematics, draw.kinematic, caller),
        m.stylus_offset_mm, caller);
    const int order = pm.probe_order();
    std::array<const double*, max_probe_harmonic_order + 1> re{}, im{};
    for (int k = 1; k <= order; ++k) {
      re[static_cast<std::size_t>(k)] = PreparedAccess::harmonic(pm, 2 * (k - 1));
      im[static_cast<std::size_t>(k)] = PreparedAccess::harmonic(pm, 2 * (k - 1) + 1);
    }
    internal::probe_shift_points(n, order, shift.tip_radius_error_mm, shift.cos_mm.data(),
                                 shift.sin_mm.data(), re.data(), im.data(),
                                 scratch.shift.data());
    internal::FusedTrialInput in;
    in.n = n;
    in.planar = PreparedAccess::planar(pm);
    in.px = PreparedAccess::column(pm, 0);
    in.py = PreparedAccess::column(pm, 1);
    in.pz = PreparedAccess::column(pm, 2);
    in.nx = PreparedAccess::column(pm, 3);
    in.ny = PreparedAccess::column(pm, 4);
    in.nz = PreparedAccess::column(pm, 5);
    in.roughness = rough;
    in.shift = scratch.shift.data();
    in.noise = z;
    in.scale = scale;
    in.inverse_scale = inverse_scale;
    in.rotation = r;
    in.location = m.placement.location_mm;
    if (internal::fused_trial_points(in, kernel, kXyz, out) != 0) {
      // A machine position out of range: recompute them and let the kinematics name it.
      for (Eigen::Index i = 0; i < n; ++i) {
        const Eigen::Vector3d q =
            (m.points_mm.col(i) + rough[i] * m.normals.col(i)) * scale;
        scratch.w.col(i) = r * q + m.placement.location_mm;
      }
      internal::report_bad_tip_position(model.kinematics, scratch.w, m.stylus_offset_mm,
                                        caller);
    }
    return true;
  }
  prepared_points_dispatch<kXyz>(
      std::make_integer_sequence<int, max_probe_harmonic_order + 1>{}, pm.probe_order(), pm,
      rough, zeros.xyz.data(), z, shift, scale,
      inverse_scale, r, out);
  return true;
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

namespace {
/// draw_errors on a measurement whose points have been validated.
void draw_errors_validated(const DigitalModel& model, const Measurement& m, RandomSource& rng,
                           const Stages& stages, ErrorDraw& out, NoiseComponents components) {
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
    rng.fill_normal(std::span<double>(out.roughness_mm.data(), static_cast<std::size_t>(n)),
                    model.roughness.sigma_mm);
  } else {
    out.roughness_mm.resize(0);
  }
  if (stages.is_enabled(ErrorSource::noise)) {
    const Eigen::Index rows = components == NoiseComponents::xy ? 2 : 3;
    out.noise_mm.resize(rows, n);
    rng.fill_normal(std::span<double>(out.noise_mm.data(), static_cast<std::size_t>(rows * n)),
                    noise_sigma_mm(model, m.mode));
  } else {
    out.noise_mm.resize(3, 0);
  }
}
}  // namespace

void draw_errors(const DigitalModel& model, const Measurement& m, RandomSource& rng,
                 const Stages& stages, ErrorDraw& out) {
  check_measurement(m, "draw_errors");
  draw_errors_validated(model, m, rng, stages, out, NoiseComponents::xyz);
}

void draw_errors(const DigitalModel& model, const PreparedMeasurement& prepared,
                 RandomSource& rng, const Stages& stages, ErrorDraw& out,
                 NoiseComponents noise) {
  draw_errors_validated(model, prepared.measurement(), rng, stages, out, noise);
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
  if (noise) check_noise(draw, n, false, "simulate");
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

void simulate_corrected(const Measurement& m, const DigitalModel& model, const ErrorDraw& draw,
                        const Stages& stages, Formula formula, Measurement& out) {
  constexpr const char* kCaller = "simulate_corrected";
  if (&out == &m) throw InvalidInput("simulate_corrected: the output may not be the input");
  if (formula != Formula::first_order) {
    thread_local Measurement simulated;
    simulate(m, model, draw, stages, formula, simulated);
    correct(simulated, model, stages, formula, out);
    return;
  }
  out.points_mm.resize(3, m.size());
  fused_trial<true>(m, model, draw, stages, kCaller, out.points_mm.data());
  copy_metadata(m, out);
}

void simulate_corrected(const Measurement& m, const DigitalModel& model, const ErrorDraw& draw,
                        const Stages& stages, Formula formula,
                        std::vector<geometry::Point2>& out_xy) {
  constexpr const char* kCaller = "simulate_corrected";
  if (formula != Formula::first_order) {
    // The exact formula evaluates the kinematic errors at the noisy reported positions: it
    // needs the z noise too.
    if (stages.is_enabled(ErrorSource::noise)) check_noise(draw, m.size(), false, kCaller);
    thread_local Measurement simulated, corrected;
    simulate(m, model, draw, stages, formula, simulated);
    correct(simulated, model, stages, formula, corrected);
    out_xy.resize(static_cast<std::size_t>(corrected.size()));
    for (Eigen::Index i = 0; i < corrected.size(); ++i)
      out_xy[static_cast<std::size_t>(i)] = {corrected.points_mm(0, i), corrected.points_mm(1, i)};
    return;
  }
  static_assert(sizeof(geometry::Point2) == 2 * sizeof(double), "Point2: two packed doubles");
  out_xy.resize(static_cast<std::size_t>(m.size()));
  fused_trial<false>(m, model, draw, stages, kCaller, reinterpret_cast<double*>(out_xy.data()));
}

PreparedMeasurement::PreparedMeasurement(Measurement m, const DigitalModel& model)
    : measurement_(std::move(m)) {
  validate_measurement(measurement_, "PreparedMeasurement");
  const Eigen::Index n = measurement_.size();
  soa_.resize(n, 6);
  soa_.leftCols<3>() = measurement_.points_mm.transpose().array();
  soa_.rightCols<3>() = measurement_.normals.transpose().array();
  // Exact tests: the fused kernel's planar form relies on pz + r·nz = pz bit for bit.
  planar_ = (soa_.col(5) == 0.0).all() &&
            std::none_of(soa_.col(2).data(), soa_.col(2).data() + n,
                         [](double z) { return z == 0.0 && std::signbit(z); });
  for (const ProbeHarmonic& h : model.probe.directional)
    probe_order_ = std::max(probe_order_, h.order);
  // Re, Im (d_x + i d_y)^k by the recurrence of probe_shifts_k (the same values).
  harmonics_.resize(n, 2 * probe_order_);
  const Eigen::Matrix3d r = measurement_.placement.rotation();
  const double c = r(0, 0), s = r(1, 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double n0 = measurement_.normals(0, i), n1 = measurement_.normals(1, i);
    const double dx = -(c * n0 - s * n1), dy = -(s * n0 + c * n1);
    double re = 1.0, im = 0.0;
    for (int k = 1; k <= probe_order_; ++k) {
      const double next_re = re * dx - im * dy;
      im = re * dy + im * dx;
      re = next_re;
      harmonics_(i, 2 * (k - 1)) = re;
      harmonics_(i, 2 * (k - 1) + 1) = im;
    }
  }
}

void simulate_corrected(const PreparedMeasurement& prepared, const DigitalModel& model,
                        const ErrorDraw& draw, const Stages& stages, Formula formula,
                        Measurement& out) {
  const Measurement& m = prepared.measurement();
  if (&out == &m) throw InvalidInput("simulate_corrected: the output may not be the input");
  if (formula == Formula::first_order) {
    out.points_mm.resize(3, m.size());
    if (prepared_trial<true>(prepared, model, draw, stages, "simulate_corrected",
                             out.points_mm.data())) {
      copy_metadata(m, out);
      return;
    }
  }
  simulate_corrected(m, model, draw, stages, formula, out);
}

void simulate_corrected(const PreparedMeasurement& prepared, const DigitalModel& model,
                        const ErrorDraw& draw, const Stages& stages, Formula formula,
                        std::vector<geometry::Point2>& out_xy) {
  if (formula == Formula::first_order) {
    out_xy.resize(static_cast<std::size_t>(prepared.size()));
    if (prepared_trial<false>(prepared, model, draw, stages, "simulate_corrected",
                              reinterpret_cast<double*>(out_xy.data())))
      return;
  }
  simulate_corrected(prepared.measurement(), model, draw, stages, formula, out_xy);
}

}  // namespace vcmm::errormodel
