// vcmm/characterization/probe_sphere.h — probe errors from points measured on a calibrated
// sphere (ISO 10360-5 style): the tip radius error δr and the directional error coefficients
// of the digital model's probe section, with standard uncertainties (docs/characterization.md,
// "Sphere: probe errors").
//
// Model (errormodel/virtual_cmm.h, stage 4, plus stage 5), for point i in machine coordinates:
//   p_i = c + (R_cal + δr + D(d_i) + f_i + ε_i) u_i,   d_i = −u_i (probing direction),
//   D(d) = Σ_{k∈K} c_k Re((d_x + i d_y)^k) + s_k Im((d_x + i d_y)^k),
// c the sphere centre, R_cal = D_cal/2 the calibrated radius, u_i the outward unit normal
// (material → air: outward on a sphere, so "positive = into the air" = a larger radius),
// f_i the sphere's form deviation (|f_i| ≤ F/2), ε_i the radial component of the noise.
// Unknowns θ = (c_x, c_y, c_z, δr, c_k, s_k …), p = 4 + 2|K|. Geometric least squares:
//   minimise Σ ρ_i²,  ρ_i = |p_i − c| − R_cal − δr − D(−(p_i − c)/|p_i − c|),
// by Gauss-Newton from the algebraic sphere fit. The radius is free — δr IS the radius change
// (δr = (D_meas − D_cal)/2): fixing the radius at R_cal would leave only the centre and push
// δr into the residuals. The basis is evaluated at the fitted directions; its dependence on c
// is left out of the Jacobian (a term of relative size |c_k|·k/R ≈ 1e-5: the fixed point moves
// by ≲ 1e-5 of the coefficients).
//
// Identifiability. The design matrix A (row i: u_iᵀ, 1, Re z_i^k, Im z_i^k with z = d_x + i d_y)
//  - order 1 is exactly confounded with the centre: Re z = −u_x, Im z = −u_y are the centre's
//    own columns. It is never estimated (listed in `not_identifiable`; no number is output);
//    a directional error of order 1 is a pure shift of every feature and changes no size or
//    form, so nothing downstream needs it;
//  - other confounding depends on the point distribution (e.g. Im z^8 vanishes on every point of
//    the ISO 10360-5 25-point plan; a single latitude circle confounds c_z with δr). It is
//    detected from the singular values of A/√N (columns are bounded by 1, so the values
//    compare the design to an ideal one): below kMinSingularValue the combination (named by
//    its right singular vector) is reported and the result is not usable.
//
// Uncertainties (GUM), per parameter j, combined in quadrature:
//  - statistical: s² = Σρ²/ν, ν = N − p, covariance s² (AᵀA)⁻¹; the standard deviation of the
//    scaled-and-shifted t distribution of JCGM 101 6.4.9 is s·√(ν/(ν−2)) times the root of the
//    diagonal (ν ≥ 3 required), so that a Gaussian Monte Carlo draw with this u has the right
//    spread even at the ISO plan's ν = 15;
//  - calibrated diameter: δr = (D_meas − D_cal)/2 takes u(D_cal)/2 in full; the coefficients do
//    not depend on D_cal (R_cal and δr enter ρ only as their sum);
//  - form: the sphere's form deviation is known only as a bound F (peak-to-valley, taken as
//    |f_i| ≤ F/2 about the calibrated sphere). Parameter j responds to it as w_jᵀ f (w_j = row
//    j of the pseudo-inverse (AᵀA)⁻¹Aᵀ), so |error| ≤ (F/2)‖w_j‖₁; a rectangular distribution
//    over that bound gives u = (F/2)‖w_j‖₁/√3 (conservative: the worst alignment of f with
//    w_j; ‖w_δr‖₁ ≥ 1 since Σ w_δr,i = 1).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vcmm/characterization/consistency.h"
#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/measurement.h"

namespace vcmm::characterization {

/// The calibrated sphere: its certificate.
struct CalibratedSphere {
  double diameter_mm = 0.0;    ///< D_cal, finite and > 0
  double diameter_u_mm = 0.0;  ///< standard uncertainty of D_cal, ≥ 0
  double form_mm = 0.0;        ///< form deviation F (peak-to-valley), ≥ 0
};

struct SphereProbeOptions {
  /// Orders k of the directional series to estimate (1 … max_probe_harmonic_order, any order,
  /// duplicates ignored). Order 1 is accepted but never estimated (file comment).
  std::vector<int> orders = {2, 3, 4};
  /// σ_p: the standard deviation of the CMM's probing noise along the normal, for one point
  /// (mm, finite, > 0), stated from elsewhere (the noise characterisation, the CMM's
  /// specification). With it, the consistency test compares the residuals with the stated
  /// u_i² = σ_p² + F²/12 (noise plus the sphere's form as a rectangular distribution over ±F/2):
  /// χ² and outliers (consistency.h). Without it, only the outlier test by studentized
  /// residuals is possible (σ is then estimated from the same residuals).
  std::optional<double> probing_sigma_mm;
};

/// Below this singular value of A/√N a parameter combination counts as not identifiable.
/// Why 1e-2: its standard uncertainty would exceed 100 σ/√N (20 σ for 25 points) — useless as
/// a calibration — and an exactly confounded combination shows up at about k·σ/R rather than 0,
/// because the probing directions are estimated from noisy points: ≤ 16 · 2 µm / 5 mm = 6e-3
/// for orders ≤ 16, noise ≤ 2 µm and spheres ≥ 10 mm, which the threshold must exceed.
inline constexpr double kMinSingularValue = 1e-2;

enum class SphereFitStatus {
  ok,              ///< converged, every requested parameter identifiable
  rank_deficient,  ///< some combination of parameters is not identifiable (see message)
  not_converged,   ///< Gauss-Newton did not converge in 50 iterations (should not happen)
};
std::string_view to_string(SphereFitStatus status);

/// One estimated parameter with its uncertainty budget (mm).
struct ProbeParameterEstimate {
  std::string name;  ///< "tip_radius_error", "cos_3", "sin_3"
  double value_mm = 0.0;
  double u_mm = 0.0;  ///< combined standard uncertainty
  double u_statistical_mm = 0.0;
  double u_diameter_mm = 0.0;  ///< non-zero only for the tip radius error
  double u_form_mm = 0.0;
};

/// A requested parameter that cannot be estimated, and why.
struct NotIdentifiable {
  std::string what;  ///< "order 1" or a combination "0.71·cos_8 − 0.71·tip_radius_error"
  std::string reason;
};

/// The result: a report with a status and a usable/not-usable verdict (STYLE.md).
struct SphereProbeCharacterization {
  SphereFitStatus status = SphereFitStatus::ok;
  bool usable = false;
  std::string message;  ///< what went wrong, or a one-line summary

  Eigen::Index point_count = 0;
  std::vector<int> orders;  ///< estimated orders (sorted, without 1)
  std::vector<NotIdentifiable> not_identifiable;
  Eigen::Vector3d center_mm = Eigen::Vector3d::Zero();  ///< fitted centre, machine coords
  double diameter_mm = 0.0;                             ///< D_meas = D_cal + 2 δr
  CalibratedSphere sphere;                              ///< the certificate used
  ProbeParameterEstimate tip_radius_error;              ///< δr
  std::vector<ProbeParameterEstimate> directional;      ///< cos_k, sin_k per estimated order
  errormodel::ProbeModel probe;  ///< the same, as the digital model's probe section

  int degrees_of_freedom = 0;        ///< ν = N − p
  double residual_sigma_mm = 0.0;    ///< s, the a-posteriori σ of the radial residuals
  double t_factor = 1.0;             ///< √(ν/(ν−2))
  double residual_range_mm = 0.0;    ///< max ρ − min ρ (cf. ISO 10360-5 P_FTU, after D(d))
  double min_singular_value = 0.0;   ///< smallest singular value of A/√N
  std::vector<double> residuals_mm;  ///< ρ_i, in input order
  int iterations = 0;
  /// The residuals against the stated σ_p and form (or studentized, without σ_p), each named
  /// "point i (x, y, z)" (1-based, input order; consistency.h). Not part of `usable`: a caller
  /// refuses the result when !consistency.passed() unless told otherwise (the CLI: exit 3, or
  /// --accept-inconsistent).
  ConsistencyTest consistency;
};

/// Estimates the probe section from N points measured on a calibrated sphere (file comment).
/// `points_mm`: 3×N, machine coordinates (mm), one probing per point, probing directions
/// along the sphere normal (as a CMM probes a sphere). Preconditions (InvalidInput, message
/// names the function, rule and value/index): every coordinate finite; sphere diameter
/// finite > 0, u and form finite, ≥ 0 and at most 1 % of the diameter (a certificate's u and
/// form are well below that; more means wrong units); probing σ, when given, finite > 0 and at
/// most 1 % of the radius; orders within 1 … max_probe_harmonic_order; N ≥ p + 3
/// (ν ≥ 3 for the t factor); the points must lie on a sphere — the fitted diameter within 1 %
/// of D_cal (probe errors are micrometres: a larger difference means the wrong sphere or
/// units) and every residual below 1 % of R_cal. A design in which a combination is not
/// identifiable is not an exception: status rank_deficient, usable false, the combination in
/// `not_identifiable` and `message`, no estimate filled in.
/// Accuracy: the estimate is the least-squares solution to ~1e-12 mm; uncertainty as above.
/// Complexity O(N p²) per iteration (a p-column SVD), 2–3 iterations; 25 or 73 points with
/// orders 2–4: ~70–80 µs (docs/characterization.md, "Performance").
SphereProbeCharacterization characterize_probe_sphere(const Eigen::Matrix3Xd& points_mm,
                                                      const CalibratedSphere& sphere,
                                                      const SphereProbeOptions& options = {});

/// The digital model's "probe" section for a usable result, as JSON text (an object with
/// "source", "tip_radius_error" and "directional_error", values in µm; the format of
/// docs/errormodel.md, loadable by errormodel::parse_digital_model when placed under "probe" in
/// a model file). `source` says where the data came from (file name, date); the method, N, ν
/// and the identifiability note are appended. Throws InvalidInput if !result.usable or a number
/// is not finite.
std::string probe_section_json(const SphereProbeCharacterization& result, std::string_view source);

/// The whole output of `vcmm characterize sphere`: {"probe": <probe_section_json>,
/// "characterization": {diagnostics: centre, diameter, ν, s, residual range, budget per
/// parameter, not-identifiable list, status, consistency}} (docs/characterization.md). Usable
/// results only; `accepted_inconsistent` records a failed consistency test the user overrode.
/// Throws InvalidInput naming the key and `source` if a number is not finite.
std::string probe_characterization_json(const SphereProbeCharacterization& result,
                                        std::string_view source,
                                        bool accepted_inconsistent = false);

// ---- measurement plans and simulated calibration data ----------------------------------

/// One circle of probing points on the sphere at polar angle θ from the pole (+Z).
struct SphereCircle {
  double polar_angle_rad = 0.0;  ///< 0 = the pole, π/2 = the equator
  int points = 1;                ///< equally spaced in azimuth (1 at the pole)
  double azimuth_offset_rad = 0.0;
};

/// Unit outward directions (3×N) of points on the given circles, circle after circle,
/// azimuth φ_j = offset + 2πj/points. Throws InvalidInput for a non-finite angle or points < 1.
Eigen::Matrix3Xd sphere_directions(std::span<const SphereCircle> circles);

/// The 25-point plan of ISO 10360-5 (as recalled, see docs/characterization.md): 1 point at
/// the pole, 4 at 22.5° below it, 8 at 45°, 4 at 67.5°, 8 on the equator, each circle turned
/// 22.5° further in azimuth than the previous one. Pole = +Z (vertical stylus).
Eigen::Matrix3Xd iso10360_5_directions();

/// A denser plan for the directional coefficients (docs/characterization.md): the pole and
/// 24 points on each of the circles at 30°, 60° and 90° from the pole (73 points).
Eigen::Matrix3Xd dense_hemisphere_directions();

/// The nominal measurement of a sphere of diameter `diameter_mm` centred on the workpiece
/// origin: point i = (D/2)·u_i, normal u_i (outward = material → air), `placement` mapping
/// workpiece to machine (its location is the sphere centre in machine coordinates), `mode`.
/// Feed it to errormodel::simulate with the probe and noise stages to get calibration data.
/// Throws InvalidInput if the diameter is not finite and positive or a direction is not a
/// unit vector (1e-9). O(N).
errormodel::Measurement sphere_measurement(double diameter_mm, const Eigen::Matrix3Xd& directions,
                                           const errormodel::Placement& placement,
                                           errormodel::ProbingMode mode);

}  // namespace vcmm::characterization
