// reference_values.cpp — reference roundness and reference diameter from a roundness-meter
// profile (vcmm/validation/reference_values.h, docs/validation.md "Reference values").
//
// Notation. Profile samples (θ_j, d_j), j = 0 … n−1, θ strictly increasing in [0, 2π), d the
// radial deviation (mm) about the meter's axis; u_j = (cos θ_j, sin θ_j); R = R_nom.
//
// (1) Why R_nom matters only at second order. The evaluated points are p_j = (R + d_j) u_j.
// About any centre c with |c| = e ≪ R,
//   |p_j − c| = (R + d_j) − c·u_j + (c × u_j)² / (2 (R + d_j)) + O(e³/R²),
// so the local deviations are the "limaçon" d_j − c·u_j — independent of R — plus a term in
// [0, e²/(2(R − max|d|))]. Every reference circle is a max/min or least-squares criterion over
// these deviations, so RONt moves by O(e²/R): for MZ |min_c f − min_c g| ≤ sup_c |f − g|
// ≤ e²/(2R) per circle, i.e. ≤ e²/R for the width. The Gaussian filter works on deviations
// about the LS centre at angles about that centre, which differ from θ_j by at most ~e/R; the
// filtered deviation then moves by about max|d'|·e/R (d' per radian) at each end of the
// peak-to-valley. Together: |ΔRONt| ≲ e·(e + 2·max|d'|)/R, with e the distance of the
// reference centre from the meter axis (the profile's eccentricity, plus at most about the
// peak-to-valley t for the form). tests/validation/reference_values_test.cpp measures the
// 1/R scaling. Choosing R_nom as the part's radius makes the points the true surface points.
//
// (2) Reference diameter. The interferometer measures L = r(0) + r(π) with r = R + d, so
// 2R = L − d(0) − d(π) and the mean diameter 2·mean(r) = L + 2·mean(d) − d(0) − d(π)
//   D = L + 2·(m − s),   s = (d(0) + d(π)) / 2,   m = (1/2π) ∮ d(θ) dθ.
// Both the mean and d(0), d(π) are taken on the periodic piecewise-linear interpolant of the
// samples: m by the trapezoidal rule, m = Σ_j w_j d_j, w_j = (h_{j−1} + h_j)/(2·Σh) with h_j
// = θ_{j+1} − θ_j (h_{n−1} = θ_0 + 2π − θ_{n−1}); d(0) = (1 − λ) d_lo + λ d_hi between the
// bracketing samples. For equiangular samples w_j = 1/n, the plain mean. D is linear in the
// readings: D = L + Σ_j c_j d_j, c_j = 2 w_j − λ⁰_j − λ¹⁸⁰_j, Σ_j c_j = 0 (a constant offset
// of the meter cancels). Independent readings with standard uncertainty u_p then give
// u_D² = u_L² + u_p² Σ_j c_j² — the correlation of d(0), d(π) with the mean that contains
// them is in the c_j. Equiangular samples through 0° and 180°: c = 2/n − 1 at those two and
// 2/n elsewhere, Σ c² = 2(1 − 2/n)² + (n − 2)·4/n² = 2 − 4/n: the naive "shift with u_p/√2,
// coefficient 2" gives the leading 2 u_p², the shared samples remove 4 u_p²/n.
// Interpolation error of d(0) for a smooth profile: |d(0) − interpolant| ≤ h²/8 · max|d''|
// over the bracketing interval h (the linear-interpolation remainder).
#include "vcmm/validation/reference_values.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/minimum_circumscribed.h"
#include "vcmm/geometry/minimum_zone.h"

namespace vcmm::validation {
namespace {

using geometry::InvalidInput;
using geometry::Point2;
constexpr double kPi = std::numbers::pi;

double degrees(double rad) { return rad * 180.0 / kPi; }

/// An angle (rad) in degrees for messages: 12 significant digits, so that 11° computed from
/// radians reads "11", not "10.999999999999998".
std::string degree_text(double rad) {
  std::ostringstream os;
  os.precision(12);
  os << degrees(rad);
  return os.str();
}

std::string number_text(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

/// d at angle t ∈ [0, 2π) on the periodic piecewise-linear interpolant:
/// d(t) = (1 − weight_hi)·d[lo] + weight_hi·d[hi]; interval = bracketing width (0: sampled).
struct Bracket {
  std::size_t lo = 0;
  std::size_t hi = 0;
  double weight_hi = 0.0;
  double interval = 0.0;
};

Bracket bracket(const std::vector<double>& a, double t) {
  const std::size_t n = a.size();
  const auto it = std::lower_bound(a.begin(), a.end(), t);
  if (it != a.end() && *it == t) {
    const auto j = static_cast<std::size_t>(it - a.begin());
    return {j, j, 0.0, 0.0};
  }
  Bracket b;
  double a_lo = 0.0, a_hi = 0.0;
  if (it == a.begin()) {  // t before the first sample: wrap from the last
    b.lo = n - 1;
    b.hi = 0;
    a_lo = a[n - 1] - 2 * kPi;
    a_hi = a[0];
  } else if (it == a.end()) {  // t after the last sample: wrap to the first
    b.lo = n - 1;
    b.hi = 0;
    a_lo = a[n - 1];
    a_hi = a[0] + 2 * kPi;
  } else {
    b.hi = static_cast<std::size_t>(it - a.begin());
    b.lo = b.hi - 1;
    a_lo = a[b.lo];
    a_hi = a[b.hi];
  }
  b.interval = a_hi - a_lo;
  b.weight_hi = (t - a_lo) / b.interval;
  return b;
}

double value_at(const Bracket& b, const std::vector<double>& d) {
  return b.lo == b.hi ? d[b.lo] : (1.0 - b.weight_hi) * d[b.lo] + b.weight_hi * d[b.hi];
}

void require_finite_non_negative(double v, const char* caller, const char* name) {
  if (!std::isfinite(v) || v < 0.0)
    throw InvalidInput(std::string(caller) + ": " + name + " must be finite and >= 0; got " +
                       number_text(v));
}

template <class Circle>
void take_circle(const Circle& c, ReferenceRoundness& out, std::span<const Point2> points) {
  out.ron = c.ron;
  out.center = c.center;
  out.certificate = c.certificate;
  out.verification = geometry::verify(points, c);
}

}  // namespace

ReferenceRoundness reference_roundness(const RoundnessProfile& profile,
                                       const ReferenceRoundnessOptions& options) {
  constexpr const char* kCaller = "reference_roundness";
  validate_roundness_profile(profile, kCaller);
  const std::size_t n = profile.angle_rad.size();
  double max_abs = 0.0;
  for (double d : profile.deviation_mm) max_abs = std::max(max_abs, std::abs(d));
  const double radius = options.nominal_radius_mm;
  if (!std::isfinite(radius) || !(radius > max_abs))
    throw InvalidInput(std::string(kCaller) +
                       ": nominal_radius_mm must be finite and exceed the largest |deviation| (" +
                       number_text(max_abs) + " mm); got " + number_text(radius));
  require_finite_non_negative(options.u_instrument_mm, kCaller, "u_instrument_mm");
  if (options.filter_cutoff_upr) {
    const double fc = *options.filter_cutoff_upr;
    if (!std::isfinite(fc) || !(fc > 0.0) || fc > 0.5 * static_cast<double>(n))
      throw InvalidInput(std::string(kCaller) +
                         ": filter_cutoff_upr must be finite, > 0 and <= n/2 = " +
                         number_text(0.5 * static_cast<double>(n)) + "; got " + number_text(fc));
    // The filter's closedness rule (gaussian_filter.h): no gap wider than λc/2 = π / f_c.
    const double max_gap = kPi / fc;
    for (std::size_t j = 0; j < n; ++j) {
      const std::size_t k = j + 1 < n ? j + 1 : 0;
      const double gap =
          (k == 0 ? profile.angle_rad[0] + 2 * kPi : profile.angle_rad[k]) - profile.angle_rad[j];
      if (gap > max_gap)
        throw InvalidInput(std::string(kCaller) + ": " +
                           geometry::profile_sample_location(profile, j) + ": angular gap of " +
                           degree_text(gap) + " deg to the next sample (at " +
                           degree_text(profile.angle_rad[k]) +
                           " deg) exceeds lambda_c/2 = 180/f_c = " + degree_text(max_gap) +
                           " deg: the filter would bridge it");
    }
  }

  std::vector<Point2> points(n);
  for (std::size_t j = 0; j < n; ++j) {
    const double r = radius + profile.deviation_mm[j];
    points[j] = {r * std::cos(profile.angle_rad[j]), r * std::sin(profile.angle_rad[j])};
  }
  std::vector<Point2> filtered;
  std::span<const Point2> evaluated = points;
  if (options.filter_cutoff_upr) {
    filtered = geometry::gaussian_filtered_profile(points, *options.filter_cutoff_upr).points;
    evaluated = filtered;
  }

  ReferenceRoundness out;
  out.reference_circle = options.reference_circle;
  out.filter_cutoff_upr = options.filter_cutoff_upr;
  out.u_mm = options.u_instrument_mm;
  switch (options.reference_circle) {
    case ReferenceCircle::minimum_zone: {
      const auto c = geometry::minimum_zone_circle(evaluated);
      take_circle(c, out, evaluated);
      out.radius_mm = 0.5 * (c.inner_radius + c.outer_radius);
      break;
    }
    case ReferenceCircle::maximum_inscribed: {
      const auto c = geometry::maximum_inscribed_circle(evaluated);
      take_circle(c, out, evaluated);
      out.radius_mm = c.radius;
      break;
    }
    case ReferenceCircle::minimum_circumscribed: {
      const auto c = geometry::minimum_circumscribed_circle(evaluated);
      take_circle(c, out, evaluated);
      out.radius_mm = c.radius;
      break;
    }
    case ReferenceCircle::least_squares: {
      const auto c = geometry::least_squares_circle(evaluated);
      out.ron = c.ron;
      out.center = c.center;
      out.radius_mm = c.radius;
      out.verification = {true, {}};
      break;
    }
  }
  out.value_mm = out.ron.ront;
  return out;
}

ReferenceDiameter reference_diameter(double interferometer_distance_mm,
                                     double u_interferometer_mm,
                                     const RoundnessProfile& profile,
                                     double u_profile_point_mm) {
  constexpr const char* kCaller = "reference_diameter";
  if (!std::isfinite(interferometer_distance_mm) || !(interferometer_distance_mm > 0.0))
    throw InvalidInput(std::string(kCaller) +
                       ": interferometer_distance_mm must be finite and > 0; got " +
                       number_text(interferometer_distance_mm));
  require_finite_non_negative(u_interferometer_mm, kCaller, "u_interferometer_mm");
  require_finite_non_negative(u_profile_point_mm, kCaller, "u_profile_point_mm");
  validate_roundness_profile(profile, kCaller);

  const std::vector<double>& a = profile.angle_rad;
  const std::vector<double>& d = profile.deviation_mm;
  const std::size_t n = a.size();
  // Trapezoidal weights of the periodic piecewise-linear interpolant.
  std::vector<double> gap(n);
  double total = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    gap[j] = (j + 1 < n ? a[j + 1] : a[0] + 2 * kPi) - a[j];
    total += gap[j];
  }
  std::vector<double> c(n);  // sensitivity of D to reading j
  double mean = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    const double w = (gap[j == 0 ? n - 1 : j - 1] + gap[j]) / (2.0 * total);
    c[j] = 2.0 * w;
    mean += w * d[j];
  }
  const Bracket b0 = bracket(a, 0.0);
  const Bracket b180 = bracket(a, kPi);
  for (const Bracket& b : {b0, b180}) {
    c[b.lo] -= b.lo == b.hi ? 1.0 : 1.0 - b.weight_hi;
    if (b.lo != b.hi) c[b.hi] -= b.weight_hi;
  }
  double sum_c2 = 0.0;
  for (double cj : c) sum_c2 += cj * cj;

  ReferenceDiameter out;
  out.interferometer_distance_mm = interferometer_distance_mm;
  out.deviation_at_0_mm = value_at(b0, d);
  out.deviation_at_180_mm = value_at(b180, d);
  out.shift_mm = 0.5 * (out.deviation_at_0_mm + out.deviation_at_180_mm);
  out.mean_deviation_mm = mean;
  out.correction_mm = 2.0 * (mean - out.shift_mm);
  out.value_mm = interferometer_distance_mm + out.correction_mm;
  out.interpolation_interval_0_rad = b0.interval;
  out.interpolation_interval_180_rad = b180.interval;
  out.u_interferometer_mm = u_interferometer_mm;
  out.profile_sensitivity = std::sqrt(sum_c2);
  out.u_profile_mm = u_profile_point_mm * out.profile_sensitivity;
  out.u_mm = std::hypot(u_interferometer_mm, out.u_profile_mm);
  return out;
}

}  // namespace vcmm::validation
