// Kinematic errors from a calibrated hole plate / ball plate measured in several placements.
//
// Sources
//  [ISO230-1]  ISO 230-1:2012, 3.4-3.5: the 18 error motions and 3 squareness errors.
//  [Zha85]     G. Zhang et al., "Error compensation of coordinate measuring machines", CIRP
//              Annals 34(1), 1985 — the 21-parameter rigid-body model (errormodel/).
//  [KTW90]     H. Kunzmann, E. Trapet, F. Wäldele, "A uniform concept for calibration,
//              acceptance test, and periodic inspection of coordinate measuring machines using
//              reference objects", CIRP Annals 39(1), 1990: the hole/ball plate measured in
//              several placements, its unknown pose per placement estimated with the machine's
//              parametric errors.
//  [Koc99]     K.-R. Koch, Parameter Estimation and Hypothesis Testing in Linear Models, 2nd
//              ed., Springer 1999: Gauss–Markov model, prior information as pseudo-
//              observations, the a-posteriori variance factor, estimable functions and the
//              datum (gauge) of a rank-deficient model.
//  The identifiability analysis, the synthetic plan for the intrinsic directions and the
//  pivot preference below are this file's own (tested in tests/characterization/).
//
// Notation
//  c_i       calibrated centre of feature i, plate frame (mm); u_i its standard uncertainty per
//            coordinate; δc_i the plate's true deviation from the calibration (unknown).
//  (R_s,T_s) pose of setup s, plate → machine; placement j belongs to setup s(j) and uses the
//            stylus offset t_j.
//  w_ij      = R_s (c_i + δc_i) + T_s, the true feature centre in machine coordinates.
//  p_ij      the centre the CMM reports (mm); σ the standard deviation of one coordinate of it.
//  θ         all kinematic parameters (P = Σ (d_f + 1) + 3), the layout of KinematicModel.
//  A_j(w)    3×P: e(w; θ, t_j) = A_j(w) θ, the first-order tip error (errormodel::tip_errors,
//            Formula::first_order, which is exactly linear in θ): column k is tip_errors of
//            the unit parameter vector e_k.
//
// Observation equations (Gauss–Markov with prior pseudo-observations, [Koc99]):
//      p_ij = w_ij + A_j(w_ij) θ + ε_ij,   ε_ij ~ N(0, σ² I)
//      0    = δc_i + η_i,                  η_i  ~ N(0, u_i² I)   (only features with u_i > 0)
// The calibration error enters every placement through the same δc_i, which is why it is an
// unknown with a prior rather than extra noise: its effect is correlated between placements.
// Linearisation about the current estimate, rotation increments left-multiplied
// (R ← Rot(δω) R):  ∂w/∂δω = −[R(c+δc)]×,  ∂w/∂T = I,  ∂w/∂δc = R,  ∂p/∂θ = A_j(w).
// A_j is evaluated once, at the closed-form starting poses (Kabsch/Horn's SVD fit of the
// calibrated to the measured centres, per setup): it depends on w only through the axis
// readings, and moving w by the µm the fit moves it changes A θ by ~1e-11 mm.
// Gauss–Newton: weighted rows (1/σ, 1/u_i), columns scaled to unit norm, Householder QR;
// stop when every scaled increment is < 1e-8 (the fit moves by < 1e-8 σ), normally after 2-3
// iterations since only the pose rotations are non-linear.
//
// Covariance. C = (JᵀJ)⁻¹ of the weighted Jacobian at the solution. The a-posteriori variance
// factor s0² = r̃ᵀr̃/(n − u) (r̃ the weighted residuals including the prior rows) tests the σ
// and u given: if s0² > 1 the covariance is multiplied by s0² (the data scatter more than
// claimed — a σ too small or an error the model does not have); if s0² ≤ 1 it is left as is
// (the given σ is the more reliable number for small n − u). Both σ and σ·s0 are reported.
//
// Identifiability ([Koc99], estimable functions). Let J_θ be the weighted design of θ and
// J_n that of the nuisance parameters (poses, δc with their prior rows). A change Δθ is
// invisible iff J_θ Δθ ∈ range(J_n), i.e. Δθ ∈ null((I − Π_n) J_θ). Columns of J_θ are
// scaled to unit norm (S = diag(1/‖J_θ e_k‖); θ = S θ̃), those of J_n too; Π_n from the QR of
// J_n; the SVD of (I − Π_n) J_θ S gives the null space as the right singular vectors whose
// singular value is ≤ rank_tolerance × the largest. Exactly invisible directions come out at
// rounding level because J_θ and J_n are evaluated at the same positions w; directions made
// invisible by a symmetry of the plan come out at ~1e-6 (the fitted positions break the
// symmetry by µm), which is why the default tolerance is 1e-3 (hole_plate.h).
// Which directions are *intrinsic* — invisible to any measurement of a rigid artefact of
// unknown pose, however rich — is found the same way on a synthetic plan: a cloud of
// Halton points filling the whole axis ranges (2P points), one rigid pose (rotation about one
// fixed point for all styli), measured with four styli (t = 0 and an offset along x, y and z:
// the effect is affine in t, so four styli span all). For a moving bridge these are 21: the 9
// translation constants c0 (a shift), 3 squareness–straightness-slope pairs
// (E_C0Y ~ E_XY c1, E_B0Z ~ E_XZ c1, E_A0Z ~ E_YZ c1), 3 rotations of the machine frame (e.g.
// E_BY c0 alone: Y carries everything, so its constant pitch turns the whole measurement) and 6
// pairings of constant rotations with each other and with straightness slopes (E_CX c0 ~
// E_CZ c0 + …: both act only through ε × t).
// These include the 9 translation constants c0 (a shift), constant rotations traded against
// straightness slopes (e.g. E_CY c0 against E_YX c1), squareness against straightness slopes
// (E_C0Y against E_XY c1) and a rotation of the machine frame.
//
// Gauge. Each invisible direction is pinned by fixing one pivot parameter at 0 (an inner
// constraint of the datum problem): pivots are chosen greedily along a preference order —
// translation c0; rotation c0; rotation c≥1; straightness c1; squareness; the rest (positioning
// c≥1, straightness c≥2) — a parameter becomes a pivot when the not-yet-pinned null directions
// move it by ≥ 0.05 (scaled, orthonormal basis: Σ_k row_k² = number of directions, so some
// row always exceeds 1/√P ≥ 0.07 and the greedy pass never stalls; 0.05 keeps badly
// conditioned pivots out). Intrinsic directions are pinned first. The null basis is then put
// in reduced echelon form on the pivots: direction i has 1 at pivot i and 0 at the other
// pivots, so the family of solutions is θ = θ̂ + Σ_i s_i n_i with s_i the (unknown) value of
// pivot i. Intrinsic pivots are 0 by convention (no measurement can tell); pivots of
// directions only this plan misses get the a-priori uncertainty U_i:  θ_free = θ̂_free + K s,
// s ~ N(0, diag U²) — so the model covariance is  [C + K U² Kᵀ, K U²; U² Kᵀ, U²].
#include "vcmm/characterization/hole_plate.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/Householder>
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "vcmm/errormodel/errors.h"

namespace vcmm::characterization {
namespace {

namespace em = vcmm::errormodel;
using em::InvalidInput;
using Eigen::Index;

// Readings may exceed an axis range by this fraction of the span (as errormodel: measured
// readings differ from the nominal ones by the error itself).
constexpr double kRangeSlack = 1e-4;
// Greedy pivot threshold (file comment).
constexpr double kPivotThreshold = 0.05;
// Gauss–Newton stop: the step moves no fitted value by more than this many σ — far below
// anything the estimate can resolve (its own standard uncertainty is ≥ σ/√M in these units).
constexpr double kStepTolerance = 1e-7;
// Collinearity: second singular value of the centred feature coordinates relative to the first.
// Features spread across the line by < 1e-6 of their extent are a line for any purpose (the
// pose rotation about it would be ~1e6 times less certain); nearer cases are caught by the rank
// check of the nuisance columns.
constexpr double kCollinear = 1e-6;

// A measured centre farther than this from the rigid fit of its setup is a blunder
// (check_gross_errors): the physical range of a CMM's kinematic errors.
constexpr double kGrossErrorMm = 1.0;

[[noreturn]] void fail(const std::string& msg) { throw InvalidInput(msg); }

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d m;
  m << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return m;
}

Eigen::Matrix3d rotation_from_vector(const Eigen::Vector3d& omega) {
  const double theta = omega.norm();
  if (theta == 0.0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(theta, omega / theta).toRotationMatrix();
}

bool is_finite(const Eigen::Vector3d& v) { return v.allFinite(); }

// ---- parameter names, units, preference ---------------------------------------------------

struct ParameterInfo {
  std::string name;
  bool rotation = false;
  int pivot_class = 0;  // preference to be fixed (0 first)
  int degree = 0;       // n of c_n (0 for squareness)
};

std::vector<ParameterInfo> parameter_info(const em::KinematicModel& layout) {
  std::vector<ParameterInfo> info(static_cast<std::size_t>(layout.parameter_count()));
  for (int f = 0; f < em::axis_error_count; ++f) {
    const auto e = static_cast<em::AxisError>(f);
    const int dir = em::direction_of(e);
    const bool rot = em::is_rotation(e);
    const bool straightness = !rot && dir != static_cast<int>(em::axis_of(e));
    for (int n = 0; n < layout.coefficient_count(e); ++n) {
      ParameterInfo& p = info[static_cast<std::size_t>(layout.parameter_offset(e) + n)];
      p.name = std::string(em::name(e)) + " c" + std::to_string(n);
      p.rotation = rot;
      p.degree = n;
      if (!rot) {
        p.pivot_class = n == 0 ? 0 : (straightness && n == 1) ? 3 : 5;
      } else {
        p.pivot_class = n == 0 ? 1 : 2;
      }
    }
  }
  for (int s = 0; s < em::squareness_count; ++s) {
    const auto sq = static_cast<em::Squareness>(s);
    ParameterInfo& p = info[static_cast<std::size_t>(layout.parameter_offset(sq))];
    p.name = std::string(em::name(sq));
    p.rotation = true;
    p.pivot_class = 4;
  }
  return info;
}

// µm or µrad in mm or rad: the JSON unit of a parameter.
double json_unit(const ParameterInfo& p) { return p.rotation ? 1e-6 : 1e-3; }

std::vector<Index> preference_order(const std::vector<ParameterInfo>& info) {
  std::vector<Index> order(info.size());
  std::iota(order.begin(), order.end(), Index{0});
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) {
    const auto& pa = info[static_cast<std::size_t>(a)];
    const auto& pb = info[static_cast<std::size_t>(b)];
    if (pa.pivot_class != pb.pivot_class) return pa.pivot_class < pb.pivot_class;
    return pa.degree < pb.degree;
  });
  return order;
}

// ---- validation ----------------------------------------------------------------------------

void validate_plate(const HolePlate& plate, const char* caller) {
  const std::string c(caller);
  const auto n = plate.ids.size();
  if (n < 3) fail(c + ": the plate needs at least 3 features; got " + std::to_string(n));
  if (static_cast<std::size_t>(plate.calibrated_mm.cols()) != n ||
      plate.calibration_u_mm.size() != n)
    fail(c + ": plate has " + std::to_string(n) + " ids, " +
         std::to_string(plate.calibrated_mm.cols()) + " calibrated centres and " +
         std::to_string(plate.calibration_u_mm.size()) + " uncertainties (must be equal)");
  std::map<std::string, std::size_t> seen;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string& id = plate.ids[i];
    if (id.empty()) fail(c + ": plate feature " + std::to_string(i) + " has an empty id");
    if (id.find_first_of(",#\r\n") != std::string::npos)
      fail(c + ": plate feature id '" + id + "' contains ',', '#' or a line break");
    if (const auto it = seen.find(id); it != seen.end())
      fail(c + ": plate feature id '" + id + "' appears twice (features " +
           std::to_string(it->second) + " and " + std::to_string(i) + ")");
    seen[id] = i;
    const Eigen::Vector3d x = plate.calibrated_mm.col(static_cast<Index>(i));
    if (!is_finite(x))
      fail(c + ": plate feature '" + id + "' has a non-finite calibrated coordinate (" +
           num(x.x()) + ", " + num(x.y()) + ", " + num(x.z()) + ")");
    const double u = plate.calibration_u_mm[i];
    if (!std::isfinite(u) || u < 0.0)
      fail(c + ": plate feature '" + id + "' calibration uncertainty must be finite and >= 0; got " +
           num(u));
  }
}

std::map<std::string, Index> id_index(const HolePlate& plate) {
  std::map<std::string, Index> m;
  for (std::size_t i = 0; i < plate.ids.size(); ++i) m[plate.ids[i]] = static_cast<Index>(i);
  return m;
}

void validate_ranges(const std::array<em::AxisRange, 3>& ranges, const char* caller) {
  for (int k = 0; k < 3; ++k) {
    const auto& r = ranges[static_cast<std::size_t>(k)];
    if (!std::isfinite(r.min) || !std::isfinite(r.max) || !(r.min < r.max))
      fail(std::string(caller) + ": axis range of " + std::string(em::name(static_cast<em::Axis>(k))) +
           " must be finite with min < max; got [" + num(r.min) + ", " + num(r.max) + "]");
  }
}

void check_readings(const std::array<em::AxisRange, 3>& ranges, const Eigen::Matrix3Xd& p,
                    const Eigen::Vector3d& t, const std::string& where,
                    const std::vector<std::string>& ids) {
  for (Index i = 0; i < p.cols(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const auto& r = ranges[static_cast<std::size_t>(k)];
      const double q = p(k, i) - t[k];
      const double slack = kRangeSlack * (r.max - r.min);
      if (!(q >= r.min - slack && q <= r.max + slack))
        fail(where + " feature '" + ids[static_cast<std::size_t>(i)] + "': the " +
             std::string(em::name(static_cast<em::Axis>(k))) + " axis reading " + num(q) +
             " mm (centre " + num(p(k, i)) + " - stylus offset " + num(t[k]) +
             ") lies outside the axis range [" + num(r.min) + ", " + num(r.max) + "] mm");
    }
  }
}

// ---- the design of θ ----------------------------------------------------------------------

// 3n × P: rows (x, y, z) per point; column k = first-order tip error of unit parameter k.
Eigen::MatrixXd kinematic_design(const em::KinematicModel& layout, const Eigen::Matrix3Xd& w,
                                 const Eigen::Vector3d& t) {
  const Index P = layout.parameter_count();
  const Index n = w.cols();
  Eigen::MatrixXd a(3 * n, P);
  Eigen::VectorXd unit = Eigen::VectorXd::Zero(P);
  Eigen::Matrix3Xd e(3, n);
  for (Index k = 0; k < P; ++k) {
    unit[k] = 1.0;
    const em::KinematicErrors errors(layout, unit);
    em::tip_errors(layout, errors, w, t, em::Formula::first_order, e);
    a.col(k) = Eigen::Map<const Eigen::VectorXd>(e.data(), 3 * n);
    unit[k] = 0.0;
  }
  return a;
}

// Null space of (I − Π_n) J_θ after unit column scaling (file comment).
struct ProjectedNullSpace {
  Eigen::VectorXd scale;     // θ = scale ∘ θ̃
  Eigen::MatrixXd basis;     // P × k, orthonormal, scaled coordinates
  double weakest_kept = 0.0; // smallest kept singular value / largest
  bool nuisance_full_rank = true;
};

Eigen::VectorXd unit_column_scale(const Eigen::MatrixXd& j) {
  Eigen::VectorXd s(j.cols());
  for (Index k = 0; k < j.cols(); ++k) {
    const double nrm = j.col(k).norm();
    s[k] = nrm > 0.0 ? 1.0 / nrm : 1.0;
  }
  return s;
}

ProjectedNullSpace projected_null_space(const Eigen::MatrixXd& j_theta,
                                        const Eigen::MatrixXd& j_nuisance, double tolerance) {
  ProjectedNullSpace out;
  out.scale = unit_column_scale(j_theta);
  const Eigen::MatrixXd jt = j_theta * out.scale.asDiagonal();
  const Index rows = jt.rows(), m = j_nuisance.cols();
  Eigen::MatrixXd bottom;
  if (m > 0) {
    const Eigen::MatrixXd jn = j_nuisance * unit_column_scale(j_nuisance).asDiagonal();
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(jn);
    const Eigen::MatrixXd r = qr.matrixQR().topRows(m).triangularView<Eigen::Upper>();
    const Eigen::VectorXd d = r.diagonal().cwiseAbs();
    // The nuisance columns are unit vectors: a pivot below 1e-10 means a pose or plate
    // correction the data do not fix (collinear features), not rounding.
    out.nuisance_full_rank = d.minCoeff() > 1e-10 * std::max(1.0, d.maxCoeff());
    const Eigen::MatrixXd qt = qr.householderQ().adjoint() * jt;
    bottom = qt.bottomRows(rows - m);
  } else {
    bottom = jt;
  }
  const Index P = jt.cols();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(bottom, Eigen::ComputeFullV);
  const Eigen::VectorXd sv = svd.singularValues();
  const double smax = sv.size() > 0 ? sv[0] : 0.0;
  std::vector<Index> null_cols;
  for (Index i = 0; i < P; ++i) {
    const double s = i < sv.size() ? sv[i] : 0.0;
    if (!(smax > 0.0) || s <= tolerance * smax) {
      null_cols.push_back(i);
    } else {
      out.weakest_kept = s / smax;
    }
  }
  out.basis.resize(P, static_cast<Index>(null_cols.size()));
  for (std::size_t c = 0; c < null_cols.size(); ++c)
    out.basis.col(static_cast<Index>(c)) = svd.matrixV().col(null_cols[c]);
  return out;
}

// Radical-inverse (Halton) sequence value of index i in `base`.
double halton(int i, int base) {
  double f = 1.0, r = 0.0;
  while (i > 0) {
    f /= base;
    r += f * (i % base);
    i /= base;
  }
  return r;
}

// Intrinsic invisible directions (file comment), physical coordinates, P × k_int.
Eigen::MatrixXd intrinsic_null_space(const em::KinematicModel& layout, double tolerance) {
  const Index P = layout.parameter_count();
  const int n = static_cast<int>(std::max<Index>(32, 2 * P));
  double span_min = 1e300;
  for (int k = 0; k < 3; ++k) {
    const auto& r = layout.range(static_cast<em::Axis>(k));
    span_min = std::min(span_min, r.max - r.min);
  }
  const double a = 0.25 * span_min;
  const std::array<Eigen::Vector3d, 4> styli = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(a, 0, 0),
                                                Eigen::Vector3d(0, a, 0), Eigen::Vector3d(0, 0, a)};
  Eigen::Matrix3Xd q(3, n);
  for (int i = 0; i < n; ++i) {
    const int bases[3] = {2, 3, 5};
    for (int k = 0; k < 3; ++k) {
      const auto& r = layout.range(static_cast<em::Axis>(k));
      q(k, i) = r.min + (r.max - r.min) * halton(i + 1, bases[k]);
    }
  }
  const Index rows = 3 * n * static_cast<Index>(styli.size());
  Eigen::MatrixXd jt(rows, P), jn(rows, 6);
  Index row = 0;
  // One rigid pose for all styli: rotation about one fixed point (the centre of the readings).
  const Eigen::Vector3d centre = q.rowwise().mean();
  for (const auto& t : styli) {
    const Eigen::Matrix3Xd p = q.colwise() + t;
    jt.middleRows(row, 3 * n) = kinematic_design(layout, p, t);
    for (int i = 0; i < n; ++i) {
      jn.block<3, 3>(row + 3 * i, 0) = -skew(p.col(i) - centre);
      jn.block<3, 3>(row + 3 * i, 3) = Eigen::Matrix3d::Identity();
    }
    row += 3 * n;
  }
  const ProjectedNullSpace ns = projected_null_space(jt, jn, tolerance);
  return ns.scale.asDiagonal() * ns.basis;
}

// Orthonormal basis of the column space of x (rank by singular values > 1e-8 of the largest:
// the intrinsic null vectors are independent by construction, the threshold only guards
// rounding).
Eigen::MatrixXd orthonormal_basis(const Eigen::MatrixXd& x) {
  if (x.cols() == 0) return Eigen::MatrixXd(x.rows(), 0);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(x, Eigen::ComputeThinU);
  const Eigen::VectorXd sv = svd.singularValues();
  Index r = 0;
  while (r < sv.size() && sv[r] > 1e-8 * sv[0]) ++r;
  return svd.matrixU().leftCols(r);
}

// Removes from the orthonormal basis b (P × k) the direction that moves row p; the remaining
// k − 1 columns are orthonormal, null directions still, and have 0 in row p.
void deflate(Eigen::MatrixXd& b, Index p) {
  const Eigen::MatrixXd v = b.row(p).transpose();
  const Eigen::HouseholderQR<Eigen::MatrixXd> h(v);
  const Eigen::MatrixXd q = h.householderQ();
  const Eigen::MatrixXd bq = b * q;
  b = bq.rightCols(b.cols() - 1);
}

// Greedy pivots along `order` (file comment). `b` is consumed.
std::vector<Index> choose_pivots(Eigen::MatrixXd b, const std::vector<Index>& order,
                                 const std::vector<Index>& already) {
  // The intrinsic pivots were chosen with rows ≥ kPivotThreshold in a sub-space of b: their
  // rows here are at least that large; 1e-6 only skips a pivot b cannot contain (a bug, reported
  // below as unpinned directions).
  for (Index p : already) {
    if (b.cols() == 0) break;
    if (b.row(p).norm() > 1e-6) deflate(b, p);
  }
  std::vector<Index> pivots;
  for (Index p : order) {
    if (b.cols() == 0) break;
    if (std::find(already.begin(), already.end(), p) != already.end()) continue;
    if (b.row(p).norm() >= kPivotThreshold) {
      pivots.push_back(p);
      deflate(b, p);
    }
  }
  if (b.cols() != 0)
    throw std::logic_error("estimate_kinematic_errors: pivot selection left " +
                           std::to_string(b.cols()) + " null directions unpinned");
  return pivots;
}

// ---- problem layout and Gauss–Newton -------------------------------------------------------

struct PlacementData {
  Index setup = 0;
  std::vector<Index> features;  // plate indices
  Eigen::Matrix3Xd measured;
  Eigen::Vector3d stylus;
  Index first_row = 0;  // first observation row
  Eigen::MatrixXd design;  // 3n × P kinematic design (unweighted)
};

struct State {
  Eigen::VectorXd theta;              // P
  std::vector<Eigen::Matrix3d> rotation;
  std::vector<Eigen::Vector3d> translation;
  Eigen::Matrix3Xd dc;                // 3 × F
};

struct Layout {
  const HolePlate* plate = nullptr;
  std::vector<PlacementData> placements;
  Index setups = 0;
  std::vector<Index> dc_column;  // per feature: first column of δc among the δc columns, or −1
  Index dc_features = 0;
  Index observation_rows = 0;
  double sigma = 0.0;
};

Eigen::Vector3d plate_point(const Layout& lay, const State& s, Index i) {
  return lay.plate->calibrated_mm.col(i) + s.dc.col(i);
}

// Weighted Jacobian (rows: observations then priors; columns: free θ, 6 per setup, 3 per δc)
// and weighted residual, at state s.
void assemble(const Layout& lay, const State& s, const std::vector<Index>& free_params,
              Eigen::MatrixXd& j, Eigen::VectorXd& r) {
  const Index nf = static_cast<Index>(free_params.size());
  const Index cols = nf + 6 * lay.setups + 3 * lay.dc_features;
  const Index rows = lay.observation_rows + 3 * lay.dc_features;
  j.setZero(rows, cols);
  r.setZero(rows);
  const double ws = 1.0 / lay.sigma;
  for (const PlacementData& pd : lay.placements) {
    const Eigen::Matrix3d& rot = s.rotation[static_cast<std::size_t>(pd.setup)];
    const Eigen::Vector3d& tr = s.translation[static_cast<std::size_t>(pd.setup)];
    const Index pose_col = nf + 6 * pd.setup;
    for (std::size_t a = 0; a < pd.features.size(); ++a) {
      const Index i = pd.features[a];
      const Index row = pd.first_row + 3 * static_cast<Index>(a);
      const Index drow = 3 * static_cast<Index>(a);
      const Eigen::Vector3d rc = rot * plate_point(lay, s, i);
      const Eigen::Vector3d pred =
          rc + tr + pd.design.middleRows(drow, 3) * s.theta;
      r.segment<3>(row) = ws * (pd.measured.col(static_cast<Index>(a)) - pred);
      for (Index c = 0; c < nf; ++c)
        j.block<3, 1>(row, c) = ws * pd.design.block<3, 1>(drow, free_params[static_cast<std::size_t>(c)]);
      j.block<3, 3>(row, pose_col) = -ws * skew(rc);
      j.block<3, 3>(row, pose_col + 3) = ws * Eigen::Matrix3d::Identity();
      const Index dcc = lay.dc_column[static_cast<std::size_t>(i)];
      if (dcc >= 0) j.block<3, 3>(row, nf + 6 * lay.setups + dcc) = ws * rot;
    }
  }
  const HolePlate& plate = *lay.plate;
  for (Index i = 0; i < plate.calibrated_mm.cols(); ++i) {
    const Index dcc = lay.dc_column[static_cast<std::size_t>(i)];
    if (dcc < 0) continue;
    const double wu = 1.0 / plate.calibration_u_mm[static_cast<std::size_t>(i)];
    const Index row = lay.observation_rows + dcc;
    j.block<3, 3>(row, nf + 6 * lay.setups + dcc) = wu * Eigen::Matrix3d::Identity();
    r.segment<3>(row) = -wu * s.dc.col(i);
  }
}

// Kabsch / Horn: the rotation and translation minimising Σ |p − (R c + T)|².
RigidPose rigid_fit(const Eigen::Matrix3Xd& c, const Eigen::Matrix3Xd& p) {
  const Eigen::Vector3d cm = c.rowwise().mean(), pm = p.rowwise().mean();
  const Eigen::Matrix3d h = (c.colwise() - cm) * (p.colwise() - pm).transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0) d(2, 2) = -1.0;
  RigidPose pose;
  pose.rotation = svd.matrixV() * d * svd.matrixU().transpose();
  pose.translation_mm = pm - pose.rotation * cm;
  return pose;
}

std::string placement_label(const HolePlatePlacement& pl, std::size_t j) {
  if (!pl.source.empty()) return pl.source;
  return pl.name.empty() ? std::to_string(j) : pl.name;
}

// "line 14, hole R3C2, y" (the line when the data came from a file).
std::string feature_label(const std::vector<std::size_t>& lines, std::size_t a,
                          const std::string& id, int coordinate, const char* what) {
  std::string s;
  if (a < lines.size()) s = "line " + std::to_string(lines[a]) + ", ";
  s += what;
  s += " ";
  s += id;
  s += ", ";
  s += "xyz"[coordinate];
  return s;
}

// The residuals of the weighted fit (rows of `assemble`: observations, then the calibration's
// pseudo-observations) against their stated uncertainties, with the leverages of `j`.
ConsistencyTest residual_consistency(const Layout& lay, std::span<const HolePlatePlacement> placements,
                                     const Eigen::MatrixXd& j, const Eigen::VectorXd& r, Index dof) {
  const Eigen::VectorXd h = leverages(j);
  std::vector<FitResidual> res(static_cast<std::size_t>(r.size()));
  for (std::size_t jj = 0; jj < lay.placements.size(); ++jj) {
    const PlacementData& pd = lay.placements[jj];
    const HolePlatePlacement& pl = placements[jj];
    const std::string group = placement_label(pl, jj);
    for (std::size_t a = 0; a < pd.features.size(); ++a) {
      for (int k = 0; k < 3; ++k) {
        const Index row = pd.first_row + 3 * static_cast<Index>(a) + k;
        FitResidual& f = res[static_cast<std::size_t>(row)];
        f.value = r[row] * lay.sigma;
        f.uncertainty = lay.sigma;
        f.leverage = h[row];
        f.group = group;
        f.where = feature_label(pl.lines, a, pl.ids[a], k, "hole");
      }
    }
  }
  const HolePlate& plate = *lay.plate;
  const std::string plate_group = plate.source.empty() ? "the plate calibration" : plate.source;
  for (Index i = 0; i < plate.calibrated_mm.cols(); ++i) {
    const Index dcc = lay.dc_column[static_cast<std::size_t>(i)];
    if (dcc < 0) continue;
    const double u = plate.calibration_u_mm[static_cast<std::size_t>(i)];
    for (int k = 0; k < 3; ++k) {
      const Index row = lay.observation_rows + dcc + k;
      FitResidual& f = res[static_cast<std::size_t>(row)];
      f.value = r[row] * u;
      f.uncertainty = u;
      f.leverage = h[row];
      f.group = plate_group;
      f.where = feature_label(plate.lines, static_cast<std::size_t>(i),
                              plate.ids[static_cast<std::size_t>(i)], k,
                              "calibrated centre of hole");
    }
  }
  return test_consistency(res, static_cast<double>(std::max<Index>(dof, 0)));
}

// Gross errors before the fit: every centre of setup s must lie within kGrossErrorMm of where
// the setup's rigid fit puts it. Kinematic errors beyond 1 mm are outside the physical range of
// a CMM (the kinematics section refuses them too), so a larger deviation is a blunder in a
// centre, a wrong '# setup:' label or stylus offset — named here, before the first-order model
// is evaluated at positions it does not describe.
void check_gross_errors(const Layout& lay, std::span<const HolePlatePlacement> placements, Index s,
                        const std::string& setup, const RigidPose& pose) {
  double worst = 0.0, worst_rms = 0.0;
  std::size_t worst_placement = 0, worst_feature = 0;
  std::string files;
  for (std::size_t jj = 0; jj < lay.placements.size(); ++jj) {
    const PlacementData& pd = lay.placements[jj];
    if (pd.setup != s) continue;
    files += (files.empty() ? "" : ", ") + placement_label(placements[jj], jj);
    double sum2 = 0.0, local_worst = 0.0;
    std::size_t local_feature = 0;
    for (std::size_t a = 0; a < pd.features.size(); ++a) {
      const Eigen::Vector3d d = pd.measured.col(static_cast<Index>(a)) -
                                (pose.rotation * lay.plate->calibrated_mm.col(pd.features[a]) +
                                 pose.translation_mm);
      sum2 += d.squaredNorm();
      if (d.norm() > local_worst) {
        local_worst = d.norm();
        local_feature = a;
      }
    }
    const double rms = std::sqrt(sum2 / static_cast<double>(pd.features.size()));
    if (rms > worst_rms || (rms == worst_rms && local_worst > worst)) {
      worst_rms = rms;
      worst = local_worst;
      worst_placement = jj;
      worst_feature = local_feature;
    }
  }
  if (!(worst > kGrossErrorMm)) return;
  const HolePlatePlacement& pl = placements[worst_placement];
  std::string at = "hole " + pl.ids[worst_feature];
  if (worst_feature < pl.lines.size()) at = "line " + std::to_string(pl.lines[worst_feature]) + ", " + at;
  fail("placement " + placement_label(pl, worst_placement) + " (setup '" + setup +
       "', with " + files + "): the measured centres do not fit one rigid position of the plate: "
       "RMS " + num(worst_rms) + " mm, largest " + num(worst) + " mm at " + at +
       "; a CMM's kinematic errors are below " + num(kGrossErrorMm) +
       " mm — a blunder in that centre (or in the plate's calibrated centre of that hole), a "
       "wrong '# setup:' label or a wrong stylus offset");
}

void validate_options(const HolePlateFitOptions& o) {
  const char* c = "estimate_kinematic_errors";
  try {
    o.chain.validate();
  } catch (const std::invalid_argument& ex) {
    fail(std::string(c) + ": invalid kinematic chain: " + ex.what());
  }
  validate_ranges(o.axis_ranges, c);
  for (int f = 0; f < em::axis_error_count; ++f) {
    const int d = o.degrees[static_cast<std::size_t>(f)];
    if (d < 0 || d > em::max_legendre_degree)
      fail(std::string(c) + ": degree of " + std::string(em::name(static_cast<em::AxisError>(f))) +
           " must be 0 to " + std::to_string(em::max_legendre_degree) + "; got " + std::to_string(d));
  }
  if (!std::isfinite(o.probing_sigma_mm) || !(o.probing_sigma_mm > 0.0))
    fail(std::string(c) + ": probing_sigma_mm must be finite and > 0; got " + num(o.probing_sigma_mm));
  if (!std::isfinite(o.rank_tolerance) || !(o.rank_tolerance > 0.0) || !(o.rank_tolerance < 1.0))
    fail(std::string(c) + ": rank_tolerance must lie in (0, 1); got " + num(o.rank_tolerance));
  if (!std::isfinite(o.unidentified_translation_u_mm) || o.unidentified_translation_u_mm < 0.0)
    fail(std::string(c) + ": unidentified_translation_u_mm must be finite and >= 0; got " +
         num(o.unidentified_translation_u_mm));
  if (!std::isfinite(o.unidentified_rotation_u_rad) || o.unidentified_rotation_u_rad < 0.0)
    fail(std::string(c) + ": unidentified_rotation_u_rad must be finite and >= 0; got " +
         num(o.unidentified_rotation_u_rad));
  if (o.max_iterations < 1)
    fail(std::string(c) + ": max_iterations must be >= 1; got " + std::to_string(o.max_iterations));
}

em::KinematicModel layout_model(const em::KinematicChain& chain,
                                const std::array<em::AxisRange, 3>& ranges,
                                const std::array<int, em::axis_error_count>& degrees) {
  std::array<em::ErrorFunctionEstimate, em::axis_error_count> fns;
  for (int f = 0; f < em::axis_error_count; ++f) {
    const auto n = static_cast<std::size_t>(degrees[static_cast<std::size_t>(f)] + 1);
    fns[static_cast<std::size_t>(f)].coefficients.assign(n, 0.0);
    fns[static_cast<std::size_t>(f)].standard_uncertainties.assign(n, 0.0);
  }
  return em::KinematicModel(chain, ranges, fns, {});
}

}  // namespace

// ---- small public helpers ------------------------------------------------------------------

RigidPose RigidPose::from_rotation_vector(const Eigen::Vector3d& omega_rad,
                                          const Eigen::Vector3d& translation_mm) {
  if (!is_finite(omega_rad) || !is_finite(translation_mm))
    fail("RigidPose::from_rotation_vector: rotation vector and translation must be finite");
  RigidPose p;
  p.rotation = rotation_from_vector(omega_rad);
  p.translation_mm = translation_mm;
  return p;
}

Eigen::Matrix3Xd RigidPose::apply(const Eigen::Matrix3Xd& plate_mm) const {
  return (rotation * plate_mm).colwise() + translation_mm;
}

std::array<int, em::axis_error_count> uniform_degrees(int degree) {
  std::array<int, em::axis_error_count> d{};
  d.fill(degree);
  return d;
}

std::array<int, em::axis_error_count> degrees_of(const em::KinematicModel& model) {
  std::array<int, em::axis_error_count> d{};
  for (int f = 0; f < em::axis_error_count; ++f)
    d[static_cast<std::size_t>(f)] = model.coefficient_count(static_cast<em::AxisError>(f)) - 1;
  return d;
}

std::string_view to_string(ParameterStatus status) {
  switch (status) {
    case ParameterStatus::identifiable: return "identifiable";
    case ParameterStatus::in_combination: return "in_combination";
    case ParameterStatus::by_convention: return "by_convention";
    case ParameterStatus::not_identifiable: return "not_identifiable";
  }
  return "?";
}

std::string_view to_string(HolePlateFitStatus status) {
  return status == HolePlateFitStatus::converged ? "converged" : "not_converged";
}

HolePlate grid_hole_plate(int n, double pitch_mm, double u_mm) {
  if (n < 2) fail("grid_hole_plate: n must be >= 2; got " + std::to_string(n));
  if (!std::isfinite(pitch_mm) || !(pitch_mm > 0.0))
    fail("grid_hole_plate: pitch must be finite and > 0; got " + num(pitch_mm));
  if (!std::isfinite(u_mm) || u_mm < 0.0)
    fail("grid_hole_plate: u must be finite and >= 0; got " + num(u_mm));
  HolePlate plate;
  plate.calibrated_mm.resize(3, n * n);
  const double half = 0.5 * (n - 1);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      std::string id = "R";  // appends: GCC 12 warns falsely (-Wrestrict) on "R" + string
      id += std::to_string(r + 1);
      id += 'C';
      id += std::to_string(c + 1);
      plate.ids.push_back(std::move(id));
      plate.calibrated_mm.col(r * n + c) =
          Eigen::Vector3d((c - half) * pitch_mm, (r - half) * pitch_mm, 0.0);
      plate.calibration_u_mm.push_back(u_mm);
    }
  }
  return plate;
}

// ---- estimation ----------------------------------------------------------------------------

KinematicCharacterization estimate_kinematic_errors(std::span<const HolePlatePlacement> placements,
                                                    const HolePlate& plate,
                                                    const HolePlateFitOptions& options) {
  const char* caller = "estimate_kinematic_errors";
  validate_options(options);
  validate_plate(plate, caller);
  if (placements.empty()) fail(std::string(caller) + ": no placements given");

  // 1. Placements: ids, setups, readings.
  const auto ids = id_index(plate);
  Layout lay;
  lay.plate = &plate;
  lay.sigma = options.probing_sigma_mm;
  std::vector<std::string> setup_names;
  std::map<std::string, Index> setup_of;
  Index row = 0;
  for (std::size_t j = 0; j < placements.size(); ++j) {
    const HolePlatePlacement& pl = placements[j];
    const std::string where = std::string(caller) + ": placement '" +
                              (pl.name.empty() ? std::to_string(j) : pl.name) + "'";
    const auto n = pl.ids.size();
    if (static_cast<std::size_t>(pl.measured_mm.cols()) != n)
      fail(where + ": " + std::to_string(n) + " ids but " + std::to_string(pl.measured_mm.cols()) +
           " measured centres");
    if (n < 3) fail(where + ": needs at least 3 measured features; got " + std::to_string(n));
    if (!is_finite(pl.stylus_offset_mm))
      fail(where + ": stylus offset must be finite");
    PlacementData pd;
    std::map<std::string, std::size_t> seen;
    for (std::size_t a = 0; a < n; ++a) {
      const std::string& id = pl.ids[a];
      const auto it = ids.find(id);
      if (it == ids.end()) fail(where + ": feature '" + id + "' is not on the plate");
      if (const auto s = seen.find(id); s != seen.end())
        fail(where + ": feature '" + id + "' measured twice (entries " + std::to_string(s->second) +
             " and " + std::to_string(a) + ")");
      seen[id] = a;
      const Eigen::Vector3d x = pl.measured_mm.col(static_cast<Index>(a));
      if (!is_finite(x))
        fail(where + ": feature '" + id + "' has a non-finite measured coordinate (" + num(x.x()) +
             ", " + num(x.y()) + ", " + num(x.z()) + ")");
      pd.features.push_back(it->second);
    }
    check_readings(options.axis_ranges, pl.measured_mm, pl.stylus_offset_mm, where, pl.ids);
    // A placement without a setup gets its own ("\x01" cannot occur in a setup name read from a file).
    std::string setup_key = pl.setup;
    if (setup_key.empty()) {
      setup_key = '\x01';
      setup_key += std::to_string(j);
    }
    if (const auto s = setup_of.find(setup_key); s != setup_of.end()) {
      pd.setup = s->second;
    } else {
      pd.setup = static_cast<Index>(setup_names.size());
      setup_of[setup_key] = pd.setup;
      setup_names.push_back(pl.setup.empty() ? (pl.name.empty() ? std::to_string(j) : pl.name)
                                             : pl.setup);
    }
    pd.measured = pl.measured_mm;
    pd.stylus = pl.stylus_offset_mm;
    pd.first_row = row;
    row += 3 * static_cast<Index>(n);
    lay.placements.push_back(std::move(pd));
  }
  lay.observation_rows = row;
  lay.setups = static_cast<Index>(setup_names.size());
  // One measurement given twice (a copied file) would look like a perfectly repeatable machine.
  for (std::size_t j = 0; j < placements.size(); ++j)
    for (std::size_t i = 0; i < j; ++i)
      if (placements[i].ids == placements[j].ids && placements[i].measured_mm == placements[j].measured_mm)
        fail(std::string(caller) + ": placements '" + placement_label(placements[i], i) + "' and '" +
             placement_label(placements[j], j) +
             "' hold identical measured centres: one measurement given twice");

  // 2. Starting poses: rigid fit per setup; collinearity check.
  const Index F = plate.calibrated_mm.cols();
  State state;
  state.dc = Eigen::Matrix3Xd::Zero(3, F);
  for (Index s = 0; s < lay.setups; ++s) {
    std::vector<Index> feats;
    std::vector<Eigen::Vector3d> cs, ps;
    for (const PlacementData& pd : lay.placements) {
      if (pd.setup != s) continue;
      for (std::size_t a = 0; a < pd.features.size(); ++a) {
        feats.push_back(pd.features[a]);
        cs.push_back(plate.calibrated_mm.col(pd.features[a]));
        ps.push_back(pd.measured.col(static_cast<Index>(a)));
      }
    }
    std::sort(feats.begin(), feats.end());
    feats.erase(std::unique(feats.begin(), feats.end()), feats.end());
    Eigen::Matrix3Xd cu(3, static_cast<Index>(feats.size()));
    for (std::size_t a = 0; a < feats.size(); ++a) cu.col(static_cast<Index>(a)) = plate.calibrated_mm.col(feats[a]);
    const Eigen::Matrix3Xd centred = cu.colwise() - cu.rowwise().mean();
    Eigen::Vector3d sv = Eigen::Vector3d::Zero();
    if (feats.size() >= 3) sv = Eigen::JacobiSVD<Eigen::MatrixXd>(centred).singularValues();
    if (feats.size() < 3 || !(sv[1] > kCollinear * sv[0]))
      fail(std::string(caller) + ": setup '" + setup_names[static_cast<std::size_t>(s)] +
           "': its " + std::to_string(feats.size()) +
           " measured features are collinear (singular values " + num(sv[0]) + ", " + num(sv[1]) +
           " mm): the plate's rotation about that line is undetermined");
    Eigen::Matrix3Xd cm(3, static_cast<Index>(cs.size())), pm(3, static_cast<Index>(ps.size()));
    for (std::size_t a = 0; a < cs.size(); ++a) {
      cm.col(static_cast<Index>(a)) = cs[a];
      pm.col(static_cast<Index>(a)) = ps[a];
    }
    const RigidPose pose = rigid_fit(cm, pm);
    check_gross_errors(lay, placements, s, setup_names[static_cast<std::size_t>(s)], pose);
    state.rotation.push_back(pose.rotation);
    state.translation.push_back(pose.translation_mm);
  }

  // 3. Kinematic design at the starting positions.
  const em::KinematicModel layout = layout_model(options.chain, options.axis_ranges, options.degrees);
  const Index P = layout.parameter_count();
  const auto info = parameter_info(layout);
  state.theta = Eigen::VectorXd::Zero(P);
  for (std::size_t j = 0; j < lay.placements.size(); ++j) {
    PlacementData& pd = lay.placements[j];
    Eigen::Matrix3Xd w(3, static_cast<Index>(pd.features.size()));
    for (std::size_t a = 0; a < pd.features.size(); ++a)
      w.col(static_cast<Index>(a)) = state.rotation[static_cast<std::size_t>(pd.setup)] *
                                         plate.calibrated_mm.col(pd.features[a]) +
                                     state.translation[static_cast<std::size_t>(pd.setup)];
    try {
      pd.design = kinematic_design(layout, w, pd.stylus);
    } catch (const std::invalid_argument& ex) {
      fail(std::string(caller) + ": placement '" + placements[j].name +
           "': the fitted feature positions leave the axis ranges (" + ex.what() + ")");
    }
  }
  lay.dc_column.assign(static_cast<std::size_t>(F), -1);
  for (Index i = 0; i < F; ++i) {
    if (plate.calibration_u_mm[static_cast<std::size_t>(i)] > 0.0) {
      lay.dc_column[static_cast<std::size_t>(i)] = 3 * lay.dc_features;
      ++lay.dc_features;
    }
  }

  // 4. Identifiability: null space of the plan, intrinsic part, pivots, echelon basis.
  std::vector<Index> all(static_cast<std::size_t>(P));
  std::iota(all.begin(), all.end(), Index{0});
  Eigen::MatrixXd jfull;
  Eigen::VectorXd rfull;
  assemble(lay, state, all, jfull, rfull);
  const ProjectedNullSpace plan =
      projected_null_space(jfull.leftCols(P), jfull.rightCols(jfull.cols() - P), options.rank_tolerance);
  if (!plan.nuisance_full_rank)
    fail(std::string(caller) + ": the plate poses are not determined by the measured features "
         "(nearly collinear features in a setup?)");
  const Eigen::MatrixXd intrinsic_phys = intrinsic_null_space(layout, options.rank_tolerance);
  Eigen::MatrixXd intrinsic_scaled = plan.scale.cwiseInverse().asDiagonal() * intrinsic_phys;
  intrinsic_scaled = orthonormal_basis(intrinsic_scaled);
  {
    const Eigen::MatrixXd outside =
        intrinsic_scaled - plan.basis * (plan.basis.transpose() * intrinsic_scaled);
    if (outside.size() > 0 && outside.norm() > 1e-6)
      throw std::logic_error("estimate_kinematic_errors: an intrinsic null direction is visible "
                             "in the plan (" + num(outside.norm()) + ")");
  }
  const auto order = preference_order(info);
  const std::vector<Index> pivots_int = choose_pivots(intrinsic_scaled, order, {});
  std::vector<Index> pivots = pivots_int;
  const std::vector<Index> pivots_lim = choose_pivots(plan.basis, order, pivots_int);
  pivots.insert(pivots.end(), pivots_lim.begin(), pivots_lim.end());
  const Index k = static_cast<Index>(pivots.size());
  // Echelon forms in scaled coordinates: column i has 1 at pivot i and 0 at the other pivots
  // of `piv`. Coefficients at or below the rank tolerance are below the resolution of the rank
  // decision (file comment) and are set to 0.
  auto echelon = [&](const Eigen::MatrixXd& basis, const std::vector<Index>& piv) {
    const auto m = static_cast<Index>(piv.size());
    Eigen::MatrixXd e(P, m);
    if (m == 0) return e;
    Eigen::MatrixXd g(m, m);
    for (Index i = 0; i < m; ++i) g.row(i) = basis.row(piv[static_cast<std::size_t>(i)]);
    e = (g.transpose().fullPivLu().solve(basis.transpose())).transpose();
    for (Index i = 0; i < m; ++i) {
      for (Index p = 0; p < P; ++p)
        if (std::abs(e(p, i)) <= options.rank_tolerance) e(p, i) = 0.0;
      for (Index q = 0; q < m; ++q) e(piv[static_cast<std::size_t>(q)], i) = q == i ? 1.0 : 0.0;
    }
    return e;
  };
  // The gauge: θ = θ̂ + Σ s_i n_i over all pivots (s_i = value of pivot i).
  const Eigen::MatrixXd echelon_scaled = echelon(plan.basis, pivots);
  // For display, an intrinsic direction is shown as the intrinsic basis alone in echelon form
  // (the full form may add multiples of directions only this plan misses).
  const Eigen::MatrixXd intrinsic_echelon = echelon(intrinsic_scaled, pivots_int);
  std::vector<char> is_pivot(static_cast<std::size_t>(P), 0);
  for (Index p : pivots) is_pivot[static_cast<std::size_t>(p)] = 1;
  std::vector<Index> free_params;
  for (Index p = 0; p < P; ++p)
    if (!is_pivot[static_cast<std::size_t>(p)]) free_params.push_back(p);
  const Index nf = static_cast<Index>(free_params.size());

  // 5. Gauss–Newton on (free θ, poses, δc).
  Eigen::MatrixXd j;
  Eigen::VectorXd r;
  int iterations = 0;
  bool converged = false;
  for (int it = 0; it < options.max_iterations; ++it) {
    assemble(lay, state, free_params, j, r);
    const Eigen::VectorXd scale = unit_column_scale(j);
    const Eigen::MatrixXd js = j * scale.asDiagonal();
    const Eigen::VectorXd y = Eigen::HouseholderQR<Eigen::MatrixXd>(js).solve(r);
    const Eigen::VectorXd step = scale.cwiseProduct(y);
    // Largest change of a fitted value (σ units): noise along weakly determined directions
    // moves y but not the fit, so the fit is what the stop criterion looks at.
    const double moved = (js * y).cwiseAbs().maxCoeff();
    for (Index c = 0; c < nf; ++c) state.theta[free_params[static_cast<std::size_t>(c)]] += step[c];
    for (Index s = 0; s < lay.setups; ++s) {
      const Eigen::Vector3d dw = step.segment<3>(nf + 6 * s);
      state.rotation[static_cast<std::size_t>(s)] =
          rotation_from_vector(dw) * state.rotation[static_cast<std::size_t>(s)];
      state.translation[static_cast<std::size_t>(s)] += step.segment<3>(nf + 6 * s + 3);
    }
    for (Index i = 0; i < F; ++i) {
      const Index dcc = lay.dc_column[static_cast<std::size_t>(i)];
      if (dcc >= 0) state.dc.col(i) += step.segment<3>(nf + 6 * lay.setups + dcc);
    }
    iterations = it + 1;
    if (!y.allFinite()) break;
    if (moved < kStepTolerance) {
      converged = true;
      break;
    }
  }

  // 6. Covariance at the solution.
  assemble(lay, state, free_params, j, r);
  const Index rows = j.rows(), cols = j.cols();
  const Index dof = rows - cols;
  const ConsistencyTest consistency = residual_consistency(lay, placements, j, r, dof);
  const double wss = r.squaredNorm();
  const double s02 = dof > 0 ? wss / static_cast<double>(dof) : 1.0;
  const Eigen::VectorXd cscale = unit_column_scale(j);
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(j * cscale.asDiagonal());
  const Eigen::MatrixXd rr = qr.matrixQR().topRows(cols).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd rinv =
      rr.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(cols, cols));
  const Eigen::MatrixXd cov_free_scaled = (rinv * rinv.transpose()).topLeftCorner(nf, nf);
  const double factor = s02 > 1.0 ? s02 : 1.0;
  Eigen::MatrixXd cov_free = factor * (cscale.head(nf).asDiagonal() * cov_free_scaled *
                                       cscale.head(nf).asDiagonal());
  cov_free = 0.5 * (cov_free + cov_free.transpose()).eval();

  Eigen::MatrixXd data_cov = Eigen::MatrixXd::Zero(P, P);
  for (Index a = 0; a < nf; ++a)
    for (Index b = 0; b < nf; ++b) data_cov(free_params[static_cast<std::size_t>(a)], free_params[static_cast<std::size_t>(b)]) = cov_free(a, b);

  // Null directions in physical units (pivot coefficient 1 in its own unit).
  std::vector<NullDirection> nulls;
  Eigen::MatrixXd direction_phys(P, k);
  for (Index i = 0; i < k; ++i) {
    const Index p = pivots[static_cast<std::size_t>(i)];
    direction_phys.col(i) = plan.scale.cwiseProduct(echelon_scaled.col(i)) / plan.scale[p];
    NullDirection nd;
    nd.pivot = p;
    nd.intrinsic = i < static_cast<Index>(pivots_int.size());
    nd.gauge_direction = direction_phys.col(i);
    const Eigen::VectorXd shown =
        nd.intrinsic ? Eigen::VectorXd(plan.scale.cwiseProduct(intrinsic_echelon.col(i)) / plan.scale[p])
                     : nd.gauge_direction;
    const double up = json_unit(info[static_cast<std::size_t>(p)]);
    nd.terms.emplace_back(p, 1.0);
    std::string text = info[static_cast<std::size_t>(p)].name;
    for (Index q = 0; q < P; ++q) {
      if (q == p || shown[q] == 0.0) continue;
      const double coef = shown[q] * up / json_unit(info[static_cast<std::size_t>(q)]);
      nd.terms.emplace_back(q, coef);
      text += (coef < 0.0 ? " - " : " + ") + num(std::abs(coef)) + "*" +
              info[static_cast<std::size_t>(q)].name;
    }
    nd.text = text;
    nulls.push_back(std::move(nd));
  }

  // Model covariance: data + a-priori u of the not-identifiable pivots through K.
  Eigen::MatrixXd model_cov = data_cov;
  for (std::size_t i = pivots_int.size(); i < pivots.size(); ++i) {
    const Index p = pivots[i];
    const double u = info[static_cast<std::size_t>(p)].rotation ? options.unidentified_rotation_u_rad
                                                                 : options.unidentified_translation_u_mm;
    const Eigen::VectorXd kcol = direction_phys.col(static_cast<Index>(i));  // 1 at p
    model_cov += (u * u) * kcol * kcol.transpose();
  }
  model_cov = 0.5 * (model_cov + model_cov.transpose()).eval();

  // 7. Parameters and the estimated model.
  std::vector<KinematicParameter> params(static_cast<std::size_t>(P));
  for (Index p = 0; p < P; ++p) {
    KinematicParameter& kp = params[static_cast<std::size_t>(p)];
    kp.name = info[static_cast<std::size_t>(p)].name;
    kp.rotation = info[static_cast<std::size_t>(p)].rotation;
    kp.value = state.theta[p];
    kp.standard_uncertainty = std::sqrt(std::max(0.0, model_cov(p, p)));
    if (is_pivot[static_cast<std::size_t>(p)]) {
      const auto pos = std::find(pivots.begin(), pivots.end(), p) - pivots.begin();
      kp.status = pos < static_cast<std::ptrdiff_t>(pivots_int.size()) ? ParameterStatus::by_convention
                                                                        : ParameterStatus::not_identifiable;
    } else {
      bool involved = false;
      for (Index i = 0; i < k; ++i) involved = involved || echelon_scaled(p, i) != 0.0;
      kp.status = involved ? ParameterStatus::in_combination : ParameterStatus::identifiable;
    }
  }
  std::array<em::ErrorFunctionEstimate, em::axis_error_count> fns;
  for (int f = 0; f < em::axis_error_count; ++f) {
    const auto e = static_cast<em::AxisError>(f);
    auto& fn = fns[static_cast<std::size_t>(f)];
    for (int n = 0; n < layout.coefficient_count(e); ++n) {
      const Index p = layout.parameter_offset(e) + n;
      fn.coefficients.push_back(state.theta[p]);
      fn.standard_uncertainties.push_back(params[static_cast<std::size_t>(p)].standard_uncertainty);
    }
  }
  std::array<em::EstimatedValue, em::squareness_count> sq{};
  for (int s = 0; s < em::squareness_count; ++s) {
    const Index p = layout.parameter_offset(static_cast<em::Squareness>(s));
    sq[static_cast<std::size_t>(s)] = {state.theta[p], params[static_cast<std::size_t>(p)].standard_uncertainty};
  }
  em::KinematicModel model(options.chain, options.axis_ranges, fns, sq);
  bool covariance_ok = true;
  std::string covariance_problem;
  try {
    model.set_covariance(model_cov);
  } catch (const std::invalid_argument& ex) {
    covariance_ok = false;
    covariance_problem = ex.what();
  }

  KinematicCharacterization result(std::move(model));
  result.status = converged ? HolePlateFitStatus::converged : HolePlateFitStatus::not_converged;
  result.data_covariance = std::move(data_cov);
  result.parameters = std::move(params);
  result.null_directions = std::move(nulls);
  result.plate_corrections_mm = state.dc;
  result.observations = rows;
  result.unknowns = cols;
  result.degrees_of_freedom = dof;
  result.variance_factor = s02;
  result.covariance_scaled = s02 > 1.0;
  result.probing_sigma_given_mm = options.probing_sigma_mm;
  result.probing_sigma_from_residuals_mm = options.probing_sigma_mm * std::sqrt(s02);
  result.weakest_direction = plan.weakest_kept;
  result.iterations = iterations;
  for (Index s = 0; s < lay.setups; ++s) {
    SetupPose sp;
    sp.setup = setup_names[static_cast<std::size_t>(s)];
    sp.pose.rotation = state.rotation[static_cast<std::size_t>(s)];
    sp.pose.translation_mm = state.translation[static_cast<std::size_t>(s)];
    result.setups.push_back(std::move(sp));
  }
  double sum2 = 0.0;
  for (std::size_t jj = 0; jj < lay.placements.size(); ++jj) {
    const PlacementData& pd = lay.placements[jj];
    PlacementResiduals pr;
    pr.name = placements[jj].name;
    const auto n = static_cast<Index>(pd.features.size());
    pr.residuals_mm = Eigen::Map<const Eigen::Matrix3Xd>(r.data() + pd.first_row, 3, n) * lay.sigma;
    pr.rms_mm = std::sqrt(pr.residuals_mm.squaredNorm() / static_cast<double>(3 * n));
    sum2 += pr.residuals_mm.squaredNorm();
    result.placements.push_back(std::move(pr));
  }
  result.residual_rms_mm = std::sqrt(sum2 / static_cast<double>(lay.observation_rows));

  int n_ident = 0, n_comb = 0, n_conv = 0, n_not = 0;
  for (const auto& p : result.parameters) {
    n_ident += p.status == ParameterStatus::identifiable;
    n_comb += p.status == ParameterStatus::in_combination;
    n_conv += p.status == ParameterStatus::by_convention;
    n_not += p.status == ParameterStatus::not_identifiable;
  }
  std::string msg = converged ? "converged in " : "NOT converged after ";
  msg += std::to_string(iterations);
  msg += " iterations; ";
  msg += std::to_string(P) + " parameters: " + std::to_string(n_ident) + " identifiable, " +
         std::to_string(n_comb) + " in combination, " + std::to_string(n_conv) +
         " fixed by convention, " + std::to_string(n_not) + " not identifiable from this plan";
  msg += "; residual RMS " + num(result.residual_rms_mm * 1e3) + " um, variance factor " +
         num(s02) + (dof > 0 ? "" : " (no redundancy: not estimated)") +
         (result.covariance_scaled ? " (covariance scaled by it)" : "");
  if (!covariance_ok) msg += "; covariance unusable: " + covariance_problem;
  msg += "; consistency: " + consistency.summary();
  result.consistency = consistency;
  result.message = msg;
  result.usable = converged && covariance_ok;
  return result;
}

Eigen::VectorXd express_in_gauge(const KinematicCharacterization& result,
                                 const Eigen::VectorXd& parameters) {
  const Index P = result.model.parameter_count();
  if (parameters.size() != P)
    fail("express_in_gauge: " + std::to_string(parameters.size()) + " parameters for a model with " +
         std::to_string(P));
  if (!parameters.allFinite()) fail("express_in_gauge: parameters must be finite");
  Eigen::VectorXd theta = parameters;
  // The echelon directions have 0 at every other pivot: subtracting each pivot's multiple
  // in turn zeroes all pivots.
  for (const NullDirection& nd : result.null_directions) {
    if (nd.gauge_direction.size() != P)
      fail("express_in_gauge: a null direction has " + std::to_string(nd.gauge_direction.size()) +
           " components for a model with " + std::to_string(P));
    theta -= theta[nd.pivot] * nd.gauge_direction;
  }
  return theta;
}

// ---- simulation ----------------------------------------------------------------------------

SimulatedHolePlateData simulate_hole_plate_measurements(
    const em::KinematicModel& model, const em::KinematicErrors& truth, const HolePlate& plate,
    std::span<const SimulatedPlacement> plan, double probing_sigma_mm, em::RandomSource& rng,
    em::Formula formula, bool draw_calibration_errors) {
  const std::string c = "simulate_hole_plate_measurements";
  validate_plate(plate, c.c_str());
  if (truth.parameters().size() != model.parameter_count())
    fail(c + ": the truth has " + std::to_string(truth.parameters().size()) +
         " parameters but the model " + std::to_string(model.parameter_count()));
  if (!std::isfinite(probing_sigma_mm) || probing_sigma_mm < 0.0)
    fail(c + ": probing sigma must be finite and >= 0; got " + num(probing_sigma_mm));
  const auto ids = id_index(plate);
  const Index F = plate.calibrated_mm.cols();
  SimulatedHolePlateData out;
  out.true_plate_mm = plate.calibrated_mm;
  if (draw_calibration_errors) {
    Eigen::Matrix3Xd z(3, F);
    rng.fill_standard_normal({z.data(), static_cast<std::size_t>(3 * F)});
    for (Index i = 0; i < F; ++i) out.true_plate_mm.col(i) += plate.calibration_u_mm[static_cast<std::size_t>(i)] * z.col(i);
  }
  std::map<std::string, const SimulatedPlacement*> setups;
  std::array<em::AxisRange, 3> ranges{};
  for (int k = 0; k < 3; ++k) ranges[static_cast<std::size_t>(k)] = model.range(static_cast<em::Axis>(k));
  for (std::size_t j = 0; j < plan.size(); ++j) {
    const SimulatedPlacement& sp = plan[j];
    const std::string where = c + ": placement '" + (sp.name.empty() ? std::to_string(j) : sp.name) + "'";
    if (!sp.true_pose.rotation.allFinite() || !is_finite(sp.true_pose.translation_mm) ||
        !is_finite(sp.stylus_offset_mm))
      fail(where + ": pose and stylus offset must be finite");
    if ((sp.true_pose.rotation.transpose() * sp.true_pose.rotation - Eigen::Matrix3d::Identity()).norm() > 1e-9 ||
        sp.true_pose.rotation.determinant() < 0.0)
      fail(where + ": the pose rotation is not a proper rotation matrix");
    if (!sp.setup.empty()) {
      if (const auto it = setups.find(sp.setup); it != setups.end()) {
        const RigidPose& a = it->second->true_pose;
        if ((a.rotation - sp.true_pose.rotation).norm() > 1e-12 ||
            (a.translation_mm - sp.true_pose.translation_mm).norm() > 1e-9)
          fail(where + ": setup '" + sp.setup + "' is used with two different poses");
      } else {
        setups[sp.setup] = &sp;
      }
    }
    HolePlatePlacement pl;
    pl.name = sp.name;
    pl.setup = sp.setup;
    pl.stylus_offset_mm = sp.stylus_offset_mm;
    std::vector<Index> feats;
    if (sp.ids.empty()) {
      pl.ids = plate.ids;
      for (Index i = 0; i < F; ++i) feats.push_back(i);
    } else {
      std::map<std::string, int> seen;
      for (const std::string& id : sp.ids) {
        const auto it = ids.find(id);
        if (it == ids.end()) fail(where + ": feature '" + id + "' is not on the plate");
        if (seen[id]++ > 0) fail(where + ": feature '" + id + "' listed twice");
        feats.push_back(it->second);
      }
      pl.ids = sp.ids;
    }
    const auto n = static_cast<Index>(feats.size());
    Eigen::Matrix3Xd w(3, n);
    for (Index a = 0; a < n; ++a)
      w.col(a) = sp.true_pose.rotation * out.true_plate_mm.col(feats[static_cast<std::size_t>(a)]) +
                 sp.true_pose.translation_mm;
    check_readings(ranges, w, sp.stylus_offset_mm, where, pl.ids);
    pl.measured_mm = em::measured_tip_positions(model, truth, w, sp.stylus_offset_mm, formula);
    Eigen::Matrix3Xd z(3, n);
    rng.fill_standard_normal({z.data(), static_cast<std::size_t>(3 * n)});
    pl.measured_mm += probing_sigma_mm * z;
    out.placements.push_back(std::move(pl));
  }
  return out;
}

}  // namespace vcmm::characterization
