// Tests of the shrinkage bias treatment (validation/form_bias.h): K from the filter, the error
// power of white noise against its analytic value, systematic orders marked dominant, the
// surrogate keeping real form and dropping noise, the no-form shortcut, and determinism over
// thread counts of the whole treatment. (Its honesty on known truth: bias_acceptance_test.cpp.)
#include "vcmm/validation/form_bias.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

#include "vcmm/errormodel/random_source.h"
#include "vcmm/errormodel/ring_gauge.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/profile_harmonics.h"
#include "vcmm/validation/ring_experiment.h"
#include "support/perfect_model.h"

namespace vcmm::validation {
namespace {

namespace em = vcmm::errormodel;

using test::perfect_model;

em::Measurement ring(Eigen::Index n, const std::vector<em::FormHarmonic>& form) {
  em::RingGauge g;
  g.form = form;
  em::RingSampling s;
  s.mode = em::ProbingMode::scanning;
  s.points = n;
  s.placement.location_mm = {600.0, 500.0, 400.0};
  return em::ring_gauge_measurement(g, s);
}

uncertainty::MonteCarloOptions pilot(std::uint64_t seed, unsigned threads = 0) {
  uncertainty::MonteCarloOptions o;
  o.seed = seed;
  o.threads = threads;
  return o;
}

TEST(FormBias, MaxOrderFollowsTheFilterGain) {
  RingEvaluationOptions e;
  e.filter_cutoff_upr = 50.0;
  // 2^−(k/50)² ≥ 0.01 ⇔ k ≤ 50 √log₂100 = 128.8.
  EXPECT_EQ(shrinkage_max_order(e, 3600, 0.01), 128u);
  EXPECT_EQ(shrinkage_max_order(e, 200, 0.01), 100u);  // capped at n/2
  EXPECT_EQ(shrinkage_max_order(e, 3600, 0.5), 50u);   // H(50) = ½
  e.filter_cutoff_upr.reset();
  EXPECT_EQ(shrinkage_max_order(e, 360, 0.01), 180u);  // unfiltered: every harmonic
  e.filter_cutoff_upr = 50.0;
  EXPECT_THROW(shrinkage_max_order(e, 3600, 0.0), std::invalid_argument);
  const auto h = filter_transmission(e, 100);
  EXPECT_DOUBLE_EQ(h[0], 1.0);
  EXPECT_DOUBLE_EQ(h[50], 0.5);
  EXPECT_DOUBLE_EQ(h[100], 1.0 / 16.0);
}

// Radial white noise of σ on n equiangular points: a_k, b_k each have variance 2σ²/n, so
// V_k = E[a_k² + b_k²] = 4σ²/n for 2 ≤ k < n/2 (the tangential noise component moves points
// along the circle: second order in σ/R). Each V̂_k is a mean of M exponentials (sd V/√M).
TEST(FormBias, ErrorPowerOfWhiteNoiseIsAnalytic) {
  em::DigitalModel model = perfect_model();
  const double sigma = 0.5e-3;
  model.noise.scanning_sigma_mm = sigma;
  const auto m = ring(720, {});
  RingEvaluationOptions e;
  e.filter_cutoff_upr = 50.0;
  ShrinkageOptions so;
  so.pilot_trials = 400;
  const auto s = estimate_harmonic_shrinkage(model, m, e, em::Stages::all(), so, pilot(7));
  ASSERT_TRUE(s.has_value());
  ASSERT_EQ(s->max_order, 128u);
  const double v = 4.0 * sigma * sigma / 720.0;
  const double sd = v / std::sqrt(400.0);
  double sum = 0.0;
  for (std::size_t k = 2; k <= s->max_order; ++k) {
    EXPECT_NEAR(s->error_power_mm2[k], v, 5.0 * sd) << "k = " << k;
    sum += s->error_power_mm2[k];
  }
  EXPECT_NEAR(sum / 127.0, v, 4.0 * sd / std::sqrt(127.0));
  // No order dominates white noise: every threshold is ln K.
  EXPECT_EQ(s->dominant_orders, 0u);
  for (std::size_t k = 2; k <= s->max_order; ++k)
    EXPECT_DOUBLE_EQ(s->threshold[k], std::log(128.0));
  EXPECT_EQ(s->threshold[0], 0.0);
  EXPECT_EQ(s->threshold[1], 0.0);
}

// Probe lobing of orders 2 and 3 with u = 0.15 µm per coefficient: V_k ≈ 2u² there, far above
// the noise floor, so those two orders (and only those) get plain power subtraction (c_k = 1).
TEST(FormBias, SystematicOrdersAreMarkedDominant) {
  em::DigitalModel model = perfect_model();
  model.noise.scanning_sigma_mm = 0.5e-3;
  const double u = 0.15e-3;
  model.probe.directional = {{2, {0.0, u}, {0.0, u}}, {3, {0.0, u}, {0.0, u}}};
  const auto m = ring(720, {});
  RingEvaluationOptions e;
  const auto s = estimate_harmonic_shrinkage(model, m, e, em::Stages::all(), {}, pilot(3));
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->dominant_orders, 2u);
  EXPECT_EQ(s->threshold[2], 1.0);
  EXPECT_EQ(s->threshold[3], 1.0);
  EXPECT_DOUBLE_EQ(s->threshold[4], std::log(static_cast<double>(s->max_order)));
  const double noise = 4.0 * 0.25e-6 / 720.0;
  for (int k : {2, 3}) {
    // Mean of 400 exponentials: 5 % standard error; 20 % is four of them.
    EXPECT_NEAR(s->error_power_mm2[static_cast<std::size_t>(k)], 2.0 * u * u + noise,
                0.2 * 2.0 * u * u)
        << "k = " << k;
  }
}

// A strong 3-lobe form survives (amplitude A√(1 − V/A²) ≈ A) while the noise harmonics of the
// measured profile are zeroed: the surrogate keeps the form and drops the noise.
TEST(FormBias, SurrogateKeepsStrongFormAndDropsNoise) {
  em::DigitalModel model = perfect_model();
  const double sigma = 0.5e-3;
  model.noise.scanning_sigma_mm = sigma;
  const double amplitude = 2e-3;
  const auto truth = ring(720, {{3, amplitude, 0.4}});
  em::SeededRandomSource rng(5);
  const auto measured = em::simulate(truth, model, em::draw_errors(model, truth, rng));
  RingEvaluationOptions e;
  e.reference = ReferenceCircle::least_squares;
  const auto s = estimate_harmonic_shrinkage(model, measured, e, em::Stages::all(), {}, pilot(9));
  ASSERT_TRUE(s.has_value());
  const Surrogate p = shrunk_ring(measured, *s, e);
  // Noise harmonics pass ln K with probability 1/K: a handful at most survive.
  EXPECT_GE(p.kept_harmonics, 1u);
  EXPECT_LE(p.kept_harmonics, 8u);
  const auto profile = ring_profile(p.surface);
  const auto ls = geometry::least_squares_circle(profile);
  const geometry::ProfileHarmonics h(profile, ls.center, ls.radius, s->max_order);
  // The 3-lobe amplitude: the measured one (noise moves it by ~√V ≈ 0.04 µm) shrunk by
  // √(1 − ln K·V/P) (0.1 %).
  EXPECT_NEAR(std::sqrt(h.power_mm2(3)), amplitude, 0.1e-3);
  double rest = 0.0;
  for (std::size_t k = 2; k <= s->max_order; ++k) rest += k == 3 ? 0.0 : h.power_mm2(k);
  const double noise_power = 126.0 * 4.0 * sigma * sigma / 720.0;  // all noise harmonics
  EXPECT_LT(rest, 0.1 * noise_power);
  // The surrogate's RONt (LS, filtered) is the 3-lobe's 2A to within the remaining noise.
  EXPECT_NEAR(p.measurands.roundness_mm, 2.0 * amplitude * std::exp2(-std::pow(3.0 / 50.0, 2)),
              0.3e-3);
}

// A perfect ring measured without form: every harmonic k ≥ 2 is zeroed, the surrogate is a
// circle and its RONt is 0 without asking the MZ fitter (which is slow on such data).
TEST(FormBias, NoFormLeftGivesZeroRoundness) {
  em::DigitalModel model = perfect_model();
  model.noise.scanning_sigma_mm = 0.5e-3;
  const auto m = ring(3600, {});
  RingEvaluationOptions e;
  e.reference = ReferenceCircle::minimum_zone;
  const auto s = estimate_harmonic_shrinkage(model, m, e, em::Stages::all(), {}, pilot(1));
  ASSERT_TRUE(s.has_value());
  const Surrogate p = shrunk_ring(m, *s, e);
  EXPECT_EQ(p.kept_harmonics, 0u);
  EXPECT_EQ(p.measurands.roundness_mm, 0.0);
  EXPECT_NEAR(p.measurands.diameter_mm, 171.0, 1e-9);
}

TEST(FormBias, TheTreatmentIsTheSameForAnyThreadCount) {
  em::DigitalModel model = perfect_model();
  model.noise.scanning_sigma_mm = 0.5e-3;
  model.probe.directional = {{2, {0.0, 0.15e-3}, {0.0, 0.15e-3}}};
  const auto m = ring(360, em::seed_study_ring_form());
  RingUncertaintyOptions o;
  o.evaluation.filter_cutoff_upr = 15.0;
  o.monte_carlo.trials = 60;
  o.monte_carlo.seed = 77;
  o.shrinkage.pilot_trials = 50;
  o.monte_carlo.threads = 1;
  const auto one = evaluate_ring_uncertainty(model, m, o);
  o.monte_carlo.threads = 3;
  const auto three = evaluate_ring_uncertainty(model, m, o);
  ASSERT_TRUE(one.surrogate && three.surrogate);
  EXPECT_EQ(one.roundness_treatment, RoundnessBiasTreatment::shrinkage);
  EXPECT_EQ(one.surrogate->shrinkage.error_power_mm2, three.surrogate->shrinkage.error_power_mm2);
  EXPECT_EQ(one.surrogate->monte_carlo.samples, three.surrogate->monte_carlo.samples);
  EXPECT_EQ(one.roundness.corrected, three.roundness.corrected);
  EXPECT_EQ(one.roundness.standard_uncertainty, three.roundness.standard_uncertainty);
  // The study's treatment is reported beside it, from the first run.
  EXPECT_EQ(one.roundness_paper.bias,
            one.monte_carlo.summaries[roundness].mean - one.estimate.roundness_mm);
  // u_c² = s(y*)² + s(z*)² + s(y*)²/M.
  const auto& ys = one.surrogate->monte_carlo.summaries[surrogate_roundness];
  const auto& zs = one.surrogate->monte_carlo.summaries[surrogate_shrunk];
  EXPECT_DOUBLE_EQ(one.roundness.bias_uncertainty, zs.standard_uncertainty);
  EXPECT_NEAR(one.roundness.standard_uncertainty,
              std::sqrt(ys.standard_uncertainty * ys.standard_uncertainty * (1.0 + 1.0 / 60.0) +
                        zs.standard_uncertainty * zs.standard_uncertainty),
              1e-15);
  // The paper treatment by name: no second run.
  o.roundness_bias = RoundnessBiasTreatment::paper;
  const auto paper = evaluate_ring_uncertainty(model, m, o);
  EXPECT_FALSE(paper.surrogate.has_value());
  EXPECT_EQ(paper.roundness.corrected, paper.roundness_paper.corrected);
}

TEST(FormBias, TreatmentNamesRoundTrip) {
  for (auto t : {RoundnessBiasTreatment::shrinkage, RoundnessBiasTreatment::paper})
    EXPECT_EQ(roundness_bias_treatment_from_string(to_string(t)), t);
  EXPECT_FALSE(roundness_bias_treatment_from_string("Paper").has_value());
}

TEST(FormBias, BadOptionsAreRefused) {
  const em::DigitalModel model = perfect_model();
  const auto m = ring(360, {});
  ShrinkageOptions so;
  so.dominance_ratio = std::nan("");
  EXPECT_THROW(estimate_harmonic_shrinkage(model, m, {}, em::Stages::all(), so, pilot(1)),
               std::invalid_argument);
  so = {};
  so.pilot_trials = 1;
  EXPECT_THROW(estimate_harmonic_shrinkage(model, m, {}, em::Stages::all(), so, pilot(1)),
               std::invalid_argument);
}

}  // namespace
}  // namespace vcmm::validation
