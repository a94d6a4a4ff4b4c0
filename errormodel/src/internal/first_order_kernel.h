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

/// The first-order tip error e = −v at the tip position p = (p0, p1, p2) (mm) for functions of
/// degree ≤ D, the rotations' of degree ≤ DR ≤ D; kZ: also e2 (else e2 is left untouched).
/// Returns 1 when a reading is out of range or non-finite (NaN fails every comparison; ±inf
/// exceeds the bound), else 0.
/// Any D, DR at least the functions' degrees give the same bits: the zero padding is +0 (the
/// power-basis coefficients are sums started at +0, never −0), and a Horner step from a +0
/// leading coefficient gives (±0)·u + m = m exactly, so the padded evaluation reaches each
/// function's true leading coefficient with the value m itself.
template <int D, bool kZ, int DR = D>
  requires(0 <= DR && DR <= D)
[[gnu::always_inline]] inline int first_order_error(const FirstOrderKernel& k, double p0,
                                                    double p1, double p2, double& e0, double& e1,
                                                    double& e2) {
  const double q[3] = {p0 - k.t[0], p1 - k.t[1], p2 - k.t[2]};
  double u[3];
  for (int a = 0; a < 3; ++a) u[a] = q[a] * k.u_scale[a] + k.u_offset[a];
  const int bad = static_cast<int>(!(u[0] * u[0] <= k.limit2) | !(u[1] * u[1] <= k.limit2) |
                                   !(u[2] * u[2] <= k.limit2));
  double v0 = 0.0, v1 = 0.0, v2 = 0.0;
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
    const double rx = k.t[0] + k.arm_mask[a][0] * q[0];
    const double ry = k.t[1] + k.arm_mask[a][1] * q[1];
    const double rz = k.t[2] + k.arm_mask[a][2] * q[2];
    v0 += f[0] + (f[4] * rz - f[5] * ry);
    v1 += f[1] + (f[5] * rx - f[3] * rz);
    if constexpr (kZ) v2 += f[2] + (f[3] * ry - f[4] * rx);
  }
  v0 += k.b0z * q[2] - k.c0y * q[1];
  v1 -= k.a0z * q[2];
  e0 = -v0;
  e1 = -v1;
  if constexpr (kZ) e2 = -v2;
  return bad;
}

}  // namespace vcmm::errormodel::internal
