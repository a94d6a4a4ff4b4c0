// tests/support/polar_profiles.h — polar profiles (vcmm/geometry/polar_profile.h) for the tests
// and benchmarks of the *_from_extremes functions: equiangular directions, and deviations in
// the regimes those functions must get right. Deterministic in the seed (test_profiles.h's
// own uniform and normal deviates: the same numbers with any standard library).
#pragma once

#include <cstdint>
#include <vector>

#include "vcmm/geometry/polar_profile.h"

namespace vcmm::test {

/// u_j = (cos 2πj/n, sin 2πj/n), j < n (n ≥ 8).
geometry::PolarDirections equiangular_directions(std::size_t n);

enum class PolarRegime {
  band_limited,  ///< a filtered form: harmonics 2 … K (K random ≤ 152) of amplitude ~2 µm/k
  noise,         ///< unfiltered white noise, σ = 1 µm: an extremum every few points
  offset,        ///< a form of 0.1 µm plus a centre offset of 2 µm: contacts deep below the top
  near_circle,   ///< σ = 1e-14 mm: every point within rounding of one circle
  circle,        ///< all zero: only the rounding of cos, sin and r·u
  lobed,         ///< one pure lobe count (2 … 8): every lobe's extremum ties to rounding
};
inline constexpr int kPolarRegimes = 6;

/// n deviations (mm) of the regime.
std::vector<double> polar_deviations(PolarRegime regime, std::size_t n, std::uint64_t seed);

}  // namespace vcmm::test
