// vcmm/validation/comparison.h — agreement of a measured value with its reference: the E_n
// number and the zeta score (ISO 13528:2022, 9.6 zeta and 9.7 E_n; docs/validation.md,
// "E_n and zeta scores").
//
// Sign convention of this project (the issue's): the difference is reference − measured, so
// a positive score means the CMM reads below the reference. ISO 13528 writes x_i − x_pt (the
// participant minus the assigned value): the opposite sign, the same magnitude.
//
// Reading the scores. With honest standard uncertainties and a normal difference,
// zeta ~ N(0, 1) and E_n = zeta / k ~ N(0, 1/k²): for k = 2, |E_n| > 1 happens 4.6 % of the
// time and the RMS of E_n over a campaign is about 0.5 (docs/validation.md).
#pragma once

namespace vcmm::validation {

/// Both scores of one comparison, with their ingredients (units of the inputs).
struct Comparison {
  double difference = 0.0;     ///< x_ref − x_meas
  double u_difference = 0.0;   ///< sqrt(u_ref² + u_meas²), the standard uncertainty of it
  double k = 2.0;              ///< coverage factor of E_n
  double en = 0.0;             ///< difference / (k · u_difference)
  double zeta = 0.0;           ///< difference / u_difference
};

/// E_n = (x_ref − x_meas) / (k · sqrt(u_ref² + u_meas²)) — the normalised error of
/// ISO 13528:2022, 9.7 with both expanded uncertainties U = k·u (ISO 17043 proficiency tests
/// use k = 2). Inputs: values in any one unit, standard uncertainties u ≥ 0 in that unit,
/// coverage factor k > 0. Throws geometry::InvalidInput (also reachable as
/// errormodel::InvalidInput) naming the function and value when an input is NaN or infinite,
/// a u is negative, both u are zero (the score is undefined), k ≤ 0, or the score itself
/// overflows double (differences near 1e308). The root is taken
/// with std::hypot (no overflow or underflow for any finite u); error a few ulps. O(1).
double en_score(double x_ref, double u_ref, double x_meas, double u_meas, double k = 2.0);

/// E_n from expanded uncertainties U_ref, U_meas given directly (each may carry its own
/// coverage factor or an added term, e.g. the "inflated" treatment U = k·u + |bias|):
/// (x_ref − x_meas) / sqrt(U_ref² + U_meas²), ISO 13528:2022, 9.7. Preconditions and
/// exceptions as en_score (U ≥ 0, not both zero). O(1).
double en_score_expanded(double x_ref, double expanded_u_ref, double x_meas,
                         double expanded_u_meas);

/// zeta = (x_ref − x_meas) / sqrt(u_ref² + u_meas²) — ISO 13528:2022, 9.6 (with standard
/// uncertainties; the reference and the measurement are assumed independent). Preconditions
/// and exceptions as en_score without k. O(1).
double zeta_score(double x_ref, double u_ref, double x_meas, double u_meas);

/// Both scores at once (same preconditions as en_score). O(1).
Comparison compare(double x_ref, double u_ref, double x_meas, double u_meas, double k = 2.0);

}  // namespace vcmm::validation
