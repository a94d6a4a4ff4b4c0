#include "support/test_profiles.h"

#include <cmath>
#include <numbers>

namespace vcmm::test {

namespace {
std::uint64_t splitmix64(std::uint64_t& s) {
  std::uint64_t z = (s += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}
}  // namespace

double uniform01(std::uint64_t& state) {
  return static_cast<double>(splitmix64(state) >> 11) * 0x1.0p-53;
}

double standard_normal(std::uint64_t& state) {
  double u1 = uniform01(state);
  while (u1 <= 0.0) u1 = uniform01(state);
  const double u2 = uniform01(state);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

std::vector<Point2> ring_profile(const RingSpec& spec) {
  std::vector<Point2> pts;
  pts.reserve(spec.n);
  std::uint64_t state = spec.seed * 0x2545F4914F6CDD1DULL + 12345u;
  const double span = spec.span > 0.0 ? spec.span : 2.0 * std::numbers::pi;
  const double step = span / static_cast<double>(spec.n);
  for (std::size_t i = 0; i < spec.n; ++i) {
    double t = spec.start_angle + step * static_cast<double>(i);
    if (spec.angle_jitter > 0.0) t += (uniform01(state) - 0.5) * spec.angle_jitter * step;
    double r = spec.radius;
    for (const auto& h : spec.harmonics) r += h.amplitude * std::cos(h.order * t + h.phase);
    if (spec.noise_sigma > 0.0) r += spec.noise_sigma * standard_normal(state);
    pts.push_back({spec.center.x + r * std::cos(t), spec.center.y + r * std::sin(t)});
  }
  return pts;
}

std::vector<Point2> lobed_noisy_ring(std::size_t n, std::uint64_t seed, double noise_sigma,
                                     Point2 center) {
  RingSpec spec;
  spec.center = center;
  spec.n = n;
  spec.seed = seed;
  spec.noise_sigma = noise_sigma;
  spec.harmonics = {{2, 1.0e-4, 0.3}, {3, 6.0e-5, 1.1}, {5, 3.0e-5, 2.0},
                    {7, 2.0e-5, 0.7}, {15, 1.0e-5, 2.9}};
  return ring_profile(spec);
}

std::vector<Point2> random_points(std::size_t n, std::uint64_t seed, double scale) {
  std::uint64_t state = seed * 0x9E3779B97F4A7C15ULL + 7u;
  std::vector<Point2> pts(n);
  for (auto& p : pts) p = {scale * uniform01(state), scale * uniform01(state)};
  return pts;
}

}  // namespace vcmm::test
