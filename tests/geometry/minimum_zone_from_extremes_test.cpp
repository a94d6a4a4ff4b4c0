// Tests of the minimum zone from a subset of extremes (vcmm/geometry/minimum_zone_from_extremes.h)
// against the minimum zone of all points, over regimes (smooth form, form + noise, pure noise,
// few points, several lobe counts); seeds in the messages.
#include "vcmm/geometry/minimum_zone_from_extremes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "vcmm/geometry/minimum_zone.h"

namespace vcmm::geometry {
namespace {

// The minimum zone from a subset equals the minimum zone of all points: smooth form, form plus
// noise (filtered and not), pure noise, few points, a lobed profile. Seeds in the messages.
TEST(MinimumZoneFromExtremes, EqualsTheMinimumZoneOfAllPoints) {
  MinimumZoneScratch scratch;
  std::vector<Point2> points;
  std::vector<double> deviation;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    std::mt19937_64 gen(seed);
    std::uniform_real_distribution<double> uniform;
    std::normal_distribution<double> normal;
    const std::size_t n = seed % 4 == 0 ? 60 : 3600;
    const double noise_mm = seed % 3 == 0 ? 0.0 : 1e-3 * uniform(gen);
    const double form_mm = seed % 5 == 0 ? 0.0 : 2e-3 * uniform(gen);
    const double lobes = 2.0 + static_cast<double>(seed % 7);
    const double phase = 6.0 * uniform(gen);
    points.resize(n);
    deviation.resize(n);
    for (std::size_t j = 0; j < n; ++j) {
      const double t = 2 * std::numbers::pi * static_cast<double>(j) / static_cast<double>(n);
      deviation[j] = form_mm * std::cos(lobes * t + phase) + noise_mm * normal(gen) +
                     1e-6 * std::cos(17 * t);
      const double r = 85.5 + deviation[j];
      points[j] = {3.0 + r * std::cos(t), -2.0 + r * std::sin(t)};  // off-centre: any frame
    }
    const double exact = minimum_zone_circle(points).ron.ront;
    const double fast = minimum_zone_ront_from_extremes(points, deviation, scratch);
    EXPECT_NEAR(fast, exact, 1e-12) << "seed " << seed << ", n " << n;
  }
  EXPECT_THROW(minimum_zone_ront_from_extremes(points, std::vector<double>(3), scratch),
               InvalidInput);
}

}  // namespace
}  // namespace vcmm::geometry
