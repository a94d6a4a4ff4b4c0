// The fused trial's one-pass per-point kernel (internal/fused_trial_kernel.h). Compiled
// without FMA contraction (errormodel/CMakeLists.txt), as SIMD clones.
#include "internal/fused_trial_kernel.h"

#include <utility>

#include "vcmm/errormodel/digital_model.h"  // max_probe_harmonic_order

namespace vcmm::errormodel::internal {
namespace {

// kArms ≠ data: the planar form (FusedTrialInput::planar, R about z with r22 = 1, constant
// arm masks: first_order_displacement), where qz = (pz + r·0)·s is pz·s and w2 = 1·qz + lz
// is qz + lz, both exactly (pz ≠ −0; 1·x = x): 3 operations fewer a point, 19 with the arms.
// In every form e = −v enters c as t·(−v) = (−t)·v (the product's rounding is symmetric):
// the same bits without the 2 negations.
template <int D, bool kXyz, int DR, ArmPattern kArms>
[[gnu::always_inline]] inline Eigen::Index points(const FusedTrialInput& in,
                                                  const FirstOrderKernel& k,
                                                  double* __restrict out) {
  constexpr bool kPlanar = kArms != ArmPattern::data;
  const double* __restrict px = in.px;
  const double* __restrict py = in.py;
  const double* __restrict pz = in.pz;
  const double* __restrict nx = in.nx;
  const double* __restrict ny = in.ny;
  const double* __restrict nz = in.nz;
  const double* __restrict rough = in.roughness;
  const double* __restrict shift = in.shift;
  const double* __restrict z = in.noise;
  const Eigen::Matrix3d& r = in.rotation;
  const double r00 = r(0, 0), r01 = r(0, 1), r10 = r(1, 0), r11 = r(1, 1), r22 = r(2, 2);
  // −Rᵀ of a rotation about z: (x, y) → −(r00 x + r10 y, r01 x + r11 y), z unchanged.
  const double t00 = -r(0, 0), t01 = -r(1, 0), t10 = -r(0, 1), t11 = -r(1, 1), t22 = -r(2, 2);
  const double lx = in.location.x(), ly = in.location.y(), lz = in.location.z();
  const double scale = in.scale, inverse_scale = in.inverse_scale;
  constexpr int kStride = kXyz ? 3 : 2;
  Eigen::Index bad = 0;
  for (Eigen::Index i = 0; i < in.n; ++i) {
    const double t = rough[i];
    const double qx = (px[i] + t * nx[i]) * scale;
    const double qy = (py[i] + t * ny[i]) * scale;
    const double qz = kPlanar ? pz[i] * scale : (pz[i] + t * nz[i]) * scale;
    const double w0 = r00 * qx + r01 * qy + lx;
    const double w1 = r10 * qx + r11 * qy + ly;
    const double w2 = kPlanar ? qz + lz : r22 * qz + lz;
    double vx = 0.0, vy = 0.0, vz = 0.0;
    bad += first_order_displacement<D, kXyz, DR, kArms>(k, w0, w1, w2, vx, vy, vz);
    const double sh = shift[i];
    const double cx = t00 * vx + t01 * vy + sh * nx[i] + z[kStride * i];
    const double cy = t10 * vx + t11 * vy + sh * ny[i] + z[kStride * i + 1];
    out[kStride * i] = (qx + cx) * inverse_scale;
    out[kStride * i + 1] = (qy + cy) * inverse_scale;
    if constexpr (kXyz) {
      const double cz = t22 * vz + sh * nz[i] + z[3 * i + 2];
      out[kStride * i + 2] = (qz + cz) * inverse_scale;
    }
  }
  return bad;
}

// Rotations of one degree less than the translations (the usual calibration: a rotation is
// about the derivative of a straightness) get their own instance in the xy form, which the
// Monte Carlo trial runs: 3 × 3 Horner steps fewer a point (first_order_error: the same bits).
template <bool kXyz, int D, ArmPattern kArms>
[[gnu::always_inline]] inline Eigen::Index degree(const FusedTrialInput& in,
                                                  const FirstOrderKernel& k, double* out) {
  if constexpr (!kXyz && D > 0) {
    if (k.rotation_degree < D) return points<D, kXyz, D - 1, kArms>(in, k, out);
  }
  return points<D, kXyz, D, kArms>(in, k, out);
}

template <bool kXyz, ArmPattern kArms>
[[gnu::always_inline]] inline Eigen::Index dispatch(const FusedTrialInput& in,
                                                    const FirstOrderKernel& k, double* out) {
  switch (k.degree) {
    case 0: return degree<kXyz, 0, kArms>(in, k, out);
    case 1: return degree<kXyz, 1, kArms>(in, k, out);
    case 2: return degree<kXyz, 2, kArms>(in, k, out);
    case 3: return degree<kXyz, 3, kArms>(in, k, out);
    case 4: return degree<kXyz, 4, kArms>(in, k, out);
    case 5: return degree<kXyz, 5, kArms>(in, k, out);
    case 6: return degree<kXyz, 6, kArms>(in, k, out);
    case 7: return degree<kXyz, 7, kArms>(in, k, out);
    case 8: return degree<kXyz, 8, kArms>(in, k, out);
    case 9: return degree<kXyz, 9, kArms>(in, k, out);
    default: return degree<kXyz, 10, kArms>(in, k, out);
  }
}
static_assert(max_legendre_degree == 10, "extend dispatch");

VCMM_SIMD_CLONES Eigen::Index points_xy(const FusedTrialInput& in, const FirstOrderKernel& k,
                                        double* out) {
  return dispatch<false, ArmPattern::data>(in, k, out);
}

// The planar forms (the ring trial's): xy only, one per built-in chain.
VCMM_SIMD_CLONES Eigen::Index points_xy_moving_bridge(const FusedTrialInput& in,
                                                      const FirstOrderKernel& k, double* out) {
  return dispatch<false, ArmPattern::moving_bridge>(in, k, out);
}

VCMM_SIMD_CLONES Eigen::Index points_xy_fixed_bridge(const FusedTrialInput& in,
                                                     const FirstOrderKernel& k, double* out) {
  return dispatch<false, ArmPattern::fixed_bridge>(in, k, out);
}

VCMM_SIMD_CLONES Eigen::Index points_xyz(const FusedTrialInput& in, const FirstOrderKernel& k,
                                         double* out) {
  return dispatch<true, ArmPattern::data>(in, k, out);
}

}  // namespace

Eigen::Index fused_trial_points(const FusedTrialInput& in, const FirstOrderKernel& kinematic,
                                bool xyz, double* out) {
  if (xyz) return points_xyz(in, kinematic, out);
  if (in.planar && in.rotation(2, 2) == 1.0) {
    switch (kinematic.arm_pattern) {
      case ArmPattern::moving_bridge: return points_xy_moving_bridge(in, kinematic, out);
      case ArmPattern::fixed_bridge: return points_xy_fixed_bridge(in, kinematic, out);
      case ArmPattern::data: break;
    }
  }
  return points_xy(in, kinematic, out);
}

namespace {

template <int K>
[[gnu::always_inline]] inline void shifts(Eigen::Index n, double base, const double* cos_k,
                                          const double* sin_k, const double* const* re,
                                          const double* const* im, double* __restrict shift) {
  double c[K + 1], s[K + 1];
  const double* a[K + 1];
  const double* b[K + 1];
  for (int k = 1; k <= K; ++k) {
    c[k] = cos_k[k];
    s[k] = sin_k[k];
    a[k] = re[k];
    b[k] = im[k];
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    double sh = base;
#pragma GCC unroll 16
    for (int k = 1; k <= K; ++k) sh += c[k] * a[k][i] + s[k] * b[k][i];
    shift[i] = sh;
  }
}

template <int... K>
[[gnu::always_inline]] inline void shifts_dispatch(std::integer_sequence<int, K...>,
                                                   Eigen::Index n, int order, double base,
                                                   const double* cos_k, const double* sin_k,
                                                   const double* const* re,
                                                   const double* const* im, double* shift) {
  ((order == K ? shifts<K>(n, base, cos_k, sin_k, re, im, shift) : void()), ...);
}

}  // namespace

VCMM_SIMD_CLONES void probe_shift_points(Eigen::Index n, int order, double base,
                                         const double* cos_k, const double* sin_k,
                                         const double* const* re, const double* const* im,
                                         double* shift) {
  shifts_dispatch(std::make_integer_sequence<int, max_probe_harmonic_order + 1>{}, n, order,
                  base, cos_k, sin_k, re, im, shift);
}

}  // namespace vcmm::errormodel::internal
