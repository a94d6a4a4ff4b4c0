// gaussian_filter_open.cpp — the Gaussian profile filter for an open profile: a partial arc of
// a roundness profile (ISO 16610-21, clause 4: open profiles), with the end effects treated by
// preserving the weighting function's zeroth and first moments.
//
// Notation as in gaussian_filter.cpp: cut-off f_c (UPR), λ_c = 2π/f_c (rad), α = √(ln 2/π),
// weighting function s(θ) ∝ exp(−π (θ/(α λ_c))²). The arc is parametrised by the angle θ about
// the LS centre, unwrapped so that it runs from the end of the largest angular gap (θ = 0) to
// its start (θ = Φ, the arc's span); d_j = r_j − R the radial deviations.
//
// Interior. The mean line at θ_i is the weighted mean Σ q_j s(θ_i − θ_j) d_j / Σ q_j s(θ_i − θ_j)
// with trapezoidal weights q_j (as the closed filter's nonuniform path), s truncated at
// ±4 α λ_c (neglected mass ~2e-24).
// End effects. Within 4 α λ_c of an end the window is cut off on one side: the plain weighted
// mean would then be biased towards the interior by the profile's slope (a tilted arc would bend
// at its ends). Here the mean line is the value at θ_i of the weighted least-squares line
// through the window — minimise Σ g_j (d_j − a − b (θ_j − θ_i))², g_j = q_j s(θ_i − θ_j):
//   a = (S2 T0 − S1 T1) / (S0 S2 − S1²),  S_k = Σ g_j (θ_j − θ_i)^k,  T_k = Σ g_j (θ_j − θ_i)^k d_j,
// which keeps the zeroth and first moments of the weighting (constant and linear components pass
// unchanged up to the ends). Where the window is symmetric, S1 = T1's weight vanishes and a is
// the weighted mean: the interior is the ISO 16610-21 open-profile filter. (ISO 16610-28 lists
// treatments of end effects; this is the moment-preserving one — we have not checked it against
// that standard's text.)
// Continuity. An interior gap wider than λ_c/2 leaves the window nothing to average over: it is
// refused, as for the closed filter.
// Reconstruction: each point moved along its ray from the LS centre to R + a_i (input order).
// Complexity O(n log n + n·m), m the points within ±4 α λ_c.
#include "vcmm/geometry/gaussian_filter.h"

#include <algorithm>
#include <limits>
#include <cmath>
#include <numbers>
#include <sstream>
#include <vector>

#include "internal/prevalidated.h"
#include "vcmm/geometry/angular_coverage.h"

namespace vcmm::geometry {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kAlpha = 0.46971863934982566;  // sqrt(ln 2 / π)

}  // namespace

FilteredProfile gaussian_filtered_open_profile(std::span<const Point2> points, double cutoff_upr) {
  constexpr const char* kCaller = "gaussian_filtered_open_profile";
  validate_profile(points, 8, kCaller);
  if (!(std::isfinite(cutoff_upr) && cutoff_upr > 0.0)) {
    std::ostringstream os;
    os << kCaller << ": the cut-off must be a finite number of UPR > 0; got " << cutoff_upr;
    throw InvalidInput(os.str());
  }
  const std::size_t n = points.size();
  const LeastSquaresCircle ls = internal::fit_least_squares_circle(points);
  const AngularCoverage coverage = angular_coverage(points, ls.center);
  // θ = 0 at the point that ends the largest gap (its own direction, so it gets exactly 0).
  const Point2 first = points[coverage.gap_end_index];
  const double start = std::atan2(first.y - ls.center.y, first.x - ls.center.x);

  std::vector<double> theta(n), dev(n), inv_r(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = points[i].x - ls.center.x, dy = points[i].y - ls.center.y;
    const double r = std::sqrt(dx * dx + dy * dy);
    if (!(r > 0.0)) {
      std::ostringstream os;
      os << kCaller << ": point " << i << " coincides with the least-squares centre";
      throw InvalidInput(os.str());
    }
    double t = std::atan2(dy, dx) - start;
    t -= 2.0 * kPi * std::floor(t / (2.0 * kPi));  // [0, 2π)
    theta[i] = t;
    dev[i] = r - ls.radius;
    inv_r[i] = 1.0 / r;
  }
  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return theta[a] < theta[b] || (theta[a] == theta[b] && a < b);
  });
  const double lambda = 2.0 * kPi / cutoff_upr;
  for (std::size_t j = 0; j + 1 < n; ++j) {
    const double gap = theta[order[j + 1]] - theta[order[j]];
    if (gap > 0.5 * lambda) {
      std::ostringstream os;
      os << kCaller << ": the arc is not continuous: an angular gap of " << gap * 180.0 / kPi
         << "° between points " << order[j] << " and " << order[j + 1] << " exceeds λc/2 = "
         << 180.0 / cutoff_upr << "° (cut-off " << cutoff_upr << " UPR)";
      throw InvalidInput(os.str());
    }
  }
  // Sorted angles, deviations and trapezoidal weights (half intervals at the ends).
  std::vector<double> t(n), d(n), q(n);
  for (std::size_t j = 0; j < n; ++j) {
    t[j] = theta[order[j]];
    d[j] = dev[order[j]];
  }
  for (std::size_t j = 0; j < n; ++j) {
    const double left = j > 0 ? t[j] - t[j - 1] : 0.0;
    const double right = j + 1 < n ? t[j + 1] - t[j] : 0.0;
    q[j] = 0.5 * (left + right);
  }
  // A run of equal angles has zero weights: give each point of the run an equal share.
  for (std::size_t j = 0; j < n; ++j)
    if (q[j] == 0.0) q[j] = std::numeric_limits<double>::min();
  const double width = kAlpha * lambda;  // α λ_c
  const double window = 4.0 * width;
  const double a = kPi / (width * width);
  std::vector<double> filtered(n);
  std::size_t lo = 0, hi = 0;  // the window [lo, hi) of sorted indices about point i
  for (std::size_t i = 0; i < n; ++i) {
    while (t[i] - t[lo] > window) ++lo;
    while (hi < n && t[hi] - t[i] <= window) ++hi;
    double s0 = 0, s1 = 0, s2 = 0, t0 = 0, t1 = 0;
    for (std::size_t j = lo; j < hi; ++j) {
      const double delta = t[j] - t[i];
      const double g = q[j] * std::exp(-a * delta * delta);
      s0 += g;
      s1 += g * delta;
      s2 += g * delta * delta;
      t0 += g * d[j];
      t1 += g * delta * d[j];
    }
    const double det = s0 * s2 - s1 * s1;
    // A window holding one distinct angle has no slope: its weighted mean.
    filtered[i] = det > 1e-14 * s0 * s2 ? (s2 * t0 - s1 * t1) / det : t0 / s0;
  }
  FilteredProfile out;
  out.filter_center = ls.center;
  out.mean_radius = ls.radius;
  out.path = FilterPath::open_profile;
  out.points.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t i = order[j];
    const double f = (filtered[j] - dev[i]) * inv_r[i];
    out.points[i] = {points[i].x + (points[i].x - ls.center.x) * f,
                     points[i].y + (points[i].y - ls.center.y) * f};
  }
  return out;
}

}  // namespace vcmm::geometry
