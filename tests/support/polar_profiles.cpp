// tests/support/polar_profiles.cpp — see polar_profiles.h.
#include "support/polar_profiles.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numbers>
#include <utility>

#include "support/test_profiles.h"

namespace vcmm::test {

geometry::PolarDirections equiangular_directions(std::size_t n) {
  std::vector<double> c(n), s(n);
  for (std::size_t j = 0; j < n; ++j) {
    const double t = 2 * std::numbers::pi * static_cast<double>(j) / static_cast<double>(n);
    c[j] = std::cos(t);
    s[j] = std::sin(t);
  }
  return geometry::PolarDirections(std::move(c), std::move(s));
}

std::vector<double> polar_deviations(PolarRegime regime, std::size_t n, std::uint64_t seed) {
  std::uint64_t state = seed;
  std::vector<double> d(n, 0.0);
  const auto add_harmonic = [&](std::size_t k, double amplitude, double phase) {
    for (std::size_t j = 0; j < n; ++j)
      d[j] += amplitude * std::cos(2 * std::numbers::pi * static_cast<double>(k * j) /
                                       static_cast<double>(n) + phase);
  };
  const auto phase = [&] { return 2 * std::numbers::pi * uniform01(state); };
  const std::size_t half = n / 2;
  switch (regime) {
    case PolarRegime::band_limited: {
      const auto top = std::min<std::size_t>(
          half, 3 + static_cast<std::size_t>(150.0 * uniform01(state)));
      for (std::size_t k = 2; k <= top; ++k)
        add_harmonic(k, 2e-3 * standard_normal(state) / static_cast<double>(k), phase());
      break;
    }
    case PolarRegime::noise:
      for (double& x : d) x = 1e-3 * standard_normal(state);
      break;
    case PolarRegime::offset:
      for (std::size_t k = 2; k <= std::min<std::size_t>(half, 20); ++k)
        add_harmonic(k, 1e-4 * standard_normal(state), phase());
      add_harmonic(1, 2e-3, phase());
      break;
    case PolarRegime::near_circle:
      for (double& x : d) x = 1e-14 * standard_normal(state);
      break;
    case PolarRegime::circle:
      break;
    case PolarRegime::lobed: {
      const std::size_t most = std::min<std::size_t>(8, half - 1);
      add_harmonic(2 + static_cast<std::size_t>(static_cast<double>(most - 1) * uniform01(state)),
                   1e-3, 0.0);
      break;
    }
  }
  return d;
}

PolarCase polar_case(std::uint64_t seed) {
  const auto regime = static_cast<PolarRegime>(seed % kPolarRegimes);
  const std::size_t n = kPolarCaseSizes[(seed / 6) % std::size(kPolarCaseSizes)];
  return {regime, n, equiangular_directions(n), polar_deviations(regime, n, seed)};
}

}  // namespace vcmm::test
