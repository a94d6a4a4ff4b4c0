// Reference values (vcmm/validation/reference_values.h): reference roundness on profiles whose
// RONt is known by hand (lobed profiles, filtered harmonics), the second-order role of the
// nominal radius, and the seed study's reference diameter on hand-computed profiles with its
// uncertainty budget checked by Monte Carlo. The profile reader and its checks are tested with
// vcmm::geometry (tests/geometry/roundness_profile_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "vcmm/geometry/point.h"
#include "vcmm/validation/reference_values.h"

namespace {

using namespace vcmm::validation;
using vcmm::geometry::InvalidInput;
using vcmm::geometry::Optimality;
constexpr double kPi = std::numbers::pi;

struct Lobe {
  int order = 2;
  double amplitude_mm = 0.0;
  double phase = 0.0;
};

/// n samples at start_deg + 360·j/n degrees (converted as the reader does), deviation
/// Σ a cos(kθ + φ).
RoundnessProfile lobed_profile(std::size_t n, const std::vector<Lobe>& lobes,
                               double start_deg = 0.0) {
  RoundnessProfile p;
  for (std::size_t j = 0; j < n; ++j) {
    const double deg = start_deg + 360.0 * static_cast<double>(j) / static_cast<double>(n);
    const double theta = deg / 180.0 * kPi;
    double d = 0.0;
    for (const Lobe& l : lobes) d += l.amplitude_mm * std::cos(l.order * theta + l.phase);
    p.angle_rad.push_back(theta);
    p.deviation_mm.push_back(d);
  }
  return p;
}

template <class F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "(no exception)";
}

// The profile type, its reader and its checks are vcmm::geometry's (tests in
// tests/geometry/roundness_profile_test.cpp); validation names them for its users.
static_assert(std::is_same_v<RoundnessProfile, vcmm::geometry::RoundnessProfile>);

// ---- reference roundness -----------------------------------------------------------------

// Tolerance for "exact" RONt: the fitters give centre and radii to a few ulps of the
// coordinates (R = 50 mm: ulp 7.1e-15 mm); the deviations d_j themselves carry the rounding of
// R + d (another ulp). 64 ulps of R = 4.5e-13 mm covers both with margin.
constexpr double kRadius = 50.0;
const double kExactTol = 64 * std::numeric_limits<double>::epsilon() * kRadius;

TEST(ReferenceRoundness, ThreeLobesGiveTwiceTheAmplitudeAboutEveryCircle) {
  // d = a cos 3θ sampled every 1°: peaks (0°, 120°, 240°) and valleys (60°, 180°, 300°) are
  // samples; by symmetry every reference circle is centred on the axis: RONt = 2a.
  const double a = 0.8e-3;
  const RoundnessProfile p = lobed_profile(360, {{3, a, 0.0}});
  for (ReferenceCircle circle :
       {ReferenceCircle::minimum_zone, ReferenceCircle::maximum_inscribed,
        ReferenceCircle::least_squares, ReferenceCircle::minimum_circumscribed}) {
    SCOPED_TRACE(std::string(to_string(circle)));
    ReferenceRoundnessOptions o;
    o.reference_circle = circle;
    o.filter_cutoff_upr.reset();
    o.u_instrument_mm = 0.01e-3;
    o.nominal_radius_mm = kRadius;
    const ReferenceRoundness r = reference_roundness(p, o);
    EXPECT_NEAR(r.value_mm, 2 * a, kExactTol);
    EXPECT_EQ(r.value_mm, r.ron.ront);
    EXPECT_EQ(r.u_mm, 0.01e-3);
    EXPECT_EQ(r.reference_circle, circle);
    EXPECT_FALSE(r.filter_cutoff_upr.has_value());
    EXPECT_NEAR(r.center.x, 0.0, kExactTol);
    EXPECT_NEAR(r.center.y, 0.0, kExactTol);
    EXPECT_TRUE(r.verification.valid) << r.verification.reason;
    EXPECT_EQ(r.certificate.has_value(), circle != ReferenceCircle::least_squares);
  }
}

TEST(ReferenceRoundness, FilteredHarmonicIsAttenuatedByTheIsoTransmission) {
  // d = a cos 10θ, 360 samples (peaks at 0°, valleys at 18°), f_c = 50 UPR: the FFT path
  // multiplies harmonic 10 by H = 2^−(10/50)² exactly; RONt = 2aH about the axis.
  const double a = 1.0e-3;
  const RoundnessProfile p = lobed_profile(360, {{10, a, 0.0}});
  ReferenceRoundnessOptions o;
  o.nominal_radius_mm = kRadius;
  ASSERT_EQ(o.filter_cutoff_upr, 50.0);  // the default, as in the campaign
  const ReferenceRoundness r = reference_roundness(p, o);
  EXPECT_NEAR(r.value_mm, 2 * a * std::exp2(-0.04), 1e-12);
  EXPECT_TRUE(r.verification.valid) << r.verification.reason;
  // A harmonic far above the cut-off is removed: H(150) at 50 UPR = 2^−9.
  const RoundnessProfile q = lobed_profile(720, {{150, a, 0.0}});
  EXPECT_NEAR(reference_roundness(q, o).value_mm, 2 * a * std::exp2(-9.0), 1e-12);
}

TEST(ReferenceRoundness, MinimumZoneIsTheNarrowestAndEveryCertificateVerifies) {
  // A generic profile (several lobes, noise): MZ minimises the width over all centres, so its
  // RONt is at most that about the LS, MI and MC centres.
  std::mt19937_64 rng(7);
  RoundnessProfile p = lobed_profile(
      1800, {{2, 0.3e-3, 0.4}, {3, 0.2e-3, 1.1}, {5, 0.08e-3, 2.0}, {15, 0.03e-3, 0.3}});
  for (double& d : p.deviation_mm)
    d += 0.01e-3 * (static_cast<double>(rng() >> 11) * 0x1.0p-53 - 0.5);
  ReferenceRoundnessOptions o;
  o.nominal_radius_mm = 85.5;
  o.reference_circle = ReferenceCircle::minimum_zone;
  const ReferenceRoundness mz = reference_roundness(p, o);
  EXPECT_TRUE(mz.verification.valid) << mz.verification.reason;
  EXPECT_EQ(mz.certificate->optimality, Optimality::global);
  for (ReferenceCircle circle : {ReferenceCircle::maximum_inscribed,
                                 ReferenceCircle::least_squares,
                                 ReferenceCircle::minimum_circumscribed}) {
    o.reference_circle = circle;
    const ReferenceRoundness r = reference_roundness(p, o);
    EXPECT_TRUE(r.verification.valid) << to_string(circle) << ": " << r.verification.reason;
    EXPECT_LE(mz.value_mm, r.value_mm + kExactTol) << to_string(circle);
  }
}

// The nominal radius enters at second order (reference_values.cpp, derivation (1)):
// |ΔRONt| ≲ e (e + 2 max|d'|) / R with e the distance of the reference centre from the axis.
// Measured on a profile with a 10 µm eccentricity (e ≈ 10 µm) and lobes of 1 µm: the change
// against R = 1e6 mm (where the effect is below 1e-16 mm) scales as 1/R and stays under the
// bound; the centred profile (e ≈ form only) changes far less.
TEST(ReferenceRoundness, NominalRadiusMattersOnlyAtSecondOrder) {
  const double e = 10e-3, a = 1e-3;
  const RoundnessProfile eccentric =
      lobed_profile(720, {{1, e, 0.3}, {3, a, 0.0}, {5, 0.4 * a, 1.0}});
  const double max_slope = e + 3 * a + 5 * 0.4 * a;  // max |d'| per radian (bound)
  ReferenceRoundnessOptions o;
  o.filter_cutoff_upr = 50.0;
  const auto ront_at = [&](const RoundnessProfile& p, double radius) {
    o.nominal_radius_mm = radius;
    return reference_roundness(p, o).value_mm;
  };
  const double far = ront_at(eccentric, 1e6);
  const double d10 = ront_at(eccentric, 10.0) - far;
  const double d100 = ront_at(eccentric, 100.0) - far;
  const double d1000 = ront_at(eccentric, 1000.0) - far;
  for (const auto& [radius, delta] : {std::pair{10.0, d10}, {100.0, d100}, {1000.0, d1000}})
    EXPECT_LE(std::abs(delta), e * (e + 2 * max_slope) / radius) << "R = " << radius;
  // Second order: the change falls tenfold per decade of R (ratio within 10 % of 10: the
  // O(e³/R²) remainder is ~e/R ≤ 1e-3 of it).
  ASSERT_GT(std::abs(d10), 1e-9);
  EXPECT_NEAR(d10 / d100, 10.0, 1.0);
  EXPECT_NEAR(d100 / d1000, 10.0, 1.0);
  // Centred, same form: the effect is bounded by the form alone (e → t/2 ≈ 1.4 µm).
  const RoundnessProfile centred = lobed_profile(720, {{3, a, 0.0}, {5, 0.4 * a, 1.0}});
  const double t = 2.8e-3;
  EXPECT_LE(std::abs(ront_at(centred, 10.0) - ront_at(centred, 1e6)),
            t * (t + 2 * (3 * a + 2 * a)) / 10.0);
}

TEST(ReferenceRoundness, EveryPreconditionIsCheckedWithAMessage) {
  const RoundnessProfile p = lobed_profile(360, {{3, 1e-3, 0.0}});
  ReferenceRoundnessOptions o;
  o.nominal_radius_mm = kRadius;
  o.nominal_radius_mm = 0.0005;
  EXPECT_EQ(message_of([&] { reference_roundness(p, o); }),
            "reference_roundness: nominal_radius_mm must be finite and exceed the largest "
            "|deviation| (0.001 mm); got 0.00050000000000000001");
  o.nominal_radius_mm = std::numeric_limits<double>::infinity();
  EXPECT_NE(message_of([&] { reference_roundness(p, o); }).find("nominal_radius_mm must be finite"),
            std::string::npos);
  o.nominal_radius_mm = kRadius;
  o.u_instrument_mm = -1e-6;
  EXPECT_EQ(
      message_of([&] { reference_roundness(p, o); }),
      "reference_roundness: u_instrument_mm must be finite and >= 0; got -9.9999999999999995e-07");
  o.u_instrument_mm = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(message_of([&] { reference_roundness(p, o); }),
            "reference_roundness: u_instrument_mm must be finite and >= 0; got nan");
  o.u_instrument_mm = 0.0;
  o.filter_cutoff_upr = 500.0;
  EXPECT_EQ(message_of([&] { reference_roundness(p, o); }),
            "reference_roundness: filter_cutoff_upr must be finite, > 0 and <= n/2 = 180; got 500");
  o.filter_cutoff_upr = 0.0;
  EXPECT_EQ(message_of([&] { reference_roundness(p, o); }),
            "reference_roundness: filter_cutoff_upr must be finite, > 0 and <= n/2 = 180; got 0");
  // The filter's closedness rule: 50 UPR allows gaps up to 3.6°; remove samples 10°…19°.
  RoundnessProfile gap;
  for (std::size_t j = 0; j < p.angle_rad.size(); ++j) {
    if (j >= 10 && j < 20) continue;
    gap.angle_rad.push_back(p.angle_rad[j]);
    gap.deviation_mm.push_back(p.deviation_mm[j]);
  }
  o.filter_cutoff_upr = 50.0;
  EXPECT_EQ(message_of([&] { reference_roundness(gap, o); }),
            "reference_roundness: sample 9: angular gap of 11 deg to the next sample (at 20 deg) "
            "exceeds lambda_c/2 = 180/f_c = 3.6 deg: the filter would bridge it");
  // Unfiltered, the same profile is accepted (closed: gaps below 180°).
  o.filter_cutoff_upr.reset();
  EXPECT_NO_THROW(reference_roundness(gap, o));
  RoundnessProfile bad = p;
  bad.deviation_mm.resize(5);
  EXPECT_EQ(message_of([&] { reference_roundness(bad, o); }),
            "reference_roundness: angle_rad and deviation_mm differ in size (360 vs 5)");
}

// ---- reference diameter ------------------------------------------------------------------

constexpr double kDistance = 171.000123;  // L (mm)

TEST(ReferenceDiameter, TwoLobesSitOutsideAtTheMeasuredPoints) {
  // d = a cos 2θ: d(0) = d(π) = a, mean 0 → s = a, D = L + 2(0 − a) = L − 2a: the
  // interferometer touches two peaks, the mean diameter is smaller.
  const double a = 0.5e-3;
  const std::size_t n = 360;
  const ReferenceDiameter r = reference_diameter(kDistance, 0.04e-3, lobed_profile(n, {{2, a}}),
                                                 0.01e-3);
  EXPECT_NEAR(r.value_mm, kDistance - 2 * a, 1e-13);
  EXPECT_EQ(r.deviation_at_0_mm, a);
  EXPECT_NEAR(r.deviation_at_180_mm, a, 1e-18);
  EXPECT_NEAR(r.shift_mm, a, 1e-18);
  EXPECT_NEAR(r.mean_deviation_mm, 0.0, 1e-18);
  EXPECT_NEAR(r.correction_mm, -2 * a, 1e-18);
  EXPECT_EQ(r.interpolation_interval_0_rad, 0.0);    // sampled at 0° and 180°
  EXPECT_EQ(r.interpolation_interval_180_rad, 0.0);
  // Budget: equiangular through 0° and 180°, Σc² = 2 − 4/n.
  EXPECT_NEAR(r.profile_sensitivity * r.profile_sensitivity, 2.0 - 4.0 / n, 1e-13);
  EXPECT_NEAR(r.u_profile_mm, 0.01e-3 * std::sqrt(2.0 - 4.0 / n), 1e-18);
  EXPECT_NEAR(r.u_mm, std::hypot(0.04e-3, 0.01e-3 * std::sqrt(2.0 - 4.0 / n)), 1e-18);
  EXPECT_EQ(r.u_interferometer_mm, 0.04e-3);
}

TEST(ReferenceDiameter, ThreeLobesAndAConstantOffsetLeaveL) {
  // a cos 3θ: +a at 0°, −a at 180° → s = 0, mean 0 → D = L.
  const ReferenceDiameter r3 =
      reference_diameter(kDistance, 0.0, lobed_profile(360, {{3, 0.7e-3}}), 0.0);
  EXPECT_NEAR(r3.value_mm, kDistance, 1e-13);
  EXPECT_NEAR(r3.deviation_at_0_mm, 0.7e-3, 1e-18);
  EXPECT_NEAR(r3.deviation_at_180_mm, -0.7e-3, 1e-18);
  // A constant offset c of all readings cancels: s = c, mean = c.
  RoundnessProfile flat = lobed_profile(360, {});
  for (double& d : flat.deviation_mm) d = 3e-3;
  EXPECT_NEAR(reference_diameter(kDistance, 0.0, flat, 0.0).value_mm, kDistance, 1e-13);
}

TEST(ReferenceDiameter, ProfileOutsideTheMeasuredPointsOnAverageMakesDLarger) {
  // d = a sin²θ = a/2 − (a/2) cos 2θ: zero at 0° and 180°, mean a/2 → D = L + a.
  const double a = 0.6e-3;
  RoundnessProfile p = lobed_profile(360, {{2, -a / 2}});
  for (double& d : p.deviation_mm) d += a / 2;
  const ReferenceDiameter r = reference_diameter(kDistance, 0.0, p, 0.0);
  EXPECT_NEAR(r.value_mm, kDistance + a, 1e-13);
  EXPECT_NEAR(r.shift_mm, 0.0, 1e-18);
  EXPECT_NEAR(r.mean_deviation_mm, a / 2, 1e-18);
}

TEST(ReferenceDiameter, InterpolatesAt0And180WithinTheDocumentedBound) {
  // Samples at 0.5°, 1.5°, …: neither 0° nor 180° is sampled. For a cos 2θ the linear
  // interpolant at 0° is the mean of the values at ±0.5°, a cos 1° (also at 180°), the mean
  // is 0: D = L − 2a cos 1° exactly. Against the true L − 2a that errs by 2a(1 − cos 1°),
  // within the bound 2 · h²/8 · max|d''| = 2 · h²/8 · 4a = a h², h = 1° in rad.
  const double a = 0.5e-3;
  const RoundnessProfile p = lobed_profile(360, {{2, a}}, 0.5);
  const ReferenceDiameter r = reference_diameter(kDistance, 0.0, p, 0.0);
  const double h = kPi / 180;
  EXPECT_NEAR(r.value_mm, kDistance - 2 * a * std::cos(h), 1e-13);
  EXPECT_LE(std::abs(r.value_mm - (kDistance - 2 * a)), a * h * h + 1e-13);
  EXPECT_NEAR(r.interpolation_interval_0_rad, h, 1e-15);
  EXPECT_NEAR(r.interpolation_interval_180_rad, h, 1e-15);
  // Midway between two samples at 0° and 180° (both wrap cases of 0° covered: before the
  // first sample here; after the last sample below).
  const RoundnessProfile q = lobed_profile(359, {{2, a}}, 0.0);  // last sample 358.997…°
  const ReferenceDiameter rq = reference_diameter(kDistance, 0.0, q, 0.0);
  EXPECT_EQ(rq.interpolation_interval_0_rad, 0.0);
  EXPECT_GT(rq.interpolation_interval_180_rad, 0.0);
  EXPECT_LE(std::abs(rq.value_mm - (kDistance - 2 * a)), 2 * (h * h / 8) * 4 * a);
}

// The budget u_D² = u_L² + u_p² Σ c_j² counts the correlation of the 0°/180° readings with the
// mean. Checked by Monte Carlo on an uneven profile that samples neither 0° nor 180°: readings
// perturbed by N(0, u_p²), M = 20 000 draws (fixed seed, own Box–Muller). The sample variance
// of D has relative standard error sqrt(2/(M − 1)) = 1.0 %; tested at 5 % (5 standard errors).
TEST(ReferenceDiameter, UncertaintyBudgetMatchesMonteCarlo) {
  const std::uint64_t seed = 99;
  std::mt19937_64 rng(seed);
  const auto uniform = [&] { return (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53; };
  const auto normal = [&] {
    return std::sqrt(-2.0 * std::log(uniform())) * std::cos(2 * kPi * uniform());
  };
  // 90 samples with uneven steps (0.5 … 1.5 of the mean step), first at 1.3°.
  RoundnessProfile p;
  double deg = 1.3;
  while (deg < 360.0 && p.angle_rad.size() < 90) {
    p.angle_rad.push_back(deg / 180 * kPi);
    p.deviation_mm.push_back(0.2e-3 * std::cos(2 * deg / 180 * kPi));
    deg += 4.0 * (0.5 + uniform());
  }
  ASSERT_LT(p.angle_rad.back(), 2 * kPi);
  const double u_p = 0.02e-3;
  const ReferenceDiameter nominal = reference_diameter(kDistance, 0.0, p, u_p);
  ASSERT_GT(nominal.interpolation_interval_0_rad, 0.0);
  ASSERT_GT(nominal.interpolation_interval_180_rad, 0.0);
  constexpr int kDraws = 20000;
  double sum = 0.0, sum_sq = 0.0;
  RoundnessProfile noisy = p;
  for (int i = 0; i < kDraws; ++i) {
    for (std::size_t j = 0; j < p.deviation_mm.size(); ++j)
      noisy.deviation_mm[j] = p.deviation_mm[j] + u_p * normal();
    const double dd = reference_diameter(kDistance, 0.0, noisy, u_p).value_mm - kDistance;
    sum += dd;
    sum_sq += dd * dd;
  }
  const double mean = sum / kDraws;
  const double variance = (sum_sq - kDraws * mean * mean) / (kDraws - 1);
  SCOPED_TRACE("seed " + std::to_string(seed));
  EXPECT_NEAR(variance / (nominal.u_mm * nominal.u_mm), 1.0, 0.05);
  // Interpolating d(0) between two readings averages their noise (variance factor
  // λ² + (1 − λ)² ∈ [½, 1]), so here Σc² lies between 1 and 2 less the mean's O(1/n) share —
  // below the naive "shift u_p/√2, coefficient 2" value of 2.
  const double sum_c2 = nominal.profile_sensitivity * nominal.profile_sensitivity;
  EXPECT_LT(sum_c2, 2.0);
  EXPECT_GT(sum_c2, 1.0 - 8.0 / 90);
}

TEST(ReferenceDiameter, EveryPreconditionIsCheckedWithAMessage) {
  const RoundnessProfile p = lobed_profile(36, {{2, 1e-3}});
  EXPECT_EQ(message_of([&] { reference_diameter(0.0, 0.0, p, 0.0); }),
            "reference_diameter: interferometer_distance_mm must be finite and > 0; got 0");
  EXPECT_EQ(message_of([&] {
              reference_diameter(std::numeric_limits<double>::quiet_NaN(), 0.0, p, 0.0);
            }),
            "reference_diameter: interferometer_distance_mm must be finite and > 0; got nan");
  EXPECT_EQ(message_of([&] { reference_diameter(171.0, -1.0, p, 0.0); }),
            "reference_diameter: u_interferometer_mm must be finite and >= 0; got -1");
  EXPECT_EQ(message_of([&] {
              reference_diameter(171.0, 0.0, p, std::numeric_limits<double>::infinity());
            }),
            "reference_diameter: u_profile_point_mm must be finite and >= 0; got inf");
  RoundnessProfile few = p;
  few.angle_rad.resize(7);
  few.deviation_mm.resize(7);
  EXPECT_EQ(message_of([&] { reference_diameter(171.0, 0.0, few, 0.0); }),
            "reference_diameter: a closed profile needs at least 8 samples; got 7");
}

TEST(ReferenceCircleNames, RoundTrip) {
  for (ReferenceCircle c : {ReferenceCircle::minimum_zone, ReferenceCircle::maximum_inscribed,
                            ReferenceCircle::least_squares, ReferenceCircle::minimum_circumscribed})
    EXPECT_EQ(reference_circle_from_string(to_string(c)), c);
  EXPECT_EQ(to_string(ReferenceCircle::minimum_zone), "MZ");
  EXPECT_EQ(to_string(ReferenceCircle::maximum_inscribed), "MI");
  EXPECT_FALSE(reference_circle_from_string("mz").has_value());
  EXPECT_FALSE(reference_circle_from_string("MZCI").has_value());
}

}  // namespace
