// certificate.cpp — the independent exact checks of reference-circle certificates.
//
// Shares no code with the fitters (the only internal headers it includes, verify_distance.h and
// verify_inscribed_cover.h, serve verify() alone): its own rational arithmetic
// (CGAL::Exact_rational, GMP mpq), its own filters — a static floating-point filter with a
// proven error bound for the per-point distance comparisons (verify_distance.h), interval
// arithmetic (CGAL::Interval_nt) elsewhere, the exact path whenever a sign is uncertain — and
// its own predicates.
// Every decision is exact; no square root is ever taken of a rational — lengths are
// compared through squares by the identities below.
//
// Notation. p_j input points (exact rationals: every double is one); c the exact centre;
// o1, o2 the outer and i1, i2 the inner contacts of a minimum zone (MZ); R² = |c − o|²,
// r² = |c − i|²; w* = R − r = √R² − √r².
//
// (1) MZ centre. c is equidistant from o1, o2 and from i1, i2:
//       2 c·(o2 − o1) = |o2|² − |o1|²,   2 c·(i2 − i1) = |i2|² − |i1|²,
//     a 2×2 linear system solved by Cramer's rule; its determinant is
//     cross(o2 − o1, i2 − i1) (zero: parallel bisectors, no certificate).
//
// (2) Strict angular alternation about c, square-root free. The *directions* u_a = o_a − c,
//     v_b = i_b − c (points at different distances, so only signs of cross/dot products of
//     these vectors are used, never the points themselves). u1, u2 (not of one direction)
//     cut the circle of directions into two open arcs, (u1→u2) and (u2→u1) counter-
//     clockwise. w lies strictly inside the arc (a→b) iff
//       cross(a,b) > 0:  cross(a,w) > 0 and cross(w,b) > 0        (arc shorter than π)
//       cross(a,b) < 0:  not (cross(b,w) ≥ 0 and cross(w,a) ≥ 0)   (complement of the
//                        closed arc (b→a), which is shorter than π)
//       cross(a,b) = 0 (a = −b direction):  cross(a,w) > 0        (a half-plane)
//     The contacts alternate strictly iff one inner direction lies in each open arc. A
//     direction equal to u1 or u2 lies in neither, so ties fail, as they must.
//
// (3) Comparing differences of square roots, a, b, c, d ≥ 0 rational:
//       sign(p + q√m)         = sign(p) if q = 0, m = 0 or sign(p) = sign(q); sign(q) if
//                               p = 0; else sign(p)·sign(p² − q² m).
//       sign((√a − √b) − (√c − √d)) = sign(A − B), A = √a + √d, B = √b + √c ≥ 0
//                             = sign(A² − B²) = sign(T), T = e + 2√(ad) − 2√(bc),
//                               e = a + d − b − c.
//       With P = e + 2√(ad) (sign by the rule above): P ≤ 0 ⇒ sign T = −1, or 0 when P = 0
//       and bc = 0; P > 0 ⇒ sign T = sign(P² − 4bc) = sign((e² + 4ad − 4bc) + 4e√(ad)).
//     A reported length ℓ ≈ √a − √b is accepted when √a − √b ∈ [ℓ − tol, ℓ + tol], each end
//     x tested as sign(√a − √b − x) = sign((√a − √b) − (√(x²) − 0)) for x ≥ 0, and
//     = sign((√a − 0) − (√b − √(x²))) for x < 0.
//
// (4) MZ global optimality, re-derived. h(c) = R(c)² − r(c)² is convex piecewise linear;
//     for any c = c* + δ (s = |δ|) and any contacts o_j, i_k:
//       h(c) ≥ |c − o_j|² − |c − i_k|² = h* + 2 δ·(i_k − o_j)          (|δ|² cancels)
//     and if f(c) = R(c) − r(c) ≤ w*, using R(c) ≤ R* + s, r(c) ≤ r* + s (1-Lipschitz):
//       h(c) = f(c)(R(c) + r(c)) ≤ w*(R* + r* + 2s) = h* + 2 w* s.
//     Hence s · (max_{j,k} d·(i_k − o_j) − w*) ≤ 0 for d = δ/s. The max is the support
//     function of the parallelogram P = {i_k − o_j}; its minimum over unit d is the
//     distance from 0 to the nearest edge line of P when 0 is inside P. The edge lines of P
//     are the translates of the lines o1o2 and i1i2, so:
//       if the segments o1o2 and i1i2 cross properly and each contact lies farther than
//       w* from the line through the other pair, then no centre other than c* has a zone
//       as narrow as w*: c* is the unique global minimum (region radius 0).
//     (It subsumes the argument "|c − c*| ≤ w*²/(2(R*γ − 2w*))" with γ = min over unit d
//     of max_j(−u_j·d) + max_k(v_k·d): since max_{j,k} d·(i_k − o_j) ≥ R*γ − w*, that
//     argument's premise R*γ > 2w* implies the test above.) The comparisons are exact:
//     dist² = cross(e, q − a)²/|e|² > w*² ⟺ dist² − R² − r² + 2√(R² r²) > 0, by (3).
//     When that test fails, global optimality is re-checked by enumeration: every local
//     minimum of f has among its active contacts a strictly alternating 2+2 set, whose
//     exact annulus then holds all points (first-order optimality: the hulls of the outer
//     and inner unit directions meet; when they meet only in directions shared by an outer
//     and an inner contact on one ray, a move within the cone where f does not grow at
//     first order lowers it at second order, by ~t²(1/r − 1/R)/2; a data point as centre
//     is never a minimum), or it is the zero-width circle of co-circular data; conversely
//     every such set is a strict local minimum. As |c| → ∞, f tends to the convex-hull
//     width W (min over hull edges of the farthest point's distance to the edge line),
//     uniformly in the direction, so inf f < W is attained at a local minimum. The claim
//     holds iff no such set is narrower than w* and W ≥ w*. Outer contacts of a set are
//     hull vertices; its inner pair is a Delaunay edge whose nearest-point Voronoi edge
//     holds c (see check_global_by_enumeration). Above kMaxEnumeratedSets (hull-vertex
//     pairs × Delaunay edges) verify() reports the claim as not re-checkable.
//
// (5) MI global optimality, re-derived from scratch (not from the author's argument). The
//     distance to the nearest point, ρ(x), over the closed convex hull H is maximal at a
//     Voronoi vertex inside H or where a Voronoi edge crosses ∂H (inside a Voronoi cell ρ
//     is convex). Voronoi vertices = circumcentres of the Delaunay triangles (CGAL
//     Delaunay_triangulation_2 on exact predicates; every circumcircle is empty): any
//     with r² > r*² and centre in H refutes the claim. On a hull edge [h1, h2] (e = h2 −
//     h1), ρ(h1 + t e)² = t²|e|² + min_p (|h1 − p|² + 2t e·(h1 − p)): the lower envelope
//     of lines plus a convex term, maximal at the envelope's breakpoints; an edge with
//     |e|² ≤ 4 r*² cannot beat r* (ρ ≤ min(t, 1 − t)|e|). The envelope is computed
//     exactly (sorted slopes, convex-hull trick) for the longer edges only.
//
// (6) Exact squared distances, integers only. With the rational centre c = (X, Y)/D over one
//     denominator (D > 0; X, Y, D integers) and s ≥ 0 such that p·2^s and q·2^s are
//     integral (doubles are dyadic),
//       |p − c|² = G_s(p) / (D² 4^s),   G_s(p) = (P_x D − X 2^s)² + (P_y D − Y 2^s)²,  P = p·2^s,
//     so sign(|p − c|² − |q − c|²) = sign(G_s(p) − G_s(q)): GMP integer products and no
//     gcd (a canonicalised rational costs several times more). Every threshold the checks
//     compare distances with is the squared distance to an input point (a contact), so the
//     interval filter's undecided cases — all points, on perfect circles — take this path.
//
// Tolerances on reported doubles: the exact values are rounded once by a correct fitter,
// but the rounding of the centre alone moves every derived length by up to ~1.5 ulp of the
// largest coordinate, so all tolerances are in ulps of scale = max(|c_x|, |c_y|, R):
// centre 4 ulp, radii 8 ulp, RON parameters 16 ulp (each is a difference of two rounded
// distances about the rounded centre).
#include "vcmm/geometry/certificate.h"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/convex_hull_2.h>
#include <gmp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "internal/verify_distance.h"
#include "internal/verify_inscribed_cover.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/minimum_circumscribed.h"
#include "vcmm/geometry/minimum_zone.h"

namespace vcmm::geometry {
namespace {

using Q = CGAL::Exact_rational;
using IA = CGAL::Interval_nt<true>;  // protects the rounding mode itself
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Delaunay = CGAL::Delaunay_triangulation_2<Kernel>;

constexpr double kCentreUlps = 4.0;
constexpr double kRadiusUlps = 8.0;
constexpr double kParameterUlps = 16.0;

// ---- exact rational geometry ------------------------------------------------------------

struct QPoint {
  Q x;
  Q y;
};

QPoint to_q(Point2 p) { return {Q(p.x), Q(p.y)}; }
QPoint operator-(const QPoint& a, const QPoint& b) { return {a.x - b.x, a.y - b.y}; }
Q dot(const QPoint& a, const QPoint& b) { return a.x * b.x + a.y * b.y; }
Q cross(const QPoint& a, const QPoint& b) { return a.x * b.y - a.y * b.x; }
Q norm2(const QPoint& a) { return dot(a, a); }
int sgn(const Q& q) { return static_cast<int>(CGAL::sign(q)); }

IA to_ia(const Q& q) { return IA(CGAL::to_interval(q)); }

/// Sign of the orientation of (a, b, c): +1 counter-clockwise.
int orientation(const QPoint& a, const QPoint& b, const QPoint& c) {
  return sgn(cross(b - a, c - a));
}

/// The point equidistant from a1, a2 and from b1, b2 (derivation (1)); none when the two
/// perpendicular bisectors are parallel.
std::optional<QPoint> equidistant_point(const QPoint& a1, const QPoint& a2, const QPoint& b1,
                                        const QPoint& b2) {
  const QPoint e = a2 - a1;
  const QPoint f = b2 - b1;
  const Q det = cross(e, f);
  if (CGAL::is_zero(det)) return std::nullopt;
  const Q g = (norm2(a2) - norm2(a1)) / Q(2);
  const Q h = (norm2(b2) - norm2(b1)) / Q(2);
  return QPoint{(g * f.y - e.y * h) / det, (e.x * h - f.x * g) / det};
}

// ---- square roots compared without taking them (derivation (3)) -------------------------

/// sign(p + q·√m), m ≥ 0.
int sign_p_plus_q_sqrt(const Q& p, const Q& q, const Q& m) {
  const int sp = sgn(p);
  const int sq = sgn(q);
  if (sq == 0 || sgn(m) == 0) return sp;
  if (sp == 0) return sq;
  if (sp == sq) return sp;
  return sp * sgn(p * p - q * q * m);
}

/// sign((√a − √b) − (√c − √d)), all arguments ≥ 0.
int compare_sqrt_differences(const Q& a, const Q& b, const Q& c, const Q& d) {
  const Q e = a + d - b - c;
  const Q ad = a * d;
  const Q bc = b * c;
  const int sp = sign_p_plus_q_sqrt(e, Q(2), ad);
  if (sp < 0) return -1;
  if (sp == 0) return sgn(bc) == 0 ? 0 : -1;
  if (sgn(bc) == 0) return 1;
  return sign_p_plus_q_sqrt(e * e + Q(4) * ad - Q(4) * bc, Q(4) * e, ad);
}

/// sign(√a − √b − x), a, b ≥ 0, x any rational.
int sign_sqrt_difference_minus(const Q& a, const Q& b, const Q& x) {
  if (sgn(x) >= 0) return compare_sqrt_differences(a, b, x * x, Q(0));
  return compare_sqrt_differences(a, Q(0), b, x * x);
}

/// dist² > (√R² − √r²)², dist the distance of q from the line through a and b, i.e.
/// dist² − R² − r² + 2√(R² r²) > 0: intervals first, exact when they cannot tell.
bool exceeds_width_squared(const QPoint& a, const QPoint& b, const QPoint& q, const Q& outer2,
                           const Q& inner2) {
  const QPoint e = b - a;
  const Q cr = cross(e, q - a);
  {
    const IA cri = to_ia(cr), o2 = to_ia(outer2), i2 = to_ia(inner2);
    const IA v = cri * cri / to_ia(norm2(e)) - o2 - i2 + IA(2) * CGAL::sqrt(o2 * i2);
    if (v.inf() > 0.0) return true;
    if (v.sup() < 0.0) return false;
  }
  const Q dist2 = cr * cr / norm2(e);
  return sign_p_plus_q_sqrt(dist2 - outer2 - inner2, Q(2), outer2 * inner2) > 0;
}

/// Orientation of three input points, exactly (CGAL's filtered predicate).
int input_orientation(Point2 a, Point2 b, Point2 c) {
  return static_cast<int>(CGAL::orientation(Kernel::Point_2(a.x, a.y), Kernel::Point_2(b.x, b.y),
                                            Kernel::Point_2(c.x, c.y)));
}

// ---- alternation (derivation (2)) --------------------------------------------------------
// Written once for exact vectors (QPoint, exact signs) and for interval vectors (IPoint,
// signs that may be uncertain): the interval run decides when no sign was uncertain.

struct IPoint {
  IA x;
  IA y;
};
IA cross(const IPoint& a, const IPoint& b) { return a.x * b.y - a.y * b.x; }
IA dot(const IPoint& a, const IPoint& b) { return a.x * b.x + a.y * b.y; }

struct ExactSign {
  bool uncertain = false;  // never set: exact signs are always certain
  int operator()(const Q& v) const { return sgn(v); }
};

/// The sign of an interval; flags `uncertain` (and answers 0) when it straddles zero.
struct IntervalSign {
  bool uncertain = false;
  int operator()(const IA& v) {
    if (v.inf() > 0.0) return 1;
    if (v.sup() < 0.0) return -1;
    if (v.inf() == 0.0 && v.sup() == 0.0) return 0;
    uncertain = true;
    return 0;
  }
};

template <class V, class Sign>
bool same_direction(const V& a, const V& b, Sign& sign) {
  return sign(cross(a, b)) == 0 && sign(dot(a, b)) > 0;
}

/// w strictly inside the counter-clockwise open arc of directions from a to b (a, b not of
/// one direction).
template <class V, class Sign>
bool in_open_ccw_arc(const V& a, const V& b, const V& w, Sign& sign) {
  const int ab = sign(cross(a, b));
  if (ab > 0) return sign(cross(a, w)) > 0 && sign(cross(w, b)) > 0;
  if (ab < 0) return !(sign(cross(b, w)) >= 0 && sign(cross(w, a)) >= 0);
  return sign(cross(a, w)) > 0;
}

template <class V, class Sign>
bool strictly_alternate(const V& u1, const V& u2, const V& v1, const V& v2, Sign& sign) {
  if (same_direction(u1, u2, sign) || same_direction(v1, v2, sign)) return false;
  const bool v1_in_12 = in_open_ccw_arc(u1, u2, v1, sign);
  const bool v1_in_21 = in_open_ccw_arc(u2, u1, v1, sign);
  const bool v2_in_12 = in_open_ccw_arc(u1, u2, v2, sign);
  const bool v2_in_21 = in_open_ccw_arc(u2, u1, v2, sign);
  return (v1_in_12 && v2_in_21) || (v1_in_21 && v2_in_12);
}

/// Strict alternation of the contacts o1, o2 (outer) and i1, i2 (inner) about the exact
/// centre c (cx, cy its enclosures): intervals first, exact when a sign is uncertain.
bool strictly_alternate_about(const QPoint& c, const IA& cx, const IA& cy, Point2 o1, Point2 o2,
                              Point2 i1, Point2 i2) {
  {
    auto ray = [&](Point2 p) { return IPoint{IA(p.x) - cx, IA(p.y) - cy}; };
    IntervalSign sign;
    const bool r = strictly_alternate(ray(o1), ray(o2), ray(i1), ray(i2), sign);
    if (!sign.uncertain) return r;
  }
  auto ray = [&](Point2 p) { return to_q(p) - c; };
  ExactSign sign;
  return strictly_alternate(ray(o1), ray(o2), ray(i1), ray(i2), sign);
}

// ---- interval filters --------------------------------------------------------------------

/// Exact squared distances from a rational centre, as integers over one denominator
/// (derivation (6)): no rational arithmetic (and no gcd) per point.
class CentreDistances {
 public:
  explicit CentreDistances(const QPoint& c) {
    mpz_inits(X_, Y_, D_, px_, py_, t_, ref_, nullptr);
    mpz_lcm(D_, c.x.get_den_mpz_t(), c.y.get_den_mpz_t());
    mpz_divexact(X_, D_, c.x.get_den_mpz_t());
    mpz_mul(X_, X_, c.x.get_num_mpz_t());
    mpz_divexact(Y_, D_, c.y.get_den_mpz_t());
    mpz_mul(Y_, Y_, c.y.get_num_mpz_t());
  }
  ~CentreDistances() { mpz_clears(X_, Y_, D_, px_, py_, t_, ref_, nullptr); }
  CentreDistances(const CentreDistances&) = delete;
  CentreDistances& operator=(const CentreDistances&) = delete;

  /// sign(|p − c|² − |q − c|²), exactly. q's numerator is kept for the next call with the
  /// same q and shift (the reference contact of a whole containment pass).
  int compare(Point2 p, Point2 q) {
    const long s = std::max(shift_of(p), shift_of(q));
    if (!(s == ref_shift_ && q == ref_point_)) {
      numerator(q, s, ref_);
      ref_shift_ = s;
      ref_point_ = q;
    }
    numerator(p, s, t_);
    return mpz_cmp(t_, ref_) > 0 ? 1 : (mpz_cmp(t_, ref_) < 0 ? -1 : 0);
  }

 private:
  /// Least s ≥ 0 with p·2^s integral.
  static long shift_of(Point2 p) {
    long s = 0;
    for (const double v : {p.x, p.y}) {
      if (v == 0.0) continue;
      int k = 0;
      (void)std::frexp(v, &k);
      s = std::max(s, 53L - k);
    }
    return s;
  }
  /// v·2^s as an integer (v a multiple of 2^−s).
  static void set_scaled(mpz_ptr out, double v, long s) {
    int k = 0;
    const double m = std::frexp(v, &k);
    mpz_set_d(out, std::ldexp(m, 53));  // exact: a 53-bit integer
    const long e = k - 53 + s;
    if (e >= 0) mpz_mul_2exp(out, out, static_cast<mp_bitcnt_t>(e));
    else mpz_tdiv_q_2exp(out, out, static_cast<mp_bitcnt_t>(-e));  // exact: low bits are 0
  }
  /// G(p) = (P_x D − X 2^s)² + (P_y D − Y 2^s)², P = p·2^s.
  void numerator(Point2 p, long s, mpz_ptr out) {
    set_scaled(px_, p.x, s);
    mpz_mul(px_, px_, D_);
    mpz_mul_2exp(out, X_, static_cast<mp_bitcnt_t>(s));
    mpz_sub(px_, px_, out);
    set_scaled(py_, p.y, s);
    mpz_mul(py_, py_, D_);
    mpz_mul_2exp(out, Y_, static_cast<mp_bitcnt_t>(s));
    mpz_sub(py_, py_, out);
    mpz_mul(out, px_, px_);
    mpz_addmul(out, py_, py_);
  }

  mpz_t X_, Y_, D_, px_, py_, t_, ref_;
  long ref_shift_ = -1;  // the shift and point ref_ holds the numerator of (none yet)
  Point2 ref_point_{};
};

/// A rational centre with its enclosures, for filtered distance comparisons.
struct FilteredCircle {
  QPoint c;
  IA cx;
  IA cy;
  internal::ApproxCentre approx;  // the static filter's view of c (verify_distance.h)
  /// The exact stage, built on first use (only near-ties need it).
  CentreDistances& exact() const {
    if (!exact_) exact_ = std::make_unique<CentreDistances>(c);
    return *exact_;
  }
  mutable std::unique_ptr<CentreDistances> exact_;
};

FilteredCircle filtered(const QPoint& c) {
  const IA cx = to_ia(c.x), cy = to_ia(c.y);
  return {c, cx, cy, internal::approx_centre({cx.inf(), cx.sup()}, {cy.inf(), cy.sup()}),
          nullptr};
}

/// |c − ref|² for a comparison made many times: the reference point, its static-filter value
/// and its interval enclosure.
struct Threshold {
  Point2 ref;
  internal::Distance2 approx;
  IA enclosure;
};

IA interval_distance2(Point2 p, const FilteredCircle& fc) {
  const IA dx = IA(p.x) - fc.cx;
  const IA dy = IA(p.y) - fc.cy;
  return dx * dx + dy * dy;
}

/// t2 = |c − ref|² exactly: its enclosure is one rounding wide, much tighter than the interval
/// computation from c's enclosure (which would send more near-ties to the exact stage).
Threshold threshold(Point2 ref, const FilteredCircle& fc, const Q& t2) {
  return {ref, internal::distance2(ref, fc.approx), to_ia(t2)};
}

/// sign(|c − p|² − |c − t.ref|²) given p's static-filter value d: three stages — the static
/// filter (a few flops), intervals (tighter, ~10× the cost: they decide most near-ties of
/// points co-circular to within rounding), exact integers (CentreDistances) for the rest.
int compare_distance2(Point2 p, const internal::Distance2& d, std::optional<IA>& ia,
                      const FilteredCircle& fc, const Threshold& t) {
  if (const int s = internal::certain_sign(d, t.approx)) return s;
  if (!ia) ia = interval_distance2(p, fc);  // once per point, however many thresholds
  const IA diff = *ia - t.enclosure;
  if (diff.inf() > 0.0) return 1;
  if (diff.sup() < 0.0) return -1;
  return fc.exact().compare(p, t.ref);
}

int compare_distance2(Point2 p, const FilteredCircle& fc, const Threshold& t) {
  std::optional<IA> ia;
  return compare_distance2(p, internal::distance2(p, fc.approx), ia, fc, t);
}

/// max_p |c − p|² (want_max) or min_p |c − p|², exact, with a filtered pre-selection: the
/// static filter's bounds, then intervals for the points they leave, then exact comparisons
/// among the points whose enclosure still reaches the best bound.
Q extreme_distance2(std::span<const Point2> points, const FilteredCircle& fc, bool want_max) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::vector<internal::Distance2> d(points.size());
  double bound = want_max ? -inf : inf;
  for (std::size_t k = 0; k < points.size(); ++k) {
    d[k] = internal::distance2(points[k], fc.approx);
    bound = want_max ? std::max(bound, d[k].value - d[k].error)
                     : std::min(bound, d[k].value + d[k].error);
  }
  // The bounds are rounded: widen the test by a relative 2⁻³⁰ so no candidate is lost to it.
  const double slack = std::fabs(bound) * 0x1p-30;
  std::vector<std::pair<std::size_t, IA>> candidates;
  double ia_bound = want_max ? -inf : inf;
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (want_max ? d[k].value + d[k].error < bound - slack
                 : d[k].value - d[k].error > bound + slack)
      continue;
    const IA v = interval_distance2(points[k], fc);
    ia_bound = want_max ? std::max(ia_bound, v.inf()) : std::min(ia_bound, v.sup());
    candidates.emplace_back(k, v);
  }
  std::optional<std::size_t> best;
  for (const auto& [k, v] : candidates) {
    if (want_max ? v.sup() < ia_bound : v.inf() > ia_bound) continue;
    if (!best) {
      best = k;
      continue;
    }
    const int s = fc.exact().compare(points[k], points[*best]);
    if (want_max ? s > 0 : s < 0) best = k;
  }
  return best ? norm2(to_q(points[*best]) - fc.c) : Q(0);
}

/// Orientation of (a, b, c) with rational c, filtered.
int orientation_filtered(Point2 a, Point2 b, const FilteredCircle& c) {
  const IA v = (IA(b.x) - IA(a.x)) * (c.cy - IA(a.y)) - (IA(b.y) - IA(a.y)) * (c.cx - IA(a.x));
  if (v.inf() > 0.0) return 1;
  if (v.sup() < 0.0) return -1;
  return orientation(to_q(a), to_q(b), c.c);
}

// ---- reported doubles --------------------------------------------------------------------

/// One ulp of |x|; a non-finite x counts as the largest double, so tolerances stay finite
/// (an exact value beyond the double range can never match a reported double anyway).
double ulp_of(double x) {
  x = std::fabs(x);
  if (!std::isfinite(x)) x = std::numeric_limits<double>::max();
  return std::nextafter(x, std::numeric_limits<double>::infinity()) - x;
}

/// sqrt(q) for q ≥ 0 without overflow or underflow: q is scaled by 4^∓k until it converts to
/// a normal double (coordinates near 1e±180 give R² near 1e±360), then the root is scaled
/// back by 2^±k.
double sqrt_of(const Q& q) {
  if (CGAL::sign(q) <= 0) return 0.0;
  Q s = q;
  int k = 0;
  while (!std::isfinite(CGAL::to_double(s))) {
    s /= Q(4);
    ++k;
  }
  while (CGAL::to_double(s) < std::numeric_limits<double>::min()) {
    s *= Q(4);
    --k;
  }
  return std::ldexp(std::sqrt(CGAL::to_double(s)), k);
}

/// The magnitude that reported doubles are compared at: max(|c_x|, |c_y|, R), clamped to the
/// double range.
double scale_of(const QPoint& c, const Q& radius2) {
  const double s = std::max({std::fabs(CGAL::to_double(c.x)), std::fabs(CGAL::to_double(c.y)),
                             sqrt_of(radius2)});
  return std::isfinite(s) ? s : std::numeric_limits<double>::max();
}

std::string describe(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

std::string describe(const Q& v) { return describe(CGAL::to_double(v)); }

/// Reported centre within tol of the exact one, per coordinate.
std::optional<std::string> check_centre(Point2 reported, const QPoint& c, double tol) {
  if (!std::isfinite(reported.x) || !std::isfinite(reported.y))
    return "reported centre is not finite";
  const IA dx = IA(reported.x) - to_ia(c.x), dy = IA(reported.y) - to_ia(c.y);
  if (CGAL::abs(dx).sup() <= tol && CGAL::abs(dy).sup() <= tol) return std::nullopt;
  const Q t(tol);
  if (CGAL::abs(Q(reported.x) - c.x) > t || CGAL::abs(Q(reported.y) - c.y) > t) {
    return "reported centre (" + describe(reported.x) + ", " + describe(reported.y) +
           ") is farther than " + describe(tol) + " from the exact centre (" +
           describe(c.x) + ", " + describe(c.y) + ")";
  }
  return std::nullopt;
}

/// Reported radius ρ with (max(ρ − tol, 0))² ≤ t ≤ (ρ + tol)².
std::optional<std::string> check_radius(const char* name, double reported, const Q& t,
                                        double tol) {
  if (!std::isfinite(reported)) return std::string("reported ") + name + " is not finite";
  {
    // Intervals first: they settle every reported value well inside its tolerance.
    const IA r = IA(reported), tl = IA(tol), ti = to_ia(t);
    const IA hi = r + tl, lo = r - tl;
    if (hi.inf() >= 0.0 && (hi * hi - ti).inf() >= 0.0 &&
        (lo.sup() <= 0.0 || (lo * lo - ti).sup() <= 0.0))
      return std::nullopt;
  }
  const Q hi = Q(reported) + Q(tol);
  const Q lo = Q(reported) - Q(tol);
  const bool ok = sgn(hi) >= 0 && hi * hi >= t && (sgn(lo) <= 0 || lo * lo <= t);
  if (!ok) {
    return std::string("reported ") + name + " " + describe(reported) +
           " differs by more than " + describe(tol) + " from the exact value sqrt(" +
           describe(t) + ")";
  }
  return std::nullopt;
}

/// Reported ℓ ≈ (√a − √b)/divisor (divisor 1 or 2): accepts when
/// √a − √b ∈ [divisor·(ℓ − tol), divisor·(ℓ + tol)], exactly (derivation (3)).
std::optional<std::string> check_difference(const char* name, double reported, const Q& a,
                                            const Q& b, double tol, int divisor) {
  if (!std::isfinite(reported)) return std::string("reported ") + name + " is not finite";
  {
    // Intervals first (√ of enclosures of a and b): they settle every reported value well
    // inside its tolerance; the exact comparison below decides the rest.
    const IA k(divisor), r = IA(reported), tl = IA(tol);
    const IA w = CGAL::sqrt(to_ia(a)) - CGAL::sqrt(to_ia(b));
    if ((w - (r - tl) * k).inf() >= 0.0 && (w - (r + tl) * k).sup() <= 0.0) return std::nullopt;
  }
  const Q k(divisor);
  const Q lo = (Q(reported) - Q(tol)) * k;
  const Q hi = (Q(reported) + Q(tol)) * k;
  if (sign_sqrt_difference_minus(a, b, lo) < 0 || sign_sqrt_difference_minus(a, b, hi) > 0) {
    std::ostringstream os;
    os.precision(17);
    os << "reported " << name << " " << reported << " differs by more than " << tol
       << " from the exact value (sqrt(" << CGAL::to_double(a) << ") - sqrt("
       << CGAL::to_double(b) << "))" << (divisor == 2 ? "/2" : "");
    return os.str();
  }
  return std::nullopt;
}

/// A reported parameter that should be ~0.
std::optional<std::string> check_zero(const char* name, double reported, double tol) {
  if (!std::isfinite(reported) || std::fabs(reported) > tol) {
    return std::string("reported ") + name + " " + describe(reported) +
           " should be 0 (tolerance " + describe(tol) + ")";
  }
  return std::nullopt;
}

std::optional<std::string> check_ronq(const RoundnessParameters& ron, double tol) {
  if (!std::isfinite(ron.ronq) || ron.ronq < 0.0 ||
      ron.ronq > std::max(ron.ronp, ron.ronv) + tol) {
    return "reported RONq " + describe(ron.ronq) + " is not in [0, max(RONp, RONv)]";
  }
  return std::nullopt;
}

// ---- common input checks -----------------------------------------------------------------

void require_finite(std::span<const Point2> points, const char* caller) {
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (!std::isfinite(points[k].x) || !std::isfinite(points[k].y)) {
      std::ostringstream os;
      os << caller << ": point " << k << " has a non-finite coordinate (x = " << points[k].x
         << ", y = " << points[k].y << ")";
      throw InvalidInput(os.str());
    }
  }
}

Verification fail(const char* what, const std::string& reason) {
  return Verification{false, std::string(what) + ": " + reason};
}

std::optional<std::string> check_indices(std::span<const Point2> points,
                                         const std::vector<std::size_t>& idx,
                                         const char* list) {
  for (std::size_t k = 0; k < idx.size(); ++k) {
    if (idx[k] >= points.size()) {
      std::ostringstream os;
      os << list << "[" << k << "] = " << idx[k] << " is out of range (" << points.size()
         << " points)";
      return os.str();
    }
  }
  return std::nullopt;
}

std::optional<std::string> check_distinct(std::span<const Point2> points,
                                          const std::vector<std::size_t>& idx,
                                          const char* list) {
  for (std::size_t a = 0; a < idx.size(); ++a) {
    for (std::size_t b = a + 1; b < idx.size(); ++b) {
      if (points[idx[a]] == points[idx[b]]) {
        std::ostringstream os;
        os << list << " contacts " << idx[a] << " and " << idx[b] << " are the same point";
        return os.str();
      }
    }
  }
  return std::nullopt;
}

std::string index_name(const char* role, std::size_t index) {
  std::ostringstream os;
  os << role << " " << index;
  return os.str();
}

/// Distinct points (first occurrence kept).
std::vector<Point2> distinct_points(std::span<const Point2> points) {
  std::vector<Point2> v(points.begin(), points.end());
  std::sort(v.begin(), v.end(), [](Point2 a, Point2 b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
  });
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

/// Convex-hull vertices, counter-clockwise, without collinear points (exact predicates).
std::vector<Point2> hull_vertices(std::span<const Point2> points) {
  std::vector<Kernel::Point_2> in;
  in.reserve(points.size());
  for (const Point2& p : points) in.emplace_back(p.x, p.y);
  std::vector<Kernel::Point_2> out;
  CGAL::convex_hull_2(in.begin(), in.end(), std::back_inserter(out));
  std::vector<Point2> hull;
  hull.reserve(out.size());
  for (const auto& p : out) hull.push_back({p.x(), p.y()});
  return hull;
}

/// Squared width of the point set: min over hull edges of the farthest point's squared
/// distance to the edge line (rotating-calipers fact: the minimum is attained at an edge
/// direction). Requires ≥ 3 hull vertices.
Q squared_width(const std::vector<Point2>& hull) {
  std::optional<Q> best;
  for (std::size_t k = 0; k < hull.size(); ++k) {
    const QPoint a = to_q(hull[k]);
    const QPoint e = to_q(hull[(k + 1) % hull.size()]) - a;
    Q far(0);
    for (const Point2& p : hull) far = std::max(far, CGAL::abs(cross(e, to_q(p) - a)));
    const Q w2 = far * far / norm2(e);
    if (!best || w2 < *best) best = w2;
  }
  return best.value_or(Q(0));
}

// ---- MZ ------------------------------------------------------------------------------------

/// An exact 2+2 zone: centre, R², r².
struct Zone {
  QPoint c;
  Q outer2;
  Q inner2;
};

/// The centre of a 2+2 set in intervals, relative to o1 (none when the bisectors may be
/// parallel), with R², r² enclosures. I is Interval_nt<false> under a rounding guard in the
/// enumeration loop (one mode switch per outer pair instead of one per operation).
template <class I>
struct IntervalZone {
  I cx;
  I cy;
  I outer2;
  I inner2;
};

template <class I>
std::optional<IntervalZone<I>> interval_zone(Point2 o1, Point2 o2, Point2 i1, Point2 i2) {
  const I ex = I(o2.x) - I(o1.x), ey = I(o2.y) - I(o1.y);
  const I q1x = I(i1.x) - I(o1.x), q1y = I(i1.y) - I(o1.y);
  const I q2x = I(i2.x) - I(o1.x), q2y = I(i2.y) - I(o1.y);
  const I fx = q2x - q1x, fy = q2y - q1y;
  const I det = ex * fy - ey * fx;
  if (!(det.inf() > 0.0 || det.sup() < 0.0)) return std::nullopt;
  const I g = (ex * ex + ey * ey) / I(2);
  const I h = (q2x * q2x + q2y * q2y - q1x * q1x - q1y * q1y) / I(2);
  const I cx = (g * fy - ey * h) / det, cy = (ex * h - fx * g) / det;
  return IntervalZone<I>{cx, cy, cx * cx + cy * cy,
                         (cx - q1x) * (cx - q1x) + (cy - q1y) * (cy - q1y)};
}

/// |p − c|² in intervals, c given relative to `origin`.
template <class I>
I interval_distance2(Point2 p, Point2 origin, const IntervalZone<I>& z) {
  const I dx = I(p.x) - I(origin.x) - z.cx, dy = I(p.y) - I(origin.y) - z.cy;
  return dx * dx + dy * dy;
}

/// Upper bound on the number of (outer pair, inner Delaunay edge) sets the global re-check
/// enumerates (~0.1 µs each behind the interval filters): beyond it, verify() reports the
/// claim as not re-checkable rather than spend seconds.
constexpr double kMaxEnumeratedSets = 5e6;

struct GlobalCheck {
  bool decided = true;
  std::optional<std::string> refutation;
};

/// Re-check of a global MZ claim by enumeration (derivation (4), second part). A narrower
/// finite minimum would be a strictly alternating 2+2 set whose centre c lies on the
/// farthest-point Voronoi edge of its outer pair (both convex-hull vertices, all hull
/// vertices within R) and on the nearest-point Voronoi edge of its inner pair: the circle
/// about c through them is empty, so they are Delaunay neighbours — in every Delaunay
/// triangulation up to diagonals of co-circular polygons, and then a polygon edge of the
/// same polygon alternates too. On the bisector, that circle is empty iff it does not hold
/// either apex of the two Delaunay triangles on the edge strictly inside. So: every pair of
/// hull vertices × every Delaunay edge (CGAL, exact predicates), intervals first, exact
/// decisions; plus the zero-width set and the convex-hull width W (the limit at infinity).
GlobalCheck check_global_by_enumeration(std::span<const Point2> points, const Zone& zone) {
  const std::vector<Point2> pts = distinct_points(points);
  const std::vector<Point2> hull = hull_vertices(pts);
  if (hull.size() < 3) return {true, "all points collinear"};
  // All distinct points on one circle: zero width beats any positive claim.
  {
    const QPoint a = to_q(hull[0]), b = to_q(hull[1]), c = to_q(hull[2]);
    if (auto cc = equidistant_point(a, b, a, c)) {
      const FilteredCircle fc = filtered(*cc);
      const Threshold r2d = threshold(hull[0], fc, norm2(a - *cc));
      bool all_on = true;
      for (const Point2& p : pts) {
        if (compare_distance2(p, fc, r2d) != 0) {
          all_on = false;
          break;
        }
      }
      if (all_on && zone.outer2 > zone.inner2)
        return {true, "all points lie on one circle (zero width), narrower than the claim"};
    }
  }
  const Q w2 = squared_width(hull);
  if (compare_sqrt_differences(zone.outer2, zone.inner2, w2, Q(0)) > 0)
    return {true, "the convex-hull width sqrt(" + describe(w2) +
                      ") is smaller than the claimed zone: no finite minimum exists"};

  struct InnerEdge {
    Point2 a;
    Point2 b;
    std::vector<Point2> apex;  // finite apexes of the adjacent triangles
  };
  std::vector<InnerEdge> edges;
  {
    std::vector<Kernel::Point_2> kp;
    kp.reserve(pts.size());
    for (const Point2& p : pts) kp.emplace_back(p.x, p.y);
    const Delaunay dt(kp.begin(), kp.end());
    auto to_p = [](const Kernel::Point_2& q) { return Point2{q.x(), q.y()}; };
    for (const auto& e : dt.finite_edges()) {
      const auto f = e.first;
      const int i = e.second;
      InnerEdge ie{to_p(f->vertex(f->cw(i))->point()), to_p(f->vertex(f->ccw(i))->point()), {}};
      if (!dt.is_infinite(f->vertex(i))) ie.apex.push_back(to_p(f->vertex(i)->point()));
      const auto m = dt.mirror_vertex(f, i);
      if (!dt.is_infinite(m)) ie.apex.push_back(to_p(m->point()));
      edges.push_back(std::move(ie));
    }
  }
  const double h = static_cast<double>(hull.size());
  if (h * (h - 1) / 2 * static_cast<double>(edges.size()) > kMaxEnumeratedSets)
    return {false, std::nullopt};

  using IF = CGAL::Interval_nt<false>;  // only under the rounding guard below
  const IA w_claim = CGAL::sqrt(to_ia(zone.outer2)) - CGAL::sqrt(to_ia(zone.inner2));
  const IF w_claim_f(w_claim.inf(), w_claim.sup());
  std::vector<const InnerEdge*> survivors;
  for (std::size_t a = 0; a < hull.size(); ++a) {
    for (std::size_t b = a + 1; b < hull.size(); ++b) {
      const Point2 o1 = hull[a], o2 = hull[b];
      survivors.clear();
      {
        const CGAL::Protect_FPU_rounding<true> guard;
        for (const InnerEdge& ie : edges) {
          if (ie.a == o1 || ie.a == o2 || ie.b == o1 || ie.b == o2) continue;
          if (const auto z = interval_zone<IF>(o1, o2, ie.a, ie.b)) {
            if (z->inner2.inf() >= z->outer2.sup()) continue;
            const IF w = CGAL::sqrt(z->outer2) - CGAL::sqrt(z->inner2);
            if (w.inf() > w_claim_f.sup()) continue;  // certainly wider than the claim
            bool reject = false;
            for (const Point2& q : ie.apex)
              reject = reject || (interval_distance2(q, o1, *z) - z->inner2).sup() < 0.0;
            for (std::size_t k = 0; k < hull.size() && !reject; ++k)
              reject = (interval_distance2(hull[k], o1, *z) - z->outer2).inf() > 0.0;
            if (reject) continue;
          }
          survivors.push_back(&ie);
        }
      }
      for (const InnerEdge* pe : survivors) {
        const InnerEdge& ie = *pe;
        const QPoint qo1 = to_q(o1), qo2 = to_q(o2), qi1 = to_q(ie.a), qi2 = to_q(ie.b);
        const auto c = equidistant_point(qo1, qo2, qi1, qi2);
        if (!c) continue;
        const Q outer2 = norm2(qo1 - *c);
        const Q inner2 = norm2(qi1 - *c);
        if (inner2 >= outer2) continue;
        if (compare_sqrt_differences(outer2, inner2, zone.outer2, zone.inner2) >= 0) continue;
        if (!strictly_alternate_about(*c, to_ia(c->x), to_ia(c->y), o1, o2, ie.a, ie.b)) continue;
        // Final, self-evident check of the narrower zone: every point in its annulus.
        const FilteredCircle fc = filtered(*c);
        const Threshold o2d = threshold(o1, fc, outer2), i2d = threshold(ie.a, fc, inner2);
        bool contained = true;
        for (std::size_t k = 0; k < pts.size() && contained; ++k)
          contained = compare_distance2(pts[k], fc, o2d) <= 0 &&
                      compare_distance2(pts[k], fc, i2d) >= 0;
        if (!contained) continue;
        std::ostringstream os;
        os.precision(17);
        os << "a narrower zone exists: outer (" << o1.x << ", " << o1.y << "), (" << o2.x
           << ", " << o2.y << "), inner (" << ie.a.x << ", " << ie.a.y << "), (" << ie.b.x
           << ", " << ie.b.y << "), width " << CGAL::to_double(w_claim) << " claimed";
        return {true, os.str()};
      }
    }
  }
  return {true, std::nullopt};
}

Verification verify_zero_width(std::span<const Point2> points, const MinimumZoneCircle& mz) {
  const char* what = "verify(minimum zone, zero width)";
  std::vector<std::size_t> a = mz.outer_contacts, b = mz.inner_contacts;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  if (a != b) return fail(what, "outer and inner contact lists must hold the same 3 points");
  if (auto e = check_indices(points, a, "contacts")) return fail(what, *e);
  if (auto e = check_distinct(points, a, "zero-width")) return fail(what, *e);
  const QPoint p0 = to_q(points[a[0]]), p1 = to_q(points[a[1]]), p2 = to_q(points[a[2]]);
  const auto c = equidistant_point(p0, p1, p0, p2);
  if (!c) return fail(what, "the 3 contacts are collinear");
  const Q r2 = norm2(p0 - *c);
  const FilteredCircle fc = filtered(*c);
  const Threshold r2d = threshold(points[a[0]], fc, r2);
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (compare_distance2(points[k], fc, r2d) != 0)
      return fail(what, index_name("point", k) + " is not on the circle of the contacts");
  }
  const double scale = scale_of(*c, r2);
  const double u = ulp_of(scale);
  if (auto e = check_centre(mz.center, *c, kCentreUlps * u)) return fail(what, *e);
  if (auto e = check_radius("outer radius", mz.outer_radius, r2, kRadiusUlps * u))
    return fail(what, *e);
  if (auto e = check_radius("inner radius", mz.inner_radius, r2, kRadiusUlps * u))
    return fail(what, *e);
  if (auto e = check_zero("RONt", mz.ron.ront, kParameterUlps * u)) return fail(what, *e);
  if (auto e = check_zero("RONp", mz.ron.ronp, kParameterUlps * u)) return fail(what, *e);
  if (auto e = check_zero("RONv", mz.ron.ronv, kParameterUlps * u)) return fail(what, *e);
  // Zero width is trivially the global minimum.
  return Verification{true, {}};
}

}  // namespace

Verification verify(std::span<const Point2> points, const MinimumZoneCircle& mz) {
  require_finite(points, "verify(minimum zone)");
  const char* what = "verify(minimum zone)";
  if (mz.outer_contacts.size() == 3 && mz.inner_contacts.size() == 3)
    return verify_zero_width(points, mz);
  if (mz.outer_contacts.size() != 2 || mz.inner_contacts.size() != 2) {
    std::ostringstream os;
    os << "needs 2 outer and 2 inner contacts (or the same 3 for zero width); got "
       << mz.outer_contacts.size() << " outer and " << mz.inner_contacts.size() << " inner";
    return fail(what, os.str());
  }
  if (auto e = check_indices(points, mz.outer_contacts, "outer_contacts")) return fail(what, *e);
  if (auto e = check_indices(points, mz.inner_contacts, "inner_contacts")) return fail(what, *e);
  if (auto e = check_distinct(points, mz.outer_contacts, "outer")) return fail(what, *e);
  if (auto e = check_distinct(points, mz.inner_contacts, "inner")) return fail(what, *e);
  const std::size_t io1 = mz.outer_contacts[0], io2 = mz.outer_contacts[1];
  const std::size_t ii1 = mz.inner_contacts[0], ii2 = mz.inner_contacts[1];
  const QPoint o1 = to_q(points[io1]), o2 = to_q(points[io2]);
  const QPoint i1 = to_q(points[ii1]), i2 = to_q(points[ii2]);
  const auto c = equidistant_point(o1, o2, i1, i2);
  if (!c) return fail(what, "the perpendicular bisectors of the outer and the inner pair are parallel");
  const Zone zone{*c, norm2(o1 - *c), norm2(i1 - *c)};
  if (zone.inner2 >= zone.outer2) return fail(what, "exact r^2 >= R^2: the inner contacts are not inside the outer circle");
  // Containment, exact (filtered).
  const FilteredCircle fc = filtered(*c);
  const Threshold o2d = threshold(points[io1], fc, zone.outer2);
  const Threshold i2d = threshold(points[ii1], fc, zone.inner2);
  for (std::size_t k = 0; k < points.size(); ++k) {
    // One static-filter distance (and at most one interval one) for both radii.
    const internal::Distance2 d = internal::distance2(points[k], fc.approx);
    std::optional<IA> ia;
    if (compare_distance2(points[k], d, ia, fc, o2d) > 0)
      return fail(what, index_name("point", k) + " lies outside the outer circle");
    if (compare_distance2(points[k], d, ia, fc, i2d) < 0)
      return fail(what, index_name("point", k) + " lies inside the inner circle");
  }
  if (!strictly_alternate_about(*c, fc.cx, fc.cy, points[io1], points[io2], points[ii1],
                                points[ii2])) {
    std::ostringstream os;
    os << "contacts do not alternate strictly in angle about the centre (outer " << io1
       << ", " << io2 << "; inner " << ii1 << ", " << ii2 << ")";
    return fail(what, os.str());
  }
  // Reported doubles.
  const double u = ulp_of(scale_of(*c, zone.outer2));
  if (auto e = check_centre(mz.center, *c, kCentreUlps * u)) return fail(what, *e);
  if (auto e = check_radius("outer radius", mz.outer_radius, zone.outer2, kRadiusUlps * u))
    return fail(what, *e);
  if (auto e = check_radius("inner radius", mz.inner_radius, zone.inner2, kRadiusUlps * u))
    return fail(what, *e);
  if (auto e = check_difference("RONt", mz.ron.ront, zone.outer2, zone.inner2,
                                kParameterUlps * u, 1))
    return fail(what, *e);
  if (auto e = check_difference("RONp", mz.ron.ronp, zone.outer2, zone.inner2,
                                kParameterUlps * u, 2))
    return fail(what, *e);
  if (auto e = check_difference("RONv", mz.ron.ronv, zone.outer2, zone.inner2,
                                kParameterUlps * u, 2))
    return fail(what, *e);
  if (auto e = check_ronq(mz.ron, kParameterUlps * u)) return fail(what, *e);
  if (mz.certificate.optimality != Optimality::global) return Verification{true, {}};

  // Global claim, derivation (4): crossing segments and distances to the other pair's line.
  const auto orient = [&](std::size_t a, std::size_t b, std::size_t k) {
    return input_orientation(points[a], points[b], points[k]);
  };
  bool unique = orient(io1, io2, ii1) * orient(io1, io2, ii2) < 0 &&
                orient(ii1, ii2, io1) * orient(ii1, ii2, io2) < 0;
  if (unique) {
    const std::array<std::array<const QPoint*, 3>, 4> tests{{{&o1, &o2, &i1},
                                                             {&o1, &o2, &i2},
                                                             {&i1, &i2, &o1},
                                                             {&i1, &i2, &o2}}};
    for (const auto& t : tests) {
      if (!exceeds_width_squared(*t[0], *t[1], *t[2], zone.outer2, zone.inner2)) {
        unique = false;
        break;
      }
    }
  }
  if (unique) return Verification{true, {}};
  const GlobalCheck g = check_global_by_enumeration(points, zone);
  if (g.refutation) return fail(what, "global optimality claim is false: " + *g.refutation);
  if (g.decided) return Verification{true, {}};
  return fail(what,
              "global optimality claim could not be re-checked independently: the contact "
              "segments do not cross with every contact farther than the zone width from "
              "the other pair's line, and (hull vertex pairs) x (Delaunay edges) exceeds "
              "the enumeration budget");
}

// ---- MC --------------------------------------------------------------------------------------

Verification verify(std::span<const Point2> points, const MinimumCircumscribedCircle& mc) {
  require_finite(points, "verify(minimum circumscribed)");
  const char* what = "verify(minimum circumscribed)";
  const auto& idx = mc.contacts;
  if (idx.size() != 2 && idx.size() != 3) {
    std::ostringstream os;
    os << "needs 2 or 3 contacts; got " << idx.size();
    return fail(what, os.str());
  }
  if (auto e = check_indices(points, idx, "contacts")) return fail(what, *e);
  if (auto e = check_distinct(points, idx, "circumscribed")) return fail(what, *e);
  QPoint c;
  const QPoint a = to_q(points[idx[0]]), b = to_q(points[idx[1]]);
  if (idx.size() == 2) {
    c = QPoint{(a.x + b.x) / Q(2), (a.y + b.y) / Q(2)};
  } else {
    const QPoint d = to_q(points[idx[2]]);
    const auto cc = equidistant_point(a, b, a, d);
    if (!cc) return fail(what, "the 3 contacts are collinear");
    c = *cc;
    const Point2 pa = points[idx[0]], pb = points[idx[1]], pd = points[idx[2]];
    const FilteredCircle centre = filtered(c);
    const int o = input_orientation(pa, pb, pd);
    if (orientation_filtered(pa, pb, centre) * o < 0 ||
        orientation_filtered(pb, pd, centre) * o < 0 ||
        orientation_filtered(pd, pa, centre) * o < 0) {
      std::ostringstream os;
      os << "the centre lies outside the triangle of contacts " << idx[0] << ", " << idx[1]
         << ", " << idx[2] << " (a smaller circle exists)";
      return fail(what, os.str());
    }
  }
  const Q r2 = norm2(a - c);
  const FilteredCircle fc = filtered(c);
  const Threshold r2d = threshold(points[idx[0]], fc, r2);
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (compare_distance2(points[k], fc, r2d) > 0)
      return fail(what, index_name("point", k) + " lies outside the circle");
  }
  const double u = ulp_of(scale_of(c, r2));
  if (auto e = check_centre(mc.center, c, kCentreUlps * u)) return fail(what, *e);
  if (auto e = check_radius("radius", mc.radius, r2, kRadiusUlps * u)) return fail(what, *e);
  const Q nearest2 = extreme_distance2(points, fc, false);
  if (auto e = check_difference("RONt", mc.ron.ront, r2, nearest2, kParameterUlps * u, 1))
    return fail(what, *e);
  if (auto e = check_difference("RONv", mc.ron.ronv, r2, nearest2, kParameterUlps * u, 1))
    return fail(what, *e);
  if (auto e = check_zero("RONp", mc.ron.ronp, kParameterUlps * u)) return fail(what, *e);
  if (auto e = check_ronq(mc.ron, kParameterUlps * u)) return fail(what, *e);
  // Convex problem: the support certificate proves global optimality.
  return Verification{true, {}};
}

// ---- MI --------------------------------------------------------------------------------------

namespace {

/// Point (rational) inside or on the convex polygon `hull` (ccw, ≥ 3 vertices): wedge
/// search about hull[0], filtered orientations.
bool in_closed_hull(const std::vector<Point2>& hull, const FilteredCircle& c) {
  const std::size_t m = hull.size();
  if (orientation_filtered(hull[0], hull[1], c) < 0) return false;
  if (orientation_filtered(hull[0], hull[m - 1], c) > 0) return false;
  std::size_t lo = 1, hi = m - 1;  // orient(h0, h_lo, c) ≥ 0, orient(h0, h_hi, c) ≤ 0
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    if (orientation_filtered(hull[0], hull[mid], c) >= 0) lo = mid;
    else hi = mid;
  }
  return orientation_filtered(hull[lo], hull[hi], c) >= 0;
}

/// Largest squared empty-circle radius of a centre on the hull edge [h1, h2], over the
/// breakpoints of the nearest-point envelope (derivation (5)); returns a breakpoint with
/// value > bound, if any.
std::optional<Q> boundary_beats(const std::vector<Point2>& pts, Point2 h1p, Point2 h2p,
                                const Q& bound) {
  const QPoint h1 = to_q(h1p);
  const QPoint e = to_q(h2p) - h1;
  const Q e2 = norm2(e);
  struct Line {
    Q alpha;
    Q beta;
  };
  std::vector<Line> lines;
  lines.reserve(pts.size());
  for (const Point2& p : pts) {
    const QPoint d = h1 - to_q(p);
    lines.push_back({norm2(d), Q(2) * dot(e, d)});
  }
  // Lower envelope: slopes decreasing from left to right; equal slopes keep the lowest.
  std::sort(lines.begin(), lines.end(), [](const Line& a, const Line& b) {
    return a.beta > b.beta || (a.beta == b.beta && a.alpha < b.alpha);
  });
  auto meet = [](const Line& a, const Line& b) -> Q {
    return (b.alpha - a.alpha) / (a.beta - b.beta);
  };
  std::vector<Line> env;
  for (const Line& l : lines) {
    if (!env.empty() && env.back().beta == l.beta) continue;  // higher, same slope
    while (env.size() >= 2 && meet(env[env.size() - 2], l) <= meet(env[env.size() - 2], env.back()))
      env.pop_back();
    env.push_back(l);
  }
  for (std::size_t k = 0; k + 1 < env.size(); ++k) {
    const Q t = meet(env[k], env[k + 1]);
    if (sgn(t) <= 0 || t >= Q(1)) continue;
    const Q rho2 = env[k].alpha + env[k].beta * t + t * t * e2;
    if (rho2 > bound) return rho2;
  }
  return std::nullopt;
}

/// Re-checks global optimality of an MI circle of squared radius r2 (derivation (5)).
std::optional<std::string> refute_global_inscribed(std::span<const Point2> points, const Q& r2) {
  const std::vector<Point2> pts = distinct_points(points);
  const std::vector<Point2> hull = hull_vertices(pts);
  if (hull.size() < 3) return "all points collinear";
  std::vector<Kernel::Point_2> kp;
  kp.reserve(pts.size());
  for (const Point2& p : pts) kp.emplace_back(p.x, p.y);
  const Delaunay dt(kp.begin(), kp.end());
  const IA r2i = to_ia(r2);
  for (const auto f : dt.finite_face_handles()) {
    const Point2 a{f->vertex(0)->point().x(), f->vertex(0)->point().y()};
    const Point2 b{f->vertex(1)->point().x(), f->vertex(1)->point().y()};
    const Point2 d{f->vertex(2)->point().x(), f->vertex(2)->point().y()};
    // Filter: circumradius² relative to a, in intervals.
    {
      const IA bx = IA(b.x) - IA(a.x), by = IA(b.y) - IA(a.y);
      const IA dx = IA(d.x) - IA(a.x), dy = IA(d.y) - IA(a.y);
      const IA den = IA(2) * (bx * dy - by * dx);
      if (den.inf() > 0.0 || den.sup() < 0.0) {
        const IA nb = bx * bx + by * by, nd = dx * dx + dy * dy;
        const IA ux = (dy * nb - by * nd) / den, uy = (bx * nd - dx * nb) / den;
        if ((ux * ux + uy * uy - r2i).sup() < 0.0) continue;
      }
    }
    const QPoint qa = to_q(a), qb = to_q(b), qd = to_q(d);
    const auto c = equidistant_point(qa, qb, qa, qd);
    if (!c) continue;  // cannot happen for a Delaunay face
    const Q rho2 = norm2(qa - *c);
    if (rho2 <= r2) continue;
    if (!in_closed_hull(hull, filtered(*c))) continue;
    std::ostringstream os;
    os.precision(17);
    os << "the empty circle through (" << a.x << ", " << a.y << "), (" << b.x << ", " << b.y
       << "), (" << d.x << ", " << d.y << ") has its centre in the convex hull and squared "
       << "radius " << CGAL::to_double(rho2) << " > " << CGAL::to_double(r2);
    return os.str();
  }
  for (std::size_t k = 0; k < hull.size(); ++k) {
    const Point2 h1 = hull[k], h2 = hull[(k + 1) % hull.size()];
    const QPoint e = to_q(h2) - to_q(h1);
    if (norm2(e) <= Q(4) * r2) continue;
    if (auto rho2 = boundary_beats(pts, h1, h2, r2)) {
      std::ostringstream os;
      os.precision(17);
      os << "a larger empty circle (squared radius " << CGAL::to_double(*rho2)
         << ") is centred on the hull edge (" << h1.x << ", " << h1.y << ") - (" << h2.x
         << ", " << h2.y << ")";
      return os.str();
    }
  }
  return std::nullopt;
}

/// The fast global test of verify_inscribed_cover.h for the MI circle about fc.c through the
/// contacts t (r2 its squared radius, farthest2 the largest squared distance of a point).
bool is_covered_by_disks(std::span<const Point2> points, const FilteredCircle& fc,
                         const std::array<QPoint, 3>& t, const Q& r2, const Q& farthest2) {
  // γ²: the squared distance from c to the nearest edge line of the contact triangle.
  std::optional<Q> gamma2;
  for (std::size_t k = 0; k < 3; ++k) {
    const QPoint e = t[(k + 1) % 3] - t[k];
    const Q cr = cross(e, fc.c - t[k]);
    const Q g = cr * cr / norm2(e);
    if (!gamma2 || g < *gamma2) gamma2 = g;
  }
  const auto enclose = [](const Q& q) { return CGAL::to_interval(q); };
  return internal::disks_cover_inscribed(
      points, fc.approx, {enclose(r2), enclose(farthest2), enclose(farthest2 - r2), enclose(*gamma2)});
}

}  // namespace

Verification verify(std::span<const Point2> points, const MaximumInscribedCircle& mi) {
  require_finite(points, "verify(maximum inscribed)");
  const char* what = "verify(maximum inscribed)";
  const auto& idx = mi.contacts;
  if (idx.size() != 3) {
    std::ostringstream os;
    os << "needs 3 contacts; got " << idx.size();
    return fail(what, os.str());
  }
  if (auto e = check_indices(points, idx, "contacts")) return fail(what, *e);
  if (auto e = check_distinct(points, idx, "inscribed")) return fail(what, *e);
  const QPoint a = to_q(points[idx[0]]), b = to_q(points[idx[1]]), d = to_q(points[idx[2]]);
  const auto cc = equidistant_point(a, b, a, d);
  if (!cc) return fail(what, "the 3 contacts are collinear");
  const QPoint c = *cc;
  const FilteredCircle fc = filtered(c);
  const Point2 pa = points[idx[0]], pb = points[idx[1]], pd = points[idx[2]];
  const int o = input_orientation(pa, pb, pd);
  const std::array<int, 3> side{orientation_filtered(pa, pb, fc) * o,
                                orientation_filtered(pb, pd, fc) * o,
                                orientation_filtered(pd, pa, fc) * o};
  if (side[0] < 0 || side[1] < 0 || side[2] < 0) {
    std::ostringstream os;
    os << "the centre is outside the triangle of contacts " << idx[0] << ", " << idx[1]
       << ", " << idx[2] << " (not a local maximum)";
    return fail(what, os.str());
  }
  const Q r2 = norm2(a - c);
  const Threshold r2d = threshold(points[idx[0]], fc, r2);
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (compare_distance2(points[k], fc, r2d) < 0)
      return fail(what, index_name("point", k) + " lies strictly inside the circle");
  }
  // Centre on an edge (then a diameter) of the contact triangle: a strict local maximum
  // needs another input point on the circle strictly beyond that edge (the co-circular
  // contacts then surround the centre: no closed half-plane through it holds them all).
  for (std::size_t e = 0; e < 3; ++e) {
    if (side[e] != 0) continue;
    const Point2 p0 = points[idx[e]], p1 = points[idx[(e + 1) % 3]];
    const int third = orientation(to_q(p0), to_q(p1), to_q(points[idx[(e + 2) % 3]]));
    bool witness = false;
    for (std::size_t k = 0; k < points.size() && !witness; ++k) {
      if (compare_distance2(points[k], fc, r2d) != 0) continue;
      witness = orientation(to_q(p0), to_q(p1), to_q(points[k])) == -third;
    }
    if (!witness) {
      std::ostringstream os;
      os << "the centre lies on the edge " << idx[e] << "-" << idx[(e + 1) % 3]
         << " of the contact triangle and no other point on the circle lies beyond that "
            "edge (not a strict local maximum)";
      return fail(what, os.str());
    }
  }
  // Inside the closed triangle of input points ⇒ inside their convex hull.
  const double u = ulp_of(scale_of(c, r2));
  if (auto e = check_centre(mi.center, c, kCentreUlps * u)) return fail(what, *e);
  if (auto e = check_radius("radius", mi.radius, r2, kRadiusUlps * u)) return fail(what, *e);
  const Q farthest2 = extreme_distance2(points, fc, true);
  if (auto e = check_difference("RONt", mi.ron.ront, farthest2, r2, kParameterUlps * u, 1))
    return fail(what, *e);
  if (auto e = check_difference("RONp", mi.ron.ronp, farthest2, r2, kParameterUlps * u, 1))
    return fail(what, *e);
  if (auto e = check_zero("RONv", mi.ron.ronv, kParameterUlps * u)) return fail(what, *e);
  if (auto e = check_ronq(mi.ron, kParameterUlps * u)) return fail(what, *e);
  if (mi.certificate.optimality != Optimality::global) return Verification{true, {}};
  // An O(n) sufficient test first (the disks of radius r about the points cover the disk of
  // radius √farthest2 about c); what it cannot settle, the exhaustion decides.
  if (is_covered_by_disks(points, fc, {a, b, d}, r2, farthest2)) return Verification{true, {}};
  if (auto e = refute_global_inscribed(points, r2))
    return fail(what, "global optimality claim is false: " + *e);
  return Verification{true, {}};
}

}  // namespace vcmm::geometry
