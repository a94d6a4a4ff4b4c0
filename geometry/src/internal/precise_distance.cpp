// internal/precise_distance.cpp — the double-double second-stage filter (derivation in
// internal/precise_distance.h).
#include "internal/precise_distance.h"

#include <mpfr.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace vcmm::geometry::internal {

namespace {
constexpr double kU = 0x1.0p-53;
constexpr double kInf = std::numeric_limits<double>::infinity();
/// Absolute allowance for underflow (each subnormal rounding loses ≤ 2⁻¹⁰⁷⁴): 2⁻¹⁰⁰⁰ covers
/// any handful of them and stays normal.
constexpr double kTiny = 0x1.0p-1000;
}  // namespace

TwoDoubles split_quotient(mpz_srcptr num, mpz_srcptr den, long exp, double* error) {
  if (mpz_sgn(num) == 0) {
    *error = 0.0;
    return {};
  }
  // hi: the correctly rounded quotient (one MPFR division to 53 bits); lo: the rounding of
  // the remainder of a 160-bit quotient (2⁻¹⁶⁰ relative, far below lo's own ulp).
  // The three MPFR numbers are kept per thread (set_prec reuses their limbs when they
  // suffice); every one is written before it is read.
  struct Scratch {
    mpfr_t n, h, q;
    Scratch() {
      mpfr_init2(n, 64);
      mpfr_init2(h, 53);
      mpfr_init2(q, 160);
    }
    ~Scratch() {
      mpfr_clear(n);
      mpfr_clear(h);
      mpfr_clear(q);
    }
    Scratch(const Scratch&) = delete;
    Scratch& operator=(const Scratch&) = delete;
  };
  thread_local Scratch s;
  auto& n = s.n;
  auto& h = s.h;
  auto& q = s.q;
  mpfr_set_prec(n, static_cast<mpfr_prec_t>(std::max<std::size_t>(mpz_sizeinbase(num, 2), 2)));
  mpfr_set_z(n, num, MPFR_RNDN);       // exact: precision = bit length
  mpfr_mul_2si(n, n, exp, MPFR_RNDN);  // exact: a power of two
  mpfr_div_z(h, n, den, MPFR_RNDN);
  mpfr_div_z(q, n, den, MPFR_RNDN);    // |q − num/den·2^exp| ≤ 2⁻¹⁶⁰|q|
  TwoDoubles out;
  out.hi = mpfr_get_d(h, MPFR_RNDN);   // exact: h has 53 bits (or out of range)
  if (std::isfinite(out.hi) && out.hi != 0.0) {
    mpfr_sub_d(q, q, out.hi, MPFR_RNDN);  // exact: |q − hi| ≤ ulp(hi) spans < 160 bits
    out.lo = mpfr_get_d(q, MPFR_RNDN);    // within u|lo| (or half a subnormal ulp)
    *error = 0x1.0p-159 * std::fabs(out.hi) + kU * std::fabs(out.lo) + kTiny;
  } else {
    *error = kInf;  // beyond the double range (or underflowed to 0): no usable filter
  }
  return out;
}

PreciseValue precise_power_gap(const PreciseCircle& circle, Point2 p) {
  const double s = circle.scale;
  // Offsets p − c* = a + m + η per coordinate (header), then scaled by s (exact).
  const TwoDoubles dx = two_sum(p.x, -circle.cx.hi), dy = two_sum(p.y, -circle.cy.hi);
  const double mx0 = dx.lo - circle.cx.lo, my0 = dy.lo - circle.cy.lo;
  // kTiny stands for underflow losses; a normal number, since subnormal operands cost ~100
  // cycles each on x86 (and exact centres give center_error = 0).
  const double eta_x = (kU * std::fabs(mx0) + circle.center_error + kTiny) * s;
  const double eta_y = (kU * std::fabs(my0) + circle.center_error + kTiny) * s;
  const double ax = dx.hi * s, ay = dy.hi * s, mx = mx0 * s, my = my0 * s;
  const TwoDoubles P = two_product(ax, ax), Q = two_product(ay, ay);
  const TwoDoubles S = two_sum(P.hi, Q.hi);
  const TwoDoubles T = two_sum(S.hi, -circle.r2.hi);
  const double t_amx = 2.0 * ax * mx, t_amy = 2.0 * ay * my;
  const double t_mm = mx * mx + my * my;
  const double small = T.lo + S.lo + P.lo + Q.lo - circle.r2.lo + t_amx + t_amy + t_mm;
  PreciseValue out;
  out.value = T.hi + small;
  const double terms = std::fabs(T.lo) + std::fabs(S.lo) + std::fabs(P.lo) + std::fabs(Q.lo) +
                       std::fabs(circle.r2.lo) + std::fabs(t_amx) + std::fabs(t_amy) + t_mm;
  out.bound = 16.0 * kU * terms + 2.0 * kU * std::fabs(out.value) +
              (2.0 * (std::fabs(ax) + std::fabs(mx)) + eta_x) * eta_x +
              (2.0 * (std::fabs(ay) + std::fabs(my)) + eta_y) * eta_y + circle.r2_error +
              1e-300;
  return out;
}

int precise_annulus_side(const PreciseCircle& outer, const PreciseCircle& inner, Point2 p) {
  if (!outer.usable || !inner.usable) return 2;
  const PreciseValue o = precise_power_gap(outer, p);
  // Inner gap = outer gap + (R² − r²)s²: hi parts differ by a TwoSum, the rest rounds once.
  const TwoDoubles d = two_sum(outer.r2.hi, -inner.r2.hi);
  const double diff = d.hi + (d.lo + (outer.r2.lo - inner.r2.lo));
  PreciseValue i{o.value + diff, 0.0};
  i.bound = o.bound + inner.r2_error +
            4.0 * kU * (std::fabs(diff) + std::fabs(i.value) + std::fabs(outer.r2.lo) +
                        std::fabs(inner.r2.lo));
  const int so = sign_of(o), si = sign_of(i);
  if (so > 0) return 1;
  if (si < 0) return -1;
  if (so < 0 && si > 0) return 0;
  return 2;
}

namespace {

/// A double-double value hi + lo with a bound on its distance to the exact value it stands
/// for. Each operation adds the propagated errors and its own rounding: for a sum, TwoSum
/// of the high parts is exact and the low parts (≤ 3u(|a| + |b|) together) are rounded
/// twice, ≤ 6u²(|a| + |b|); for a product, TwoProduct of the high parts is exact, the
/// cross terms (≤ 2u|a||b|) and their sum with p.lo are rounded four times and the dropped
/// lo·lo is ≤ u²|a||b|:
/// ≤ 8u²|a||b|. 10u² covers both with the magnitudes taken as |hi| + |lo|.
struct Bounded {
  double hi = 0.0, lo = 0.0, err = 0.0;
  double magnitude() const { return std::fabs(hi) + std::fabs(lo); }
};

Bounded renormalised(double s, double t, double err) {
  const TwoDoubles r = two_sum(s, t);  // exact (s may have cancelled below |t|)
  return {r.hi, r.lo, err};
}

Bounded operator+(const Bounded& a, const Bounded& b) {
  const TwoDoubles s = two_sum(a.hi, b.hi);
  const double t = s.lo + (a.lo + b.lo);
  return renormalised(s.hi, t,
                      a.err + b.err + 10.0 * kU * kU * (a.magnitude() + b.magnitude()));
}

Bounded operator-(const Bounded& a) { return {-a.hi, -a.lo, a.err}; }
Bounded operator-(const Bounded& a, const Bounded& b) { return a + (-b); }

Bounded operator*(const Bounded& a, const Bounded& b) {
  const TwoDoubles p = two_product(a.hi, b.hi);
  const double t = p.lo + (a.hi * b.lo + a.lo * b.hi);
  const double ma = a.magnitude(), mb = b.magnitude();
  return renormalised(p.hi, t,
                      ma * b.err + mb * a.err + a.err * b.err + 10.0 * kU * kU * ma * mb);
}

Bounded exact_difference(double x, double y) {
  const TwoDoubles d = two_sum(x, y == 0.0 ? 0.0 : -y);
  return {d.hi, d.lo, 0.0};
}

}  // namespace

int precise_incircle(Point2 a, Point2 b, Point2 c, Point2 d) {
  // Stage 2: double-double with running error bounds (differences exact by TwoSum).
  const Bounded adx = exact_difference(a.x, d.x), ady = exact_difference(a.y, d.y);
  const Bounded bdx = exact_difference(b.x, d.x), bdy = exact_difference(b.y, d.y);
  const Bounded cdx = exact_difference(c.x, d.x), cdy = exact_difference(c.y, d.y);
  const Bounded alift = adx * adx + ady * ady, blift = bdx * bdx + bdy * bdy;
  const Bounded clift = cdx * cdx + cdy * cdy;
  const Bounded det = alift * (bdx * cdy - cdx * bdy) + blift * (cdx * ady - adx * cdy) +
                      clift * (adx * bdy - bdx * ady);
  const double value = det.hi + det.lo;
  const double bound = det.err + 2.0 * kU * std::fabs(value) + kTiny;
  if (!std::isfinite(value) || !std::isfinite(bound)) return 2;
  if (value > bound) return 1;
  if (value < -bound) return -1;
  return 2;
}

}  // namespace vcmm::geometry::internal
