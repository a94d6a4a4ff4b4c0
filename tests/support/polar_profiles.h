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

/// One case of the *_from_extremes tests' seed sweep: the regime seed mod kPolarRegimes, the
/// size kPolarCaseSizes[(seed / 6) mod 5], equiangular directions, the regime's deviations.
inline constexpr std::size_t kPolarCaseSizes[] = {8, 17, 64, 360, 3600};
struct PolarCase {
  PolarRegime regime;
  std::size_t n;
  geometry::PolarDirections directions;
  std::vector<double> deviation;
  /// The profile about radius 85.5 mm (it refers to this case's directions and deviations).
  geometry::PolarProfile profile() const { return {85.5, deviation, &directions}; }
};
PolarCase polar_case(std::uint64_t seed);

}  // namespace vcmm::test
