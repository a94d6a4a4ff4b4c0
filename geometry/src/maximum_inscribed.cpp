// maximum_inscribed.cpp — the maximum-inscribed circle (MICI, ISO 12181-1).
//
// Definition implemented
//   r(c) = min_i |c − p_i| (radius of the largest circle centred at c with no point strictly
//   inside). The MI circle is the maximiser of r over the convex hull H of the points,
//   provided it is a strict local maximum of r in the plane — a nearest-point Voronoi
//   vertex whose nearest points ("contacts") surround it. Otherwise (the maximum over H
//   lies on ∂H: partial arcs, too sparse profiles; or no Voronoi vertex is surrounded)
//   the MI circle is not defined and UndefinedResult is thrown.
//
// Facts used (notation: c* centre, r* = r(c*), contacts p_k at distance r*,
// v_k = (c* − p_k)/r* unit vectors, d = c − c*)
//   (F1) |c − p_k|² = r*² + 2r*·v_k·d + |d|² exactly, for every contact k.
//   (F2) A point c with nearest set K is a local maximum of r (even a non-strict one) only
//        if 0 lies in the interior of conv{v_k : k ∈ K}: otherwise some unit n has
//        v_k·n ≥ 0 for all k and (F1) gives r(c + t·n) > r(c) for small t > 0. So c is a
//        Voronoi vertex strictly inside the hull of its nearest points (for 3 contacts:
//        strictly inside their triangle ⇔ the triangle is acute). Such a vertex is
//        automatically in the interior of H.
//   (F3) Hence max_H r is attained at a surrounded vertex or on ∂H: with M the best
//        surrounded vertex value and B = max_{∂H} r, the MI is defined iff M exists and
//        M ≥ B (a non-surrounded interior vertex u with r(u) > M cannot be the maximum,
//        and following its ascent direction ends on ∂H or at a surrounded vertex).
//   (F4) Locality: r is 1-Lipschitz, so from a centre c with |c − c*| ≤ ρ the nearest point
//        p has |p − c*| ≤ r(c) + ρ ≤ r* + 2ρ. On the disc D(c*, ρ), r therefore equals the
//        nearest distance to the points within r* + 2ρ of c* alone.
//
// Fast path (round profiles), O(n)
//   1. Kåsa warm start c₀ (internal/extremal_circle.h); candidates: the nearest point to c₀
//      in each of s ≤ 64 pseudo-angle sectors, taken on a stride sample of ~512 points.
//      The same pass marks 256 pseudo-angle occupancy buckets (about c₀) for step 5b.
//   2. The linearised program (internal/inscribed_lp.h): the largest circle about c₀ + δ
//      that no candidate enters, to first order in δ, with costs ρ_i − s kept to ~1e-32
//      relative by double-double arithmetic — so it ranks candidates whose radii differ by
//      1e-16 relative (perfect circles, ulp-level forms), where a floating Voronoi walk sees
//      rounding noise. Re-linearised at c₀ + δ while |δ|²/2ρ exceeds 1e-3 of the costs;
//      steps capped at ρ_min/4 (a trust region). Its basis is three candidates around the
//      model's centre.
//   3. Exact circumcircle of the three (GMP integers, rounded once) and one O(n) pass over
//      all points: a rigorous double filter, then double-double for the ~1e-15 band
//      (internal/precise_distance.h), then the circle's own integers for exact ties
//      (internal/extremal_circle.cpp). Points strictly inside join the candidates (the 32
//      deepest per round, ranked by the finest value available) and step 2 repeats from the
//      circle's centre. Typically 1-2 rounds. Before the pass, a local refinement
//      (internal::local_extreme, at most twice, not for a walk step's triple): each
//      contact's nearest neighbour along the input order within n/64 indices and down the
//      slope beyond (about the circle's centre) joins the candidates when it is not one,
//      and step 2 repeats — on filtered scans that is where the pass's violators were.
//   4. Contacts: the three, and every point found exactly on the circle (ties: co-circular
//      data, symmetric polygons). Among them the reported triple is the acute one of
//      largest β (below): the one nearest in angle to 0°, 120°, 240° from the lowest-index
//      contact, or the program's own triple if that is better. Acute (exact dot-product
//      signs) ⇒ a strict local maximum. No acute triple (the program's basis was degenerate
//      to within rounding: 0 on an edge of its triangle of directions): one step of the
//      Voronoi walk along the edge of the other two contacts (walk_step), and step 3 again.
//   5. Global proof (internal/inscribed_region.h): (a) the contact cone r(c) < r* for
//      0 < |d| < 2r*β (β: distance from 0 to the boundary of the triangle of the v_k);
//      (b) angular coverage for |d| from about the profile's peak-to-valley up to the hull's
//      extent; (c) when a nearly antipodal contact pair leaves a gap between them (β tiny:
//      2-lobe dominated smooth forms), caps of directions at halving scales of |d|, each
//      from the shallowest point of its angular bucket. If (c) fails below some ρ*, every
//      centre as good as c* lies within ρ* of it, and by (F4) the Delaunay triangulation of
//      the points within r* + 2ρ* (a handful near the contacts) is exhausted there: every
//      surrounded vertex with its centre in that disc is compared exactly.
//
// Fallback (whatever the fast path cannot settle: sparse or partial profiles, strongly
// non-round shapes, n < 16), O(n log n): exhaustive.
//   Delaunay triangulation (Epick) of the distinct points (each with its lowest index);
//   every finite face whose circumcentre is surrounded — an acute face, or a right face
//   whose neighbour across the hypotenuse is co-circular (4+ co-circular points with the
//   centre on a diagonal, e.g. a square) — is a local maximum; the best one by floating
//   radius (from the vertex opposite the longest edge: ~30u relative error), with every
//   near-tie (1e-10 relative) compared exactly, is M. B (the maximum of r on ∂H) is
//   bounded by half the longest hull edge; the hull edges that could beat M are walked
//   exactly (GMP rationals) through the Voronoi cells they cross (the next cell is among
//   the Delaunay neighbours of the current site), B_e = max of r at the crossings.
//   MI defined iff a surrounded vertex exists and M ≥ max_e B_e. Global by exhaustion.
//
// Exactness: contacts decided by exact predicates; centre = exact circumcentre rounded
// once (≤ 1.25 ulp per coordinate), radius = sqrt of the exact r*² rounded (~1.3 ulp).
// Contacts are the lowest index among duplicated points. RONt = max_i |p_i − c*| − r*
// computed as (ρ_j² − r*²)/(ρ̃_j + r̃) with the numerator exact (j = the farthest point in
// the last pass): a few ulps of RONt. RONv = 0, RONp = RONt, RONq from
// roundness_parameters about (c̃, r̃).
// Co-circular degeneracy: when no 3 contacts hold the centre strictly inside (a square),
// the 3 reported hold it in their closed triangle and the certificate names the 4th.
//
// Complexity: fast path O(n) (validation, a sample pass, 1-3 full passes, O(1) exact
// work; the cap scales O(n + 256·scales) when needed, a local Delaunay triangulation of
// the few band points); fallback O(n log n) (CGAL Delaunay) + O(n) filtered predicates.
#include "vcmm/geometry/maximum_inscribed.h"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "internal/exact.h"
#include "internal/extremal_circle.h"
#include "internal/inscribed_lp.h"
#include "internal/inscribed_region.h"
#include "internal/maximum_inscribed_detail.h"
#include "internal/precise_distance.h"
#include "internal/prevalidated.h"

namespace vcmm::geometry {

namespace {

using internal::Epick;
using internal::EPoint;
using internal::ExactCircle;
using internal::to_epick;

/// Exact rationals for the rare hull-boundary walk (GMP, canonical).
using Q = mpq_class;
struct QPoint {
  Q x, y;
};
QPoint to_q(const EPoint& p) { return {Q(p.x()), Q(p.y())}; }
Q squared_distance(const QPoint& a, const QPoint& b) {
  const Q dx = a.x - b.x, dy = a.y - b.y;
  return dx * dx + dy * dy;
}

constexpr const char* kCaller = "maximum_inscribed_circle";
constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

// ---------------------------------------------------------------------------------------
// The O(n) pass about an exact circle
// ---------------------------------------------------------------------------------------

/// Rigorous classification of every point about the exact circle.
struct PassResult {
  /// Strictly inside (exact), with a depth key (larger = deeper): the first stage's
  /// r̃² − D̃, or the double-double gap where that stage could not decide.
  std::vector<std::pair<double, std::size_t>> violators;
  std::vector<std::size_t> on_circle;  ///< exactly on the circle, by increasing index
  std::size_t farthest = 0;            ///< argmax of D̃ (scaled units, see scan_distances)
  double max_d2 = 0.0;
  std::size_t exact_calls = 0;
  /// RONq's sums about the circle, taken in the same pass (used when it is the last).
  internal::RonqSums ronq;
};

PassResult classify_all(std::span<const Point2> points, const ExactCircle& circle) {
  PassResult r;
  const Point2 c = circle.center_d;
  thread_local std::vector<std::size_t> flagged;  // inside or ambiguous (kept: no allocation)
  flagged.clear();
  r.on_circle.reserve(8);  // the contacts and their duplicates: one allocation
  const double hi = circle.filter_usable ? circle.outside_above
                                         : std::numeric_limits<double>::infinity();
  r.ronq.radius = circle.radius;
  r.ronq.inv_scale = internal::ronq_inv_scale(points, c, circle.radius);
  const internal::DistanceScan scan = internal::scan_distances<internal::Track::kFarthest>(
      points, c, circle.scale, hi, flagged, &r.ronq);
  r.farthest = scan.index;
  r.max_d2 = scan.d2;
  const double r2s = circle.radius_scaled * circle.radius_scaled;
  for (std::size_t i : flagged) {
    const double d2 = internal::scaled_distance2(points[i], c, circle.scale);
    if (circle.filter_usable && d2 < circle.inside_below) {
      r.violators.push_back({r2s - d2, i});  // strictly inside
      continue;
    }
    ++r.exact_calls;
    double gap = d2 - r2s;
    const CGAL::Bounded_side side = internal::exact_side(circle, points[i], &gap);
    if (side == CGAL::ON_BOUNDED_SIDE) r.violators.push_back({-gap, i});
    if (side == CGAL::ON_BOUNDARY) r.on_circle.push_back(i);
  }
  return r;
}

// ---------------------------------------------------------------------------------------
// Result assembly (both paths)
// ---------------------------------------------------------------------------------------

MaximumInscribedCircle make_result(std::span<const Point2> points, const ExactCircle& circle,
                                   const std::array<std::size_t, 3>& contacts,
                                   std::size_t farthest, double max_d2,
                                   Certificate certificate,
                                   const internal::RonqSums* ronq = nullptr) {
  MaximumInscribedCircle mi;
  mi.center = circle.center_d;
  mi.radius = circle.radius;
  mi.contacts.assign(contacts.begin(), contacts.end());
  // Scaled units: (ρ² − r*²)s² / ((ρ + r*)s), then back by s⁻¹ (exact).
  const double gap_s = -internal::exact_power_gap(circle, points[farthest]);  // ≥ 0 exactly
  const double ront = gap_s > 0.0 ? std::ldexp(gap_s / (std::sqrt(max_d2) + circle.radius_scaled),
                                               -circle.scale_exponent)
                                  : 0.0;
  // RONq (RONt bounds every deviation from the radius: it picks the distance series'
  // degree), from the sums of the circle's pass when it took them.
  mi.ron.ronq = ronq ? internal::ronq_of_valid(points, mi.center, mi.radius, ront, *ronq)
                     : internal::roundness_parameters_of_valid(points, mi.center, mi.radius,
                                                               ront).ronq;
  mi.ron.ront = ront;
  mi.ron.ronp = mi.ron.ront;
  mi.ron.ronv = 0.0;
  mi.certificate = std::move(certificate);
  return mi;
}

// ---------------------------------------------------------------------------------------
// Delaunay exhaustion (the fallback, and the local step of the fast path)
// ---------------------------------------------------------------------------------------

using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::size_t, Epick>;
using Fb = CGAL::Triangulation_face_base_2<Epick>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Delaunay = CGAL::Delaunay_triangulation_2<Epick, Tds>;

/// Floating circumradius² of a non-obtuse triangle, from the vertex opposite the longest
/// edge (angle in [60°, 90°], sin ≥ 0.86): relative error below ~30u.
double circumradius2(Point2 a, Point2 b, Point2 c) {
  auto d2 = [](Point2 p, Point2 q) {
    const double dx = p.x - q.x, dy = p.y - q.y;
    return dx * dx + dy * dy;
  };
  const double ab = d2(a, b), bc = d2(b, c), ca = d2(c, a);
  // Relabel so that a is the vertex opposite the longest edge (then bc is that edge).
  if (ab >= bc && ab >= ca) {
    std::swap(a, c);
  } else if (ca >= bc && ca >= ab) {
    std::swap(a, b);
  }
  const double ux = b.x - a.x, uy = b.y - a.y, vx = c.x - a.x, vy = c.y - a.y;
  const double cross = ux * vy - uy * vx;
  return (ux * ux + uy * uy) * (vx * vx + vy * vy) * d2(b, c) / (4.0 * cross * cross);
}

struct Surrounded {
  std::array<std::size_t, 3> contacts{};  ///< input indices (lowest among duplicates)
  std::size_t extra = kNone;               ///< 4th co-circular contact, or kNone
  double r2 = 0.0;                         ///< floating
};

/// Delaunay triangulation of the distinct points among `which` (each with its lowest
/// index).
void triangulate(std::span<const Point2> points, std::vector<std::size_t> which,
                 Delaunay& dt) {
  std::sort(which.begin(), which.end(), [&](std::size_t a, std::size_t b) {
    const Point2 &p = points[a], &q = points[b];
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    return a < b;
  });
  which.erase(std::unique(which.begin(), which.end(),
                          [&](std::size_t a, std::size_t b) { return points[a] == points[b]; }),
              which.end());
  std::vector<std::pair<EPoint, std::size_t>> input;
  input.reserve(which.size());
  for (std::size_t i : which) input.emplace_back(to_epick(points[i]), i);
  dt.insert(input.begin(), input.end());
}

/// Surrounded Voronoi vertices: acute faces, and right faces whose neighbour across the
/// hypotenuse is co-circular (the centre is then interior to the co-circular
/// quadrilateral). Exact angle and in-circle predicates.
std::vector<Surrounded> surrounded_vertices(const Delaunay& dt) {
  std::vector<Surrounded> found;
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
    const std::array<EPoint, 3> p{f->vertex(0)->point(), f->vertex(1)->point(),
                                  f->vertex(2)->point()};
    const std::array<Point2, 3> d{Point2{p[0].x(), p[0].y()}, Point2{p[1].x(), p[1].y()},
                                  Point2{p[2].x(), p[2].y()}};
    int right = -1;
    bool obtuse = false;
    for (int k = 0; k < 3; ++k) {
      const int sign = internal::dot_sign(d[k], d[(k + 1) % 3], d[(k + 2) % 3]);
      if (sign < 0) {
        obtuse = true;
        break;
      }
      if (sign == 0) right = k;
    }
    if (obtuse) continue;
    Surrounded s;
    for (int k = 0; k < 3; ++k) s.contacts[k] = f->vertex(k)->info();
    if (right >= 0) {
      const auto g = f->neighbor(right);
      if (dt.is_infinite(g)) continue;
      const auto w = g->vertex(g->index(f));
      if (dt.side_of_oriented_circle(f, w->point()) != CGAL::ON_ORIENTED_BOUNDARY) continue;
      s.extra = w->info();
    }
    s.r2 = circumradius2(d[0], d[1], d[2]);
    found.push_back(s);
  }
  return found;
}

/// The largest of `found` by exact comparison among the near-ties (1e-10 relative) of the
/// floating maximum, restricted to those `accept` takes; ties = other centres with exactly
/// the same radius.
template <class Accept>
const Surrounded* best_vertex(std::span<const Point2> points,
                              const std::vector<Surrounded>& found, Accept accept,
                              ExactCircle& best_circle, std::size_t& ties) {
  double best_r2 = -1.0;
  for (const Surrounded& s : found) best_r2 = std::max(best_r2, s.r2);
  const Surrounded* best = nullptr;
  ties = 0;
  for (const Surrounded& s : found) {
    if (s.r2 < best_r2 * (1.0 - 1e-10)) continue;
    ExactCircle c = internal::exact_circumcircle(points[s.contacts[0]], points[s.contacts[1]],
                                                 points[s.contacts[2]]);
    if (!accept(c)) continue;
    const int cmp = best == nullptr ? 1 : internal::compare_radius(c, best_circle);
    if (cmp > 0) {
      best = &s;
      best_circle = std::move(c);
      ties = 0;
    } else if (cmp == 0 && !internal::same_center(c, best_circle)) {
      ++ties;
    }
  }
  return best;
}

/// Max of r over the hull edge (u, w): walk from u to w through the Voronoi cells the
/// segment crosses (exact rationals; candidate next cells are the Delaunay neighbours of
/// the current site). Returns the exact max of r² at the crossings.
Q hull_edge_max(const Delaunay& dt, Delaunay::Vertex_handle u,
                       Delaunay::Vertex_handle w) {
  const QPoint ru = to_q(u->point()), rw = to_q(w->point());
  const Q ex = rw.x - ru.x, ey = rw.y - ru.y;
  Q best(0);
  Delaunay::Vertex_handle s = u;
  // Each step moves to a different Voronoi cell along a segment: at most n steps.
  for (std::size_t guard = 0; s != w && guard <= dt.number_of_vertices(); ++guard) {
    const QPoint rs = to_q(s->point());
    const Q us2 = squared_distance(ru, rs);
    Delaunay::Vertex_handle next;
    Q next_t, next_slope;
    bool found = false;
    Delaunay::Vertex_circulator vc = dt.incident_vertices(s), done = vc;
    do {
      if (dt.is_infinite(vc)) continue;
      const QPoint rq = to_q(vc->point());
      const Q slope = ex * (rq.x - rs.x) + ey * (rq.y - rs.y);
      if (!CGAL::is_positive(slope)) continue;
      // |x(t) − q|² − |x(t) − s|² = |u − q|² − |u − s|² − 2t·slope = 0.
      const Q t = (squared_distance(ru, rq) - us2) / (slope * 2);
      if (!found || t < next_t || (t == next_t && slope > next_slope)) {
        found = true;
        next = vc;
        next_t = t;
        next_slope = slope;
      }
    } while (++vc != done);
    if (!found) break;
    if (next_t > 1) break;
    const QPoint x{ru.x + next_t * ex, ru.y + next_t * ey};
    const Q r2 = squared_distance(x, rs);
    if (r2 > best) best = r2;
    s = next;
  }
  return best;
}

MaximumInscribedCircle exhaustive(std::span<const Point2> points) {
  std::vector<std::size_t> all(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) all[i] = i;
  Delaunay dt;
  triangulate(points, std::move(all), dt);
  if (dt.dimension() < 2)
    throw std::logic_error(std::string(kCaller) + ": triangulation is not 2D (internal)");
  const std::vector<Surrounded> found = surrounded_vertices(dt);
  if (found.empty())
    throw UndefinedResult(std::string(kCaller) +
                          ": no Voronoi vertex is surrounded by its nearest points (every "
                          "Delaunay triangle is obtuse): the largest empty circle centred in "
                          "the convex hull touches the hull boundary — partial arc or too "
                          "sparse a profile; the MI circle is not defined");
  ExactCircle best_circle;
  std::size_t ties = 0;
  const Surrounded* best =
      best_vertex(points, found, [](const ExactCircle&) { return true; }, best_circle, ties);
  double best_r2 = -1.0;
  for (const Surrounded& s : found) best_r2 = std::max(best_r2, s.r2);

  // Hull boundary: B ≤ max over hull edges of |e|/2; edges that might reach M are walked.
  std::size_t walked = 0;
  {
    const Q m2 = internal::exact_r2(best_circle);
    Delaunay::Vertex_circulator vc = dt.incident_vertices(dt.infinite_vertex()), done = vc;
    do {
      Delaunay::Vertex_circulator next = vc;
      ++next;
      const EPoint &pu = vc->point(), &pw = next->point();
      const double dx = pu.x() - pw.x(), dy = pu.y() - pw.y();
      const double quarter = 0.25 * (dx * dx + dy * dy);
      // Floating screen: 1e-6 relative is far above the few-ulp error of either side.
      if (quarter < best_r2 * (1.0 - 1e-6)) continue;
      const Q half2 = squared_distance(to_q(pu), to_q(pw)) / 4;
      if (half2 <= m2) continue;
      ++walked;
      const Q b2 = hull_edge_max(dt, vc, next);
      if (b2 > m2) {
        std::ostringstream os;
        os << kCaller << ": the largest empty circle centred in the convex hull has its "
           << "centre on the hull boundary (between points " << vc->info() << " and "
           << next->info() << ", radius " << std::sqrt(CGAL::to_double(b2))
           << " > best surrounded Voronoi vertex " << best_circle.radius
           << ") — partial arc or too sparse a profile; the MI circle is not defined";
        throw UndefinedResult(os.str());
      }
    } while (++vc != done);
  }

  // Farthest point for RONt (scaled units).
  std::vector<std::size_t> none;
  const internal::DistanceScan far = internal::scan_distances<internal::Track::kFarthest>(
      points, best_circle.center_d, best_circle.scale,
      -std::numeric_limits<double>::infinity(), none);
  std::ostringstream arg;
  arg << "exhaustive: Delaunay triangulation of " << dt.number_of_vertices()
      << " distinct points; " << found.size()
      << " surrounded Voronoi vertices (exact angle/in-circle predicates), the best by exact "
         "comparison of r^2";
  if (best->extra != kNone)
    arg << " (4 co-circular contacts: with point " << best->extra
        << " the centre is interior to their hull; the 3 reported contain it in their closed "
           "triangle)";
  else
    arg << "; exact centre strictly inside the contact triangle";
  arg << "; hull boundary bounded by half edge lengths, " << walked
      << " hull edge(s) walked exactly; global by exhaustion";
  if (ties > 0) arg << "; " << ties << " other centre(s) with exactly the same radius";
  return make_result(points, best_circle, best->contacts, far.index, far.d2,
                     Certificate{Optimality::global, arg.str(), 0.0});
}

// ---------------------------------------------------------------------------------------
// Fast path
// ---------------------------------------------------------------------------------------

/// Exact: the triangle a, b, c is acute (its circumcentre strictly inside).
bool is_acute(Point2 a, Point2 b, Point2 c) {
  return internal::dot_sign(a, b, c) > 0 && internal::dot_sign(b, a, c) > 0 &&
         internal::dot_sign(c, a, b) > 0;
}

/// β of step 5a in floating point (selection only; the proof recomputes it rigorously):
/// the least half-length |v_k + v_l|/2 over the triangle's edges.
double beta_of(std::span<const Point2> points, Point2 c, const std::array<std::size_t, 3>& t) {
  std::array<double, 3> vx{}, vy{};
  for (std::size_t k = 0; k < 3; ++k) {
    const double dx = c.x - points[t[k]].x, dy = c.y - points[t[k]].y;
    const double l = std::hypot(dx, dy);
    vx[k] = dx / l;
    vy[k] = dy / l;
  }
  double beta = 1.0;
  for (std::size_t k = 0; k < 3; ++k)
    beta = std::min(beta, 0.5 * std::hypot(vx[k] + vx[(k + 1) % 3], vy[k] + vy[(k + 1) % 3]));
  return beta;
}

/// Step 4: the reported contact triple among the program's `triple` and the points found
/// exactly on the circle (`ties`, ascending, so ties.front() is the lowest index): acute, of
/// largest β. None when no acute triple is found (not a strict local maximum as far as this
/// step can tell).
std::optional<std::array<std::size_t, 3>> contact_triple(std::span<const Point2> points,
                                                         const ExactCircle& circle,
                                                         std::array<std::size_t, 3> triple,
                                                         const std::vector<std::size_t>& ties) {
  const Point2 c = circle.center_d;
  std::optional<std::array<std::size_t, 3>> best;
  double best_beta = -1.0;
  auto consider = [&](const std::array<std::size_t, 3>& t) {
    if (points[t[0]] == points[t[1]] || points[t[1]] == points[t[2]] ||
        points[t[0]] == points[t[2]])
      return;
    const double b = beta_of(points, c, t);
    if (b <= best_beta || !is_acute(points[t[0]], points[t[1]], points[t[2]])) return;
    best = t;
    best_beta = b;
  };
  consider(triple);
  if (ties.empty()) return best;
  // The contacts nearest in angle to 120° and 240° from the lowest-index contact a: all lie
  // on one circle about c, so the largest dot product with the turned direction of a picks
  // them (floating: a selection only, the triple is checked exactly).
  std::size_t ia = std::min({triple[0], triple[1], triple[2], ties.front()});
  const double ax = points[ia].x - c.x, ay = points[ia].y - c.y;
  constexpr double kCos = -0.5, kSin = 0.8660254037844386;  // of 120°
  const std::array<std::array<double, 2>, 2> target{
      {{kCos * ax - kSin * ay, kSin * ax + kCos * ay},
       {kCos * ax + kSin * ay, -kSin * ax + kCos * ay}}};
  std::array<std::size_t, 3> t{ia, ia, ia};
  std::array<double, 2> dot{-std::numeric_limits<double>::infinity(),
                            -std::numeric_limits<double>::infinity()};
  auto visit = [&](std::size_t i) {
    const double x = points[i].x - c.x, y = points[i].y - c.y;
    for (std::size_t k = 0; k < 2; ++k) {
      const double d = x * target[k][0] + y * target[k][1];
      if (d > dot[k]) {
        dot[k] = d;
        t[k + 1] = i;
      }
    }
  };
  for (std::size_t i : ties) visit(i);
  for (std::size_t i : triple) visit(i);
  consider(t);
  return best;
}

/// Step 4, repair: the program's triple gives an empty circle whose triangle is right or
/// obtuse (its basis was degenerate to within rounding: 0 on the edge of the triangle of
/// directions). Then r grows from the centre along the bisector of the two other contacts,
/// away from the wide-angle vertex, until a point X becomes equidistant: with n that unit
/// direction, |c + tn − X|² − |c + tn − B|² = g(X) − 2t·n·(X − B) with g(X) = |c − X|² − r²
/// ≥ 0, so X minimises g(X)/(2n·(X − B)) over the points ahead. One step of the Voronoi walk;
/// g from the double-double gap where the first stage cannot resolve it. The next triple is
/// re-derived exactly by the caller, like the program's.
std::optional<std::array<std::size_t, 3>> walk_step(std::span<const Point2> points,
                                                    const ExactCircle& circle,
                                                    const std::array<std::size_t, 3>& t) {
  int wide = -1;
  for (int k = 0; k < 3; ++k)
    if (internal::dot_sign(points[t[static_cast<std::size_t>(k)]],
                           points[t[static_cast<std::size_t>((k + 1) % 3)]],
                           points[t[static_cast<std::size_t>((k + 2) % 3)]]) <= 0)
      wide = k;
  if (wide < 0) return std::nullopt;
  const std::size_t ia = t[static_cast<std::size_t>(wide)];
  const std::size_t ib = t[static_cast<std::size_t>((wide + 1) % 3)];
  const std::size_t ic = t[static_cast<std::size_t>((wide + 2) % 3)];
  const Point2 a = points[ia], b = points[ib], cc = points[ic];
  double nx = -(cc.y - b.y), ny = cc.x - b.x;
  if (nx * (a.x - b.x) + ny * (a.y - b.y) > 0.0) {
    nx = -nx;
    ny = -ny;
  }
  const double s = circle.scale, r2 = circle.radius_scaled * circle.radius_scaled;
  const Point2 c = circle.center_d;
  const bool precise = circle.filter_usable && circle.precise().usable;
  std::size_t best = kNone;
  double best_num = 1.0, best_den = 0.0;  // +infinity
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Point2 x = points[i];
    if (x == a || x == b || x == cc) continue;
    const double den = (nx * (x.x - b.x) + ny * (x.y - b.y)) * s;
    if (!(den > 0.0)) continue;
    double g = internal::scaled_distance2(x, c, s) - r2;
    if (precise && g < 0x1.0p20 * internal::kUnitRoundoff)
      g = internal::precise_power_gap(circle.precise(), x).value;
    g = std::max(g, 0.0);
    if (best == kNone || g * best_den < best_num * den) {
      best = i;
      best_num = g;
      best_den = den;
    }
  }
  if (best == kNone) return std::nullopt;  // an unbounded Voronoi edge: no maximum ahead
  return std::array<std::size_t, 3>{ib, ic, best};
}

/// Step 5, local part: the Delaunay triangulation of the points within r* + 2ρ of c*
/// (F4), where ρ = region.radius; its surrounded vertices with centres in D(c*, ρ) are
/// compared exactly with the fast path's circle. Returns the winner and its contacts.
struct LocalOutcome {
  ExactCircle circle;
  std::array<std::size_t, 3> contacts{};
  std::size_t extra = kNone;
  std::size_t sites = 0, vertices = 0;
};
std::optional<LocalOutcome> local_exhaustion(std::span<const Point2> points,
                                             const ExactCircle& circle,
                                             const std::array<std::size_t, 3>& contacts,
                                             double radius) {
  const double u = internal::kUnitRoundoff;
  const double delta = circle.center_error_scaled;
  // Sites: |p − c*| ≤ r* + 2ρ_b with ρ_b = ρ + 16δ (the acceptance test below keeps
  // centres within ρ + 12δ of c*); selected on D̃ with margins for its rounding (4.1u) and
  // for δ.
  const double rho_b = radius + 16.0 * delta;
  const double reach = (circle.radius_scaled * (1.0 + 8.0 * u) + 2.0 * rho_b + delta) *
                       (1.0 + 8.0 * u);
  const double reach2 = reach * reach;
  const Point2 c = circle.center_d;
  std::vector<std::size_t> sites;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (internal::scaled_distance2(points[i], c, circle.scale) <= reach2) sites.push_back(i);
  LocalOutcome out;
  out.sites = sites.size();
  Delaunay dt;
  triangulate(points, std::move(sites), dt);
  if (dt.dimension() < 2) return std::nullopt;
  const std::vector<Surrounded> found = surrounded_vertices(dt);
  out.vertices = found.size();
  // Accept centres within ρ + 8δ of c̃ (computed distance; its error, < 2δ + 4u·dist, keeps
  // every accepted centre within ρ + 12δ of c* and every rejected one beyond ρ): accepted
  // ones are true Voronoi vertices of all points (F4); rejected ones are worse than r*.
  auto accept = [&](const ExactCircle& e) {
    const double dx = (e.center_d.x - c.x) * circle.scale;
    const double dy = (e.center_d.y - c.y) * circle.scale;
    return std::hypot(dx, dy) * (1.0 - 8.0 * u) <= radius + 8.0 * delta;
  };
  ExactCircle best_circle;
  std::size_t ties = 0;
  const Surrounded* best = best_vertex(points, found, accept, best_circle, ties);
  if (best == nullptr || internal::compare_radius(best_circle, circle) <= 0) {
    out.circle = circle;
    out.contacts = contacts;
    return out;
  }
  out.circle = std::move(best_circle);
  out.contacts = best->contacts;
  out.extra = best->extra;
  return out;
}

std::optional<MaximumInscribedCircle> fast_path(std::span<const Point2> points,
                                                const internal::SectorSample* shared) {
  const std::size_t n = points.size();
  // Candidates: the nearest point to c0 in each of the sample's pseudo-angle sectors (64 for
  // dense profiles, ≥ 8 points per sector for small n), on a stride sample of ~512 points:
  // the contacts the sample misses are violators of the first round (found by the O(n)
  // pass that runs anyway), and the coverage proof needs only some points in every
  // direction, not all (any subset of points lies at distance ≥ r* from c*). The same
  // sample marks 256 pseudo-angle occupancy buckets about c0 for the global proof; it is the
  // caller's when it has taken it for MC too (internal::sector_sample).
  std::optional<internal::SectorSample> own;
  const internal::SectorSample& sample =
      shared ? *shared : own.emplace(internal::sector_sample(points));
  const Point2 c0 = sample.warm.center;
  const std::array<std::uint64_t, 4>& occupied = sample.occupied;
  // Warm-start arithmetic on (p − c0)·s0 (s0 a power of two: coordinates O(1) whatever the
  // input magnitude; the program and the sectors are invariant under scaling).
  internal::InscribedLp lp(points, sample.warm.scale);
  std::size_t candidates = 0;
  for (const std::size_t i : sample.nearest)
    if (i < n) {
      lp.add(i);
      ++candidates;
    }

  Point2 c = c0;
  // Rounds: linearisations, violator rounds and walk steps together. 24 is far above what
  // round profiles need (2-4); beyond it the fallback is cheaper than more rounds.
  int violator_rounds = 0;
  int refinements = 0;  // local refinements (no O(n) pass)
  constexpr int kMaxRefinements = 2;
  std::optional<std::array<std::size_t, 3>> walked;  // the next triple, from a walk step
  std::array<std::size_t, 3> last{kNone, kNone, kNone};  // the program's previous triple
  for (int round = 0; round < 24; ++round) {
    std::array<std::size_t, 3> triple{};
    const bool from_walk = walked.has_value();
    if (walked) {
      triple = *walked;
      walked.reset();
    } else {
      if (!lp.solve(c)) return std::nullopt;
      const Point2 delta = lp.delta();
      const double step = std::hypot(delta.x, delta.y);
      // Trust region: the model is only good for |δ| ≪ ρ.
      const double max_step = 0.25 * lp.rho_min();
      if (step > max_step) {
        c = {c.x + delta.x * max_step / step, c.y + delta.y * max_step / step};
        continue;
      }
      if (lp.relative_linearisation_error() > 1e-3) {
        c = {c.x + delta.x, c.y + delta.y};
        continue;
      }
      triple = lp.basis_points();
      // The same basis again although the last round added violators or walked on: its
      // plain costs cannot separate these points (radii within ~u·ρ of each other near the
      // optimum). Precise costs from now on.
      if (triple == last) lp.force_precise();
      last = triple;
    }
    const Point2 pa = points[triple[0]], pb = points[triple[1]], pc = points[triple[2]];
    if (CGAL::orientation(to_epick(pa), to_epick(pb), to_epick(pc)) == CGAL::COLLINEAR)
      return std::nullopt;
    const ExactCircle circle = internal::exact_circumcircle(pa, pb, pc);
    // Local refinement (internal::local_extreme): a contact of the program's triple with a
    // nearer neighbour along the profile about this centre is a few indices off a contact
    // of the full set; add those neighbours and re-solve before paying for the O(n) pass
    // (twice at most, and not for a walk step's triple).
    if (!from_walk && refinements < kMaxRefinements && circle.filter_usable) {
      bool grew = false;
      for (const std::size_t k : triple) {
        const std::size_t j =
            internal::local_extreme<false>(points, k, circle.center_d, circle.scale, n / 64, n / 8);
        if (j != k && !lp.contains(j)) {
          lp.add(j);
          ++candidates;
          grew = true;
        }
      }
      if (grew) {
        ++refinements;
        c = circle.center_d;
        continue;
      }
    }
    PassResult pass = classify_all(points, circle);
    if (!pass.violators.empty()) {
      // Add the deepest violators (at most 32 a round keeps the program small; any one of
      // them already invalidates the circle).
      auto& vio = pass.violators;
      const std::size_t keep = std::min<std::size_t>(32, vio.size());
      std::partial_sort(vio.begin(), vio.begin() + static_cast<std::ptrdiff_t>(keep), vio.end(),
                        [](const auto& a, const auto& b) {
                          return a.first > b.first || (a.first == b.first && a.second < b.second);
                        });
      for (std::size_t k = 0; k < keep; ++k) lp.add(vio[k].second);
      candidates += keep;
      ++violator_rounds;
      c = circle.center_d;
      continue;
    }
    // Steps 4-5.
    const std::optional<std::array<std::size_t, 3>> chosen =
        contact_triple(points, circle, triple, pass.on_circle);
    if (!chosen) {
      walked = walk_step(points, circle, triple);
      if (!walked) return std::nullopt;
      lp.add((*walked)[2]);
      c = circle.center_d;
      continue;
    }
    std::array<std::size_t, 3> contacts = *chosen;
    const internal::InscribedRegion region = internal::inscribed_region(
        points, circle, contacts, pass.max_d2, occupied, c0);
    std::ostringstream arg;
    arg << "fast path: exact centre strictly inside the triangle of 3 contacts (exact "
           "dot-product signs); no point strictly inside the circle (floating filters with "
           "rigorous bounds, "
        << pass.exact_calls << " second-stage/exact tests, " << violator_rounds + 1
        << " round(s), " << candidates << " candidates";
    if (refinements > 0) arg << ", " << refinements << " local refinement(s) of the contacts";
    if (pass.on_circle.size() > 3)
      arg << ", " << pass.on_circle.size() << " points exactly on the circle";
    arg << "); global: r < r* for 0 < |c - c*| < 2r*·beta = "
        << std::ldexp(region.t1, -circle.scale_exponent)
        << " mm (contact cone), and from " << std::ldexp(region.t_cov, -circle.scale_exponent)
        << " mm up to the hull's extent by angular coverage of the points about the centre";
    if (region.proven) {
      if (region.scales > 0)
        arg << ", in between by caps of directions at " << region.scales << " halving scales";
      for (std::size_t& k : contacts)  // lowest index among duplicates (all on the circle)
        for (std::size_t i : pass.on_circle)
          if (i < k && points[i] == points[k]) k = i;
      const double t1 = std::ldexp(region.t1, -circle.scale_exponent);  // back to mm
      Certificate cert{Optimality::global, arg.str(), t1};
      return make_result(points, circle, contacts, pass.farthest, pass.max_d2,
                         std::move(cert), &pass.ronq);
    }
    if (!std::isfinite(region.radius)) return std::nullopt;
    const std::optional<LocalOutcome> local =
        local_exhaustion(points, circle, contacts, region.radius);
    if (!local) return std::nullopt;
    const double rho = std::ldexp(region.radius, -circle.scale_exponent);
    arg << ", in between by caps of directions at " << region.scales
        << " halving scales down to " << rho
        << " mm; within that distance every centre was exhausted: Delaunay triangulation of "
           "the "
        << local->sites << " points that can be nearest from there (within r* + 2·" << rho
        << " mm of the centre), " << local->vertices
        << " surrounded Voronoi vertices, compared exactly";
    if (local->extra != kNone)
      arg << " (4 co-circular contacts: with point " << local->extra
          << " the centre is interior to their hull)";
    std::vector<std::size_t> none;
    const internal::DistanceScan far = internal::scan_distances<internal::Track::kFarthest>(
        points, local->circle.center_d, local->circle.scale,
        -std::numeric_limits<double>::infinity(), none);
    std::array<std::size_t, 3> k3 = local->contacts;
    for (std::size_t& k : k3)  // lowest index among duplicates
      for (std::size_t i = 0; i < k; ++i)
        if (points[i] == points[k]) {
          k = i;
          break;
        }
    Certificate cert{Optimality::global, arg.str(), rho};
    return make_result(points, local->circle, k3, far.index, far.d2, std::move(cert));
  }
  return std::nullopt;
}

}  // namespace

MaximumInscribedCircle maximum_inscribed_circle(std::span<const Point2> points) {
  validate_profile(points, 3, kCaller, /*require_non_collinear=*/true);
  return internal::fit_maximum_inscribed_circle(points);
}

MaximumInscribedCircle internal::maximum_inscribed_exhaustive(std::span<const Point2> points) {
  return exhaustive(points);
}

MaximumInscribedCircle internal::fit_maximum_inscribed_circle(std::span<const Point2> points,
                                                              const SectorSample* shared) {
  // Small inputs: the exhaustive method is as fast and needs no warm start.
  if (points.size() >= 16) {
    if (std::optional<MaximumInscribedCircle> mi = fast_path(points, shared))
      return *std::move(mi);
  }
  return exhaustive(points);
}

}  // namespace vcmm::geometry
