// vcmm/characterization/consistency.h — are the residuals of a calibration fit consistent with
// the uncertainties stated for its observations? A χ² test (with the Birge ratio) and an outlier
// test that names the culprit (docs/characterization.md, "Consistency of a calibration").
//
// Notation. Observation i of a least-squares fit has the residual r_i (observed − fitted), the
// stated standard uncertainty u_i and the leverage h_ii (diagonal of the hat matrix
// J(JᵀJ)⁻¹Jᵀ of the weighted design J). ν = observations − unknowns.
//  - χ² = Σ (r_i/u_i)², Birge ratio R_B = √(χ²/ν), p = P(χ²_ν ≥ χ²) (Boost.Math chi_squared).
//    For a linear(ised) model with independent Gaussian errors of the stated u, χ² ~ χ²_ν
//    (R. T. Birge, Phys. Rev. 40, 1932; CODATA's consistency test, e.g. P. J. Mohr et al.,
//    Rev. Mod. Phys. 80, 2008).
//  - Normalised residual w_i = r_i / (u_i √(1 − h_ii)) ~ N(0, 1) (Baarda's data snooping,
//    W. Baarda, Netherlands Geodetic Commission 2(5), 1968): var(r_i) = u_i²(1 − h_ii). For a
//    single blunder in observation k, E|w_i| ≤ E|w_k| for every i (Cauchy–Schwarz on the
//    residual covariance), so the largest |w_i| names the culprit. Tested against the
//    Bonferroni-corrected two-sided quantile z = Φ⁻¹(1 − α_out/(2n)) over the n tested residuals.
//  - When the u_i are known only up to a common factor (σ estimated from the same residuals),
//    χ² is not a test (it is ν by construction); outliers are then tested by the externally
//    studentized residual t_i = w_i/s_(i) ~ t_{ν−1}, s_(i)² = (Σ w_j²(1 − h_jj) − w_i²)/(ν − 1)
//    (the fit's scale without observation i), against t_{ν−1}⁻¹(1 − α_out/(2n)).
// Levels: one overall false-refusal level α = 1 % for correct data, split α_χ² = α_out = 0.5 %;
// by the union bound P(refuse | correct data) ≤ α_χ² + α_out = 1 % (tested on simulated
// calibrations: tests/characterization/consistency_test.cpp).
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace vcmm::characterization {

/// The overall probability of refusing a correct calibration, and its split between the χ²
/// test and the outlier test (the union bound keeps the sum; see the file comment).
inline constexpr double kFalseRefusalLevel = 0.01;

struct ConsistencyLevels {
  double chi_squared = 0.5 * kFalseRefusalLevel;  ///< α_χ²: refuse when p < α_χ²
  double outlier = 0.5 * kFalseRefusalLevel;      ///< α_out: family-wise, over all residuals
};

/// One observation of a fit, with the name that a refusal shows.
struct FitResidual {
  double value = 0.0;        ///< r_i = observed − fitted (mm; the summary shows µm)
  double uncertainty = 0.0;  ///< u_i > 0 (mm), the stated standard uncertainty of the observation
  double leverage = 0.0;     ///< h_ii ∈ [0, 1]; residuals with h_ii > 1 − 1e-9 are not tested
  std::string group;         ///< the input it came from (a file), for the χ² share
  std::string where;         ///< the culprit's name inside it: "line 14, hole R3C2, y"
};

struct ResidualOutlier {
  std::size_t index = 0;    ///< into the residuals given
  std::string group, where;
  double value = 0.0;       ///< r_i
  double uncertainty = 0.0; ///< u_i
  double normalized = 0.0;  ///< w_i (σ stated) or t_i (σ estimated)
};

/// The χ² contribution of one group (input file).
struct GroupShare {
  std::string group;
  std::size_t residuals = 0;
  double chi_squared = 0.0;
};

/// The verdict: a report with the numbers (STYLE.md: a status and a usable verdict).
struct ConsistencyTest {
  bool sigma_stated = true;        ///< false: no χ² test, outliers by studentized residuals
  ConsistencyLevels levels;
  double chi_squared = 0.0;        ///< Σ (r/u)²
  double degrees_of_freedom = 0.0; ///< ν
  double birge_ratio = 1.0;        ///< √(χ²/ν) (1 when ν = 0)
  double p_value = 1.0;            ///< P(χ²_ν ≥ χ²) (1 when ν = 0 or σ not stated)
  bool chi_squared_passed = true;
  std::size_t tested = 0;          ///< residuals in the outlier test
  double outlier_threshold = 0.0;  ///< the Bonferroni quantile |w| or |t| must not exceed
  std::optional<ResidualOutlier> largest;  ///< the largest |normalized residual|
  std::vector<ResidualOutlier> outliers;   ///< above the threshold, largest first
  bool outliers_passed = true;
  std::vector<GroupShare> groups;  ///< χ² per group, largest first

  bool passed() const { return chi_squared_passed && outliers_passed; }
  /// One line: "chi2/nu = 1.02 (nu = 341), Birge ratio 1.01, p = 0.39; largest normalized
  /// residual 2.9 (limit 4.36) at …", and for a failure what failed and the culprit.
  std::string summary() const;
};

/// Tests residuals against their stated uncertainties (file comment). `degrees_of_freedom`
/// ν ≥ 0 of the fit. σ stated: χ² and the normal outlier test; not stated (u_i known up to a
/// common factor): the studentized outlier test only (needs ν ≥ 2, else nothing is tested).
/// Throws std::invalid_argument for a non-finite value or u_i ≤ 0, a leverage outside [0, 1]
/// (1e-9 slack), ν < 0 or more than the number of residuals, levels outside (0, 0.5).
/// O(n log n).
ConsistencyTest test_consistency(std::span<const FitResidual> residuals, double degrees_of_freedom,
                                 bool sigma_stated = true, ConsistencyLevels levels = {});

/// The leverages h_ii = diag(J (JᵀJ)⁻¹ Jᵀ) of a weighted design J (rows: observations), from
/// the thin QR: h_ii = ‖row i of Q‖². J must have full column rank (else the leverages of the
/// rank-deficient fit's own column space are returned, which is the same projector). O(m n²).
Eigen::VectorXd leverages(const Eigen::MatrixXd& weighted_design);

}  // namespace vcmm::characterization
