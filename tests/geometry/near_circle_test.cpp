// Tests of the near-circle kernel (internal/near_circle.h): distances and reciprocal
// distances by series about a 26-bit reference radius. Accuracy over millions of random points
// at |s| up to each degree's bound, radii 1e-3 … 1e4 mm about far-from-origin centres, against
// a long-double square root (the error bound of the header: ½ ulp + 2⁻⁵⁹ relative) and against
// std::sqrt (never more than 1 ulp apart, equal for nearly all points); the constants; the
// degree choice; vector evaluation bit-identical to scalar evaluation.
#include "../../geometry/src/internal/near_circle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <random>
#include <vector>

#include "../../geometry/src/internal/isa.h"

namespace vcmm::geometry::internal {
namespace {

/// |x − ref| in units of the ulp of the double nearest to ref (the spacing at x's binade).
double ulps(double x, long double ref) {
  const double r = static_cast<double>(ref);
  const double ulp = std::nextafter(std::fabs(r), std::numeric_limits<double>::infinity()) -
                     std::fabs(r);
  return static_cast<double>(std::fabs(static_cast<long double>(x) - ref) / ulp);
}

/// Distance in ulps between two doubles of the same sign (0 when equal).
std::int64_t ulp_distance(double a, double b) {
  std::int64_t ia, ib;
  std::memcpy(&ia, &a, sizeof a);
  std::memcpy(&ib, &b, sizeof b);
  return ia > ib ? ia - ib : ib - ia;
}

struct Errors {
  double r_max_ulps = 0.0, inv_max_ulps = 0.0;       // against long double
  std::int64_t r_vs_sqrt = 0, inv_vs_div = 0;         // largest ulp distance to std::sqrt, 1/√
  std::size_t r_differ = 0, inv_differ = 0, count = 0;  // points where they differ
};

template <int D>
Errors measure(double radius, double cx, double cy, std::size_t count, std::uint64_t seed) {
  const NearCircle k = near_circle_about(radius);
  const double s_max = near_circle_s_max(D);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> angle(0.0, 6.283185307179586);
  std::uniform_real_distribution<double> rel(-1.0, 1.0);
  Errors e;
  for (std::size_t i = 0; i < count; ++i) {
    // A point at r = R₀ √(1 + t) about a far centre; its q as a caller forms it.
    const double t = rel(rng) * s_max;
    const double rho = k.r0 * std::sqrt(1.0 + t);
    const double a = angle(rng);
    const double px = cx + rho * std::cos(a), py = cy + rho * std::sin(a);
    const double dx = px - cx, dy = py - cy;
    const double q = dx * dx + dy * dy;
    const double s = near_circle_s(q, k);
    if (!(std::fabs(s) <= s_max)) continue;  // rounding pushed it just outside
    ++e.count;
    const double r = k.r0 + near_circle_offset<D>(s, k);
    const double inv = near_circle_inverse<D>(s, k);
    const long double ref = std::sqrt(static_cast<long double>(q));
    e.r_max_ulps = std::max(e.r_max_ulps, ulps(r, ref));
    e.inv_max_ulps = std::max(e.inv_max_ulps, ulps(inv, 1.0L / ref));
    const double r_sqrt = std::sqrt(q), inv_div = 1.0 / r_sqrt;
    const std::int64_t dr = ulp_distance(r, r_sqrt), di = ulp_distance(inv, inv_div);
    e.r_vs_sqrt = std::max(e.r_vs_sqrt, dr);
    e.inv_vs_div = std::max(e.inv_vs_div, di);
    e.r_differ += dr != 0;
    e.inv_differ += di != 0;
  }
  return e;
}

// The header's bound: ½ ulp + ε with ε ≤ 2⁻⁵⁹ r ≤ 2⁻⁶ ulp, for r and for 1/r; so never more
// than 1 ulp from std::sqrt (itself within ½ ulp), equal to it except within ε of a midpoint.
// 1/√ by std::sqrt then a division rounds twice (up to ~1 ulp off); the kernel's is closer.
TEST(NearCircle, DistancesAreCorrectlyRoundedToWithinASixtyFourthUlp) {
  const double radii[] = {1e-3, 0.0371, 1.0, 85.5, 1234.5678, 1e4};
  const double centres[][2] = {{0.0, 0.0}, {600.0, -900.0}, {-8.1e3, 2.7e3}};
  std::uint64_t seed = 20261127;
  std::size_t total = 0;
  const auto check = [&](const Errors& e, int degree, double radius) {
    SCOPED_TRACE(::testing::Message() << "degree " << degree << ", radius " << radius
                                      << " mm, seed " << seed);
    total += e.count;
    EXPECT_GT(e.count, 100000u);
    EXPECT_LE(e.r_max_ulps, 0.5 + 1.0 / 64);
    EXPECT_LE(e.inv_max_ulps, 0.5 + 1.0 / 64);
    EXPECT_LE(e.r_vs_sqrt, 1);
    EXPECT_LE(e.inv_vs_div, 1);
    // Differences from std::sqrt only within ε of a midpoint: a fraction ≲ 2ε/ulp ≤ 1/32.
    EXPECT_LE(static_cast<double>(e.r_differ), static_cast<double>(e.count) / 32.0);
  };
  for (const double radius : radii) {
    for (const auto& c : centres) {
      // Offsets from the centre stay small against the centre's coordinates' ulp only when
      // the radius is not tiny next to them; tiny radii far out lose digits in dx (not the
      // kernel's concern): keep |c| ≤ 1e6 radius.
      if (std::hypot(c[0], c[1]) > 1e6 * radius) continue;
      check(measure<3>(radius, c[0], c[1], 120000, ++seed), 3, radius);
      check(measure<4>(radius, c[0], c[1], 120000, ++seed), 4, radius);
      check(measure<6>(radius, c[0], c[1], 120000, ++seed), 6, radius);
    }
  }
  EXPECT_GT(total, 4000000u);
}

// The measured figures the header quotes (printed, not asserted beyond the test above).
TEST(NearCircle, ReportsItsMeasuredErrors) {
  for (const int degree : {3, 4, 6}) {
    Errors e = degree == 3   ? measure<3>(85.5, 600.0, -900.0, 400000, 7)
               : degree == 4 ? measure<4>(85.5, 600.0, -900.0, 400000, 8)
                             : measure<6>(85.5, 600.0, -900.0, 400000, 9);
    std::cout << "degree " << degree << " (|s| ≤ " << near_circle_s_max(degree)
              << "), R = 85.5 mm, " << e.count << " points: r within " << e.r_max_ulps
              << " ulp of √q, 1/r within " << e.inv_max_ulps << " ulp of 1/√q; r ≠ std::sqrt at "
              << e.r_differ << ", 1/r ≠ 1/std::sqrt at " << e.inv_differ << " points\n";
    EXPECT_LE(e.r_max_ulps, 0.5 + 1.0 / 64);
  }
}

TEST(NearCircle, ConstantsAreExactWhereTheBoundNeedsThem) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> decades(-3.0, 4.0);
  for (int i = 0; i < 10000; ++i) {
    const double radius = std::pow(10.0, decades(rng));
    const NearCircle k = near_circle_about(radius);
    ASSERT_LE(std::fabs(k.r0 - radius), 0x1p-26 * radius) << radius;
    ASSERT_EQ(std::fma(k.r0, k.r0, -k.r0_sq), 0.0) << "R0² not exact for " << radius;
    for (int j = 0; j < kNearCircleMaxDegree; ++j) {
      const double c = k.a[j] / k.r0;  // R₀·c_k exact: dividing back gives c_k exactly
      ASSERT_EQ(std::fma(k.r0, c, -k.a[j]), 0.0) << radius;
    }
    // h + l = 1/R₀ to ~2⁻¹⁰⁵ relative.
    const long double inv = 1.0L / static_cast<long double>(k.r0);
    const long double err = (static_cast<long double>(k.inv_hi) + k.inv_lo) - inv;
    ASSERT_LE(std::fabs(static_cast<double>(err / inv)), 0x1p-62) << radius;
  }
}

TEST(NearCircle, DegreeIsTheSmallestWhoseRangeCovers) {
  EXPECT_EQ(near_circle_degree(0.0), 3);
  EXPECT_EQ(near_circle_degree(0x1p-15), 3);
  EXPECT_EQ(near_circle_degree(std::nextafter(0x1p-15, 1.0)), 4);
  EXPECT_EQ(near_circle_degree(0x1p-12), 4);
  EXPECT_EQ(near_circle_degree(0x1p-10), 6);
  EXPECT_EQ(near_circle_degree(0x1p-9), 6);
  EXPECT_EQ(near_circle_degree(std::nextafter(0x1p-9, 1.0)), 0);
  EXPECT_EQ(near_circle_degree(std::numeric_limits<double>::infinity()), 0);
  EXPECT_EQ(near_circle_degree(std::numeric_limits<double>::quiet_NaN()), 0);
}

// Vectors: element-wise, the same operations — the same bits as the scalar code, with the
// baseline's 2-lane vectors and with AVX2's 4-lane ones.
using V2 = double __attribute__((vector_size(16)));
using V4 = double __attribute__((vector_size(32)));

template <int D>
void scalar_values(const std::vector<double>& q, const NearCircle& k, std::vector<double>& r,
                   std::vector<double>& inv) {
  for (std::size_t i = 0; i < q.size(); ++i) {
    const double s = near_circle_s(q[i], k);
    r[i] = k.r0 + near_circle_offset<D>(s, k);
    inv[i] = near_circle_inverse<D>(s, k);
  }
}

/// The values by vectors of type V (lanes: sizeof(V) / 8), inlined into the ISA's caller.
template <int D, class V>
[[gnu::always_inline]] inline void vector_values(const std::vector<double>& q,
                                                 const NearCircle& k, std::vector<double>& r,
                                                 std::vector<double>& inv) {
  constexpr std::size_t lanes = sizeof(V) / sizeof(double);
  for (std::size_t i = 0; i + lanes <= q.size(); i += lanes) {
    V v;
    std::memcpy(&v, &q[i], sizeof v);
    const V s = near_circle_s(v, k);
    const V a = k.r0 + near_circle_offset<D>(s, k), b = near_circle_inverse<D>(s, k);
    std::memcpy(&r[i], &a, sizeof a);
    std::memcpy(&inv[i], &b, sizeof b);
  }
}

template <int D>
void baseline_values(const std::vector<double>& q, const NearCircle& k, std::vector<double>& r,
                     std::vector<double>& inv) {
  vector_values<D, V2>(q, k, r, inv);
}

#if VCMM_GEOMETRY_X86
template <int D>
__attribute__((target("avx2"))) void avx2_values(const std::vector<double>& q,
                                                 const NearCircle& k, std::vector<double>& r,
                                                 std::vector<double>& inv) {
  vector_values<D, V4>(q, k, r, inv);
}
#endif

template <int D>
void expect_vectors_match_scalar(double radius) {
  const NearCircle k = near_circle_about(radius);
  std::mt19937_64 rng(D);
  std::uniform_real_distribution<double> rel(-1.0, 1.0);
  std::vector<double> q(4096);
  for (double& v : q) v = k.r0_sq * (1.0 + rel(rng) * near_circle_s_max(D));
  std::vector<double> r(q.size()), inv(q.size()), r2(q.size()), inv2(q.size());
  scalar_values<D>(q, k, r, inv);
  baseline_values<D>(q, k, r2, inv2);
  EXPECT_EQ(std::memcmp(r.data(), r2.data(), r.size() * sizeof(double)), 0) << D;
  EXPECT_EQ(std::memcmp(inv.data(), inv2.data(), inv.size() * sizeof(double)), 0) << D;
#if VCMM_GEOMETRY_X86
  if (cpu_has_avx2()) {
    std::vector<double> r4(q.size()), inv4(q.size());
    avx2_values<D>(q, k, r4, inv4);
    EXPECT_EQ(std::memcmp(r.data(), r4.data(), r.size() * sizeof(double)), 0) << D;
    EXPECT_EQ(std::memcmp(inv.data(), inv4.data(), inv.size() * sizeof(double)), 0) << D;
  }
#endif
}

TEST(NearCircle, VectorEvaluationIsBitIdenticalToScalar) {
  for (const double radius : {0.0371, 85.5, 1e4}) {
    expect_vectors_match_scalar<3>(radius);
    expect_vectors_match_scalar<4>(radius);
    expect_vectors_match_scalar<6>(radius);
  }
}

}  // namespace
}  // namespace vcmm::geometry::internal
