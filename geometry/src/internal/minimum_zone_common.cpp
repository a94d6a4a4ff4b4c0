// internal/minimum_zone_common.cpp — building the public minimum-zone result from an exact
// contact set (shared by the fast exchange path and the Voronoi-overlay method).
//
// Notation. Outer contacts o1, o2 (on R), inner contacts i1, i2 (on r). The centre c is the
// intersection of the perpendicular bisectors
//   (o2 − o1)·c = (|o2|² − |o1|²)/2,   (i2 − i1)·c = (|i2|² − |i1|²)/2,
// solved by Cramer's rule on coordinates relative to o1. Every double is an integer times a
// power of two, so with E the least exponent among the eight coordinates (of their lowest
// set bit), the local coordinates P = (p − o1)·2^−E are integers and, with b = P(o2),
// e = P(i1), d = P(i2), a = d − e:
//   D = 2(b × a),  X = |b|² a_y − b_y (d + e)·a,  Y = b_x (d + e)·a − |b|² a_x,
//   c = o1 + 2^E (X, Y)/D,  R² = 4^E (X² + Y²)/D²,  r² = 4^E ((X − e_x D)² + (Y − e_y D)²)/D²
// — integer ring operations only (no gcd: several times faster than rationals). Each
// reported double is the correctly rounded quotient (MPFR), one rounding; centre and radii
// also get a low part (internal/precise_distance.h) for the containment pass's second-stage
// filter on thin zones. Then
//   R − r = (R² − r²) / (R + r),
// where R² − r² is the exact integer difference rounded once and R, r are the rounded square
// roots of the rounded R², r² (each within ~1 ulp): the quotient is within a few ulps of
// R − r itself (no cancellation), which matters when R ≈ 85 mm and R − r ≈ 1e-4 mm.
#include "internal/minimum_zone_common.h"

#include <gmp.h>
#include <mpfr.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "internal/exact.h"
#include "internal/minimum_zone_exact.h"
#include "internal/precise_distance.h"

namespace vcmm::geometry::internal {

std::optional<ExactAnnulus> exact_annulus(std::span<const Point2> points,
                                          std::array<std::size_t, 2> outer,
                                          std::array<std::size_t, 2> inner) {
  const Point2 o1 = points[outer[0]], o2 = points[outer[1]];
  const Point2 i1 = points[inner[0]], i2 = points[inner[1]];
  if (o1 == o2 || i1 == i2) return std::nullopt;
  // Local coordinates: o1 at the origin.
  const Rational ox(o1.x), oy(o1.y);
  const Rational bx = Rational(o2.x) - ox, by = Rational(o2.y) - oy;
  const Rational ex = Rational(i1.x) - ox, ey = Rational(i1.y) - oy;
  const Rational dx = Rational(i2.x) - ox, dy = Rational(i2.y) - oy;
  // b·c = |b|²/2 ;  (d − e)·c = (|d|² − |e|²)/2
  const Rational ax = dx - ex, ay = dy - ey;
  const Rational det = bx * ay - by * ax;
  if (CGAL::is_zero(det)) return std::nullopt;
  const Rational rhs1 = (bx * bx + by * by) / 2;
  const Rational rhs2 = ((dx + ex) * ax + (dy + ey) * ay) / 2;  // (|d|² − |e|²)/2
  const Rational cx = (rhs1 * ay - by * rhs2) / det;
  const Rational cy = (bx * rhs2 - rhs1 * ax) / det;
  ExactAnnulus out;
  out.outer_sq = cx * cx + cy * cy;
  const Rational qx = cx - ex, qy = cy - ey;
  out.inner_sq = qx * qx + qy * qy;
  out.center = {cx + ox, cy + oy};
  return out;
}

namespace {

/// Minimal RAII holder of a GMP integer.
class Int {
 public:
  Int() { mpz_init(v_); }
  ~Int() { mpz_clear(v_); }
  Int(const Int&) = delete;
  Int& operator=(const Int&) = delete;
  mpz_ptr get() { return v_; }
  mpz_srcptr get() const { return v_; }

 private:
  mpz_t v_;
};

/// Exponent of the lowest set bit of a finite nonzero double (v = odd · 2^result).
int low_bit_exponent(double v) {
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(v);
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  std::uint64_t mantissa = bits & ((std::uint64_t{1} << 52) - 1);
  if (biased != 0) mantissa |= std::uint64_t{1} << 52;  // normal: implicit bit
  const int exponent = (biased != 0 ? biased : 1) - 1075;  // v = mantissa · 2^exponent
  return exponent + std::countr_zero(mantissa);
}

/// out = v · 2^−E, exact (v a multiple of 2^E).
void set_scaled(mpz_ptr out, double v, int E) {
  if (v == 0.0) {
    mpz_set_ui(out, 0);
    return;
  }
  int e = 0;
  const double m = std::ldexp(std::frexp(v, &e), 53);  // |m| < 2^53, integer
  mpz_set_d(out, m);
  const int shift = e - 53 - E;
  if (shift >= 0) {
    mpz_mul_2exp(out, out, static_cast<mp_bitcnt_t>(shift));
  } else {
    mpz_tdiv_q_2exp(out, out, static_cast<mp_bitcnt_t>(-shift));  // exact: low bits are 0
  }
}

/// Nearest double of num/den · 2^exp (den > 0): MPFR division, one rounding. The two MPFR
/// numbers are kept per thread (set_prec reuses their limbs when they suffice).
double rounded_quotient(mpz_srcptr num, mpz_srcptr den, long exp) {
  if (mpz_sgn(num) == 0) return 0.0;
  struct Scratch {
    mpfr_t n, q;
    Scratch() {
      mpfr_init2(n, 64);
      mpfr_init2(q, 53);
    }
    ~Scratch() {
      mpfr_clear(n);
      mpfr_clear(q);
    }
    Scratch(const Scratch&) = delete;
    Scratch& operator=(const Scratch&) = delete;
  };
  thread_local Scratch s;
  mpfr_set_prec(s.n,
                static_cast<mpfr_prec_t>(std::max<std::size_t>(mpz_sizeinbase(num, 2), 2)));
  mpfr_set_z(s.n, num, MPFR_RNDN);  // exact: precision = bit length
  mpfr_mul_2si(s.n, s.n, exp, MPFR_RNDN);  // exact: a power of two
  mpfr_div_z(s.q, s.n, den, MPFR_RNDN);
  return mpfr_get_d(s.q, MPFR_RNDN);  // exact: q has 53 bits
}

/// The integers of rounded_annulus, kept per thread (~30 heap allocations a call before;
/// every one is written before it is read, so nothing carries over between calls).
struct AnnulusScratch {
  Int c[8];
  Int bx, by, ex, ey, dx, dy, ax, ay, t1, t2, D, r1, r2, X, Y, NR, Nr, D2, Cx, Cy;
};

}  // namespace

std::optional<RoundedAnnulus> rounded_annulus(std::span<const Point2> points,
                                              std::array<std::size_t, 2> outer,
                                              std::array<std::size_t, 2> inner,
                                              bool low_parts) {
  const Point2 q[4] = {points[outer[0]], points[outer[1]], points[inner[0]], points[inner[1]]};
  if (q[0] == q[1] || q[2] == q[3]) return std::nullopt;
  int E = std::numeric_limits<int>::max();
  for (const Point2& p : q)
    for (const double v : {p.x, p.y})
      if (v != 0.0) E = std::min(E, low_bit_exponent(v));
  if (E == std::numeric_limits<int>::max()) return std::nullopt;  // all zero: coincident
  thread_local AnnulusScratch w;
  Int(&c)[8] = w.c;
  for (int i = 0; i < 4; ++i) {
    set_scaled(c[2 * i].get(), q[i].x, E);
    set_scaled(c[2 * i + 1].get(), q[i].y, E);
  }
  Int &bx = w.bx, &by = w.by, &ex = w.ex, &ey = w.ey, &dx = w.dx, &dy = w.dy, &ax = w.ax,
      &ay = w.ay, &t1 = w.t1, &t2 = w.t2, &D = w.D, &r1 = w.r1, &r2 = w.r2, &X = w.X, &Y = w.Y;
  mpz_sub(bx.get(), c[2].get(), c[0].get());
  mpz_sub(by.get(), c[3].get(), c[1].get());
  mpz_sub(ex.get(), c[4].get(), c[0].get());
  mpz_sub(ey.get(), c[5].get(), c[1].get());
  mpz_sub(dx.get(), c[6].get(), c[0].get());
  mpz_sub(dy.get(), c[7].get(), c[1].get());
  mpz_sub(ax.get(), dx.get(), ex.get());
  mpz_sub(ay.get(), dy.get(), ey.get());
  // D = 2 (b × a)
  mpz_mul(t1.get(), bx.get(), ay.get());
  mpz_mul(t2.get(), by.get(), ax.get());
  mpz_sub(D.get(), t1.get(), t2.get());
  if (mpz_sgn(D.get()) == 0) return std::nullopt;  // parallel bisectors
  mpz_mul_2exp(D.get(), D.get(), 1);
  // r1 = |b|², r2 = (d + e)·a
  mpz_mul(r1.get(), bx.get(), bx.get());
  mpz_addmul(r1.get(), by.get(), by.get());
  mpz_add(t1.get(), dx.get(), ex.get());
  mpz_mul(r2.get(), t1.get(), ax.get());
  mpz_add(t1.get(), dy.get(), ey.get());
  mpz_addmul(r2.get(), t1.get(), ay.get());
  // X = r1 a_y − b_y r2,  Y = b_x r2 − r1 a_x
  mpz_mul(X.get(), r1.get(), ay.get());
  mpz_submul(X.get(), by.get(), r2.get());
  mpz_mul(Y.get(), bx.get(), r2.get());
  mpz_submul(Y.get(), r1.get(), ax.get());
  if (mpz_sgn(D.get()) < 0) {
    mpz_neg(D.get(), D.get());
    mpz_neg(X.get(), X.get());
    mpz_neg(Y.get(), Y.get());
  }
  // NR = X² + Y², Nr = (X − e_x D)² + (Y − e_y D)²
  Int &NR = w.NR, &Nr = w.Nr, &D2 = w.D2, &Cx = w.Cx, &Cy = w.Cy;
  mpz_mul(NR.get(), X.get(), X.get());
  mpz_addmul(NR.get(), Y.get(), Y.get());
  mpz_set(t1.get(), X.get());
  mpz_submul(t1.get(), ex.get(), D.get());
  mpz_set(t2.get(), Y.get());
  mpz_submul(t2.get(), ey.get(), D.get());
  mpz_mul(Nr.get(), t1.get(), t1.get());
  mpz_addmul(Nr.get(), t2.get(), t2.get());
  mpz_mul(D2.get(), D.get(), D.get());
  RoundedAnnulus out;
  out.valid = mpz_cmp(Nr.get(), NR.get()) < 0;
  // Centre: o1 + 2^E X/D = 2^E (O1·D + X)/D with O1 = o1·2^−E an integer.
  mpz_set(Cx.get(), X.get());
  mpz_addmul(Cx.get(), c[0].get(), D.get());
  mpz_set(Cy.get(), Y.get());
  mpz_addmul(Cy.get(), c[1].get(), D.get());
  if (!low_parts) {
    out.center = {rounded_quotient(Cx.get(), D.get(), E), rounded_quotient(Cy.get(), D.get(), E)};
    out.outer_sq = rounded_quotient(NR.get(), D2.get(), 2L * E);
    out.inner_sq = rounded_quotient(Nr.get(), D2.get(), 2L * E);
    mpz_sub(t1.get(), NR.get(), Nr.get());
    out.diff_sq = rounded_quotient(t1.get(), D2.get(), 2L * E);
    return out;
  }
  // The same correctly rounded doubles, with the low parts for the second-stage filter.
  double ex_err = 0.0, ey_err = 0.0, eo_err = 0.0, ei_err = 0.0;
  const TwoDoubles cx = split_quotient(Cx.get(), D.get(), E, &ex_err);
  const TwoDoubles cy = split_quotient(Cy.get(), D.get(), E, &ey_err);
  const TwoDoubles o2 = split_quotient(NR.get(), D2.get(), 2L * E, &eo_err);
  const TwoDoubles i2 = split_quotient(Nr.get(), D2.get(), 2L * E, &ei_err);
  out.center = {cx.hi, cy.hi};
  out.outer_sq = o2.hi;
  out.inner_sq = i2.hi;
  out.outer_precise = {cx, cy, std::max(ex_err, ey_err), o2, eo_err, 1.0, true};
  out.outer_precise.usable = std::isfinite(out.outer_precise.center_error) &&
                             std::isfinite(eo_err);
  out.inner_precise = out.outer_precise;
  out.inner_precise.r2 = i2;
  out.inner_precise.r2_error = ei_err;
  out.inner_precise.usable = out.outer_precise.usable && std::isfinite(ei_err);
  mpz_sub(t1.get(), NR.get(), Nr.get());
  out.diff_sq = rounded_quotient(t1.get(), D2.get(), 2L * E);
  return out;
}

void normalise_duplicate_indices(std::span<const Point2> points,
                                 std::span<std::size_t> indices) {
  for (std::size_t& idx : indices) {
    const Point2 p = points[idx];
    for (std::size_t j = 0; j < idx; ++j) {
      if (points[j] == p) {
        idx = j;
        break;
      }
    }
  }
}

namespace {

/// RONq about the mean circle of radius rm centred at c, in double on coordinates relative
/// to the centre: d_i = (|p_i − c|² − rm²) / (|p_i − c| + rm) avoids the cancellation of
/// |p_i − c| − rm (both ≈ 85 mm, difference ≈ 1e-4 mm).
double rms_deviation(std::span<const Point2> points, Point2 c, double rm) {
  double sum = 0.0;
  const double rm2 = rm * rm;
  for (const Point2& p : points) {
    const double dx = p.x - c.x, dy = p.y - c.y;
    const double s = dx * dx + dy * dy;
    const double d = (s - rm2) / (std::sqrt(s) + rm);
    sum += d * d;
  }
  return std::sqrt(sum / static_cast<double>(points.size()));
}

}  // namespace

MinimumZoneCircle make_minimum_zone_result(std::span<const Point2> points,
                                           const RoundedAnnulus& annulus,
                                           std::array<std::size_t, 2> outer,
                                           std::array<std::size_t, 2> inner,
                                           Certificate certificate,
                                           std::optional<double> ronq,
                                           bool indices_normalised) {
  MinimumZoneCircle out;
  out.center = annulus.center;
  out.outer_radius = std::sqrt(annulus.outer_sq);
  out.inner_radius = std::sqrt(annulus.inner_sq);
  const double sum = out.outer_radius + out.inner_radius;
  out.ron.ront = sum > 0.0 ? annulus.diff_sq / sum : 0.0;
  out.ron.ronp = 0.5 * out.ron.ront;
  out.ron.ronv = 0.5 * out.ron.ront;
  out.ron.ronq = ronq ? *ronq : rms_deviation(points, out.center, 0.5 * sum);

  std::array<std::size_t, 4> idx = {outer[0], outer[1], inner[0], inner[1]};
  if (!indices_normalised) normalise_duplicate_indices(points, idx);
  out.outer_contacts = {std::min(idx[0], idx[1]), std::max(idx[0], idx[1])};
  out.inner_contacts = {std::min(idx[2], idx[3]), std::max(idx[2], idx[3])};
  out.certificate = std::move(certificate);
  return out;
}

MinimumZoneCircle make_minimum_zone_result(std::span<const Point2> points,
                                           std::array<std::size_t, 2> outer,
                                           std::array<std::size_t, 2> inner,
                                           Certificate certificate) {
  for (std::size_t idx : {outer[0], outer[1], inner[0], inner[1]}) {
    if (idx >= points.size()) {
      std::ostringstream os;
      os << "make_minimum_zone_result: contact index " << idx << " out of range (n = "
         << points.size() << ")";
      throw std::logic_error(os.str());
    }
  }
  const std::optional<RoundedAnnulus> annulus = rounded_annulus(points, outer, inner);
  if (!annulus || !annulus->valid) {
    std::ostringstream os;
    os << "make_minimum_zone_result: outer contacts {" << outer[0] << ", " << outer[1]
       << "} and inner contacts {" << inner[0] << ", " << inner[1] << "} "
       << (annulus ? "give r >= R (the inner pair is not strictly inside the outer circle)"
                   : "have coincident points or parallel perpendicular bisectors");
    throw std::logic_error(os.str());
  }
  return make_minimum_zone_result(points, *annulus, outer, inner, std::move(certificate),
                                  std::nullopt);
}

MinimumZoneCircle make_cocircular_result(std::span<const Point2> points, std::size_t a,
                                         std::size_t b, std::size_t c) {
  for (std::size_t idx : {a, b, c}) {
    if (idx >= points.size()) {
      std::ostringstream os;
      os << "make_cocircular_result: index " << idx << " out of range (n = " << points.size()
         << ")";
      throw std::logic_error(os.str());
    }
  }
  const Point2 pa = points[a], pb = points[b], pc = points[c];
  // Circumcentre relative to pa: q·center = |q|²/2 for q = pb − pa and q = pc − pa.
  const Rational ax(pa.x), ay(pa.y);
  const Rational bx = Rational(pb.x) - ax, by = Rational(pb.y) - ay;
  const Rational cx = Rational(pc.x) - ax, cy = Rational(pc.y) - ay;
  const Rational det = bx * cy - by * cx;
  if (CGAL::is_zero(det)) {
    std::ostringstream os;
    os << "make_cocircular_result: points " << a << ", " << b << ", " << c
       << " are collinear (or coincide): they define no circle";
    throw std::logic_error(os.str());
  }
  const Rational b2 = (bx * bx + by * by) / 2, c2 = (cx * cx + cy * cy) / 2;
  const Rational ux = (b2 * cy - by * c2) / det;
  const Rational uy = (bx * c2 - b2 * cx) / det;
  MinimumZoneCircle out;
  out.center = to_point(RationalPoint{ux + ax, uy + ay});
  out.outer_radius = std::sqrt(to_double(ux * ux + uy * uy));
  out.inner_radius = out.outer_radius;
  out.ron = {};  // all points lie exactly on the circle: every deviation is exactly 0

  std::array<std::size_t, 3> idx = {a, b, c};
  normalise_duplicate_indices(points, idx);
  std::sort(idx.begin(), idx.end());
  out.outer_contacts = {idx[0], idx[1], idx[2]};
  out.inner_contacts = out.outer_contacts;
  out.certificate.optimality = Optimality::global;
  std::ostringstream os;
  os << "all " << points.size()
     << " points lie exactly on one circle (exact in-circle tests): zone width 0, "
        "the least possible";
  out.certificate.argument = os.str();
  out.certificate.region_radius = 0.0;
  return out;
}

}  // namespace vcmm::geometry::internal
