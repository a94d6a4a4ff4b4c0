// tests/support/exhaustive_oracle.cpp — see exhaustive_oracle.h for what is computed.
//
// Minimum-zone contact test, o1 taken as origin (q = p − o1, e = o2 − o1, f = i2 − i1):
//   centre x = N / D with D = 2 cross(e, f), N = (|e|² f_y − e_y g, e_x g − f_x |e|²),
//   g = |i2 − o1|² − |i1 − o1|² (Cramer on 2x·e = |e|², 2x·f = g);
//   R² = |x|², so |x − q|² − R² = |q|² − 2x·q  → sign(D)·sign(D|q|² − 2N·q);
//   r² = |x − q1|², so |x − q|² − r² = |q|² − |q1|² − 2x·(q − q1), likewise scaled by D;
//   directions from the centre, scaled by D: D q − N (cross and dot products keep their
//   signs, multiplied by D²).
// Each test is a polynomial sign, evaluated in Interval_nt and redone in exact rationals
// when an interval sign is uncertain (CGAL's filtered-predicate pattern).
//
// Comparing widths √a − √b against √c − √d (all ≥ 0): their difference is
// (√a + √d) − (√b + √c), whose sign is that of the squares' difference x − m with
// x = 2√(ad) − 2√(bc) (sign of ad − bc) and m = b + c − a − d. Opposite or zero signs
// decide at once; otherwise compare x² = 4ad + 4bc − 8√(abcd) with m²: sign(s − 8√(abcd))
// with s = 4ad + 4bc − m², i.e. −1 if s ≤ 0 (0 if s = 0 = abcd), else sign(s² − 64abcd);
// the result flips when x and m are both negative.
#include "support/exhaustive_oracle.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/convex_hull_2.h>

#include <algorithm>
#include <iomanip>
#include <sstream>

namespace vcmm::test {
namespace {

using IA = CGAL::Interval_nt<true>;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;

int sg(const Rational& v) { return static_cast<int>(CGAL::sign(v)); }
int sg(const IA& v) { return static_cast<int>(static_cast<CGAL::Sign>(CGAL::sign(v))); }

template <class NT>
struct Vec {
  NT x;
  NT y;
};

template <class NT>
Vec<NT> relative(Point2 p, Point2 origin) {
  return {NT(p.x) - NT(origin.x), NT(p.y) - NT(origin.y)};
}
template <class NT>
NT dot(const Vec<NT>& a, const Vec<NT>& b) {
  return a.x * b.x + a.y * b.y;
}
template <class NT>
NT cross(const Vec<NT>& a, const Vec<NT>& b) {
  return a.x * b.y - a.y * b.x;
}

template <class NT>
bool same_direction(const Vec<NT>& a, const Vec<NT>& b) {
  return sg(cross(a, b)) == 0 && sg(dot(a, b)) > 0;
}

/// w strictly inside the counter-clockwise open arc of directions from a to b.
template <class NT>
bool in_open_arc(const Vec<NT>& a, const Vec<NT>& b, const Vec<NT>& w) {
  const int ab = sg(cross(a, b));
  const int aw = sg(cross(a, w));
  const int wb = sg(cross(w, b));
  if (ab > 0) return aw > 0 && wb > 0;
  if (ab < 0) return aw > 0 || wb > 0;  // not in the closed short arc (b→a)
  return aw > 0;                       // a, b opposite: the left half-plane of a
}

template <class NT>
bool alternate(const Vec<NT>& u1, const Vec<NT>& u2, const Vec<NT>& v1, const Vec<NT>& v2) {
  if (same_direction(u1, u2) || same_direction(v1, v2)) return false;
  if (same_direction(u1, v1) || same_direction(u1, v2) || same_direction(u2, v1) ||
      same_direction(u2, v2))
    return false;
  return in_open_arc(u1, u2, v1) != in_open_arc(u1, u2, v2);
}

/// 2+2 set (pts[a], pts[b] outer; pts[k], pts[l] inner) strictly alternating with every
/// point in its closed annulus.
template <class NT>
bool valid_quadruple(const std::vector<Point2>& pts, std::size_t a, std::size_t b,
                     std::size_t k, std::size_t l) {
  const Point2 o = pts[a];
  const Vec<NT> e = relative<NT>(pts[b], o);
  const Vec<NT> q1 = relative<NT>(pts[k], o);
  const Vec<NT> q2 = relative<NT>(pts[l], o);
  const Vec<NT> f{q2.x - q1.x, q2.y - q1.y};
  const NT det = cross(e, f);
  const int sd = sg(det);
  if (sd == 0) return false;
  const NT ee = dot(e, e);
  const NT q1q1 = dot(q1, q1);
  const NT g = dot(q2, q2) - q1q1;
  const Vec<NT> n{ee * f.y - e.y * g, e.x * g - f.x * ee};
  const NT d = NT(2) * det;
  if (sd * sg(d * q1q1 - NT(2) * dot(n, q1)) >= 0) return false;  // needs r² < R²
  const Vec<NT> u1{-n.x, -n.y};
  const Vec<NT> u2{d * e.x - n.x, d * e.y - n.y};
  const Vec<NT> v1{d * q1.x - n.x, d * q1.y - n.y};
  const Vec<NT> v2{d * q2.x - n.x, d * q2.y - n.y};
  if (!alternate(u1, u2, v1, v2)) return false;
  for (std::size_t m = 0; m < pts.size(); ++m) {
    if (m == a || m == b || m == k || m == l) continue;
    const Vec<NT> q = relative<NT>(pts[m], o);
    const NT qq = dot(q, q);
    if (sd * sg(d * qq - NT(2) * dot(n, q)) > 0) return false;
    const Vec<NT> dq{q.x - q1.x, q.y - q1.y};
    if (sd * sg(d * (qq - q1q1) - NT(2) * dot(n, dq)) < 0) return false;
  }
  return true;
}

bool valid_quadruple_filtered(const std::vector<Point2>& pts, std::size_t a, std::size_t b,
                              std::size_t k, std::size_t l) {
  try {
    return valid_quadruple<IA>(pts, a, b, k, l);
  } catch (const CGAL::Uncertain_conversion_exception&) {
    return valid_quadruple<Rational>(pts, a, b, k, l);
  }
}

RationalPoint to_q(Point2 p) { return {Rational(p.x), Rational(p.y)}; }
Rational qdist2(const RationalPoint& a, const RationalPoint& b) {
  const Rational dx = a.x - b.x, dy = a.y - b.y;
  return dx * dx + dy * dy;
}
Rational qcross(const RationalPoint& o, const RationalPoint& a, const RationalPoint& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

/// Point equidistant from a1, a2 and from b1, b2.
std::optional<RationalPoint> equidistant(const RationalPoint& a1, const RationalPoint& a2,
                                         const RationalPoint& b1, const RationalPoint& b2) {
  const Rational ex = a2.x - a1.x, ey = a2.y - a1.y, fx = b2.x - b1.x, fy = b2.y - b1.y;
  const Rational det = ex * fy - ey * fx;
  if (sg(det) == 0) return std::nullopt;
  const Rational g = (a2.x * a2.x + a2.y * a2.y - a1.x * a1.x - a1.y * a1.y) / Rational(2);
  const Rational h = (b2.x * b2.x + b2.y * b2.y - b1.x * b1.x - b1.y * b1.y) / Rational(2);
  return RationalPoint{(g * fy - ey * h) / det, (ex * h - fx * g) / det};
}

/// Distinct points and the lowest input index of each.
struct Distinct {
  std::vector<Point2> pts;
  std::vector<std::size_t> index;
};

Distinct distinct(std::span<const Point2> points) {
  Distinct d;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (std::find(d.pts.begin(), d.pts.end(), points[i]) == d.pts.end()) {
      d.pts.push_back(points[i]);
      d.index.push_back(i);
    }
  }
  return d;
}

K::Point_2 kp(Point2 p) { return {p.x, p.y}; }

/// Indices (into pts) of the convex-hull vertices, counter-clockwise.
std::vector<std::size_t> hull_indices(const std::vector<Point2>& pts) {
  std::vector<K::Point_2> in;
  for (const Point2& p : pts) in.push_back(kp(p));
  std::vector<K::Point_2> out;
  CGAL::convex_hull_2(in.begin(), in.end(), std::back_inserter(out));
  std::vector<std::size_t> idx;
  for (const auto& h : out) {
    const Point2 p{h.x(), h.y()};
    idx.push_back(static_cast<std::size_t>(std::find(pts.begin(), pts.end(), p) - pts.begin()));
  }
  return idx;
}

bool collinear_set(const std::vector<Point2>& pts) {
  for (std::size_t k = 2; k < pts.size(); ++k)
    if (CGAL::orientation(kp(pts[0]), kp(pts[1]), kp(pts[k])) != CGAL::COLLINEAR) return false;
  return true;
}

std::array<std::size_t, 2> sorted_pair(std::size_t a, std::size_t b) {
  return a < b ? std::array<std::size_t, 2>{a, b} : std::array<std::size_t, 2>{b, a};
}

/// Exact point-in-closed-convex-polygon (hull ccw).
bool in_closed_hull(const std::vector<Point2>& pts, const std::vector<std::size_t>& hull,
                    const RationalPoint& c) {
  for (std::size_t k = 0; k < hull.size(); ++k) {
    const RationalPoint a = to_q(pts[hull[k]]);
    const RationalPoint b = to_q(pts[hull[(k + 1) % hull.size()]]);
    if (sg(qcross(a, b, c)) < 0) return false;
  }
  return true;
}

}  // namespace

bool operator==(const RationalPoint& a, const RationalPoint& b) {
  return a.x == b.x && a.y == b.y;
}

int compare_sqrt_differences(const Rational& a, const Rational& b, const Rational& c,
                             const Rational& d) {
  const Rational ad = a * d, bc = b * c, m = b + c - a - d;
  const int sx = sg(ad - bc);
  const int sm = sg(m);
  if (sx == 0) return -sm;
  if (sm == 0) return sx;
  if (sx != sm) return sx;
  const Rational s = Rational(4) * ad + Rational(4) * bc - m * m;
  const Rational abcd = ad * bc;
  int sdiff = 0;  // sign(x² − m²) = sign(s − 8√(abcd))
  if (sg(s) <= 0) sdiff = (sg(s) == 0 && sg(abcd) == 0) ? 0 : -1;
  else sdiff = sg(s * s - Rational(64) * abcd);
  return sx > 0 ? sdiff : -sdiff;
}

const char* to_string(OracleStatus s) {
  switch (s) {
    case OracleStatus::defined: return "defined";
    case OracleStatus::undefined: return "undefined";
  }
  return "?";
}

std::size_t representative(std::span<const Point2> points, std::size_t i) {
  for (std::size_t j = 0; j < i; ++j)
    if (points[j] == points[i]) return j;
  return i;
}

std::string cpp_literal(std::span<const Point2> points) {
  std::ostringstream os;
  os << std::hexfloat << "{";
  for (std::size_t i = 0; i < points.size(); ++i)
    os << (i ? ", " : "") << "{" << points[i].x << ", " << points[i].y << "}";
  os << "}";
  return os.str();
}

std::optional<ZoneSupport> exact_zone(std::span<const Point2> points, std::size_t o1,
                                      std::size_t o2, std::size_t i1, std::size_t i2) {
  const RationalPoint a = to_q(points[o1]), b = to_q(points[o2]);
  const RationalPoint c = to_q(points[i1]), d = to_q(points[i2]);
  const auto x = equidistant(a, b, c, d);
  if (!x) return std::nullopt;
  ZoneSupport z;
  z.outer = sorted_pair(o1, o2);
  z.inner = sorted_pair(i1, i2);
  z.center = *x;
  z.outer2 = qdist2(a, *x);
  z.inner2 = qdist2(c, *x);
  return z;
}

OracleMinimumZone oracle_minimum_zone(std::span<const Point2> points) {
  OracleMinimumZone out;
  const Distinct dd = distinct(points);
  const auto& pts = dd.pts;
  if (pts.size() < 3 || collinear_set(pts)) {
    out.explanation = "fewer than 3 distinct points or all collinear";
    return out;
  }
  const std::vector<std::size_t> hull = hull_indices(pts);
  // Zero width: every distinct point on the circle through three hull vertices.
  {
    const K::Point_2 a = kp(pts[hull[0]]), b = kp(pts[hull[1]]), c = kp(pts[hull[2]]);
    bool all_on = true;
    for (const Point2& p : pts)
      if (CGAL::side_of_bounded_circle(a, b, c, kp(p)) != CGAL::ON_BOUNDARY) all_on = false;
    if (all_on) {
      out.status = OracleStatus::defined;
      out.zero_width = true;
      const RationalPoint qa = to_q(pts[hull[0]]);
      out.center = *equidistant(qa, to_q(pts[hull[1]]), qa, to_q(pts[hull[2]]));
      out.outer2 = out.inner2 = qdist2(qa, out.center);
      out.explanation = "all points co-circular";
      return out;
    }
  }
  // Hull width W².
  {
    std::optional<Rational> best;
    for (std::size_t k = 0; k < hull.size(); ++k) {
      const RationalPoint a = to_q(pts[hull[k]]);
      const RationalPoint b = to_q(pts[hull[(k + 1) % hull.size()]]);
      Rational far(0);
      for (std::size_t h : hull) far = std::max(far, CGAL::abs(qcross(a, b, to_q(pts[h]))));
      const Rational w2 = far * far / qdist2(a, b);
      if (!best || w2 < *best) best = w2;
    }
    out.hull_width2 = *best;
  }
  const std::size_t n = pts.size();
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = a + 1; b < n; ++b) {
      for (std::size_t k = 0; k < n; ++k) {
        if (k == a || k == b) continue;
        for (std::size_t l = k + 1; l < n; ++l) {
          if (l == a || l == b) continue;
          if (!valid_quadruple_filtered(pts, a, b, k, l)) continue;
          ZoneSupport z = *exact_zone(pts, a, b, k, l);
          z.outer = sorted_pair(dd.index[a], dd.index[b]);
          z.inner = sorted_pair(dd.index[k], dd.index[l]);
          const int cmp = out.optima.empty()
                              ? -1
                              : compare_sqrt_differences(z.outer2, z.inner2,
                                                         out.optima[0].outer2,
                                                         out.optima[0].inner2);
          if (cmp < 0) out.optima.clear();
          if (cmp <= 0) out.optima.push_back(z);
          out.locals.push_back(z);
        }
      }
    }
  }
  if (out.optima.empty()) {
    out.explanation = "no strictly alternating 2+2 contact set holds all points";
    return out;
  }
  out.center = out.optima[0].center;
  out.outer2 = out.optima[0].outer2;
  out.inner2 = out.optima[0].inner2;
  const int vs_width = compare_sqrt_differences(out.outer2, out.inner2, out.hull_width2, 0);
  if (vs_width <= 0) {
    out.status = OracleStatus::defined;
  } else {
    out.status = OracleStatus::undefined;
    out.explanation = "the narrowest local minimum is wider than the convex hull's width";
  }
  return out;
}

OracleCircle oracle_minimum_circumscribed(std::span<const Point2> points) {
  OracleCircle out;
  const Distinct dd = distinct(points);
  const auto& pts = dd.pts;
  const std::size_t n = pts.size();
  if (n < 2) {
    out.explanation = "fewer than 2 distinct points";
    return out;
  }
  struct Candidate {
    std::vector<std::size_t> idx;  // into pts
    RationalPoint c;
    Rational r2;
  };
  std::vector<Candidate> enclosing;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      bool ok = true;
      for (std::size_t m = 0; m < n && ok; ++m)
        ok = CGAL::side_of_bounded_circle(kp(pts[i]), kp(pts[j]), kp(pts[m])) !=
             CGAL::ON_UNBOUNDED_SIDE;
      if (!ok) continue;
      const RationalPoint a = to_q(pts[i]), b = to_q(pts[j]);
      const RationalPoint c{(a.x + b.x) / Rational(2), (a.y + b.y) / Rational(2)};
      enclosing.push_back({{i, j}, c, qdist2(a, c)});
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      for (std::size_t k = j + 1; k < n; ++k) {
        if (CGAL::orientation(kp(pts[i]), kp(pts[j]), kp(pts[k])) == CGAL::COLLINEAR) continue;
        bool ok = true;
        for (std::size_t m = 0; m < n && ok; ++m)
          ok = CGAL::side_of_bounded_circle(kp(pts[i]), kp(pts[j]), kp(pts[k]), kp(pts[m])) !=
               CGAL::ON_UNBOUNDED_SIDE;
        if (!ok) continue;
        const RationalPoint a = to_q(pts[i]);
        const RationalPoint c = *equidistant(a, to_q(pts[j]), a, to_q(pts[k]));
        enclosing.push_back({{i, j, k}, c, qdist2(a, c)});
      }
    }
  }
  const auto best = std::min_element(enclosing.begin(), enclosing.end(),
                                     [](const Candidate& a, const Candidate& b) { return a.r2 < b.r2; });
  out.status = OracleStatus::defined;
  out.center = best->c;
  out.radius2 = best->r2;
  for (const Candidate& cand : enclosing) {
    if (cand.r2 != out.radius2) continue;
    if (!(cand.c == out.center)) {
      out.explanation = "internal error: two different smallest enclosing circles";
      out.status = OracleStatus::undefined;
    }
    if (cand.idx.size() == 3) {
      const RationalPoint a = to_q(pts[cand.idx[0]]), b = to_q(pts[cand.idx[1]]),
                          d = to_q(pts[cand.idx[2]]);
      const int o = sg(qcross(a, b, d));
      if (sg(qcross(a, b, cand.c)) * o < 0 || sg(qcross(b, d, cand.c)) * o < 0 ||
          sg(qcross(d, a, cand.c)) * o < 0)
        continue;
    }
    std::vector<std::size_t> s;
    for (std::size_t i : cand.idx) s.push_back(dd.index[i]);
    std::sort(s.begin(), s.end());
    out.supports.push_back(s);
  }
  return out;
}

OracleCircle oracle_maximum_inscribed(std::span<const Point2> points) {
  OracleCircle out;
  const Distinct dd = distinct(points);
  const auto& pts = dd.pts;
  const std::size_t n = pts.size();
  if (n < 3 || collinear_set(pts)) {
    out.explanation = "fewer than 3 distinct points or all collinear";
    return out;
  }
  const std::vector<std::size_t> hull = hull_indices(pts);
  struct Vertex {
    std::array<std::size_t, 3> idx;
    RationalPoint c;
    Rational r2;
    bool closed;  // centre inside the closed triangle
  };
  std::vector<Vertex> vertices;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      for (std::size_t k = j + 1; k < n; ++k) {
        const auto o = CGAL::orientation(kp(pts[i]), kp(pts[j]), kp(pts[k]));
        if (o == CGAL::COLLINEAR) continue;
        bool empty = true;
        for (std::size_t m = 0; m < n && empty; ++m)
          empty = CGAL::side_of_bounded_circle(kp(pts[i]), kp(pts[j]), kp(pts[k]),
                                               kp(pts[m])) != CGAL::ON_BOUNDED_SIDE;
        if (!empty) continue;
        const RationalPoint a = to_q(pts[i]), b = to_q(pts[j]), d = to_q(pts[k]);
        const RationalPoint c = *equidistant(a, b, a, d);
        if (!in_closed_hull(pts, hull, c)) continue;
        const int so = static_cast<int>(o);
        const bool closed = sg(qcross(a, b, c)) * so >= 0 && sg(qcross(b, d, c)) * so >= 0 &&
                            sg(qcross(d, a, c)) * so >= 0;
        vertices.push_back({{i, j, k}, c, qdist2(a, c), closed});
      }
    }
  }
  Rational best(0);
  for (const Vertex& v : vertices) best = std::max(best, v.r2);
  // Bisector crossings of the hull edges.
  for (std::size_t h = 0; h < hull.size(); ++h) {
    const RationalPoint h1 = to_q(pts[hull[h]]);
    const RationalPoint h2 = to_q(pts[hull[(h + 1) % hull.size()]]);
    if (qdist2(h1, h2) < Rational(4) * best) continue;  // ρ ≤ |e|/2 on the edge
    const Rational ex = h2.x - h1.x, ey = h2.y - h1.y;
    for (std::size_t p = 0; p < n; ++p) {
      for (std::size_t q = p + 1; q < n; ++q) {
        const RationalPoint a = to_q(pts[p]), b = to_q(pts[q]);
        const Rational den = Rational(2) * (ex * (b.x - a.x) + ey * (b.y - a.y));
        if (sg(den) == 0) continue;
        const Rational t = (qdist2(h1, b) - qdist2(h1, a)) / den;
        if (sg(t) <= 0 || t >= Rational(1)) continue;
        const RationalPoint x{h1.x + t * ex, h1.y + t * ey};
        const Rational rho2 = qdist2(x, a);
        if (rho2 <= best) continue;
        bool nearest = true;
        for (std::size_t m = 0; m < n && nearest; ++m) nearest = qdist2(x, to_q(pts[m])) >= rho2;
        if (nearest) best = rho2;
      }
    }
  }
  out.radius2 = best;
  // A vertex is a strict local maximum iff the points on its circle surround its centre
  // (no closed half-plane through the centre holds them all); its certificates are the
  // triples among them whose closed triangle holds the centre.
  auto surrounded = [&](const Vertex& v) {
    std::vector<RationalPoint> on;
    for (const Point2& p : pts)
      if (qdist2(to_q(p), v.c) == v.r2) on.push_back(to_q(p));
    for (const RationalPoint& s : on) {
      int lo = 0, hi = 0;
      for (const RationalPoint& t : on) {
        const int side = sg(qcross(v.c, s, t));
        lo = std::min(lo, side);
        hi = std::max(hi, side);
      }
      if (lo == 0 || hi == 0) return false;
    }
    return true;
  };
  for (const Vertex& v : vertices) {
    if (!v.closed || !surrounded(v)) continue;
    std::vector<std::size_t> s{dd.index[v.idx[0]], dd.index[v.idx[1]], dd.index[v.idx[2]]};
    std::sort(s.begin(), s.end());
    out.locals.push_back({s, v.c, v.r2});
    if (v.r2 != best) continue;
    if (out.supports.empty()) out.center = v.c;
    out.supports.push_back(s);
  }
  if (!out.supports.empty()) {
    out.status = OracleStatus::defined;
    return out;
  }
  out.status = OracleStatus::undefined;
  out.explanation = "the largest empty circle in the hull is not surrounded by its contacts";
  return out;
}

}  // namespace vcmm::test
