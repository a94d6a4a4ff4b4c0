// vcmm/characterization/hole_plate.h — the 21 kinematic errors of a CMM (the digital model's
// "kinematics" section) estimated from a calibrated hole plate or ball plate measured in several
// placements, with their covariance and an identifiability analysis (docs/characterization.md,
// "Hole plate: kinematic errors"; derivation in characterization/src/hole_plate.cpp).
//
// Model. Feature i of the plate has calibrated coordinates c_i (plate frame, mm) with standard
// uncertainty u_i per coordinate. Placement j puts the plate in setup s = s(j) at the unknown
// rigid pose (R_s, T_s) (plate → machine) and measures feature centres with stylus offset t_j:
//     p_ij = w_ij + e(w_ij; θ, t_j) + ε_ij,     w_ij = R_s (c_i + δc_i) + T_s,
// p_ij the feature centre the CMM reports (machine coordinates, mm), θ the Legendre
// coefficients of the 18 error functions and the 3 squareness errors (errormodel/
// kinematic_errors.h), e the first-order tip error (linear in θ), δc_i ~ N(0, u_i² I) the
// plate's calibration error (common to all placements), ε_ij ~ N(0, σ² I) the probing
// repeatability of a feature centre. Unknowns: θ, one 6-DOF pose per setup (nuisance), δc.
// Weighted least squares (Gauss–Newton; only the pose rotations are non-linear) with the
// calibration as pseudo-observations δc_i = 0 ± u_i, so the covariance carries the plate's
// uncertainty and its correlation between placements.
//
// Identifiability. A combination of θ whose effect on every measured centre a change of the
// poses can mimic is invisible. The null space of the weighted Jacobian after projecting out
// the poses and plate corrections is found by SVD with a relative tolerance; each invisible
// direction is pinned by fixing one "pivot" parameter to 0 (a gauge). Directions invisible to
// *any* rigid-artefact measurement (constant translations c0, constant rotations traded for
// straightness slopes, squareness against straightness slopes, a rotation of the machine
// frame) are fixed by convention; directions only this plan cannot see are reported as not
// identifiable and get an a-priori uncertainty in the model, not an estimate.
#pragma once

#include <Eigen/Core>

#include <array>
#include <iosfwd>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "vcmm/characterization/consistency.h"
#include "vcmm/errormodel/kinematic_errors.h"
#include "vcmm/errormodel/random_source.h"

namespace vcmm::characterization {

/// The calibrated plate: feature ids, calibrated centre coordinates in the plate frame and
/// their standard uncertainty. Any 3D arrangement works (hole plate: z = 0; ball plate: the
/// ball centres); the features of every setup must not all lie on one line.
struct HolePlate {
  std::vector<std::string> ids;         ///< unique, non-empty, no ',' or '#'
  Eigen::Matrix3Xd calibrated_mm;       ///< 3×F, plate frame (mm)
  std::vector<double> calibration_u_mm; ///< F values ≥ 0: standard uncertainty of each
                                        ///< calibrated coordinate (isotropic, mm)
  std::string source;               ///< the file it was read from (messages; may be empty)
  std::vector<std::size_t> lines;   ///< 1-based file line of each feature (empty: built in code)
};

/// A rigid pose, plate → machine: m = rotation · c + translation_mm.
struct RigidPose {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation_mm = Eigen::Vector3d::Zero();

  /// Rot(ω) (Rodrigues, ω in rad) and translation (mm).
  static RigidPose from_rotation_vector(const Eigen::Vector3d& omega_rad,
                                        const Eigen::Vector3d& translation_mm);
  /// The machine coordinates of plate points (3×N).
  Eigen::Matrix3Xd apply(const Eigen::Matrix3Xd& plate_mm) const;
};

/// One placement: the feature centres the CMM reported with one stylus.
struct HolePlatePlacement {
  std::string name;   ///< for messages and the report (e.g. the file name)
  /// Placements with the same non-empty setup name were measured without moving the plate
  /// (e.g. with several styli) and share one pose; an empty setup gives the placement its own.
  std::string setup;
  std::vector<std::string> ids;   ///< features measured (plate ids, each at most once)
  Eigen::Matrix3Xd measured_mm;   ///< 3×n feature centres, machine coordinates (mm), tip centre
  Eigen::Vector3d stylus_offset_mm = Eigen::Vector3d::Zero();  ///< t (errormodel convention)
  std::string source;               ///< the file it was read from (messages; may be empty)
  std::vector<std::size_t> lines;   ///< 1-based file line of each centre (empty: built in code)
};

/// The same degree for all 18 error functions.
std::array<int, errormodel::axis_error_count> uniform_degrees(int degree);
/// The degrees of a model's 18 functions (to fit with the layout of an existing model).
std::array<int, errormodel::axis_error_count> degrees_of(const errormodel::KinematicModel& model);

struct HolePlateFitOptions {
  errormodel::KinematicChain chain = errormodel::KinematicChain::moving_bridge();
  /// Travel of X, Y, Z (mm): the domain of the Legendre series; every reading must lie inside.
  std::array<errormodel::AxisRange, 3> axis_ranges{};
  /// Legendre degree of each of the 18 functions (0 … max_legendre_degree), AxisError order.
  std::array<int, errormodel::axis_error_count> degrees = uniform_degrees(2);
  /// σ: standard deviation of one coordinate of a measured feature centre (probing
  /// repeatability of the centre, not of a single point), mm, > 0.
  double probing_sigma_mm = 0.0;
  /// A direction is invisible when its singular value, relative to the largest, is at or below
  /// this (columns scaled to unit norm before the poses are projected out); coefficients of the
  /// echelon null basis at or below it count as 0. Why 1e-3: exactly invisible directions come
  /// out at rounding level (≤ 1e-12), but a symmetry of the plan (e.g. two plate heights
  /// symmetric about the middle of the Z travel make P_2 of the Z functions invisible) is
  /// broken only by the µm by which the fitted positions differ from the nominal ones: ~1e-6
  /// relative, up to ~1e-4 for degree-10 terms (|P_n'| ≤ n²/2 … ); real directions of the
  /// plans in docs/characterization.md come out ≥ 0.05. A direction seen at 1e-3 would have an
  /// uncertainty ~1000 times that of a well-seen one: no loss to call it invisible.
  double rank_tolerance = 1e-3;
  /// A-priori standard uncertainty written into the model for each coefficient this plan
  /// cannot identify (not an estimate: the machine's specification should say). Translations
  /// (mm) and rotations/squareness (rad).
  double unidentified_translation_u_mm = 1e-3;
  double unidentified_rotation_u_rad = 1e-6;
  int max_iterations = 20;  ///< Gauss–Newton iterations (≥ 1); 2–3 are normal
};

/// How the data determine one parameter.
enum class ParameterStatus {
  identifiable,     ///< its own estimate, independent of the gauge
  in_combination,   ///< estimated, but only with the pivots of its null directions fixed at 0:
                    ///< the number is meaningful in this gauge (see null_directions)
  by_convention,    ///< a pivot of a direction no rigid-artefact measurement can see: 0 ± 0
  not_identifiable, ///< a pivot of a direction this plan cannot see: 0 ± the a-priori u
};
std::string_view to_string(ParameterStatus status);

/// One parameter of the kinematic model (parameter-vector order of errormodel::KinematicModel).
struct KinematicParameter {
  std::string name;  ///< "E_XX c1", "E_C0Y"
  bool rotation = false;  ///< rad (rotations, squareness) rather than mm
  ParameterStatus status = ParameterStatus::identifiable;
  double value = 0.0;                 ///< mm or rad (0 for the two pivot statuses)
  double standard_uncertainty = 0.0;  ///< mm or rad, from the model covariance
};

/// An invisible direction of the parameters: adding any multiple of it changes no measured
/// centre of this plan. Normalised so that the pivot's coefficient is 1; coefficients in the
/// JSON units (µm for translations, µrad for rotations and squareness).
struct NullDirection {
  Eigen::Index pivot = 0;  ///< parameter fixed at 0 to pin this direction
  bool intrinsic = false;  ///< also invisible to any rigid-artefact measurement (convention)
  std::vector<std::pair<Eigen::Index, double>> terms;  ///< (parameter index, coefficient)
  std::string text;        ///< e.g. "E_XY c1 + 2*E_C0Y"
  /// The same direction as used by the gauge (physical units, mm or rad per mm or rad of the
  /// pivot; 0 at every other pivot). For an intrinsic direction it may add multiples of
  /// directions only this plan misses to what `terms` shows.
  Eigen::VectorXd gauge_direction;
};

struct SetupPose {
  std::string setup;  ///< setup name (or the placement name for a placement on its own)
  RigidPose pose;     ///< estimated plate → machine pose
};

struct PlacementResiduals {
  std::string name;
  Eigen::Matrix3Xd residuals_mm;  ///< measured − fitted model, per feature (mm)
  double rms_mm = 0.0;            ///< RMS of all coordinates
};

enum class HolePlateFitStatus {
  converged,      ///< Gauss–Newton converged
  not_converged,  ///< max_iterations reached (the numbers are the last iterate)
};
std::string_view to_string(HolePlateFitStatus status);

/// The result: a report with a status and a usable/not-usable verdict (STYLE.md).
struct KinematicCharacterization {
  explicit KinematicCharacterization(errormodel::KinematicModel estimated)
      : model(std::move(estimated)) {}

  HolePlateFitStatus status = HolePlateFitStatus::not_converged;
  bool usable = false;
  std::string message;  ///< one-line summary or what went wrong

  /// The estimated model: mean = estimates (0 at pivots), covariance = the full joint
  /// covariance (data, scaled as below, plus the a-priori u of not-identifiable pivots
  /// propagated into their combinations). Load it as the digital model's kinematics.
  errormodel::KinematicModel model;
  /// The covariance from the data alone (P×P, zero rows/columns at the pivots), scaled by
  /// the variance factor when that exceeds 1: the uncertainty of the gauge-fixed estimate.
  Eigen::MatrixXd data_covariance;
  std::vector<KinematicParameter> parameters;    ///< P entries, parameter-vector order
  std::vector<NullDirection> null_directions;    ///< intrinsic first
  std::vector<SetupPose> setups;
  std::vector<PlacementResiduals> placements;    ///< input order
  Eigen::Matrix3Xd plate_corrections_mm;         ///< estimated δc (3×F), plate frame

  Eigen::Index observations = 0;       ///< 3 × measured centres (+ 3 per uncertain feature)
  Eigen::Index unknowns = 0;           ///< estimated θ + 6 per setup + 3 per uncertain feature
  Eigen::Index degrees_of_freedom = 0;
  double residual_rms_mm = 0.0;        ///< RMS of all measured − fitted coordinates
  double variance_factor = 1.0;        ///< s0² = weighted residual sum / dof (1 if dof = 0)
  bool covariance_scaled = false;      ///< s0² > 1: the covariance was multiplied by s0²
  double probing_sigma_given_mm = 0.0;
  double probing_sigma_from_residuals_mm = 0.0;  ///< σ·s0: the σ that would make s0² = 1
  double weakest_direction = 0.0;  ///< smallest kept / largest singular value (scaled)
  int iterations = 0;
  /// The residuals against σ (measured centres) and u_i (the calibration's pseudo-observations)
  /// with the leverages of the weighted Jacobian at the solution: χ² with ν =
  /// degrees_of_freedom (χ² = ν·variance_factor) and the outlier test (consistency.h). Each
  /// residual is named by its placement (source file, else name), file line, feature id and
  /// coordinate; a calibration residual by the plate file and feature. A caller must not use
  /// the model when !consistency.passed() unless it says so (the CLI refuses it, exit 3, or
  /// records it with --accept-inconsistent).
  ConsistencyTest consistency;
};

/// Estimates the kinematic errors (file comment; docs/characterization.md) from the plate and
/// its placements. Preconditions (InvalidInput naming the function, the placement/feature and
/// the value): ≥ 3 features, ids unique and non-empty, coordinates and u finite, u ≥ 0; ≥ 1
/// placement; in each placement ≥ 3 features, known ids, no id twice, finite coordinates and
/// stylus offset, every axis reading q = p − t within its axis range (slack 1e-4 of the span,
/// as errormodel); the features of each setup not collinear; options: chain valid, ranges
/// finite with min < max, degrees 0 … max_legendre_degree, σ finite > 0, tolerance in (0, 1),
/// a-priori u finite ≥ 0, max_iterations ≥ 1. A plan that leaves parameters unidentified is
/// not an error: they are reported (status, null_directions, message). Two placements with the
/// same ids and bit-identical centres are refused (one measurement given twice).
/// Accuracy: the least-squares solution to rounding. The first-order tip error is evaluated at
/// the true positions w of the starting poses rather than at the readings p = w + e (so that
/// invisible directions are exactly invisible): a model error of second order, |e|·|∇e| — e.g.
/// 1.3e-8 mm for a 4 µm scale error over 600 mm, below 0.1 nm for µm-size errors on a 1 m
/// machine — and ∇(A θ)·(µm the poses move while fitting) ~1e-11 mm.
/// Complexity: O(M·K²) per iteration for M observations and K unknowns (K = P + 6 setups +
/// 3 F), plus one SVD of the M×P projected design and one of a synthetic 24P-row design;
/// 16 features × 10 placements, 66 parameters: ~25 ms; 36 placements: ~85 ms (one core of the
/// 2-core Xeon here, Release).
KinematicCharacterization estimate_kinematic_errors(std::span<const HolePlatePlacement> placements,
                                                    const HolePlate& plate,
                                                    const HolePlateFitOptions& options);

/// The machine errors `parameters` (layout of result.model) expressed in the result's gauge:
/// moved along the null directions until every pivot is 0. Equal effect on every centre of the
/// plan (and, for intrinsic directions, on any rigid-artefact measurement); compare an
/// estimate with a known truth this way. Throws InvalidInput on a size mismatch or NaN.
Eigen::VectorXd express_in_gauge(const KinematicCharacterization& result,
                                 const Eigen::VectorXd& parameters);

// ---- the digital model's kinematics section and the report ---------------------------------

/// Any kinematic model as the "kinematics" section of the digital-model file (JSON text of the
/// object, docs/kinematics.md): chain, axis ranges, µm/µrad coefficients, uncertainties and the
/// per-function correlation taken from the model's covariance (correlation between different
/// functions cannot be written in this schema and is dropped). `comment` goes to "comment".
std::string kinematics_json(const errormodel::KinematicModel& model, std::string_view comment);

/// The estimated section (kinematics_json of result.model) with "source" = `source`, a
/// "comment" listing the gauge convention, the not-identifiable coefficients and the invisible
/// combinations, and a per-function "comment" naming its coefficients' status. Loadable by
/// errormodel::parse_digital_model when placed under "kinematics" in a model file. Throws
/// InvalidInput if !result.usable, if a number is not finite, or if a coefficient or its
/// uncertainty exceeds the physical range of a CMM's kinematic errors (1 mm, 1 mrad), naming
/// the parameter and `source`. The consistency verdict is part of the section comment.
std::string kinematics_json_section(const KinematicCharacterization& result,
                                    std::string_view source);

/// The diagnostics as JSON text (docs/characterization.md): status, message, counts, σ given
/// and from residuals, variance factor, per-parameter value/u/status (µm, µrad), null
/// directions, setup poses, per-placement residual RMS, the consistency test (χ², Birge ratio,
/// p, outliers; `accepted_inconsistent` records a failed test that the user overrode).
/// Throws InvalidInput if a number is not finite.
std::string hole_plate_report_json(const KinematicCharacterization& result,
                                   bool accepted_inconsistent = false);

// ---- files (docs/characterization.md, "File formats") --------------------------------------

/// Plate calibration CSV: optional `# format: vcmm.hole_plate 1`, `#` comments, the header
/// `id,x_mm,y_mm,z_mm,u_um`, one feature a line. Throws InvalidInput "source:line: ..." naming
/// the field: bad header, wrong field count, empty/duplicate id, non-finite or unparsable
/// number, negative u, fewer than 3 features.
HolePlate read_hole_plate_csv(std::istream& in, const std::string& source_name);
HolePlate read_hole_plate_csv_file(const std::string& path);
/// Writes the plate CSV (shortest round-trip doubles; u as the shortest µm text that the reader
/// turns back into the same calibration_u_mm); `comments` become `# ` lines.
std::string hole_plate_csv(const HolePlate& plate, std::span<const std::string> comments = {});

/// Placement CSV: metadata `# stylus_offset_mm: x, y, z` (required), `# setup: NAME` and
/// `# name: NAME` (optional; default name = source_name), optional `# format:
/// vcmm.hole_plate_placement 1`; header `id,x_mm,y_mm,z_mm`; one measured centre a line.
/// Throws InvalidInput "source:line: ..." (missing/duplicate metadata, a name or setup with a
/// carriage return inside, bad header, field count, unparsable or non-finite number, empty or
/// repeated id, no data).
HolePlatePlacement read_hole_plate_placement_csv(std::istream& in, const std::string& source_name);
HolePlatePlacement read_hole_plate_placement_csv_file(const std::string& path);
std::string hole_plate_placement_csv(const HolePlatePlacement& placement,
                                     std::span<const std::string> comments = {});

// ---- simulated calibration data --------------------------------------------------------------

/// One placement of a simulated measurement plan, with its true pose.
struct SimulatedPlacement {
  std::string name;
  std::string setup;  ///< placements of one setup must have the same true pose
  RigidPose true_pose;
  Eigen::Vector3d stylus_offset_mm = Eigen::Vector3d::Zero();
  std::vector<std::string> ids;  ///< features measured; empty = all, in plate order
};

struct SimulatedHolePlateData {
  std::vector<HolePlatePlacement> placements;
  Eigen::Matrix3Xd true_plate_mm;  ///< plate coordinates in effect (calibrated + drawn error)
};

/// What a CMM with kinematic errors `truth` (layout of `model`) reports when measuring the
/// plate in the given placements: true plate = calibrated + N(0, u_i²) per coordinate (one draw
/// for all placements, if `draw_calibration_errors`), true centres w = R c + T, reported
/// p = errormodel::measured_tip_positions(w) + N(0, σ²) per coordinate. Random numbers: one
/// fill_standard_normal call for the plate (3F), then one per placement (3n). Throws
/// InvalidInput for an unknown/duplicate id, a non-finite pose/offset/σ, σ < 0, setups with
/// different poses, readings outside the axis ranges. O(total centres).
SimulatedHolePlateData simulate_hole_plate_measurements(
    const errormodel::KinematicModel& model, const errormodel::KinematicErrors& truth,
    const HolePlate& plate, std::span<const SimulatedPlacement> plan, double probing_sigma_mm,
    errormodel::RandomSource& rng, errormodel::Formula formula = errormodel::Formula::exact,
    bool draw_calibration_errors = true);

/// A square n×n grid plate in its xy-plane (z = 0), pitch `pitch_mm`, origin at the centre,
/// ids "R<row>C<col>" (1-based), every coordinate with standard uncertainty `u_mm`. Throws
/// InvalidInput unless n ≥ 2, pitch finite > 0, u finite ≥ 0.
HolePlate grid_hole_plate(int n, double pitch_mm, double u_mm);

}  // namespace vcmm::characterization
