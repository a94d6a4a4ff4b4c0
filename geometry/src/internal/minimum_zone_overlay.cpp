// internal/minimum_zone_overlay.cpp — the general exact minimum-zone (MZ) method: overlay of
// the farthest-point and the nearest-point Voronoi diagrams.
//
// References: Ebara, Ebara, Fukuda & Yamada (1989), Le & Lee (1991) "Out-of-roundness problem
// revisited" (IEEE PAMI 13(3)), Roy & Zhang (1992) "Establishing the minimum zone…"
// (Int. J. Mach. Tools Manuf.): the MZ centre is a vertex of the overlay of the two diagrams.
// The pruning (§4) and the exactness scheme (§5) are ours.
//
// §1 Notation. Points p_1..p_n (distinct after removing duplicates, lowest index kept).
//   R(c) = max_i |c − p_i|, r(c) = min_i |c − p_i|, f(c) = R(c) − r(c) (zone width).
//   FVD: farthest-point Voronoi diagram (only convex-hull vertices have cells); dual: the
//   farthest-point Delaunay triangulation (FDT). NVD: nearest-point Voronoi diagram; dual: the
//   Delaunay triangulation (DT). A Voronoi edge of a pair (a, b) with third vertices e1, e2 of
//   the two dual triangles is, exactly, the part of the bisector of a and b where
//     FVD: |x − a| ≥ |x − e_k|   (k = 1, 2; a, b farthest),
//     NVD: |x − a| ≤ |x − e_k|   (a, b nearest);
//   one condition only for a hull edge (unbounded edge, a ray). Degenerate (zero-length)
//   edges of co-circular dual faces satisfy the same description and need no special case.
//
// §2 Where the minimum is. O(c), I(c) are the outer / inner contact sets, v_p the unit vector
//   from c to p. The directional derivative is f'(c; u) = max_{o∈O}(−v_o·u) + max_{i∈I} v_i·u.
//   (a) At a local minimum f' ≥ 0 in every direction, i.e. {v_o} and {v_i} cannot be strictly
//   separated by a line: their convex hulls on the unit circle meet, so either two chords
//   o1o2, i1i2 cross (the contacts alternate o, i, o, i in angle), or an outer and an inner
//   contact lie on one ray from c (the "ray case").
//   (b) Ray case, o and i on a ray: g = |·−o| − |·−i| ≤ |o − i| with equality only on that
//   ray, f ≥ g, f(c) = g(c). If a secant line through the ray's direction leaves the other
//   outer directions on one closed side and the other inner ones on the other (i.e. the
//   remaining contacts are weakly separable), moving c along the secant's normal keeps
//   f = max of smooth terms each non-increasing to first order and strictly decreasing to
//   second order ((1 − s²)(1/R − 1/r) < 0), so c is no local minimum. Hence a local minimum
//   has four contacts o1, i1, o2, i2 in four distinct, strictly alternating directions, except
//   when the contacts occupy exactly three directions, each holding an outer and an inner
//   point (exact "three-ray" degeneracy, e.g. o_k = 10 v_k, i_k = 5 v_k for three unit
//   vectors v_k: f' > 0 in every direction, a strict minimum, yet no strictly alternating
//   subset; then we report a 2+2 with crossing bisectors and say so in the certificate).
//   3+1 and 1+3 sets are never local minima (move towards / away from the single point).
//   (c) Strict alternation makes the two bisectors cross in one point (mirror-symmetric pairs,
//   the only parallel case, cannot alternate). So every local minimiser c* lies on a closed
//   FVD edge of an outer pair and a closed NVD edge of an inner pair whose bisectors cross:
//   if |O| = 2 the FVD edge is the one of (o1, o2); if |O| ≥ 3, c* is an FVD vertex and an
//   endpoint of ≥ 3 FVD edges on ≥ 2 distinct lines (likewise for the NVD), so some crossing
//   (possibly touching at an endpoint) pair of non-parallel edges contains c*.
//   (d) Candidates. For an FVD edge (a, b, …) and an NVD edge (c, d, …) with non-parallel
//   bisectors, x = bisector(a,b) ∩ bisector(c,d) is a rational point; if x lies on both
//   closed edges (four exact squared-distance signs, §1) then a is farthest and c nearest at
//   x, so f(x) = |x − a| − |x − c| exactly, with no O(n) scan. Every candidate is thus a
//   feasible centre with its exact width, and min over candidates = min f whenever the
//   minimum is attained.
//   (e) Attainment. As |c| → ∞ in direction u, f(c) → W(u), the width of the point set in
//   direction u, uniformly; hence inf f = min(w*, w_min) with w* the best candidate and
//   w_min the minimal width of the convex hull (rotating calipers, an edge-vertex pair). The
//   minimum is attained iff w* ≤ w_min; otherwise UndefinedResult.
//
// §3 Diagrams. DT: CGAL::Delaunay_triangulation_2 on Epick (exact predicates). FDT: the
//   convex-hull polygon (monotone chain, exact orientation, collinear points dropped: a
//   point inside a hull edge is never farthest) triangulated by Chew's randomized scheme:
//   remove the vertices in random order, then re-insert each between its two neighbours at
//   removal time and legalise by flips with the exact in-circle predicate (flip when the new
//   vertex is strictly outside the opposite triangle's circle; co-circular is legal). A
//   locally legal triangulation of a convex polygon is the FDT (the lifted surface is then
//   concave, hence the upper hull). Expected O(h log h) here, O(h) flips.
//
// §4 Pruning (the region). Any centre c0 with an upper bound W ≥ f(c0) ≥ min f. For any two
//   points p, q and c = c0 + δu (|u| = 1, δ > 0), with ρ_p = |c0 − p|, S = ρ_p + ρ_q,
//   B = (q − p)·u:
//     |c − p|² − |c − q|² = ρ_p² − ρ_q² + 2δB,    |c − p| + |c − q| ≤ S + 2δ,
//   so whenever the numerator is ≥ 0,
//     f(c) ≥ |c − p| − |c − q| ≥ (S(ρ_p − ρ_q) + 2δB) / (S + 2δ),
//   which exceeds W as soon as B > W and
//     δ > δ_pq(u) = S (W − ρ_p + ρ_q) / (2 (B − W))          (numerator ≥ 0 since W ≥ f(c0)).
//   Directions are covered by K = 64 cones spanned by consecutive double vectors b_k, b_k+1
//   (the cones tile the plane whatever the rounding); for u in cone k,
//   B ≥ min((q − p)·b_k, (q − p)·b_k+1) / max|b| (u is a non-negative combination of the
//   two). With ρ* = max_k min_(p,q) δ_pq (pairs drawn from the extreme points about c0), every
//   centre with f ≤ W lies in the disk D(c0, ρ*); only Voronoi edges meeting that disk can
//   carry the optimum, and all their crossings are exhausted. Every quantity in the bound is
//   computed in interval arithmetic, so ρ* is a proven radius. If some cone has no pair
//   with B > W the region is unbounded and the whole overlay is exhausted.
//   When c0 is the optimum with contacts o, i, the pairs (o, i) give δ = 0 up to rounding in
//   every direction in which (i − o)·u > W; for alternating contacts of a thin annulus these
//   half-planes cover all directions, so ρ* is of the order of the rounding of c0 (1e-13 mm)
//   and a handful of edges remain. (verify() in certificate.cpp re-derives the same
//   inequality from h = R² − r².) Short arcs determine their centre poorly: the bound is
//   then larger (~0.1 mm for a 0.3 rad arc) but still finite and exhausted.
//   Local diagrams. R and r are 1-Lipschitz, so from a centre in D(c0, ρ') only points with
//   |c0 − p| ≥ R(c0) − 2ρ' can be farthest and only those with |c0 − p| ≤ r(c0) + 2ρ'
//   nearest (decided conservatively in intervals; the 8 extreme ones are always added). On
//   D(c0, ρ') the FVD of the first set and the NVD of the second coincide with the diagrams
//   of all points, so they are built for those sites only (ρ' = 2ρ* + rounding margin), and a
//   crossing is kept only when it is proven to lie in D(c0, ρ') (else, if it is not proven
//   outside D(c0, ρ*), decided exactly). On dense rings both sets have ~8 sites.
//   The seed c0 comes from a subset search: the exact method on the extreme points per
//   angular sector about an algebraic (Kåsa) centre, enlarged with the violators of the
//   subset optimum until none remain (constraint generation); it only has to be good, not
//   proven. If no crossing with width ≤ W exists in the region, the minimum is not attained
//   (an attained minimum is a local one, and lies in the region).
//
// §5 Exactness. Edge membership and widths are first evaluated in interval arithmetic
//   (CGAL::Interval_nt) on coordinates relative to a reference double point; undecided signs
//   are re-evaluated in exact rationals (GMP) from the input doubles. Widths are compared
//   exactly without square roots: sign(√P1 + √Q1 − √P2 − √Q2) by two squarings with sign
//   care (compare_sqrt_sums). The reported quadruple, contacts and attainment are exact.
//
// Complexity: O(n log n) to sort out duplicates and O(n) for the hull, the seed rounds (a
// few) and the region; then diagrams of the local sites and O(k_F · k_N) pair tests for the
// k edges meeting the region — a handful on round profiles (measured: 0.2 ms at n = 360,
// 1 ms at 3 600, 13-16 ms at 36 000 on lobed_noisy_ring). Without a usable region (random
// or nearly straight data: no pair bounds some direction cone) the whole overlay is
// exhausted: O(n log n) for the DT, O(h log h) for the FDT and O(n · h) pair tests.
#include "internal/minimum_zone_overlay.h"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "internal/exact.h"
#include "internal/minimum_zone_common.h"
#include "internal/minimum_zone_overlay_detail.h"

namespace vcmm::geometry::internal {

namespace {

using Interval = CGAL::Interval_nt<false>;
using RoundingGuard = CGAL::Protect_FPU_rounding<true>;

constexpr int kNone = -1;
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Sets with at most this many distinct points exhaust the whole overlay (O(n·h) pairs is
/// then cheaper than the seed search).
constexpr std::size_t kFullOverlayMaxSites = 64;
/// Cones covering the directions in the region bound (§4): more cones, tighter bound, more
/// work; 64 keeps the loss below cos(π/64) ≈ 0.9988 and costs O(64 · 40²).
constexpr int kCones = 64;
/// Angular sectors for picking extreme points about a centre.
constexpr int kSectors = 32;

// ---------------------------------------------------------------------------------------
// Sites: distinct points.

struct Sites {
  std::vector<Point2> p;               ///< distinct points sorted by (x, y)
  std::vector<std::size_t> original;   ///< lowest input index of each
};

Sites distinct_sites(std::span<const Point2> points) {
  struct Item {
    Point2 p;
    std::size_t index;
  };
  std::vector<Item> items(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) items[i] = {points[i], i};
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    if (a.p.x != b.p.x) return a.p.x < b.p.x;
    if (a.p.y != b.p.y) return a.p.y < b.p.y;
    return a.index < b.index;
  });
  Sites s;
  s.p.reserve(points.size());
  s.original.reserve(points.size());
  for (const Item& it : items) {
    if (!s.p.empty() && s.p.back() == it.p) continue;
    s.p.push_back(it.p);
    s.original.push_back(it.index);
  }
  return s;
}

// ---------------------------------------------------------------------------------------
// Convex hull and the farthest-point Delaunay triangulation (§3).

/// Strictly convex hull, counter-clockwise, of the sites `idx` (ascending indices into `p`,
/// hence sorted by (x, y)): Andrew's monotone chain with the exact orientation predicate.
/// O(n).
std::vector<int> convex_hull_ccw(const std::vector<Point2>& p, const std::vector<int>& idx) {
  const int n = static_cast<int>(idx.size());
  std::vector<int> h(2 * idx.size() + 1);
  auto left = [&](int a, int b, int c) {
    return CGAL::orientation(to_epick(p[a]), to_epick(p[b]), to_epick(p[c])) ==
           CGAL::LEFT_TURN;
  };
  int k = 0;
  for (int i = 0; i < n; ++i) {
    while (k >= 2 && !left(h[k - 2], h[k - 1], idx[i])) --k;
    h[k++] = idx[i];
  }
  for (int i = n - 2, t = k + 1; i >= 0; --i) {
    while (k >= t && !left(h[k - 2], h[k - 1], idx[i])) --k;
    h[k++] = idx[i];
  }
  h.resize(static_cast<std::size_t>(k > 1 ? k - 1 : k));
  return h;
}

double square_distance(Point2 a, Point2 b) {
  const double dx = a.x - b.x, dy = a.y - b.y;
  return dx * dx + dy * dy;
}

std::vector<int> all_sites(std::size_t n) {
  std::vector<int> idx(n);
  std::iota(idx.begin(), idx.end(), 0);
  return idx;
}

struct Triangle {
  std::array<int, 3> v;   ///< counter-clockwise
  std::array<int, 3> nb;  ///< nb[i]: triangle across the edge opposite v[i], or kNone
};

std::uint64_t splitmix64(std::uint64_t& s) {
  std::uint64_t z = (s += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

/// Farthest-point Delaunay triangulation of the convex polygon `hull` (ccw site indices,
/// ≥ 3): every triangle's circumcircle encloses all hull vertices (closed disk). Chew's
/// randomized scheme with exact in-circle flips; deterministic (fixed seed).
std::vector<Triangle> farthest_delaunay(const std::vector<Point2>& p,
                                        const std::vector<int>& hull) {
  const int h = static_cast<int>(hull.size());
  auto P = [&](int local) { return to_epick(p[hull[local]]); };
  std::vector<int> prev(hull.size()), next(hull.size());
  for (int i = 0; i < h; ++i) {
    prev[i] = (i + h - 1) % h;
    next[i] = (i + 1) % h;
  }
  std::vector<int> order(hull.size());
  std::iota(order.begin(), order.end(), 0);
  std::uint64_t state = 0x5EEDF00DULL;
  for (int i = h - 1; i > 0; --i) {
    const int j = static_cast<int>(splitmix64(state) % static_cast<std::uint64_t>(i + 1));
    std::swap(order[i], order[j]);
  }
  struct Removal {
    int v, before, after;
  };
  std::vector<Removal> removals;
  removals.reserve(hull.size());
  for (int k = 0; k + 3 < h; ++k) {
    const int v = order[k];
    removals.push_back({v, prev[v], next[v]});
    next[prev[v]] = next[v];
    prev[next[v]] = prev[v];
  }
  const int r0 = order[h - 1], r1 = next[r0], r2 = next[r1];
  std::vector<Triangle> tri;
  tri.reserve(2 * hull.size());
  tri.push_back({{r0, r1, r2}, {kNone, kNone, kNone}});
  std::vector<int> boundary(hull.size(), kNone);  // triangle holding the edge v → next(v)
  boundary[r0] = boundary[r1] = boundary[r2] = 0;

  auto index_of = [](const Triangle& t, int vertex) {
    return t.v[0] == vertex ? 0 : (t.v[1] == vertex ? 1 : 2);
  };
  auto neighbour_index = [](const Triangle& t, int other) {
    return t.nb[0] == other ? 0 : (t.nb[1] == other ? 1 : 2);
  };
  // Flip the edge opposite v = tri[t].v[i]; afterwards v is v[0] of both new triangles.
  auto flip = [&](int t, int i, int u) {
    const Triangle T = tri[t], U = tri[u];
    const int v = T.v[i], a = T.v[(i + 1) % 3], b = T.v[(i + 2) % 3];
    const int tA = T.nb[(i + 1) % 3], tB = T.nb[(i + 2) % 3];
    const int j = neighbour_index(U, t);
    const int w = U.v[j];
    const int uB = U.nb[(j + 1) % 3], uA = U.nb[(j + 2) % 3];
    tri[t] = {{v, a, w}, {uB, u, tB}};
    tri[u] = {{v, w, b}, {uA, tA, t}};
    if (uB != kNone) tri[uB].nb[neighbour_index(tri[uB], u)] = t;
    else boundary[a] = t;
    if (tA != kNone) tri[tA].nb[neighbour_index(tri[tA], t)] = u;
    else boundary[b] = u;
  };

  std::vector<std::pair<int, int>> stack;
  for (auto it = removals.rbegin(); it != removals.rend(); ++it) {
    const int v = it->v, pb = it->before, qa = it->after;
    const int t = boundary[pb];
    const int j = index_of(tri[t], pb);  // edge pb → qa is opposite v[(j + 2) % 3]
    const int n = static_cast<int>(tri.size());
    tri.push_back({{v, qa, pb}, {t, kNone, kNone}});
    tri[t].nb[(j + 2) % 3] = n;
    boundary[pb] = n;
    boundary[v] = n;
    stack.assign(1, {n, 0});
    while (!stack.empty()) {
      const auto [tt, ii] = stack.back();
      stack.pop_back();
      const int u = tri[tt].nb[ii];
      if (u == kNone) continue;
      const Triangle& U = tri[u];
      if (CGAL::side_of_oriented_circle(P(U.v[0]), P(U.v[1]), P(U.v[2]), P(v)) ==
          CGAL::ON_NEGATIVE_SIDE) {
        flip(tt, ii, u);
        stack.push_back({tt, 0});
        stack.push_back({u, 0});
      }
    }
  }
  for (Triangle& t : tri)
    for (int& v : t.v) v = hull[v];
  return tri;
}

// ---------------------------------------------------------------------------------------
// Voronoi edges (§1).

struct Edge {
  int a, b;    ///< the pair; the edge lies on their bisector
  int e1, e2;  ///< third vertices of the dual triangles (kNone: unbounded side)
};

using Vb = CGAL::Triangulation_vertex_base_with_info_2<int, Epick>;
using Tds = CGAL::Triangulation_data_structure_2<Vb>;
using Delaunay = CGAL::Delaunay_triangulation_2<Epick, Tds>;

struct Diagrams {
  bool ok = false;  ///< false: a site set too small or collinear for 2D diagrams
  std::vector<Edge> fvd;
  std::vector<Edge> nvd;
};

/// The FVD of the sites `far_sites` (its cells: their hull vertices) and the NVD of the
/// sites `near_sites` (ascending indices into p), as edge lists.
Diagrams build_diagrams(const std::vector<Point2>& p, const std::vector<int>& far_sites,
                        const std::vector<int>& near_sites) {
  Diagrams d;
  const std::vector<int> hull = convex_hull_ccw(p, far_sites);
  if (hull.size() < 3) return d;
  const std::vector<Triangle> fdt = farthest_delaunay(p, hull);
  d.fvd.reserve(2 * hull.size());
  for (int t = 0; t < static_cast<int>(fdt.size()); ++t) {
    for (int i = 0; i < 3; ++i) {
      const int u = fdt[t].nb[i];
      if (u != kNone && u < t) continue;
      int e2 = kNone;
      if (u != kNone) {
        const Triangle& U = fdt[u];
        e2 = U.nb[0] == t ? U.v[0] : (U.nb[1] == t ? U.v[1] : U.v[2]);
      }
      d.fvd.push_back({fdt[t].v[(i + 1) % 3], fdt[t].v[(i + 2) % 3], fdt[t].v[i], e2});
    }
  }
  std::vector<std::pair<EPoint, int>> input;
  input.reserve(near_sites.size());
  for (int i : near_sites) input.emplace_back(to_epick(p[i]), i);
  Delaunay dt;
  dt.insert(input.begin(), input.end());
  if (dt.dimension() != 2) return d;
  d.nvd.reserve(3 * near_sites.size());
  for (auto e = dt.finite_edges_begin(); e != dt.finite_edges_end(); ++e) {
    const auto f = e->first;
    const int i = e->second;
    const auto vc = f->vertex(i);
    const auto vd = dt.mirror_vertex(f, i);
    d.nvd.push_back({f->vertex(f->ccw(i))->info(), f->vertex(f->cw(i))->info(),
                     dt.is_infinite(vc) ? kNone : vc->info(),
                     dt.is_infinite(vd) ? kNone : vd->info()});
  }
  d.ok = true;
  return d;
}

// ---------------------------------------------------------------------------------------
// The crossing predicate, generic over Interval (filter) and Rational (exact) (§2d, §5).

template <class NT>
struct Rel {  // a site relative to the reference point o, with its squared norm
  NT x, y, n;
};

template <class NT>
Rel<NT> relative(Point2 p, Point2 o) {
  NT x = NT(p.x) - NT(o.x);
  NT y = NT(p.y) - NT(o.y);
  NT n = x * x + y * y;
  return {std::move(x), std::move(y), std::move(n)};
}

/// Bisector crossing: 2(x − o) = (zx, zy) / det, from
///   (b − a)·2(x − o) = |b'|² − |a'|²,  (d − c)·2(x − o) = |d'|² − |c'|².
template <class NT>
struct Crossing {
  NT zx, zy, det;
};

template <class NT>
Crossing<NT> crossing(const Rel<NT>& a, const Rel<NT>& b, const Rel<NT>& c, const Rel<NT>& d) {
  const NT u1x = b.x - a.x, u1y = b.y - a.y, k1 = b.n - a.n;
  const NT u2x = d.x - c.x, u2y = d.y - c.y, k2 = d.n - c.n;
  return {k1 * u2y - k2 * u1y, u1x * k2 - u2x * k1, u1x * u2y - u1y * u2x};
}

/// det · (|x − s|² − |x − e|²) for x the crossing.
template <class NT>
NT distance_difference(const Rel<NT>& s, const Rel<NT>& e, const Crossing<NT>& c) {
  return (s.n - e.n) * c.det - (c.zx * (s.x - e.x) + c.zy * (s.y - e.y));
}

/// 4 det² |x − s|².
template <class NT>
NT squared_distance_4det2(const Rel<NT>& s, const Crossing<NT>& c) {
  const NT dx = c.zx - 2 * c.det * s.x;
  const NT dy = c.zy - 2 * c.det * s.y;
  return dx * dx + dy * dy;
}

constexpr int kUnknown = 2;
int sign_of(const Interval& v) {
  if (v.inf() > 0) return 1;
  if (v.sup() < 0) return -1;
  if (v.inf() == 0 && v.sup() == 0) return 0;
  return kUnknown;
}
int sign_of(const Rational& v) { return static_cast<int>(CGAL::sign(v)); }

/// 1: the crossing lies on both closed edges; 0: it does not, or the bisectors are parallel;
/// kUnknown: the interval filter cannot tell.
template <class NT, class SiteFn>
int crossing_on_edges(const Edge& F, const Edge& N, SiteFn&& site, Crossing<NT>& c) {
  c = crossing(site(F.a), site(F.b), site(N.a), site(N.b));
  const int sd = sign_of(c.det);
  if (sd == kUnknown) return kUnknown;
  if (sd == 0) return 0;
  bool unknown = false;
  // FVD: |x − a|² − |x − e|² ≥ 0; NVD: |x − c|² − |x − e|² ≤ 0.
  auto holds = [&](int s, int e, int want) {
    if (e == kNone) return true;
    const int sg = sign_of(distance_difference(site(s), site(e), c));
    if (sg == kUnknown) {
      unknown = true;
      return true;
    }
    return want > 0 ? sg * sd >= 0 : sg * sd <= 0;
  };
  if (!holds(F.a, F.e1, +1) || !holds(F.a, F.e2, +1) || !holds(N.a, N.e1, -1) ||
      !holds(N.a, N.e2, -1))
    return 0;
  return unknown ? kUnknown : 1;
}

// ---------------------------------------------------------------------------------------
// Exact comparison of sums of square roots (§5).

/// sign(t + √u), u ≥ 0.
int sign_plus_sqrt(const Rational& t, const Rational& u) {
  if (CGAL::sign(t) >= 0) return (CGAL::is_positive(t) || CGAL::is_positive(u)) ? 1 : 0;
  return static_cast<int>(CGAL::sign(u - t * t));
}

/// sign(k + m√u), u ≥ 0.
int sign_linear_sqrt(const Rational& k, const Rational& m, const Rational& u) {
  if (CGAL::sign(m) >= 0) {
    if (CGAL::sign(k) >= 0)
      return (CGAL::is_positive(k) || (CGAL::is_positive(m) && CGAL::is_positive(u))) ? 1 : 0;
    return static_cast<int>(CGAL::sign(m * m * u - k * k));
  }
  if (CGAL::sign(k) <= 0) return (CGAL::is_zero(k) && CGAL::is_zero(u)) ? 0 : -1;
  return static_cast<int>(CGAL::sign(k * k - m * m * u));
}

/// sign(√P1 + √Q1 − √P2 − √Q2) for non-negative rationals, exactly: both sums are ≥ 0, so
/// the sign is that of the difference of their squares, t + √u − √v with
/// t = P1 + Q1 − P2 − Q2, u = 4 P1 Q1, v = 4 P2 Q2; then once more with sign care.
int compare_sqrt_sums(const Rational& P1, const Rational& Q1, const Rational& P2,
                      const Rational& Q2) {
  const Rational t = P1 + Q1 - P2 - Q2;
  const Rational u = 4 * P1 * Q1;
  const Rational v = 4 * P2 * Q2;
  const int s = sign_plus_sqrt(t, u);  // sign(t + √u)
  if (s < 0) return -1;
  if (s == 0) return CGAL::is_positive(v) ? -1 : 0;
  // t + √u > 0: sign((t + √u)² − v) = sign(t² + u − v + 2t√u).
  return sign_linear_sqrt(t * t + u - v, 2 * t, u);
}

/// sign((√A1 − √B1) − (√A2 − √B2)).
int compare_widths(const Rational& A1, const Rational& B1, const Rational& A2,
                   const Rational& B2) {
  return compare_sqrt_sums(A1, B2, A2, B1);
}

// ---------------------------------------------------------------------------------------
// Candidates and the exhaustion (§2d, §4).

/// The exhausted part of the plane. Pairs are tested only for edges meeting D(c0, radius);
/// a crossing is kept only if it is proven to lie in D(c0, accept) (accept ≥ radius), the
/// disk on which the (possibly local) diagrams coincide with those of all points (§4).
struct Region {
  Point2 c0;
  double radius = kInf;  ///< kInf: no region (exhaust everything)
  double accept = kInf;
};

struct ExactCandidate {
  Edge F{}, N{};
  RationalPoint x;
  Rational A, B;  ///< R² = |x − a|², r² = |x − c|²
};

struct SearchResult {
  std::optional<ExactCandidate> best;
  std::size_t fvd_used = 0, nvd_used = 0, pairs = 0, exact_pairs = 0, candidates = 0,
              exact_widths = 0;
};

/// Does the edge meet the disk D(0, ρ) (coordinates relative to the region centre)?
/// Conservative: false only when proven. `farthest`: FVD edge (else NVD).
template <class RelFn>
bool edge_meets_disk(const Edge& E, RelFn&& rel, double rho, bool farthest) {
  const Rel<Interval>& a = rel(E.a);
  const Rel<Interval>& b = rel(E.b);
  const Interval ux = b.x - a.x, uy = b.y - a.y;
  const Interval u2 = ux * ux + uy * uy;
  if (!(u2.inf() > 0)) return true;  // undecidable in intervals: keep (conservative)
  const Interval k = b.n - a.n;  // line: 2 x·u = k
  // distance² from the centre to the line = k² / (4|u|²)
  const Interval dist2 = (k * k) / (4 * u2);
  const Interval rho2 = Interval(rho) * Interval(rho);
  if (dist2.inf() > rho2.sup()) return false;
  // Parametrise x = m + s t, m = (a + b)/2, t = (−uy, ux); |t|² = |u|².
  const Interval mx = (a.x + b.x) / 2, my = (a.y + b.y) / 2;
  const Interval tx = -uy, ty = ux;
  const Interval sc = -(mx * tx + my * ty) / u2;
  const Interval half2 = (rho2 - dist2) / u2;
  if (!std::isfinite(half2.sup()) || !std::isfinite(sc.inf()) || !std::isfinite(sc.sup()))
    return true;
  const double half = half2.sup() > 0 ? CGAL::sqrt(Interval(half2.sup())).sup() : 0.0;
  double lo = (sc - Interval(half)).inf();
  double hi = (sc + Interval(half)).sup();
  // Membership along the line: |x − a|² − |x − e|² = α − β s.
  auto clip = [&](int e) {
    if (e == kNone) return;
    const Rel<Interval>& q = rel(e);
    const Interval dx = a.x - q.x, dy = a.y - q.y;
    const Interval alpha = (a.n - q.n) - 2 * (mx * dx + my * dy);
    const Interval beta = 2 * (tx * dx + ty * dy);
    const int sb = sign_of(beta);
    if (sb == kUnknown || sb == 0) return;  // no usable constraint: stay conservative
    const Interval ratio = alpha / beta;
    // FVD wants α − βs ≥ 0, NVD wants α − βs ≤ 0.
    const bool upper = farthest ? sb > 0 : sb < 0;
    if (upper) hi = std::min(hi, ratio.sup());
    else lo = std::max(lo, ratio.inf());
  };
  clip(E.e1);
  clip(E.e2);
  return lo <= hi;
}

SearchResult exhaust_overlay(const std::vector<Point2>& p, const Diagrams& d,
                             const Region& region, Point2 origin) {
  SearchResult out;
  struct Found {
    int f, n;
    Interval width;
  };
  std::vector<Found> found;
  const bool bounded = std::isfinite(region.radius);
  const bool check_accept = std::isfinite(region.accept);
  if (bounded) origin = region.c0;
  auto site_q = [&](int i) { return relative<Rational>(p[i], origin); };
  {
    RoundingGuard guard;
    // Interval coordinates relative to the origin, for the sites the edges reference.
    std::vector<int> slot(p.size(), kNone);
    std::vector<Rel<Interval>> rel;
    for (const auto* edges : {&d.fvd, &d.nvd})
      for (const Edge& e : *edges)
        for (int i : {e.a, e.b, e.e1, e.e2})
          if (i != kNone && slot[i] == kNone) {
            slot[i] = static_cast<int>(rel.size());
            rel.push_back(relative<Interval>(p[i], origin));
          }
    auto site_i = [&](int i) -> const Rel<Interval>& { return rel[slot[i]]; };
    std::vector<int> fsel, nsel;
    for (int i = 0; i < static_cast<int>(d.fvd.size()); ++i)
      if (!bounded || edge_meets_disk(d.fvd[i], site_i, region.radius, true)) fsel.push_back(i);
    for (int i = 0; i < static_cast<int>(d.nvd.size()); ++i)
      if (!bounded || edge_meets_disk(d.nvd[i], site_i, region.radius, false))
        nsel.push_back(i);
    out.fvd_used = fsel.size();
    out.nvd_used = nsel.size();
    const Interval accept2 = check_accept ? CGAL::square(Interval(region.accept)) : Interval(0);
    const Interval radius2 = bounded ? CGAL::square(Interval(region.radius)) : Interval(0);
    for (int fi : fsel) {
      const Edge& F = d.fvd[fi];
      for (int ni : nsel) {
        const Edge& N = d.nvd[ni];
        if (F.a == N.a && F.b == N.b) continue;  // same bisector (hull edge in both)
        if (F.a == N.b && F.b == N.a) continue;
        ++out.pairs;
        Crossing<Interval> c;
        int on = crossing_on_edges<Interval>(F, N, site_i, c);
        bool inside = true;
        if (on == 1 && check_accept) {
          const Interval den = 4 * CGAL::square(c.det);
          const Interval d2 = (CGAL::square(c.zx) + CGAL::square(c.zy)) / den;
          if (d2.inf() > radius2.sup()) continue;  // outside the region: irrelevant
          if (!(d2.sup() <= accept2.inf())) on = kUnknown;  // decide exactly
        }
        if (on == kUnknown) {
          ++out.exact_pairs;
          Crossing<Rational> cq;
          on = crossing_on_edges<Rational>(F, N, site_q, cq);
          if (on != 1) continue;
          if (check_accept) {
            const Rational two_det = 2 * cq.det;
            const Rational dx = cq.zx / two_det, dy = cq.zy / two_det;
            const Rational acc(region.accept);
            inside = dx * dx + dy * dy <= acc * acc;
          }
          if (!inside) continue;
          // Enclose the width from the exact crossing.
          const Rational A = squared_distance_4det2(site_q(F.a), cq);
          const Rational B = squared_distance_4det2(site_q(N.a), cq);
          const Interval den = 4 * CGAL::square(Interval(CGAL::to_interval(cq.det)));
          const Interval w = CGAL::sqrt(Interval(CGAL::to_interval(A)) / den) -
                             CGAL::sqrt(Interval(CGAL::to_interval(B)) / den);
          found.push_back({fi, ni, w});
          continue;
        }
        if (on != 1) continue;
        const Interval den = 4 * CGAL::square(c.det);
        const Interval A = squared_distance_4det2(site_i(F.a), c) / den;
        const Interval B = squared_distance_4det2(site_i(N.a), c) / den;
        found.push_back({fi, ni, CGAL::sqrt(A) - CGAL::sqrt(B)});
      }
    }
  }
  out.candidates = found.size();
  if (found.empty()) return out;
  // Contenders: every candidate whose enclosure reaches below the best upper bound.
  double best_sup = kInf;
  for (const Found& f : found) best_sup = std::min(best_sup, f.width.sup());
  std::vector<const Found*> contenders;
  for (const Found& f : found)
    if (!(f.width.inf() > best_sup)) contenders.push_back(&f);
  std::sort(contenders.begin(), contenders.end(),
            [](const Found* a, const Found* b) { return a->width.inf() < b->width.inf(); });
  for (const Found* f : contenders) {
    const Edge& F = d.fvd[f->f];
    const Edge& N = d.nvd[f->n];
    const Rel<Rational> fa = site_q(F.a), na = site_q(N.a);
    const Crossing<Rational> c = crossing(fa, site_q(F.b), na, site_q(N.b));
    const Rational den = 4 * c.det * c.det;
    ExactCandidate e;
    e.F = F;
    e.N = N;
    e.A = squared_distance_4det2(fa, c) / den;
    e.B = squared_distance_4det2(na, c) / den;
    const Rational two_det = 2 * c.det;
    e.x = {Rational(origin.x) + c.zx / two_det, Rational(origin.y) + c.zy / two_det};
    ++out.exact_widths;
    if (!out.best || compare_widths(e.A, e.B, out.best->A, out.best->B) < 0)
      out.best = std::move(e);
  }
  return out;
}

// ---------------------------------------------------------------------------------------
// Seeds and the region bound (§4).

/// Proven upper bound of f(c) (interval arithmetic). O(n).
double zone_width_upper(const std::vector<Point2>& p, Point2 c) {
  RoundingGuard guard;
  double max_sup = 0.0, min_inf = kInf;
  const Interval cx(c.x), cy(c.y);
  for (const Point2& q : p) {
    const Interval dx = Interval(q.x) - cx, dy = Interval(q.y) - cy;
    const Interval d2 = CGAL::square(dx) + CGAL::square(dy);
    max_sup = std::max(max_sup, d2.sup());
    min_inf = std::min(min_inf, d2.inf());
  }
  return (CGAL::sqrt(Interval(max_sup)) - CGAL::sqrt(Interval(std::max(0.0, min_inf)))).sup();
}

/// Algebraic (Kåsa) circle centre on centred data: a start, nothing more.
Point2 kasa_center(const std::vector<Point2>& p) {
  double mx = 0.0, my = 0.0;
  for (const Point2& q : p) {
    mx += q.x;
    my += q.y;
  }
  mx /= static_cast<double>(p.size());
  my /= static_cast<double>(p.size());
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (const Point2& q : p) {
    const double x = q.x - mx, y = q.y - my;
    const Eigen::Vector3d row(x, y, 1.0);
    M += row * row.transpose();
    v -= row * (x * x + y * y);
  }
  const Eigen::Vector3d s = M.ldlt().solve(v);
  if (!s.allFinite()) return {mx, my};
  return {mx - s[0] / 2.0, my - s[1] / 2.0};
}

/// A pseudo-angle of (dx, dy) in [0, 4), monotone in the true angle (no atan2).
double pseudo_angle(double dx, double dy) {
  const double s = std::abs(dx) + std::abs(dy);
  if (s == 0.0) return 0.0;
  const double t = dy / s;
  return dx >= 0.0 ? (dy >= 0.0 ? t : 4.0 + t) : 2.0 - t;
}

/// Indices of the extreme points about c: the `top` farthest and nearest overall and, if
/// `sectors` > 0, the farthest and the nearest of each angular sector. Returns (far, near),
/// each sorted and without repetitions. O(n).
std::pair<std::vector<int>, std::vector<int>> extreme_points(const std::vector<Point2>& p,
                                                             Point2 c, int sectors,
                                                             std::size_t top) {
  std::vector<double> rho2(p.size());
  std::vector<int> far_s(static_cast<std::size_t>(std::max(sectors, 0)), kNone),
      near_s(static_cast<std::size_t>(std::max(sectors, 0)), kNone);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double dx = p[i].x - c.x, dy = p[i].y - c.y;
    rho2[i] = dx * dx + dy * dy;
    if (sectors <= 0) continue;
    const auto s = static_cast<std::size_t>(
        std::min(static_cast<double>(sectors - 1), pseudo_angle(dx, dy) * sectors / 4.0));
    if (far_s[s] == kNone || rho2[i] > rho2[far_s[s]]) far_s[s] = static_cast<int>(i);
    if (near_s[s] == kNone || rho2[i] < rho2[near_s[s]]) near_s[s] = static_cast<int>(i);
  }
  std::vector<int> idx(p.size());
  std::iota(idx.begin(), idx.end(), 0);
  const auto k = static_cast<std::ptrdiff_t>(std::min(top, p.size()));
  std::vector<int> far_set, near_set;
  std::nth_element(idx.begin(), idx.begin() + k, idx.end(),
                   [&](int a, int b) { return rho2[a] > rho2[b]; });
  far_set.assign(idx.begin(), idx.begin() + k);
  std::nth_element(idx.begin(), idx.begin() + k, idx.end(),
                   [&](int a, int b) { return rho2[a] < rho2[b]; });
  near_set.assign(idx.begin(), idx.begin() + k);
  for (int i : far_s)
    if (i != kNone) far_set.push_back(i);
  for (int i : near_s)
    if (i != kNone) near_set.push_back(i);
  for (auto* v : {&far_set, &near_set}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  return {far_set, near_set};
}

/// The cone bound of §4 for the candidate pairs far × near: max over cones of the least
/// proven δ; kInf when a cone has no usable pair.
double cone_bound(const std::vector<Point2>& p, Point2 c0, double W,
                  const std::vector<int>& far_set, const std::vector<int>& near_set) {
  std::array<Point2, kCones + 1> b;
  for (int k = 0; k < kCones; ++k) {
    const double t = 2.0 * std::numbers::pi * k / kCones;
    b[static_cast<std::size_t>(k)] = {std::cos(t), std::sin(t)};
  }
  b[kCones] = b[0];  // the same doubles: the cones tile the plane exactly
  struct Pair {
    int p, q;
    double dx, dy, num;
  };
  std::vector<Pair> pairs;
  pairs.reserve(far_set.size() * near_set.size());
  for (int i : far_set) {
    const double rp = std::sqrt(square_distance(p[i], c0));
    for (int j : near_set) {
      if (i == j) continue;
      const double rq = std::sqrt(square_distance(p[j], c0));
      pairs.push_back({i, j, p[j].x - p[i].x, p[j].y - p[i].y,
                       std::max(0.0, (rp + rq) * (W - rp + rq))});
    }
  }
  double radius = 0.0;
  RoundingGuard guard;
  const Interval Wi(W);
  const Interval bmax(1.0, 1.0 + 1e-15);  // |b_k| ≤ 1 + a few ulps
  for (int k = 0; k < kCones; ++k) {
    const Point2 b0 = b[static_cast<std::size_t>(k)], b1 = b[static_cast<std::size_t>(k) + 1];
    // Two best pairs in double, then the proven bound for them.
    std::array<std::pair<double, int>, 2> best{{{kInf, -1}, {kInf, -1}}};
    for (int m = 0; m < static_cast<int>(pairs.size()); ++m) {
      const Pair& q = pairs[static_cast<std::size_t>(m)];
      const double bl = std::min(q.dx * b0.x + q.dy * b0.y, q.dx * b1.x + q.dy * b1.y);
      if (!(bl > W)) continue;
      const double delta = q.num / (2.0 * (bl - W));
      if (delta < best[1].first) {
        best[1] = {delta, m};
        if (best[1].first < best[0].first) std::swap(best[0], best[1]);
      }
    }
    double cone = kInf;
    for (const auto& [approx, m] : best) {
      if (m < 0) continue;
      const Pair& q = pairs[static_cast<std::size_t>(m)];
      const Rel<Interval> rp = relative<Interval>(p[q.p], c0);
      const Rel<Interval> rq = relative<Interval>(p[q.q], c0);
      const Interval dx = rq.x - rp.x, dy = rq.y - rp.y;
      const Interval B0 = dx * b0.x + dy * b0.y, B1 = dx * b1.x + dy * b1.y;
      const double lower = std::min(B0.inf(), B1.inf());
      if (!(lower > 0)) continue;
      const Interval excess = Interval(lower) / bmax - Wi;
      if (!(excess.inf() > 0)) continue;
      const Interval rhop = CGAL::sqrt(rp.n), rhoq = CGAL::sqrt(rq.n);
      const Interval num = (rhop + rhoq) * (Wi - rhop + rhoq);
      cone = std::min(cone, std::max(0.0, (num / (2 * excess)).sup()));
    }
    radius = std::max(radius, cone);
    if (!std::isfinite(radius)) return kInf;
  }
  return radius;
}

/// Proven radius ρ* about c0 containing every centre c with f(c) ≤ W (§4); kInf when some
/// direction cone has no usable pair. Pairs: the 12 farthest × 12 nearest points about c0
/// (enough when c0 is near the optimum), else also the extremes of 32 angular sectors.
double region_radius(const std::vector<Point2>& p, Point2 c0, double W) {
  {
    const auto [far_set, near_set] = extreme_points(p, c0, 0, 12);
    const double r = cone_bound(p, c0, W, far_set, near_set);
    if (std::isfinite(r)) return r;
  }
  const auto [far_set, near_set] = extreme_points(p, c0, kSectors, 8);
  return cone_bound(p, c0, W, far_set, near_set);
}

/// The sites that can be farthest (far) or nearest (near) from some centre in D(c0, ρ):
/// |c0 − p| ≥ R(c0) − 2ρ, resp. ≤ r(c0) + 2ρ (R, r are 1-Lipschitz), decided
/// conservatively in interval arithmetic; at least the 8 extreme ones each.
std::pair<std::vector<int>, std::vector<int>> local_sites(const std::vector<Point2>& p,
                                                         Point2 c0, double rho) {
  auto [far_set, near_set] = extreme_points(p, c0, 0, 8);
  RoundingGuard guard;
  std::vector<Interval> d(p.size());
  double R_lo = 0.0, r_hi = kInf;
  for (std::size_t i = 0; i < p.size(); ++i) {
    d[i] = CGAL::sqrt(relative<Interval>(p[i], c0).n);
    R_lo = std::max(R_lo, d[i].inf());
    r_hi = std::min(r_hi, d[i].sup());
  }
  const double far_limit = (Interval(R_lo) - 2 * Interval(rho)).inf();
  const double near_limit = (Interval(r_hi) + 2 * Interval(rho)).sup();
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (d[i].sup() >= far_limit) far_set.push_back(static_cast<int>(i));
    if (d[i].inf() <= near_limit) near_set.push_back(static_cast<int>(i));
  }
  for (auto* v : {&far_set, &near_set}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  return {std::move(far_set), std::move(near_set)};
}

struct Seed {
  Point2 c;
  std::size_t rounds = 0;
};

/// A good centre for the region (§4): the exact method on extreme subsets, enlarged with
/// violators until none remain. Only its quality matters, not its proof.
Seed seed_center(const std::vector<Point2>& p) {
  Seed seed{kasa_center(p), 0};
  double best_w = kInf;
  {
    const auto [far_set, near_set] = extreme_points(p, seed.c, kSectors, 8);
    std::vector<int> subset = far_set;
    subset.insert(subset.end(), near_set.begin(), near_set.end());
    std::vector<char> in(p.size(), 0);
    Point2 c = seed.c;
    for (int round = 0; round < 12; ++round) {
      std::sort(subset.begin(), subset.end());
      subset.erase(std::unique(subset.begin(), subset.end()), subset.end());
      for (int i : subset) in[static_cast<std::size_t>(i)] = 1;
      std::vector<Point2> sp;
      sp.reserve(subset.size());
      for (int i : subset) sp.push_back(p[static_cast<std::size_t>(i)]);  // sorted by (x, y)
      ++seed.rounds;
      // The subset must span a non-degenerate, non-co-circular set; otherwise stop.
      const std::vector<int> everything = all_sites(sp.size());
      const Diagrams ds = build_diagrams(sp, everything, everything);
      if (!ds.ok) break;
      const double Ws = zone_width_upper(sp, c);
      const Region region{c, region_radius(sp, c, Ws), kInf};
      SearchResult rs = exhaust_overlay(sp, ds, region, c);
      if (!rs.best) break;
      const Point2 x = to_point(rs.best->x);
      const double Rs = std::sqrt(to_double(rs.best->A)), rs_ = std::sqrt(to_double(rs.best->B));
      // Evaluate on all points; collect the violators.
      std::vector<std::pair<double, int>> out_v, in_v;
      double R = 0.0, r = kInf;
      for (std::size_t i = 0; i < p.size(); ++i) {
        const double rho = std::sqrt(square_distance(p[i], x));
        R = std::max(R, rho);
        r = std::min(r, rho);
        if (in[i]) continue;
        if (rho > Rs) out_v.push_back({rho - Rs, static_cast<int>(i)});
        if (rho < rs_) in_v.push_back({rs_ - rho, static_cast<int>(i)});
      }
      if (R - r < best_w) {
        best_w = R - r;
        seed.c = x;
      }
      if (out_v.empty() && in_v.empty()) break;
      c = x;
      for (auto* v : {&out_v, &in_v}) {
        const std::size_t k = std::min<std::size_t>(16, v->size());
        std::partial_sort(v->begin(), v->begin() + static_cast<std::ptrdiff_t>(k), v->end(),
                          std::greater<>());
        for (std::size_t j = 0; j < k; ++j) subset.push_back((*v)[j].second);
      }
    }
  }
  return seed;
}

// ---------------------------------------------------------------------------------------
// Attainment (§2e).

/// true when w* = √A − √B ≤ w_min, the minimal width of the hull (then the minimum is
/// attained). `w_min_approx` receives an approximation of w_min for messages.
bool minimum_is_attained(const std::vector<Point2>& p, const std::vector<int>& hull,
                         const Rational& A, const Rational& B, double& w_min_approx) {
  const int h = static_cast<int>(hull.size());
  const Point2 o = p[hull[0]];
  w_min_approx = kInf;
  Interval w_star;
  std::vector<std::pair<int, int>> undecided;  // (edge start, antipodal vertex)
  {
    RoundingGuard guard;
    w_star = CGAL::sqrt(Interval(CGAL::to_interval(A))) - CGAL::sqrt(Interval(CGAL::to_interval(B)));
    // Rotating calipers in double (relative coordinates) to find each edge's farthest
    // vertex; the height of that vertex is then enclosed in interval arithmetic.
    std::vector<Point2> q(hull.size());
    for (int i = 0; i < h; ++i) q[i] = {p[hull[i]].x - o.x, p[hull[i]].y - o.y};
    auto cross_d = [&](int i, int j) {
      const Point2 a = q[i], b = q[(i + 1) % h], v = q[j];
      return (b.x - a.x) * (v.y - a.y) - (b.y - a.y) * (v.x - a.x);
    };
    int j = 1;
    for (int i = 0; i < h; ++i) {
      if (j == i) j = (j + 1) % h;
      while (cross_d(i, (j + 1) % h) >= cross_d(i, j) && (j + 1) % h != i) j = (j + 1) % h;
      const Rel<Interval> a = relative<Interval>(p[hull[i]], o);
      const Rel<Interval> b = relative<Interval>(p[hull[(i + 1) % h]], o);
      const Rel<Interval> v = relative<Interval>(p[hull[j]], o);
      const Interval ex = b.x - a.x, ey = b.y - a.y;
      const Interval w = (ex * (v.y - a.y) - ey * (v.x - a.x)) / CGAL::sqrt(ex * ex + ey * ey);
      w_min_approx = std::min(w_min_approx, CGAL::to_double(w));
      if (!(w.inf() > w_star.sup())) undecided.push_back({i, j});
    }
  }
  for (const auto& [i, j] : undecided) {
    // Exact: the width for edge i is the largest height over all vertices.
    const RationalPoint a = to_rational(p[hull[i]]), b = to_rational(p[hull[(i + 1) % h]]);
    const Rational ex = b.x - a.x, ey = b.y - a.y, e2 = ex * ex + ey * ey;
    auto cross_to = [&](int k) -> Rational {
      const RationalPoint v = to_rational(p[hull[k]]);
      return ex * (v.y - a.y) - ey * (v.x - a.x);
    };
    Rational cr = cross_to(j);
    if (compare_sqrt_sums(A, 0, B, cr * cr / e2) <= 0) continue;  // w* ≤ height(j) ≤ width
    for (int k = 0; k < h; ++k) {
      Rational ck = cross_to(k);
      if (ck > cr) cr = std::move(ck);
    }
    if (compare_sqrt_sums(A, 0, B, cr * cr / e2) > 0) return false;
  }
  return true;
}

// ---------------------------------------------------------------------------------------
// Contacts and the reported quadruple (§2b).

Rational cross(const RationalPoint& a, const RationalPoint& b) { return a.x * b.y - a.y * b.x; }
int half_plane(const RationalPoint& v) {
  return (CGAL::is_positive(v.y) || (CGAL::is_zero(v.y) && CGAL::is_positive(v.x))) ? 0 : 1;
}
bool angle_less(const RationalPoint& a, const RationalPoint& b) {
  const int ha = half_plane(a), hb = half_plane(b);
  if (ha != hb) return ha < hb;
  return CGAL::is_positive(cross(a, b));
}
bool same_direction(const RationalPoint& a, const RationalPoint& b) {
  return half_plane(a) == half_plane(b) && CGAL::is_zero(cross(a, b));
}

struct Contact {
  int site;
  bool outer;
  RationalPoint dir;  ///< site − centre
};

struct Quadruple {
  std::array<int, 2> outer{}, inner{};
  bool strict = false;
};

/// Four contacts, strictly alternating if possible (always, except the three-ray case).
std::optional<Quadruple> alternating_quadruple(std::vector<Contact> contacts) {
  std::sort(contacts.begin(), contacts.end(),
            [](const Contact& a, const Contact& b) { return angle_less(a.dir, b.dir); });
  struct Group {
    int outer = kNone, inner = kNone;
  };
  std::vector<Group> groups;
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    if (k == 0 || !same_direction(contacts[k - 1].dir, contacts[k].dir)) groups.push_back({});
    (contacts[k].outer ? groups.back().outer : groups.back().inner) = contacts[k].site;
  }
  // Greedy alternating subsequence with both choices of the first label (a group holding
  // both labels serves as either).
  for (int first_outer = 1; first_outer >= 0; --first_outer) {
    std::vector<int> picks;
    bool want_outer = first_outer == 1;
    for (const Group& g : groups) {
      const int s = want_outer ? g.outer : g.inner;
      if (s == kNone) continue;
      picks.push_back(s);
      want_outer = !want_outer;
      if (picks.size() == 4) break;
    }
    if (picks.size() == 4) {
      Quadruple q;
      q.strict = true;
      if (first_outer == 1) {
        q.outer = {picks[0], picks[2]};
        q.inner = {picks[1], picks[3]};
      } else {
        q.outer = {picks[1], picks[3]};
        q.inner = {picks[0], picks[2]};
      }
      return q;
    }
  }
  // Three-ray degeneracy: any two outer and two inner contacts whose bisectors cross.
  std::vector<int> outs, ins;
  std::vector<RationalPoint> od, id;
  for (const Contact& c : contacts) {
    (c.outer ? outs : ins).push_back(c.site);
    (c.outer ? od : id).push_back(c.dir);
  }
  for (std::size_t a = 0; a < outs.size(); ++a)
    for (std::size_t b = a + 1; b < outs.size(); ++b)
      for (std::size_t c = 0; c < ins.size(); ++c)
        for (std::size_t e = c + 1; e < ins.size(); ++e) {
          const RationalPoint u{od[b].x - od[a].x, od[b].y - od[a].y};
          const RationalPoint v{id[e].x - id[c].x, id[e].y - id[c].y};
          if (!CGAL::is_zero(cross(u, v))) {
            Quadruple q;
            q.outer = {outs[a], outs[b]};
            q.inner = {ins[c], ins[e]};
            return q;
          }
        }
  return std::nullopt;
}

/// All outer and inner contacts at the exact centre x (interval filter, exact decision).
/// Throws std::logic_error if a point lies outside the annulus (an internal error).
std::vector<Contact> contacts_at(const std::vector<Point2>& p, const ExactCandidate& e) {
  std::vector<int> maybe;
  {
    RoundingGuard guard;
    const Interval xx(CGAL::to_interval(e.x.x)), xy(CGAL::to_interval(e.x.y));
    const Interval A(CGAL::to_interval(e.A)), B(CGAL::to_interval(e.B));
    for (int i = 0; i < static_cast<int>(p.size()); ++i) {
      const Interval dx = Interval(p[i].x) - xx, dy = Interval(p[i].y) - xy;
      const Interval d2 = CGAL::square(dx) + CGAL::square(dy);
      if (d2.sup() < A.inf() && d2.inf() > B.sup()) continue;
      maybe.push_back(i);
    }
  }
  std::vector<Contact> contacts;
  for (int i : maybe) {
    const RationalPoint d{Rational(p[i].x) - e.x.x, Rational(p[i].y) - e.x.y};
    const Rational d2 = d.x * d.x + d.y * d.y;
    const int so = CGAL::compare(d2, e.A), si = CGAL::compare(d2, e.B);
    if (so > 0 || si < 0)
      throw std::logic_error("minimum_zone_overlay: internal error: a point lies outside the "
                             "annulus of an overlay vertex");
    if (so == 0) contacts.push_back({i, true, d});
    else if (si == 0) contacts.push_back({i, false, d});
  }
  return contacts;
}

std::string format_double(double v) {
  std::ostringstream os;
  os.precision(3);
  os << v;
  return os.str();
}

}  // namespace

MinimumZoneCircle minimum_zone_overlay(std::span<const Point2> points,
                                       const OverlayOptions& options,
                                       OverlayStatistics* statistics) {
  OverlayStatistics stats_local;
  OverlayStatistics& stats = statistics ? *statistics : stats_local;
  stats = {};
  auto clock = std::chrono::steady_clock::now();
  auto lap = [&clock](double& ms) {
    const auto now = std::chrono::steady_clock::now();
    ms = std::chrono::duration<double, std::milli>(now - clock).count();
    clock = now;
  };
  const Sites sites = distinct_sites(points);
  const std::vector<Point2>& p = sites.p;
  stats.distinct_points = p.size();
  if (p.size() < 3)
    throw InvalidInput("minimum_zone_overlay: needs at least 3 distinct points; got " +
                       std::to_string(p.size()));

  // All points on one circle (includes 3 distinct points): zero width.
  {
    std::size_t c = 2;
    while (c < p.size() && CGAL::orientation(to_epick(p[0]), to_epick(p[1]), to_epick(p[c])) ==
                               CGAL::COLLINEAR)
      ++c;
    if (c == p.size())
      throw InvalidInput("minimum_zone_overlay: all points are collinear (exact test)");
    bool cocircular = true;
    for (std::size_t k = 2; k < p.size() && cocircular; ++k)
      cocircular = CGAL::side_of_oriented_circle(to_epick(p[0]), to_epick(p[1]),
                                                 to_epick(p[c]), to_epick(p[k])) ==
                   CGAL::ON_ORIENTED_BOUNDARY;
    if (cocircular) {
      stats.cocircular = true;
      return make_cocircular_result(points, sites.original[0], sites.original[1],
                                    sites.original[c]);
    }
  }

  const std::vector<int> everything = all_sites(p.size());
  const std::vector<int> hull = convex_hull_ccw(p, everything);
  stats.hull_vertices = hull.size();
  lap(stats.ms_prepare);

  // Region (§4): seed, proven radius, and the local sites that can be farthest / nearest
  // from a centre in the acceptance disk. Without a region: the whole overlay.
  Region region;
  Point2 origin;
  double W = kInf;
  Diagrams d;
  std::size_t far_count = p.size(), near_count = p.size();
  if (options.prune && p.size() > kFullOverlayMaxSites) {
    const Seed seed = seed_center(p);
    stats.seed_rounds = seed.rounds;
    lap(stats.ms_seed);
    W = zone_width_upper(p, seed.c);
    region.c0 = seed.c;
    region.radius = region_radius(p, seed.c, W);
    if (std::isfinite(region.radius)) {
      // Any accept > radius works; the margin keeps it positive and above the rounding of
      // the crossings' enclosures.
      const double scale = std::abs(seed.c.x) + std::abs(seed.c.y) +
                           std::sqrt(square_distance(p[hull[0]], seed.c));
      region.accept = 2.0 * region.radius + 1e-12 * scale;
      const auto [far_set, near_set] = local_sites(p, seed.c, region.accept);
      lap(stats.ms_region);
      d = build_diagrams(p, far_set, near_set);
      far_count = far_set.size();
      near_count = near_set.size();
    } else {
      lap(stats.ms_region);
    }
    origin = seed.c;
  } else {
    double xmin = kInf, xmax = -kInf, ymin = kInf, ymax = -kInf;
    for (const Point2& q : p) {
      xmin = std::min(xmin, q.x);
      xmax = std::max(xmax, q.x);
      ymin = std::min(ymin, q.y);
      ymax = std::max(ymax, q.y);
    }
    origin = {xmin + (xmax - xmin) / 2, ymin + (ymax - ymin) / 2};
  }
  if (!d.ok) {  // no region, or local sites too few / collinear: all sites
    region.accept = kInf;
    far_count = near_count = p.size();
    d = build_diagrams(p, everything, everything);
    if (!d.ok)
      throw std::logic_error("minimum_zone_overlay: internal error: no 2D Voronoi diagrams");
  }
  stats.far_sites = far_count;
  stats.near_sites = near_count;
  stats.fvd_edges = d.fvd.size();
  stats.nvd_edges = d.nvd.size();
  stats.region_used = std::isfinite(region.radius);
  stats.region_radius = stats.region_used ? region.radius : 0.0;
  lap(stats.ms_diagrams);

  SearchResult search = exhaust_overlay(p, d, region, origin);
  lap(stats.ms_exhaustion);
  stats.fvd_edges_in_region = search.fvd_used;
  stats.nvd_edges_in_region = search.nvd_used;
  stats.edge_pairs = search.pairs;
  stats.exact_pair_tests = search.exact_pairs;
  stats.candidates = search.candidates;
  stats.exact_width_evaluations = search.exact_widths;

  if (!search.best) {
    std::ostringstream os;
    os << "minimum_zone_overlay: the minimum zone is not attained: no overlay vertex of the "
          "nearest/farthest Voronoi diagrams has a zone width ≤ "
       << format_double(W) << " mm (" << p.size()
       << " distinct points); the width only tends to its infimum, the minimal width of the "
          "convex hull, as the centre recedes to infinity (nearly straight data)";
    throw UndefinedResult(os.str());
  }
  const ExactCandidate& best = *search.best;
  double w_min = kInf;
  if (!minimum_is_attained(p, hull, best.A, best.B, w_min)) {
    std::ostringstream os;
    os << "minimum_zone_overlay: the minimum zone is not attained: the best overlay vertex "
          "has width "
       << format_double(std::sqrt(to_double(best.A)) - std::sqrt(to_double(best.B)))
       << " mm, more than the minimal width of the convex hull (" << format_double(w_min)
       << " mm), the infimum approached only as the centre recedes to infinity (nearly "
          "straight data)";
    throw UndefinedResult(os.str());
  }

  // The reported quadruple: a strictly alternating four among all contacts at the optimum
  // (§2b).
  const std::vector<Contact> contacts = contacts_at(p, best);
  const std::optional<Quadruple> quad = alternating_quadruple(contacts);
  if (!quad)
    throw std::logic_error("minimum_zone_overlay: internal error: no 2+2 contact set at the "
                           "optimal overlay vertex");

  std::ostringstream arg;
  arg << (quad->strict ? "2+2 alternating contacts" : "2+2 contacts (degenerate: contacts on "
                                                      "three rays, none strictly alternating)")
      << "; global: exact overlay of the farthest-point and nearest-point Voronoi diagrams ("
      << p.size() << " distinct points, " << hull.size() << " hull vertices): ";
  double region_radius_out = 0.0;
  if (stats.region_used) {
    const Point2 x = to_point(best.x);
    region_radius_out = region.radius + std::hypot(x.x - region.c0.x, x.y - region.c0.y);
    region_radius_out = std::nextafter(region_radius_out * (1 + 1e-12), kInf);
    arg << "every centre with width <= " << format_double(W) << " mm lies within "
        << format_double(region.radius) << " mm of a seed centre (hyperbola bound); there "
        << far_count << " sites can be farthest and " << near_count
        << " nearest, and their diagrams' " << search.fvd_used << " x " << search.nvd_used
        << " edge pairs meeting the region were exhausted";
  } else {
    arg << "all " << search.pairs << " edge pairs exhausted";
  }
  arg << " (" << search.candidates << " overlay vertices, least width decided exactly); "
      << "minimum attained (below the hull's minimal width " << format_double(w_min) << " mm)";
  Certificate cert{Optimality::global, arg.str(), region_radius_out};
  MinimumZoneCircle result = make_minimum_zone_result(
      points, {sites.original[quad->outer[0]], sites.original[quad->outer[1]]},
      {sites.original[quad->inner[0]], sites.original[quad->inner[1]]}, std::move(cert));
  lap(stats.ms_finish);
  return result;
}

MinimumZoneCircle minimum_zone_overlay(std::span<const Point2> points) {
  return minimum_zone_overlay(points, OverlayOptions{}, nullptr);
}

}  // namespace vcmm::geometry::internal
