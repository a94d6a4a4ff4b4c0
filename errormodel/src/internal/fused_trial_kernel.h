// errormodel/src/internal/fused_trial_kernel.h — the one-pass per-point kernel of the fused
// Monte Carlo trial on a prepared measurement (virtual_cmm.h, simulate_corrected; derivation in
// docs/errormodel.md, "The fused trial"). Internal: virtual_cmm.cpp only.
//
// For every point, in registers (no machine-position or tip-error array in between):
//   q = (p + r_i n)·s,  w = L + R q,  e = e_Δ(w) (internal::first_order_error),
//   c = Rᵀ e + shift_i·n + z_i,  out = (q + c)·(1/ŝ)
// — the same operations in the same order as the three passes it replaces (machine positions,
// tip_errors, corrected points), so the same values bit for bit. Built as SIMD clones without
// FMA contraction (first_order_kernel.h): the same bits on every CPU.
#pragma once

#include <Eigen/Core>

#include "internal/first_order_kernel.h"

namespace vcmm::errormodel::internal {

/// What the kernel reads: structure-of-arrays points p and normals n (workpiece axes, mm),
/// per-point roughness r_i, probe shift and noise — 3 × N (x, y, z) for the xyz form, 2 × N
/// (x, y) for the xy form — (zeros for a stage that is off), the
/// drawn and the inverse estimated expansion factors, the placement rotation R (about z) and
/// location L.
struct FusedTrialInput {
  Eigen::Index n = 0;
  const double* px = nullptr;
  const double* py = nullptr;
  const double* pz = nullptr;
  const double* nx = nullptr;
  const double* ny = nullptr;
  const double* nz = nullptr;
  const double* roughness = nullptr;
  const double* shift = nullptr;
  const double* noise = nullptr;
  /// Every nz is 0 and no pz is −0 (recorded by PreparedMeasurement): lets the xy form drop
  /// the z normal's terms (the same bits; fused_trial_kernel.cpp).
  bool planar = false;
  double scale = 1.0;
  double inverse_scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d location = Eigen::Vector3d::Zero();
};

/// Writes the corrected x, y (xyz false: stride 2, a Point2 array) or x, y, z (stride 3) of
/// every point to `out`. Returns the number of points whose machine position is out of the
/// axis ranges or non-finite (then `out` is garbage and the caller reports the error).
Eigen::Index fused_trial_points(const FusedTrialInput& in, const FirstOrderKernel& kinematic,
                                bool xyz, double* out);

/// shift_i = base + Σ_{k=1..K} (c_k re_k[i] + s_k im_k[i]) for i < n, accumulated in k order
/// (the probe shift δr + D of the prepared harmonics; cos, sin indexed by order, 0 unused).
void probe_shift_points(Eigen::Index n, int order, double base, const double* cos_k,
                        const double* sin_k, const double* const* re, const double* const* im,
                        double* shift);

}  // namespace vcmm::errormodel::internal
