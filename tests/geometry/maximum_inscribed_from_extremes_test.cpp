// Tests of the maximum-inscribed circle from a subset of extremes
// (vcmm/geometry/maximum_inscribed_from_extremes.h) against maximum_inscribed_circle on all
// points, over the regimes of the minimum-zone analogue's test: band-limited profiles of
// several bandwidths and sizes, unfiltered noise, a large centre offset (the inner contacts
// far from the starting valleys: several rounds), nearly perfect and exact circles, pure lobed
// forms (symmetric near-ties); seeds in the messages.
#include "vcmm/geometry/maximum_inscribed_from_extremes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "vcmm/geometry/maximum_inscribed.h"

namespace vcmm::geometry {
namespace {

PolarDirections equiangular(std::size_t n) {
  std::vector<double> c(n), s(n);
  for (std::size_t j = 0; j < n; ++j) {
    const double t = 2 * std::numbers::pi * static_cast<double>(j) / static_cast<double>(n);
    c[j] = std::cos(t);
    s[j] = std::sin(t);
  }
  return PolarDirections(std::move(c), std::move(s));
}

enum class Regime { band_limited, noise, offset, near_circle, circle, lobed };

std::vector<double> deviations(Regime regime, std::size_t n, std::mt19937_64& gen) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal;
  std::vector<double> d(n, 0.0);
  const auto add_harmonic = [&](std::size_t k, double amplitude, double phase) {
    for (std::size_t j = 0; j < n; ++j)
      d[j] += amplitude * std::cos(2 * std::numbers::pi * static_cast<double>(k * j) /
                                       static_cast<double>(n) + phase);
  };
  const std::size_t half = n / 2;
  switch (regime) {
    case Regime::band_limited: {
      const std::size_t top = std::min<std::size_t>(half, 3 + gen() % 150);
      for (std::size_t k = 2; k <= top; ++k)
        add_harmonic(k, 2e-3 * normal(gen) / static_cast<double>(k), 6.3 * uniform(gen));
      break;
    }
    case Regime::noise:
      for (double& x : d) x = 1e-3 * normal(gen);
      break;
    case Regime::offset:
      for (std::size_t k = 2; k <= std::min<std::size_t>(half, 20); ++k)
        add_harmonic(k, 1e-4 * normal(gen), 6.3 * uniform(gen));
      add_harmonic(1, 2e-3, 6.3 * uniform(gen));
      break;
    case Regime::near_circle:
      for (double& x : d) x = 1e-14 * normal(gen);
      break;
    case Regime::circle:
      break;
    case Regime::lobed:
      add_harmonic(3 + gen() % std::min<std::size_t>(6, half - 2), 1e-3, 0.0);
      break;
  }
  return d;
}

// RONt bit for bit as maximum_inscribed_circle on all points reports it, in every regime
// (and the same centre where the MI is unique: not on exact circles or symmetric lobes).
TEST(MaximumInscribedFromExtremes, EqualsTheMaximumInscribedCircleOfAllPoints) {
  ExtremesScratch scratch;
  const std::vector<std::size_t> sizes{8, 17, 64, 360, 3600};
  int fast_paths = 0, rounds_above_one = 0;
  for (std::uint64_t seed = 1; seed <= 300; ++seed) {
    std::mt19937_64 gen(seed);
    const auto regime = static_cast<Regime>(seed % 6);
    const std::size_t n = sizes[(seed / 6) % sizes.size()];
    const PolarDirections directions = equiangular(n);
    const std::vector<double> d = deviations(regime, n, gen);
    const PolarProfile profile{85.5, d, &directions};
    std::vector<Point2> points(n);
    for (std::size_t j = 0; j < n; ++j) points[j] = polar_point(profile, j);
    const MaximumInscribedCircle full = maximum_inscribed_circle(points);
    const double fast = maximum_inscribed_ront_from_extremes(profile, scratch);
    EXPECT_EQ(fast, full.ron.ront) << "seed " << seed << ", n " << n;
    if (regime != Regime::circle && regime != Regime::lobed && regime != Regime::near_circle) {
      EXPECT_EQ(scratch.center, full.center) << "seed " << seed << ", n " << n;
    }
    fast_paths += scratch.fell_back ? 0 : 1;
    rounds_above_one += !scratch.fell_back && scratch.rounds > 1 ? 1 : 0;
  }
  EXPECT_GT(fast_paths, 150);  // most profiles are decided by their subset
  EXPECT_GT(rounds_above_one, 0);
}

TEST(MaximumInscribedFromExtremes, RejectsBadInput) {
  ExtremesScratch scratch;
  const PolarDirections directions = equiangular(16);
  EXPECT_THROW(
      maximum_inscribed_ront_from_extremes({85.0, std::vector<double>(15), &directions}, scratch),
      InvalidInput);
  std::vector<double> d(16, 0.0);
  d[3] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(maximum_inscribed_ront_from_extremes({85.0, d, &directions}, scratch),
               InvalidInput);
}

}  // namespace
}  // namespace vcmm::geometry
