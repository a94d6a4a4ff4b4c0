// minimum_zone.cpp — the minimum-zone (MZ) reference circles, ISO 12181-1 (MZCI):
// fast exchange path, exact certificate and global-optimality proof.
//
// ── Notation ──────────────────────────────────────────────────────────────────────────────
// Points p_1..p_n (the input doubles), centre c. Distances d_i(c) = |c − p_i|;
//   R(c) = max_i d_i(c),  r(c) = min_i d_i(c),  f(c) = R(c) − r(c)  (the zone width).
// MZ: minimise f over c ∈ ℝ². Unit directions u = (c − o)/|c − o| for outer contacts o
// (d = R), v = (c − i)/|c − i| for inner contacts i (d = r). A "quadruple" is two outer
// contacts o1, o2 and two inner contacts i1, i2; its centre c* is the intersection of the
// perpendicular bisectors of o1o2 and i1i2 (a rational function of the input doubles,
// computed exactly: internal/minimum_zone_exact.h), R*² = |c* − o1|², r*² = |c* − i1|²,
// w* = R* − r*.
//
// ── 1. Local optimality (certificate) ─────────────────────────────────────────────────────
// f is locally Lipschitz; its Clarke subdifferential satisfies
//   ∂f(c) ⊆ conv{u_j : j outer-active} − conv{v_k : k inner-active}.                   (1)
// On the circle of directions, 0 ∈ conv{u} − conv{v} holds iff an outer and an inner point
// share a direction from c (then f(c) = |o − i|) or two chords u_a u_b and v_a v_b cross,
// i.e. two outer and two inner directions alternate in angle. If u1, v1, u2, v2 are distinct
// and strictly alternate, then
//   f'(c*; d) = max_j u_j·d − min_k v_k·d > 0   for every d ≠ 0                      (2)
// (a line {x·d = t} separating the u's from the v's would leave an arc between v1 and v2
// inside {x·d ≥ t}, and the u on that arc in its interior: contradiction). Hence a quadruple
// whose exact annulus contains every point and whose contacts alternate strictly about c* is
// a strict local minimum of f. Both conditions are decided exactly here: containment by a
// floating filter with a rigorous error bound and exact rational comparison for the few
// ambiguous points (contacts, near-ties); alternation by orientation signs of p − c* (filter,
// then rationals). 3+1 / 1+3 contact sets are never strict local optima (a direction d with
// f'(c; d) < 0 exists), so the certificate needs exactly 2+2.
//
// ── 2. Fast path (finding the quadruple) ──────────────────────────────────────────────────
// Warm start c0 = the algebraic (Kåsa) centre of a strided subsample of ≤ 1024 points (raw
// sums about the first point, so far-from-origin data keep their µm form). Linearise
//   d_i(c0 + δ) = ρ_i + e_i·δ + O(|δ|²/2ρ_i),  ρ_i = d_i(c0), e_i = (c0 − p_i)/ρ_i,   (3)
// and solve the Chebyshev LP  min R − r  s.t.  r ≤ ρ_i + e_i·δ ≤ R  over (δ, R, r), as its
// dual — max Σλ_iρ_i − Σμ_iρ_i s.t. Σλ_i e_i = Σμ_i e_i, Σλ = Σμ = 1, λ, μ ≥ 0 — by a
// revised simplex with a 4×4 basis (4 equality rows), started from the feasible degenerate
// basis {outer i, inner i, outer j, outer k} (λ_i = μ_i = 1: objective 0; Bland's rule after
// runs of degenerate pivots). Its optimal basis is the active 2+2 set, its multipliers give
// (δ, R, r). Costs are shifted by a constant (Σλ = Σμ = 1 leaves the objective unchanged)
// so the LP works on µm-size numbers. Constraint generation: the columns start as the
// farthest and nearest point of each of 32 index blocks (≈ angular sectors for scanned
// data); the LP optimum on them is certified exactly at once — the certification's
// containment pass checks every point anyway — and only when that fails does a pricing
// pass (squared distances at c0 + δ, no square root) add each block's worst violator.
// The linearisation error |δ|²/2ρ can misorder points whose radii differ by less than it,
// so we re-linearise at c0 + δ while it exceeds 1e-3 of the zone width (steps are capped
// at ρ_min/4: a trust region for partial arcs and sparse data). When the model has settled
// and certification still fails (near-ties, e.g. symmetric lobed data), the few points
// within a small tolerance of the extreme radii are enumerated exactly (section 4).
// Before the first certification, each contact of the model's 2+2 is replaced, as a
// candidate, by its farthest (outer) or nearest (inner) neighbour along the profile about
// the model's centre (internal::local_extreme, as the MC and MI fitters do) and the model
// solved once more: on filtered scans the seeds miss contacts a few indices off, which
// were the violators of the first pass (issue 11: then a pricing pass and a second
// containment pass followed).
// Typical measured rings: one LP of ~5 pivots, one certification pass; 6% need a second.
// Thin zones (issue 11: perfect circles, ulp-level forms — the zone narrower than 2¹²u·ρ,
// ≈ 4e-11 mm at ρ = 85 mm, or the plain LP settling on an uncertified optimum): plain costs
// ρ_i − s and squared distances carry ~u·ρ of rounding, as much as the zone itself, so the
// LP switches to costs (ρ_i² − s²)/(ρ_i + s) and pricing powers |p − c0 − δ|² − s² with the
// squares in double-double (internal/precise_distance.h) and a tolerance relative to the
// costs; the containment pass places what its first filter cannot with the double-double
// annulus (rigorous bound ~1e-30 of R²), so rational arithmetic is left to exact ties.
// Exact ties (whole symmetric orbits on R* and r*): an annulus that holds every point but
// whose quadruple does not alternate is certified through an alternating 2+2 among all its
// contacts at the same centre (alternating_among_ties).
//
// ── 3. Global optimality: the sharpness argument ──────────────────────────────────────
// With any origin, g_i(c) = |c − p_i|² − |c|² is affine in c, so
//   h(c) = max_i g_i − min_i g_i = R(c)² − r(c)²
// is convex piecewise linear, and f = h/(R + r); h* = h(c*) = w*(R* + r*). For c = c* + δ,
// s = |δ|, and any outer contact o_j and inner contact i_k of the quadruple (|δ|² cancels):
//   h(c) ≥ |c − o_j|² − |c − i_k|² = h* + 2δ·(i_k − o_j).                                 (4)
// If f(c) ≤ w*, then, R and r being 1-Lipschitz,
//   h(c) = f(c)(R(c) + r(c)) ≤ w*(R* + r* + 2s) = h* + 2w*s.                              (5)
// Hence s·(max_{j,k} d·(i_k − o_j) − w*) ≤ 0 with d = δ/s. The max is the support function
// of the parallelogram P = conv{i_k − o_j} = [i1, i2] − [o1, o2]; its minimum over unit d is
// the distance from 0 to the nearest edge line of P when 0 is interior to P. The edges of P
// are translates of the segments o1o2 and i1i2, so:
//   if the segments o1o2 and i1i2 cross properly and each contact lies farther than w*
//   from the line through the other pair, then s = 0: c* is the UNIQUE global minimiser —
//   no other centre is even as good.                                                       (6)
// Both parts are decided exactly (orientation predicates; squared distances against w*²
// by exact comparison of square-root differences, behind a floating filter). Near-round
// profiles pass with a huge margin: the point-line distances are ~R, w* ~ 1e-3 mm.
// This is the lead's region argument made sharp: writing the support function through unit
// directions, max_{j,k} d·(i_k − o_j) ≥ R*γ − w* with γ = min_{|d|=1}[max_j u_j·d −
// min_k v_k·d]; the draft bounded R(c) + r(c) ≤ 2R* + 2|d| (losing w*(R* − r*)) and so left
// a ball of radius w*²/(2(R*γ − 2w*)) around c* to exhaust; (5) closes it to the point c*
// whenever R*γ > 2w*, and (6) holds even more often. The same criterion is re-derived
// independently in certificate.cpp (derivation (4)). region_radius is then 0: no centre
// can beat (or tie) the result.
//
// ── 4. Sparse data: exhaustive exact search, and the near-tie repair ───────────────────
// Lemma: every local minimiser c of f is the bisector intersection of some quadruple of
// points active at c (two at R(c), two at r(c), non-parallel bisectors), whose annulus
// therefore holds all points. Proof: by (1), Clarke stationarity gives either (A) a strictly
// alternating 2+2 among the active directions — its bisectors are not parallel, since
// alternating directions make crossing chords u_a u_b, v_a v_b and o_b − o_a = R(u_a − u_b)
// — or (B) only shared directions (u0 = v0, no crossing chords). In case (B), if two
// active outer and two active inner points with non-parallel bisectors exist, they form
// the quadruple. Otherwise the non-shared outer directions lie on one arc next to u0 and
// the inner ones on the other arc, so a line through u0 (and not tangent there) separates
// them: along its normal d, f'(c; d) = 0 with only the shared pair first-order active
// (with a second shared pair w, d is forced to the bisector of u0 and w, symmetric to
// both), and the second-order term (1/R − 1/r)|d⊥|²/2 < 0 makes f decrease: c is not a
// local minimiser. (A data point is never one either: f(p + d) ≤ f(p) + max_j u_j·d − |d|.)
// Consequences for n ≤ kSmallN: enumerating all quadruples, the narrowest one whose
// annulus holds all points is the global minimum if it alternates strictly (certified) and
// if a minimiser exists at all; existence holds when its width is below the minimum strip
// width w_strip = min_{a≠b} [max − min of the signed distances to line ab], because f(c)
// tends to the width of the projection onto ĉ as |c| → ∞ along ĉ, so {f ≤ w*} is bounded.
// When every such zone is wider than w_strip, no minimiser exists (UndefinedResult, exact
// up to the 1e-12 relative margin kept around w_strip). A narrowest containing quadruple
// that does not alternate strictly (measure-zero ties) leaves the question open.
// The same enumeration, restricted to the few points within a small tolerance of the
// extreme radii, repairs the fast path when the linear model's active set cannot be
// certified (near-ties, e.g. symmetric lobed data): the narrowest certified quadruple among
// them is kept. Candidates are screened with rigorous interval arithmetic first.
//
// ── 5. Nearly straight data ───────────────────────────────────────────────────────────────
// inf f ≤ w_strip always (the limit at infinity), and the infimum may be approached only as
// the radius grows without bound. Sparse data (≤ kSmallN distinct points) are decided
// exactly by section 4. For larger data the fast path uses two rules, both modelling
// choices of the exchange method: (a) when its centre moves beyond kMaxRadiusFactor = 1e6
// data extents L, the circle deviates from its chord over the data by less than
// L²/(8·10⁶L) = 1.25e-7·L: straight to that resolution; (b) when the best certified circle
// is no narrower than the circle 10⁶ L away across the data's principal axis, it is not
// the global minimum and the zone is (as far as this method can tell) approached by ever
// larger circles. The exchange method then throws UndefinedResult; the automatic method
// hands the decision to the exact overlay, which throws UndefinedResult when the infimum is
// not attained.
//
// Complexity, measured rings: input validation, one seeding pass (squared distances), one
// certification pass (squared distances, RONq by a series), O(1) work on ≤ 1024 points for
// the warm start and ~64 LP columns, GMP integer arithmetic (no gcd) for one quadruple;
// about 6% of rings need one pricing pass and a second certification. O(n) overall;
// sparse data O(k⁴·n) for k ≤ 12 distinct points.
#include "vcmm/geometry/minimum_zone.h"

#include <CGAL/Interval_nt.h>
#include <Eigen/Core>
#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "internal/distance_scan.h"
#include "internal/exact.h"
#include "internal/isa.h"
#include "internal/extremal_circle.h"
#include "internal/minimum_zone_common.h"
#include "internal/minimum_zone_exact.h"
#include "internal/minimum_zone_overlay.h"
#include "internal/precise_distance.h"
#include "internal/prevalidated.h"
#include "internal/vec.h"

namespace vcmm::geometry {
namespace {

using internal::ExactAnnulus;
using internal::Rational;
using internal::RationalPoint;

constexpr const char* kCaller = "minimum_zone_circle";
/// Unit roundoff of double.
constexpr double kU = 0x1.0p-53;
/// Section 5: beyond this many data extents the data are treated as straight.
constexpr double kMaxRadiusFactor = 1e6;
/// Linearisations of (3) before giving up (typically 1-2 are used; wild partial arcs more).
constexpr int kMaxLinearisations = 40;
/// Re-linearise while |δ|²/2ρ exceeds this fraction of the zone width: the linear model may
/// then misorder points whose radii differ by less than that.
constexpr double kLinearisationTolerance = 1e-3;
/// Sparse data up to this size get the all-points exhaustion of section 4.
constexpr std::size_t kSmallN = 12;
/// Index blocks for the LP's candidate columns (farthest and nearest point of each): 32
/// leaves ~6% of measured rings needing a second pricing round (16: ~12%; 64: ~1%, but a
/// larger LP that costs more than it saves).
constexpr std::size_t kBlocks = 32;
/// Points used for the algebraic warm start (strided subsample).
constexpr std::size_t kStartSample = 1024;
/// Near-tie sets for the repair step: at most this many points per side.
constexpr std::size_t kMaxRepair = 6;
/// Pricing switches to double-double powers when the model's zone is narrower than this
/// many u·ρ: plain squared distances carry ~3u·ρ² of rounding (~1.5u·ρ in radius), so below
/// ~2¹²u·ρ (4e-11 mm at ρ = 85 mm) they no longer rank the extreme points reliably.
constexpr double kPrecisePricing = 4096.0;


struct Quad {
  std::array<std::size_t, 2> outer;
  std::array<std::size_t, 2> inner;
};

// ───────────────────────────── exact / rigorous helpers ────────────────────────────────

double sqrt_down(double x) { return x <= 0.0 ? 0.0 : std::sqrt(x) * (1.0 - 2.0 * kU); }
double sqrt_up(double x) { return x <= 0.0 ? 0.0 : std::sqrt(x) * (1.0 + 2.0 * kU); }

/// Sign of (√a − √b) − (√c − √d) for non-negative rationals, exactly (repeated squaring).
int compare_sqrt_differences(const Rational& a, const Rational& b, const Rational& c,
                             const Rational& d) {
  // sign((√a + √d) − (√b + √c)) = sign(k + 2m), k = a + d − b − c, m = √(ad) − √(bc).
  const Rational k = a + d - b - c;
  const Rational p = a * d, q = b * c;
  const int sk = CGAL::sign(k);
  const int sm = CGAL::sign(Rational(p - q));
  if (sm == 0) return sk;
  if (sk == 0 || sk == sm) return sm;
  // Opposite signs: compare 4(√p − √q)² with k², i.e. z = 4(p + q) − k² with 8√(pq).
  const Rational z = 4 * (p + q) - k * k;
  int s2m_vs_k;  // sign(|2m| − |k|)
  if (CGAL::sign(z) <= 0) {
    s2m_vs_k = (CGAL::sign(z) == 0 && CGAL::sign(Rational(p * q)) == 0) ? 0 : -1;
  } else {
    s2m_vs_k = CGAL::sign(Rational(z * z - 64 * p * q));
  }
  if (s2m_vs_k == 0) return 0;
  return s2m_vs_k > 0 ? sm : sk;
}

/// A quadruple with its annulus: correctly rounded doubles and rigorous bounds from the
/// integer computation (internal::rounded_annulus), and the rational form, built lazily
/// for the rare exact comparisons the floating filters cannot decide.
struct Candidate {
  Quad quad;
  std::span<const Point2> points;
  internal::RoundedAnnulus rounded;
  Point2 c;            ///< nearest double of c*
  double dc = 0.0;     ///< |ĉ − c*| ≤ dc (per coordinate)
  double R = 0.0, r = 0.0, w = 0.0;  ///< doubles of R*, r*, w*
  double R_lo = 0.0, R_hi = 0.0, r_lo = 0.0, r_hi = 0.0, w_lo = 0.0, w_hi = 0.0;

  /// The exact rational annulus (computed on first use).
  const ExactAnnulus& exact() const {
    if (!exact_) exact_ = internal::exact_annulus(points, quad.outer, quad.inner);
    return *exact_;
  }

  /// The annulus with double-double centre and radii² for the second-stage filter
  /// (computed on first use: only points the first stage cannot place need it).
  const internal::RoundedAnnulus& precise() const {
    if (!precise_) {
      precise_ = internal::rounded_annulus(points, quad.outer, quad.inner, true);
      if (!precise_) precise_ = internal::RoundedAnnulus{};  // unusable (cannot happen)
    }
    return *precise_;
  }

 private:
  mutable std::optional<ExactAnnulus> exact_;
  mutable std::optional<internal::RoundedAnnulus> precise_;
};

/// One ulp of v: a generous bound on the error of a nearest double (at most half an ulp).
double ulp_of(double v) {
  const double a = std::abs(v);
  return std::nextafter(a, std::numeric_limits<double>::infinity()) - a;
}

std::optional<Candidate> make_candidate(std::span<const Point2> points, const Quad& q) {
  std::optional<internal::RoundedAnnulus> a = internal::rounded_annulus(points, q.outer, q.inner);
  // An annulus needs r* < R* (equality: four co-circular contacts, zero width — decided by
  // the co-circularity test; r* > R*: the "inner" pair lies outside the "outer" circle).
  // One named result and one return (so the return is elided): moving a Candidate out of
  // this function would move its empty lazy caches, which GCC 12 -O2 with ASan reports as
  // maybe-uninitialized GMP reads.
  std::optional<Candidate> result;
  if (!a || !a->valid) return result;
  Candidate& k = result.emplace();
  k.quad = q;
  k.points = points;
  k.rounded = *a;
  k.c = a->center;
  k.dc = std::max(ulp_of(a->center.x), ulp_of(a->center.y));
  // Enclosures of R*², r*², R*² − r*² (nearest doubles: within half an ulp), then of the
  // roots and of w* = (R*² − r*²)/(R* + r*) (each operation adds ≤ 1 ulp; 4u covers it).
  const double R2_lo = a->outer_sq - ulp_of(a->outer_sq), R2_hi = a->outer_sq + ulp_of(a->outer_sq);
  const double r2_lo = a->inner_sq - ulp_of(a->inner_sq), r2_hi = a->inner_sq + ulp_of(a->inner_sq);
  const double w2_lo = a->diff_sq - ulp_of(a->diff_sq), w2_hi = a->diff_sq + ulp_of(a->diff_sq);
  k.R = std::sqrt(a->outer_sq);
  k.r = std::sqrt(a->inner_sq);
  k.R_lo = sqrt_down(R2_lo);
  k.R_hi = sqrt_up(R2_hi);
  k.r_lo = sqrt_down(r2_lo);
  k.r_hi = sqrt_up(r2_hi);
  k.w = (k.R + k.r) > 0.0 ? a->diff_sq / (k.R + k.r) : 0.0;
  k.w_lo = std::max(0.0, w2_lo / (k.R_hi + k.r_hi) * (1.0 - 4.0 * kU));
  k.w_hi = (k.R_lo + k.r_lo) > 0.0 ? w2_hi / (k.R_lo + k.r_lo) * (1.0 + 4.0 * kU)
                                   : std::numeric_limits<double>::infinity();
  return result;
}

/// p − c*, approximated in double, with a per-component error bound.
struct ApproxVector {
  double x, y, err;
};

ApproxVector approx_vector(const Candidate& k, Point2 p) {
  const double x = p.x - k.c.x, y = p.y - k.c.y;
  return {x, y, k.dc + 2.0 * kU * std::max(std::abs(x), std::abs(y))};
}

RationalPoint exact_vector(const Candidate& k, Point2 p) {
  return {Rational(p.x) - k.exact().center.x, Rational(p.y) - k.exact().center.y};
}

/// Exact sign of cross(p − c*, q − c*) (floating filter, rational fallback).
int cross_sign(const Candidate& k, Point2 p, Point2 q) {
  const ApproxVector a = approx_vector(k, p), b = approx_vector(k, q);
  const double value = a.x * b.y - a.y * b.x;
  const double bound = 1.25 * (a.err * (std::abs(b.x) + std::abs(b.y)) +
                               b.err * (std::abs(a.x) + std::abs(a.y)) + 2.0 * a.err * b.err +
                               3.0 * kU * (std::abs(a.x * b.y) + std::abs(a.y * b.x)));
  if (value > bound) return 1;
  if (value < -bound) return -1;
  const RationalPoint ea = exact_vector(k, p), eb = exact_vector(k, q);
  return CGAL::sign(Rational(ea.x * eb.y - ea.y * eb.x));
}

/// Exact sign of dot(p − c*, q − c*).
int dot_sign(const Candidate& k, Point2 p, Point2 q) {
  const ApproxVector a = approx_vector(k, p), b = approx_vector(k, q);
  const double value = a.x * b.x + a.y * b.y;
  const double bound = 1.25 * (a.err * (std::abs(b.x) + std::abs(b.y)) +
                               b.err * (std::abs(a.x) + std::abs(a.y)) + 2.0 * a.err * b.err +
                               3.0 * kU * (std::abs(a.x * b.x) + std::abs(a.y * b.y)));
  if (value > bound) return 1;
  if (value < -bound) return -1;
  const RationalPoint ea = exact_vector(k, p), eb = exact_vector(k, q);
  return CGAL::sign(Rational(ea.x * eb.x + ea.y * eb.y));
}

/// Strict alternation of the outer and inner contacts in angle about c* (section 1), exact.
/// Directions of o1, o2 split the circle into two open arcs; the inner directions must lie
/// one in each, none on a boundary direction.
bool is_strictly_alternating(std::span<const Point2> points, const Candidate& k) {
  Point2 o1 = points[k.quad.outer[0]], o2 = points[k.quad.outer[1]];
  const Point2 i1 = points[k.quad.inner[0]], i2 = points[k.quad.inner[1]];
  int s12 = cross_sign(k, o1, o2);
  if (s12 < 0) {
    std::swap(o1, o2);
    s12 = 1;
  }
  if (s12 == 0 && dot_sign(k, o1, o2) > 0) return false;  // same direction
  // arc(x): +1 in the open ccw arc o1 → o2, −1 in the other open arc, 0 on a boundary.
  auto arc = [&](Point2 x) -> int {
    const int a = cross_sign(k, o1, x);
    if (s12 == 0) return a;  // o1, o2 antipodal: half-planes
    const int b = cross_sign(k, x, o2);
    if (a > 0 && b > 0) return 1;
    if (a == 0 && dot_sign(k, o1, x) > 0) return 0;
    if (b == 0 && dot_sign(k, x, o2) > 0) return 0;
    return -1;
  };
  const int a1 = arc(i1), a2 = arc(i2);
  return a1 != 0 && a2 != 0 && a1 != a2;
}

// ───────────────────────────── containment pass ─────────────────────────────────────────

/// Exact place of p with respect to the closed annulus of `k`: +1 strictly outside R*,
/// −1 strictly inside r*, 0 in the closed annulus. The double-double filter
/// (internal/precise_distance.h) decides all but the exact ties (contacts, co-circular
/// points), which get the rational comparison.
int annulus_side(const Candidate& k, Point2 p) {
  const int s = internal::precise_annulus_side(k.precise().outer_precise,
                                               k.precise().inner_precise, p);
  if (s != 2) return s;
  const Rational d2 = internal::squared_distance(internal::to_rational(p), k.exact().center);
  if (d2 > k.exact().outer_sq) return 1;
  if (d2 < k.exact().inner_sq) return -1;
  return 0;
}

struct PassResult {
  bool contains = true;
  /// Points the floating filter could not place (ascending): the contacts, their duplicates
  /// and near-ties — every duplicate of a contact is among them.
  std::vector<std::size_t> ambiguous;
  double ronq = 0.0;
};

struct Certified {
  Candidate candidate;
  PassResult pass;
};

bool same_point_as_contact(std::span<const Point2> points, const Quad& q, Point2 p) {
  return p == points[q.outer[0]] || p == points[q.outer[1]] || p == points[q.inner[0]] ||
         p == points[q.inner[1]];
}

/// The per-point work of containment_pass (see there) over points [lo, hi), lo a multiple
/// of 4: squared distances s_i from (cx, cy); squared deviations from the mean circle rm
/// (series on a thin zone, else the direct formula) added into four partial sums, point i
/// into lane i mod 4 — the order of the Eigen reduction they replace (below); the points
/// the filter cannot place (s_i ∉ (t_in, t_out)) appended in increasing index, and
/// `surely_outside` set when one of them lies beyond t_out_hi or t_in_lo.
struct ContainmentMap {
  double cx, cy, rm, rm2, inv, t_out, t_in, t_out_hi, t_in_lo;
};
template <int W>
struct ContainmentLanes;  // internal/vec.h's vectors, points in order
template <>
struct ContainmentLanes<4> {
  using V = internal::VecOf<4>::type;
  using M = internal::VecOf<4>::mask;
  static constexpr M kX = {0, 2, 4, 6}, kY = {1, 3, 5, 7};
  static constexpr M kSwap2 = {2, 3, 0, 1}, kSwap1 = {1, 0, 3, 2};
};
template <>
struct ContainmentLanes<8> {
  using V = internal::VecOf<8>::type;
  using M = internal::VecOf<8>::mask;
  static constexpr M kX = {0, 2, 4, 6, 8, 10, 12, 14}, kY = {1, 3, 5, 7, 9, 11, 13, 15};
  static constexpr M kSwap2 = {2, 3, 0, 1, 6, 7, 4, 5}, kSwap1 = {1, 0, 3, 2, 5, 4, 7, 6};
};
using Sum4 = internal::VecOf<4>::type;

/// The deviation from rm of a point at squared distance sq (a double or a vector: the same
/// operations lane by lane, no FMA): the series on a thin zone, else the direct formula.
template <bool kThin, class T>
[[gnu::always_inline]] inline T deviation_of(const T& sq, double rm, double rm2, double inv) {
  if constexpr (kThin) {
    const T x = (sq - rm2) * inv;
    return rm * x * (1.0 + x * (-0.5 + x * (0.5 - 0.625 * x)));
  } else if constexpr (std::is_same_v<T, double>) {
    return (sq - rm2) / (std::sqrt(sq) + rm);
  } else {
    T dev;  // the vector square root is the scalar one, lane by lane (rare: wide zones)
    for (int k = 0; k < static_cast<int>(sizeof(T) / sizeof(double)); ++k)
      dev[k] = (sq[k] - rm2) / (std::sqrt(sq[k]) + rm);
    return dev;
  }
}

template <int W, bool kThin>
[[gnu::always_inline]] inline void containment_body(const ContainmentMap& m, const Point2* p,
                                                    std::size_t lo, std::size_t hi,
                                                    Sum4& sum, std::vector<std::size_t>& ambiguous,
                                                    bool& surely_outside) {
  using V = typename ContainmentLanes<W>::V;
  using M = typename ContainmentLanes<W>::M;
  const double* xy = reinterpret_cast<const double*>(p);
  const V cx = V{} + m.cx, cy = V{} + m.cy, t_out = V{} + m.t_out, t_in = V{} + m.t_in;
  const auto place = [&](std::size_t i, double sq) {
    if (sq < m.t_out && sq > m.t_in) return;
    if (sq > m.t_out_hi || sq < m.t_in_lo) surely_outside = true;
    ambiguous.push_back(i);
  };
  Sum4 acc = sum;  // in registers through the loop
  std::size_t i = lo;
  for (; i + W <= hi; i += W) {
    V a, b;
    __builtin_memcpy(&a, xy + 2 * i, sizeof a);
    __builtin_memcpy(&b, xy + 2 * i + W, sizeof b);
    const V dx = __builtin_shuffle(a, b, ContainmentLanes<W>::kX) - cx;
    const V dy = __builtin_shuffle(a, b, ContainmentLanes<W>::kY) - cy;
    const V sq = dx * dx + dy * dy;
    const V dev = deviation_of<kThin>(sq, m.rm, m.rm2, m.inv);
    const V dev2 = dev * dev;
    internal::add_in_point_order(acc, dev2);
    // Surely placed: t_in < s < t_out, i.e. max(s − t_out, t_in − s) < 0 (a difference of
    // doubles has the sign of the exact one; NaN compares false): one compare (two masks
    // combined are not vectorised for every target), the lanes AND-ed by shuffles.
    const V gap = sq - t_out, gap_in = t_in - sq;
    M placed = (gap > gap_in ? gap : gap_in) < 0.0;
    if constexpr (W == 8) placed &= __builtin_shuffle(placed, M{4, 5, 6, 7, 0, 1, 2, 3});
    placed &= __builtin_shuffle(placed, ContainmentLanes<W>::kSwap2);
    placed &= __builtin_shuffle(placed, ContainmentLanes<W>::kSwap1);
    if (placed[0] == 0) [[unlikely]] {
      for (int k = 0; k < W; ++k) place(i + k, sq[k]);
    }
  }
  // The last < W points of the profile (blocks are multiples of 4 long, but W may be 8).
  double rest[4] = {0.0, 0.0, 0.0, 0.0};
  for (; i < hi; ++i) {
    const double dx = p[i].x - m.cx, dy = p[i].y - m.cy;
    const double sq = dx * dx + dy * dy;
    const double dev = deviation_of<kThin>(sq, m.rm, m.rm2, m.inv);
    rest[i % 4] = dev * dev;
    if (i % 4 == 3 || i + 1 == hi) {
      acc += Sum4{rest[0], rest[1], rest[2], rest[3]};  // lanes not reached add +0: exact
      rest[0] = rest[1] = rest[2] = rest[3] = 0.0;
    }
    place(i, sq);
  }
  sum = acc;
}

template <int W>
[[gnu::always_inline]] inline void containment_dispatch(bool thin, const ContainmentMap& m,
                                                        const Point2* p, std::size_t lo,
                                                        std::size_t hi, Sum4& sum,
                                                        std::vector<std::size_t>& ambiguous,
                                                        bool& surely_outside) {
  if (thin) containment_body<W, true>(m, p, lo, hi, sum, ambiguous, surely_outside);
  else containment_body<W, false>(m, p, lo, hi, sum, ambiguous, surely_outside);
}
// Compiled for the baseline ISA, AVX2 and AVX-512, chosen per call (internal/isa.h): the
// same element-wise operations (no FMA: -ffp-contract=off; sqrt and division correctly
// rounded) and the same partial sums, so the same bits.
void containment_baseline(bool thin, const ContainmentMap& m, const Point2* p, std::size_t lo,
                          std::size_t hi, Sum4& sum, std::vector<std::size_t>& ambiguous,
                          bool& surely_outside) {
  containment_dispatch<4>(thin, m, p, lo, hi, sum, ambiguous, surely_outside);
}
#if VCMM_GEOMETRY_X86
__attribute__((target("avx2"))) void containment_avx2(bool thin, const ContainmentMap& m,
                                                      const Point2* p, std::size_t lo,
                                                      std::size_t hi, Sum4& sum,
                                                      std::vector<std::size_t>& ambiguous,
                                                      bool& surely_outside) {
  containment_dispatch<4>(thin, m, p, lo, hi, sum, ambiguous, surely_outside);
}
__attribute__((target("avx512f"))) void containment_avx512(
    bool thin, const ContainmentMap& m, const Point2* p, std::size_t lo, std::size_t hi,
    Sum4& sum, std::vector<std::size_t>& ambiguous, bool& surely_outside) {
  containment_dispatch<8>(thin, m, p, lo, hi, sum, ambiguous, surely_outside);
}
#endif
void containment_block(bool thin, const ContainmentMap& m, const Point2* p, std::size_t lo,
                       std::size_t hi, Sum4& sum, std::vector<std::size_t>& ambiguous,
                       bool& surely_outside) {
#if VCMM_GEOMETRY_X86
  if (internal::use_avx512())
    return containment_avx512(thin, m, p, lo, hi, sum, ambiguous, surely_outside);
  if (internal::use_avx2())
    return containment_avx2(thin, m, p, lo, hi, sum, ambiguous, surely_outside);
#endif
  containment_baseline(thin, m, p, lo, hi, sum, ambiguous, surely_outside);
}

/// One pass: exact containment of every point in the closed annulus of `k` — a floating
/// filter with rigorous thresholds (surely inside, surely outside), exact rational
/// comparison only for the ambiguous rest, stopping at the first violation — and RONq about
/// the mean circle. `stop_at_violation`: a point surely outside ends the pass early (ronq and
/// ambiguous then incomplete: for callers that only need the verdict).
PassResult containment_pass(std::span<const Point2> points, const Candidate& k,
                            bool stop_at_violation = false) {
  PassResult out;

  // |p − c*| ≤ √(s/(1 − 4u)) + dc with s the computed |p − ĉ|²; thresholds on s with every
  // rounding covered (factors 8u, 16u are generous).
  const double Rl = k.R_lo * (1.0 - 8.0 * kU) - k.dc;
  const double t_out = Rl > 0.0 ? Rl * Rl * (1.0 - 16.0 * kU) : 0.0;  // s < t_out: inside R*
  const double rh = k.r_hi * (1.0 + 8.0 * kU) + k.dc;
  const double t_in = rh * rh * (1.0 + 16.0 * kU);                    // s > t_in: outside r*
  const double Rh = k.R_hi * (1.0 + 8.0 * kU) + k.dc;
  const double t_out_hi = Rh * Rh * (1.0 + 16.0 * kU);                 // s > t_out_hi: outside R*
  const double rl = k.r_lo * (1.0 - 8.0 * kU) - k.dc;
  const double t_in_lo = rl > 0.0 ? rl * rl * (1.0 - 16.0 * kU) : -1.0;  // s < t_in_lo: inside r*
  // RONq about the mean circle rm: deviation e = √s − rm = rm(√(1 + 2x) − 1) with
  // x = (s − rm²)/(2rm²). For a thin zone (|x| ≤ 1e-4 for every contained point) the
  // series rm(x − x²/2 + x³/2 − 5x⁴/8) is used: truncation ≤ (7/8)x⁴ ≤ 1e-16 relative, no
  // square root or division per point; otherwise the direct formula.
  const double rm = 0.5 * (k.R + k.r), rm2 = rm * rm;
  const bool thin = std::max(std::abs(k.rounded.outer_sq - rm2),
                             std::abs(k.rounded.inner_sq - rm2)) <= 2e-4 * rm2;
  const double inv = 0.5 / rm2;
  // Blocks of kBlock points (a multiple of 4): one vectorised kernel per block maps every
  // point and keeps the few the filter cannot place; with `stop_at_violation` a point surely
  // outside ends the pass at its block (the caller only needs the verdict). The squared
  // deviations are summed as Eigen's vectorised reduction of the whole buffer summed them
  // (its 2-double packets, two of them: point i into partial sum i mod 4 up to the last
  // whole four; then (S₀ + S₂) and (S₁ + S₃), the next two points into them, their sum,
  // and a last odd point), so RONq keeps its bits.
  const std::size_t n = points.size();
  const ContainmentMap map{k.c.x, k.c.y, rm, rm2, inv, t_out, t_in, t_out_hi, t_in_lo};
  constexpr std::size_t kBlock = 512;
  const std::size_t whole = n - n % 4;
  bool surely_outside = false;
  Sum4 sum = {};
  for (std::size_t lo = 0; lo < whole; lo += kBlock) {
    containment_block(thin, map, points.data(), lo, std::min(lo + kBlock, whole), sum,
                      out.ambiguous, surely_outside);
    if (surely_outside && stop_at_violation) {
      out.contains = false;
      return out;
    }
  }
  double tail[3] = {0.0, 0.0, 0.0};  // the squared deviations of points whole … n − 1
  for (std::size_t i = whole; i < n; ++i) {
    Sum4 one = {};
    std::vector<std::size_t> flagged;
    containment_block(thin, map, points.data(), i, i + 1, one, flagged, surely_outside);
    tail[i - whole] = one[i % 4];
    out.ambiguous.insert(out.ambiguous.end(), flagged.begin(), flagged.end());
  }
  double s0 = sum[0] + sum[2], s1 = sum[1] + sum[3];
  if (n % 4 >= 2) {
    s0 += tail[0];
    s1 += tail[1];
  }
  double total = s0 + s1;
  if (n % 2 == 1) total += tail[n % 4 - 1];
  out.ronq = std::sqrt(total / static_cast<double>(n));
  if (surely_outside) {
    out.contains = false;
    return out;
  }
  for (std::size_t i : out.ambiguous) {
    if (same_point_as_contact(points, k.quad, points[i])) continue;  // on by construction
    if (annulus_side(k, points[i]) != 0) {
      out.contains = false;
      break;
    }
  }
  return out;
}

/// Quick exact test of a few points before a full pass.
bool contains_points(std::span<const Point2> points, const Candidate& k,
                     std::span<const std::size_t> which) {
  for (std::size_t i : which) {
    if (same_point_as_contact(points, k.quad, points[i])) continue;
    if (annulus_side(k, points[i]) != 0) return false;
  }
  return true;
}

// ───────────────────────────── exact ties: many contacts ───────────────────────────────

/// +1 when p lies exactly on the outer circle of k, −1 exactly on the inner one, 0 otherwise.
int boundary_of(const Candidate& k, Point2 p) {
  const internal::RoundedAnnulus& a = k.precise();
  const internal::PreciseValue o = internal::precise_power_gap(a.outer_precise, p);
  const bool maybe_outer = !a.outer_precise.usable || internal::sign_of(o) == 0;
  const internal::PreciseValue i = internal::precise_power_gap(a.inner_precise, p);
  const bool maybe_inner = !a.inner_precise.usable || internal::sign_of(i) == 0;
  if (!maybe_outer && !maybe_inner) return 0;
  const Rational d2 = internal::squared_distance(internal::to_rational(p), k.exact().center);
  if (maybe_outer && d2 == k.exact().outer_sq) return 1;
  if (maybe_inner && d2 == k.exact().inner_sq) return -1;
  return 0;
}

/// Section 4, exact ties (e.g. an 8-fold symmetric polygon: whole orbits exactly on R* or
/// r*): the annulus of k holds every point but its own quadruple does not alternate. At its
/// centre every tied point is a contact; if some outer and inner contacts alternate, any
/// 2+2 of them gives the same centre (alternation makes the bisectors cross) and certifies
/// it. Rule: contacts in counter-clockwise order from the direction of k's first outer
/// contact, grouped in runs of one kind (lowest index kept per run); the first four runs
/// alternate by construction. The exact alternation test of the new quadruple decides.
std::optional<Quad> alternating_among_ties(std::span<const Point2> points, const Candidate& k,
                                           const PassResult& pass) {
  struct Contact {
    std::size_t index;
    bool outer;
  };
  std::vector<Contact> contacts;
  auto add = [&](std::size_t i, bool outer) {
    for (const Contact& t : contacts)
      if (points[t.index] == points[i]) return;  // duplicates: the first (lowest) index
    contacts.push_back({i, outer});
  };
  for (std::size_t i : {k.quad.outer[0], k.quad.outer[1]}) add(i, true);
  for (std::size_t i : {k.quad.inner[0], k.quad.inner[1]}) add(i, false);
  for (std::size_t i : pass.ambiguous) {
    const int b = boundary_of(k, points[i]);
    if (b != 0) add(i, b > 0);
  }
  // Counter-clockwise from a = the first outer contact's direction: half-turn first.
  const Point2 a = points[k.quad.outer[0]];
  auto half = [&](Point2 x) {
    const int s = cross_sign(k, a, x);
    return (s > 0 || (s == 0 && dot_sign(k, a, x) > 0)) ? 0 : 1;
  };
  std::sort(contacts.begin(), contacts.end(), [&](const Contact& x, const Contact& y) {
    const Point2 px = points[x.index], py = points[y.index];
    const int hx = half(px), hy = half(py);
    if (hx != hy) return hx < hy;
    const int s = cross_sign(k, px, py);
    if (s != 0) return s > 0;
    return x.index < y.index;
  });
  std::vector<Contact> runs;  // first contact of each run of one kind
  for (const Contact& t : contacts)
    if (runs.empty() || runs.back().outer != t.outer) runs.push_back(t);
  if (runs.size() > 1 && runs.front().outer == runs.back().outer) runs.pop_back();  // cyclic
  if (runs.size() < 4) return std::nullopt;
  Quad q;
  q.outer = runs[0].outer ? std::array{runs[0].index, runs[2].index}
                          : std::array{runs[1].index, runs[3].index};
  q.inner = runs[0].outer ? std::array{runs[1].index, runs[3].index}
                          : std::array{runs[0].index, runs[2].index};
  return q;
}

// ───────────────────────────── sharpness argument (section 3) ───────────────────────────

struct Sharpness {
  bool proven = false;       ///< criterion (6) holds (exact)
  double min_distance = 0.0; ///< least contact-to-other-line distance (double, for the text)
};

/// Criterion (6), exact: the contact segments cross properly and every contact is farther
/// than w* from the line through the other pair.
Sharpness sharpness(std::span<const Point2> points, const Candidate& k) {
  Sharpness out;
  const Point2 o1 = points[k.quad.outer[0]], o2 = points[k.quad.outer[1]];
  const Point2 i1 = points[k.quad.inner[0]], i2 = points[k.quad.inner[1]];
  auto orient = [](Point2 a, Point2 b, Point2 c) {
    return static_cast<int>(
        CGAL::orientation(internal::to_epick(a), internal::to_epick(b), internal::to_epick(c)));
  };
  if (!(orient(o1, o2, i1) * orient(o1, o2, i2) < 0 &&
        orient(i1, i2, o1) * orient(i1, i2, o2) < 0))
    return out;
  const std::array<std::array<Point2, 3>, 4> tests{
      {{o1, o2, i1}, {o1, o2, i2}, {i1, i2, o1}, {i1, i2, o2}}};
  out.min_distance = std::numeric_limits<double>::infinity();
  for (const auto& [a, b, q] : tests) {
    const double ex = b.x - a.x, ey = b.y - a.y, qx = q.x - a.x, qy = q.y - a.y;
    const double cr = ex * qy - ey * qx;
    // Each difference is rounded (≤ u relative), then two products and a subtraction.
    const double err = 8.0 * kU * (std::abs(ex * qy) + std::abs(ey * qx));
    const double len = std::hypot(ex, ey);
    const double dist = std::abs(cr) / len;
    out.min_distance = std::min(out.min_distance, dist);
    const double dist_lo = (std::abs(cr) - err) / (len * (1.0 + 8.0 * kU));
    if (dist_lo > k.w_hi) continue;
    const RationalPoint e{Rational(b.x) - Rational(a.x), Rational(b.y) - Rational(a.y)};
    const RationalPoint w{Rational(q.x) - Rational(a.x), Rational(q.y) - Rational(a.y)};
    const Rational c = e.x * w.y - e.y * w.x;
    const Rational dist2 = c * c / (e.x * e.x + e.y * e.y);
    if (compare_sqrt_differences(dist2, Rational(0), k.exact().outer_sq, k.exact().inner_sq) <= 0)
      return out;
  }
  out.proven = true;
  return out;
}

/// Rigorous interval screen of a quadruple (CGAL::Interval_nt under upward rounding):
/// false when it certainly cannot give an annulus (r* < R*) holding the `probe` points that
/// is strictly narrower than `w_bound`. True means "decide exactly".
bool passes_screen(std::span<const Point2> points, const Quad& q,
                   std::span<const std::size_t> probe, double w_bound) {
  using I = CGAL::Interval_nt<false>;
  CGAL::Protect_FPU_rounding<true> guard;  // upward rounding, restored on exit
  const Point2 o1 = points[q.outer[0]];
  auto rel = [&](std::size_t idx) {
    return std::array<I, 2>{I(points[idx].x) - I(o1.x), I(points[idx].y) - I(o1.y)};
  };
  const auto b = rel(q.outer[1]), e = rel(q.inner[0]), d = rel(q.inner[1]);
  const I ax = d[0] - e[0], ay = d[1] - e[1];
  const I det = b[0] * ay - b[1] * ax;
  if (det.inf() <= 0.0 && det.sup() >= 0.0) return true;  // maybe parallel: exact test
  const I rhs1 = (b[0] * b[0] + b[1] * b[1]) / 2;
  const I rhs2 = ((d[0] + e[0]) * ax + (d[1] + e[1]) * ay) / 2;
  const I cx = (rhs1 * ay - b[1] * rhs2) / det, cy = (b[0] * rhs2 - rhs1 * ax) / det;
  const I R2 = cx * cx + cy * cy;
  const I r2 = CGAL::square(cx - e[0]) + CGAL::square(cy - e[1]);
  if (R2.sup() <= r2.inf()) return false;                                // no annulus
  if ((CGAL::sqrt(R2) - CGAL::sqrt(r2)).inf() >= w_bound) return false;  // not narrower
  for (std::size_t idx : probe) {
    const auto v = rel(idx);
    const I d2 = CGAL::square(v[0] - cx) + CGAL::square(v[1] - cy);
    if (d2.inf() > R2.sup() || d2.sup() < r2.inf()) return false;  // point outside
  }
  return true;
}

struct Search {
  std::optional<Certified> best;  ///< narrowest certified quadruple below the bound
  /// A quadruple narrower than `best` (or than the bound) holds all points but does not
  /// alternate: its centre beats the bound yet is not certified (the search is undecided).
  bool unresolved = false;
  std::size_t examined = 0;
};

/// Exhaustive exact search over O×O×I×I (sections 2 and 4): the narrowest quadruple whose
/// annulus holds every point, strictly narrower than `bound` (if given), with strictly
/// alternating contacts. `probe` points are tried first (rigorous interval screen, then
/// exact); survivors get the full exact containment pass.
Search narrowest_certified(std::span<const Point2> points, std::span<const std::size_t> O,
                           std::span<const std::size_t> I, const Candidate* bound,
                           std::span<const std::size_t> probe) {
  Search out;
  std::optional<Candidate> unresolved;  // narrowest non-alternating containing quadruple
  auto threshold = [&]() -> const Candidate* {
    return out.best ? &out.best->candidate : bound;
  };
  for (std::size_t a = 0; a < O.size(); ++a) {
    for (std::size_t b = a + 1; b < O.size(); ++b) {
      if (points[O[a]] == points[O[b]]) continue;
      for (std::size_t c = 0; c < I.size(); ++c) {
        for (std::size_t d = c + 1; d < I.size(); ++d) {
          if (points[I[c]] == points[I[d]]) continue;
          // A point cannot be both outer and inner at a centre with positive width.
          if (points[O[a]] == points[I[c]] || points[O[a]] == points[I[d]] ||
              points[O[b]] == points[I[c]] || points[O[b]] == points[I[d]])
            continue;
          const Quad q{{O[a], O[b]}, {I[c], I[d]}};
          ++out.examined;
          const Candidate* t = threshold();
          const double w_bound = t ? t->w_hi : std::numeric_limits<double>::infinity();
          if (!passes_screen(points, q, probe, w_bound)) continue;
          std::optional<Candidate> k = make_candidate(points, q);
          if (!k) continue;
          if (t && compare_sqrt_differences(k->exact().outer_sq, k->exact().inner_sq,
                                            t->exact().outer_sq, t->exact().inner_sq) >= 0)
            continue;
          if (!contains_points(points, *k, probe)) continue;
          PassResult pass = containment_pass(points, *k);
          if (!pass.contains) continue;
          if (is_strictly_alternating(points, *k)) {
            out.best = Certified{std::move(*k), std::move(pass)};
          } else if (!unresolved ||
                     compare_sqrt_differences(k->exact().outer_sq, k->exact().inner_sq,
                                              unresolved->exact().outer_sq,
                                              unresolved->exact().inner_sq) < 0) {
            unresolved = std::move(*k);
          }
        }
      }
    }
  }
  if (unresolved) {
    const Candidate* t = threshold();
    out.unresolved = !t || compare_sqrt_differences(unresolved->exact().outer_sq,
                                                    unresolved->exact().inner_sq,
                                                    t->exact().outer_sq, t->exact().inner_sq) < 0;
  }
  return out;
}

/// Minimum strip width of the points (O(n³): sparse data only), rounded to nearest; its
/// relative error is far below the 1e-12 margins the callers keep.
double strip_width(std::span<const Point2> points) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t a = 0; a < points.size(); ++a) {
    for (std::size_t b = a + 1; b < points.size(); ++b) {
      const double ex = points[b].x - points[a].x, ey = points[b].y - points[a].y;
      const double len = std::hypot(ex, ey);
      if (len == 0.0) continue;
      // Width of the points across the line ab: max − min of the signed distances (equal
      // to the strip width in that direction; hull edges attain the minimum strip).
      double hi = 0.0, lo = 0.0;
      for (const Point2& p : points) {
        const double px = p.x - points[a].x, py = p.y - points[a].y;
        const double cr = ex * py - ey * px;
        hi = std::max(hi, cr);
        lo = std::min(lo, cr);
      }
      best = std::min(best, (hi - lo) / len);
    }
  }
  return best;
}

// ───────────────────────────── co-circular input ────────────────────────────────────────

/// Three points defining a circle through every point (exact in-circle tests), if any.
std::optional<std::array<std::size_t, 3>> cocircular_triple(std::span<const Point2> points) {
  using internal::EPoint;
  const std::size_t n = points.size();
  std::size_t j = 1;
  while (j < n && points[j] == points[0]) ++j;
  if (j == n) return std::nullopt;
  const EPoint a = internal::to_epick(points[0]), b = internal::to_epick(points[j]);
  std::size_t k = j + 1;
  while (k < n && CGAL::orientation(a, b, internal::to_epick(points[k])) == CGAL::COLLINEAR)
    ++k;
  if (k == n) return std::nullopt;
  const EPoint c = internal::to_epick(points[k]);
  // Almost always the first other point decides (CGAL's static filter); once one lies on
  // the circle, the rest are tested against the circle's own exact representation
  // (double-double filter, then its integers: ~5× cheaper than a full in-circle predicate
  // on exact ties, which is what every point of co-circular data is).
  std::optional<internal::ExactCircle> circle;
  for (std::size_t i = 1; i < n; ++i) {
    if (i == j || i == k) continue;
    if (!circle) {
      if (CGAL::side_of_oriented_circle(a, b, c, internal::to_epick(points[i])) !=
          CGAL::ON_ORIENTED_BOUNDARY)
        return std::nullopt;
      circle = internal::exact_circumcircle(points[0], points[j], points[k]);
      continue;
    }
    if (internal::exact_side(*circle, points[i]) != CGAL::ON_BOUNDARY) return std::nullopt;
  }
  return std::array<std::size_t, 3>{0, j, k};
}

// ───────────────────────────── linearised Chebyshev LP (section 2) ──────────────────────

struct Column {
  std::size_t point = 0;
  bool outer = true;
  friend bool operator==(const Column&, const Column&) = default;
};

enum class LpStatus { optimal, failed };

/// The LP of (3) in dual form on a growing set of candidate columns. Columns hold the
/// linearisation at c0 of their point: ρ − shift and e. `solve` optimises over the
/// candidates; the driver first tries to certify that optimum exactly (its containment pass
/// checks every point anyway) and only on failure prices all points (`full_pricing`, squared
/// distances at c0 + δ, no square root). A point already among the candidates is not
/// re-added, so the difference between the model and the true distances (≤ |δ|²/2ρ) cannot
/// make the loop cycle — it is removed by re-linearising.
class ChebyshevLp {
 public:
  explicit ChebyshevLp(std::span<const Point2> points)
      : points_(points), in_candidates_(points.size(), 0) {
    entries_.reserve(256);  // seeds, refinements and a few pricing rounds: one allocation
  }

  /// Adds the largest and smallest distance from c per index block (contiguous blocks ≈
  /// angular sectors for scanned data): the initial candidates.
  void seed_candidates(Point2 c) {
    c0_ = c;
    shift_ = 0.0;
    const std::size_t n = points_.size(), blocks = block_count();
    for (std::size_t b = 0; b < blocks; ++b) {
      const internal::DistanceExtremes e =
          internal::distance_extremes(points_, b * n / blocks, (b + 1) * n / blocks, c);
      add_candidate({e.imax, true});
      add_candidate({e.imin, false});
    }
  }

  /// Linearises every candidate column at c0 (original coordinates) and solves, warm-started
  /// from the previous basis when it is still feasible.
  LpStatus solve(Point2 c0) {
    c0_ = c0;
    rho_min_ = std::numeric_limits<double>::infinity();
    rho_max_ = 0.0;
    for (Entry& e : entries_) {
      const double dx = c0.x - points_[e.column.point].x, dy = c0.y - points_[e.column.point].y;
      e.rho = std::sqrt(dx * dx + dy * dy);
      e.ex = e.rho > 0.0 ? dx / e.rho : 0.0;
      e.ey = e.rho > 0.0 ? dy / e.rho : 0.0;
      rho_min_ = std::min(rho_min_, e.rho);
      rho_max_ = std::max(rho_max_, e.rho);
    }
    shift_ = 0.5 * (rho_min_ + rho_max_);
    cost_scale_ = 0.0;
    for (Entry& e : entries_) {
      e.rho = shifted_cost(e.column.point, e.rho);
      cost_scale_ = std::max(cost_scale_, std::abs(e.rho));
    }
    if (!(have_basis_ && set_basis(basis_))) {
      if (!degenerate_start()) return LpStatus::failed;
    }
    int degenerate_run = 0;
    for (int pivots = 0; pivots < 1000; ++pivots) {
      const int step = pivot(degenerate_run > 8);
      if (step < 0) return LpStatus::failed;
      if (step == 0) break;  // optimal on the candidates
      degenerate_run = (step == 2) ? degenerate_run + 1 : 0;
      if (pivots == 999) return LpStatus::failed;
    }
    // Thin zones: plain costs and squared distances (rounded to ~1.5u·ρ) cannot rank the
    // points any more; costs and pricing switch to double-double (internal/
    // precise_distance.h) for good, from the next solve on.
    precise_ = precise_ || width() < kPrecisePricing * kU * rho_max_;
    return LpStatus::optimal;
  }

  /// Adds each block's farthest / nearest point at c0 + δ when it lies outside the model's
  /// annulus (by more than the tolerance); returns how many columns were added. One pass
  /// over all points: squared distances only (double-double powers on thin zones).
  int full_pricing() {
    const Point2 c{c0_.x - y_[0], c0_.y - y_[1]};
    const double tol = tolerance();
    const std::size_t n = points_.size(), blocks = block_count();
    int added = 0;
    if (precise_) {
      // Powers |p − c|² − s² against the model's (R² − s², r² − s²), s = shift: with
      // R = s + y₂ + tol, R² − s² = (y₂ + tol)(y₂ + tol + 2s), likewise for r. The centre
      // c0 + δ is not rounded (a rounding of ~1e-13 mm would be the zone's own size):
      // |p − c0 − δ|² = |p − c0|² + 2(c0 − p)·δ + |δ|² exactly, the first term in
      // double-double, the others (≪ the first) in double.
      const double ro = y_[2] + tol, ri = -y_[3] - tol;
      const double g_out = ro * (ro + 2.0 * shift_), g_in = ri * (ri + 2.0 * shift_);
      const double dx = -y_[0], dy = -y_[1], d2 = dx * dx + dy * dy;
      for (std::size_t b = 0; b < blocks; ++b) {
        std::size_t imax = b * n / blocks, imin = imax;
        double gmax = -std::numeric_limits<double>::infinity(), gmin = -gmax;
        for (std::size_t i = b * n / blocks; i < (b + 1) * n / blocks; ++i) {
          const Point2 p = points_[i];
          const double g = internal::precise_power(p, c0_, shift_) +
                           2.0 * ((c0_.x - p.x) * dx + (c0_.y - p.y) * dy) + d2;
          if (g > gmax) {
            gmax = g;
            imax = i;
          }
          if (g < gmin) {
            gmin = g;
            imin = i;
          }
        }
        if (gmax > g_out && add_candidate({imax, true})) ++added;
        if (gmin < g_in && add_candidate({imin, false})) ++added;
      }
      return added;
    }
    const double R = y_[2] + shift_ + tol, r = std::max(0.0, -y_[3] + shift_ - tol);
    const double R2 = R * R, r2 = r * r;
    for (std::size_t b = 0; b < blocks; ++b) {
      const internal::DistanceExtremes e =
          internal::distance_extremes(points_, b * n / blocks, (b + 1) * n / blocks, c);
      if (e.smax > R2 && add_candidate({e.imax, true})) ++added;
      if (e.smin < r2 && add_candidate({e.imin, false})) ++added;
    }
    return added;
  }

  /// Switches costs and pricing to double-double (from the next solve on); false when they
  /// already are.
  bool escalate_precision() {
    if (precise_) return false;
    precise_ = true;
    return true;
  }

  /// Adds the point as a column of the given kind (linearised at the current c0); false if
  /// it is one already.
  bool add_point(std::size_t point, bool outer) { return add_candidate({point, outer}); }
  /// Whether costs and pricing are double-double (a thin zone).
  bool precise() const { return precise_; }

  /// True once, when the zone has just been found thin (pricing became precise).
  bool first_precise_round() {
    const bool first = precise_ && !precise_announced_;
    precise_announced_ = precise_announced_ || precise_;
    return first;
  }

  Point2 delta() const { return {-y_[0], -y_[1]}; }
  double width() const { return y_[2] + y_[3]; }
  double rho_min() const { return rho_min_; }
  std::array<Column, 4> basis() const {
    std::array<Column, 4> out;
    for (std::size_t j = 0; j < 4; ++j) out[j] = entries_[basis_[j]].column;
    return out;
  }

 private:
  struct Entry {
    Column column;
    double rho = 0.0, ex = 0.0, ey = 0.0;
  };

  std::size_t block_count() const { return std::min<std::size_t>(kBlocks, points_.size()); }

  Eigen::Vector4d column(const Entry& e) const {
    return e.column.outer ? Eigen::Vector4d(e.ex, e.ey, 1.0, 0.0)
                          : Eigen::Vector4d(-e.ex, -e.ey, 0.0, 1.0);
  }
  static double cost(const Entry& e) { return e.column.outer ? e.rho : -e.rho; }
  double reduced_cost(const Entry& e) const {
    const double t = e.rho - e.ex * y_[0] - e.ey * y_[1];
    return e.column.outer ? t - y_[2] : -t - y_[3];
  }

  /// Adds a column (linearised at the current c0); false if it is already there.
  bool add_candidate(Column c) {
    const std::uint8_t bit = c.outer ? 1 : 2;
    if (in_candidates_[c.point] & bit) return false;
    in_candidates_[c.point] = static_cast<std::uint8_t>(in_candidates_[c.point] | bit);
    Entry e;
    e.column = c;
    const double dx = c0_.x - points_[c.point].x, dy = c0_.y - points_[c.point].y;
    const double rho = std::sqrt(dx * dx + dy * dy);
    e.ex = rho > 0.0 ? dx / rho : 0.0;
    e.ey = rho > 0.0 ? dy / rho : 0.0;
    e.rho = shifted_cost(c.point, rho);
    cost_scale_ = std::max(cost_scale_, std::abs(e.rho));
    entries_.push_back(e);
    return true;
  }

  /// ρ − s for the point at distance ρ from c0, s = shift. Thin zones: (ρ² − s²)/(ρ + s)
  /// with the numerator in double-double, so the costs keep their ~1e-16 relative
  /// differences (a plain ρ − s rounds them away on perfect circles and ulp-level forms);
  /// otherwise the plain difference, whose ~u·ρ error is far below the zone.
  double shifted_cost(std::size_t point, double rho) const {
    if (!precise_) return rho - shift_;
    const double den = rho + shift_;
    return den > 0.0 ? internal::precise_power(points_[point], c0_, shift_) / den : 0.0;
  }

  /// Ties below the costs' resolution are left to the exact stage. Plain costs carry ~u·ρ:
  /// 64u·ρ_max. Precise costs: reduced costs are sums of a cost (≤ cost_scale_) and products
  /// of unit directions with y, each rounded: 64u of their magnitudes, plus the costs' own
  /// error (a few u² of ρ).
  double tolerance() const {
    if (!precise_) return 64.0 * kU * std::max(1.0, rho_max_);
    return 64.0 * kU * (cost_scale_ + y_.cwiseAbs().sum()) + 1024.0 * kU * kU * rho_max_;
  }

  /// Factorises the basis; false if singular or infeasible.
  bool set_basis(const std::array<std::size_t, 4>& b) {
    Eigen::Matrix4d B;
    for (int j = 0; j < 4; ++j) B.col(j) = column(entries_[b[static_cast<std::size_t>(j)]]);
    Eigen::FullPivLU<Eigen::Matrix4d> lu(B);
    if (!lu.isInvertible() || std::abs(lu.determinant()) < 1e-14) return false;
    const Eigen::Matrix4d inv = lu.inverse();
    const Eigen::Vector4d xb = inv * Eigen::Vector4d(0.0, 0.0, 1.0, 1.0);
    if (xb.minCoeff() < -1e-9) return false;
    basis_ = b;
    have_basis_ = true;
    binv_ = inv;
    xb_ = xb.cwiseMax(0.0);
    Eigen::Vector4d cb;
    for (int j = 0; j < 4; ++j) cb[j] = cost(entries_[b[static_cast<std::size_t>(j)]]);
    y_ = binv_.transpose() * cb;
    return true;
  }

  /// Basis {outer i, inner i, outer j, outer k}: λ_i = μ_i = 1 is feasible (objective 0);
  /// i the farthest candidate point, j the direction farthest from e_i, k the one spanning
  /// the largest triangle e_i e_j e_k with them (a well-conditioned basis, O(m)).
  bool degenerate_start() {
    std::size_t i = 0;
    for (std::size_t c = 1; c < entries_.size(); ++c)
      if (entries_[c].rho > entries_[i].rho) i = c;
    const Entry ei = entries_[i];
    std::size_t bj = i, bk = i;
    double best = 0.0;
    for (std::size_t a = 0; a < entries_.size(); ++a) {
      const Entry& ej = entries_[a];
      const double d2 = (ej.ex - ei.ex) * (ej.ex - ei.ex) + (ej.ey - ei.ey) * (ej.ey - ei.ey);
      if (ej.column.point != ei.column.point && d2 > best) {
        best = d2;
        bj = a;
      }
    }
    if (bj == i) return false;
    const Entry ej = entries_[bj];
    best = 0.0;
    for (std::size_t b = 0; b < entries_.size(); ++b) {
      const Entry& ek = entries_[b];
      if (ek.column.point == ei.column.point || ek.column.point == ej.column.point) continue;
      const double area =
          std::abs((ej.ex - ei.ex) * (ek.ey - ei.ey) - (ej.ey - ei.ey) * (ek.ex - ei.ex));
      if (area > best) {
        best = area;
        bk = b;
      }
    }
    if (bk == i) return false;
    const std::size_t pi = ei.column.point;
    const std::size_t pj = entries_[bj].column.point, pk = entries_[bk].column.point;
    // Make sure the four columns exist (outer i is there; the others may not be).
    add_candidate({pi, false});
    add_candidate({pj, true});
    add_candidate({pk, true});
    auto find = [&](Column c) {
      for (std::size_t t = 0; t < entries_.size(); ++t)
        if (entries_[t].column == c) return t;
      return entries_.size();
    };
    return set_basis({find({pi, true}), find({pi, false}), find({pj, true}), find({pk, true})});
  }

  /// One simplex step on the candidates: 0 = optimal on them, 1 = step, 2 = degenerate
  /// step, −1 = numerical failure. Bland's rule against cycling when `bland`.
  int pivot(bool bland) {
    std::size_t entering = entries_.size();
    double best_rc = tolerance();
    for (std::size_t c = 0; c < entries_.size(); ++c) {
      const double rc = reduced_cost(entries_[c]);
      if (rc > best_rc) {
        if (std::find(basis_.begin(), basis_.end(), c) != basis_.end()) continue;
        best_rc = rc;
        entering = c;
        if (bland) break;
      }
    }
    if (entering == entries_.size()) return 0;
    const Eigen::Vector4d d = binv_ * column(entries_[entering]);
    int leave = -1;
    double theta = std::numeric_limits<double>::infinity();
    for (int j = 0; j < 4; ++j) {
      if (d[j] <= 1e-12) continue;
      const double t = xb_[j] / d[j];
      if (t < theta - 1e-15 || (t <= theta + 1e-15 && leave >= 0 && d[j] > d[leave])) {
        theta = std::min(theta, t);
        leave = j;
      }
    }
    if (leave < 0) return -1;  // unbounded: impossible for this LP (Σλ = Σμ = 1)
    std::array<std::size_t, 4> next = basis_;
    next[static_cast<std::size_t>(leave)] = entering;
    if (!set_basis(next)) return -1;
    return theta <= 1e-15 ? 2 : 1;
  }

  std::span<const Point2> points_;
  std::vector<std::uint8_t> in_candidates_;  ///< bit 1: outer column, bit 2: inner column
  std::vector<Entry> entries_;
  Point2 c0_;
  double shift_ = 0.0, rho_min_ = 0.0, rho_max_ = 0.0, cost_scale_ = 0.0;
  bool precise_ = false;  ///< pricing in double-double (thin zones)
  bool precise_announced_ = false;
  std::array<std::size_t, 4> basis_{};
  bool have_basis_ = false;
  Eigen::Matrix4d binv_;
  Eigen::Vector4d xb_, y_;
};

/// The 2+2 quadruple of an LP basis, if it has two outer and two inner columns on four
/// different points.
std::optional<Quad> quad_of_basis(const std::array<Column, 4>& basis) {
  std::vector<std::size_t> o, i;
  for (const Column& c : basis) (c.outer ? o : i).push_back(c.point);
  if (o.size() != 2 || i.size() != 2) return std::nullopt;
  if (o[0] == i[0] || o[0] == i[1] || o[1] == i[0] || o[1] == i[1]) return std::nullopt;
  return Quad{{o[0], o[1]}, {i[0], i[1]}};
}

// ───────────────────────────── driver ──────────────────────────────────────────────────

/// Certifies a quadruple: strict alternation and exact containment (section 1).
std::optional<Certified> certify(std::span<const Point2> points, const Quad& q) {
  std::optional<Candidate> k = make_candidate(points, q);
  if (!k) return std::nullopt;
  const bool alternating = is_strictly_alternating(points, *k);
  PassResult pass = containment_pass(points, *k, /*stop_at_violation=*/true);
  if (!pass.contains) return std::nullopt;
  if (alternating) return Certified{std::move(*k), std::move(pass)};
  // Exact ties: another 2+2 of the contacts at the same centre may alternate.
  const std::optional<Quad> tied = alternating_among_ties(points, *k, pass);
  if (!tied) return std::nullopt;
  std::optional<Candidate> t = make_candidate(points, *tied);
  if (!t || !is_strictly_alternating(points, *t)) return std::nullopt;
  PassResult tied_pass = containment_pass(points, *t, /*stop_at_violation=*/true);
  if (!tied_pass.contains) return std::nullopt;
  return Certified{std::move(*t), std::move(tied_pass)};
}

/// Exact repair (section 2): the least-width certified quadruple among the near-extremal
/// points at a centre `c` (original coordinates).
std::optional<Certified> repair(std::span<const Point2> points, Point2 c, double tau) {
  std::vector<std::pair<double, std::size_t>> d(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    d[i] = {std::hypot(points[i].x - c.x, points[i].y - c.y), i};
  const std::size_t m = std::min(kMaxRepair, points.size());
  std::partial_sort(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(m), d.end());
  std::vector<std::size_t> I, O;
  for (std::size_t j = 0; j < m; ++j)
    if (d[j].first <= d[0].first + tau || j < 2) I.push_back(d[j].second);
  std::partial_sort(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(m), d.end(),
                    [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t j = 0; j < m; ++j)
    if (d[j].first >= d[0].first - tau || j < 2) O.push_back(d[j].second);
  std::vector<std::size_t> probe = O;
  probe.insert(probe.end(), I.begin(), I.end());
  return narrowest_certified(points, O, I, nullptr, probe).best;
}

/// The side of the contact pair (a1, a2) — directions about c* — on which x lies: +1 or −1
/// for the two open arcs they bound, 0 on a boundary direction (exact).
int arc_side(const Candidate& k, Point2 a1, Point2 a2, Point2 x) {
  int s12 = cross_sign(k, a1, a2);
  if (s12 < 0) {
    std::swap(a1, a2);
    s12 = 1;
  }
  const int a = cross_sign(k, a1, x);
  if (s12 == 0) return dot_sign(k, a1, a2) > 0 ? 0 : a;
  const int b = cross_sign(k, x, a2);
  if (a > 0 && b > 0) return 1;
  if ((a == 0 && dot_sign(k, a1, x) > 0) || (b == 0 && dot_sign(k, x, a2) > 0)) return 0;
  return -1;
}

/// Exact exchange (section 2), the Remez step on the true distances: while some point lies
/// outside the quadruple's annulus (decided exactly, worst first), swap it for the contact
/// of the same kind that shares its arc between the other pair's directions, which keeps
/// the contacts alternating. Resolves near-ties the linear model cannot see (symmetric
/// lobed data: many contacts equal to within rounding). Bounded number of steps.
std::optional<Certified> exact_exchange(std::span<const Point2> points, Quad q) {
  for (int step = 0; step < 64; ++step) {
    std::optional<Candidate> k = make_candidate(points, q);
    if (!k || !is_strictly_alternating(points, *k)) return std::nullopt;
    PassResult pass = containment_pass(points, *k);
    if (pass.contains) return Certified{std::move(*k), std::move(pass)};
    // The worst violator in floating order whose violation is exact.
    std::vector<std::pair<double, std::size_t>> outer, inner;
    for (std::size_t i : pass.ambiguous) {
      if (same_point_as_contact(points, q, points[i])) continue;
      const double s = (points[i].x - k->c.x) * (points[i].x - k->c.x) +
                        (points[i].y - k->c.y) * (points[i].y - k->c.y);
      (s > k->rounded.outer_sq * 0.5 + k->rounded.inner_sq * 0.5 ? outer : inner)
          .push_back({s, i});
    }
    std::sort(outer.begin(), outer.end(), std::greater<>());
    std::sort(inner.begin(), inner.end());
    auto first_exact = [&](const std::vector<std::pair<double, std::size_t>>& list, bool out) {
      for (std::size_t j = 0; j < list.size() && j < 64; ++j)
        if (annulus_side(*k, points[list[j].second]) == (out ? 1 : -1)) return list[j].second;
      return points.size();
    };
    const double over = outer.empty() ? 0.0 : outer.front().first - k->rounded.outer_sq;
    const double under = inner.empty() ? 0.0 : k->rounded.inner_sq - inner.front().first;
    std::size_t p = points.size();
    bool is_outer = over >= under;
    p = first_exact(is_outer ? outer : inner, is_outer);
    if (p == points.size()) {
      is_outer = !is_outer;
      p = first_exact(is_outer ? outer : inner, is_outer);
    }
    if (p == points.size()) return std::nullopt;
    const Point2 x = points[p];
    if (is_outer) {
      const int side = arc_side(*k, points[q.inner[0]], points[q.inner[1]], x);
      if (side == 0) return std::nullopt;
      const int s0 = arc_side(*k, points[q.inner[0]], points[q.inner[1]], points[q.outer[0]]);
      q.outer[s0 == side ? 0 : 1] = p;
    } else {
      const int side = arc_side(*k, points[q.outer[0]], points[q.outer[1]], x);
      if (side == 0) return std::nullopt;
      const int s0 = arc_side(*k, points[q.outer[0]], points[q.outer[1]], points[q.inner[0]]);
      q.inner[s0 == side ? 0 : 1] = p;
    }
  }
  return std::nullopt;
}

std::string format_local_argument(std::size_t n) {
  std::ostringstream os;
  os << "2+2 contacts alternating strictly in angle about the exact centre (exact "
        "orientation tests) and all "
     << n << " points in the closed annulus (exact): strict local minimum of R - r";
  return os.str();
}

struct FastPath {
  std::optional<Certified> certified;
  bool diverged = false;
  std::string failure;
  Point2 centroid;       ///< of the data
  Point2 minor_axis;     ///< unit normal of the data's principal axis
  double extent = 0.0;   ///< bounding-box diagonal
};

/// Zone width of the circle centred `distance` away from the centroid along ±minor axis
/// (the nearer of the two sides): a nearly straight zone. Evaluated as h/(R + r) with
/// h = max − min of |q|² − 2c·q on centroid-relative q (no cancellation of R − r).
double straight_zone_width(std::span<const Point2> points, const FastPath& f, double distance) {
  double best = std::numeric_limits<double>::infinity();
  for (const double side : {1.0, -1.0}) {
    const Point2 c{side * distance * f.minor_axis.x, side * distance * f.minor_axis.y};
    double gmax = -std::numeric_limits<double>::infinity(), gmin = -gmax;
    double smax = 0.0, smin = std::numeric_limits<double>::infinity();
    for (const Point2& p : points) {
      const double qx = p.x - f.centroid.x, qy = p.y - f.centroid.y;
      const double g = qx * qx + qy * qy - 2.0 * (c.x * qx + c.y * qy);
      gmax = std::max(gmax, g);
      gmin = std::min(gmin, g);
      const double dx = qx - c.x, dy = qy - c.y;
      const double s = dx * dx + dy * dy;
      smax = std::max(smax, s);
      smin = std::min(smin, s);
    }
    best = std::min(best, (gmax - gmin) / (std::sqrt(smax) + std::sqrt(smin)));
  }
  return best;
}

FastPath run_fast_path(std::span<const Point2> points) {
  FastPath out;
  const std::size_t n = points.size();
  // Kåsa start, min Σ (x² + y² − 2ax − 2by − k)², on a strided subsample of at most
  // kStartSample points (a warm start only: the LP corrects it; its statistical error on
  // 1024 points is ~σ/30, nanometres for measured rings). Raw sums about p0 = the first
  // point (small, exact-ish differences for far-from-origin data), then central sums:
  //   Σ X Z = Sxz − 2mx Sxx − 2my Sxy − mx Sz + 2m mx q,  q = mx² + my², Z = X² + Y²,
  // (X, Y) = (x − mx, y − my); symmetrically for Σ Y Z. Their cancellation, ~u·R relative
  // to the centre offset, is harmless for a start.
  const Point2 p0 = points[0];
  const std::size_t stride = (n + kStartSample - 1) / kStartSample;
  double m = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0, sxz = 0, syz = 0;
  double xmin = 0, xmax = 0, ymin = 0, ymax = 0;
  for (std::size_t i = 0; i < n; i += stride) {
    const double x = points[i].x - p0.x, y = points[i].y - p0.y;
    const double xx = x * x, yy = y * y, z = xx + yy;
    m += 1.0;
    sx += x;
    sy += y;
    sxx += xx;
    sxy += x * y;
    syy += yy;
    sxz += x * z;
    syz += y * z;
    xmin = std::min(xmin, x);
    xmax = std::max(xmax, x);
    ymin = std::min(ymin, y);
    ymax = std::max(ymax, y);
  }
  // Extent of the subsample: a scale for the divergence rule of section 5 only.
  const double extent = std::hypot(xmax - xmin, ymax - ymin);
  const double far = kMaxRadiusFactor * extent;
  out.extent = extent;
  Point2 c0;
  {
    const double mx = sx / m, my = sy / m, q = mx * mx + my * my, sz = sxx + syy;
    const double cxx = sxx - m * mx * mx, cyy = syy - m * my * my, cxy = sxy - m * mx * my;
    const double cxz = sxz - 2 * mx * sxx - 2 * my * sxy - mx * sz + 2 * m * mx * q;
    const double cyz = syz - 2 * my * syy - 2 * mx * sxy - my * sz + 2 * m * my * q;
    out.centroid = {p0.x + mx, p0.y + my};
    // Minor axis of the second-moment matrix [[cxx, cxy], [cxy, cyy]]: normal of the line.
    const double theta = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);  // major-axis angle
    out.minor_axis = {-std::sin(theta), std::cos(theta)};
    const double det = cxx * cyy - cxy * cxy;
    if (!(det > 0.0) || !std::isfinite(det)) {
      out.diverged = true;
      out.failure = "the algebraic start is singular (numerically collinear data)";
      return out;
    }
    const double a = 0.5 * (cyy * cxz - cxy * cyz) / det;
    const double b = 0.5 * (cxx * cyz - cxy * cxz) / det;
    if (!(std::hypot(a, b) < far)) {
      out.diverged = true;
      out.failure = "the algebraic start circle is centred beyond 1e6 data extents";
      return out;
    }
    c0 = {p0.x + mx + a, p0.y + my + b};
  }
  auto too_far = [&](Point2 c) { return !(std::hypot(c.x - p0.x, c.y - p0.y) < far); };

  ChebyshevLp lp(points);
  lp.seed_candidates(c0);
  Point2 last_failed{std::numeric_limits<double>::quiet_NaN(), 0.0};
  bool refined = false;  // the local refinement below, once
  for (int iter = 0; iter < kMaxLinearisations; ++iter) {
    if (lp.solve(c0) != LpStatus::optimal) {
      out.failure = "the linearised Chebyshev LP failed numerically";
      return out;
    }
    const Point2 delta = lp.delta();
    const double step = std::hypot(delta.x, delta.y);
    const double width = std::max(lp.width(), 0.0);
    const Point2 c1{c0.x + delta.x, c0.y + delta.y};
    if (too_far(c1)) {
      out.diverged = true;
      out.failure = "the iterated centre moved beyond 1e6 data extents";
      return out;
    }
    // Trust region: the model (3) is only good for |δ| ≪ ρ.
    const double max_step = 0.25 * lp.rho_min();
    if (step > max_step) {
      c0 = {c0.x + delta.x * max_step / step, c0.y + delta.y * max_step / step};
      continue;
    }
    const double lin_error = step * step / (2.0 * lp.rho_min());
    if (lin_error > kLinearisationTolerance * width && iter + 1 < kMaxLinearisations) {
      c0 = c1;
      continue;
    }
    // A thin zone just detected: the seeds were ranked by plain squared distances, which
    // cannot tell its points apart; one precise pricing pass first (cheaper than a
    // containment pass that would fail).
    if (lp.first_precise_round() && lp.full_pricing() > 0) continue;
    const std::optional<Quad> quad = quad_of_basis(lp.basis());
    // Local refinement before the first containment pass (as the MC and MI fitters do,
    // internal::local_extreme): on a profile scanned in angular order a contact of the
    // full set sits a few indices off the model's contact of the same kind, where the seeds
    // (each block's extremes about the start) missed it; such points are the violators the
    // pass would find. Each contact's farthest (outer) or nearest (inner) neighbour along
    // the profile about the model's centre joins the candidates, and the model is solved
    // again — once, on plain costs (thin zones rank by double-double pricing instead).
    if (quad && !refined && !lp.precise()) {
      refined = true;
      bool grew = false;
      for (const std::size_t o : quad->outer) {
        const std::size_t j = internal::local_extreme<true>(points, o, c1, 1.0, n / 64, n / 8);
        grew = (j != o && lp.add_point(j, true)) || grew;
      }
      for (const std::size_t i : quad->inner) {
        const std::size_t j = internal::local_extreme<false>(points, i, c1, 1.0, n / 64, n / 8);
        grew = (j != i && lp.add_point(j, false)) || grew;
      }
      if (grew) continue;
    }
    if (quad) {
      std::optional<Certified> cert = certify(points, *quad);
      if (cert) {
        out.certified = std::move(cert);
        return out;
      }
    }
    // Points the candidates missed: add each block's worst and re-solve the same model.
    if (lp.full_pricing() > 0) continue;
    // Settled on an uncertified optimum with plain costs: near-ties below their ~u·ρ
    // resolution (a zone wider than the thin threshold whose contacts still differ by less).
    // Double-double costs and pricing from here on, before the exact repairs.
    if (lp.escalate_precision()) continue;
    // The model has settled on this candidate set and its optimum is not certified:
    // near-ties (or a degenerate basis). Exact exchange from the LP's quadruple, then exact
    // enumeration of the near-extremal points; if both fail, re-linearise at the model's
    // centre once more, and give up when that centre no longer moves.
    const bool settled = std::hypot(c1.x - last_failed.x, c1.y - last_failed.y) <=
                         std::max(1e-9 * lp.rho_min(), 1e-3 * width);
    if (quad) {
      if (std::optional<Certified> fixed = exact_exchange(points, *quad)) {
        out.certified = std::move(fixed);
        return out;
      }
    }
    const double tau = 4.0 * lin_error + 1e-6 * width + 1e-12 * lp.rho_min();
    if (std::optional<Certified> fixed = repair(points, c1, tau)) {
      out.certified = std::move(fixed);
      return out;
    }
    if (settled) break;
    last_failed = c1;
    c0 = c1;
  }
  out.failure = "no certified 2+2 contact set after the maximum number of linearisations";
  return out;
}

/// Lowest index of each distinct point, when there are at most kSmallN of them (sparse data,
/// section 4); empty otherwise.
std::vector<std::size_t> sparse_representatives(std::span<const Point2> points) {
  std::vector<std::size_t> reps;
  if (points.size() > 8 * kSmallN) return reps;
  for (std::size_t i = 0; i < points.size(); ++i) {
    bool seen = false;
    for (std::size_t j : reps) seen = seen || points[j] == points[i];
    if (seen) continue;
    if (reps.size() == kSmallN) return {};
    reps.push_back(i);
  }
  return reps;
}

enum class GlobalStatus { proven, undefined, unknown };

struct GlobalOutcome {
  GlobalStatus status = GlobalStatus::unknown;
  Certificate certificate;
  std::string reason;  ///< for undefined
};

/// Global proof for a certified result: sharpness (section 3), else, for n ≤ kSmallN, the
/// exhaustive search of section 4, which also replaces `cert` by the narrowest certified
/// zone when the fast path stopped at a poorer local minimum, and which can show that no
/// minimiser exists.
GlobalOutcome prove_global(std::span<const Point2> points, Certified& cert) {
  GlobalOutcome out;
  std::ostringstream os;
  os.precision(3);
  const Sharpness sharp = sharpness(points, cert.candidate);
  if (sharp.proven) {
    out.status = GlobalStatus::proven;
    out.certificate.optimality = Optimality::global;
    os << "2+2 contacts alternating strictly about the exact centre and all " << points.size()
       << " points in the closed annulus (exact tests); global: the contact segments cross "
          "and every contact lies "
       << sharp.min_distance << " mm or more from the other pair's line, farther than the "
       << "width " << cert.candidate.w
       << " mm, so by convexity of R^2 - r^2 every other centre is strictly worse (unique "
          "global minimum)";
    out.certificate.argument = os.str();
    return out;
  }
  const std::vector<std::size_t> all = sparse_representatives(points);
  if (all.empty()) return out;
  Search search = narrowest_certified(points, all, all, &cert.candidate, all);
  if (search.unresolved) return out;
  if (search.best) cert = std::move(*search.best);
  // cert is now the narrowest zone of all quadruples holding all points (section 4).
  const double strip = strip_width(points);
  if (cert.candidate.w_hi < strip * (1.0 - 1e-12)) {
    out.status = GlobalStatus::proven;
    out.certificate.optimality = Optimality::global;
    os << "2+2 contacts alternating strictly about the exact centre and all " << points.size()
       << " points in the closed annulus (exact tests); global: the width is below the "
          "minimum strip width "
       << strip << " mm (a minimiser exists) and all " << search.examined
       << " other quadruples were exhausted exactly, none narrower (every local minimiser is "
          "a quadruple's centre)";
    out.certificate.argument = os.str();
  } else if (cert.candidate.w_lo > strip * (1.0 + 1e-12)) {
    out.status = GlobalStatus::undefined;
    os << "every finite zone (narrowest width " << cert.candidate.w
       << ", by exhaustion of all quadruples) is wider than the minimum strip width " << strip
       << ": the zone width is approached only as the radius grows without bound";
    out.reason = os.str();
  }
  return out;
}

MinimumZoneCircle result_of(std::span<const Point2> points, const Certified& cert,
                            Certificate certificate) {
  // Lowest index among duplicates: duplicates of a contact are ambiguous points (section 1).
  std::array<std::size_t, 4> idx = {cert.candidate.quad.outer[0], cert.candidate.quad.outer[1],
                                    cert.candidate.quad.inner[0], cert.candidate.quad.inner[1]};
  for (std::size_t& i : idx) {
    for (std::size_t j : cert.pass.ambiguous) {
      if (j >= i) break;
      if (points[j] == points[i]) {
        i = j;
        break;
      }
    }
  }
  return internal::make_minimum_zone_result(points, cert.candidate.rounded, {idx[0], idx[1]},
                                            {idx[2], idx[3]}, std::move(certificate),
                                            cert.pass.ronq, /*indices_normalised=*/true);
}

}  // namespace

namespace {
MinimumZoneCircle minimum_zone_unscaled(std::span<const Point2> points,
                                        const MinimumZoneOptions& options);

/// Binary exponent band in which every double quantity of the result (R², r², |p − c|²,
/// their sums over n points) stays normal and finite: lengths up to 2^±400 (~1e±120).
constexpr int kSafeExponent = 400;

bool in_safe_band(double v) {
  const int e = v != 0.0 ? std::ilogb(v) : 0;
  return std::isfinite(v) && e >= -kSafeExponent && e <= kSafeExponent;
}
}  // namespace

// Power-of-two scaling is exact and commutes with every exact decision and with correct
// rounding, so data outside the safe band are solved as 2^−e·p and the lengths scaled back.
// Deciding costs O(1) on ordinary data (no extra pass over the points, which would be
// memory-bound at large n): the first point's magnitude, and afterwards the result's own
// lengths; the full magnitude scan runs only when one of them is out of band.
MinimumZoneCircle minimum_zone_circle(std::span<const Point2> points,
                                      const MinimumZoneOptions& options) {
  validate_profile(points, 3, kCaller);
  return internal::fit_minimum_zone_circle(points, options);
}

MinimumZoneCircle internal::fit_minimum_zone_circle(std::span<const Point2> points,
                                                    const MinimumZoneOptions& options) {
  if (in_safe_band(std::max(std::fabs(points[0].x), std::fabs(points[0].y)))) {
    MinimumZoneCircle mz = minimum_zone_unscaled(points, options);
    if (in_safe_band(mz.outer_radius) && in_safe_band(mz.inner_radius) &&
        std::isfinite(mz.ron.ronq))
      return mz;
  }
  double magnitude = 0.0;
  for (const Point2& p : points) magnitude = std::max({magnitude, std::fabs(p.x), std::fabs(p.y)});
  const int e = std::ilogb(magnitude);
  std::vector<Point2> scaled(points.begin(), points.end());
  for (Point2& p : scaled) p = {std::ldexp(p.x, -e), std::ldexp(p.y, -e)};
  MinimumZoneCircle mz = minimum_zone_unscaled(scaled, options);
  mz.center = {std::ldexp(mz.center.x, e), std::ldexp(mz.center.y, e)};
  mz.inner_radius = std::ldexp(mz.inner_radius, e);
  mz.outer_radius = std::ldexp(mz.outer_radius, e);
  mz.ron = {std::ldexp(mz.ron.ront, e), std::ldexp(mz.ron.ronp, e), std::ldexp(mz.ron.ronv, e),
            std::ldexp(mz.ron.ronq, e)};
  mz.certificate.region_radius = std::ldexp(mz.certificate.region_radius, e);
  mz.certificate.argument += " (solved on the data scaled by 2^" + std::to_string(-e) +
                             ", exact; lengths scaled back)";
  return mz;
}

namespace {
MinimumZoneCircle minimum_zone_unscaled(std::span<const Point2> points,
                                        const MinimumZoneOptions& options) {
  if (options.method == MinimumZoneMethod::overlay)
    return internal::minimum_zone_overlay(points);
  if (const auto t = cocircular_triple(points))
    return internal::make_cocircular_result(points, (*t)[0], (*t)[1], (*t)[2]);
  const bool automatic = options.method == MinimumZoneMethod::automatic;
  const std::vector<std::size_t> reps = sparse_representatives(points);
  const bool sparse = !reps.empty();
  auto undefined = [&](const std::string& why) {
    throw UndefinedResult(std::string(kCaller) + ": " + why + ": no minimum-zone circle");
  };

  FastPath fast = run_fast_path(points);
  if (!fast.certified && sparse) {
    // Section 4: exhaustive exact search decides sparse data completely.
    Search search = narrowest_certified(points, reps, reps, nullptr, reps);
    if (search.best) {
      fast.certified = std::move(search.best);
    } else if (!search.unresolved) {
      undefined("no quadruple of the points gives a zone holding them all (exhaustive exact "
                "search), so no finite centre is a local minimum and the zone width is "
                "approached only as the radius grows without bound");
    }
  }
  if (!fast.certified) {
    if (automatic) return internal::minimum_zone_overlay(points);
    std::ostringstream os;
    os << kCaller << ": " << fast.failure;
    if (fast.diverged) {
      os << "; the data are straight to within 1.25e-7 of their extent and the zone width is "
            "approached only as the radius grows without bound: no minimum-zone circle";
      throw UndefinedResult(os.str());
    }
    os << " (n = " << points.size() << "); use MinimumZoneMethod::automatic or overlay";
    throw std::runtime_error(os.str());
  }
  Certified& cert = *fast.certified;
  if (!options.prove_global) {
    Certificate local;
    local.argument = format_local_argument(points.size()) + "; global proof not requested";
    return result_of(points, cert, std::move(local));
  }
  GlobalOutcome global = prove_global(points, cert);
  if (global.status == GlobalStatus::proven)
    return result_of(points, cert, std::move(global.certificate));
  if (global.status == GlobalStatus::undefined) undefined(global.reason);
  if (automatic) return internal::minimum_zone_overlay(points);
  // Section 5 for the exchange method: a circle 1e6 data extents away is at least as good
  // as the best certified circle, so this local minimum is not the global one and the
  // zone width is (as far as the exchange method can tell) approached by ever larger
  // circles: nearly straight data.
  const double straight = straight_zone_width(points, fast, kMaxRadiusFactor * fast.extent);
  if (!(cert.candidate.w_lo < straight)) {
    std::ostringstream os;
    os << "a circle " << kMaxRadiusFactor << " data extents away (zone width " << straight
       << ") is at least as good as the best certified finite circle (width "
       << cert.candidate.w
       << "): the data are nearly straight and the zone width is approached only as the "
          "radius grows without bound (the overlay method decides exactly)";
    undefined(os.str());
  }
  Certificate local;
  local.argument = format_local_argument(points.size()) +
                   "; global optimality not shown (the contact segments do not cross with "
                   "every contact farther than the width from the other pair's line, and the "
                   "profile is too large to exhaust)";
  return result_of(points, cert, std::move(local));
}
}  // namespace

}  // namespace vcmm::geometry
