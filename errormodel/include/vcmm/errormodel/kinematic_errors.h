// vcmm/errormodel/kinematic_errors.h — the 21 kinematic (rigid-body) errors of a 3-axis CMM
// and the error they cause at the probe tip, for any kinematic chain.
//
// Model (derivation, sources and conventions in errormodel/src/kinematic_errors.cpp and
// docs/kinematics.md):
//  - Each linear axis k ∈ {X, Y, Z} has six error motions (ISO 230-1:2012, 3.4): three
//    translations (positioning E_XX, straightness E_YX, E_ZX for X; and so on) and three
//    rotations (E_AX, E_BX, E_CX: about x, y, z — roll, pitch, yaw for X), each a function of
//    that axis' own reading q_k only. Plus three squareness errors E_C0Y, E_B0Z, E_A0Z.
//  - Error functions are Legendre series in the normalised position
//        u = (2 q − q_min − q_max) / (q_max − q_min) ∈ [−1, 1],   f(q) = Σ_n c_n P_n(u),
//    (orthogonal on the range: coefficients from a calibration are nearly uncorrelated and
//    well scaled — c_0 mean value, c_1 half the end-to-end linear change, c_2 bow — where a
//    power series in q (mm) would be badly conditioned).
//  - Units inside: translations in mm, rotations and squareness in rad. (JSON: µm and µrad.)
//  - Sign convention (ISO 230-1 / ISO 230-2: error = actual − nominal): every error motion is
//    the actual minus the nominal motion of the tool (probe) relative to the workpiece caused
//    by that axis; rotations right-handed about +x (A), +y (B), +z (C).
//    For an axis on the workpiece side (a moving table) the errors keep this relative sign,
//    but the rotation centre is fixed to the moving component (the table), not to the tool.
//  - Squareness (X is the reference axis): E_C0Y is the rotation about +z of Y's direction
//    of motion, E_B0Z and E_A0Z those of Z's direction about +y and +x:
//        actual Y direction = (−E_C0Y, 1, 0),  actual Z direction = (E_B0Z, −E_A0Z, 1)
//    to first order. So a positive E_C0Y = γ opens the angle between +X and +Y to 90° + γ,
//    and a true point at (0, y) is *measured* at x = +γ·y (tip error e_x = +γ·y).
//  - Machine coordinates: the CMM reports the tip centre p = q + t, where q = (q_x, q_y, q_z)
//    are the axis readings and t the stylus offset (tip centre relative to the ram reference
//    point). So each error function is evaluated at q_k = p_k − t_k. All carriage reference
//    points (rotation centres) coincide with the ram reference point at q = 0.
//  - The result is the tip error e = measured − true = −(actual − nominal tip position), mm.
//
// Accuracy: Formula::exact composes proper rotation matrices (rotation-vector / Rodrigues
// parametrisation), accumulated as a deviation from the nominal position, and is exact for
// the model to rounding (~1e-16 relative to the error itself); first_order drops the terms of
// second order in the errors (|e_exact − e_first| ≲ |ε|·|δ| + |ε|²·|arm|, ~1e-9 mm for
// µrad rotations and µm translations on a 1 m machine; the exact/first-order agreement to
// second order is tested by scaling).
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vcmm/errormodel/random_source.h"

namespace vcmm::errormodel {

/// A linear machine axis.
enum class Axis : std::uint8_t { x = 0, y = 1, z = 2 };

/// The 18 axis error motions, ISO 230-1 names: E_<direction><axis>. Direction X, Y, Z is a
/// translation along it (mm), A, B, C a rotation about x, y, z (rad). The enumerator value is
/// 6·axis + direction (direction 0..5 = X, Y, Z, A, B, C).
enum class AxisError : std::uint8_t {
  E_XX, E_YX, E_ZX, E_AX, E_BX, E_CX,  // of the X axis: positioning, straightness ×2, roll, pitch, yaw
  E_XY, E_YY, E_ZY, E_AY, E_BY, E_CY,  // of the Y axis: straightness, positioning, straightness, rotations
  E_XZ, E_YZ, E_ZZ, E_AZ, E_BZ, E_CZ,  // of the Z axis: straightness ×2, positioning, rotations
};
inline constexpr int axis_error_count = 18;

/// The three squareness errors (rad), X being the reference axis: E_C0Y (Y to X, about z),
/// E_B0Z (Z to X, about y), E_A0Z (Z to Y, about x). See the file comment for signs.
enum class Squareness : std::uint8_t { E_C0Y = 0, E_B0Z = 1, E_A0Z = 2 };
inline constexpr int squareness_count = 3;

/// Largest supported Legendre degree of an error function (the evaluation converts to the
/// power basis in u; at degree 10 that costs < 3 of the 16 significant digits).
inline constexpr int max_legendre_degree = 10;

constexpr Axis axis_of(AxisError e) { return static_cast<Axis>(static_cast<int>(e) / 6); }
/// 0..5 for direction X, Y, Z, A, B, C.
constexpr int direction_of(AxisError e) { return static_cast<int>(e) % 6; }
constexpr bool is_rotation(AxisError e) { return direction_of(e) >= 3; }
constexpr AxisError axis_error(Axis axis, int direction) {
  return static_cast<AxisError>(6 * static_cast<int>(axis) + direction);
}
/// "E_XX", …, "E_CZ"; "E_C0Y", "E_B0Z", "E_A0Z"; "X", "Y", "Z".
std::string_view name(AxisError e);
std::string_view name(Squareness s);
std::string_view name(Axis a);

/// The kinematic chain: which axes carry the probe (tool side) and which carry the workpiece,
/// each list in order from the machine base. Every axis appears exactly once in the union.
struct KinematicChain {
  std::vector<Axis> tool_side;
  std::vector<Axis> workpiece_side;

  /// Moving bridge (and gantry): base → Y → X → Z → stylus; workpiece on the base.
  static KinematicChain moving_bridge();
  /// Fixed bridge with moving table: base → X → Z → stylus; workpiece on the Y table.
  static KinematicChain fixed_bridge();
  /// Throws std::invalid_argument unless every axis appears exactly once.
  void validate() const;
  friend bool operator==(const KinematicChain&, const KinematicChain&) = default;
};

/// Travel of one axis (mm): the error functions are defined on [min, max], min < max.
struct AxisRange {
  double min = 0.0;
  double max = 0.0;
};

/// Estimated Legendre coefficients of one error function and their covariance.
struct ErrorFunctionEstimate {
  /// c_0 … c_d (mm for translations, rad for rotations), 1 ≤ size ≤ max_legendre_degree + 1.
  std::vector<double> coefficients;
  /// Standard uncertainties of the coefficients (same units), same size, each ≥ 0.
  std::vector<double> standard_uncertainties;
  /// Optional correlation matrix of the coefficients (symmetric, unit diagonal, positive
  /// definite on the coefficients with non-zero uncertainty); empty = uncorrelated.
  Eigen::MatrixXd correlation;
};

/// A scalar with its standard uncertainty (squareness: rad).
struct EstimatedValue {
  double value = 0.0;
  double standard_uncertainty = 0.0;
};

class KinematicErrors;

/// The digital model of the machine's kinematics: chain, axis ranges, and the joint
/// distribution (mean, covariance) of all error parameters.
///
/// Parameter vector layout (used by mean(), covariance() and KinematicErrors::parameters()):
/// the Legendre coefficients of the 18 functions in AxisError order, then E_C0Y, E_B0Z, E_A0Z.
class KinematicModel {
 public:
  /// Validates everything (throws std::invalid_argument naming the item, value and rule):
  /// chain; ranges finite with min < max; coefficient counts 1…max_legendre_degree+1; values
  /// finite; uncertainties finite and ≥ 0; correlation shape, symmetry, unit diagonal and
  /// positive definiteness. The covariance is block diagonal (no correlation between
  /// functions); replace it with set_covariance() for a joint covariance.
  KinematicModel(KinematicChain chain, const std::array<AxisRange, 3>& ranges,
                 const std::array<ErrorFunctionEstimate, axis_error_count>& functions,
                 const std::array<EstimatedValue, squareness_count>& squareness);

  /// A model with every error exactly zero (one coefficient per function, no uncertainty).
  /// Constant errors can then be set on nominal() with KinematicErrors::set_coefficients;
  /// higher degrees need the full constructor.
  static KinematicModel zero(KinematicChain chain, const std::array<AxisRange, 3>& ranges);

  const KinematicChain& chain() const { return chain_; }
  const AxisRange& range(Axis a) const { return ranges_[static_cast<int>(a)]; }
  /// Number of Legendre coefficients of `e` (degree + 1).
  int coefficient_count(AxisError e) const;
  /// Index of the first coefficient of `e` / of squareness `s` in the parameter vector.
  Eigen::Index parameter_offset(AxisError e) const;
  Eigen::Index parameter_offset(Squareness s) const;
  Eigen::Index parameter_count() const { return mean_.size(); }

  /// Estimated values (mm, rad) and joint covariance of all parameters.
  const Eigen::VectorXd& mean() const { return mean_; }
  const Eigen::MatrixXd& covariance() const { return covariance_; }
  /// Replaces the joint covariance (parameter_count² , symmetric, finite; positive definite
  /// on the parameters with non-zero variance; parameters with zero variance must have zero
  /// covariance with all others). Throws std::invalid_argument otherwise.
  void set_covariance(const Eigen::MatrixXd& covariance);

  /// The estimated errors: the known systematic part, which correction removes.
  KinematicErrors nominal() const;
  /// The model of the same machine when its estimated errors are NOT corrected but only taken
  /// into account in the uncertainty (the seed study's treatment of the kinematic errors):
  /// every parameter has estimate 0 and variance u_i² + m_i² (m_i its estimate), i.e. the
  /// uncorrected systematic error enters as a zero-mean quantity with the second moment of the
  /// error it leaves (GUM F.2.4.5 practice); covariances between parameters are kept. O(k³).
  KinematicModel uncorrected() const;
  /// A realisation drawn from N(mean, covariance): mean + L z, L the Cholesky factor of the
  /// covariance of the uncertain parameters, z from rng.fill_standard_normal (one bulk call,
  /// as many normals as parameters with non-zero variance). O(k²) for k such parameters.
  KinematicErrors draw(RandomSource& rng) const;
  /// As draw(), into `out` (reuses its storage: no allocation once sized).
  void draw(RandomSource& rng, KinematicErrors& out) const;

 private:
  KinematicModel() = default;
  void rebuild_layout(const std::array<int, axis_error_count>& counts);

  KinematicChain chain_;
  std::array<AxisRange, 3> ranges_{};
  std::array<Eigen::Index, axis_error_count + 1> offsets_{};  // offsets_[18] = squareness
  Eigen::VectorXd mean_;
  Eigen::MatrixXd covariance_;
  std::vector<Eigen::Index> uncertain_;  // parameters with non-zero variance
  Eigen::MatrixXd cholesky_;             // lower factor of covariance_[uncertain_, uncertain_]
  std::vector<Eigen::Index> column_end_;  // rows of cholesky_'s column j that draw() adds
};

/// One realisation of the kinematic errors: the parameter values actually in effect (mm,
/// rad), laid out as in the KinematicModel it came from (check: parameters().size() ==
/// model.parameter_count(); the evaluation functions throw otherwise).
class KinematicErrors {
 public:
  KinematicErrors() = default;
  /// Values for `model`'s layout. Throws std::invalid_argument on a size mismatch or NaN/inf.
  KinematicErrors(const KinematicModel& model, Eigen::VectorXd parameters);

  const Eigen::VectorXd& parameters() const { return parameters_; }
  /// The Legendre coefficients of error function `e` (mm or rad).
  std::span<const double> coefficients(const KinematicModel& model, AxisError e) const;
  /// Sets the coefficients of `e`; the count must equal model.coefficient_count(e).
  void set_coefficients(const KinematicModel& model, AxisError e, std::span<const double> c);
  double squareness(const KinematicModel& model, Squareness s) const;
  void set_squareness(const KinematicModel& model, Squareness s, double value_rad);
  /// Every parameter multiplied by s (for sensitivity and order-of-magnitude studies).
  KinematicErrors scaled(double s) const;

 private:
  friend class KinematicModel;
  Eigen::VectorXd parameters_;
};

/// Value of error function `e` at axis reading q (mm; within the axis range, else throws
/// std::invalid_argument): mm for translations, rad for rotations.
double error_function_value(const KinematicModel& model, const KinematicErrors& errors,
                            AxisError e, double q);

/// Which rigid-body formula to evaluate (file comment; docs/kinematics.md).
enum class Formula {
  first_order,  ///< e = −[Σ δ_k + Σ ε_k × r_k + squareness]: linear in the errors, fast
  exact,        ///< chain of proper rotation matrices (Rodrigues), slower
};

/// Tip errors e = measured − true (mm), one column per point, at the given *measured* tip
/// positions p (machine coordinates as the CMM reports them, mm) with stylus offset t (mm):
/// each error function is evaluated at its axis reading q_k = p_k − t_k. Exact for the
/// model given the readings (correction: true = p − e). Throws std::invalid_argument
/// (naming the point index and axis) if a coordinate is NaN/inf or a reading lies outside
/// its axis range, or if `errors` does not match `model`.
/// Complexity O(n·(max degree + 1)); first order, 3 600 points, cubic functions: ~18-25 µs on
/// one core of the 2.6 GHz Xeon here, SIMD (docs/performance.md); exact: ~380 µs. No per-point
/// allocation (the Eigen::Ref overloads copy only non-packed 3 × n input/output).
Eigen::Matrix3Xd tip_errors(const KinematicModel& model, const KinematicErrors& errors,
                            const Eigen::Ref<const Eigen::Matrix3Xd>& tip_positions,
                            const Eigen::Vector3d& stylus_offset,
                            Formula formula = Formula::first_order);
/// As above, writing into `out` (3 × n, preallocated by the caller; may not alias the input).
void tip_errors(const KinematicModel& model, const KinematicErrors& errors,
                const Eigen::Ref<const Eigen::Matrix3Xd>& tip_positions,
                const Eigen::Vector3d& stylus_offset, Formula formula,
                Eigen::Ref<Eigen::Matrix3Xd> out);

/// Simulation: the tip positions the CMM reports when its tip centre truly is at
/// `true_positions` (mm). Solves p = w + e(p) by fixed-point iteration from p = w (two
/// evaluations; the residual after them is ~|∇e|²·|e| < 1e-15 mm for µm/m-level errors).
Eigen::Matrix3Xd measured_tip_positions(const KinematicModel& model,
                                        const KinematicErrors& errors,
                                        const Eigen::Ref<const Eigen::Matrix3Xd>& true_positions,
                                        const Eigen::Vector3d& stylus_offset,
                                        Formula formula = Formula::first_order);

/// Correction: the true tip positions w = p − e(p) for measured positions p (exact for the
/// model). With errors = model.nominal() this removes the estimated systematic errors.
Eigen::Matrix3Xd true_tip_positions(const KinematicModel& model, const KinematicErrors& errors,
                                    const Eigen::Ref<const Eigen::Matrix3Xd>& measured_positions,
                                    const Eigen::Vector3d& stylus_offset,
                                    Formula formula = Formula::first_order);

}  // namespace vcmm::errormodel
