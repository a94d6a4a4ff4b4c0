// vcmm/errormodel/virtual_cmm.h — the virtual CMM: the five error sources as ordered stages,
// one realisation of all of them (ErrorDraw), simulation of what the CMM reports, and the
// correction of the known systematic part (docs/errormodel.md).
//
// Stages, applied in this order to each point p (workpiece coordinates, mm) with unit normal n
// (material → air; probing direction d = −n; R = placement rotation, L = location):
//   1 roughness    p ← p + r_i · n                     r_i ~ N(0, σ_rough²)
//   2 temperature  p ← p · (1 + α (T − 20 °C))         the workpiece expands about its origin
//   3 kinematic    w = L + R p (machine);  p ← p + Rᵀ (m(w) − w), m(w) the tip position the
//                  machine reports when its tip truly is at w (measured_tip_positions; the
//                  error functions are evaluated at the surface point, not the tip centre:
//                  that changes the error by ≤ |∇e|·r_tip ≈ 1e-6 · 1.5 mm = 1.5 nm)
//   4 probe        p ← p + (δr + D(R d)) · n           δr tip radius error, D directional error
//   5 noise        p ← p + σ_mode · z_i                z_i ~ N(0, I₃)
// Normals pass through unchanged: they are the probing directions the CMM used.
//
// Directional probe error, for a probing direction d = (dx, dy, dz) in machine coordinates:
//   D(d) = Σ_k [ c_k Re((dx + i·dy)^k) + s_k Im((dx + i·dy)^k) ]
// For horizontal probing (|d_xy| = 1, azimuth φ) this is the Fourier series Σ c_k cos kφ +
// s_k sin kφ; in 3D it is the sectoral spherical-harmonic series sin^k θ · (c_k cos kφ +
// s_k sin kφ) (θ polar angle from +Z), which vanishes for vertical probing.
//
// correct() inverts stages 4, 3, 2 (in that order) with the model's *estimated* values: the
// nominal probe errors, the nominal kinematic errors evaluated at the measured positions
// (tip_errors; exact inverse of stage 3), and the expansion with the nominal α and the
// temperature *reading*. Roughness and noise are random and are not corrected. So one
// Monte Carlo trial is  correct(simulate(best_estimate, draw_errors(...)));  with every
// uncertainty and σ zero it returns its input to < 1e-12 mm (tests/errormodel/virtual_cmm_test).
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string_view>
#include <vector>

#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/kinematic_errors.h"
#include "vcmm/errormodel/measurement.h"
#include "vcmm/errormodel/random_source.h"
#include "vcmm/geometry/point.h"

namespace vcmm::errormodel {

/// The error sources, in stage order.
enum class ErrorSource { roughness, temperature, kinematic, probe, noise };
inline constexpr std::array<ErrorSource, 5> all_error_sources = {
    ErrorSource::roughness, ErrorSource::temperature, ErrorSource::kinematic,
    ErrorSource::probe, ErrorSource::noise};

/// "roughness", "temperature", "kinematic", "probe", "noise".
std::string_view to_string(ErrorSource source);
std::optional<ErrorSource> error_source_from_string(std::string_view text);

/// Which stages are switched on (all by default).
struct Stages {
  std::array<bool, 5> enabled = {true, true, true, true, true};

  static constexpr Stages all() { return {}; }
  static constexpr Stages none() { return {{false, false, false, false, false}}; }
  static constexpr Stages only(ErrorSource s) {
    Stages out = none();
    out.enabled[static_cast<std::size_t>(s)] = true;
    return out;
  }
  constexpr bool is_enabled(ErrorSource s) const { return enabled[static_cast<std::size_t>(s)]; }
  constexpr Stages& set(ErrorSource s, bool on) {
    enabled[static_cast<std::size_t>(s)] = on;
    return *this;
  }
  friend constexpr bool operator==(const Stages&, const Stages&) = default;
};

/// One realisation of the probe errors (mm): fixed-size, no allocation.
struct ProbeErrors {
  double tip_radius_error_mm = 0.0;
  std::array<double, max_probe_harmonic_order + 1> cos_mm{};  ///< index = order (0 unused)
  std::array<double, max_probe_harmonic_order + 1> sin_mm{};
  int max_order = 0;  ///< highest order evaluated, 0 … max_probe_harmonic_order (0: none)
};

/// The effective radius error δr + D(d) (mm) for a unit probing direction d in machine
/// coordinates (formula in the file comment). Throws InvalidInput if probe.max_order is out of
/// range. O(max_order).
double probe_error_mm(const ProbeErrors& probe, const Eigen::Vector3d& probing_direction);

/// One realisation of every error source for one measurement.
struct ErrorDraw {
  double temperature_c = reference_temperature_c;  ///< true workpiece temperature (°C)
  double expansion_coefficient_per_k = 0.0;        ///< true α (1/K)
  KinematicErrors kinematic;                       ///< true kinematic errors
  ProbeErrors probe;                               ///< true probe errors
  Eigen::VectorXd roughness_mm;  ///< N deviations along the normals (empty: stage off)
  /// Noise vectors, workpiece axes: 3×N (x, y, z), or 2×N (x, y) when drawn with
  /// NoiseComponents::xy for the x, y form of simulate_corrected (empty: stage off).
  Eigen::MatrixXd noise_mm;
};

/// Which components of the noise a draw holds. The x, y form of the fused trial
/// (simulate_corrected into Point2) never reads z: its first-order kinematic term is evaluated
/// at the noise-free machine position, so z noise moves only the z coordinate. A Monte Carlo
/// loop that evaluates x, y only draws the 2N numbers it uses instead of 3N (xy); everything
/// else needs all three (xyz).
enum class NoiseComponents {
  xyz,  ///< 3N normals, point i's (x, y, z) consecutive: every form
  xy,   ///< 2N normals, point i's (x, y) consecutive: the x, y form, first-order formula only
};

/// The estimated (nominal) values of every source for measurement `m`: T = the reading,
/// α, kinematic and probe errors at their estimates, roughness and noise zero (sized N).
/// simulate() with it adds exactly what correct() removes.
ErrorDraw nominal_errors(const DigitalModel& model, const Measurement& m);

/// Draws one realisation: T ~ N(reading, u_T²), α ~ N(α̂, u(α)²), kinematic errors by
/// model.kinematics.draw(), probe coefficients ~ N(value, u²), roughness N(0, σ²) per point,
/// noise N(0, σ_mode² I₃) per point. Sources whose stage is off keep their nominal value and
/// consume no random numbers. Random numbers come in bulk calls, in stage order: temperature
/// and probe scalars (one call), kinematic (its own call), roughness (N), noise (3N, point i's
/// x, y, z consecutive).
/// `out` is reused: no allocation once sized. Validates `m` (InvalidInput). O(N).
void draw_errors(const DigitalModel& model, const Measurement& m, RandomSource& rng,
                 const Stages& stages, ErrorDraw& out);
ErrorDraw draw_errors(const DigitalModel& model, const Measurement& m, RandomSource& rng,
                      const Stages& stages = Stages::all());

/// What the CMM would report for the workpiece surface `m` (the true, or best-estimate,
/// points) under the errors `draw`, applying the enabled stages in order (file comment).
/// The result keeps m's normals, placement, mode, temperature reading and stylus offset.
/// Throws InvalidInput if `m` is invalid, `draw` lacks a per-point array an enabled stage
/// needs (wrong size) or has a bad probe max_order; std::invalid_argument from the kinematic
/// model if a point lies outside the machine's axis ranges or the kinematic realisation does
/// not match the model. `formula`: the rigid-body formula of stage 3. Safe to call from
/// several threads at once (work arrays are per thread). O(N); ~25 ns a point with
/// first-order kinematics (docs/errormodel.md, "Performance").
Measurement simulate(const Measurement& m, const DigitalModel& model, const ErrorDraw& draw,
                     const Stages& stages = Stages::all(),
                     Formula formula = Formula::first_order);
/// As above, into `out` (its storage is reused; `out` may not be `m`).
void simulate(const Measurement& m, const DigitalModel& model, const ErrorDraw& draw,
              const Stages& stages, Formula formula, Measurement& out);

/// Removes the known systematic part of the enabled stages from measured data (file
/// comment): probe (nominal δr and D), kinematic (nominal errors, exact inverse), temperature
/// (to 20 °C with the nominal α and the reading). Roughness and noise stages are ignored.
/// Throws as simulate(). O(N).
Measurement correct(const Measurement& measured, const DigitalModel& model,
                    const Stages& stages = Stages::all(),
                    Formula formula = Formula::first_order);
void correct(const Measurement& measured, const DigitalModel& model, const Stages& stages,
             Formula formula, Measurement& out);

/// A measurement validated once and laid out for the Monte Carlo loop, where the same best
/// estimate is simulated ~10⁴–10⁶ times: the overloads of draw_errors and simulate_corrected
/// that take it skip the O(N) validation of the points (done here, once) and reuse what does
/// not change between trials — coordinates and normals in structure-of-arrays form, and the
/// harmonics Re, Im (d_x + i d_y)^k of every probing direction d = −R n for the orders
/// k ≤ the model's highest directional probe order (the probe stage then costs 2K products a
/// point instead of the complex recurrence). Results are bit for bit those of the
/// Measurement overloads (tests/errormodel/simulate_corrected_test.cpp). Immutable and
/// safe to share between threads.
class PreparedMeasurement {
 public:
  /// Validates `m` as validate_measurement does (InvalidInput naming "PreparedMeasurement")
  /// and precomputes the probe harmonics for `model`'s probe orders. O(N·K).
  PreparedMeasurement(Measurement m, const DigitalModel& model);

  const Measurement& measurement() const { return measurement_; }
  Eigen::Index size() const { return measurement_.size(); }
  /// Highest probe order whose harmonics are stored (draws of higher order, which the
  /// model cannot produce, are simulated through the Measurement overload).
  int probe_order() const { return probe_order_; }

 private:
  friend struct PreparedAccess;
  Measurement measurement_;
  Eigen::ArrayXXd soa_;         ///< N × 6: x, y, z, n_x, n_y, n_z (workpiece axes)
  Eigen::ArrayXXd harmonics_;   ///< N × 2K: Re_k, Im_k for k = 1 … K
  int probe_order_ = 0;
  bool planar_ = false;  ///< every n_z is 0 and no z is −0 (a ring scan's points and normals)
};

/// draw_errors for a prepared measurement: the same draw as draw_errors(model,
/// prepared.measurement(), rng, stages, out), without validating the points again. With
/// `noise` = NoiseComponents::xy the noise stage draws 2N numbers, (x, y) per point, into a
/// 2×N noise_mm (every other source as above): a draw only the x, y form of
/// simulate_corrected with the first-order formula accepts (the others throw InvalidInput).
/// O(N).
void draw_errors(const DigitalModel& model, const PreparedMeasurement& prepared,
                 RandomSource& rng, const Stages& stages, ErrorDraw& out,
                 NoiseComponents noise = NoiseComponents::xyz);

/// One Monte Carlo trial's corrected data, correct(simulate(m, draw)), computed in one pass
/// over the points (plus the kinematic kernel's, on per-thread work arrays: no 3×N result in
/// between, no allocation once sized): every stage's draw enters as its difference from
/// the estimate that correct() removes (docs/errormodel.md, "The fused trial"):
///   p' = (p + r_i n)·(s/ŝ) + [Rᵀ e_Δ(w) + (δr + D − δr̂ − D̂)(R d)·n + z_i] / ŝ,
/// s = 1 + α(T − 20 °C) and ŝ = 1 + α̂(T_reading − 20 °C) the drawn and estimated expansion
/// factors, w = L + R (p + r_i n)·s the machine position, e_Δ the first-order tip error of
/// the kinematic parameter difference (draw − nominal; the first-order formula is linear in
/// the parameters). Probe, temperature, roughness and noise terms are the composition's to
/// rounding (~1e-13 mm at 100 mm). The kinematic term differs from the composition's
/// e_draw(m) − e_nominal(w') only by evaluating both at w instead of at the simulated
/// position m = w + e_draw(w) and the probe-corrected reported position
/// w' = w + e_draw(m) + R (δprobe_draw − δprobe_nominal)·n + R z_i, each a few µm from w:
///   |fused − composed| ≤ G·(2|e_draw| + |δprobe_draw − δprobe_nominal| + |z_i|) + 1e-13 mm,
/// G the largest |∇e| (mm/mm) of the drawn and of the estimated errors along those µm
/// segments. For µm-level errors that change by µm over the travel (G ~ 1e-6) and µm noise
/// this is ~1e-11 to 1e-8 mm (measured: docs/errormodel.md, "The fused trial"); with the
/// kinematic stage off the two agree to rounding.
/// Formula::exact is not linear in the parameters: it is computed as the composition
/// (simulate then correct, in per-thread buffers) and equals it exactly.
/// `out`: the corrected measurement, with m's normals, placement, mode, temperature reading
/// and stylus offset (storage reused; `out` may not be `m`). Throws as simulate().
/// Safe to call from several threads. O(N): one first-order kinematic evaluation instead of
/// the composition's three (docs/performance.md).
void simulate_corrected(const Measurement& m, const DigitalModel& model, const ErrorDraw& draw,
                        const Stages& stages, Formula formula, Measurement& out);
/// As above, only the x and y coordinates of the corrected points (workpiece axes, mm), for
/// the 2-D evaluation of a section (e.g. a ring gauge's roundness and diameter): no metadata
/// is copied. `out_xy` is resized to N (storage reused). With the first-order formula the
/// draw's noise may be 2×N (NoiseComponents::xy) or 3×N (its z is not read); the exact
/// formula needs 3×N (InvalidInput otherwise).
void simulate_corrected(const Measurement& m, const DigitalModel& model, const ErrorDraw& draw,
                        const Stages& stages, Formula formula,
                        std::vector<geometry::Point2>& out_xy);
/// The same two forms for a prepared measurement (the Monte Carlo loop): bit for bit the
/// results of the overloads above for prepared.measurement(), without validating its points
/// again (the draw is still checked: sizes, probe order; O(1)). With the kinematic stage on,
/// one SIMD pass over the points computes the machine positions, the kinematic error and the
/// corrected points in registers (docs/errormodel.md, "The fused trial"): ~23 µs at 3600
/// points with all stages (docs/performance.md).
void simulate_corrected(const PreparedMeasurement& prepared, const DigitalModel& model,
                        const ErrorDraw& draw, const Stages& stages, Formula formula,
                        Measurement& out);
void simulate_corrected(const PreparedMeasurement& prepared, const DigitalModel& model,
                        const ErrorDraw& draw, const Stages& stages, Formula formula,
                        std::vector<geometry::Point2>& out_xy);

}  // namespace vcmm::errormodel
