// vcmm/errormodel/ring_gauge.h — nominal measurements of a ring gauge (the seed study's
// artefact): the inner cylindrical surface of a ring, with a form deviation given as
// harmonics, sampled by scanning (dense) or touch-trigger (sparse) probing at one height.
//
// Profile (workpiece coordinates, ring axis = workpiece Z, centre at the origin):
//   r(θ) = D/2 + Σ_k a_k cos(k θ + φ_k),   point  (r cos θ, r sin θ, h),
//   θ_i = θ_0 + 2π i / N  (i = 0 … N−1; closed, the first point not repeated).
// Normal (material → air, i.e. towards the axis for this inner surface): the exact normal of
// the profile curve, n = (−r u + r′ u⊥) / √(r² + r′²) with u = (cos θ, sin θ, 0),
// u⊥ = (−sin θ, cos θ, 0); for a perfect ring n = −u.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "vcmm/errormodel/measurement.h"

namespace vcmm::errormodel {

/// One harmonic of the form deviation: a_k cos(k θ + φ_k).
struct FormHarmonic {
  int order = 2;              ///< k ≥ 1 (undulations per revolution)
  double amplitude_mm = 0.0;  ///< a_k (mm), radial, positive outwards
  double phase_rad = 0.0;     ///< φ_k
};

/// The ring: inner diameter and form deviation.
struct RingGauge {
  double diameter_mm = 171.0;       ///< the seed study's ring
  std::vector<FormHarmonic> form;   ///< empty: a perfect circle
};

/// The seed study's form deviation: harmonics 2, 3, 4, 5, 7, 11, 17 with amplitudes 45, 30,
/// 12, 10, 6, 4, 3 nm — about 200 nm peak-to-valley (the same profile as
/// examples/profiles/make_example_profiles.py).
std::vector<FormHarmonic> seed_study_ring_form();

/// How the ring is probed and where it sits in the machine.
struct RingSampling {
  ProbingMode mode = ProbingMode::scanning;
  Eigen::Index points = 3600;   ///< N ≥ 3 (touch-trigger studies use e.g. 16)
  double height_mm = 0.0;       ///< z of the section in workpiece coordinates
  double start_angle_rad = 0.0; ///< θ_0, workpiece coordinates
  Placement placement;          ///< ring centre (workpiece origin) and orientation in the machine
  double temperature_c = reference_temperature_c;  ///< reading stored in the result (°C)
  Eigen::Vector3d stylus_offset_mm = Eigen::Vector3d::Zero();
};

/// The nominal (error-free) measurement of the ring: points on r(θ) at height h, exact unit
/// normals, and the sampling's placement, mode, temperature reading and stylus offset.
/// Throws InvalidInput if the diameter is not finite and positive, N < 3, an order < 1, a
/// value is not finite, or Σ k·|a_k| ≥ D/4 (the profile must stay a smooth star-shaped curve
/// far from self-intersection; real form deviations are 1e-6 of that). O(N·K).
Measurement ring_gauge_measurement(const RingGauge& ring, const RingSampling& sampling);

}  // namespace vcmm::errormodel
