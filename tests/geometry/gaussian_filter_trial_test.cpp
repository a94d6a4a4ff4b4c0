// The Gaussian filter in the Monte Carlo trial (docs/performance.md, "the ring-gauge trial"):
//  - the overload that takes the caller's least-squares circle returns bit for bit what the
//    one-argument form returns (which fits that circle itself), on every path: FFT,
//    nonuniform, and a closed scan repeating its first point; and rejects a non-finite or
//    non-positive circle naming the function;
//  - the acceptance of the FFT path for samples slightly off the equiangular grid: a profile
//    the earlier one-pass rule (2·δ_max·max|w'| ≤ 1e-3 of the filtered peak-to-valley) sent to
//    the nonuniform path is now kept when the first-order error E = w'δ − F(w'δ) is within
//    that tolerance — and its FFT result is then indeed within the tolerance of the exact
//    filtered profile at the true angles (known in closed form);
//  - simulated CMM scans whose noise moves every point tangentially by ~σ/R (0.7 µm on
//    85.5 mm) stay on the FFT path (the earlier rule sent ~40 % of them to the ~40× slower
//    nonuniform path);
//  - the overload filling the caller's FilteredProfile gives the same points bit for bit, and
//    the LS circle of the filtered points it returns (one step on the rays, least_squares.cpp)
//    agrees with least_squares_circle of those points to rounding (~1e-14 mm), noisy trials
//    and the FFT, nonuniform, closed-scan and shuffled-order paths alike;
//  - evaluate_roundness, which now validates the profile once, still reports bad input
//    through the first requested fitter, as each fitter did on its own.
// Fixed seeds; each filter call is ~0.1 ms (FFT) to ~3 ms (nonuniform) at 3600 points.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "support/filtered_least_squares.h"
#include "support/test_profiles.h"
#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/roundness.h"

namespace {

using vcmm::geometry::FilteredProfile;
using vcmm::geometry::FilterPath;
using vcmm::geometry::FilterPathChoice;
using vcmm::geometry::gaussian_filtered_profile;
using vcmm::geometry::InvalidInput;
using vcmm::geometry::LeastSquaresCircle;
using vcmm::geometry::least_squares_circle;
using vcmm::geometry::Point2;
using vcmm::test::Harmonic;
using vcmm::test::ring_profile;
using vcmm::test::RingSpec;

constexpr double kPi = std::numbers::pi;

void expect_identical(const FilteredProfile& a, const FilteredProfile& b) {
  EXPECT_EQ(a.path, b.path);
  EXPECT_EQ(a.filter_center, b.filter_center);
  EXPECT_EQ(a.mean_radius, b.mean_radius);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) ASSERT_EQ(a.points[i], b.points[i]) << i;
}

/// One profile per filter path: FFT (a lobed noisy ring off the origin), nonuniform (±0.2 step
/// of angular jitter on a steep 30-lobe profile), a closed scan repeating its first point (the
/// n − 1 path).
struct PathProfiles {
  std::vector<Point2> lobed = vcmm::test::lobed_noisy_ring(3600, 7, 5e-5, {250.0, -120.0});
  std::vector<Point2> jittered = [] {
    RingSpec spec;
    spec.n = 720;
    spec.harmonics = {Harmonic{30, 1e-3, 0.4}};
    spec.angle_jitter = 0.4;
    return ring_profile(spec);
  }();
  std::vector<Point2> closed = [] {
    std::vector<Point2> p = vcmm::test::lobed_noisy_ring(900, 8, 2e-5);
    p.push_back(p.front());
    return p;
  }();
};

TEST(GaussianFilterSharedLeastSquares, BitForBitTheSameAsFittingItAgain) {
  const PathProfiles p;
  const auto& [lobed, jittered, closed] = p;
  const std::vector<const std::vector<Point2>*> profiles = {&lobed, &jittered, &closed};
  for (const std::vector<Point2>* pts : profiles) {
    for (double fc : {15.0, 50.0, 150.0}) {
      SCOPED_TRACE("n " + std::to_string(pts->size()) + ", cut-off " + std::to_string(fc));
      const LeastSquaresCircle ls = least_squares_circle(*pts);
      const FilteredProfile refit = gaussian_filtered_profile(*pts, fc);
      const FilteredProfile shared = gaussian_filtered_profile(*pts, fc, ls);
      expect_identical(refit, shared);
      expect_identical(gaussian_filtered_profile(*pts, fc, FilterPathChoice::nonuniform),
                       gaussian_filtered_profile(*pts, fc, ls, FilterPathChoice::nonuniform));
    }
  }
  EXPECT_EQ(gaussian_filtered_profile(lobed, 50).path, FilterPath::fft);
  EXPECT_EQ(gaussian_filtered_profile(jittered, 50).path, FilterPath::nonuniform);
  EXPECT_EQ(gaussian_filtered_profile(closed, 50).path, FilterPath::fft);
}

using vcmm::test::expect_same_least_squares;

TEST(GaussianFilterIntoCallersProfile, SamePointsAndTheFilteredLeastSquaresCircle) {
  const PathProfiles p;
  const auto& [lobed, jittered, closed] = p;
  // A shuffled scan: filtered in angular order, the output back in input order.
  std::vector<Point2> shuffled = vcmm::test::lobed_noisy_ring(360, 9, 2e-5);
  std::swap(shuffled[10], shuffled[200]);
  std::swap(shuffled[3], shuffled[77]);
  const std::vector<const std::vector<Point2>*> profiles = {&lobed, &jittered, &closed,
                                                            &shuffled};
  FilteredProfile reused;  // one object for every call: sizes change, storage is reused
  for (const std::vector<Point2>* pts : profiles) {
    for (double fc : {15.0, 50.0, 150.0}) {
      SCOPED_TRACE("n " + std::to_string(pts->size()) + ", cut-off " + std::to_string(fc));
      const LeastSquaresCircle ls = least_squares_circle(*pts);
      LeastSquaresCircle filtered_ls;
      gaussian_filtered_profile(*pts, fc, ls, reused, &filtered_ls);
      expect_identical(gaussian_filtered_profile(*pts, fc, ls), reused);
      expect_same_least_squares(filtered_ls, reused.points, 1e-12);
      gaussian_filtered_profile(*pts, fc, ls, reused, nullptr, FilterPathChoice::nonuniform);
      expect_identical(gaussian_filtered_profile(*pts, fc, ls, FilterPathChoice::nonuniform),
                       reused);
    }
  }
  EXPECT_EQ(gaussian_filtered_profile(shuffled, 50).path, FilterPath::fft);
}

TEST(GaussianFilterIntoCallersProfile, FilteredLeastSquaresOfNoisyScansToRounding) {
  // The Monte Carlo trial's case: a 171 mm ring with ~0.1 µm form and 0.7 µm noise, filtered
  // at 50 UPR about its LS circle; the LS centre of the filtered points is ~1e-10 mm away.
  // Measured worst differences from the full fit over these 50 scans: see the tolerance.
  double worst_center = 0.0, worst_ront = 0.0;
  for (int seed = 1; seed <= 50; ++seed) {
    std::uint64_t state = 0xD1B54A32D192ED03ULL * static_cast<std::uint64_t>(seed);
    std::vector<Point2> pts;
    for (int i = 0; i < 3600; ++i) {
      const double t = 2 * kPi * i / 3600.0;
      const double r = 85.5 + 4.5e-5 * std::cos(2 * t + 0.3) + 3e-5 * std::cos(3 * t + 1.1);
      pts.push_back({12.0 + r * std::cos(t) + 7e-4 * vcmm::test::standard_normal(state),
                     -7.0 + r * std::sin(t) + 7e-4 * vcmm::test::standard_normal(state)});
    }
    const LeastSquaresCircle ls = least_squares_circle(pts);
    FilteredProfile f;
    LeastSquaresCircle filtered_ls;
    gaussian_filtered_profile(pts, 50, ls, f, &filtered_ls);
    ASSERT_EQ(f.path, FilterPath::fft);
    EXPECT_EQ(filtered_ls.iterations, 1);  // the one-step path, not the fallback
    expect_same_least_squares(filtered_ls, f.points, 1e-13);
    const LeastSquaresCircle full = least_squares_circle(f.points);
    worst_center = std::max({worst_center, std::fabs(filtered_ls.center.x - full.center.x),
                             std::fabs(filtered_ls.center.y - full.center.y)});
    worst_ront = std::max(worst_ront, std::fabs(filtered_ls.ron.ront - full.ron.ront));
    // The step from the input's LS centre is real (the cheap shortcut "same centre" is not
    // exact): ~1e-10 mm, i.e. far above the agreement asserted.
    EXPECT_GT(std::hypot(full.center.x - ls.center.x, full.center.y - ls.center.y), 1e-13);
  }
  std::printf("filtered LS on rays vs full fit, 50 scans: centre %.3g mm, RONt %.3g mm\n",
              worst_center, worst_ront);
}

void expect_same_bits(const LeastSquaresCircle& a, const LeastSquaresCircle& b) {
  EXPECT_EQ(a.center, b.center);
  EXPECT_EQ(a.radius, b.radius);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.contacts, b.contacts);
  EXPECT_EQ(a.ron.ront, b.ron.ront);
  EXPECT_EQ(a.ron.ronp, b.ron.ronp);
  EXPECT_EQ(a.ron.ronv, b.ron.ronv);
  EXPECT_EQ(a.ron.ronq, b.ron.ronq);
}

TEST(GaussianFilteredLeastSquaresCircle, BitForBitTheCircleOfTheProfileOverload) {
  // gaussian_filtered_least_squares_circle (no output points formed where the one step on the
  // rays applies, and with points_validated no second check of the points) against
  // *filtered_least_squares of the overload that forms them: every path, the one-step result
  // and its fallback (a circle off the LS centre by 1e-3 mm: the step exceeds 2⁻³⁰ R).
  const PathProfiles p;
  const auto& [lobed, jittered, closed] = p;
  std::vector<Point2> shuffled = vcmm::test::lobed_noisy_ring(360, 9, 2e-5);
  std::swap(shuffled[10], shuffled[200]);
  const std::vector<const std::vector<Point2>*> profiles = {&lobed, &jittered, &closed,
                                                            &shuffled};
  int one_step = 0, fallback = 0;
  for (const std::vector<Point2>* pts : profiles) {
    for (double fc : {15.0, 50.0, 150.0}) {
      for (double offset : {0.0, 1e-3}) {
        SCOPED_TRACE("n " + std::to_string(pts->size()) + ", cut-off " + std::to_string(fc) +
                     ", centre offset " + std::to_string(offset));
        LeastSquaresCircle ls = least_squares_circle(*pts);
        ls.center.x += offset;
        FilteredProfile f;
        LeastSquaresCircle expected;
        gaussian_filtered_profile(*pts, fc, ls, f, &expected);
        (expected.iterations == 1 ? one_step : fallback) += 1;
        expect_same_bits(vcmm::geometry::gaussian_filtered_least_squares_circle(*pts, fc, ls),
                         expected);
        expect_same_bits(
            vcmm::geometry::gaussian_filtered_least_squares_circle(*pts, fc, ls, true),
            expected);
        FilteredProfile vouched;
        gaussian_filtered_profile(*pts, fc, ls, vouched, nullptr, FilterPathChoice::automatic,
                                  /*points_validated=*/true);
        expect_identical(vouched, f);
      }
    }
  }
  EXPECT_GT(one_step, 0);
  EXPECT_GT(fallback, 0);
}

TEST(GaussianFilteredLeastSquaresCircle, BadPointsStillNamedWhenTheCallerVouchesForThem) {
  // points_validated skips the per-point check only for points the filter takes near the
  // circle; a non-finite or a collinear set still throws with the full check's message.
  const auto good = vcmm::test::lobed_noisy_ring(360, 3);
  const LeastSquaresCircle ls = least_squares_circle(good);
  auto expect_invalid = [&](const std::vector<Point2>& pts, double fc,
                            const std::string& fragment) {
    for (int entry = 0; entry < 2; ++entry) {
      try {
        if (entry == 0) {
          vcmm::geometry::gaussian_filtered_least_squares_circle(pts, fc, ls, true);
        } else {
          FilteredProfile f;
          gaussian_filtered_profile(pts, fc, ls, f, nullptr, FilterPathChoice::automatic, true);
        }
        ADD_FAILURE() << "expected InvalidInput mentioning '" << fragment << "'";
      } catch (const InvalidInput& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("gaussian_filtered_profile"), std::string::npos) << what;
        EXPECT_NE(what.find(fragment), std::string::npos) << what;
      }
    }
  };
  std::vector<Point2> bad = good;
  bad[17].y = std::nan("");
  expect_invalid(bad, 50, "point 17 has a non-finite coordinate");
  bad = good;
  bad[300].x = -INFINITY;
  expect_invalid(bad, 50, "point 300 has a non-finite coordinate");
  std::vector<Point2> line;
  for (int i = 0; i < 40; ++i) line.push_back({0.5 * i, 0.25 * i});
  expect_invalid(line, 5, "collinear");
  expect_invalid(std::vector<Point2>(good.begin(), good.begin() + 7), 2, "at least 8");
  expect_invalid(good, 181, "must not exceed n/2");
  LeastSquaresCircle off = ls;
  off.radius = 0.0;
  try {
    vcmm::geometry::gaussian_filtered_least_squares_circle(good, 50, off, true);
    ADD_FAILURE() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("radius > 0"), std::string::npos) << e.what();
  }
}

TEST(GaussianFilterSharedLeastSquaresBadInput, CircleMustBeFiniteWithPositiveRadius) {
  const auto pts = vcmm::test::lobed_noisy_ring(360, 3);
  const LeastSquaresCircle good = least_squares_circle(pts);
  auto expect_invalid = [&](const LeastSquaresCircle& ls, const std::string& fragment) {
    try {
      gaussian_filtered_profile(pts, 50, ls);
      ADD_FAILURE() << "expected InvalidInput mentioning '" << fragment << "'";
    } catch (const InvalidInput& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("gaussian_filtered_profile"), std::string::npos) << what;
      EXPECT_NE(what.find(fragment), std::string::npos) << what;
    }
  };
  LeastSquaresCircle bad = good;
  bad.center.y = std::nan("");
  expect_invalid(bad, "finite centre");
  bad = good;
  bad.radius = 0.0;
  expect_invalid(bad, "radius > 0; got centre");
  bad.radius = -85.5;
  expect_invalid(bad, "radius -85.5");
  bad.radius = INFINITY;
  expect_invalid(bad, "radius inf");
  // The profile's own preconditions still apply (they are checked first).
  try {
    gaussian_filtered_profile(std::vector<Point2>(pts.begin(), pts.begin() + 5), 2, good);
    ADD_FAILURE() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("at least 8"), std::string::npos) << e.what();
  }
}

/// Angles of the points about `c`, and their displacement δ_j from the equiangular grid
/// anchored at point 0 (counter-clockwise samples).
std::vector<double> grid_displacements(const std::vector<Point2>& pts, Point2 c) {
  const std::size_t n = pts.size();
  const double theta0 = std::atan2(pts[0].y - c.y, pts[0].x - c.x);
  std::vector<double> delta(n);
  for (std::size_t j = 0; j < n; ++j) {
    const double theta = std::atan2(pts[j].y - c.y, pts[j].x - c.x);
    delta[j] = std::remainder(theta - theta0 - 2 * kPi * static_cast<double>(j) /
                                                   static_cast<double>(n), 2 * kPi);
  }
  return delta;
}

std::vector<double> filtered_deviations(const FilteredProfile& f) {
  std::vector<double> d;
  for (const Point2& p : f.points)
    d.push_back(std::hypot(p.x - f.filter_center.x, p.y - f.filter_center.y) - f.mean_radius);
  return d;
}

TEST(GaussianFilterGridAcceptance, KeepsTheFftWhenTheFirstOrderErrorIsWithinTolerance) {
  // Harmonic k = 20 of amplitude A = 1 µm, jitter uniform in ±δ_max = ±7e-5 rad (0.08 of a
  // step at n = 3600). Filtered: w = H A cos(kθ + φ), peak-to-valley 2HA, tolerance 2e-3 HA.
  // Earlier rule: 2·δ_max·max|w'| = 2·7e-5·20·HA = 2.8e-3 HA > tolerance → nonuniform. The
  // first-order error of the FFT result is E = w'δ − F(w'δ) ≈ w'δ (random δ averages out
  // under F), |E| ≲ 20·7e-5·HA = 1.4e-3 HA ≤ tolerance → kept. Then the FFT result must be
  // within the tolerance of the exact filtered profile at the true angles (second-order
  // terms, ~(kδ)²·HA ≈ 2e-6 HA, are far below it).
  const int k = 20;
  const double amplitude = 1e-3, phase = 0.7, fc = 50.0;
  const double h = std::exp2(-(k / fc) * (k / fc));
  for (std::uint64_t seed : {1u, 2u, 3u, 4u, 5u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    RingSpec spec;
    spec.n = 3600;
    spec.harmonics = {Harmonic{k, amplitude, phase}};
    spec.angle_jitter = 2 * 7e-5 / (2 * kPi / 3600.0);
    spec.seed = seed;
    const auto pts = ring_profile(spec);
    const FilteredProfile f = gaussian_filtered_profile(pts, fc);
    ASSERT_EQ(f.path, FilterPath::fft);
    const std::vector<double> w = filtered_deviations(f);
    const double pv = *std::max_element(w.begin(), w.end()) - *std::min_element(w.begin(), w.end());
    const double tolerance = 1e-3 * pv;
    // The earlier rule rejects this profile (so the test exercises the new stages).
    const std::vector<double> delta = grid_displacements(pts, f.filter_center);
    double delta_max = 0.0, slope_max = 0.0;
    for (std::size_t j = 0; j < w.size(); ++j) {
      delta_max = std::max(delta_max, std::fabs(delta[j]));
      slope_max = std::max(slope_max, std::fabs(w[j] - w[j == 0 ? w.size() - 1 : j - 1]) /
                                          (2 * kPi / 3600.0));
    }
    EXPECT_GT(2.0 * delta_max * slope_max, tolerance);
    // The accepted result is within the tolerance of the exact filtered profile.
    double worst = 0.0;
    for (std::size_t j = 0; j < pts.size(); ++j) {
      const double theta = std::atan2(pts[j].y - f.filter_center.y, pts[j].x - f.filter_center.x);
      worst = std::max(worst, std::fabs(w[j] - h * amplitude * std::cos(k * theta + phase)));
    }
    EXPECT_LE(worst, tolerance);
    EXPECT_GT(worst, 0.1 * tolerance);  // the first-order error is really there (not zero)
  }
  // Twice the jitter: |E| ≈ 2.8e-3 HA exceeds the tolerance → nonuniform, as before.
  RingSpec spec;
  spec.n = 3600;
  spec.harmonics = {Harmonic{k, amplitude, phase}};
  spec.angle_jitter = 2 * 2.0 * 7e-5 / (2 * kPi / 3600.0);
  EXPECT_EQ(gaussian_filtered_profile(ring_profile(spec), fc).path, FilterPath::nonuniform);
}

TEST(GaussianFilterGridAcceptance, NoisyScansStayOnTheFftPath) {
  // A 171 mm ring (seed-study-like form, ~250 nm) scanned at 3600 equiangular points with
  // isotropic 0.7 µm noise: the tangential noise moves each point by ~8e-6 rad (up to ~3e-5
  // rad), and the filtered noise has slopes of ~10 µm/rad, so the earlier one-pass bound
  // 2·δ_max·max|w'| (~1.3e-6 mm) exceeded 1e-3 of the filtered peak-to-valley (~1.2e-6 mm)
  // on ~40 % of such scans. The first-order error itself is ~3e-7 mm.
  int fft = 0;
  const int scans = 20;
  for (int seed = 1; seed <= scans; ++seed) {
    std::uint64_t state = 0x9E3779B97F4A7C15ULL * static_cast<std::uint64_t>(seed);
    const std::vector<Harmonic> form = {{2, 4.5e-5, 0.3}, {3, 3e-5, 1.1}, {4, 1.2e-5, 2.0},
                                        {5, 1e-5, 0.7},  {7, 6e-6, 2.9}, {11, 4e-6, 1.3},
                                        {17, 3e-6, 0.2}};
    std::vector<Point2> pts;
    for (int i = 0; i < 3600; ++i) {
      const double t = 2 * kPi * i / 3600.0;
      double r = 85.5;
      for (const Harmonic& hm : form) r += hm.amplitude * std::cos(hm.order * t + hm.phase);
      const double nx = 7e-4 * vcmm::test::standard_normal(state);
      const double ny = 7e-4 * vcmm::test::standard_normal(state);
      pts.push_back({r * std::cos(t) + nx, r * std::sin(t) + ny});
    }
    fft += gaussian_filtered_profile(pts, 50).path == FilterPath::fft;
  }
  EXPECT_EQ(fft, scans);
}

TEST(EvaluateRoundnessBadInput, ReportedByTheFirstRequestedFitter) {
  const std::vector<Point2> collinear = {{0, 0}, {1, 1}, {2, 2}, {3, 3}, {4, 4}};
  auto message = [&](const vcmm::geometry::RoundnessRequest& r) -> std::string {
    try {
      vcmm::geometry::evaluate_roundness(collinear, r);
    } catch (const InvalidInput& e) {
      return e.what();
    }
    return "";
  };
  vcmm::geometry::RoundnessRequest request;  // all four circles, unfiltered
  EXPECT_NE(message(request).find("least_squares_circle: all 5 points are collinear"),
            std::string::npos) << message(request);
  request.least_squares = false;
  EXPECT_NE(message(request).find("minimum_zone_circle"), std::string::npos) << message(request);
  request.minimum_zone = false;
  EXPECT_NE(message(request).find("maximum_inscribed_circle"), std::string::npos)
      << message(request);
  // MC alone needs only two distinct points: collinear data are fine.
  request.maximum_inscribed = false;
  const auto mc = vcmm::geometry::evaluate_roundness(collinear, request);
  ASSERT_TRUE(mc.minimum_circumscribed.has_value());
  EXPECT_DOUBLE_EQ(mc.minimum_circumscribed->radius, std::sqrt(32.0) / 2.0);
  EXPECT_FALSE(mc.least_squares.has_value());
}

}  // namespace
