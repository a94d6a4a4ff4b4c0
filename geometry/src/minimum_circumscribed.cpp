// minimum_circumscribed.cpp — the minimum-circumscribed circle (MCCI, ISO 12181-1).
//
// Notation
//   p_0 … p_{n−1}  input points (doubles, taken as exact rationals)
//   MC(S)          smallest closed disc containing the set S (unique: Welzl 1991, Lemma 1)
//   c*, R*²        exact rational centre and squared radius of MC(P); c̃, R̃ their doubles
//
// Derivation
//   The MC problem  min_c max_i |c − p_i|  is convex; its optimum is unique and is fixed by
//   2 or 3 support points on the circle whose closed convex hull contains c* (KKT: 0 is in
//   the convex hull of the active gradients c* − p_k). Conversely such a circle that
//   encloses every point is optimal — this is the certificate, checked exactly.
//
//   1. Warm start: a centre estimate c₀ (Kåsa on a stride sample: O(1)); the candidate
//      set S holds, for each of s ≤ 64 pseudo-angle sectors about c₀, the point farthest
//      from c₀ among a stride sample of ~512 points (a division per sampled point only).
//   2. MC(S) by Welzl's algorithm (iterative three-loop form, candidates farthest-first).
//      A circle is represented by its 1, 2 or 3 support points and every "strictly
//      outside" decision is exact on input points: for 2 supports the sign of
//      (t − a)·(t − b), for 3 CGAL's statically filtered side_of_oriented_circle re-signed
//      by the supports' orientation. No constructed double circle is ever tested, so the
//      support set is exact.
//   3. The exact circle of the supports (midpoint or circumcentre, GMP integers) is built
//      once per round, and every input point is classified by the rigorous floating filter
//      of internal/extremal_circle.cpp (error bound ~1e-15 relative); only points in the
//      ambiguous band go to the exact predicate. Points strictly outside join S (the
//      farthest per sector when there are more than 64); repeat. Before that pass, a
//      local refinement (internal::local_extreme, once): each support's
//      farthest neighbour along the input order within n/64 indices and up the slope
//      beyond (about the round's centre) joins S when it is not a support — on filtered
//      scans the contacts of the full set sit there, so one O(n) pass usually suffices.
//      Termination: a violator q of MC(S) gives MC(S ∪ {q}) a larger radius, and S only
//      grows. Correctness: a circle that is MC(S) and encloses all of P is MC(P), because
//      any disc containing P contains S and is therefore not smaller than MC(S).
//   4. Contacts: when the 3 supports form a right triangle the hypotenuse pair (c* is its
//      midpoint) is reported; when they form an obtuse triangle (possible only with ≥ 4
//      co-circular points of S) the co-circular points of S are collected exactly and 2 or
//      3 of them whose closed hull contains c* are chosen (see choose_contacts). Among
//      duplicated points the lowest index is reported (duplicates of a contact lie on the
//      circle, so the final pass meets them all in its exact band).
//   5. Centre: exact value rounded once (each coordinate within 1.25 ulp); radius: sqrt of
//      the exact R*² rounded (within ~1.3 ulp). RONt = R* − min_i |p_i − c*| is computed as
//      (R*² − |p_j − c*|²)/(R̃ + ρ̃_j) with the numerator exact (j = the nearest point by
//      the last floating pass): a few ulps of RONt, no cancellation. RONp = 0,
//      RONv = RONt, RONq from roundness_parameters about (c̃, R̃).
//
// Complexity: O(n) per round (one floating pass) plus the exact work on |S| candidates;
// on nearly round profiles 1-2 rounds (the sample misses the highest points of a dense
// profile and the first full pass finds them) and |S| ≤ ~130. Worst case (bad warm
// start) the number of rounds is bounded by n, each adding at least one point.
#include "vcmm/geometry/minimum_circumscribed.h"

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
#include "internal/precise_distance.h"
#include "internal/prevalidated.h"

namespace vcmm::geometry {

namespace {

using internal::EPoint;
using internal::ExactCircle;
using internal::to_epick;

/// A circle of Welzl's recursion, represented only by its support points (indices into
/// the input).
struct Support {
  int size = 0;
  std::array<std::size_t, 3> idx{};
};

/// Welzl's algorithm on a small set, in the iterative three-loop form (de Berg et al.,
/// Computational Geometry, 3rd ed., 4.7; expected O(m) predicate calls for a random order,
/// O(m³) worst case) with Welzl's move-to-front heuristic (Welzl 1991, section 3; Gärtner's
/// miniball): a point found outside moves to the front of the list, so the later loops meet
/// the supports first. Started farthest-first (order_farthest_first). Works on positions
/// into the set; every decision is an exact predicate. The circle is unique; which of ≥ 4
/// exactly co-circular points support it depends on the order (`move_to_front` false: the
/// plain three-loop form, whose choice the reported contacts keep on such sets).
class Welzl {
 public:
  Welzl(std::span<const Point2> points, std::span<const std::size_t> set,
        bool move_to_front = true)
      : set_(set), mtf_(move_to_front) {
    pt_.reserve(set.size());
    ep_.reserve(set.size());
    order_.reserve(set.size());
    for (std::size_t i : set) {
      order_.push_back(pt_.size());
      pt_.push_back(points[i]);
      ep_.push_back(to_epick(points[i]));
    }
  }

  /// MC of the set (precondition: non-empty).
  Support run() {
    Pos d{1, {order_[0], 0, 0}, CGAL::COLLINEAR};
    for (std::size_t t = 1; t < order_.size(); ++t)
      if (is_outside(d, order_[t])) {
        d = with_one(t);
        move_to_front(t);
      }
    Support s{d.size, {}};
    for (int k = 0; k < d.size; ++k) s.idx[k] = set_[d.pos[k]];
    return s;
  }

 private:
  struct Pos {
    int size = 0;
    std::array<std::size_t, 3> pos{};
    CGAL::Orientation orientation = CGAL::COLLINEAR;  ///< of 3 supports, once known
  };
  /// The list entry at t moves to the front; entries 0..t−1 shift back by one.
  void move_to_front(std::size_t t) {
    if (!mtf_) return;
    std::rotate(order_.begin(), order_.begin() + static_cast<std::ptrdiff_t>(t),
                order_.begin() + static_cast<std::ptrdiff_t>(t) + 1);
  }
  // MC of the list's first t points and point i = order_[t], with i on the boundary.
  Pos with_one(std::size_t t) {
    const std::size_t i = order_[t];
    Pos d{1, {i, 0, 0}, CGAL::COLLINEAR};
    for (std::size_t u = 0; u < t; ++u)
      if (is_outside(d, order_[u])) {
        d = with_two(u, i);
        move_to_front(u);
      }
    return d;
  }
  // MC of the list's first u points and j = order_[u], i, with j and i on the boundary.
  // Welzl's Lemma 1 makes the circle through i, j and a violator k exist, so the three are
  // never collinear (the decisions being exact, this holds exactly).
  Pos with_two(std::size_t u, std::size_t i) {
    const std::size_t j = order_[u];
    Pos d{2, {j, i, 0}, CGAL::COLLINEAR};
    for (std::size_t v = 0; v < u; ++v)
      if (is_outside(d, order_[v])) {
        d = Pos{3, {j, i, order_[v]}, CGAL::COLLINEAR};
        move_to_front(v);
      }
    return d;
  }
  // Exact "strictly outside" tests: for 2 supports the sign of (t − a)·(t − b) (filtered
  // dot product), for 3 the statically filtered side_of_oriented_circle re-signed by the
  // supports' orientation (computed once per support change).
  bool is_outside(Pos& d, std::size_t k) const {
    switch (d.size) {
      case 1:
        return pt_[k] != pt_[d.pos[0]];
      case 2:
        return internal::dot_sign(pt_[k], pt_[d.pos[0]], pt_[d.pos[1]]) > 0;
      default: {
        if (d.orientation == CGAL::COLLINEAR)
          d.orientation = CGAL::orientation(ep_[d.pos[0]], ep_[d.pos[1]], ep_[d.pos[2]]);
        // Floating stages first (near-co-circular candidates defeat CGAL's static filter
        // and would all go to its exact arithmetic), CGAL's exact predicate for the ties.
        const int s = internal::filtered_incircle(pt_[d.pos[0]], pt_[d.pos[1]],
                                                  pt_[d.pos[2]], pt_[k]);
        if (s != 2) return s != 0 && (s < 0) == (d.orientation == CGAL::COUNTERCLOCKWISE);
        return internal::side_of_circumcircle(ep_[d.pos[0]], ep_[d.pos[1]], ep_[d.pos[2]],
                                              d.orientation,
                                              ep_[k]) == CGAL::ON_UNBOUNDED_SIDE;
      }
    }
  }

  std::span<const std::size_t> set_;
  std::vector<Point2> pt_;
  std::vector<EPoint> ep_;
  std::vector<std::size_t> order_;  ///< the list: positions into pt_, moved to front
  bool mtf_;
};

ExactCircle exact_circle_of(std::span<const Point2> points, const Support& s) {
  switch (s.size) {
    case 1:
      return internal::exact_point_circle(points[s.idx[0]]);
    case 2:
      return internal::exact_diametral_circle(points[s.idx[0]], points[s.idx[1]]);
    default:
      return internal::exact_circumcircle(points[s.idx[0]], points[s.idx[1]],
                                          points[s.idx[2]]);
  }
}

/// Orders the candidates farthest-first about c (ties by index). Welzl's loops then meet
/// the eventual supports early and rarely restart: on our profiles this beats a random
/// order (the classical expected-O(m) bound) by a factor ~2. The worst case of the
/// three-loop formulation is O(m³) predicate calls, with m ≤ a few hundred candidates.
void order_farthest_first(std::span<const Point2> points, Point2 c,
                          std::vector<std::size_t>& v) {
  thread_local std::vector<std::pair<double, std::size_t>> key;  // kept: no allocation per call
  key.clear();
  for (std::size_t i : v) {
    const double dx = points[i].x - c.x, dy = points[i].y - c.y;
    key.emplace_back(-(dx * dx + dy * dy), i);
  }
  std::sort(key.begin(), key.end());
  for (std::size_t k = 0; k < v.size(); ++k) v[k] = key[k].second;
}

/// The supports listed as the plain three-loop Welzl run on the farthest-first `set` lists
/// them (so the reported contacts keep their order whatever list order found them): with
/// positions in `set` a < b < c, a pair is (a, b) and a triple (b, c, a) — the last restart
/// of the middle loop, of the outer loop, then of the inner loop.
Support in_three_loop_order(Support s, const std::vector<std::size_t>& set) {
  const auto position = [&](std::size_t i) {
    return static_cast<std::size_t>(std::find(set.begin(), set.end(), i) - set.begin());
  };
  for (int k = 1; k < s.size; ++k)  // insertion sort of ≤ 3 by position
    for (int j = k; j > 0 && position(s.idx[j]) < position(s.idx[j - 1]); --j)
      std::swap(s.idx[j], s.idx[j - 1]);
  if (s.size == 3) s.idx = {s.idx[1], s.idx[2], s.idx[0]};
  return s;
}

/// The final contacts: 2 or 3 indices whose closed hull contains the exact centre.
/// `support` is Welzl's answer for the set `set` (its MC). Right triangle → hypotenuse;
/// obtuse triangle → choose among the points of `set` on the circle (decided exactly):
/// with a = any of them and x the one farthest from a (the nearest, in angle, to the
/// antipode of a, since chord length grows monotonically with the arc up to π), either
/// (a, x) is a diameter, or the ray from c* opposite a leaves conv(B) through an edge
/// (x, y) with y another point of B, and the closed triangle (a, x, y) contains c*. We test
/// every y with exact angle predicates (c* ∈ closed triangle ⇔ no angle is obtuse).
std::vector<std::size_t> choose_contacts(std::span<const Point2> points,
                                         const std::vector<std::size_t>& set,
                                         const Support& support, const ExactCircle& circle) {
  if (support.size == 2) return {support.idx[0], support.idx[1]};
  if (support.size == 1) return {support.idx[0]};
  const Point2 a = points[support.idx[0]], b = points[support.idx[1]],
               c = points[support.idx[2]];
  // Angle at each vertex: sign of the dot product (exact): +1 acute, 0 right, −1 obtuse.
  const std::array<int, 3> ang{internal::dot_sign(a, b, c), internal::dot_sign(b, a, c),
                               internal::dot_sign(c, a, b)};
  for (int k = 0; k < 3; ++k)
    if (ang[k] == 0) {
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      return {support.idx[i], support.idx[j]};
    }
  if (ang[0] > 0 && ang[1] > 0 && ang[2] > 0)
    return {support.idx[0], support.idx[1], support.idx[2]};
  // Obtuse: collect the co-circular points of the set (distinct by construction of set).
  std::vector<std::size_t> on;
  for (std::size_t i : set)
    if (internal::exact_side(circle, points[i]) == CGAL::ON_BOUNDARY) on.push_back(i);
  const std::size_t ia = on[0];
  const EPoint pa = to_epick(points[ia]);
  std::size_t ix = ia;
  for (std::size_t i : on)
    if (points[i] != points[ia] &&
        (ix == ia || CGAL::compare_distance_to_point(pa, to_epick(points[i]),
                                                     to_epick(points[ix])) == CGAL::LARGER))
      ix = i;
  const Point2 qa = points[ia], qx = points[ix];
  for (std::size_t iy : on) {
    const Point2 qy = points[iy];
    if (qy == qa || qy == qx) continue;  // S may hold duplicated points
    const int at_y = internal::dot_sign(qy, qa, qx);
    if (at_y == 0) return {ia, ix};  // a, x diametral (Thales)
    if (at_y > 0 && internal::dot_sign(qa, qy, qx) >= 0 && internal::dot_sign(qx, qa, qy) >= 0)
      return {ia, ix, iy};
  }
  throw std::logic_error(
      "minimum_circumscribed_circle: no contact pair/triple surrounds the centre "
      "(internal error: Welzl's circle is not the MC of its set)");
}

}  // namespace

MinimumCircumscribedCircle minimum_circumscribed_circle(std::span<const Point2> points) {
  validate_profile(points, 2, "minimum_circumscribed_circle", /*require_non_collinear=*/false);
  return internal::fit_minimum_circumscribed_circle(points);
}

MinimumCircumscribedCircle internal::fit_minimum_circumscribed_circle(
    std::span<const Point2> points, const SectorSample* shared) {
  const std::size_t n = points.size();

  // 1. Warm start and candidate set: the farthest point from c0 in each of `sectors`
  //    pseudo-angle sectors (64 for dense profiles: 5.6° each; fewer for small n so that
  //    sectors are not mostly empty), taken on a stride sample of ~512 points: the
  //    supports the sample misses are violators of the first round, found by the O(n)
  //    pass that has to run anyway (a full sector pass would cost a division per point).
  //    The sample is the caller's when it has taken it for MI too (internal::sector_sample).
  std::optional<internal::SectorSample> own;
  const internal::SectorSample& sample =
      shared ? *shared : own.emplace(internal::sector_sample(points));
  const Point2 c0 = sample.warm.center;
  std::vector<std::size_t> set;
  set.reserve(sample.farthest.size() + 256);
  for (const std::size_t i : sample.farthest)
    if (i < n) set.push_back(i);
  if (set.size() < 2) set.push_back(0);  // degenerate warm start; the loop repairs it

  // Per-thread scratch, kept between calls (no allocation per round or call); a first round
  // on a sparse sample flags a few hundred points.
  thread_local std::vector<std::size_t> violators, flagged, list;
  thread_local std::vector<std::pair<double, std::size_t>> violator_keys;
  std::vector<std::size_t> on_circle;
  on_circle.reserve(8);
  Support support;
  ExactCircle circle;
  std::size_t rounds = 0, exact_calls = 0;
  std::size_t nearest = 0;
  double nearest_d2 = 0.0;
  internal::RonqSums ronq;
  Point2 order_center = c0;
  std::size_t refinements = 0;  // local refinements (no O(n) pass)
  constexpr std::size_t kMaxRefinements = 1;
  while (true) {
    order_farthest_first(points, order_center, set);
    // After the first round the last round's supports go first: their circle is nearly the
    // answer, so most candidates are inside it when met and cost one predicate each.
    // (A stable partition of the set, written out: no temporary buffer.)
    const auto is_support = [&](std::size_t i) {
      for (int k = 0; k < support.size; ++k)
        if (support.idx[k] == i) return true;
      return false;
    };
    list.clear();
    if (rounds + refinements > 0) {
      for (std::size_t i : set)
        if (is_support(i)) list.push_back(i);
      for (std::size_t i : set)
        if (!is_support(i)) list.push_back(i);
    } else {
      list.assign(set.begin(), set.end());
    }
    support = in_three_loop_order(Welzl(points, list).run(), set);
    circle = exact_circle_of(points, support);
    // Local refinement (internal::local_extreme): a support with a farther neighbour along
    // the profile about this circle's centre is a few indices off a contact of the full
    // set; add those neighbours and re-solve before paying for the O(n) pass (once
    // at most; each adds a point, so S still grows).
    if (refinements < kMaxRefinements && circle.filter_usable) {
      bool grew = false;
      for (int k = 0; k < support.size; ++k) {
        const std::size_t j = internal::local_extreme<true>(
            points, support.idx[k], circle.center_d, circle.scale, n / 64, n / 8);
        if (j != support.idx[k] && std::find(set.begin(), set.end(), j) == set.end()) {
          set.push_back(j);
          grew = true;
        }
      }
      if (grew) {
        ++refinements;
        order_center = circle.center_d;
        continue;
      }
    }
    ++rounds;

    // 3. Classify every point; keep the nearest one (for RONt) and those exactly on the
    //    circle (every duplicate of a support lands in the filter's ambiguous band).
    violators.clear();
    on_circle.clear();
    flagged.clear();
    const Point2 cd = circle.center_d;
    const double lo = circle.filter_usable ? circle.inside_below
                                           : -std::numeric_limits<double>::infinity();
    ronq.radius = circle.radius;  // RONq's sums in the same pass (used for the last one)
    ronq.inv_scale = internal::ronq_inv_scale(points, cd, circle.radius);
    const internal::DistanceScan scan = internal::scan_distances<internal::Track::kNearest>(
        points, cd, circle.scale, lo, flagged, &ronq);
    nearest = scan.index;
    nearest_d2 = scan.d2;
    // Violators with a ranking key: how far outside (scaled squared units) — the double-
    // double gap where the second stage ran (points within ~1e-15 of the radius, where
    // plain squared distances cannot rank them), else the first stage's value.
    violator_keys.clear();
    const double r2s = circle.radius_scaled * circle.radius_scaled;
    for (std::size_t i : flagged) {
      const double d2 = internal::scaled_distance2(points[i], cd, circle.scale);
      if (circle.filter_usable && d2 > circle.outside_above) {
        violator_keys.push_back({d2 - r2s, i});
        continue;
      }
      ++exact_calls;
      double gap = d2 - r2s;
      const CGAL::Bounded_side side = internal::exact_side(circle, points[i], &gap);
      if (side == CGAL::ON_UNBOUNDED_SIDE) violator_keys.push_back({gap, i});
      if (side == CGAL::ON_BOUNDARY) on_circle.push_back(i);
    }
    if (violator_keys.empty()) break;
    // Many violators (a sparse first sample of a dense profile): keep the farthest one per
    // pseudo-angle sector about the current centre — S stays small, every direction that
    // has violators keeps its extreme one, and at least one violator is added (progress).
    violators.clear();
    if (violator_keys.size() > 64) {
      std::array<double, 64> far;
      far.fill(-std::numeric_limits<double>::infinity());
      std::array<std::size_t, 64> far_idx{};
      std::array<bool, 64> used{};
      for (const auto& [key, i] : violator_keys) {
        const double dx = points[i].x - cd.x, dy = points[i].y - cd.y;
        auto sct = static_cast<std::size_t>(internal::pseudo_angle(dx, dy) * 16.0);
        if (sct > 63) sct = 63;
        if (!used[sct] || key > far[sct]) {
          used[sct] = true;
          far[sct] = key;
          far_idx[sct] = i;
        }
      }
      for (std::size_t k = 0; k < 64; ++k)
        if (used[k]) violators.push_back(far_idx[k]);
    } else {
      for (const auto& [key, i] : violator_keys) violators.push_back(i);
    }
    set.insert(set.end(), violators.begin(), violators.end());
    order_center = cd;
  }

  // ≥ 4 exactly co-circular points on the circle: the supports among them depend on the
  // list order, so take those of the plain three-loop run on the farthest-first set (the
  // same circle: MC(set) is unique), whose choice the contacts have always reported.
  const auto is_support_point = [&](std::size_t i) {
    for (int k = 0; k < support.size; ++k)
      if (points[i] == points[support.idx[k]]) return true;
    return false;
  };
  if (!std::all_of(on_circle.begin(), on_circle.end(), is_support_point))
    support = Welzl(points, set, /*move_to_front=*/false).run();

  MinimumCircumscribedCircle mc;
  mc.center = circle.center_d;
  mc.radius = circle.radius;
  mc.contacts = choose_contacts(points, set, support, circle);
  for (std::size_t& c : mc.contacts)  // lowest index among duplicates (all on the circle)
    for (std::size_t i : on_circle)
      if (i < c && points[i] == points[c]) c = i;
  // 5. Roundness parameters: RONq from the shared evaluator; RONt without cancellation.
  // In the filter's scaled units: (R*² − ρ²)s² / ((R* + ρ)s), then back by s⁻¹ (exact).
  const double rho_s = std::sqrt(nearest_d2);
  const double gap_s = internal::exact_power_gap(circle, points[nearest]);  // ≥ 0 exactly
  const double ront = gap_s > 0.0 ? std::ldexp(gap_s / (circle.radius_scaled + rho_s),
                                               -circle.scale_exponent)
                                  : 0.0;
  // RONq (RONt bounds every deviation from the radius: it picks the distance series'
  // degree), from the sums of the last pass, about this circle.
  mc.ron.ronq = internal::ronq_of_valid(points, mc.center, mc.radius, ront, ronq);
  mc.ron.ront = ront;
  mc.ron.ronv = mc.ron.ront;
  mc.ron.ronp = 0.0;

  std::ostringstream arg;
  arg << "convex problem (unique optimum): exact centre in the closed hull of the "
      << mc.contacts.size() << " contacts (exact dot-product signs); all " << n
      << " points enclosed (floating filter with rigorous bound, " << exact_calls
      << " exact in-circle predicates) after " << rounds << " round(s) on "
      << set.size() << " candidates";
  if (refinements > 0) arg << " (" << refinements << " local refinement(s) of the supports)";
  mc.certificate.optimality = Optimality::global;
  mc.certificate.argument = arg.str();
  mc.certificate.region_radius = 0.0;
  return mc;
}

}  // namespace vcmm::geometry
