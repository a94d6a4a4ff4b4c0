// least_squares.cpp — the geometric least-squares (LS) circle, ISO 12181-1 (LSCI).
//
// Notation. Points p_i (i = 1..n), centre c, radius R, distances r_i(c) = |p_i − c|, unit
// directions u_i = (p_i − c) / r_i, residuals e_i = r_i − R. The LS circle minimises
//   F(c, R) = Σ e_i².
// For fixed c the optimal R is the mean distance r̄(c); eliminating R ("variable
// projection") leaves F(c) = Σ (r_i − r̄)², whose Gauss-Newton step δ solves
//   M δ = b,   M = Σ (u_i − ū)(u_i − ū)ᵀ,   b = Σ (u_i − ū)(r_i − r̄)            (1)
// (∂r_i/∂c = −u_i; (1) is also the full 3-parameter GN step for (c, R) with R solved out by
// the Schur complement). The stationary point is b = 0; M only sets the rate of
// convergence, which is fast because the residuals are small next to R: after a step δ,
// |b| shrinks by a factor ~ (max|e_i| + |δ|) / R.
//
// Numerics (what gives ~1e-13 mm on NIST's Circle2d sets, whose centres sit up to ~900 mm
// from the origin with µm-level form):
//  - The data are shifted once by their first point p₀: p_i − p₀ is exact whenever the two
//    are within a factor 2 per coordinate (Sterbenz), i.e. for all far-from-origin data. The
//    fit runs in these local coordinates and the centre is shifted back once at the end.
//  - Distances enter only as d_i = r_i − R₀ with R₀ the previous radius estimate, so the
//    sums Σ d, Σ d², Σ u d are sums of small terms; b = Σ u d − d̄ Σ u is (1) rearranged.
//    With small terms, plain (SIMD-blocked) summation is as good as compensated summation:
//    the rounding of each r_i (½ ulp of R) dominates.
//  - M is accumulated with directions shifted by u_ref ≈ ū (from the start circle), v = u −
//    u_ref: M = Σ v vᵀ − n v̄ v̄ᵀ then loses nothing to cancellation on short arcs (for a 30°
//    arc, Σ u_x² − n ū_x² would lose four digits).
//  - M is re-formed only after a step larger than 1e-8 R: a matrix from a centre that close
//    changes the rate of convergence by ~1e-8, never the fixed point. Those "full" passes also
//    form F, and a full step that increases F beyond its rounding noise is halved
//    (backtracking; never triggered on roughly circular data). Steps below 1e-8 R are
//    descent steps inside the region where the GN model is exact to ~1e-8, so the cheap
//    passes that follow them need no such check.
//  - Start: the algebraic (Kåsa) fit, min Σ (x² + y² − 2ax − 2by − k)² on centred moments:
//    exact for 3 points, otherwise off by ~max|e|²/R — a start one GN step from the answer.
//  - Stop when the GN step is below 2⁻⁵²·R (one ulp of R: the rounding floor of r_i), or
//    when steps stop contracting below 1e-9·R (the iteration has reached its rounding noise,
//    e.g. on ill-conditioned short arcs). The last (negligible) step is not applied: the
//    reported centre is the one at which R and the residuals were evaluated, so `ron` and
//    `contacts` are exactly about the reported circle.
//  - Result on NIST's 30 Circle2d sets: centre within 7.8e-14 mm and diameter within
//    1.4e-13 mm of the 60-digit reference fits; the diameter's worst case (set 2, a 90° arc)
//    is the floor set by rounding the 5-decimal input to double (a 50-digit fit of the
//    rounded input differs from the reference by the same 1.39e-13 mm).
//
// Points on rays (least_squares_circle_on_rays, for the Gaussian filter's output). The filter
// builds its output points on the rays from a centre c — the LS centre of its input — as
// q_i = c + (R + w_i) u_i, and knows u_i and w_i. Their LS centre is c + δ with |δ| tiny (the
// filter passes harmonic 1 with gain ≈ 1 and the input's harmonic 1 about c is zero: δ ~ 1e-10
// mm on simulated 3600-point rings). Near c, r_i(c + δ) = (R + w_i) − u_i·δ + q_i with
// 0 ≤ q_i ≤ |δ|² / (2 (R + w_i)) (the next term of |ρu − δ| in δ), so F is, up to q, the
// linear least-squares problem min Σ ((w_i − w̄) − (u_i − ū)·δ)², whose minimiser is the GN
// step (1) at c: δ = M⁻¹ b, M = Σ (u − ū)(u − ū)ᵀ, b = Σ (u − ū)(w − w̄). Ignoring q moves the
// minimiser by at most 2 max q (M⁻¹ Σ (u − ū) q with M ≈ n/2 I on a closed profile) and each
// residual by max q; with |δ| ≤ 2⁻³⁰ min(R + w) both are ≤ 2⁻⁶⁰ of the radius, far below the
// ulp of R that bounds the iterative fit above. So one pass for the sums (no square root,
// no division: u_i is the filter's ray times its reciprocal length) and one for the residuals
// e_i = w_i − u_i·δ give the fit; |δ| beyond 2⁻³⁰ R (never seen on roundness data) returns
// nothing and the caller fits the points in full. Against least_squares_circle(q) on 200
// simulated trials: centre within 2e-14 mm, RONt within 3e-14 mm
// (tests/geometry/gaussian_filter_trial_test.cpp).
//
// Distances without square roots. Each GN pass needs r_i and u_i = (p_i − c)/r_i. The points
// of a roundness profile lie within ~1e-3 R of the circle, where internal/near_circle.h gives
// both by a short series in s = (q − R₀²)/R₀² (q = |p_i − c|², R₀ = r0 to 26 bits): r_i within
// ½ ulp + 2⁻⁵⁹ relative of √q — equal to std::sqrt(q) but near rounding midpoints, at most 1 ulp
// from it — and 1/r_i likewise. Each pass takes the smallest degree (3, 4, 6) whose range
// covers |s| as bounded from the previous pass (the first pass, at the Kåsa centre, degree 4:
// deviations up to ~1e-4 R), measures max |s| and is redone with the degree it needs when a
// point falls outside (then with square root and division beyond |s| = 2⁻⁹). The centre and
// radius move by ulps at most against square roots (the rare r_i that differ by an ulp).
//
// Cost: one pass for the start (no square root; it also proves every coordinate finite for
// least_squares_circle's input check), then per GN iteration one vectorised pass (AVX-512 or
// AVX2 where the CPU has it, else SSE2; the same bits, see "the Gauss-Newton pass" below)
// that also keeps the extremes of r and Σ d² — the residual summary needs no pass of its own:
// Σ e² = Σ d² − n d̄² and the contacts are the first indices of the extremes. Typically 2
// iterations: the step from the Kåsa centre, then the pass that finds the next step
// negligible and supplies R.
#include "vcmm/geometry/least_squares.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "internal/isa.h"
#include "internal/least_squares_on_rays.h"
#include "internal/near_circle.h"
#include "internal/prevalidated.h"
#include "internal/vec.h"

#if VCMM_GEOMETRY_X86
#include <immintrin.h>
#endif

namespace vcmm::geometry {
namespace {

constexpr const char* kCaller = "least_squares_circle";

/// Every sum the GN step (1) needs, evaluated at one centre, and what the residual summary
/// needs of the same pass. The Σ v vᵀ sums are formed in full passes only.
struct PassSums {
  double sum_d = 0.0, sum_dd = 0.0;     // Σ d, Σ d²     (d = r − R₀)
  double sum_vx = 0.0, sum_vy = 0.0;    // Σ v           (v = u − shift)
  double sum_vxd = 0.0, sum_vyd = 0.0;  // Σ v d
  double sum_vxx = 0.0, sum_vxy = 0.0, sum_vyy = 0.0;  // Σ v vᵀ
  double r_max = 0.0, r_min = 0.0;      // extreme distances
  double s_max = 0.0;  // series passes: max |s| (near_circle.h), the check of their range
};

// The passes are written on Eigen's SIMD packets (2 doubles with SSE2, 4 with AVX, 1 without
// vectorisation): the compiler does not vectorise std::sqrt (errno) nor reorder sums, and
// one fused pass per iteration is ~3x faster than separate Eigen array reductions.
namespace simd = Eigen::internal;
using Packet = simd::packet_traits<double>::type;
constexpr Eigen::Index kLanes = simd::packet_traits<double>::size;

/// First index i < n with a[i] == v (v is a value of a): packet scan, four packets per test.
std::size_t first_index_baseline(const double* a, Eigen::Index n, double v) {
  const Packet pv = simd::pset1<Packet>(v);
  Eigen::Index i = 0;
  const Eigen::Index block = 4 * kLanes;
  while (i + block <= n) {
    const Packet hit = simd::por(
        simd::por(simd::pcmp_eq(simd::ploadu<Packet>(a + i), pv),
                  simd::pcmp_eq(simd::ploadu<Packet>(a + i + kLanes), pv)),
        simd::por(simd::pcmp_eq(simd::ploadu<Packet>(a + i + 2 * kLanes), pv),
                  simd::pcmp_eq(simd::ploadu<Packet>(a + i + 3 * kLanes), pv)));
    if (simd::predux_any(hit)) break;
    i += block;
  }
  while (i < n && a[i] != v) ++i;
  return static_cast<std::size_t>(i);
}

#if VCMM_GEOMETRY_X86
/// first_index_baseline with 8-lane vectors (four per test).
__attribute__((target("avx512f"))) std::size_t first_index_avx512(const double* a,
                                                                  Eigen::Index n, double v) {
  const __m512d pv = _mm512_set1_pd(v);
  Eigen::Index i = 0;
  for (; i + 32 <= n; i += 32) {
    const __mmask8 hit =
        static_cast<__mmask8>(_mm512_cmp_pd_mask(_mm512_loadu_pd(a + i), pv, _CMP_EQ_OQ) |
                              _mm512_cmp_pd_mask(_mm512_loadu_pd(a + i + 8), pv, _CMP_EQ_OQ) |
                              _mm512_cmp_pd_mask(_mm512_loadu_pd(a + i + 16), pv, _CMP_EQ_OQ) |
                              _mm512_cmp_pd_mask(_mm512_loadu_pd(a + i + 24), pv, _CMP_EQ_OQ));
    if (hit != 0) break;
  }
  while (i < n && a[i] != v) ++i;
  return static_cast<std::size_t>(i);
}
#endif

/// First index i < n with a[i] == v (v is a value of a).
std::size_t first_index(const double* a, Eigen::Index n, double v) {
#if VCMM_GEOMETRY_X86
  if (internal::use_avx512()) return first_index_avx512(a, n, v);
#endif
  return first_index_baseline(a, n, v);
}

/// Spans of the data (mm) the fit handles: the Kåsa start forms products up to the 5th power
/// of the local coordinates (cyy·cxz), sums over up to ~1e8 points add 8 decades, and the
/// results must stay inside the normal double range (1e±308): 1e-50 ≤ s ≤ 1e50 leaves a margin
/// of ~50 decades. Beyond, the moments overflow or underflow and Gauss-Newton would call the
/// data straight; a span outside is a wrong unit or corrupt data, not a roundness profile.
constexpr double kMinSpanMm = 1e-50;
constexpr double kMaxSpanMm = 1e50;

/// Extremes of the raw coordinates.
struct Extent {
  double x0, x1, y0, y1;
};

/// The extent of the points: interleaved x, y doubles, a packet holds kLanes / 2 whole
/// points, so lane-wise extremes are per coordinate (even lanes x, odd lanes y); two packets
/// an iteration (independent chains). Used where the fused pass of Fitter is not compiled.
[[maybe_unused]] Extent extent_of(std::span<const Point2> points) {
  double x0 = points[0].x, x1 = x0, y0 = points[0].y, y1 = y0;
  std::size_t i = 0;
  if constexpr (kLanes % 2 == 0) {
    static_assert(sizeof(Point2) == 2 * sizeof(double), "Point2: two packed doubles");
    const double* p = reinterpret_cast<const double*>(points.data());
    constexpr std::size_t per_step = kLanes;  // points per iteration (two packets)
    if (points.size() >= per_step) {
      Packet lo0 = simd::ploadu<Packet>(p), hi0 = lo0, lo1 = lo0, hi1 = lo0;
      for (; i + per_step <= points.size(); i += per_step) {
        const Packet a = simd::ploadu<Packet>(p + 2 * i);
        const Packet b = simd::ploadu<Packet>(p + 2 * i + kLanes);
        lo0 = simd::pmin(lo0, a);
        hi0 = simd::pmax(hi0, a);
        lo1 = simd::pmin(lo1, b);
        hi1 = simd::pmax(hi1, b);
      }
      alignas(64) double lo[kLanes], hi[kLanes];
      simd::pstoreu(lo, simd::pmin(lo0, lo1));
      simd::pstoreu(hi, simd::pmax(hi0, hi1));
      for (Eigen::Index k = 0; k < kLanes; k += 2) {
        x0 = std::min(x0, lo[k]);
        y0 = std::min(y0, lo[k + 1]);
        x1 = std::max(x1, hi[k]);
        y1 = std::max(y1, hi[k + 1]);
      }
    }
  }
  for (; i < points.size(); ++i) {
    x0 = std::min(x0, points[i].x);
    x1 = std::max(x1, points[i].x);
    y0 = std::min(y0, points[i].y);
    y1 = std::max(y1, points[i].y);
  }
  return {x0, x1, y0, y1};
}

/// Refuses data whose span is outside [kMinSpanMm, kMaxSpanMm] (InvalidInput).
void check_span(const Extent& e) {
  const double span = std::max(e.x1 - e.x0, e.y1 - e.y0);  // may be inf for ±1e308 data
  if (span >= kMinSpanMm && span <= kMaxSpanMm) return;
  std::ostringstream os;
  os.precision(3);
  os << kCaller << ": the points span " << span << " mm; a circle is fitted in double precision "
     << "only to data spanning " << kMinSpanMm << " to " << kMaxSpanMm
     << " mm (its moments reach the 5th power of the span and would overflow or underflow): "
     << "wrong unit or corrupt data?";
  throw InvalidInput(os.str());
}

// ---- the Gauss-Newton pass -------------------------------------------------------------------
// One pass over the local coordinates at a centre: r_i, d_i = r_i − R₀, u_i = (p_i − c)/r_i and
// the sums of (1), plus the extremes of r and, on a series pass, max |s|. Distances and their
// reciprocals by the series of internal/near_circle.h (degree D = 3, 4, 6) or, D = 0, by
// square root and division. Written on GCC vectors of W lanes and compiled three times
// (internal/isa.h): W = 2 for the baseline (SSE2), W = 4 in a target("avx2") function, W = 8
// in a target("avx512f") one. Every sum is accumulated in four lanes whatever W — lane j takes
// the points i ≡ j (mod 4), one AVX2 vector, two SSE2 vectors or the low then the high half of
// an AVX-512 vector — and the lanes are added as (l₀ + l₂) + (l₁ + l₃), then the last n mod 4
// points in order: the same operations in the same order on every element, so all variants
// give the same bits (no FMA: -ffp-contract=off).

template <int W>
using Lanes = typename internal::VecOf<W>::type;
constexpr int kSumLanes = 4;

// max/min as a > b ? a : b (maxpd/minpd on vectors); |v| by clearing the sign bit.
template <class V>
[[gnu::always_inline]] inline V lanes_max(const V& a, const V& b) { return a > b ? a : b; }
template <class V>
[[gnu::always_inline]] inline V lanes_min(const V& a, const V& b) { return a < b ? a : b; }
[[gnu::always_inline]] inline double lanes_abs(double v) { return std::fabs(v); }
template <class V>
[[gnu::always_inline]] inline V lanes_abs(const V& v) {
  using M = typename internal::VecOf<sizeof(V) / sizeof(double)>::mask;
  return V(M(v) & 0x7fffffffffffffffLL);
}
[[gnu::always_inline]] inline double lanes_sqrt(double v) { return std::sqrt(v); }
template <class V>
[[gnu::always_inline]] inline V lanes_sqrt(const V& v) {
#if defined(__SSE2__)
  if constexpr (sizeof(V) == 16) {
    return __builtin_ia32_sqrtpd(v);
  } else if constexpr (sizeof(V) == 64) {
    const Lanes<4> lo = lanes_sqrt(internal::low_half(v)), hi = lanes_sqrt(internal::high_half(v));
    return __builtin_shufflevector(lo, hi, 0, 1, 2, 3, 4, 5, 6, 7);
  } else {
    const Lanes<2> lo = __builtin_shufflevector(v, v, 0, 1);
    const Lanes<2> hi = __builtin_shufflevector(v, v, 2, 3);
    return __builtin_shufflevector(__builtin_ia32_sqrtpd(lo), __builtin_ia32_sqrtpd(hi), 0, 1, 2,
                                   3);
  }
#else
  V r;
  for (std::size_t l = 0; l < sizeof(V) / sizeof(double); ++l) r[l] = std::sqrt(v[l]);
  return r;
#endif
}

/// The inputs of a pass (local coordinates, distances written to r).
struct PassInput {
  const double* x;
  const double* y;
  double* r;
  std::size_t n;
  double cx, cy, r0, urx, ury;
  internal::NearCircle k;  ///< about r0 (series passes)
};

/// The per-lane accumulators of a pass, for V = Lanes<W> or double (the tail).
template <class V>
struct PassLanes {
  V sd{}, sdd{}, svx{}, svy{}, svxd{}, svyd{}, svxx{}, svxy{}, svyy{};
  V rmax = V{} - std::numeric_limits<double>::infinity();
  V rmin = V{} + std::numeric_limits<double>::infinity();
  V smax{};
};

/// The terms W points (V = Lanes<W>) or one (V = double) add to the sums of a pass, and what
/// they give the extremes.
template <class V>
struct PassTerms {
  V r, s_abs, d, dd, vx, vy, vxd, vyd, vxx, vxy, vyy;
};

/// The pass's work on the points at i: distances stored, the terms of the sums returned.
template <bool kFull, int D, class V>
[[gnu::always_inline]] inline PassTerms<V> pass_terms(const PassInput& in, std::size_t i) {
  PassTerms<V> t{};
  const V dx = internal::load<V>(in.x + i) - in.cx, dy = internal::load<V>(in.y + i) - in.cy;
  const V q = dx * dx + dy * dy;
  V w;
  if constexpr (D > 0) {
    const V s = internal::near_circle_s(q, in.k);
    t.s_abs = lanes_abs(s);
    t.r = in.k.r0 + internal::near_circle_offset<D>(s, in.k);
    w = internal::near_circle_inverse<D>(s, in.k);
  } else {
    t.r = lanes_sqrt(q);
    w = 1.0 / t.r;
  }
  internal::store(in.r + i, t.r);
  t.d = t.r - in.r0;
  t.vx = dx * w;
  t.vy = dy * w;
  if constexpr (kFull) {
    t.vx = t.vx - in.urx;
    t.vy = t.vy - in.ury;
    t.vxx = t.vx * t.vx;
    t.vxy = t.vx * t.vy;
    t.vyy = t.vy * t.vy;
  }
  t.dd = t.d * t.d;
  t.vxd = t.vx * t.d;
  t.vyd = t.vy * t.d;
  return t;
}

/// Adds the terms to the sums (same lanes).
template <bool kFull, class V>
[[gnu::always_inline]] inline void add_sums(PassLanes<V>& a, const PassTerms<V>& t) {
  if constexpr (kFull) {
    a.svxx += t.vxx;
    a.svxy += t.vxy;
    a.svyy += t.vyy;
  }
  a.sdd += t.dd;
  a.sd += t.d;
  a.svx += t.vx;
  a.svy += t.vy;
  a.svxd += t.vxd;
  a.svyd += t.vyd;
}

/// Takes the terms into the extremes (same lanes).
template <int D, class V>
[[gnu::always_inline]] inline void add_extremes(PassLanes<V>& a, const PassTerms<V>& t) {
  a.rmax = lanes_max(a.rmax, t.r);
  a.rmin = lanes_min(a.rmin, t.r);
  if constexpr (D > 0) a.smax = lanes_max(a.smax, t.s_abs);
}

/// The sums of W points (V = Lanes<W>) or one (V = double) into their accumulators.
template <bool kFull, int D, class V>
[[gnu::always_inline]] inline void pass_points(const PassInput& in, std::size_t i,
                                               PassLanes<V>& a) {
  const PassTerms<V> t = pass_terms<kFull, D, V>(in, i);
  add_extremes<D>(a, t);
  add_sums<kFull>(a, t);
}

/// The four lanes of each sum in point order, added as (l₀ + l₂) + (l₁ + l₃), the extremes
/// over every lane, then the last points from i on one at a time, added in order.
template <bool kFull, int D, int W, int kPackets>
[[gnu::always_inline]] inline PassSums finish_pass(const PassInput& in, std::size_t i,
                                                   const PassLanes<Lanes<W>> (&a)[kPackets]) {
  static_assert(W * kPackets == kSumLanes);
  using V = Lanes<W>;
  const auto sum = [&](V PassLanes<V>::*field) {
    double l[kSumLanes];
    for (int p = 0; p < kPackets; ++p)
      for (int j = 0; j < W; ++j) l[p * W + j] = (a[p].*field)[j];
    return (l[0] + l[2]) + (l[1] + l[3]);
  };
  PassLanes<double> t;
  t.sd = sum(&PassLanes<V>::sd);
  t.sdd = sum(&PassLanes<V>::sdd);
  t.svx = sum(&PassLanes<V>::svx);
  t.svy = sum(&PassLanes<V>::svy);
  t.svxd = sum(&PassLanes<V>::svxd);
  t.svyd = sum(&PassLanes<V>::svyd);
  if constexpr (kFull) {
    t.svxx = sum(&PassLanes<V>::svxx);
    t.svxy = sum(&PassLanes<V>::svxy);
    t.svyy = sum(&PassLanes<V>::svyy);
  }
  for (int p = 0; p < kPackets; ++p)
    for (int j = 0; j < W; ++j) {
      t.rmax = std::max(t.rmax, a[p].rmax[j]);
      t.rmin = std::min(t.rmin, a[p].rmin[j]);
      t.smax = std::max(t.smax, a[p].smax[j]);
    }
  for (; i < in.n; ++i) pass_points<kFull, D>(in, i, t);
  return {t.sd, t.sdd, t.svx, t.svy, t.svxd, t.svyd, t.svxx, t.svxy, t.svyy, t.rmax, t.rmin, t.smax};
}

template <int W, bool kFull, int D>
[[gnu::always_inline]] inline PassSums gn_pass_body(const PassInput& input) {
  // A local copy: the stores to in.r cannot alias it, so its constants stay in registers.
  const PassInput in = input;
  constexpr int kPackets = kSumLanes / W;
  PassLanes<Lanes<W>> a[kPackets];
  std::size_t i = 0;
  for (; i + kSumLanes <= in.n; i += kSumLanes)
    for (int p = 0; p < kPackets; ++p) pass_points<kFull, D>(in, i + p * W, a[p]);
  return finish_pass<kFull, D, W, kPackets>(in, i, a);
}

template <bool kFull, int D>
PassSums gn_pass_baseline(const PassInput& in) {
  return gn_pass_body<2, kFull, D>(in);
}
#if VCMM_GEOMETRY_X86
template <bool kFull, int D>
__attribute__((target("avx2"))) PassSums gn_pass_avx2(const PassInput& in) {
  return gn_pass_body<4, kFull, D>(in);
}

/// The AVX-512 variant: the terms of 8 points in one vector, added to the four-lane sums as
/// its low half, then its high half — the points i..i+3, then i+4..i+7, into lanes 0..3: the
/// additions of the AVX2 variant in its order, so the same bits. Two sums share an 8-lane
/// accumulator (lanes 0..3 the one, 4..7 the other): one shuffle and one addition per half for
/// both. Then 4 points more if n mod 8 ≥ 4, and the tail as there. (The extremes are
/// order-free: 8 lanes.)
template <bool kFull, int D>
__attribute__((target("avx512f"))) PassSums gn_pass_avx512(const PassInput& input) {
  const PassInput in = input;
  using V8 = Lanes<8>;
  using V4 = Lanes<4>;
  using internal::high_halves;
  using internal::low_halves;
  V8 d_dd{}, vx_vy{}, vxd_vyd{}, vxx_vyy{};
  V4 vxy{};
  PassLanes<V8> e;  // the extremes only
  std::size_t i = 0;
  for (; i + 8 <= in.n; i += 8) {
    const PassTerms<V8> t = pass_terms<kFull, D, V8>(in, i);
    add_extremes<D>(e, t);
    if constexpr (kFull) {
      vxx_vyy += low_halves(t.vxx, t.vyy);
      vxx_vyy += high_halves(t.vxx, t.vyy);
      internal::add_in_point_order(vxy, t.vxy);
    }
    d_dd += low_halves(t.d, t.dd);
    d_dd += high_halves(t.d, t.dd);
    vx_vy += low_halves(t.vx, t.vy);
    vx_vy += high_halves(t.vx, t.vy);
    vxd_vyd += low_halves(t.vxd, t.vyd);
    vxd_vyd += high_halves(t.vxd, t.vyd);
  }
  PassLanes<V4> a[1];
  a[0].sd = internal::low_half(d_dd);
  a[0].sdd = internal::high_half(d_dd);
  a[0].svx = internal::low_half(vx_vy);
  a[0].svy = internal::high_half(vx_vy);
  a[0].svxd = internal::low_half(vxd_vyd);
  a[0].svyd = internal::high_half(vxd_vyd);
  a[0].svxx = internal::low_half(vxx_vyy);
  a[0].svyy = internal::high_half(vxx_vyy);
  a[0].svxy = vxy;
  a[0].rmax = lanes_max(internal::low_half(e.rmax), internal::high_half(e.rmax));
  a[0].rmin = lanes_min(internal::low_half(e.rmin), internal::high_half(e.rmin));
  a[0].smax = lanes_max(internal::low_half(e.smax), internal::high_half(e.smax));
  if (i + 4 <= in.n) {
    pass_points<kFull, D>(in, i, a[0]);
    i += 4;
  }
  return finish_pass<kFull, D, 4, 1>(in, i, a);
}
#endif

template <bool kFull, int D>
PassSums gn_pass_variant(const PassInput& in) {
#if VCMM_GEOMETRY_X86
  if (internal::use_avx512()) return gn_pass_avx512<kFull, D>(in);
  if (internal::use_avx2()) return gn_pass_avx2<kFull, D>(in);
#endif
  return gn_pass_baseline<kFull, D>(in);
}

/// The pass with the series of the given degree (3, 4, 6), or square root and division (0).
template <bool kFull>
PassSums gn_pass(const PassInput& in, int degree) {
  switch (degree) {
    case 3: return gn_pass_variant<kFull, 3>(in);
    case 4: return gn_pass_variant<kFull, 4>(in);
    case 6: return gn_pass_variant<kFull, 6>(in);
    default: return gn_pass_variant<kFull, 0>(in);
  }
}

// ---- two-lane sums in AVX-512 registers ------------------------------------------------------
// Sums kept in two lanes (lane 0 the even points, lane 1 the odd ones, each in point order) are
// latency-bound: one addition per two points and sum. The AVX-512 variants below keep four
// such sums side by side in an 8-lane accumulator, [s₀ | s₁ | s₂ | s₃], and add the four
// 2-point packets of a block of 8 points in order: the additions of the 2-lane code in its
// order (the same bits), a quarter of the additions.

/// [a | b | c | d] from four 2-lane sums.
[[gnu::always_inline]] inline Lanes<8> join_packets(const Lanes<2>& a, const Lanes<2>& b,
                                                    const Lanes<2>& c, const Lanes<2>& d) {
  const Lanes<4> ab = __builtin_shufflevector(a, b, 0, 1, 2, 3);
  const Lanes<4> cd = __builtin_shufflevector(c, d, 0, 1, 2, 3);
  return __builtin_shufflevector(ab, cd, 0, 1, 2, 3, 4, 5, 6, 7);
}

/// The 2-lane packet k (lanes 2k, 2k + 1) of v.
[[gnu::always_inline]] inline Lanes<2> part(const Lanes<8>& v, int k) {
  return k == 0   ? Lanes<2>(__builtin_shufflevector(v, v, 0, 1))
         : k == 1 ? Lanes<2>(__builtin_shufflevector(v, v, 2, 3))
         : k == 2 ? Lanes<2>(__builtin_shufflevector(v, v, 4, 5))
                  : Lanes<2>(__builtin_shufflevector(v, v, 6, 7));
}

/// The eight 2-lane sums [a | b | c | d] and [e | f | g | h] back into *sums[k] (k = 0..7;
/// a null pointer drops its sum).
[[gnu::always_inline]] inline void split_packets(const Lanes<8>& acc_a, const Lanes<8>& acc_b,
                                                 Lanes<2>* const (&sums)[8]) {
  for (int k = 0; k < 8; ++k)
    if (sums[k]) *sums[k] = part(k < 4 ? acc_a : acc_b, k % 4);
}

/// acc_a += packets k = 0..3 of [a | b | c | d], acc_b of [e | f | g | h], in order k: the
/// per-point terms of 8 sums over 8 points (a 4 × 4 transpose of 2-lane packets each).
[[gnu::always_inline]] inline void add_packets(Lanes<8>& acc_a, Lanes<8>& acc_b,
                                               const Lanes<8>& a, const Lanes<8>& b,
                                               const Lanes<8>& c, const Lanes<8>& d,
                                               const Lanes<8>& e, const Lanes<8>& f,
                                               const Lanes<8>& g, const Lanes<8>& h) {
  // [a₀ b₀ a₁ b₁] and [a₂ b₂ a₃ b₃] (2-lane packets), the same for c, d and so on.
  const Lanes<8> ab_lo = __builtin_shufflevector(a, b, 0, 1, 8, 9, 2, 3, 10, 11);
  const Lanes<8> ab_hi = __builtin_shufflevector(a, b, 4, 5, 12, 13, 6, 7, 14, 15);
  const Lanes<8> cd_lo = __builtin_shufflevector(c, d, 0, 1, 8, 9, 2, 3, 10, 11);
  const Lanes<8> cd_hi = __builtin_shufflevector(c, d, 4, 5, 12, 13, 6, 7, 14, 15);
  const Lanes<8> ef_lo = __builtin_shufflevector(e, f, 0, 1, 8, 9, 2, 3, 10, 11);
  const Lanes<8> ef_hi = __builtin_shufflevector(e, f, 4, 5, 12, 13, 6, 7, 14, 15);
  const Lanes<8> gh_lo = __builtin_shufflevector(g, h, 0, 1, 8, 9, 2, 3, 10, 11);
  const Lanes<8> gh_hi = __builtin_shufflevector(g, h, 4, 5, 12, 13, 6, 7, 14, 15);
  acc_a += __builtin_shufflevector(ab_lo, cd_lo, 0, 1, 2, 3, 8, 9, 10, 11);
  acc_b += __builtin_shufflevector(ef_lo, gh_lo, 0, 1, 2, 3, 8, 9, 10, 11);
  acc_a += __builtin_shufflevector(ab_lo, cd_lo, 4, 5, 6, 7, 12, 13, 14, 15);
  acc_b += __builtin_shufflevector(ef_lo, gh_lo, 4, 5, 6, 7, 12, 13, 14, 15);
  acc_a += __builtin_shufflevector(ab_hi, cd_hi, 0, 1, 2, 3, 8, 9, 10, 11);
  acc_b += __builtin_shufflevector(ef_hi, gh_hi, 0, 1, 2, 3, 8, 9, 10, 11);
  acc_a += __builtin_shufflevector(ab_hi, cd_hi, 4, 5, 6, 7, 12, 13, 14, 15);
  acc_b += __builtin_shufflevector(ef_hi, gh_hi, 4, 5, 6, 7, 12, 13, 14, 15);
}

// ---- the load pass ---------------------------------------------------------------------------
// One pass over the input points (x, y pairs): the local coordinates p_i − p₀ into the
// workspace, the extent of the raw coordinates and the moments of the Kåsa start, each moment
// a two-lane sum (lane 0 the even points, lane 1 the odd ones, each in point order; the lanes
// are added at the end) — the order of the original SSE2 pass, kept by every variant below, so
// the start circle has the same bits whichever runs.

/// The two-lane moments and, per coordinate (lane 0 x, lane 1 y), the extremes.
struct LoadSums {
  Lanes<2> sx{}, sy{}, sxx{}, syy{}, sxy{}, sxz{}, syz{};
  Lanes<2> lo, hi;
};

/// Points i and i + 1 (p: the points as x, y pairs).
[[gnu::always_inline]] inline void load_pair(const double* p, std::size_t i, Point2 shift,
                                             double* xs, double* ys, LoadSums& m) {
  const Lanes<2> a = internal::load<Lanes<2>>(p + 2 * i);
  const Lanes<2> b = internal::load<Lanes<2>>(p + 2 * i + 2);
  m.lo = lanes_min(m.lo, lanes_min(a, b));
  m.hi = lanes_max(m.hi, lanes_max(a, b));
  const Lanes<2> x = __builtin_shufflevector(a, b, 0, 2) - shift.x;
  const Lanes<2> y = __builtin_shufflevector(a, b, 1, 3) - shift.y;
  internal::store(xs + i, x);
  internal::store(ys + i, y);
  const Lanes<2> xx = x * x, yy = y * y;
  const Lanes<2> z = xx + yy;
  m.sx += x;
  m.sy += y;
  m.sxx += xx;
  m.syy += yy;
  m.sxy += x * y;
  m.sxz += x * z;
  m.syz += y * z;
}

#if VCMM_GEOMETRY_X86
/// The load pass on blocks of 8 points from 0 while they fit below `packed`; returns the
/// first point not taken. Element-wise the operations of load_pair, the moments added as
/// there (add_packets).
__attribute__((target("avx512f"))) std::size_t load_blocks_avx512(const double* p,
                                                                  std::size_t packed,
                                                                  Point2 shift, double* xs,
                                                                  double* ys, LoadSums& m) {
  using V8 = Lanes<8>;
  V8 acc_a = join_packets(m.sx, m.sy, m.sxx, m.syy);         // [sx | sy | sxx | syy]
  V8 acc_b = join_packets(m.sxy, m.sxz, m.syz, Lanes<2>{});  // [sxy | sxz | syz | 0]
  V8 lo = join_packets(m.lo, m.lo, m.lo, m.lo), hi = join_packets(m.hi, m.hi, m.hi, m.hi);
  std::size_t i = 0;
  for (; i + 8 <= packed; i += 8) {
    const V8 a = internal::load<V8>(p + 2 * i), b = internal::load<V8>(p + 2 * i + 8);
    lo = lanes_min(lo, lanes_min(a, b));
    hi = lanes_max(hi, lanes_max(a, b));
    const V8 x = __builtin_shufflevector(a, b, 0, 2, 4, 6, 8, 10, 12, 14) - shift.x;
    const V8 y = __builtin_shufflevector(a, b, 1, 3, 5, 7, 9, 11, 13, 15) - shift.y;
    internal::store(xs + i, x);
    internal::store(ys + i, y);
    const V8 xx = x * x, yy = y * y;
    const V8 z = xx + yy;
    const V8 xy = x * y, xz = x * z, yz = y * z;
    add_packets(acc_a, acc_b, x, y, xx, yy, xy, xz, yz, V8{});
  }
  split_packets(acc_a, acc_b, {&m.sx, &m.sy, &m.sxx, &m.syy, &m.sxy, &m.sxz, &m.syz, nullptr});
  for (int k = 0; k < 4; ++k) {
    m.lo = lanes_min(m.lo, part(lo, k));
    m.hi = lanes_max(m.hi, part(hi, k));
  }
  return i;
}
#endif

// ---- points on rays ---------------------------------------------------------------------------
// least_squares_circle_on_rays's two passes. Pass 1: the unit directions (stored) and eight
// sums in two lanes (as the load pass; ray_pair, ray_blocks_avx512). Pass 2: the residuals
// (stored), their extremes and two sums in four lanes (lane j the points i ≡ j mod 4, added as
// (l₀ + l₂) + (l₁ + l₃)) — with AVX-512 the halves of 8 points in point order, as the GN passes.

struct RayInput {
  const double* w;
  const double* ray_x;
  const double* ray_y;
  const double* inv_length;
  double* ux;
  double* uy;
};

/// The eight sums of pass 1 (two lanes each).
struct RaySums {
  Lanes<2> w{}, ux{}, uy{}, uxw{}, uyw{}, uxx{}, uxy{}, uyy{};
};

/// Points i, i + 1 of pass 1.
[[gnu::always_inline]] inline void ray_pair(const RayInput& in, std::size_t i, RaySums& m) {
  const Lanes<2> inv = internal::load<Lanes<2>>(in.inv_length + i);
  const Lanes<2> x = internal::load<Lanes<2>>(in.ray_x + i) * inv;
  const Lanes<2> y = internal::load<Lanes<2>>(in.ray_y + i) * inv;
  const Lanes<2> w = internal::load<Lanes<2>>(in.w + i);
  internal::store(in.ux + i, x);
  internal::store(in.uy + i, y);
  m.w += w;
  m.ux += x;
  m.uy += y;
  m.uxw += x * w;
  m.uyw += y * w;
  m.uxx += x * x;
  m.uxy += x * y;
  m.uyy += y * y;
}

/// The residual sums of pass 2 (lanes as described above, or one point: V = double).
template <class V>
struct ResidualLanes {
  V max = V{} - std::numeric_limits<double>::infinity();
  V min = V{} + std::numeric_limits<double>::infinity();
  V e{}, ee{};
};

struct ResidualInput {
  const double* w;
  const double* ux;
  const double* uy;
  double* e;
  double dx, dy;
};

/// The residuals of the points at i (V = Lanes<W> or double): stored, their terms returned.
template <class V>
[[gnu::always_inline]] inline V residuals(const ResidualInput& in, std::size_t i) {
  const V ei = internal::load<V>(in.w + i) -
               (internal::load<V>(in.ux + i) * in.dx + internal::load<V>(in.uy + i) * in.dy);
  internal::store(in.e + i, ei);
  return ei;
}

template <class V>
[[gnu::always_inline]] inline void add_residuals(const ResidualInput& in, std::size_t i,
                                                 ResidualLanes<V>& a) {
  const V ei = residuals<V>(in, i);
  a.max = lanes_max(a.max, ei);
  a.min = lanes_min(a.min, ei);
  a.e += ei;
  a.ee += ei * ei;
}

#if VCMM_GEOMETRY_X86
/// Pass 1 on blocks of 8 points from 0 while they fit below `packed`; returns the first point
/// not taken. Element-wise the operations of ray_pair, the sums added as there (add_packets).
__attribute__((target("avx512f"))) std::size_t ray_blocks_avx512(const RayInput& in,
                                                                 std::size_t packed,
                                                                 RaySums& m) {
  using V8 = Lanes<8>;
  V8 acc_a = join_packets(m.w, m.ux, m.uy, m.uxw);     // [w | ux | uy | uxw]
  V8 acc_b = join_packets(m.uyw, m.uxx, m.uxy, m.uyy);  // [uyw | uxx | uxy | uyy]
  std::size_t i = 0;
  for (; i + 8 <= packed; i += 8) {
    const V8 inv = internal::load<V8>(in.inv_length + i);
    const V8 x = internal::load<V8>(in.ray_x + i) * inv;
    const V8 y = internal::load<V8>(in.ray_y + i) * inv;
    const V8 w = internal::load<V8>(in.w + i);
    internal::store(in.ux + i, x);
    internal::store(in.uy + i, y);
    add_packets(acc_a, acc_b, w, x, y, x * w, y * w, x * x, x * y, y * y);
  }
  split_packets(acc_a, acc_b, {&m.w, &m.ux, &m.uy, &m.uxw, &m.uyw, &m.uxx, &m.uxy, &m.uyy});
  return i;
}

/// Pass 2 on blocks of 8 points from 0 while they fit below `packed`, into the four lanes of
/// a (the halves of each block in point order); returns the first point not taken.
__attribute__((target("avx512f"))) std::size_t residual_blocks_avx512(const ResidualInput& in,
                                                                      std::size_t packed,
                                                                      ResidualLanes<Lanes<4>>& a) {
  using V8 = Lanes<8>;
  V8 e_ee = internal::concat(a.e, a.ee);  // [e | ee]
  ResidualLanes<V8> x;  // the extremes
  std::size_t i = 0;
  for (; i + 8 <= packed; i += 8) {
    const V8 ei = residuals<V8>(in, i);
    x.max = lanes_max(x.max, ei);
    x.min = lanes_min(x.min, ei);
    const V8 sq = ei * ei;
    e_ee += internal::low_halves(ei, sq);
    e_ee += internal::high_halves(ei, sq);
  }
  a.e = internal::low_half(e_ee);
  a.ee = internal::high_half(e_ee);
  a.max = lanes_max(a.max, lanes_max(internal::low_half(x.max), internal::high_half(x.max)));
  a.min = lanes_min(a.min, lanes_min(internal::low_half(x.min), internal::high_half(x.min)));
  return i;
}
#endif

/// Per-thread scratch arrays, kept between calls: reallocating ~1 MB per call at n = 36 000
/// cost ~100 page faults and a quarter of the run time.
struct Workspace {
  std::vector<double> x, y, r;
};

class Fitter {
 public:
  /// Sizes the structure-of-arrays workspace; the data enter it in load_and_kasa_start.
  Fitter(std::span<const Point2> points, Workspace& ws)
      : n_(static_cast<Eigen::Index>(points.size())),
        packed_(n_ - n_ % kLanes),
        shift_(points[0]) {
    ws.x.resize(points.size());
    ws.y.resize(points.size());
    ws.r.resize(points.size());
    x_ = ws.x.data();
    y_ = ws.y.data();
    r_ = ws.r.data();
  }

  /// One pass over the input: the local coordinates p_i − p₀ into the workspace, the span
  /// check (check_span, on the raw coordinates) and the moments of the Kåsa start below.
  /// With SSE2 two points are loaded as two packets and unpacked into an x and a y packet
  /// (load_pair; blocks of 8 with AVX-512, load_blocks_avx512); every sum is accumulated
  /// exactly as from the stored arrays (same packets, same order).
  /// check: when set, the checks of validate_profile(points, check->min_points,
  /// check->caller) beyond the count (which the caller has made), in the same order with the
  /// same messages, the finiteness of every coordinate decided from the moments of this pass.
  void load_and_kasa_start(std::span<const Point2> points, const internal::ProfileCheck* check,
                           double& cx, double& cy, double& radius) {
    Packet sx = simd::pset1<Packet>(0.0), sy = sx, sxx = sx, syy = sx, sxy = sx, sxz = sx,
           syz = sx;
#if defined(__SSE2__) && !defined(__AVX__)
    static_assert(kLanes == 2 && sizeof(Point2) == 2 * sizeof(double));
    const double* p = reinterpret_cast<const double*>(points.data());
    LoadSums m;
    m.lo = m.hi = internal::load<Lanes<2>>(p);  // per coordinate: lane 0 x, lane 1 y
    std::size_t i = 0;
    const auto packed = static_cast<std::size_t>(packed_);
#if VCMM_GEOMETRY_X86
    if (internal::use_avx512()) i = load_blocks_avx512(p, packed, shift_, x_, y_, m);
#endif
    for (; i < packed; i += 2) load_pair(p, i, shift_, x_, y_, m);
    sx = m.sx;
    sy = m.sy;
    sxx = m.sxx;
    syy = m.syy;
    sxy = m.sxy;
    sxz = m.sxz;
    syz = m.syz;
    Extent extent{std::min(m.lo[0], points[0].x), std::max(m.hi[0], points[0].x),
                  std::min(m.lo[1], points[0].y), std::max(m.hi[1], points[0].y)};
    bool finite = true;
    for (Eigen::Index j = packed_; j < n_; ++j) {
      const Point2 q = points[static_cast<std::size_t>(j)];
      extent = {std::min(extent.x0, q.x), std::max(extent.x1, q.x), std::min(extent.y0, q.y),
                std::max(extent.y1, q.y)};
      x_[j] = q.x - shift_.x;
      y_[j] = q.y - shift_.y;
      finite = finite && std::isfinite(q.x) && std::isfinite(q.y);
    }
    if (check) {
      // A coordinate that is not finite makes x² or y² of its point (p − p₀; for p₀ itself
      // ∞ − ∞) +∞ or NaN, and a lane sum that takes one stays so: finite lane sums of x² and
      // y² prove every packed coordinate finite. (Sums that overflow on finite data only
      // send the search to validate_profile, which finds nothing; check_span then refuses.)
      const Lanes<2> squares = m.sxx + m.syy;
      if (!(finite && std::isfinite(squares[0]) && std::isfinite(squares[1])))
        validate_profile(points, check->min_points, check->caller);
      internal::validate_profile_shape(points, check->min_points, check->caller,
                                       /*require_non_collinear=*/true);
    }
    check_span(extent);
#else
    if (check) validate_profile(points, check->min_points, check->caller);
    const auto accumulate = [&](Packet x, Packet y) {
      const Packet xx = simd::pmul(x, x), yy = simd::pmul(y, y);
      const Packet z = simd::padd(xx, yy);
      sx = simd::padd(sx, x);
      sy = simd::padd(sy, y);
      sxx = simd::padd(sxx, xx);
      syy = simd::padd(syy, yy);
      sxy = simd::pmadd(x, y, sxy);
      sxz = simd::pmadd(x, z, sxz);
      syz = simd::pmadd(y, z, syz);
    };
    check_span(extent_of(points));
    for (std::size_t i = 0; i < points.size(); ++i) {
      x_[i] = points[i].x - shift_.x;
      y_[i] = points[i].y - shift_.y;
    }
    for (Eigen::Index i = 0; i < packed_; i += kLanes)
      accumulate(simd::ploadu<Packet>(x_ + i), simd::ploadu<Packet>(y_ + i));
#endif
    kasa_start(sx, sy, sxx, syy, sxy, sxz, syz, cx, cy, radius);
  }

 private:
  /// Kåsa (algebraic) circle of the local data, min Σ (x² + y² − 2ax − 2by − k)²: start
  /// centre and radius, from the packet moments of the whole packets (the rest is added
  /// here). Moments about p₀, centred afterwards (the offset is ~R, so the centring loses a
  /// digit or two at most — plenty for a start). Also sets the centroid.
  void kasa_start(Packet sx, Packet sy, Packet sxx, Packet syy, Packet sxy, Packet sxz,
                  Packet syz, double& cx, double& cy, double& radius) {
    const double nd = static_cast<double>(n_);
    double m_x = simd::predux(sx), m_y = simd::predux(sy), m_xx = simd::predux(sxx),
           m_yy = simd::predux(syy), m_xy = simd::predux(sxy), m_xz = simd::predux(sxz),
           m_yz = simd::predux(syz);
    for (Eigen::Index i = packed_; i < n_; ++i) {
      const double x = x_[i], y = y_[i], z = x * x + y * y;
      m_x += x;
      m_y += y;
      m_xx += x * x;
      m_yy += y * y;
      m_xy += x * y;
      m_xz += x * z;
      m_yz += y * z;
    }
    // Centred moments about the centroid g: C_ab = Σ a b − n g_a g_b, z centred too.
    const double gx = m_x / nd, gy = m_y / nd, gz = (m_xx + m_yy) / nd;
    const double cxx = m_xx - m_x * gx, cyy = m_yy - m_y * gy, cxy = m_xy - m_x * gy;
    const double cxz = m_xz - m_x * gz, cyz = m_yz - m_y * gz;
    const double det = cxx * cyy - cxy * cxy;
    if (!(det > 0.0) || !std::isfinite(det)) {
      // validate_profile has excluded exactly collinear data; this is its floating-point twin
      // (check_span has excluded spans whose moments leave the double range).
      std::ostringstream os;
      os << kCaller << ": no circle can be fitted in double precision: the points are "
         << "numerically collinear (algebraic-fit determinant " << det << ")";
      throw InvalidInput(os.str());
    }
    // Centred normal equations [cxx cxy; cxy cyy] (2a, 2b) = (cxz, cyz). As z is not
    // re-expressed about g, (a, b) is the centre itself in the local frame.
    const double a = 0.5 * (cyy * cxz - cxy * cyz) / det;
    const double b = 0.5 * (cxx * cyz - cxy * cxz) / det;
    cx = a;
    cy = b;
    // R² = mean |p − c|² = |g − c|² + mean |p − g|² (Kåsa's k).
    radius = std::sqrt((gx - a) * (gx - a) + (gy - b) * (gy - b) + (cxx + cyy) / nd);
    centroid_ = {gx, gy};
  }


 public:
  /// One Gauss-Newton pass at centre (cx, cy) (gn_pass): distances stored in r_, sums about
  /// the reference radius r0, by the series of near_circle.h where they are valid.
  PassSums evaluate(bool full, double cx, double cy, double r0, double urx, double ury,
                    int degree) {
    const PassInput in{x_, y_, r_, static_cast<std::size_t>(n_), cx, cy, r0, urx, ury,
                       degree > 0 ? internal::near_circle_about(r0) : internal::NearCircle{}};
    return full ? gn_pass<true>(in, degree) : gn_pass<false>(in, degree);
  }

  /// First index of a stored distance equal to r (one of its values).
  std::size_t first_distance_index(double r) const { return first_index(r_, n_, r); }

  Eigen::Index size() const { return n_; }
  Point2 shift() const { return shift_; }
  Point2 centroid() const { return centroid_; }  ///< local frame; set by kasa_start

 private:
  Eigen::Index n_;
  Eigen::Index packed_;  ///< points handled by whole packets
  Point2 shift_;
  Point2 centroid_;
  double* x_ = nullptr;  // local coordinates and distances, in the workspace
  double* y_ = nullptr;
  double* r_ = nullptr;
};

[[noreturn]] void throw_not_circular(const char* what, double value, int iteration) {
  std::ostringstream os;
  os << kCaller << ": Gauss-Newton " << what << " " << value << " at iteration " << iteration
     << "; the data are too close to a straight line to fit a circle in double precision";
  throw UndefinedResult(os.str());
}

}  // namespace

namespace {

LeastSquaresCircle fit_circle(std::span<const Point2> points,
                              const internal::ProfileCheck* check);

}  // namespace

LeastSquaresCircle least_squares_circle(std::span<const Point2> points) {
  // validate_profile(points, 3, kCaller): the count here, the rest in the fit's first pass.
  if (points.size() < 3) validate_profile(points, 3, kCaller);
  const internal::ProfileCheck check{3, kCaller};
  return fit_circle(points, &check);
}

LeastSquaresCircle internal::fit_least_squares_circle(std::span<const Point2> points) {
  return fit_circle(points, nullptr);
}

LeastSquaresCircle internal::fit_least_squares_circle_checked(std::span<const Point2> points,
                                                              const ProfileCheck& check) {
  const std::size_t min_points = std::max<std::size_t>(check.min_points, 3);
  if (points.size() < min_points) validate_profile(points, min_points, check.caller);
  return fit_circle(points, &check);
}

namespace {

LeastSquaresCircle fit_circle(std::span<const Point2> points,
                              const internal::ProfileCheck* check) {
  thread_local Workspace workspace;
  Fitter fit(points, workspace);
  const double nd = static_cast<double>(fit.size());

  double cx = 0.0, cy = 0.0, r0 = 0.0;
  fit.load_and_kasa_start(points, check, cx, cy, r0);
  // Shift for the directions in M: ≈ ū ≈ (centroid − c) / R — zero for a full circle,
  // towards the arc's middle for an arc.
  const Point2 g = fit.centroid();
  const double urx = (g.x - cx) / r0, ury = (g.y - cy) / r0;

  constexpr int kMaxIterations = 100;
  constexpr double kStepTolerance = 0x1.0p-52;  // relative to R: one ulp, the floor of r_i
  constexpr double kNoiseRegime = 1e-9;         // relative step below which stagnation stops
  constexpr double kFullPassStep = 1e-8;        // relative step after which M is re-formed
  constexpr double kEps = std::numeric_limits<double>::epsilon();

  // Last centre where a full pass was accepted, its objective and its step.
  double prev_cx = cx, prev_cy = cy, prev_f = std::numeric_limits<double>::infinity();
  double prev_dx = 0.0, prev_dy = 0.0, prev_step = std::numeric_limits<double>::infinity();
  double lambda = 1.0;  // backtracking factor on the previous full step
  bool full = true;
  double mxx = 0.0, mxy = 0.0, myy = 0.0;  // M of (1), from the last full pass
  int iterations = 0;
  double mean_d = 0.0;
  // Distances by the series of near_circle.h where |s| allows (degree 3, 4 or 6; 0: square
  // root and division). The first pass, at the Kåsa centre, assumes the deviations of a
  // roundness profile (kFirstDegree); each later pass takes the smallest degree whose range
  // covers every point as bounded from the previous pass. A pass whose points leave its range
  // (its max |s| says so) is redone at once with the degree that max |s| needs: |s| does not
  // depend on the degree, so never twice. The redo is not an iteration.
  constexpr int kFirstDegree = 4;
  int degree = internal::near_circle_radius_ok(r0) ? kFirstDegree : 0;
  PassSums s;  // the last pass
  const auto evaluate = [&](bool full_pass, double ux, double uy) {
    s = fit.evaluate(full_pass, cx, cy, r0, ux, uy, degree);
    if (degree > 0 && !(s.s_max <= internal::near_circle_s_max(degree))) {
      degree = internal::near_circle_degree(s.s_max);
      s = fit.evaluate(full_pass, cx, cy, r0, ux, uy, degree);
    }
    ++iterations;
  };
  // The degree for a pass whose centre has moved by `moved` from the last pass's, about
  // reference radius r0_next: each distance moves by at most `moved`.
  const auto predict = [&](double moved, double r0_next) {
    degree = internal::near_circle_degree_for(
        r0_next, std::max(s.r_max - r0_next, r0_next - s.r_min) + moved);
  };
  for (;;) {
    evaluate(full, urx, ury);
    mean_d = s.sum_d / nd;
    const double radius = r0 + mean_d;
    if (!std::isfinite(radius)) throw_not_circular("produced a non-finite radius", radius,
                                                   iterations);
    const double vbx = s.sum_vx / nd, vby = s.sum_vy / nd;
    const double ubx = full ? vbx + urx : vbx, uby = full ? vby + ury : vby;  // ū
    if (full) {
      const double f = std::max(0.0, s.sum_dd - nd * mean_d * mean_d);
      // Backtracking: an increase beyond the rounding noise of F halves the previous step.
      // Each d_i carries an error of a few ulps of the distance scale (R + |c|), so F = Σ e²
      // is uncertain by ~2 Σ|e_i| · that, and Σ|e_i| ≤ sqrt(n F) (Cauchy-Schwarz).
      const double scale = radius + std::hypot(cx, cy);
      const double f_noise = 16.0 * kEps * scale * std::sqrt(nd * prev_f) +
                             64.0 * kEps * prev_f + nd * (kEps * scale) * (kEps * scale);
      if (f > prev_f + f_noise) {
        lambda *= 0.5;
        if (lambda < 0x1.0p-40 || iterations >= kMaxIterations) {
          // No decrease along the GN direction: the previous full iterate is stationary to
          // within rounding. Re-evaluate there so that R and the residuals refer to it.
          predict(std::hypot(prev_cx - cx, prev_cy - cy), r0);
          cx = prev_cx;
          cy = prev_cy;
          evaluate(false, 0.0, 0.0);
          mean_d = s.sum_d / nd;
          break;
        }
        const double next_x = prev_cx + lambda * prev_dx, next_y = prev_cy + lambda * prev_dy;
        predict(std::hypot(next_x - cx, next_y - cy), r0);
        cx = next_x;
        cy = next_y;
        continue;
      }
      prev_f = f;
      mxx = s.sum_vxx - nd * vbx * vbx;
      mxy = s.sum_vxy - nd * vbx * vby;
      myy = s.sum_vyy - nd * vby * vby;
    }
    // GN step (1) with the shifted sums.
    const double bx = s.sum_vxd - mean_d * s.sum_vx;
    const double by = s.sum_vyd - mean_d * s.sum_vy;
    const double det = mxx * myy - mxy * mxy;
    if (!(det > 0.0) || !std::isfinite(det))
      throw_not_circular("normal matrix is singular: determinant", det, iterations);
    const double dx = (myy * bx - mxy * by) / det;
    const double dy = (mxx * by - mxy * bx) / det;
    const double step = std::hypot(dx, dy);
    const bool converged = step <= kStepTolerance * radius;
    const bool stagnating = step <= kNoiseRegime * radius && step > 0.5 * prev_step;
    if (converged || stagnating) break;
    if (iterations >= kMaxIterations)
      throw_not_circular("did not converge in 100 iterations; last step", step, iterations);
    if (!full && step > kFullPassStep * radius) {
      // A large step from a stale M (rare): redo this centre with a full pass instead.
      full = true;
      prev_f = std::numeric_limits<double>::infinity();
      continue;
    }
    if (full) {
      prev_cx = cx;
      prev_cy = cy;
      prev_dx = dx;
      prev_dy = dy;
      lambda = 1.0;
    }
    prev_step = step;
    full = step > kFullPassStep * radius;
    // New reference radius: r̄ at the new centre to first order (r_i(c+δ) ≈ r_i − u_i·δ),
    // so that the next d_i stay small.
    r0 = radius - (ubx * dx + uby * dy);
    predict(step, r0);
    cx += dx;
    cy += dy;
  }

  LeastSquaresCircle out;
  const Point2 shift = fit.shift();
  out.center = {shift.x + cx, shift.y + cy};
  out.radius = r0 + mean_d;
  out.iterations = iterations;
  // Residuals about (centre, R), from the last pass: e_i = (r_i − R₀) − d̄, Σ e² = Σ d² − n d̄².
  // Contacts: the first positions of the extreme distances (lowest index wins ties).
  out.contacts = {fit.first_distance_index(s.r_max), fit.first_distance_index(s.r_min)};
  const double emax = (s.r_max - r0) - mean_d;
  const double emin = (s.r_min - r0) - mean_d;
  out.ron.ront = emax - emin;
  out.ron.ronp = std::max(0.0, emax);
  out.ron.ronv = std::max(0.0, -emin);
  out.ron.ronq = std::sqrt(std::max(0.0, s.sum_dd - nd * mean_d * mean_d) / nd);
  return out;
}

}  // namespace

std::optional<LeastSquaresCircle> internal::least_squares_circle_on_rays(
    Point2 center, double radius, const double* w, const double* ray_x, const double* ray_y,
    const double* inv_length, std::size_t count) {
  const std::size_t n = count, packed = n - n % 2;
  const double nd = static_cast<double>(n);
  thread_local Workspace ws;
  ws.x.resize(count);
  ws.y.resize(count);
  ws.r.resize(count);
  double* ux = ws.x.data();
  double* uy = ws.y.data();
  double* e = ws.r.data();
#if VCMM_GEOMETRY_X86
  const bool avx512 = internal::use_avx512();
#endif

  // Pass 1: unit directions (stored for pass 2) and the sums of the GN step at the centre.
  const RayInput rays{w, ray_x, ray_y, inv_length, ux, uy};
  RaySums m;
  std::size_t i = 0;
#if VCMM_GEOMETRY_X86
  if (avx512) i = ray_blocks_avx512(rays, packed, m);
#endif
  for (; i < packed; i += 2) ray_pair(rays, i, m);
  double s_w = m.w[0] + m.w[1], s_ux = m.ux[0] + m.ux[1], s_uy = m.uy[0] + m.uy[1];
  double s_uxw = m.uxw[0] + m.uxw[1], s_uyw = m.uyw[0] + m.uyw[1];
  double s_uxx = m.uxx[0] + m.uxx[1], s_uxy = m.uxy[0] + m.uxy[1];
  double s_uyy = m.uyy[0] + m.uyy[1];
  for (i = packed; i < n; ++i) {
    const double x = ray_x[i] * inv_length[i], y = ray_y[i] * inv_length[i];
    ux[i] = x;
    uy[i] = y;
    s_w += w[i];
    s_ux += x;
    s_uy += y;
    s_uxw += x * w[i];
    s_uyw += y * w[i];
    s_uxx += x * x;
    s_uxy += x * y;
    s_uyy += y * y;
  }
  const double wbar = s_w / nd, ubx = s_ux / nd, uby = s_uy / nd;
  const double mxx = s_uxx - nd * ubx * ubx, mxy = s_uxy - nd * ubx * uby;
  const double myy = s_uyy - nd * uby * uby;
  const double bx = s_uxw - wbar * s_ux, by = s_uyw - wbar * s_uy;
  const double det = mxx * myy - mxy * mxy;
  if (!(det > 0.0) || !std::isfinite(det)) return std::nullopt;
  const double dx = (myy * bx - mxy * by) / det;
  const double dy = (mxx * by - mxy * bx) / det;
  const double step = std::hypot(dx, dy);
  if (!(step <= 0x1.0p-30 * radius)) return std::nullopt;

  // Pass 2: residuals about R, e_i = w_i − u_i·δ (the distance from c + δ minus R), in four
  // lanes: two 2-lane packets an iteration (one AVX-512 vector of 8 points), a last packet
  // into lanes 0 and 1, the last point alone.
  const ResidualInput res{w, ux, uy, e, dx, dy};
  ResidualLanes<Lanes<4>> r4;
  i = 0;
#if VCMM_GEOMETRY_X86
  if (avx512) i = residual_blocks_avx512(res, packed, r4);
#endif
  ResidualLanes<Lanes<2>> r2[2];
  for (int h = 0; h < 2; ++h) {  // r4 as two packets
    r2[h].max = Lanes<2>{r4.max[2 * h], r4.max[2 * h + 1]};
    r2[h].min = Lanes<2>{r4.min[2 * h], r4.min[2 * h + 1]};
    r2[h].e = Lanes<2>{r4.e[2 * h], r4.e[2 * h + 1]};
    r2[h].ee = Lanes<2>{r4.ee[2 * h], r4.ee[2 * h + 1]};
  }
  for (; i + 4 <= packed; i += 4) {
    add_residuals(res, i, r2[0]);
    add_residuals(res, i + 2, r2[1]);
  }
  if (i < packed) add_residuals(res, i, r2[0]);
  const Lanes<2> lane_max = lanes_max(r2[0].max, r2[1].max);
  const Lanes<2> lane_min = lanes_min(r2[0].min, r2[1].min);
  const Lanes<2> lane_e = r2[0].e + r2[1].e, lane_ee = r2[0].ee + r2[1].ee;
  double e_max = std::max(lane_max[0], lane_max[1]);
  double e_min = std::min(lane_min[0], lane_min[1]);
  double s_e = lane_e[0] + lane_e[1];
  double s_ee = lane_ee[0] + lane_ee[1];
  for (i = packed; i < n; ++i) {
    ResidualLanes<double> t;
    add_residuals(res, i, t);
    e_max = std::max(e_max, t.max);
    e_min = std::min(e_min, t.min);
    s_e += t.e;
    s_ee += t.ee;
  }
  // The exactness bound needs |δ| ≤ 2⁻³⁰ min_i (R + w_i); R + w_i ≥ R + e_min − |δ|.
  const double rho_min = radius + e_min - step;
  if (!(rho_min > 0.0) || !(step <= 0x1.0p-30 * rho_min)) return std::nullopt;
  const double ebar = s_e / nd;
  LeastSquaresCircle out;
  out.center = {center.x + dx, center.y + dy};
  out.radius = radius + ebar;
  out.iterations = 1;
  const auto signed_n = static_cast<Eigen::Index>(n);
  out.contacts = {first_index(e, signed_n, e_max), first_index(e, signed_n, e_min)};
  out.ron.ront = e_max - e_min;
  out.ron.ronp = std::max(0.0, e_max - ebar);
  out.ron.ronv = std::max(0.0, ebar - e_min);
  out.ron.ronq = std::sqrt(std::max(0.0, s_ee / nd - ebar * ebar));
  return out;
}

}  // namespace vcmm::geometry
