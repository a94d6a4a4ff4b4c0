// vcmm/validation/reference_values.h — the reference values a virtual-CMM result is compared
// with: roundness from a roundness-meter profile, and the seed study's diameter from a laser
// interferometer plus that profile (docs/validation.md, "Reference values").
//
// Notation. A roundness-meter profile is the radial deviation d(θ) of the surface from a base
// circle about the meter's spindle axis, sampled at angles θ_j ∈ [0, 2π) (file: degrees and
// µm; here radians and mm). The surface point at θ is r(θ) = R + d(θ) from the axis, R the
// (unknown, nominal) radius of the part.
//
// Reference roundness: the points (R_nom + d_j)(cos θ_j, sin θ_j) are evaluated exactly like
// a CMM profile — optional ISO 16610-21 Gaussian filter, then the chosen ISO 12181-1
// reference circle — and RONt is the peak-to-valley deviation about it. R_nom enters only at
// second order (derivation (1) in reference_values.cpp): |ΔRONt| ≲ e·(e + 2·max|d'|)/R_nom,
// e the distance of the reference centre from the meter's axis, d' per radian. Measured: a
// profile with 10 µm eccentricity and 2.2 µm of lobing changes RONt by 0.31 nm between
// R_nom = 85.5 mm and R_nom → ∞ (bound 4.7 nm); centred, by 0.001 nm.
//
// Reference diameter (seed study): the interferometer gives L = r(0) + r(π), the distance
// between the 0° and 180° surface points. The mean diameter is 2·mean r = L + 2·mean(d̃),
// d̃ = d − (d(0) + d(π))/2 (the profile shifted so its 0°/180° mean is zero). Positive: when
// the profile lies on average outside the 0°/180° points the mean diameter exceeds L.
#pragma once

#include <optional>
#include <string_view>

#include "vcmm/geometry/certificate.h"
#include "vcmm/geometry/point.h"
#include "vcmm/geometry/roundness_parameters.h"
#include "vcmm/geometry/roundness.h"
#include "vcmm/geometry/roundness_profile.h"

namespace vcmm::validation {

/// The ISO 12181-1 reference circle a roundness value refers to, its names "MZ", "MI", "LS",
/// "MC" and their parser are vcmm::geometry's (vcmm/geometry/roundness.h).
using geometry::ReferenceCircle;
using geometry::reference_circle_from_string;
using geometry::to_string;

/// The roundness-meter profile, its CSV reader and its checks are vcmm::geometry's
/// (vcmm/geometry/roundness_profile.h; file format in docs/formats.md), named here too so
/// that validation code and its users can keep writing validation::RoundnessProfile.
using geometry::RoundnessProfile;
using geometry::read_roundness_profile_csv;
using geometry::read_roundness_profile_csv_file;
using geometry::validate_roundness_profile;

struct ReferenceRoundnessOptions {
  ReferenceCircle reference_circle = ReferenceCircle::minimum_zone;
  /// Gaussian filter cut-off (UPR); none: unfiltered. Default: the campaign default, 50 UPR.
  std::optional<double> filter_cutoff_upr = 50.0;
  /// Standard uncertainty of the reference RONt from the instrument's budget (mm), ≥ 0.
  double u_instrument_mm = 0.0;
  /// Base radius R_nom (mm) at which the deviations are placed; > max |d|. Use the part's
  /// nominal radius: it matters only at second order (file comment).
  double nominal_radius_mm = 0.0;
};

/// A reference roundness with what was proven about its reference circle.
struct ReferenceRoundness {
  double value_mm = 0.0;  ///< RONt about the reference circle (mm)
  double u_mm = 0.0;      ///< standard uncertainty = options.u_instrument_mm
  ReferenceCircle reference_circle = ReferenceCircle::minimum_zone;
  std::optional<double> filter_cutoff_upr;
  geometry::RoundnessParameters ron;  ///< RONt, RONp, RONv, RONq about the circle (mm)
  geometry::Point2 center;  ///< circle centre in the meter's frame (axis at the origin), mm
  double radius_mm = 0.0;   ///< reference radius (MZ: mean of the two circles)
  /// MZ, MI, MC: the fitter's certificate; none for LS (a smooth least-squares problem).
  std::optional<geometry::Certificate> certificate;
  /// MZ, MI, MC: geometry::verify() of the certificate on the evaluated points (exact);
  /// LS: valid, with an empty reason. A reference whose verification failed is reported, not
  /// thrown: the caller decides (reason says what failed).
  geometry::Verification verification;
};

/// Reference roundness RONt (peak-to-valley roundness deviation, ISO 12181-1:2011; symbols in
/// docs/notation.md) of a roundness-meter profile: points p_j = (R_nom + d_j)(cos θ_j, sin θ_j), then
/// geometry::gaussian_filtered_profile (if a cut-off is given) and the chosen reference circle
/// (geometry::minimum_zone_circle, maximum_inscribed_circle, least_squares_circle or
/// minimum_circumscribed_circle), RONt = peak-to-valley about it; u = u_instrument_mm.
/// Preconditions (geometry::InvalidInput naming the function): a valid profile
/// (validate_roundness_profile); R_nom finite and > max_j |d_j|; u_instrument_mm finite ≥ 0;
/// cut-off finite, > 0, ≤ n/2, and with a filter no angular gap wider than λ_c/2 = 180°/f_c
/// (the filter's closedness rule, checked here to name the angles and lines). Exceptions of
/// the fitters pass through (geometry::UndefinedResult for an MI circle that does not exist).
/// Accuracy: as the geometry functions (exact contacts, centre and radii to a few ulps) plus
/// the second-order R_nom effect above. Complexity: O(n log n) filter + the fitter (O(n) on
/// round profiles) + the exact verification; measured at n = 3600, 50 UPR: MZ 1.2 ms, MI
/// 16 ms, MC 0.7 ms, LS 0.2 ms (docs/validation.md).
ReferenceRoundness reference_roundness(const RoundnessProfile& profile,
                                       const ReferenceRoundnessOptions& options);

/// The seed study's reference diameter with its uncertainty budget.
struct ReferenceDiameter {
  double value_mm = 0.0;  ///< D = L + 2·mean(d̃)
  double u_mm = 0.0;      ///< sqrt(u_L² + u_profile²)
  // Components.
  double interferometer_distance_mm = 0.0;  ///< L
  double deviation_at_0_mm = 0.0;           ///< d(0), sampled or linearly interpolated
  double deviation_at_180_mm = 0.0;         ///< d(π)
  double shift_mm = 0.0;                    ///< s = (d(0) + d(π)) / 2
  double mean_deviation_mm = 0.0;           ///< mean of d over the revolution (trapezoidal)
  double correction_mm = 0.0;               ///< D − L = 2·(mean d − s)
  /// Angular width (rad) of the sample interval that brackets 0° (180°): 0 when a sample sits
  /// exactly there. Linear interpolation errs by at most h²/8 · max|d''| over it.
  double interpolation_interval_0_rad = 0.0;
  double interpolation_interval_180_rad = 0.0;
  double u_interferometer_mm = 0.0;  ///< u_L
  /// Profile contribution u_p · sqrt(Σ c_j²), c_j the sensitivity of D to reading j.
  double u_profile_mm = 0.0;
  /// sqrt(Σ c_j²) (= sqrt(2 − 4/n) for n equiangular samples that include 0° and 180°).
  double profile_sensitivity = 0.0;
};

/// Reference diameter of the seed study: D = L + 2·(m − s), with m the mean deviation of the
/// whole profile (trapezoidal rule on the periodic piecewise-linear interpolant of the
/// samples; the plain mean for equiangular samples) and s = (d(0) + d(π))/2, d(0) and d(π)
/// taken at a sample when one sits exactly at 0° or 180° and else by periodic linear
/// interpolation between the two bracketing samples (error ≤ h²/8 · max|d''| for a smooth
/// profile, h the bracketing interval in rad — for a·cos kθ: a k² h²/8 at each point).
/// Uncertainty (docs/validation.md): D is linear in the readings, D = L + Σ_j c_j d_j with
/// c_j = 2 w_j − λ⁰_j − λ¹⁸⁰_j (w_j the trapezoidal weights, λ the interpolation weights), so
/// with independent readings of standard uncertainty u_p
///   u_D² = u_L² + u_p² Σ_j c_j²,
/// which counts the correlation between the 0°/180° readings and the mean they are part of;
/// for equiangular samples through 0° and 180°: Σ c_j² = 2 − 4/n. A common offset of all
/// readings cancels (Σ c_j = 0). A gain error g of the meter adds g·|D − L| (not included).
/// Preconditions (geometry::InvalidInput naming the function): a valid profile
/// (validate_roundness_profile), L finite > 0, u_L and u_p finite ≥ 0. Exact arithmetic is
/// not needed: the result is a short weighted sum (rounding ~1e-16 of L). Complexity O(n).
ReferenceDiameter reference_diameter(double interferometer_distance_mm,
                                     double u_interferometer_mm,
                                     const RoundnessProfile& profile,
                                     double u_profile_point_mm);

}  // namespace vcmm::validation
