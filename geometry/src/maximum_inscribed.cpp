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
//
// Fast path (round profiles), O(n)
//   1. Kåsa warm start c₀ (internal/extremal_circle.h); candidates: the nearest point to c₀
//      in each of s ≤ 64 pseudo-angle sectors, taken on a stride sample of ~512 points.
//      The same pass marks 256 pseudo-angle occupancy buckets (about c₀) for step 5b.
//   2. A Voronoi walk on the candidates (floating, heuristic): from c₀ go straight away
//      from the nearest candidate until a second one is equidistant, then along that
//      Voronoi edge away from the pair's midpoint to a vertex; while the vertex's triangle
//      is not acute, leave along the edge of the pair opposite the non-acute angle, away
//      from the third point. r strictly increases along every step (the distance to the
//      pair grows away from its midpoint, the third point recedes faster), so the walk
//      ends at a local maximum of the candidates' r. Fractions compared by
//      cross-multiplication; O(candidates) per step.
//   3. Exact circumcircle of the three contacts (GMP integers, rounded once) and one O(n)
//      pass over all points with the rigorous floating filter (internal/extremal_circle.cpp;
//      exact in-circle predicates on the contacts only in the ~1e-15 relative band).
//      Points strictly inside join the candidates (the 32 deepest per round) and the walk
//      restarts from the vertex. Typically 1-2 rounds (the sample misses the deepest
//      points of a dense profile; the first full pass finds them).
//   4. Exact acuteness of the contact triangle (signs of dot products: a floating value
//      with a rigorous bound, CGAL's exact Angle_2 otherwise) ⇒ strict local maximum.
//   5. Global proof (rigorous bounds on every floating quantity: see prove_global):
//      (a) local disc: by (F1), r(c)² ≤ r*² + |d|² + 2r*·min_k v_k·d (each |c − p_k|² is
//          exactly r*² + 2r*·v_k·d + |d|²; the lead's "linearisation of the concave
//          min_k g_k" gives the same bound). With β = distance from 0 to ∂conv{v_k}
//          (= min over the triangle's edges of |v_k + v_l|/2, the chord midpoints, for unit
//          vectors), min_k v_k·d ≤ −β|d|, so r(c) < r* for 0 < |d| < 2r*β.
//      (b) angular coverage: every point lies at distance ρ ∈ [r*, R_max] from c* (none is
//          inside the circle). If every direction e seen from c* has a point within angle
//          h of it, then for c = c* + t·e
//            r(c)² ≤ |c − p|² = t² + ρ² − 2tρ·cos α ≤ max_{ρ ∈ {r*, R_max}} t² + ρ² − 2tρ·cos h
//          (convex in ρ). Both quadratics are convex in t, so checking them < r*² at
//          t₁ = 2r*β (a lower bound of it) and t₂ = R_max (an upper bound; H lies in the
//          disc (c*, R_max)) proves r(c) < r* for every centre of H with |d| ∈ [t₁, t₂].
//          Any subset of the points may serve (each still has ρ ∈ [r*, R_max]): we use the
//          stride sample of step 1. h: with E the longest circular run of empty buckets,
//          circularly consecutive sample points are < (E + 2)/64 pseudo units apart about
//          c₀, i.e. < 2(E + 2)/64 rad (pseudo_angle's derivative is ≥ 1/2); the nearer of
//          two is within half of that; moving the viewpoint from c₀ to c* turns each
//          direction by ≤ asin(d₀/ρ) ≤ (π/2)·d₀/r* (d₀ = |c* − c₀| < r*/2). O(n), no sort.
//          On round profiles h ≈ 0.05 rad and t₁ ≈ 0.1-0.9·r*: the two ranges overlap by a
//          wide margin (the quadratic in ρ = R_max is negative from t ≈ R_max − r*).
//      (a) ∪ (b) cover H \ {c*}: c* is the unique maximiser of r over H, so the MI is
//      defined and global. The certificate's region_radius is t₁ (the radius of the disc
//      of (a); outside it (b) applies).
//
// Fallback (whatever the fast path cannot prove: sparse or partial profiles, strongly
// non-round shapes, degenerate co-circular candidates, n < 16), O(n log n): exhaustive.
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
// work); fallback O(n log n) (CGAL Delaunay) + O(n) filtered predicates.
#include "vcmm/geometry/maximum_inscribed.h"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "internal/exact.h"
#include "internal/extremal_circle.h"
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

// ---------------------------------------------------------------------------------------
// Fast path
// ---------------------------------------------------------------------------------------

struct Candidate {
  double x = 0.0;  ///< (p − c0)·s0, relative to the warm start (rounded: heuristic use only)
  double y = 0.0;
  std::size_t index = 0;
};

struct LocalVertex {
  std::array<int, 3> pos{};  ///< positions in the candidate list
};

/// Floating circumcentre of three candidates (relative to the first); false if degenerate.
bool circumcentre(const Candidate& a, const Candidate& b, const Candidate& c, double& x,
                  double& y) {
  const double ux = b.x - a.x, uy = b.y - a.y, vx = c.x - a.x, vy = c.y - a.y;
  const double d = 2.0 * (ux * vy - uy * vx);
  if (d == 0.0 || !std::isfinite(d)) return false;
  const double u2 = ux * ux + uy * uy, v2 = vx * vx + vy * vy;
  x = a.x + (vy * u2 - uy * v2) / d;
  y = a.y + (ux * v2 - vx * u2) / d;
  return std::isfinite(x) && std::isfinite(y);
}

/// Among candidates p (other than the excluded positions) with den = n·(p − o) > 0, the one
/// that becomes equidistant first when moving from x along n, where o is at distance² r2
/// from x: t_p = (|x − p|² − r2)/(2·den). Returns −1 if none.
int first_equidistant(const std::vector<Candidate>& q, double x, double y, double nx,
                      double ny, const Candidate& o, double r2, int ex0, int ex1) {
  // Fractions compared by cross-multiplication (den > 0): no division in the loop.
  int best = -1;
  double best_num = 1.0, best_den = 0.0;  // +infinity
  for (int k = 0; k < static_cast<int>(q.size()); ++k) {
    if (k == ex0 || k == ex1) continue;
    const double den = nx * (q[k].x - o.x) + ny * (q[k].y - o.y);
    if (!(den > 0.0)) continue;
    const double dx = x - q[k].x, dy = y - q[k].y;
    const double num = dx * dx + dy * dy - r2;
    if (best < 0 || num * best_den < best_num * den) {
      best_num = num;
      best_den = den;
      best = k;
    }
  }
  return best;
}

/// The Voronoi walk of step 2, from (x0, y0). Returns the acute triple reached, or nothing
/// when the walk leaves to infinity, degenerates or exceeds its step budget (the caller
/// then falls back to the exhaustive method).
std::optional<LocalVertex> voronoi_walk(const std::vector<Candidate>& q, double x0,
                                        double y0) {
  const int m = static_cast<int>(q.size());
  if (m < 3) return std::nullopt;
  int a = 0;
  double da = std::numeric_limits<double>::infinity();
  for (int k = 0; k < m; ++k) {
    const double dx = x0 - q[k].x, dy = y0 - q[k].y, d2 = dx * dx + dy * dy;
    if (d2 < da) {
      da = d2;
      a = k;
    }
  }
  // Leave the nearest candidate a along the ray from a through x0.
  double wx = x0 - q[a].x, wy = y0 - q[a].y;
  double wl = std::hypot(wx, wy);
  if (wl == 0.0) {
    wx = 1.0;
    wy = 0.0;
    wl = 1.0;
  }
  wx /= wl;
  wy /= wl;
  const int b = first_equidistant(q, x0, y0, wx, wy, q[a], da, a, a);
  if (b < 0) return std::nullopt;
  {
    const double dx = x0 - q[b].x, dy = y0 - q[b].y;
    const double den = wx * (q[b].x - q[a].x) + wy * (q[b].y - q[a].y);
    const double t = std::max(0.0, (dx * dx + dy * dy - da) / (2.0 * den));
    x0 += t * wx;
    y0 += t * wy;
  }
  // Along the bisector of (a, b), away from their midpoint.
  double nx = -(q[b].y - q[a].y), ny = q[b].x - q[a].x;
  const double nl = std::hypot(nx, ny);
  nx /= nl;
  ny /= nl;
  if (nx * (x0 - 0.5 * (q[a].x + q[b].x)) + ny * (y0 - 0.5 * (q[a].y + q[b].y)) < 0.0) {
    nx = -nx;
    ny = -ny;
  }
  {
    const double dx = x0 - q[a].x, dy = y0 - q[a].y;
    const int c = first_equidistant(q, x0, y0, nx, ny, q[a], dx * dx + dy * dy, a, b);
    if (c < 0) return std::nullopt;
    LocalVertex v{{a, b, c}};
    // Walk vertex to vertex. The step budget (4m + 16) exceeds the number of distinct
    // vertices a strictly ascending walk can visit on typical inputs by far; exceeding it
    // means floating degeneracy (co-circular candidates), handled by the fallback.
    double last_r2 = -1.0;
    for (int step = 0; step < 4 * m + 16; ++step) {
      const Candidate &A = q[v.pos[0]], &B = q[v.pos[1]], &C = q[v.pos[2]];
      double vx = 0, vy = 0;
      if (!circumcentre(A, B, C, vx, vy)) return std::nullopt;
      const double r2 = (vx - A.x) * (vx - A.x) + (vy - A.y) * (vy - A.y);
      if (r2 < last_r2 * (1.0 - 1e-12)) return std::nullopt;  // not ascending: degenerate
      last_r2 = r2;
      const std::array<double, 3> dots{(B.x - A.x) * (C.x - A.x) + (B.y - A.y) * (C.y - A.y),
                                       (A.x - B.x) * (C.x - B.x) + (A.y - B.y) * (C.y - B.y),
                                       (A.x - C.x) * (B.x - C.x) + (A.y - C.y) * (B.y - C.y)};
      int x = 0;
      for (int k = 1; k < 3; ++k)
        if (dots[k] < dots[x]) x = k;
      if (dots[x] > 0.0) return v;  // acute (in floating): a local maximum
      const int y = v.pos[(x + 1) % 3], z = v.pos[(x + 2) % 3];
      const Candidate &X = q[v.pos[x]], &Y = q[y], &Z = q[z];
      double ex = -(Z.y - Y.y), ey = Z.x - Y.x;
      const double el = std::hypot(ex, ey);
      ex /= el;
      ey /= el;
      if (ex * (X.x - Y.x) + ey * (X.y - Y.y) > 0.0) {
        ex = -ex;
        ey = -ey;
      }
      const int p = first_equidistant(q, vx, vy, ex, ey, Y, r2, y, z);
      if (p < 0) return std::nullopt;  // unbounded Voronoi edge: r grows without bound
      v = LocalVertex{{y, z, p}};
    }
  }
  return std::nullopt;
}

/// Rigorous bounds from one pass over all points about the exact circle.
struct PassResult {
  std::vector<std::size_t> violators;  ///< strictly inside (exact), by increasing index
  std::vector<std::size_t> on_circle;  ///< exactly on the circle (duplicates of contacts)
  std::size_t farthest = 0;            ///< argmax of D̃ (scaled units, see scan_distances)
  double max_d2 = 0.0;
  std::size_t exact_calls = 0;
};

PassResult classify_all(std::span<const Point2> points, const ExactCircle& circle) {
  PassResult r;
  const Point2 c = circle.center_d;
  std::vector<std::size_t> flagged;  // inside or ambiguous
  flagged.reserve(1024);
  const double hi = circle.filter_usable ? circle.outside_above
                                         : std::numeric_limits<double>::infinity();
  const internal::DistanceScan scan = internal::scan_distances<internal::Track::kFarthest>(
      points, c, circle.scale, hi, flagged);
  r.farthest = scan.index;
  r.max_d2 = scan.d2;
  for (std::size_t i : flagged) {
    if (circle.filter_usable &&
        internal::scaled_distance2(points[i], c, circle.scale) < circle.inside_below) {
      r.violators.push_back(i);  // strictly inside
      continue;
    }
    ++r.exact_calls;
    const CGAL::Bounded_side side = internal::exact_side(circle, points[i]);
    if (side == CGAL::ON_BOUNDED_SIDE) r.violators.push_back(i);
    if (side == CGAL::ON_BOUNDARY) r.on_circle.push_back(i);
  }
  return r;
}

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

/// Step 5: the region + coverage argument. Returns t₁ (> 0, in the circle's scaled units)
/// when it proves that c* is the unique maximiser of r over the hull, 0 otherwise. Every
/// floating quantity is replaced by a rigorous bound (comments give the margins; all are
/// generous).
double prove_global(std::span<const Point2> points, const ExactCircle& circle,
                    const std::array<std::size_t, 3>& contacts, const PassResult& pass,
                    const std::array<std::uint64_t, 4>& occupied, Point2 c0) {
  // Everything in the filter's scaled units (lengths × circle.scale, r* ≈ 1): the
  // inequalities below are homogeneous, and no square leaves the double range.
  const double u = internal::kUnitRoundoff;
  const double delta = circle.center_error_scaled;
  // r*s ∈ [r̃(1 − 2.3u), r̃(1 + 2.3u)] (extremal_circle.cpp); 8u leaves room for roundings.
  const double r_lo = circle.radius_scaled * (1.0 - 8.0 * u);
  if (!circle.filter_usable || !(r_lo > 100.0 * delta)) return 0.0;
  // R_max = max |p − c*| ≤ √(D̃max(1 + 4.1u)) + δ; ×(1 + 8u) covers sqrt and sum roundings.
  const double r_hi = (std::sqrt(pass.max_d2 * (1.0 + 5.0 * u)) + delta) * (1.0 + 8.0 * u);
  // β: contact directions from c̃. |ŵ(a) − ŵ(b)| ≤ 2|a − b|/|a| for unit vectors of a, b,
  // so each computed v_k is within η = 2δ/r_lo + 1e-14 (rounding of the normalisation,
  // ~4u, with a wide margin) of the exact one; |v_k + v_l|/2 moves by at most η.
  std::array<double, 3> vx{}, vy{};
  for (int k = 0; k < 3; ++k) {
    const double dx = circle.center_d.x - points[contacts[k]].x;
    const double dy = circle.center_d.y - points[contacts[k]].y;
    const double l = std::hypot(dx, dy);
    vx[k] = dx / l;
    vy[k] = dy / l;
  }
  double beta = 1.0;
  for (int k = 0; k < 3; ++k) {
    const int l = (k + 1) % 3;
    beta = std::min(beta, 0.5 * std::hypot(vx[k] + vx[l], vy[k] + vy[l]));
  }
  const double eta = 2.0 * delta / r_lo + 1e-14;
  const double beta_lo = beta - eta - 1e-15;
  if (!(beta_lo > 0.0)) return 0.0;
  const double t1 = 2.0 * r_lo * beta_lo * (1.0 - 4.0 * u);
  if (t1 >= r_hi) return t1;  // the local disc alone contains H ⊂ disc(c*, R_max)
  // Angular gap about c*. The buckets were filled about the warm start c₀: consecutive
  // points are < (E + 2) buckets of 1/64 pseudo unit apart about c₀, plus 1e-14 for the
  // pseudo-angle's own rounding (a few ulps of a value ≤ 4); ×2 converts to radians. From
  // c₀ to c* the direction of p turns by the angle at p of the triangle (c₀, c*, p), at
  // most asin(d₀/ρ) ≤ (π/2)·d₀/r_lo with d₀ = |c* − c₀| ≤ |c̃ − c₀|(1 + 4u) + δ and
  // ρ ≥ r* ≥ r_lo (no point is inside); so gaps grow by at most π·d₀/r_lo.
  const int empty = longest_empty_run(occupied);
  if (empty >= 200) return 0.0;
  const double d0 = std::hypot(circle.center_d.x - c0.x, circle.center_d.y - c0.y) *
                        circle.scale * (1.0 + 4.0 * u) +
                    delta;
  if (!(d0 < 0.5 * r_lo)) return 0.0;
  const double gap = 2.0 * ((empty + 2) / 64.0 + 1e-14) +
                     std::numbers::pi * d0 / r_lo * (1.0 + 1e-12);
  const double h = 0.5 * gap;
  if (!(h < 1.5)) return 0.0;
  // cos is within 1 ulp in glibc; subtract 1e-15 absolute for it and for h's rounding.
  const double cos_lo = std::cos(h) - 1e-15;
  if (!(cos_lo > 0.0)) return 0.0;
  for (const double t : {t1, r_hi}) {
    // ρ = r*: t² − 2t·r*·cos h < 0 ⇐ t < 2·r_lo·cos_lo (margin 1e-12 relative).
    if (!(t * (1.0 + 1e-12) < 2.0 * r_lo * cos_lo)) return 0.0;
    // ρ = R_max: t² + R² − 2tR·cos h − r*² ≤ t² + R_hi² − 2t·R_hi·cos_lo − r_lo²
    // (valid since [r*, R_max] ⊂ [r*, R_hi] and the bound is convex in ρ); its floating
    // evaluation errs by less than 8u·S, S = sum of the magnitudes: demand −16u·S.
    const double s = t * t + r_hi * r_hi + 2.0 * t * r_hi + r_lo * r_lo;
    const double q2 = t * t + r_hi * r_hi - 2.0 * t * r_hi * cos_lo - r_lo * r_lo;
    if (!(q2 < -16.0 * u * s)) return 0.0;
  }
  return t1;
}

// ---------------------------------------------------------------------------------------
// Result assembly (both paths)
// ---------------------------------------------------------------------------------------

MaximumInscribedCircle make_result(std::span<const Point2> points, const ExactCircle& circle,
                                   const std::array<std::size_t, 3>& contacts,
                                   std::size_t farthest, double max_d2,
                                   Certificate certificate) {
  MaximumInscribedCircle mi;
  mi.center = circle.center_d;
  mi.radius = circle.radius;
  mi.contacts.assign(contacts.begin(), contacts.end());
  mi.ron = roundness_parameters(points, mi.center, mi.radius);
  // Scaled units: (ρ² − r*²)s² / ((ρ + r*)s), then back by s⁻¹ (exact).
  const double gap_s = -internal::exact_power_gap(circle, points[farthest]);  // ≥ 0 exactly
  mi.ron.ront = gap_s > 0.0 ? std::ldexp(gap_s / (std::sqrt(max_d2) + circle.radius_scaled),
                                         -circle.scale_exponent)
                            : 0.0;
  mi.ron.ronp = mi.ron.ront;
  mi.ron.ronv = 0.0;
  mi.certificate = std::move(certificate);
  return mi;
}

std::optional<MaximumInscribedCircle> fast_path(std::span<const Point2> points) {
  const std::size_t n = points.size();
  const internal::WarmStart warm = internal::kasa_center(points);
  const Point2 c0 = warm.center;
  // Candidates: the nearest point to c0 in each of `sectors` pseudo-angle sectors (64 for
  // dense profiles, ≥ 8 points per sector for small n), on a stride sample of ~512 points:
  // the contacts the sample misses are violators of the first round (found by the O(n)
  // pass that runs anyway), and the coverage proof needs only some points in every
  // direction, not all (any subset of points lies at distance ≥ r* from c*).
  const std::size_t stride = std::max<std::size_t>(1, n / 512);
  const std::size_t sectors = std::clamp<std::size_t>(n / stride / 8, 4, 64);
  // The same pass fills 256 pseudo-angle occupancy buckets about c0 for the global proof.
  // (Sector winners are replaced only on a strictly smaller distance, and the violators
  // are added by increasing index; contacts are mapped to the lowest index among their
  // duplicates at the end.)
  std::vector<double> best(sectors, std::numeric_limits<double>::infinity());
  std::vector<std::size_t> best_idx(sectors, n);
  std::array<std::uint64_t, 4> occupied{};
  const double scale = static_cast<double>(sectors) / 4.0;
  // Warm-start arithmetic on (p − c0)·s0 (s0 a power of two: coordinates O(1) whatever the
  // input magnitude; the walk and the sectors are invariant under scaling).
  const double s0 = warm.scale;
  for (std::size_t i = 0; i < n; i += stride) {
    const double dx = (points[i].x - c0.x) * s0, dy = (points[i].y - c0.y) * s0;
    const double d2 = dx * dx + dy * dy;
    const double phi = internal::pseudo_angle(dx, dy);  // in [0, 4]
    // Truncation of values in [0, 256] (4 − tiny may round up to 4: clamp).
    auto bucket = static_cast<unsigned>(phi * 64.0);
    if (bucket > 255u) bucket = 255u;
    occupied[bucket >> 6] |= std::uint64_t{1} << (bucket & 63u);
    auto s = static_cast<std::size_t>(phi * scale);
    if (s >= sectors) s = sectors - 1;
    if (d2 < best[s]) {
      best[s] = d2;
      best_idx[s] = i;
    }
  }
  // Sector winners are distinct points (equal points share a sector and only one wins).
  std::vector<Candidate> cand;
  cand.reserve(sectors + 12 * 32);
  auto local = [&](std::size_t i) {
    return Candidate{(points[i].x - c0.x) * s0, (points[i].y - c0.y) * s0, i};
  };
  for (std::size_t s = 0; s < sectors; ++s)
    if (best_idx[s] < n) cand.push_back(local(best_idx[s]));

  double x0 = 0.0, y0 = 0.0;
  // Rounds: each adds the violators of the current vertex. 12 is far above what round
  // profiles need (1-3); beyond it the fallback is cheaper than more walking.
  for (int round = 0; round < 12; ++round) {
    const std::optional<LocalVertex> v = voronoi_walk(cand, x0, y0);
    if (!v) return std::nullopt;
    std::array<std::size_t, 3> contacts{cand[v->pos[0]].index, cand[v->pos[1]].index,
                                        cand[v->pos[2]].index};
    const EPoint a = to_epick(points[contacts[0]]), b = to_epick(points[contacts[1]]),
                 c = to_epick(points[contacts[2]]);
    if (CGAL::orientation(a, b, c) == CGAL::COLLINEAR) return std::nullopt;
    const ExactCircle circle =
        internal::exact_circumcircle(points[contacts[0]], points[contacts[1]],
                                     points[contacts[2]]);
    PassResult pass = classify_all(points, circle);
    if (!pass.violators.empty()) {
      // Add the deepest violators (at most 32 a round keeps the walk cheap; any one of
      // them already invalidates the vertex).
      std::vector<std::size_t>& vio = pass.violators;
      if (vio.size() > 32) {
        auto d2 = [&](std::size_t i) {
          return internal::scaled_distance2(points[i], circle.center_d, circle.scale);
        };
        std::nth_element(vio.begin(), vio.begin() + 32, vio.end(),
                         [&](std::size_t p, std::size_t q) {
                           const double dp = d2(p), dq = d2(q);
                           return dp < dq || (dp == dq && p < q);
                         });
        vio.resize(32);
        std::sort(vio.begin(), vio.end());
      }
      // A candidate among the violators means the floating walk disagrees with the exact
      // test (near-degenerate input): leave it to the exhaustive method. Otherwise no
      // violator equals a candidate (equal points are on the same side), and duplicated
      // violators are kept once (the first, i.e. lowest, index: `vio` is sorted).
      for (const Candidate& held : cand)
        if (std::binary_search(vio.begin(), vio.end(), held.index)) return std::nullopt;
      const std::size_t before = cand.size();
      for (std::size_t i : vio) {
        bool dup = false;
        for (std::size_t k = before; k < cand.size() && !dup; ++k)
          dup = points[cand[k].index] == points[i];
        if (!dup) cand.push_back(local(i));
      }
      x0 = (circle.center_d.x - c0.x) * s0;
      y0 = (circle.center_d.y - c0.y) * s0;
      continue;
    }
    // Step 4: strict local maximum ⇔ acute contact triangle (exact dot-product signs).
    const Point2 pa = points[contacts[0]], pb = points[contacts[1]], pc = points[contacts[2]];
    if (internal::dot_sign(pa, pb, pc) <= 0 || internal::dot_sign(pb, pa, pc) <= 0 ||
        internal::dot_sign(pc, pa, pb) <= 0)
      return std::nullopt;
    const double t1_scaled = prove_global(points, circle, contacts, pass, occupied, c0);
    if (!(t1_scaled > 0.0)) return std::nullopt;
    const double t1 = std::ldexp(t1_scaled, -circle.scale_exponent);  // back to mm
    for (std::size_t& k : contacts)  // lowest index among duplicates (all on the circle)
      for (std::size_t i : pass.on_circle)
        if (i < k && points[i] == points[k]) k = i;
    std::ostringstream arg;
    arg << "fast path: 3 contacts, exact centre strictly inside their triangle (exact "
           "dot-product signs); no point strictly inside the circle (floating filter with "
           "rigorous bound, "
        << pass.exact_calls << " exact in-circle predicates, " << round + 1
        << " round(s), " << cand.size()
        << " candidates); global: r < r* for 0 < |c − c*| < 2r*·beta = " << t1
        << " mm (contact cone), and for larger |c − c*| up to the hull's extent by angular "
           "coverage of the points about the centre";
    Certificate cert{Optimality::global, arg.str(), t1};
    return make_result(points, circle, contacts, pass.farthest, pass.max_d2,
                       std::move(cert));
  }
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------
// Exhaustive method
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
  std::size_t extra = 0;                   ///< 4th co-circular contact, or SIZE_MAX
  double r2 = 0.0;                         ///< floating
};

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
  const std::size_t n = points.size();
  // Distinct points, each with its lowest index.
  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const Point2 &p = points[a], &q = points[b];
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    return a < b;
  });
  order.erase(std::unique(order.begin(), order.end(),
                          [&](std::size_t a, std::size_t b) { return points[a] == points[b]; }),
              order.end());
  std::vector<std::pair<EPoint, std::size_t>> input;
  input.reserve(order.size());
  for (std::size_t i : order) input.emplace_back(to_epick(points[i]), i);
  Delaunay dt;
  dt.insert(input.begin(), input.end());
  if (dt.dimension() < 2)
    throw std::logic_error(std::string(kCaller) + ": triangulation is not 2D (internal)");

  // Surrounded vertices: acute faces, and right faces whose neighbour across the hypotenuse
  // is co-circular (the centre is then interior to the co-circular quadrilateral).
  std::vector<Surrounded> found;
  double best_r2 = -1.0;
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
    s.extra = std::numeric_limits<std::size_t>::max();
    for (int k = 0; k < 3; ++k) s.contacts[k] = f->vertex(k)->info();
    if (right >= 0) {
      const auto g = f->neighbor(right);
      if (dt.is_infinite(g)) continue;
      const auto w = g->vertex(g->index(f));
      if (dt.side_of_oriented_circle(f, w->point()) != CGAL::ON_ORIENTED_BOUNDARY) continue;
      s.extra = w->info();
    }
    s.r2 = circumradius2(d[0], d[1], d[2]);
    best_r2 = std::max(best_r2, s.r2);
    found.push_back(s);
  }
  if (found.empty())
    throw UndefinedResult(std::string(kCaller) +
                          ": no Voronoi vertex is surrounded by its nearest points (every "
                          "Delaunay triangle is obtuse): the largest empty circle centred in "
                          "the convex hull touches the hull boundary — partial arc or too "
                          "sparse a profile; the MI circle is not defined");
  // Exact maximum among the near-ties of the floating maximum.
  const Surrounded* best = nullptr;
  ExactCircle best_circle;
  std::size_t ties = 0;
  for (const Surrounded& s : found) {
    if (s.r2 < best_r2 * (1.0 - 1e-10)) continue;
    ExactCircle c = internal::exact_circumcircle(points[s.contacts[0]], points[s.contacts[1]],
                                                 points[s.contacts[2]]);
    const int cmp = best == nullptr ? 1 : internal::compare_radius(c, best_circle);
    if (cmp > 0) {
      best = &s;
      best_circle = std::move(c);
      ties = 0;
    } else if (cmp == 0 && !same_center(c, best_circle)) {
      ++ties;
    }
  }

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
  if (best->extra != std::numeric_limits<std::size_t>::max())
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

}  // namespace

MaximumInscribedCircle maximum_inscribed_circle(std::span<const Point2> points) {
  validate_profile(points, 3, kCaller, /*require_non_collinear=*/true);
  return internal::fit_maximum_inscribed_circle(points);
}

MaximumInscribedCircle internal::fit_maximum_inscribed_circle(std::span<const Point2> points) {
  // Small inputs: the exhaustive method is as fast and needs no warm start.
  if (points.size() >= 16) {
    if (std::optional<MaximumInscribedCircle> mi = fast_path(points)) return *std::move(mi);
  }
  return exhaustive(points);
}

}  // namespace vcmm::geometry
