// The 21 kinematic errors of a 3-axis CMM and the rigid-body error at the probe tip.
//
// Sources
//  [ISO230-1] ISO 230-1:2012, Test code for machine tools — Part 1: Geometric accuracy of
//             machines operating under no-load or quasi-static conditions, 3.4 (error motions
//             E_XX … E_CZ of linear axes) and 3.5 (location/squareness errors E_C0Y, E_B0Z,
//             E_A0Z). [ISO230-2] ISO 230-2 (positioning deviation = actual − target).
//  [Zha85]    G. Zhang, R. Veale, T. Charlton, B. Borchardt, R. Hocken, "Error compensation of
//             coordinate measuring machines", CIRP Annals 34(1), 1985, 445–448: the
//             21-parameter rigid-body model of a 3-axis CMM, each error a function of its own
//             axis position, Abbe arms from the stylus offset.
//  [HP11]     R. J. Hocken, P. H. Pereira (eds.), Coordinate Measuring Machines and Systems,
//             2nd ed., CRC Press 2011 (kinematic error models and compensation of CMMs).
//  The chain formulas below are derived here from homogeneous transforms; they reduce to
//  the moving-bridge formula of [Zha85] (docs/kinematics.md has the same derivation).
//
// Notation
//  q = (q_x, q_y, q_z)   axis readings (mm); p = q + t the tip centre the CMM reports;
//  t                     stylus offset: tip centre relative to the ram reference point (mm);
//  a_k                   nominal direction of axis k (x̂, ŷ, ẑ); a'_k the actual direction:
//                        a'_X = x̂, a'_Y = Rot(E_C0Y ẑ) ŷ, a'_Z = Rot(E_A0Z x̂ + E_B0Z ŷ) ẑ;
//  δ_k(q_k) = (E_Xk, E_Yk, E_Zk)  translation error motion of axis k (mm);
//  ε_k(q_k) = (E_Ak, E_Bk, E_Ck)  rotation error motion of axis k (rad);
//  Rot(ω) = exp([ω]×)    the proper rotation with rotation vector ω (Rodrigues):
//                        I + (sin θ/θ)[ω]× + ((1 − cos θ)/θ²)[ω]×², θ = |ω|.
//  Every error is actual − nominal of the relative motion tool→workpiece produced by the
//  axis ([ISO230-2] sign), rotations right-handed.
//
// Chain. Tool-side axes T_1 … T_n (base → ram), workpiece-side axes W_1 … W_m (base →
// workpiece). A tool-side carriage k sits, relative to its parent, at
//      A_k(x) = q_k a'_k + δ_k + Rot(ε_k) x,
// i.e. it rotates about its own reference point, which moves with it; all reference points
// coincide with the ram reference point at q = 0 (another choice of reference point only
// re-distributes ε × offset into the straightness functions). A workpiece-side carriage k
// moves the workpiece by the inverse relative motion and rotates about a point fixed to
// itself (the table):  workpiece→parent map  x ↦ −(q_k a'_k + δ_k) + Rot(−ε_k) x, so a point
// x of the parent frame has table coordinates
//      B_k(x) = Rot(ε_k) (x + q_k a'_k + δ_k).
// The tip centre in workpiece coordinates is
//      w(q) = B_{W_m}( … B_{W_1}( A_{T_1}( … A_{T_n}(t) … ) ) … ),
// nominally (all errors zero) Σ q_k a_k + t = p. The volumetric error is v = w − p
// (actual − nominal tip position); the CMM reports p while the tip truly is at w, so the
// tip error (measured − true) is
//      e = p − w = −v                      (Formula::exact; exact given the readings).
//
// First order (drop products of errors; Rot(ω) x ≈ x + ω × x):
//      v = Σ_k δ_k + Σ_{tool i} ε_{T_i} × r_{T_i} + Σ_{wp i} ε_{W_i} × r_{W_i}
//          + q_y (−E_C0Y, 0, 0) + q_z (E_B0Z, −E_A0Z, 0),
//      r_{T_i} = t + Σ_{j > i} q_{T_j} a_{T_j}           (nominal tip relative to carriage T_i),
//      r_{W_i} = t + Σ_{tool} q a + Σ_{j ≤ i} q_{W_j} a_{W_j} (nominal tip relative to table W_i).
// Moving bridge (T = Y, X, Z; no W):  v = δ_Y + δ_X + δ_Z + ε_Y × (q_x x̂ + q_z ẑ + t)
//      + ε_X × (q_z ẑ + t) + ε_Z × t + squareness terms, as in [Zha85].
// Fixed bridge (T = X, Z; W = Y): the same except ε_Y × (q_x x̂ + q_y ŷ + q_z ẑ + t): the
// table's pitch and yaw act with the extra arm q_y ŷ along the axis itself; roll, positioning
// and straightness act identically (tested).
// exact − first order = O(|ε|·|δ| + |ε|²·|r|) (tested by scaling all errors by s: the
// difference falls like s²).
//
// Error functions: Legendre series f(q) = Σ c_n P_n(u), u = (2q − q_min − q_max)/(q_max − q_min).
// For speed each series is converted once per call to the power basis in u (Bonnet's
// recurrence (n+1)P_{n+1} = (2n+1) u P_n − n P_{n−1} on coefficient vectors) and evaluated by
// Horner's rule in a vectorised loop over points (no heap). For degree ≤ 10 the largest
// power-basis coefficient of any P_n is 46189/256 ≈ 180 (in P_10), so at most ~3 of the 16
// digits are lost: irrelevant at nm resolution on µm-size errors (tested against the
// recurrence to 1e-15 mm at degree 10).
#include "vcmm/errormodel/kinematic_errors.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "internal/first_order_kernel.h"

namespace vcmm::errormodel {
namespace {

constexpr int kMaxCoeffs = max_legendre_degree + 1;
constexpr int kMaxParameters = axis_error_count * kMaxCoeffs + squareness_count;

// Readings may lie outside an axis range by this fraction of the span: simulated readings
// differ from the true positions by the tip error itself (µm on a ≥ 100 mm axis, < 1e-4 of it),
// and a ring touching the end of travel must not be refused for that.
constexpr double kRangeSlack = 1e-4;

[[noreturn]] void fail(const std::string& msg) { throw std::invalid_argument(msg); }

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

// Power-basis coefficients of the Legendre polynomials P_0 … P_10 (row n, column j: u^j).
struct LegendreTable {
  double c[kMaxCoeffs][kMaxCoeffs] = {};
  LegendreTable() {
    c[0][0] = 1.0;
    c[1][1] = 1.0;
    for (int n = 1; n + 1 < kMaxCoeffs; ++n) {
      for (int j = 0; j < kMaxCoeffs; ++j) {
        const double up = j > 0 ? c[n][j - 1] : 0.0;
        c[n + 1][j] = ((2.0 * n + 1.0) * up - n * c[n - 1][j]) / (n + 1.0);
      }
    }
  }
};
const LegendreTable& legendre_table() {
  static const LegendreTable table;
  return table;
}

double legendre_series(std::span<const double> c, double u) {
  // Bonnet recurrence on the P_n values (a single point: no power-basis conversion).
  double p_prev = 1.0, p = u, sum = c[0];
  if (c.size() > 1) sum += c[1] * u;
  for (std::size_t n = 1; n + 1 < c.size(); ++n) {
    const double nd = static_cast<double>(n);
    const double p_next = ((2.0 * nd + 1.0) * u * p - nd * p_prev) / (nd + 1.0);
    p_prev = p;
    p = p_next;
    sum += c[n + 1] * p;
  }
  return sum;
}

Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d m;
  m << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return m;
}

// Rot(ω) − I = (sin θ/θ)[ω]× + ((1 − cos θ)/θ²)[ω]×², θ = |ω| (Rodrigues), with the
// cancellation-free 1 − cos θ = 2 sin²(θ/2). Kept apart from I so that the exact chain is
// accumulated as a deviation from the nominal position, with relative (not absolute) accuracy.
Eigen::Matrix3d rotation_minus_identity(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  if (theta == 0.0) return Eigen::Matrix3d::Zero();
  const Eigen::Matrix3d k = skew(w);
  const double a = std::sin(theta) / theta;
  const double h = std::sin(0.5 * theta) / theta;
  const double b = 2.0 * h * h;
  return a * k + b * k * k;
}

constexpr int kBlock = 64;
using BlockArray = Eigen::Array<double, kBlock, 1>;

void check_errors_match(const KinematicModel& model, const KinematicErrors& errors,
                        const char* caller) {
  if (errors.parameters().size() != model.parameter_count()) {
    fail(std::string(caller) + ": errors have " + std::to_string(errors.parameters().size()) +
         " parameters but the model has " + std::to_string(model.parameter_count()) +
         " (a KinematicErrors from another model?)");
  }
}

// Per-call preparation: power-basis coefficients in u and the affine map p_k → u_k.
struct Prepared {
  std::array<std::array<double, kMaxCoeffs>, axis_error_count> mono{};
  std::array<int, axis_error_count> degree{};
  std::array<double, 3> u_scale{};   // u = u_scale·q + u_offset, q = p − t
  std::array<double, 3> u_offset{};
  std::array<double, 3> q_mid{};     // mid-range reading (padding of a partial block)
  std::array<double, squareness_count> squareness{};
};

Prepared prepare(const KinematicModel& model, const KinematicErrors& errors) {
  const auto& table = legendre_table();
  Prepared pr;
  for (int f = 0; f < axis_error_count; ++f) {
    const auto e = static_cast<AxisError>(f);
    const auto c = errors.coefficients(model, e);
    const int d = static_cast<int>(c.size()) - 1;
    pr.degree[f] = d;
    for (int n = 0; n <= d; ++n) {
      for (int j = 0; j <= n; ++j) pr.mono[f][j] += c[n] * table.c[n][j];
    }
  }
  for (int k = 0; k < 3; ++k) {
    const AxisRange& r = model.range(static_cast<Axis>(k));
    const double span = r.max - r.min;
    pr.u_scale[k] = 2.0 / span;
    pr.u_offset[k] = -(r.min + r.max) / span;
    pr.q_mid[k] = 0.5 * (r.min + r.max);
  }
  for (int s = 0; s < squareness_count; ++s) {
    pr.squareness[s] = errors.squareness(model, static_cast<Squareness>(s));
  }
  return pr;
}

}  // namespace

[[noreturn]] void internal::report_bad_tip_position(const KinematicModel& model,
                                                    const Eigen::Ref<const Eigen::Matrix3Xd>& p,
                                                    const Eigen::Vector3d& stylus,
                                                    const char* caller) {
  for (Eigen::Index i = 0; i < p.cols(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const double v = p(k, i);
      if (!std::isfinite(v)) {
        fail(std::string(caller) + ": point " + std::to_string(i) + " has a non-finite " +
             std::string(1, "xyz"[k]) + " coordinate (" + fmt(v) + ")");
      }
      const AxisRange& r = model.range(static_cast<Axis>(k));
      const double q = v - stylus[k];
      const double slack = kRangeSlack * (r.max - r.min);
      if (!(q >= r.min - slack && q <= r.max + slack)) {
        fail(std::string(caller) + ": point " + std::to_string(i) + " needs the " +
             std::string(name(static_cast<Axis>(k))) + " axis at q = " + fmt(q) +
             " mm (tip " + fmt(v) + " − stylus offset " + fmt(stylus[k]) +
             "), outside the axis range [" + fmt(r.min) + ", " + fmt(r.max) + "] mm");
      }
    }
  }
  fail(std::string(caller) + ": invalid point (not located)");
}

namespace {

// ---- first-order kernel ---------------------------------------------------------------------
//
// The per-point formula is internal::first_order_error (internal/first_order_kernel.h), shared
// with the fused trial's one-pass kernel. All functions are padded to a common degree D (a
// template parameter: Horner fully unrolled) and the loop over points is vectorised by the
// compiler. Built three times (target_clones: AVX-512, AVX2 and baseline x86-64 on GCC/ELF),
// the clone chosen at load time; without FMA contraction (-ffp-contract=off, the
// top-level CMakeLists.txt) all three round identically: results are bit-reproducible across
// CPUs.
using internal::FirstOrderKernel;

template <int D>
[[gnu::always_inline]] inline Eigen::Index first_order_points(const FirstOrderKernel& k,
                                                              const double* __restrict p,
                                                              double* __restrict out,
                                                              Eigen::Index n) {
  Eigen::Index bad = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    bad += internal::first_order_error<D, true>(k, p[3 * i], p[3 * i + 1], p[3 * i + 2],
                                                out[3 * i], out[3 * i + 1], out[3 * i + 2]);
  }
  return bad;
}

// Returns the number of points with a reading out of range or non-finite.
VCMM_SIMD_CLONES Eigen::Index first_order_dispatch(const FirstOrderKernel& k, const double* p,
                                                   double* out, Eigen::Index n, int degree) {
  switch (degree) {
    case 0: return first_order_points<0>(k, p, out, n);
    case 1: return first_order_points<1>(k, p, out, n);
    case 2: return first_order_points<2>(k, p, out, n);
    case 3: return first_order_points<3>(k, p, out, n);
    case 4: return first_order_points<4>(k, p, out, n);
    case 5: return first_order_points<5>(k, p, out, n);
    case 6: return first_order_points<6>(k, p, out, n);
    case 7: return first_order_points<7>(k, p, out, n);
    case 8: return first_order_points<8>(k, p, out, n);
    case 9: return first_order_points<9>(k, p, out, n);
    default: return first_order_points<10>(k, p, out, n);
  }
}
static_assert(max_legendre_degree == 10, "extend first_order_dispatch");

FirstOrderKernel kernel_of(const KinematicModel& model, const Prepared& pr,
                           const Eigen::Vector3d& t) {
  FirstOrderKernel k;
  for (int f = 0; f < axis_error_count; ++f) {
    k.degree = std::max(k.degree, pr.degree[f]);
    if (is_rotation(static_cast<AxisError>(f)))
      k.rotation_degree = std::max(k.rotation_degree, pr.degree[f]);
    for (int j = 0; j <= pr.degree[f]; ++j) k.mono[f][j] = pr.mono[f][j];
  }
  for (int a = 0; a < 3; ++a) {
    k.u_scale[a] = pr.u_scale[a];
    k.u_offset[a] = pr.u_offset[a];
    k.t[a] = t[a];
  }
  const KinematicChain& chain = model.chain();
  const auto nt = chain.tool_side.size();
  for (std::size_t i = 0; i < nt; ++i) {
    const int a = static_cast<int>(chain.tool_side[i]);
    for (std::size_t j = i + 1; j < nt; ++j) k.arm_mask[a][static_cast<int>(chain.tool_side[j])] = 1.0;
  }
  for (std::size_t i = 0; i < chain.workpiece_side.size(); ++i) {
    const int a = static_cast<int>(chain.workpiece_side[i]);
    for (Axis b : chain.tool_side) k.arm_mask[a][static_cast<int>(b)] = 1.0;
    for (std::size_t j = 0; j <= i; ++j) {
      k.arm_mask[a][static_cast<int>(chain.workpiece_side[j])] = 1.0;
    }
  }
  // Constant arm masks give the same bits unless a stylus component is −0 (first_order_kernel.h).
  const auto negative_zero = [](double v) { return v == 0.0 && std::signbit(v); };
  if (!negative_zero(t[0]) && !negative_zero(t[1]) && !negative_zero(t[2])) {
    for (const auto p : {internal::ArmPattern::moving_bridge, internal::ArmPattern::fixed_bridge}) {
      bool same = true;
      for (int a = 0; a < 3; ++a) {
        for (int j = 0; j < 3; ++j)
          same = same && k.arm_mask[a][j] == (internal::arm_mask_of(p, a, j) ? 1.0 : 0.0);
      }
      if (same) k.arm_pattern = p;
    }
  }
  k.c0y = pr.squareness[0];
  k.b0z = pr.squareness[1];
  k.a0z = pr.squareness[2];
  const double u_limit = 1.0 + 2.0 * kRangeSlack;
  k.limit2 = u_limit * u_limit;
  return k;
}

void check_stylus(const Eigen::Vector3d& t, const char* caller) {
  if (!t.allFinite()) {
    fail(std::string(caller) + ": stylus offset must be finite; got (" + fmt(t.x()) + ", " +
         fmt(t.y()) + ", " + fmt(t.z()) + ")");
  }
}

void evaluate_first_order(const KinematicModel& model, const Prepared& pr,
                          const Eigen::Ref<const Eigen::Matrix3Xd>& p, const Eigen::Vector3d& t,
                          Eigen::Ref<Eigen::Matrix3Xd> out, const char* caller) {
  const FirstOrderKernel k = kernel_of(model, pr, t);
  const int degree = k.degree;
  const Eigen::Index n = p.cols();
  // The kernel wants packed 3 × n storage (outer stride 3); copy otherwise (rare).
  const bool packed_in = p.outerStride() == 3 || n <= 1;
  const bool packed_out = out.outerStride() == 3 || n <= 1;
  Eigen::Matrix3Xd in_copy, out_copy;
  if (!packed_in) in_copy = p;
  if (!packed_out) out_copy.resize(3, n);
  const double* pin = packed_in ? p.data() : in_copy.data();
  double* pout = packed_out ? out.data() : out_copy.data();
  if (first_order_dispatch(k, pin, pout, n, degree) != 0) internal::report_bad_tip_position(model, p, t, caller);
  if (!packed_out) out = out_copy;
}

void evaluate(const KinematicModel& model, const KinematicErrors& errors,
              const Eigen::Ref<const Eigen::Matrix3Xd>& p, const Eigen::Vector3d& t,
              Formula formula, Eigen::Ref<Eigen::Matrix3Xd> out, const char* caller) {
  check_errors_match(model, errors, caller);
  check_stylus(t, caller);
  if (out.cols() != p.cols()) {
    fail(std::string(caller) + ": output has " + std::to_string(out.cols()) +
         " columns for " + std::to_string(p.cols()) + " points");
  }
  const Prepared pr = prepare(model, errors);
  if (formula == Formula::first_order) {
    evaluate_first_order(model, pr, p, t, out, caller);
    return;
  }
  // Exact chain: error functions over blocks of points (Eigen arrays), then the chain of
  // rotations point by point.
  const KinematicChain& chain = model.chain();
  const double u_limit = 1.0 + 2.0 * kRangeSlack;
  const Eigen::Index n = p.cols();
  BlockArray u[3], q[3], val[axis_error_count];
  // Deviation form: x = x_nom + d, a'_k = a_k + da_k (see the file comment):
  //   tool side:      d ← d + q da + δ + (Rot(ε) − I)(x_nom + d),   x_nom ← x_nom + q a
  //   workpiece side: x_nom ← x_nom + q a,  d ← d + q da + δ,  d ← d + (Rot(ε) − I)(x_nom + d)
  const Eigen::Vector3d da[3] = {
      Eigen::Vector3d::Zero(),
      rotation_minus_identity(Eigen::Vector3d(0.0, 0.0, pr.squareness[0])) *
          Eigen::Vector3d::UnitY(),
      rotation_minus_identity(Eigen::Vector3d(pr.squareness[2], pr.squareness[1], 0.0)) *
          Eigen::Vector3d::UnitZ()};
  for (Eigen::Index start = 0; start < n; start += kBlock) {
    const int m = static_cast<int>(std::min<Eigen::Index>(kBlock, n - start));
    for (int k = 0; k < 3; ++k) {
      for (int i = 0; i < m; ++i) q[k][i] = p(k, start + i) - t[k];
      for (int i = m; i < kBlock; ++i) q[k][i] = pr.q_mid[k];  // padding, never written out
      u[k] = q[k] * pr.u_scale[k] + pr.u_offset[k];
      // Finite and in range: NaN fails the comparison, inf exceeds the limit.
      if (!(u[k].abs().maxCoeff() <= u_limit) || !((u[k] * 0.0).sum() == 0.0)) {
        internal::report_bad_tip_position(model, p, t, caller);
      }
    }
    for (int f = 0; f < axis_error_count; ++f) {
      const int k = f / 6;
      const auto& c = pr.mono[f];
      const int d = pr.degree[f];
      BlockArray acc = BlockArray::Constant(c[d]);
      for (int j = d - 1; j >= 0; --j) acc = acc * u[k] + c[j];
      val[f] = acc;
    }
    for (int i = 0; i < m; ++i) {
      auto delta = [&](int k) {
        return Eigen::Vector3d(val[6 * k][i], val[6 * k + 1][i], val[6 * k + 2][i]);
      };
      auto eps = [&](int k) {
        return Eigen::Vector3d(val[6 * k + 3][i], val[6 * k + 4][i], val[6 * k + 5][i]);
      };
      Eigen::Vector3d x_nom = t;
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      for (auto it = chain.tool_side.rbegin(); it != chain.tool_side.rend(); ++it) {
        const int k = static_cast<int>(*it);
        d += q[k][i] * da[k] + delta(k) + rotation_minus_identity(eps(k)) * (x_nom + d);
        x_nom[k] += q[k][i];
      }
      for (Axis a : chain.workpiece_side) {
        const int k = static_cast<int>(a);
        x_nom[k] += q[k][i];
        d += q[k][i] * da[k] + delta(k);
        d += rotation_minus_identity(eps(k)) * (x_nom + d);
      }
      out.col(start + i) = -d;  // e = p − w = −(x − x_nom), x_nom = q + t = p
    }
  }
}

}  // namespace

internal::FirstOrderKernel internal::first_order_kernel(const KinematicModel& model,
                                                        const KinematicErrors& errors,
                                                        const Eigen::Vector3d& t,
                                                        const char* caller) {
  check_errors_match(model, errors, caller);
  check_stylus(t, caller);
  return kernel_of(model, prepare(model, errors), t);
}

// ---- names ---------------------------------------------------------------------------------

std::string_view name(AxisError e) {
  static constexpr std::string_view names[axis_error_count] = {
      "E_XX", "E_YX", "E_ZX", "E_AX", "E_BX", "E_CX", "E_XY", "E_YY", "E_ZY",
      "E_AY", "E_BY", "E_CY", "E_XZ", "E_YZ", "E_ZZ", "E_AZ", "E_BZ", "E_CZ"};
  return names[static_cast<int>(e)];
}
std::string_view name(Squareness s) {
  static constexpr std::string_view names[squareness_count] = {"E_C0Y", "E_B0Z", "E_A0Z"};
  return names[static_cast<int>(s)];
}
std::string_view name(Axis a) {
  static constexpr std::string_view names[3] = {"X", "Y", "Z"};
  return names[static_cast<int>(a)];
}

// ---- chain ---------------------------------------------------------------------------------

KinematicChain KinematicChain::moving_bridge() { return {{Axis::y, Axis::x, Axis::z}, {}}; }
KinematicChain KinematicChain::fixed_bridge() { return {{Axis::x, Axis::z}, {Axis::y}}; }

void KinematicChain::validate() const {
  int seen[3] = {0, 0, 0};
  for (Axis a : tool_side) ++seen[static_cast<int>(a) % 3];
  for (Axis a : workpiece_side) ++seen[static_cast<int>(a) % 3];
  for (Axis a : tool_side) {
    if (static_cast<int>(a) > 2) fail("KinematicChain: invalid axis value in tool_side");
  }
  for (Axis a : workpiece_side) {
    if (static_cast<int>(a) > 2) fail("KinematicChain: invalid axis value in workpiece_side");
  }
  for (int k = 0; k < 3; ++k) {
    if (seen[k] != 1) {
      fail("KinematicChain: every axis must appear exactly once in tool_side + "
           "workpiece_side; axis " +
           std::string(name(static_cast<Axis>(k))) + " appears " + std::to_string(seen[k]) +
           " times");
    }
  }
}

// ---- model ---------------------------------------------------------------------------------

void KinematicModel::rebuild_layout(const std::array<int, axis_error_count>& counts) {
  Eigen::Index off = 0;
  for (int f = 0; f < axis_error_count; ++f) {
    offsets_[f] = off;
    off += counts[f];
  }
  offsets_[axis_error_count] = off;
  mean_ = Eigen::VectorXd::Zero(off + squareness_count);
  covariance_ = Eigen::MatrixXd::Zero(off + squareness_count, off + squareness_count);
}

KinematicModel::KinematicModel(KinematicChain chain, const std::array<AxisRange, 3>& ranges,
                               const std::array<ErrorFunctionEstimate, axis_error_count>& functions,
                               const std::array<EstimatedValue, squareness_count>& squareness)
    : chain_(std::move(chain)), ranges_(ranges) {
  const std::string where = "KinematicModel: ";
  chain_.validate();
  for (int k = 0; k < 3; ++k) {
    const AxisRange& r = ranges_[k];
    if (!std::isfinite(r.min) || !std::isfinite(r.max) || !(r.min < r.max)) {
      fail(where + "range of axis " + std::string(name(static_cast<Axis>(k))) +
           " must be finite with min < max; got [" + fmt(r.min) + ", " + fmt(r.max) + "]");
    }
  }
  std::array<int, axis_error_count> counts{};
  for (int f = 0; f < axis_error_count; ++f) {
    const ErrorFunctionEstimate& fn = functions[f];
    const std::string fname = where + std::string(name(static_cast<AxisError>(f)));
    const auto nc = fn.coefficients.size();
    if (nc < 1 || nc > static_cast<std::size_t>(kMaxCoeffs)) {
      fail(fname + ": needs 1 to " + std::to_string(kMaxCoeffs) +
           " Legendre coefficients; got " + std::to_string(nc));
    }
    if (fn.standard_uncertainties.size() != nc) {
      fail(fname + ": " + std::to_string(fn.standard_uncertainties.size()) +
           " standard uncertainties for " + std::to_string(nc) + " coefficients");
    }
    for (std::size_t j = 0; j < nc; ++j) {
      if (!std::isfinite(fn.coefficients[j])) {
        fail(fname + ": coefficient " + std::to_string(j) + " must be finite; got " +
             fmt(fn.coefficients[j]));
      }
      const double uj = fn.standard_uncertainties[j];
      if (!std::isfinite(uj) || uj < 0.0) {
        fail(fname + ": standard uncertainty " + std::to_string(j) +
             " must be finite and >= 0; got " + fmt(uj));
      }
    }
    const auto n = static_cast<Eigen::Index>(nc);
    if (fn.correlation.size() != 0) {
      const Eigen::MatrixXd& r = fn.correlation;
      if (r.rows() != n || r.cols() != n) {
        fail(fname + ": correlation must be " + std::to_string(n) + "x" + std::to_string(n) +
             "; got " + std::to_string(r.rows()) + "x" + std::to_string(r.cols()));
      }
      for (Eigen::Index i = 0; i < n; ++i) {
        for (Eigen::Index j = 0; j < n; ++j) {
          const double rij = r(i, j);
          const std::string at = "correlation(" + std::to_string(i) + ", " +
                                 std::to_string(j) + ")";
          if (!std::isfinite(rij)) fail(fname + ": " + at + " must be finite; got " + fmt(rij));
          // 1e-12: JSON round-trips of hand-typed decimals are exact to ~1e-16; anything
          // larger is a typing error, not rounding.
          if (i == j && std::abs(rij - 1.0) > 1e-12) {
            fail(fname + ": " + at + " must be 1 (unit diagonal); got " + fmt(rij));
          }
          if (std::abs(rij) > 1.0 + 1e-12) {
            fail(fname + ": " + at + " must lie in [-1, 1]; got " + fmt(rij));
          }
          if (std::abs(rij - r(j, i)) > 1e-12) {
            fail(fname + ": correlation must be symmetric; (" + std::to_string(i) + ", " +
                 std::to_string(j) + ") = " + fmt(rij) + " but (" + std::to_string(j) + ", " +
                 std::to_string(i) + ") = " + fmt(r(j, i)));
          }
        }
      }
    }
    counts[f] = static_cast<int>(nc);
  }
  for (int s = 0; s < squareness_count; ++s) {
    const EstimatedValue& v = squareness[s];
    const std::string sname = where + std::string(name(static_cast<Squareness>(s)));
    if (!std::isfinite(v.value)) fail(sname + ": value must be finite; got " + fmt(v.value));
    if (!std::isfinite(v.standard_uncertainty) || v.standard_uncertainty < 0.0) {
      fail(sname + ": standard uncertainty must be finite and >= 0; got " +
           fmt(v.standard_uncertainty));
    }
  }
  rebuild_layout(counts);
  for (int f = 0; f < axis_error_count; ++f) {
    const ErrorFunctionEstimate& fn = functions[f];
    const Eigen::Index off = offsets_[f], n = counts[f];
    for (Eigen::Index j = 0; j < n; ++j) {
      mean_[off + j] = fn.coefficients[static_cast<std::size_t>(j)];
    }
    const Eigen::VectorXd u = Eigen::Map<const Eigen::VectorXd>(fn.standard_uncertainties.data(), n);
    Eigen::MatrixXd block = u * u.transpose();
    if (fn.correlation.size() != 0) {
      block = block.cwiseProduct(fn.correlation);
    } else {
      block = u.cwiseAbs2().asDiagonal();
    }
    // Check positive definiteness per function, to name the culprit.
    std::vector<Eigen::Index> idx;
    for (Eigen::Index j = 0; j < n; ++j) {
      if (u[j] > 0.0) idx.push_back(j);
    }
    if (!idx.empty()) {
      Eigen::MatrixXd sub(static_cast<Eigen::Index>(idx.size()), static_cast<Eigen::Index>(idx.size()));
      for (std::size_t a = 0; a < idx.size(); ++a) {
        for (std::size_t b = 0; b < idx.size(); ++b) {
          sub(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) = block(idx[a], idx[b]);
        }
      }
      Eigen::LLT<Eigen::MatrixXd> llt(sub);
      if (llt.info() != Eigen::Success) {
        fail(where + std::string(name(static_cast<AxisError>(f))) +
             ": correlation matrix is not positive definite (on the coefficients with "
             "non-zero uncertainty)");
      }
    }
    covariance_.block(off, off, n, n) = block;
  }
  for (int s = 0; s < squareness_count; ++s) {
    const Eigen::Index i = offsets_[axis_error_count] + s;
    mean_[i] = squareness[s].value;
    covariance_(i, i) = squareness[s].standard_uncertainty * squareness[s].standard_uncertainty;
  }
  set_covariance(covariance_);
}

KinematicModel KinematicModel::zero(KinematicChain chain, const std::array<AxisRange, 3>& ranges) {
  std::array<ErrorFunctionEstimate, axis_error_count> functions;
  for (auto& fn : functions) {
    fn.coefficients = {0.0};
    fn.standard_uncertainties = {0.0};
  }
  return KinematicModel(std::move(chain), ranges, functions, {});
}

int KinematicModel::coefficient_count(AxisError e) const {
  const int f = static_cast<int>(e);
  return static_cast<int>(offsets_[f + 1] - offsets_[f]);
}
Eigen::Index KinematicModel::parameter_offset(AxisError e) const {
  return offsets_[static_cast<int>(e)];
}
Eigen::Index KinematicModel::parameter_offset(Squareness s) const {
  return offsets_[axis_error_count] + static_cast<int>(s);
}

KinematicModel KinematicModel::uncorrected() const {
  KinematicModel out = *this;
  Eigen::MatrixXd covariance = covariance_;
  covariance.diagonal() += mean_.cwiseAbs2();
  out.mean_.setZero();
  out.set_covariance(covariance);
  return out;
}

void KinematicModel::set_covariance(const Eigen::MatrixXd& covariance) {
  const Eigen::Index n = parameter_count();
  const std::string where = "KinematicModel::set_covariance: ";
  if (covariance.rows() != n || covariance.cols() != n) {
    fail(where + "must be " + std::to_string(n) + "x" + std::to_string(n) + "; got " +
         std::to_string(covariance.rows()) + "x" + std::to_string(covariance.cols()));
  }
  if (!covariance.allFinite()) fail(where + "entries must be finite");
  const double scale = covariance.cwiseAbs().maxCoeff();
  std::vector<Eigen::Index> uncertain;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double cii = covariance(i, i);
    if (cii < 0.0) fail(where + "variance " + std::to_string(i) + " is negative: " + fmt(cii));
    for (Eigen::Index j = 0; j < i; ++j) {
      // Symmetry to rounding of the entries' magnitude.
      if (std::abs(covariance(i, j) - covariance(j, i)) > 1e-12 * scale) {
        fail(where + "must be symmetric; (" + std::to_string(i) + ", " + std::to_string(j) +
             ") = " + fmt(covariance(i, j)) + " but (" + std::to_string(j) + ", " +
             std::to_string(i) + ") = " + fmt(covariance(j, i)));
      }
    }
    if (cii > 0.0) {
      uncertain.push_back(i);
    } else {
      for (Eigen::Index j = 0; j < n; ++j) {
        if (covariance(i, j) != 0.0) {
          fail(where + "parameter " + std::to_string(i) +
               " has zero variance but non-zero covariance with parameter " +
               std::to_string(j) + " (" + fmt(covariance(i, j)) + ")");
        }
      }
    }
  }
  const auto k = static_cast<Eigen::Index>(uncertain.size());
  Eigen::MatrixXd sub(k, k);
  for (Eigen::Index a = 0; a < k; ++a) {
    for (Eigen::Index b = 0; b < k; ++b) {
      sub(a, b) = covariance(uncertain[static_cast<std::size_t>(a)],
                             uncertain[static_cast<std::size_t>(b)]);
    }
  }
  Eigen::LLT<Eigen::MatrixXd> llt(sub);
  if (k > 0 && llt.info() != Eigen::Success) {
    fail(where + "not positive definite on the parameters with non-zero variance");
  }
  covariance_ = covariance;
  uncertain_ = std::move(uncertain);
  cholesky_ = k > 0 ? Eigen::MatrixXd(llt.matrixL()) : Eigen::MatrixXd();
  // draw() adds column j of L only down to its last non-zero entry. The factor of a block
  // diagonal covariance (the default: no correlation between functions) is block diagonal,
  // and a skipped term l·z = ±0 leaves a parameter p unchanged unless p = −0 (−0 + +0 = +0);
  // p can be −0 only where its estimate is −0 (a sum is −0 only as −0 + −0). So with no
  // estimate −0 the skip gives the same bits: ~k²/2 products → the blocks' (75 → ~9 each).
  column_end_.assign(static_cast<std::size_t>(k), k);
  bool negative_zero = false;
  for (const Eigen::Index i : uncertain_)
    negative_zero = negative_zero || (mean_[i] == 0.0 && std::signbit(mean_[i]));
  for (Eigen::Index j = 0; j < k && !negative_zero; ++j) {
    Eigen::Index end = j + 1;
    for (Eigen::Index i = j + 1; i < k; ++i) {
      if (cholesky_(i, j) != 0.0) end = i + 1;
    }
    column_end_[static_cast<std::size_t>(j)] = end;
  }
}

KinematicErrors KinematicModel::nominal() const {
  KinematicErrors e;
  e.parameters_ = mean_;
  return e;
}

KinematicErrors KinematicModel::draw(RandomSource& rng) const {
  KinematicErrors e;
  draw(rng, e);
  return e;
}

void KinematicModel::draw(RandomSource& rng, KinematicErrors& out) const {
  out.parameters_ = mean_;  // no allocation when already sized
  const auto k = static_cast<Eigen::Index>(uncertain_.size());
  if (k == 0) return;
  std::array<double, kMaxParameters> z;
  rng.fill_standard_normal({z.data(), static_cast<std::size_t>(k)});
  // out[uncertain] += L z, column by column (contiguous in column-major L). Each parameter
  // gets its terms in the same order (j ascending) either way, so both loops give the same bits.
  if (uncertain_.back() - uncertain_.front() == k - 1) {  // sorted, distinct: a contiguous run
    double* __restrict p = out.parameters_.data() + uncertain_.front();
    for (Eigen::Index j = 0; j < k; ++j) {
      const double zj = z[static_cast<std::size_t>(j)];
      const double* __restrict l = cholesky_.col(j).data();
      const Eigen::Index end = column_end_[static_cast<std::size_t>(j)];
      for (Eigen::Index i = j; i < end; ++i) p[i] += l[i] * zj;
    }
    return;
  }
  for (Eigen::Index j = 0; j < k; ++j) {
    const double zj = z[static_cast<std::size_t>(j)];
    for (Eigen::Index i = j; i < column_end_[static_cast<std::size_t>(j)]; ++i) {
      out.parameters_[uncertain_[static_cast<std::size_t>(i)]] += cholesky_(i, j) * zj;
    }
  }
}

// ---- realisation ---------------------------------------------------------------------------

KinematicErrors::KinematicErrors(const KinematicModel& model, Eigen::VectorXd parameters)
    : parameters_(std::move(parameters)) {
  if (parameters_.size() != model.parameter_count()) {
    fail("KinematicErrors: " + std::to_string(parameters_.size()) +
         " parameters for a model with " + std::to_string(model.parameter_count()));
  }
  for (Eigen::Index i = 0; i < parameters_.size(); ++i) {
    if (!std::isfinite(parameters_[i])) {
      fail("KinematicErrors: parameter " + std::to_string(i) + " must be finite; got " +
           fmt(parameters_[i]));
    }
  }
}

std::span<const double> KinematicErrors::coefficients(const KinematicModel& model,
                                                      AxisError e) const {
  check_errors_match(model, *this, "KinematicErrors::coefficients");
  return {parameters_.data() + model.parameter_offset(e),
          static_cast<std::size_t>(model.coefficient_count(e))};
}

void KinematicErrors::set_coefficients(const KinematicModel& model, AxisError e,
                                       std::span<const double> c) {
  check_errors_match(model, *this, "KinematicErrors::set_coefficients");
  if (static_cast<int>(c.size()) != model.coefficient_count(e)) {
    fail("KinematicErrors::set_coefficients: " + std::string(name(e)) + " has " +
         std::to_string(model.coefficient_count(e)) + " coefficients in the model; got " +
         std::to_string(c.size()));
  }
  for (std::size_t j = 0; j < c.size(); ++j) {
    if (!std::isfinite(c[j])) {
      fail("KinematicErrors::set_coefficients: " + std::string(name(e)) + " coefficient " +
           std::to_string(j) + " must be finite; got " + fmt(c[j]));
    }
    parameters_[model.parameter_offset(e) + static_cast<Eigen::Index>(j)] = c[j];
  }
}

double KinematicErrors::squareness(const KinematicModel& model, Squareness s) const {
  check_errors_match(model, *this, "KinematicErrors::squareness");
  return parameters_[model.parameter_offset(s)];
}

void KinematicErrors::set_squareness(const KinematicModel& model, Squareness s, double value) {
  check_errors_match(model, *this, "KinematicErrors::set_squareness");
  if (!std::isfinite(value)) {
    fail("KinematicErrors::set_squareness: " + std::string(name(s)) + " must be finite; got " +
         fmt(value));
  }
  parameters_[model.parameter_offset(s)] = value;
}

KinematicErrors KinematicErrors::scaled(double s) const {
  if (!std::isfinite(s)) fail("KinematicErrors::scaled: factor must be finite; got " + fmt(s));
  KinematicErrors e;
  e.parameters_ = parameters_ * s;
  return e;
}

// ---- evaluation ----------------------------------------------------------------------------

double error_function_value(const KinematicModel& model, const KinematicErrors& errors,
                            AxisError e, double q) {
  check_errors_match(model, errors, "error_function_value");
  const AxisRange& r = model.range(axis_of(e));
  const double slack = kRangeSlack * (r.max - r.min);
  if (!(q >= r.min - slack && q <= r.max + slack)) {
    fail("error_function_value: " + std::string(name(e)) + " at q = " + fmt(q) +
         " mm, outside the axis range [" + fmt(r.min) + ", " + fmt(r.max) + "] mm");
  }
  const double u = (2.0 * q - r.min - r.max) / (r.max - r.min);
  return legendre_series(errors.coefficients(model, e), u);
}

void tip_errors(const KinematicModel& model, const KinematicErrors& errors,
                const Eigen::Ref<const Eigen::Matrix3Xd>& tip_positions,
                const Eigen::Vector3d& stylus_offset, Formula formula,
                Eigen::Ref<Eigen::Matrix3Xd> out) {
  evaluate(model, errors, tip_positions, stylus_offset, formula, out, "tip_errors");
}

Eigen::Matrix3Xd tip_errors(const KinematicModel& model, const KinematicErrors& errors,
                            const Eigen::Ref<const Eigen::Matrix3Xd>& tip_positions,
                            const Eigen::Vector3d& stylus_offset, Formula formula) {
  Eigen::Matrix3Xd out(3, tip_positions.cols());
  evaluate(model, errors, tip_positions, stylus_offset, formula, out, "tip_errors");
  return out;
}

Eigen::Matrix3Xd measured_tip_positions(const KinematicModel& model,
                                        const KinematicErrors& errors,
                                        const Eigen::Ref<const Eigen::Matrix3Xd>& true_positions,
                                        const Eigen::Vector3d& stylus_offset, Formula formula) {
  Eigen::Matrix3Xd e(3, true_positions.cols());
  evaluate(model, errors, true_positions, stylus_offset, formula, e, "measured_tip_positions");
  Eigen::Matrix3Xd p = true_positions + e;
  evaluate(model, errors, p, stylus_offset, formula, e, "measured_tip_positions");
  p = true_positions + e;
  return p;
}

Eigen::Matrix3Xd true_tip_positions(const KinematicModel& model, const KinematicErrors& errors,
                                    const Eigen::Ref<const Eigen::Matrix3Xd>& measured_positions,
                                    const Eigen::Vector3d& stylus_offset, Formula formula) {
  Eigen::Matrix3Xd e(3, measured_positions.cols());
  evaluate(model, errors, measured_positions, stylus_offset, formula, e, "true_tip_positions");
  return measured_positions - e;
}

}  // namespace vcmm::errormodel
