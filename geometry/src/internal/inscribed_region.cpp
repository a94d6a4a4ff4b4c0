// internal/inscribed_region.cpp — the MI region argument (derivation in
// internal/inscribed_region.h). Every floating quantity is replaced by a rigorous bound;
// the comments give the margins (all generous).
#include "internal/inscribed_region.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

#include "internal/precise_distance.h"

namespace vcmm::geometry::internal {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = std::numbers::pi;
/// Angular buckets of (c), one representative each: 1024 keep enough of the shallow points
/// beside a contact for their caps to close the gap down to a few t1 on smooth 2-lobe forms
/// (with 256 the region left to exhaust was ~4× wider); the per-scale work is ~B log B.
constexpr int kBuckets = 1024;
/// Intervals of (c) at most (each halves t): 2⁻⁶⁴ of t_cov is far below any t1 that a
/// non-degenerate contact triangle gives.
constexpr int kMaxScales = 64;

/// Longest circular run of empty buckets among the 256.
int longest_empty_run(const std::array<std::uint64_t, 4>& occ) {
  auto is_set = [&](int b) { return ((occ[b >> 6] >> (b & 63)) & 1u) != 0; };
  int first = -1;
  for (int b = 0; b < 256; ++b)
    if (is_set(b)) {
      first = b;
      break;
    }
  if (first < 0) return 256;
  int longest = 0, run = 0;
  for (int k = 1; k <= 256; ++k) {
    const int b = (first + k) % 256;
    if (is_set(b)) {
      longest = std::max(longest, run);
      run = 0;
    } else {
      ++run;
    }
  }
  return longest;
}

/// The quadratic of (b) at ρ = R_hi: t² + R_hi² − 2t·R_hi·cos_lo − r_lo² < 0, with its
/// floating evaluation error (< 8u·S, S the sum of the magnitudes) covered twice.
bool coverage_quadratic_negative(double t, double r_lo, double r_hi, double cos_lo) {
  const double u = kUnitRoundoff;
  const double s = t * t + r_hi * r_hi + 2.0 * t * r_hi + r_lo * r_lo;
  const double q2 = t * t + r_hi * r_hi - 2.0 * t * r_hi * cos_lo - r_lo * r_lo;
  return q2 < -16.0 * u * s;
}

struct Representative {
  double eps_hi = kInf;     ///< ≥ ρ_p² − r*² (scaled units)
  double x = 0.0, y = 0.0;  ///< p − c̃ (scaled)
  double theta = 0.0;       ///< atan2(y, x), once the pass is done
  bool used = false;
};

/// Does the union of the caps of (2), for t anywhere in [ta, tb], cover every direction?
bool caps_cover(const std::vector<Representative>& reps, double ta, double tb, double r_lo,
                double eta) {
  std::vector<std::pair<double, double>> arcs;  // [start, end), start ∈ [−π, π)
  arcs.reserve(reps.size());
  for (const Representative& r : reps) {
    if (!r.used) continue;
    const double eps = std::max(r.eps_hi, 0.0);
    // q = max over the ends (convex in t); the 1e-12 factor covers the few roundings.
    const double q = std::max((eps + ta * ta) / (2.0 * ta * r_lo),
                              (eps + tb * tb) / (2.0 * tb * r_lo)) *
                     (1.0 + 1e-12);
    if (!(q < 1.0)) continue;
    // acos within a few ulps (1e-15 rad), the direction within eta: shrink by both.
    const double half = std::acos(q) - eta - 1e-15;
    if (!(half > 0.0)) continue;
    double start = r.theta - half;
    if (start < -kPi) start += 2.0 * kPi;
    arcs.emplace_back(start, start + 2.0 * half);
  }
  if (arcs.empty()) return false;
  std::sort(arcs.begin(), arcs.end());
  // Covered from −π up to `reach` (exclusive) by the arcs seen; arcs running past π wrap.
  double reach = -kPi;
  for (const auto& [s, e] : arcs)
    if (e > kPi) reach = std::max(reach, e - 2.0 * kPi);
  for (const auto& [s, e] : arcs) {
    if (!(s < reach)) return false;  // a gap at s (open arcs: touching is not enough)
    reach = std::max(reach, e);
  }
  return reach > kPi;
}

}  // namespace

InscribedRegion inscribed_region(std::span<const Point2> points, const ExactCircle& circle,
                                 const std::array<std::size_t, 3>& contacts, double max_d2,
                                 const std::array<std::uint64_t, 4>& occupied, Point2 c0) {
  InscribedRegion out;
  out.radius = kInf;
  // Everything in the filter's scaled units (lengths × circle.scale, r* ≈ 1): the
  // inequalities are homogeneous, and no square leaves the double range.
  const double u = kUnitRoundoff;
  const double delta = circle.center_error_scaled;
  // r*s ∈ [r̃(1 − 2.3u), r̃(1 + 2.3u)] (extremal_circle.cpp); 8u leaves room for roundings.
  const double r_lo = circle.radius_scaled * (1.0 - 8.0 * u);
  if (!circle.filter_usable || !(r_lo > 100.0 * delta)) return out;
  // R_max = max |p − c*| ≤ √(D̃max(1 + 4.1u)) + δ; ×(1 + 8u) covers sqrt and sum roundings.
  const double r_hi = (std::sqrt(max_d2 * (1.0 + 5.0 * u)) + delta) * (1.0 + 8.0 * u);

  // (a) β: contact directions from c̃. |ŵ(a) − ŵ(b)| ≤ 2|a − b|/|a| for unit vectors of
  // a, b, so each computed v_k is within η = 2δ/r_lo + 1e-14 (rounding of the
  // normalisation, ~4u, with a wide margin) of the exact one; |v_k + v_l|/2 moves by ≤ η.
  std::array<double, 3> vx{}, vy{};
  for (int k = 0; k < 3; ++k) {
    const double dx = circle.center_d.x - points[contacts[static_cast<std::size_t>(k)]].x;
    const double dy = circle.center_d.y - points[contacts[static_cast<std::size_t>(k)]].y;
    const double l = std::hypot(dx, dy);
    vx[static_cast<std::size_t>(k)] = dx / l;
    vy[static_cast<std::size_t>(k)] = dy / l;
  }
  double beta = 1.0;
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t l = (k + 1) % 3;
    beta = std::min(beta, 0.5 * std::hypot(vx[k] + vx[l], vy[k] + vy[l]));
  }
  const double eta = 2.0 * delta / r_lo + 1e-14;
  const double beta_lo = beta - eta - 1e-15;
  if (!(beta_lo > 0.0)) return out;
  const double t1 = 2.0 * r_lo * beta_lo * (1.0 - 4.0 * u);
  out.t1 = t1;
  if (t1 >= r_hi) {  // the local disc alone contains H ⊂ disc(c*, R_max)
    out.proven = true;
    out.radius = 0.0;
    return out;
  }

  // (b) Angular gap about c*. The buckets were filled about the warm start c₀:
  // consecutive points are < (E + 2) buckets of 1/64 pseudo unit apart about c₀, plus
  // 1e-14 for the pseudo-angle's own rounding (a few ulps of a value ≤ 4); ×2 converts to
  // radians. From c₀ to c* the direction of p turns by the angle at p of the triangle
  // (c₀, c*, p), at most asin(d₀/ρ) ≤ (π/2)·d₀/r_lo with d₀ = |c* − c₀| ≤ |c̃ − c₀|(1 + 4u)
  // + δ and ρ ≥ r* ≥ r_lo (no point is inside); so gaps grow by at most π·d₀/r_lo.
  const int empty = longest_empty_run(occupied);
  if (empty >= 200) return out;
  const double d0 = std::hypot(circle.center_d.x - c0.x, circle.center_d.y - c0.y) *
                        circle.scale * (1.0 + 4.0 * u) +
                    delta;
  if (!(d0 < 0.5 * r_lo)) return out;
  const double gap = 2.0 * ((empty + 2) / 64.0 + 1e-14) + kPi * d0 / r_lo * (1.0 + 1e-12);
  const double h = 0.5 * gap;
  if (!(h < 1.5)) return out;
  // cos is within 1 ulp in glibc; subtract 1e-15 absolute for it and for h's rounding.
  const double cos_lo = std::cos(h) - 1e-15;
  if (!(cos_lo > 0.0)) return out;
  // ρ = r*: t² − 2t·r*·cos h < 0 for t < 2r_lo·cos_lo; at t = R_hi it must hold (margin
  // 1e-12 relative), and the quadratic in ρ = R_max must be negative there.
  if (!(r_hi * (1.0 + 1e-12) < 2.0 * r_lo * cos_lo)) return out;
  if (!coverage_quadratic_negative(r_hi, r_lo, r_hi, cos_lo)) return out;
  // t_cov: just above the smaller root of t² − 2A t + C (A = R_hi cos_lo, C = R_hi² − r_lo²),
  // computed without cancellation and then checked rigorously; both quadratics are convex
  // in t, so negative at t_cov and at R_hi means negative in between.
  const double A = r_hi * cos_lo, C = r_hi * r_hi - r_lo * r_lo;
  const double disc = A * A - C;
  if (!(disc > 0.0)) return out;
  double t_cov = std::max(C, 0.0) / (A + std::sqrt(disc)) * (1.0 + 1e-9) + 1e-300;
  if (!coverage_quadratic_negative(t_cov, r_lo, r_hi, cos_lo)) {
    t_cov = t_cov * (1.0 + 1e-6) + 1e-12 * r_lo;
    if (!coverage_quadratic_negative(t_cov, r_lo, r_hi, cos_lo)) return out;
  }
  out.t_cov = t_cov;
  if (t1 >= t_cov) {
    out.proven = true;
    out.radius = 0.0;
    return out;
  }

  // (c) Least ε per angular bucket about c̃, from one pass. ε_p = d² − r*² with d the
  // exact scaled distance: from D̃ = fl(X² + Y²) (X = fl(p − c̃)·s), d ≤ √(D̃(1 + 4.1u)) + δ
  // (extremal_circle.cpp) and r* ≥ r_lo give ε ≤ D̃ − r_lo² + 8u(D̃ + r_lo²) + 2.01δ√D̃ + δ²;
  // where that bound is too coarse to rank the points (ε below 2²⁰u: perfect circles, the
  // contacts' neighbours) the double-double gap is used (value + its rigorous bound).
  std::vector<Representative> reps(kBuckets);
  const Point2 c = circle.center_d;
  const double s = circle.scale;
  const PreciseCircle* precise = circle.precise().usable ? &circle.precise() : nullptr;
  for (const Point2& p : points) {
    const double x = (p.x - c.x) * s, y = (p.y - c.y) * s;
    const double d2 = x * x + y * y;
    // √D̃ ≤ (D̃ + 1)/2 (AM-GM; D̃ ≈ 1 here): no square root per point.
    double eps = d2 - r_lo * r_lo + 8.0 * u * (d2 + r_lo * r_lo) +
                 1.01 * delta * (d2 + 1.0) + delta * delta;
    if (eps < 0x1.0p20 * u && precise != nullptr) {
      const PreciseValue v = precise_power_gap(*precise, p);
      if (std::isfinite(v.value) && std::isfinite(v.bound)) eps = std::min(eps, v.value + v.bound);
    }
    auto b = static_cast<int>(pseudo_angle(x, y) * (kBuckets / 4.0));
    b = std::clamp(b, 0, kBuckets - 1);
    Representative& r = reps[static_cast<std::size_t>(b)];
    if (!r.used || eps < r.eps_hi) r = {eps, x, y, 0.0, true};
  }
  for (Representative& r : reps)
    if (r.used) r.theta = std::atan2(r.y, r.x);
  // Directions about c̃ instead of c*: off by at most asin(δ/ρ) ≤ 1.001δ/r_lo, plus atan2's
  // own rounding (a few ulps of π).
  const double eta_dir = 1.001 * delta / r_lo + 1e-14;
  double tb = t_cov;
  while (tb > t1) {
    if (out.scales == kMaxScales) {
      out.radius = tb;
      break;
    }
    ++out.scales;
    const double ta = std::max(0.5 * tb, t1);
    if (!caps_cover(reps, ta, tb, r_lo, eta_dir)) {
      out.radius = tb;
      break;
    }
    tb = ta;
  }
  if (!(tb > t1)) {
    out.proven = true;
    out.radius = 0.0;
    return out;
  }
  // The caller exhausts a disc of radius up to 2ρ* (+ rounding margins) about c*: it must
  // lie inside H, whose boundary is ≥ r*·cos h from c* (some point lies within h of every
  // edge's outward normal, at distance ≥ r* from c*).
  if (!(2.0 * out.radius * (1.0 + 1e-9) + 64.0 * delta < r_lo * cos_lo)) out.radius = kInf;
  return out;
}

}  // namespace vcmm::geometry::internal
