#include "support/test_profiles.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <utility>

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

std::vector<Point2> symmetric_polygon(std::size_t n, double radius) {
  if (n == 0 || n % 8 != 0) throw std::invalid_argument("symmetric_polygon: n % 8 != 0");
  const std::size_t quarter = n / 4, eighth = n / 8;
  std::vector<Point2> first(quarter);  // angles 2πj/n, j in [0, n/4)
  for (std::size_t j = 0; j <= eighth && j < quarter; ++j) {
    const double t = 2.0 * std::numbers::pi * static_cast<double>(j) / static_cast<double>(n);
    first[j] = {radius * std::cos(t), radius * std::sin(t)};
  }
  for (std::size_t j = eighth + 1; j < quarter; ++j)  // reflection in the diagonal
    first[j] = {first[quarter - j].y, first[quarter - j].x};
  std::vector<Point2> pts;
  pts.reserve(n);
  for (int q = 0; q < 4; ++q)  // rotations by 90°: exact
    for (const Point2& p : first) {
      const Point2 r = q == 0 ? p : q == 1 ? Point2{-p.y, p.x} : q == 2 ? Point2{-p.x, -p.y}
                                                                          : Point2{p.y, -p.x};
      pts.push_back(r);
    }
  return pts;
}

std::vector<Point2> lattice_circle(std::size_t n, Point2 center) {
  // Every x + iy with x² + y² = r², r = ∏ p_k over the primes p_k ≡ 1 (mod 4) below: with
  // p_k = π_k·conj(π_k) in the Gaussian integers, x + iy = unit · ∏ π_k^a_k conj(π_k)^(2−a_k),
  // a_k ∈ {0, 1, 2}: 4·3⁸ = 26 244 distinct points (unique factorisation), sorted by angle.
  // |x|, |y| ≤ r ≈ 1.57e11: every partial product fits in int64.
  struct Gauss {
    std::int64_t re, im;
  };
  auto mul = [](Gauss a, Gauss b) {
    return Gauss{a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re};
  };
  static const std::vector<Gauss> all = [&] {
    const Gauss primes[] = {{1, 2}, {2, 3}, {1, 4}, {2, 5}, {1, 6}, {4, 5}, {2, 7}, {5, 6}};
    std::vector<Gauss> v{{1, 0}};
    for (const Gauss p : primes) {
      const Gauss q{p.re, -p.im};
      const Gauss choice[3] = {mul(p, p), mul(p, q), mul(q, q)};
      std::vector<Gauss> next;
      for (const Gauss z : v)
        for (const Gauss c : choice) next.push_back(mul(z, c));
      v = std::move(next);
    }
    std::vector<Gauss> out;
    for (const Gauss z : v)  // the four units
      for (const Gauss u : {Gauss{1, 0}, Gauss{0, 1}, Gauss{-1, 0}, Gauss{0, -1}})
        out.push_back(mul(z, u));
    std::sort(out.begin(), out.end(), [](Gauss a, Gauss b) {
      return std::atan2(static_cast<double>(a.im), static_cast<double>(a.re)) <
             std::atan2(static_cast<double>(b.im), static_cast<double>(b.re));
    });
    return out;
  }();
  if (n == 0 || n > all.size()) throw std::invalid_argument("lattice_circle: n out of range");
  std::vector<Point2> pts;
  pts.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Gauss z = all[i * all.size() / n];
    pts.push_back({center.x + std::ldexp(static_cast<double>(z.re), -31),
                   center.y + std::ldexp(static_cast<double>(z.im), -31)});
  }
  return pts;
}

}  // namespace vcmm::test
