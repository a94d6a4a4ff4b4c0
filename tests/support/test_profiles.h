// tests/support/test_profiles.h — synthetic profiles for the test suites and benchmarks.
// Every generator is deterministic in its seed (std::mt19937_64 with our own transforms,
// so the numbers are the same with any standard library).
#pragma once

#include <cstdint>
#include <vector>

#include "vcmm/geometry/point.h"

namespace vcmm::test {

using geometry::Point2;

struct Harmonic {
  int order = 2;          ///< undulations per revolution
  double amplitude = 0.0; ///< radial amplitude (mm)
  double phase = 0.0;     ///< rad
};

struct RingSpec {
  Point2 center{0.0, 0.0};
  double radius = 85.5;              ///< mm (171 mm ring gauge)
  std::size_t n = 3600;              ///< points
  double start_angle = 0.0;          ///< rad
  double span = 0.0;                 ///< rad; 0 means a full revolution (closed profile)
  std::vector<Harmonic> harmonics;   ///< form deviation
  double noise_sigma = 0.0;          ///< radial Gaussian noise (mm)
  double angle_jitter = 0.0;         ///< uniform jitter of the sampling angle, fraction of step
  std::uint64_t seed = 1;
};

/// Points at angles start + span·i/n (span = 2π: closed, no repeated end point), radius
/// R + Σ a_k cos(k θ + φ_k) + noise.
std::vector<Point2> ring_profile(const RingSpec& spec);

/// A typical nearly-round measured profile: R = 85.5 mm, lobing of a few hundred nm
/// (orders 2, 3, 5, 7, 15) plus white noise of `noise_sigma` mm.
std::vector<Point2> lobed_noisy_ring(std::size_t n, std::uint64_t seed,
                                     double noise_sigma = 5e-5, Point2 center = {0, 0});

/// Uniform random points in the unit square [0,1]² scaled by `scale` (general position with
/// probability 1) — for small-n cross-checks.
std::vector<Point2> random_points(std::size_t n, std::uint64_t seed, double scale = 1.0);

/// Degenerate but valid inputs (issue 11): every point exactly co-circular, or co-circular to
/// the last ulp.
///
/// A polygon of n vertices (n a multiple of 8) on the circle of `radius` about the origin
/// whose coordinates have the exact symmetry of the square: the first octant comes from
/// cos/sin, the rest by exact reflections (swap, sign changes). So the 8 images of a vertex
/// are exactly co-circular about the origin, though different orbits differ in |p|² by an ulp
/// or so: exact ties everywhere, and a minimum zone one or two ulps wide.
std::vector<Point2> symmetric_polygon(std::size_t n, double radius = 85.5);

/// n distinct integer points exactly on the circle x² + y² = r², r = 5·13·17·29·37·41·53·61
/// (26 244 lattice points: Pythagorean triples), evenly spread in angle, scaled by 2⁻³¹
/// (exact) and moved by `center` (exact when its coordinates are multiples of 2⁻³¹ below 2²¹,
/// as the default): all n exactly co-circular, radius ≈ 73.2 mm. n ≤ 26 244.
std::vector<Point2> lattice_circle(std::size_t n, Point2 center = {600.0, 500.0});

/// Standard normal deviate from a uniform 64-bit stream (Box-Muller on our own uniform:
/// identical across standard libraries).
double standard_normal(std::uint64_t& state);
/// Uniform in [0, 1) from a splitmix64 state.
double uniform01(std::uint64_t& state);

}  // namespace vcmm::test
