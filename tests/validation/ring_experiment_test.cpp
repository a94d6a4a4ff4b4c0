// Tests of the ring-gauge virtual experiment (validation/ring_experiment.h): the measurands of
// known profiles, an analytic uncertainty (temperature only), determinism over thread counts,
// the noise bias of RONt and its refusal, the denoised truth.
#include "vcmm/validation/ring_experiment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <array>
#include <numbers>
#include <span>
#include <vector>
#include <string>
#include <memory>

#include "internal/stream_random_source.h"
#include "vcmm/errormodel/ring_gauge.h"
#include "vcmm/geometry/point.h"
#include "support/perfect_model.h"

namespace vcmm::validation {
namespace {

namespace em = vcmm::errormodel;

using test::perfect_model;

em::Measurement ring(em::ProbingMode mode, Eigen::Index n, bool form) {
  em::RingGauge g;
  if (form) g.form = em::seed_study_ring_form();
  em::RingSampling s;
  s.mode = mode;
  s.points = n;
  s.placement.location_mm = {600.0, 500.0, 400.0};
  return em::ring_gauge_measurement(g, s);
}

TEST(RingExperiment, ReferenceCircleNamesRoundTrip) {
  for (auto c : {ReferenceCircle::minimum_zone, ReferenceCircle::maximum_inscribed,
                 ReferenceCircle::least_squares, ReferenceCircle::minimum_circumscribed}) {
    EXPECT_EQ(reference_circle_from_string(to_string(c)), c);
  }
  EXPECT_FALSE(reference_circle_from_string("MZCI").has_value());
}

// (A numerically perfect circle is avoided on purpose: all points co-circular to rounding is
// the minimum zone's degenerate case, which falls to the slow exact overlay — docs/method.md.)
TEST(RingExperiment, PerfectRingHasItsDiameterAndNoRoundness) {
  const auto m = ring(em::ProbingMode::touch_trigger, 12, false);
  RingEvaluationOptions o;
  o.filter_cutoff_upr.reset();
  o.reference = ReferenceCircle::least_squares;
  const RingMeasurands y = evaluate_ring(m, o);
  EXPECT_NEAR(y.diameter_mm, 171.0, 1e-12);
  EXPECT_LT(y.roundness_mm, 1e-12);
}

TEST(RingExperiment, SingleHarmonicRoundnessIsItsPeakToValleyTimesTheTransmission) {
  // r(θ) = R + a cos(5θ): MZ RONt = 2a unfiltered; the 50 UPR Gaussian passes harmonic 5 with
  // H(5) = 2^−(5/50)² = 0.99309..., so RONt = 2a·H(5) to first order in a/R.
  em::RingGauge g;
  const double a = 1e-4;
  g.form = {{5, a, 0.3}};
  em::RingSampling s;
  s.points = 3600;
  const auto m = em::ring_gauge_measurement(g, s);
  // Sampling: the nearest sample to a peak or valley lies within kπ/N rad of phase, so the
  // sampled peak-to-valley falls short by at most 2a(1 − cos(kπ/N)) = 1.9e-9 mm here.
  const double sampling = 2 * a * (1 - std::cos(5 * std::numbers::pi / 3600));
  RingEvaluationOptions unfiltered;
  unfiltered.filter_cutoff_upr.reset();
  EXPECT_NEAR(evaluate_ring(m, unfiltered).roundness_mm, 2 * a, sampling + 1e-12);
  const double h5 = std::pow(2.0, -(5.0 / 50.0) * (5.0 / 50.0));
  EXPECT_NEAR(evaluate_ring(m, {}).roundness_mm, 2 * a * h5, sampling + 1e-12);
  for (auto c : {ReferenceCircle::maximum_inscribed, ReferenceCircle::least_squares,
                 ReferenceCircle::minimum_circumscribed}) {
    RingEvaluationOptions o;
    o.reference = c;
    o.filter_cutoff_upr.reset();
    EXPECT_NEAR(evaluate_ring(m, o).roundness_mm, 2 * a, 2e-9) << to_string(c);
  }
}

TEST(RingExperiment, ProfileDeviationsAreAboutTheReferenceCircle) {
  em::RingGauge g;
  g.form = {{3, 2e-4, 0.0}};
  em::RingSampling s;
  s.points = 720;
  const auto m = em::ring_gauge_measurement(g, s);
  RingEvaluationOptions o;
  o.filter_cutoff_upr.reset();
  const auto e = evaluate_ring_profile(ring_profile(m), o);
  double lo = 1e9, hi = -1e9;
  for (double d : e.deviation_mm) lo = std::min(lo, d), hi = std::max(hi, d);
  EXPECT_NEAR(hi - lo, e.measurands.roundness_mm, 1e-12);
  EXPECT_NEAR(hi, -lo, 1e-12);  // MZ: the reference radius is the zone's mid radius
  EXPECT_NEAR(e.angle_rad[180], std::numbers::pi / 2, 1e-6);
}

// Temperature only: D_corrected = D (1 + α (T − 20)) / (1 + α̂ (T̂ − 20)), with α ~ N(α̂, u_α²),
// T ~ N(T̂, u_T²). To first order u(D)² = (D ΔT u_α)² + (D α̂ u_T)², ΔT = T̂ − 20.
TEST(RingExperiment, TemperatureOnlyDiameterUncertaintyIsAnalytic) {
  em::DigitalModel model = perfect_model();
  model.temperature.expansion_coefficient_per_k = {11.5e-6, 1e-6};
  model.temperature.thermometer_u_k = 0.1;
  auto m = ring(em::ProbingMode::scanning, 720, true);
  m.temperature_c = 22.0;
  RingUncertaintyOptions o;
  o.stages = em::Stages::only(em::ErrorSource::temperature);
  o.monte_carlo.trials = 4000;
  o.monte_carlo.seed = 7;
  o.monte_carlo.threads = 2;
  const auto r = evaluate_ring_uncertainty_on_surface(model, m, o);
  const double D = 171.0, dT = 2.0;
  const double u = std::hypot(D * dT * 1e-6, D * 11.5e-6 * 0.1);
  const auto& s = r.monte_carlo.summaries[diameter];
  // The sample sd has relative standard error 1/√(2(M−1)) = 1.1 %: allow 5 of them.
  EXPECT_NEAR(s.standard_uncertainty, u, 5 * u / std::sqrt(2.0 * 3999));
  // The mean: unbiased to first order; 5 standard errors u/√M.
  EXPECT_NEAR(s.mean, r.estimate.diameter_mm, 5 * u / std::sqrt(4000.0));
  // Roundness is scaled by (1 + αΔT)/(1 + α̂ΔT̂): its spread is ~1e-6 relative.
  EXPECT_LT(r.monte_carlo.summaries[roundness].standard_uncertainty,
            1e-5 * r.estimate.roundness_mm);
}

TEST(RingExperiment, AZeroModelReproducesTheEstimateInEveryTrial) {
  const em::DigitalModel model = perfect_model();
  const auto m = ring(em::ProbingMode::touch_trigger, 16, true);
  RingUncertaintyOptions o;
  o.evaluation.filter_cutoff_upr.reset();  // 16 points: no filter
  o.monte_carlo.trials = 50;
  const auto r = evaluate_ring_uncertainty(model, m, o);
  for (std::uint64_t t = 0; t < r.monte_carlo.trials; ++t) {
    EXPECT_NEAR(r.monte_carlo.samples[2 * t + diameter], r.estimate.diameter_mm, 1e-12);
    EXPECT_NEAR(r.monte_carlo.samples[2 * t + roundness], r.estimate.roundness_mm, 1e-12);
  }
  EXPECT_NEAR(r.roundness.bias, 0.0, 1e-12);
  EXPECT_TRUE(r.roundness.applied);
}

TEST(RingExperiment, SameSeedSameNumbersWhateverTheThreadCount) {
  em::DigitalModel model = perfect_model();
  model.noise.scanning_sigma_mm = 0.7e-3;
  model.roughness.sigma_mm = 0.05e-3;
  model.probe.tip_radius_error_mm = {0.0, 0.1e-3};
  const auto m = ring(em::ProbingMode::scanning, 360, true);
  RingUncertaintyOptions o;
  o.evaluation.filter_cutoff_upr = 15.0;
  o.monte_carlo.trials = 64;
  o.monte_carlo.seed = 1234;
  o.monte_carlo.threads = 1;
  const auto one = evaluate_ring_uncertainty(model, m, o);
  o.monte_carlo.threads = 3;
  const auto three = evaluate_ring_uncertainty(model, m, o);
  ASSERT_EQ(one.monte_carlo.samples.size(), three.monte_carlo.samples.size());
  EXPECT_EQ(one.monte_carlo.samples, three.monte_carlo.samples);
  o.monte_carlo.seed = 1235;
  const auto other = evaluate_ring_uncertainty(model, m, o);
  EXPECT_NE(one.monte_carlo.samples, other.monte_carlo.samples);
}

em::DigitalModel example_model() {
  return em::read_digital_model_file(std::string(VCMM_SOURCE_DIR) + "/examples/cmm_model.json");
}

/// A scan of the seed study's ring with n points where the example model's axes reach it.
em::Measurement example_scan(Eigen::Index n) {
  em::RingGauge g;
  g.form = em::seed_study_ring_form();
  em::RingSampling sampling;
  sampling.points = n;
  sampling.mode = em::ProbingMode::scanning;
  sampling.placement.location_mm = {600.0, 500.0, 250.0};
  sampling.stylus_offset_mm = {0.0, 0.0, -100.0};
  sampling.temperature_c = 20.3;
  return em::ring_gauge_measurement(g, sampling);
}

/// The ring trial as it drew before the x, y noise rule: 3N noise numbers a trial (x, y, z per
/// point; the z never read), everything else as RingTrial.
uncertainty::ExperimentFactory xyz_noise_factory(const em::DigitalModel& model,
                                                 const em::Measurement& best,
                                                 const RingEvaluationOptions& options,
                                                 const em::Stages& stages) {
  auto prepared = std::make_shared<const em::PreparedMeasurement>(best, model);
  return [&model, prepared, options, stages]() -> uncertainty::Experiment {
    auto draw = std::make_shared<em::ErrorDraw>();
    auto profile = std::make_shared<std::vector<geometry::Point2>>();
    return [&model, prepared, options, stages, draw, profile](uncertainty::RandomStream& rng,
                                                              std::span<double> out) {
      internal::StreamRandomSource source(rng);
      em::draw_errors(model, *prepared, source, stages, *draw, em::NoiseComponents::xyz);
      em::simulate_corrected(*prepared, model, *draw, stages, em::Formula::first_order,
                             *profile);
      const RingMeasurands y = evaluate_ring(*profile, options);
      out[diameter] = y.diameter_mm;
      out[roundness] = y.roundness_mm;
    };
  };
}

// The trial draws the noise as x, y only (errormodel::NoiseComponents::xy), 2N numbers
// instead of 3N: other samples, the same distribution. Against the old rule over independent
// seeds (the example model, 720 points, a 50 UPR filter, MZ, all stages and the noise alone):
// the means agree within 4.5 standard errors √(u_a²/M + u_b²/M), the u's within 4.5 standard
// errors of their difference, u·√(2 · 1/(2(M − 1))). The noise-only case would see a
// wrong σ (e.g. √(2/3) of it: u of RONt ~18 % lower, ~10 standard errors at M = 3000).
TEST(RingExperiment, XyNoiseDrawsGiveTheDistributionOfTheXyzDraws) {
  const em::DigitalModel model = example_model();
  const em::Measurement best = example_scan(720);
  RingEvaluationOptions options;  // 50 UPR, MZ
  constexpr std::uint64_t kTrials = 3000;
  for (const em::Stages& stages : {em::Stages::all(), em::Stages::only(em::ErrorSource::noise)}) {
    for (const std::uint64_t seed : {11u, 12u, 13u}) {
      uncertainty::MonteCarloOptions mc;
      mc.trials = kTrials;
      mc.threads = 2;
      mc.seed = seed;
      const auto xy = uncertainty::run_monte_carlo(
          ring_experiment_factory(model, best, options, stages), ring_measurand_count, mc);
      mc.seed = seed + 1000;  // independent samples of the old rule
      const auto xyz = uncertainty::run_monte_carlo(
          xyz_noise_factory(model, best, options, stages), ring_measurand_count, mc);
      for (const std::size_t q : {std::size_t{diameter}, std::size_t{roundness}}) {
        const auto& a = xy.summaries[q];
        const auto& b = xyz.summaries[q];
        SCOPED_TRACE("seed " + std::to_string(seed) + ", measurand " + std::to_string(q) +
                     (stages.is_enabled(em::ErrorSource::kinematic) ? ", all" : ", noise"));
        const double m = static_cast<double>(kTrials);
        const double se_mean = std::sqrt((a.standard_uncertainty * a.standard_uncertainty +
                                          b.standard_uncertainty * b.standard_uncertainty) /
                                         m);
        EXPECT_NEAR(a.mean, b.mean, 4.5 * se_mean);
        const double se_u = b.standard_uncertainty / std::sqrt(m - 1.0);
        EXPECT_NEAR(a.standard_uncertainty, b.standard_uncertainty, 4.5 * se_u);
      }
    }
  }
}

// The trial's MZ and MI RONt (from the filtered profile's extremes, *_from_extremes.h) are
// bit for bit those of the fits of all filtered points (evaluate_ring_profile's full fit), on
// 40 simulated trial profiles of the example model at 3 600 points each.
TEST(RingExperiment, MinimumZoneAndInscribedRontAreTheFullFitsBitForBit) {
  const em::DigitalModel model = example_model();
  const em::Measurement best = example_scan(3600);
  const em::PreparedMeasurement prepared(best, model);
  for (const ReferenceCircle reference :
       {ReferenceCircle::minimum_zone, ReferenceCircle::maximum_inscribed}) {
    RingEvaluationOptions options;  // 50 UPR
    options.reference = reference;
    auto trial = ring_experiment_factory(model, best, options, em::Stages::all())();
    for (std::uint64_t t = 0; t < 40; ++t) {
      uncertainty::RandomStream rng(77, t);
      internal::StreamRandomSource source(rng);
      em::ErrorDraw draw;
      em::draw_errors(model, prepared, source, em::Stages::all(), draw, em::NoiseComponents::xy);
      std::vector<geometry::Point2> profile;
      em::simulate_corrected(prepared, model, draw, em::Stages::all(), em::Formula::first_order,
                             profile);
      EXPECT_EQ(evaluate_ring(profile, options).roundness_mm,
                evaluate_ring_profile(profile, options).measurands.roundness_mm)
          << "trial " << t;
      // And the trial itself computes exactly this.
      uncertainty::RandomStream same(77, t);
      std::array<double, ring_measurand_count> y{};
      trial(same, y);
      EXPECT_EQ(y[roundness], evaluate_ring(profile, options).roundness_mm) << "trial " << t;
    }
  }
}

// Noise on a perfect circle: every trial's RONt is positive, so the estimate from the data
// (zero) is biased low against the Monte Carlo mean by the whole noise-induced roundness; the
// correction would give a negative roundness and is refused.
TEST(RingExperiment, NoiseBiasOnAPerfectRingIsRefused) {
  em::DigitalModel model = perfect_model();
  model.noise.scanning_sigma_mm = 0.5e-3;
  const auto m = ring(em::ProbingMode::scanning, 360, false);
  RingUncertaintyOptions o;
  o.evaluation.filter_cutoff_upr.reset();
  o.evaluation.reference = ReferenceCircle::least_squares;  // (MZ of a perfect circle: see above)
  o.stages = em::Stages::only(em::ErrorSource::noise);
  o.monte_carlo.trials = 200;
  const auto r = evaluate_ring_uncertainty_on_surface(model, m, o);
  EXPECT_LT(r.estimate.roundness_mm, 1e-12);
  // RONt about LS of 360 noisy points is ~5.9σ (NOTES.md): well above zero.
  EXPECT_GT(r.roundness.bias, 4.0 * 0.5e-3);
  EXPECT_LT(r.roundness.bias, 8.0 * 0.5e-3);
  EXPECT_FALSE(r.roundness.applied);
  EXPECT_TRUE(r.roundness.refused);
  EXPECT_DOUBLE_EQ(r.roundness.corrected, r.estimate.roundness_mm);
  EXPECT_TRUE(r.diameter.applied);
}

TEST(RingExperiment, DenoisedRingRemovesTheHighFrequencies) {
  auto m = ring(em::ProbingMode::scanning, 3600, true);
  em::DigitalModel model = perfect_model();
  model.noise.scanning_sigma_mm = 0.5e-3;
  em::SeededRandomSource rng(3);
  const auto noisy = em::simulate(m, model, em::draw_errors(model, m, rng));
  const auto den = denoised_ring(noisy, 50.0);
  RingEvaluationOptions unfiltered;
  unfiltered.filter_cutoff_upr.reset();
  const double ron_noisy = evaluate_ring(noisy, unfiltered).roundness_mm;
  const double ron_den = evaluate_ring(den, unfiltered).roundness_mm;
  const double ron_true = evaluate_ring(m, unfiltered).roundness_mm;
  EXPECT_LT(ron_den, 0.5 * ron_noisy);
  EXPECT_LT(std::abs(ron_den - ron_true), 0.5 * (ron_noisy - ron_true));
}

TEST(RingExperiment, BadInputIsRejected) {
  auto m = ring(em::ProbingMode::scanning, 360, true);
  m.points_mm(0, 7) = std::nan("");
  EXPECT_THROW(evaluate_ring(m, {}), geometry::InvalidInput);
  EXPECT_THROW(evaluate_ring_uncertainty(perfect_model(), m, {}), geometry::InvalidInput);
  const auto few = ring(em::ProbingMode::touch_trigger, 5, false);
  EXPECT_THROW(evaluate_ring(few, {}), geometry::InvalidInput);  // too few to filter
}

TEST(RingExperiment, ANonFiniteTrialProfileFailsNamingThePoint) {
  // The trial checks the simulated points once (least_squares_circle), not again in the
  // filter: a trial profile with a NaN or an infinity still fails with a clear message.
  const auto m = ring(em::ProbingMode::scanning, 360, true);
  RingEvaluationOptions o;
  ASSERT_TRUE(o.filter_cutoff_upr.has_value());
  for (const auto c : {ReferenceCircle::least_squares, ReferenceCircle::minimum_zone,
                       ReferenceCircle::maximum_inscribed,
                       ReferenceCircle::minimum_circumscribed}) {
    o.reference = c;
    for (const double bad : {std::nan(""), static_cast<double>(INFINITY)}) {
      std::vector<geometry::Point2> profile = ring_profile(m);
      profile[123].x = bad;
      try {
        evaluate_ring(profile, o);
        ADD_FAILURE() << "expected InvalidInput";
      } catch (const geometry::InvalidInput& e) {
        EXPECT_NE(std::string(e.what()).find("point 123 has a non-finite coordinate"),
                  std::string::npos)
            << e.what();
      }
    }
  }
}

}  // namespace
}  // namespace vcmm::validation
