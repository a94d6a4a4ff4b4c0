// tests/geometry/roundness_properties_test.cpp — property suites over regimes for the four
// reference circles: lobed noisy rings (R = 85.5 mm, lobing 10-100 nm, noise 50 nm)
// at n = 16, 360, 3600, centred at the origin and ~1.2 m away from it.
//
//  - invariance under exact transformations: translation, rotation by 90°, permutation.
//    The profiles are quantised to multiples of 2⁻⁴⁰ mm (~1e-12 mm, far below the noise)
//    so that a translation by a multiple of 2⁻⁴⁰ keeps every coordinate exact (|x| < 2¹³);
//    the exact problems are then identical, so the exact fitters must return the same
//    contact sets and values equal to a few ulps (LS, an iteration, to 1e-10 mm);
//  - ordering: RONt(MZ) ≤ RONt(LS), RONt(MI), RONt(MC); r(MI) ≤ R(LS) ≤ R(MC);
//  - every certificate passes verify() (MC always global);
//  - evaluate_roundness equals the individual calls, and with the Gaussian filter its
//    certificates verify against the filtered profile.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "internal/isa.h"
#include "support/filtered_least_squares.h"
#include "support/test_profiles.h"
#include "vcmm/geometry/certificate.h"
#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/minimum_circumscribed.h"
#include "vcmm/geometry/minimum_zone.h"
#include "vcmm/geometry/roundness.h"

namespace vcmm::test {
namespace {

using namespace vcmm::geometry;

constexpr int kQuantumExponent = -40;  // profiles on the 2⁻⁴⁰ mm grid

double quantise(double v) { return std::ldexp(std::nearbyint(std::ldexp(v, -kQuantumExponent)), kQuantumExponent); }

struct Profile {
  std::string name;
  std::vector<Point2> pts;
};

std::vector<Profile> profiles() {
  std::vector<Profile> out;
  for (std::size_t n : {16u, 360u, 3600u}) {
    for (Point2 c : {Point2{0, 0}, Point2{1000.5, -733.25}}) {
      auto pts = lobed_noisy_ring(n, 7 + n, 5e-5, c);
      for (auto& p : pts) p = {quantise(p.x), quantise(p.y)};
      std::ostringstream os;
      os << "lobed_noisy_ring(n=" << n << ", seed=" << 7 + n << ", centre=(" << c.x << ", "
         << c.y << "))";
      out.push_back({os.str(), std::move(pts)});
    }
  }
  return out;
}

struct Fits {
  LeastSquaresCircle ls;
  MinimumZoneCircle mz;
  MaximumInscribedCircle mi;
  MinimumCircumscribedCircle mc;
};

Fits fit_all(const std::vector<Point2>& pts) {
  return {least_squares_circle(pts), minimum_zone_circle(pts), maximum_inscribed_circle(pts),
          minimum_circumscribed_circle(pts)};
}

double ulp(double x) {
  x = std::fabs(x);
  return std::nextafter(x, 2 * x + 1) - x;
}

std::vector<std::size_t> mapped(const std::vector<std::size_t>& idx,
                                const std::function<std::size_t(std::size_t)>& map) {
  std::vector<std::size_t> out;
  for (std::size_t i : idx) out.push_back(map(i));
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::size_t> sorted(std::vector<std::size_t> v) {
  std::sort(v.begin(), v.end());
  return v;
}

/// b is the fit of the transformed profile: its centre must be map(a's centre), its
/// contacts the images of a's, its lengths a's — to the few ulps the roundings allow.
void expect_equivalent(const Fits& a, const Fits& b, const std::function<Point2(Point2)>& map,
                       const std::function<std::size_t(std::size_t)>& index_map,
                       const std::string& what) {
  SCOPED_TRACE(what);
  auto near_centre = [&](Point2 ca, Point2 cb, double radius, double ulps) {
    const Point2 m = map(ca);
    const double u = ulp(std::max({std::fabs(cb.x), std::fabs(cb.y), radius}));
    EXPECT_LE(std::fabs(m.x - cb.x), ulps * u) << "centre x " << m.x << " vs " << cb.x;
    EXPECT_LE(std::fabs(m.y - cb.y), ulps * u) << "centre y " << m.y << " vs " << cb.y;
    return u;
  };
  // Exact fitters: centres within 4 ulp of the same exact point (+ rounding of the map).
  {
    const double u = near_centre(a.mz.center, b.mz.center, b.mz.outer_radius, 12);
    EXPECT_EQ(mapped(a.mz.outer_contacts, index_map), sorted(b.mz.outer_contacts));
    EXPECT_EQ(mapped(a.mz.inner_contacts, index_map), sorted(b.mz.inner_contacts));
    EXPECT_NEAR(a.mz.outer_radius, b.mz.outer_radius, 16 * u);
    EXPECT_NEAR(a.mz.inner_radius, b.mz.inner_radius, 16 * u);
    EXPECT_NEAR(a.mz.ron.ront, b.mz.ron.ront, 32 * u);
  }
  {
    const double u = near_centre(a.mi.center, b.mi.center, b.mi.radius, 12);
    EXPECT_EQ(mapped(a.mi.contacts, index_map), sorted(b.mi.contacts));
    EXPECT_NEAR(a.mi.radius, b.mi.radius, 16 * u);
    EXPECT_NEAR(a.mi.ron.ront, b.mi.ron.ront, 32 * u);
  }
  {
    const double u = near_centre(a.mc.center, b.mc.center, b.mc.radius, 12);
    EXPECT_EQ(mapped(a.mc.contacts, index_map), sorted(b.mc.contacts));
    EXPECT_NEAR(a.mc.radius, b.mc.radius, 16 * u);
    EXPECT_NEAR(a.mc.ron.ront, b.mc.ron.ront, 32 * u);
  }
  // LS is an iteration (rounding differs with the frame): 1e-10 mm.
  const Point2 ls = map(a.ls.center);
  EXPECT_NEAR(ls.x, b.ls.center.x, 1e-10);
  EXPECT_NEAR(ls.y, b.ls.center.y, 1e-10);
  EXPECT_NEAR(a.ls.radius, b.ls.radius, 1e-10);
  EXPECT_NEAR(a.ls.ron.ront, b.ls.ron.ront, 1e-10);
}

void expect_certificates_verify(const std::vector<Point2>& pts, const Fits& f) {
  const auto vz = verify(pts, f.mz);
  EXPECT_TRUE(vz.valid) << "MZ: " << vz.reason << "\n  argument: " << f.mz.certificate.argument;
  const auto vi = verify(pts, f.mi);
  EXPECT_TRUE(vi.valid) << "MI: " << vi.reason << "\n  argument: " << f.mi.certificate.argument;
  const auto vc = verify(pts, f.mc);
  EXPECT_TRUE(vc.valid) << "MC: " << vc.reason;
  EXPECT_EQ(f.mc.certificate.optimality, Optimality::global);
}

class RoundnessProperties : public ::testing::TestWithParam<std::size_t> {
 protected:
  static const std::vector<Profile>& all() {
    static const std::vector<Profile> p = profiles();
    return p;
  }
  const Profile& profile() const { return all()[GetParam()]; }
};

TEST_P(RoundnessProperties, CertificatesVerifyAndCirclesAreOrdered) {
  const Profile& p = profile();
  SCOPED_TRACE(p.name);
  const Fits f = fit_all(p.pts);
  expect_certificates_verify(p.pts, f);
  // Claims on closed, round profiles: MZ and MI are expected to prove global optimality.
  EXPECT_EQ(f.mz.certificate.optimality, Optimality::global) << f.mz.certificate.argument;
  EXPECT_EQ(f.mi.certificate.optimality, Optimality::global) << f.mi.certificate.argument;
  const double tol = 1e-12;  // roundings of RONt about different centres
  EXPECT_LE(f.mz.ron.ront, f.ls.ron.ront + tol);
  EXPECT_LE(f.mz.ron.ront, f.mi.ron.ront + tol);
  EXPECT_LE(f.mz.ron.ront, f.mc.ron.ront + tol);
  EXPECT_LE(f.mi.radius, f.ls.radius);
  EXPECT_LE(f.ls.radius, f.mc.radius);
  EXPECT_LE(f.mz.inner_radius, f.mz.outer_radius);
}

TEST_P(RoundnessProperties, InvariantUnderExactTranslation) {
  const Profile& p = profile();
  const Point2 t{-512.125, 256.0625};
  std::vector<Point2> moved;
  for (const Point2& q : p.pts) moved.push_back({q.x + t.x, q.y + t.y});
  for (std::size_t i = 0; i < moved.size(); ++i) {  // exactness of the translation
    ASSERT_EQ(moved[i].x - t.x, p.pts[i].x);
    ASSERT_EQ(moved[i].y - t.y, p.pts[i].y);
  }
  const Fits a = fit_all(p.pts), b = fit_all(moved);
  expect_certificates_verify(moved, b);
  expect_equivalent(a, b, [&](Point2 c) { return Point2{c.x + t.x, c.y + t.y}; },
                    [](std::size_t i) { return i; }, p.name + " translated");
}

TEST_P(RoundnessProperties, InvariantUnderRotationBy90Degrees) {
  const Profile& p = profile();
  std::vector<Point2> turned;
  for (const Point2& q : p.pts) turned.push_back({-q.y, q.x});
  const Fits a = fit_all(p.pts), b = fit_all(turned);
  expect_certificates_verify(turned, b);
  expect_equivalent(a, b, [](Point2 c) { return Point2{-c.y, c.x}; },
                    [](std::size_t i) { return i; }, p.name + " rotated by 90 degrees");
}

TEST_P(RoundnessProperties, InvariantUnderPermutation) {
  const Profile& p = profile();
  const std::size_t n = p.pts.size();
  std::vector<std::size_t> perm(n);  // new index -> old index
  for (std::size_t i = 0; i < n; ++i) perm[i] = i;
  std::uint64_t s = 99;
  for (std::size_t i = n; i > 1; --i)
    std::swap(perm[i - 1], perm[static_cast<std::size_t>(uniform01(s) * static_cast<double>(i)) % i]);
  std::vector<std::size_t> inverse(n);
  for (std::size_t i = 0; i < n; ++i) inverse[perm[i]] = i;
  std::vector<Point2> shuffled(n);
  for (std::size_t i = 0; i < n; ++i) shuffled[i] = p.pts[perm[i]];
  const Fits a = fit_all(p.pts), b = fit_all(shuffled);
  expect_certificates_verify(shuffled, b);
  expect_equivalent(a, b, [](Point2 c) { return c; },
                    [&](std::size_t old_index) { return inverse[old_index]; },
                    p.name + " permuted");
}

TEST_P(RoundnessProperties, EvaluateRoundnessWithAndWithoutFilter) {
  const Profile& p = profile();
  SCOPED_TRACE(p.name);
  RoundnessRequest request;
  const RoundnessEvaluation plain = evaluate_roundness(p.pts, request);
  ASSERT_TRUE(plain.least_squares && plain.minimum_zone && plain.maximum_inscribed &&
              plain.minimum_circumscribed);
  EXPECT_EQ(plain.n_points, p.pts.size());
  const Fits f = fit_all(p.pts);
  EXPECT_EQ(plain.minimum_zone->outer_contacts, f.mz.outer_contacts);
  EXPECT_EQ(plain.minimum_zone->inner_contacts, f.mz.inner_contacts);
  EXPECT_EQ(plain.minimum_zone->ron.ront, f.mz.ron.ront);
  EXPECT_EQ(plain.maximum_inscribed->contacts, f.mi.contacts);
  EXPECT_EQ(plain.minimum_circumscribed->contacts, f.mc.contacts);
  EXPECT_EQ(plain.least_squares->radius, f.ls.radius);

  // Filtered: cut-off 15 UPR where the profile allows it (f_c ≤ n/2), else n/2 − 1.
  const double cutoff = std::min(15.0, static_cast<double>(p.pts.size()) / 2 - 1);
  request.filter_cutoff_upr = cutoff;
  const RoundnessEvaluation filtered = evaluate_roundness(p.pts, request);
  ASSERT_TRUE(filtered.filter_cutoff_upr.has_value());
  EXPECT_EQ(*filtered.filter_cutoff_upr, cutoff);
  const std::vector<Point2> fp = gaussian_filtered_profile(p.pts, cutoff).points;
  ASSERT_EQ(fp.size(), p.pts.size());
  ASSERT_TRUE(filtered.minimum_zone && filtered.maximum_inscribed &&
              filtered.minimum_circumscribed && filtered.least_squares);
  const auto vz = verify(fp, *filtered.minimum_zone);
  EXPECT_TRUE(vz.valid) << vz.reason;
  const auto vi = verify(fp, *filtered.maximum_inscribed);
  EXPECT_TRUE(vi.valid) << vi.reason;
  const auto vc = verify(fp, *filtered.minimum_circumscribed);
  EXPECT_TRUE(vc.valid) << vc.reason;
  // LS of the filtered profile: the filter's one-step circle on its rays (or the full fit
  // where that step is not exact) — the full fit of the filtered points to a few ulps of the
  // coordinates, with the same structure (2 contacts, all four parameters).
  double scale = 0.0;
  for (const Point2& q : fp) scale = std::max({scale, std::fabs(q.x), std::fabs(q.y)});
  vcmm::test::expect_same_least_squares(*filtered.least_squares, fp,
                                        16.0 * std::numeric_limits<double>::epsilon() * scale);
  EXPECT_GE(filtered.least_squares->iterations, 1);
  EXPECT_LE(filtered.minimum_zone->ron.ront, filtered.least_squares->ron.ront + 1e-12);
  // The filter is a positive-weight smoothing of the deviations about the LS centre: their
  // peak-to-valley can only shrink, and the MZ zone is at most that.
  EXPECT_LE(filtered.minimum_zone->ron.ront, plain.least_squares->ron.ront + 1e-12);
}

// The vectorised kernels (internal/isa.h: filter, FFT, distance scans, MZ containment map)
// run the same operations in both ISA variants: the whole evaluation, filtered and not, is
// bit for bit the same with the baseline variant forced.
TEST_P(RoundnessProperties, EvaluateRoundnessIsTheSameInEveryIsaVariant) {
  const Profile& p = profile();
  SCOPED_TRACE(p.name);
  for (double cutoff : {0.0, std::min(50.0, static_cast<double>(p.pts.size()) / 2 - 1)}) {
    RoundnessRequest request;
    if (cutoff > 0.0) request.filter_cutoff_upr = cutoff;
    const RoundnessEvaluation a = evaluate_roundness(p.pts, request);
    vcmm::geometry::internal::ForceBaselineIsa baseline;
    const RoundnessEvaluation b = evaluate_roundness(p.pts, request);
    EXPECT_EQ(a.filtered_points, b.filtered_points) << cutoff;
    ASSERT_TRUE(a.least_squares && b.least_squares && a.minimum_zone && b.minimum_zone &&
                a.maximum_inscribed && b.maximum_inscribed && a.minimum_circumscribed &&
                b.minimum_circumscribed);
    const auto same_ron = [&](const RoundnessParameters& x, const RoundnessParameters& y,
                              const char* what) {
      EXPECT_EQ(x.ront, y.ront) << what << " " << cutoff;
      EXPECT_EQ(x.ronp, y.ronp) << what << " " << cutoff;
      EXPECT_EQ(x.ronv, y.ronv) << what << " " << cutoff;
      EXPECT_EQ(x.ronq, y.ronq) << what << " " << cutoff;
    };
    same_ron(a.least_squares->ron, b.least_squares->ron, "LS");
    same_ron(a.minimum_zone->ron, b.minimum_zone->ron, "MZ");
    same_ron(a.maximum_inscribed->ron, b.maximum_inscribed->ron, "MI");
    same_ron(a.minimum_circumscribed->ron, b.minimum_circumscribed->ron, "MC");
    EXPECT_EQ(a.least_squares->center, b.least_squares->center) << cutoff;
    EXPECT_EQ(a.minimum_zone->center, b.minimum_zone->center) << cutoff;
    EXPECT_EQ(a.minimum_zone->outer_contacts, b.minimum_zone->outer_contacts) << cutoff;
    EXPECT_EQ(a.minimum_zone->inner_contacts, b.minimum_zone->inner_contacts) << cutoff;
    EXPECT_EQ(a.maximum_inscribed->contacts, b.maximum_inscribed->contacts) << cutoff;
    EXPECT_EQ(a.minimum_circumscribed->contacts, b.minimum_circumscribed->contacts) << cutoff;
    EXPECT_EQ(a.coverage.largest_gap_rad, b.coverage.largest_gap_rad) << cutoff;
  }
}

// Harder shapes: partial arcs (MI undefined there, MZ always has a finite minimum for
// non-collinear data), sparse profiles with large form. Whatever the fitters claim must
// verify; MI may refuse with UndefinedResult.
TEST(RoundnessHardProfiles, CertificatesVerify) {
  struct Shape {
    const char* name;
    RingSpec spec;
  };
  std::vector<Shape> shapes;
  auto lobed = [](std::size_t n, double span, double radius, double form, double noise) {
    RingSpec s;
    s.n = n;
    s.span = span;
    s.radius = radius;
    s.harmonics = {{2, form, 0.3}, {3, 0.6 * form, 1.1}, {5, 0.3 * form, 2.0}};
    s.noise_sigma = noise;
    s.angle_jitter = 0.3;
    return s;
  };
  shapes.push_back({"arc 90 deg, n=360", lobed(360, std::numbers::pi / 2, 85.5, 1e-4, 5e-5)});
  shapes.push_back({"arc 270 deg, n=360", lobed(360, 1.5 * std::numbers::pi, 85.5, 1e-4, 5e-5)});
  shapes.push_back({"arc 0.2 rad, n=100", lobed(100, 0.2, 85.5, 1e-4, 5e-5)});
  shapes.push_back({"sparse, large form, n=40", lobed(40, 0.0, 10.0, 0.5, 0.01)});
  shapes.push_back({"sparse, large form, n=200", lobed(200, 0.0, 10.0, 0.8, 0.05)});
  for (const Shape& shape : shapes) {
    SCOPED_TRACE(shape.name);
    const std::vector<Point2> pts = ring_profile(shape.spec);
    const MinimumZoneCircle mz = minimum_zone_circle(pts);
    const auto vz = verify(pts, mz);
    EXPECT_TRUE(vz.valid) << vz.reason << "\n  argument: " << mz.certificate.argument;
    const MinimumCircumscribedCircle mc = minimum_circumscribed_circle(pts);
    const auto vc = verify(pts, mc);
    EXPECT_TRUE(vc.valid) << vc.reason;
    try {
      const MaximumInscribedCircle mi = maximum_inscribed_circle(pts);
      const auto vi = verify(pts, mi);
      EXPECT_TRUE(vi.valid) << vi.reason << "\n  argument: " << mi.certificate.argument;
    } catch (const UndefinedResult&) {
      EXPECT_GT(shape.spec.span, 0.0) << "MI refused a closed profile";
    }
  }
}

// Filtered dense scans (the 171 mm ring of the benchmarks, 50 UPR, as evaluate_roundness
// fits them): near each smooth extremum the MC and MI circles of the sparse first candidates
// have their contacts a few indices (or one valley) off those of the full set, which the
// O(n) pass used to find as violators (MC 2-3 passes, MI 3-4). The local refinement of the
// supports and contacts finds them along the profile first: one pass each at n = 3600 (MC at
// 36 000, refined once only, two); the certificates verify.
TEST(RoundnessSmoothProfiles, CirclesTakeFewerFullPasses) {
  for (const std::size_t n : {3600u, 36000u}) {
    SCOPED_TRACE(n);
    const auto raw = vcmm::test::lobed_noisy_ring(n, 20261122, 5e-5);
    const std::vector<Point2> p = gaussian_filtered_profile(raw, 50.0).points;
    const MinimumCircumscribedCircle mc = minimum_circumscribed_circle(p);
    const MaximumInscribedCircle mi = maximum_inscribed_circle(p);
    const std::string mc_rounds = n == 3600 ? "after 1 round(s)" : "after 2 round(s)";
    EXPECT_NE(mc.certificate.argument.find(mc_rounds), std::string::npos)
        << mc.certificate.argument;
    EXPECT_NE(mi.certificate.argument.find(" 1 round(s)"), std::string::npos)
        << mi.certificate.argument;
    for (const std::string& argument : {mc.certificate.argument, mi.certificate.argument})
      EXPECT_NE(argument.find("local refinement"), std::string::npos) << argument;
    const auto vc = verify(p, mc);
    EXPECT_TRUE(vc.valid) << vc.reason;
    const auto vi = verify(p, mi);
    EXPECT_TRUE(vi.valid) << vi.reason;
  }
}

std::string profile_name(const ::testing::TestParamInfo<std::size_t>& info) {
  static const char* names[] = {"n16_origin",  "n16_far",  "n360_origin",
                                "n360_far",    "n3600_origin", "n3600_far"};
  return names[info.param];
}

INSTANTIATE_TEST_SUITE_P(LobedRings, RoundnessProperties, ::testing::Range<std::size_t>(0, 6),
                         profile_name);

// Regression: a 3-lobed 12-point ring scaled to 1e±180. Before the fix, verify() trapped in
// GMP (SIGFPE) on a NaN tolerance at 1e180, MZ reported infinite radii and MI/MC an infinite
// or wrong RONq, and LS blamed "collinear" points. Now MZ/MI/MC give finite results that
// verify exactly, consistent with the unit-scale answer, and LS names the span it cannot fit
// (not "collinear", not "too close to a straight line").
TEST(ExtremeScale, CirclesStayFiniteAndCertifiedLeastSquaresSaysWhy) {
  for (const double scale : {1e180, 1e-180}) {
    std::vector<Point2> p;
    for (int i = 0; i < 12; ++i) {
      const double t = 2 * std::numbers::pi * i / 12, r = 1 + 0.01 * std::cos(3 * t);
      p.push_back({scale * r * std::cos(t), scale * r * std::sin(t)});
    }
    SCOPED_TRACE("scale " + std::to_string(std::log10(scale)));
    const auto mz = minimum_zone_circle(p);
    EXPECT_TRUE(std::isfinite(mz.outer_radius) && std::isfinite(mz.ron.ronq));
    EXPECT_NEAR(mz.ron.ront / scale, 0.02, 1e-3);  // two lobe amplitudes of 0.01
    EXPECT_TRUE(verify(p, mz).valid) << verify(p, mz).reason;
    const auto mi = maximum_inscribed_circle(p);
    EXPECT_LE(mi.ron.ronq, mi.ron.ront);
    EXPECT_TRUE(verify(p, mi).valid) << verify(p, mi).reason;
    const auto mc = minimum_circumscribed_circle(p);
    EXPECT_LE(mc.ron.ronq, mc.ron.ront);
    EXPECT_TRUE(verify(p, mc).valid) << verify(p, mc).reason;
    try {
      least_squares_circle(p);
      ADD_FAILURE() << "least squares cannot form its moments at this scale";
    } catch (const InvalidInput& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(scale > 1 ? "the points span 2e+180 mm" : "the points span 2e-180 mm"),
                std::string::npos) << what;
      EXPECT_EQ(what.find("collinear"), std::string::npos) << what;
    }
  }
}

}  // namespace
// evaluate_roundness with a filter checks the raw profile inside the LS fit's first pass
// (its moments prove every coordinate finite) instead of a validate_profile pass of its own:
// the refusal must stay validate_profile(points, 8, "gaussian_filtered_profile")'s, naming
// the first non-finite point, at every position (packed blocks and the tail) and ISA level.
TEST(EvaluateRoundnessInput, FilteredEvaluationNamesTheFirstNonFinitePoint) {
  std::vector<Point2> ring;
  for (int i = 0; i < 67; ++i) {
    const double t = 2.0 * std::numbers::pi * i / 67.0;
    ring.push_back({40.0 + 12.5 * std::cos(t), -7.0 + 12.5 * std::sin(t)});
  }
  RoundnessRequest request;
  request.filter_cutoff_upr = 15.0;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  using vcmm::geometry::internal::IsaLevel;
  int checked = 0;
  for (const IsaLevel isa : {IsaLevel::avx512, IsaLevel::avx2, IsaLevel::baseline}) {
    const vcmm::geometry::internal::LimitIsa limit(isa);
    for (std::size_t at : {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{8},
                           std::size_t{33}, std::size_t{64}, std::size_t{66}}) {
      for (const double bad : {nan, inf, -inf}) {
        for (int coordinate = 0; coordinate < 2; ++coordinate) {
          std::vector<Point2> p = ring;
          (coordinate == 0 ? p[at].x : p[at].y) = bad;
          if (at != 0) p[at - 1].y = bad;  // two bad points: the first is named
          std::string expected;
          try {
            validate_profile(p, 8, "gaussian_filtered_profile");
          } catch (const InvalidInput& e) {
            expected = e.what();
          }
          ASSERT_NE(expected.find("non-finite"), std::string::npos) << expected;
          try {
            (void)evaluate_roundness(p, request);
            ADD_FAILURE() << "accepted a non-finite coordinate at " << at;
          } catch (const InvalidInput& e) {
            EXPECT_EQ(std::string(e.what()), expected) << at;
          }
          ++checked;
        }
      }
    }
  }
  EXPECT_EQ(checked, 3 * 7 * 3 * 2);
  // Too few points and collinear points keep their messages too.
  const std::vector<Point2> few(ring.begin(), ring.begin() + 7);
  std::vector<Point2> line;
  for (int i = 0; i < 20; ++i) line.push_back({1.0 * i, 2.0 * i});
  for (const std::vector<Point2>* p : {&few, static_cast<const std::vector<Point2>*>(&line)}) {
    std::string expected;
    try {
      validate_profile(*p, 8, "gaussian_filtered_profile");
    } catch (const InvalidInput& e) {
      expected = e.what();
    }
    ASSERT_FALSE(expected.empty());
    try {
      (void)evaluate_roundness(*p, request);
      ADD_FAILURE() << "accepted " << expected;
    } catch (const InvalidInput& e) {
      EXPECT_EQ(std::string(e.what()), expected);
    }
  }
}

}  // namespace vcmm::test
