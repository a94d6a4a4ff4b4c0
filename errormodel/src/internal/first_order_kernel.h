// errormodel/src/internal/first_order_kernel.h — the first-order tip error of one point as
// branch-free data-driven code (kinematic_errors.cpp, "first-order kernel"), shared by the
// kinematic evaluation (tip_errors) and the fused Monte Carlo trial's one-pass kernel
// (fused_trial_kernel.cpp), so that both compute every point with the same operations in the
// same order: their results are bit for bit the same. Internal: errormodel sources only.
//
// Both including files are compiled without FMA contraction (-ffp-contract=off,
// top-level CMakeLists.txt): their SIMD clones (AVX-512, AVX2, baseline x86-64, chosen at
// load time) then round identically on every CPU.
#pragma once

#include <Eigen/Core>

#include "vcmm/errormodel/kinematic_errors.h"
#include "vcmm/internal/simd_clones.h"

namespace vcmm::errormodel::internal {

inline constexpr int kFirstOrderMaxCoeffs = max_legendre_degree + 1;

/// The arm masks M of the two built-in chains (KinematicChain), for kernels that take them
/// as compile-time constants (first_order_displacement's kArms); `data` reads them from
/// FirstOrderKernel::arm_mask. Rows: the axis whose rotation acts; columns: the travel.
///   moving bridge (base → Y → X → Z): X {0,0,1}, Y {1,0,1}, Z {0,0,0}
///   fixed bridge (base → X → Z, workpiece on Y): X {0,0,1}, Y {1,1,1}, Z {0,0,0}
enum class ArmPattern { data, moving_bridge, fixed_bridge };

inline constexpr bool arm_mask_of(ArmPattern p, int a, int j) {
  constexpr bool moving[3][3] = {{false, false, true}, {true, false, true}, {false, false, false}};
  constexpr bool fixed[3][3] = {{false, false, true}, {true, true, true}, {false, false, false}};
  return p == ArmPattern::moving_bridge ? moving[a][j] : fixed[a][j];
}

/// The first-order formula with the chain turned into data: the arm of axis k is
///   r_k = t + Σ_j M_kj q_j a_j,   M_kj = 1 if axis j's travel lies between carriage k's
/// rotation centre and the tip (tool side: axes after k; workpiece side: all tool axes, the
/// workpiece axes before k, and k itself). Error functions in the power basis of u, padded
/// with zeros to a common degree.
struct FirstOrderKernel {
  double mono[axis_error_count][kFirstOrderMaxCoeffs] = {};  // power basis in u, zero-padded
  double u_scale[3] = {}, u_offset[3] = {};
  double t[3] = {};
  double arm_mask[3][3] = {};
  double c0y = 0.0, b0z = 0.0, a0z = 0.0;
  double limit2 = 0.0;  // bound on u²
  int degree = 0;           // highest degree of any function (the D of first_order_error)
  int rotation_degree = 0;  // highest degree of a rotation function (its DR)
  /// The pattern arm_mask equals, when no component of t is −0 (first_order_displacement:
  /// then the constant masks give the same bits); else ArmPattern::data.
  ArmPattern arm_pattern = ArmPattern::data;
};

/// The kernel of `errors` (a realisation of `model`) with stylus offset t. Throws
/// std::invalid_argument as tip_errors() when `errors` does not belong to the model or t is
/// not finite (`caller` names the entry point in the message).
FirstOrderKernel first_order_kernel(const KinematicModel& model, const KinematicErrors& errors,
                                    const Eigen::Vector3d& t, const char* caller);

/// Throws std::invalid_argument naming the first of the tip positions `p` (3 × n) whose axis
/// reading q = p − t is non-finite or outside the model's axis ranges (as tip_errors does).
[[noreturn]] void report_bad_tip_position(const KinematicModel& model,
                                          const Eigen::Ref<const Eigen::Matrix3Xd>& p,
                                          const Eigen::Vector3d& t, const char* caller);

/// The first-order tip displacement v = −e at the tip position p = (p0, p1, p2) (mm) for
/// functions of degree ≤ D, the rotations' of degree ≤ DR ≤ D; kZ: also v2 (else v2 is left
/// untouched). Returns 1 when a reading is out of range or non-finite (NaN fails every
/// comparison; ±inf exceeds the bound), else 0.
/// Any D, DR at least the functions' degrees give the same bits: the zero padding is +0 (the
/// power-basis coefficients are sums started at +0, never −0), and a Horner step from a +0
/// leading coefficient gives (±0)·u + m = m exactly, so the padded evaluation reaches each
/// function's true leading coefficient with the value m itself.
/// kArms ≠ data (k.arm_pattern == kArms, which holds only when no t_j is −0): the arm
/// r_aj = t_j + M_aj q_j is t_j + q_j where M_aj = 1 (1·q = q exactly) and t_j where M_aj = 0
/// (0·q = ±0 for finite q, and t + ±0 = t for t ≠ 0, +0 + ±0 = +0): the same bits without
/// the 9 multiplications and with 2 or 3 additions instead of 9. (A non-finite q makes the point
/// bad, and the caller discards every output then.)
template <int D, bool kZ, int DR = D, ArmPattern kArms = ArmPattern::data>
  requires(0 <= DR && DR <= D)
[[gnu::always_inline]] inline int first_order_displacement(const FirstOrderKernel& k, double p0,
                                                           double p1, double p2, double& v0,
                                                           double& v1, double& v2) {
  const double q[3] = {p0 - k.t[0], p1 - k.t[1], p2 - k.t[2]};
  double u[3];
  for (int a = 0; a < 3; ++a) u[a] = q[a] * k.u_scale[a] + k.u_offset[a];
  const int bad = static_cast<int>(!(u[0] * u[0] <= k.limit2) | !(u[1] * u[1] <= k.limit2) |
                                   !(u[2] * u[2] <= k.limit2));
  double tq[3] = {};  // t_j + q_j, the arm of a masked travel (constant masks only)
  if constexpr (kArms != ArmPattern::data) {
    for (int j = 0; j < 3; ++j) {
      if (arm_mask_of(kArms, 0, j) || arm_mask_of(kArms, 1, j) || arm_mask_of(kArms, 2, j))
        tq[j] = k.t[j] + q[j];
    }
  }
  const auto arm = [&](int a, int j) {
    if constexpr (kArms == ArmPattern::data) {
      return k.t[j] + k.arm_mask[a][j] * q[j];
    } else {
      return arm_mask_of(kArms, a, j) ? tq[j] : k.t[j];
    }
  };
  double s0 = 0.0, s1 = 0.0, s2 = 0.0;
  // Fully unrolled (constant trip counts) so that the loop over points vectorises.
#pragma GCC unroll 3
  for (int a = 0; a < 3; ++a) {
    double f[6];
#pragma GCC unroll 6
    for (int c = 0; c < 6; ++c) {
      if (!kZ && c == 2) continue;  // E_Z of the axis: only in v2
      const double* m = k.mono[6 * a + c];
      constexpr int kDegree[6] = {D, D, D, DR, DR, DR};  // translations, rotations
      double acc = m[kDegree[c]];
#pragma GCC unroll 11
      for (int j = kDegree[c] - 1; j >= 0; --j) acc = acc * u[a] + m[j];
      f[c] = acc;
    }
    const double rx = arm(a, 0);
    const double ry = arm(a, 1);
    const double rz = arm(a, 2);
    s0 += f[0] + (f[4] * rz - f[5] * ry);
    s1 += f[1] + (f[5] * rx - f[3] * rz);
    if constexpr (kZ) s2 += f[2] + (f[3] * ry - f[4] * rx);
  }
  s0 += k.b0z * q[2] - k.c0y * q[1];
  s1 -= k.a0z * q[2];
  v0 = s0;
  v1 = s1;
  if constexpr (kZ) v2 = s2;
  return bad;
}

/// The first-order tip error e = −v at p (first_order_displacement, data-driven arms).
template <int D, bool kZ, int DR = D>
  requires(0 <= DR && DR <= D)
[[gnu::always_inline]] inline int first_order_error(const FirstOrderKernel& k, double p0,
                                                    double p1, double p2, double& e0, double& e1,
                                                    double& e2) {
  double v0 = 0.0, v1 = 0.0, v2 = 0.0;
  const int bad = first_order_displacement<D, kZ, DR>(k, p0, p1, p2, v0, v1, v2);
  e0 = -v0;
  e1 = -v1;
  if constexpr (kZ) e2 = -v2;
  return bad;
}

}  // namespace vcmm::errormodel::internal
