// Tests of the uncertainty budget (validation/ring_uncertainty_budget.h): a model with one
// non-zero source gives that source the full u exactly (common random numbers) and the others
// 0; the diameter's one-at-a-time u's add in quadrature to the full u within the Monte Carlo
// precision; a source switched off gives 0; the same numbers for any thread count; fewer
// budget trials compare with the full run over the same trials.
#include "vcmm/validation/ring_uncertainty_budget.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "vcmm/errormodel/ring_gauge.h"
#include "vcmm/validation/ring_experiment.h"
#include "support/perfect_model.h"

namespace vcmm::validation {
namespace {

namespace em = vcmm::errormodel;

using test::perfect_model;

/// 180 scanning points of the seed study's ring form, at 20 °C unless said.
em::Measurement ring(double temperature_c = 20.0) {
  em::RingGauge g;
  g.form = em::seed_study_ring_form();
  em::RingSampling s;
  s.points = 180;
  s.placement.location_mm = {600.0, 500.0, 400.0};
  s.temperature_c = temperature_c;
  return em::ring_gauge_measurement(g, s);
}

/// Small and fast: the study's bias treatment (no second run), a 15 UPR filter.
RingUncertaintyOptions options(std::uint64_t trials) {
  RingUncertaintyOptions o;
  o.evaluation.filter_cutoff_upr = 15.0;
  o.roundness_bias = RoundnessBiasTreatment::paper;
  o.monte_carlo.trials = trials;
  o.monte_carlo.seed = 11;
  o.monte_carlo.threads = 2;
  o.budget = BudgetOptions{};
  return o;
}

const SourceContribution& of(const UncertaintyBudget& b, em::ErrorSource s) {
  return b.sources.at(static_cast<std::size_t>(s));
}

/// The model with only source `s` non-zero.
em::DigitalModel only(em::ErrorSource s) {
  em::DigitalModel m = perfect_model();
  switch (s) {
    case em::ErrorSource::roughness: m.roughness.sigma_mm = 0.2e-3; break;
    case em::ErrorSource::temperature:
      m.temperature.expansion_coefficient_per_k = {11.5e-6, 1e-6};
      m.temperature.thermometer_u_k = 0.1;
      break;
    case em::ErrorSource::kinematic: break;  // the perfect machine: nothing to draw
    case em::ErrorSource::probe:
      m.probe.tip_radius_error_mm = {0.0, 0.1e-3};
      m.probe.directional = {{3, {0.0, 0.05e-3}, {0.0, 0.05e-3}}};
      break;
    case em::ErrorSource::noise: m.noise.scanning_sigma_mm = 0.3e-3; break;
  }
  return m;
}

// With one non-zero source the full run and that source's run see the same numbers and do the
// same arithmetic (at 20 °C the expansion factors are exactly 1): equal u, bit for bit; every
// other source's run repeats the estimate in every trial: u = 0 (to rounding of the mean).
TEST(UncertaintyBudget, OneNonZeroSourceTakesTheWholeUncertainty) {
  for (const em::ErrorSource s : {em::ErrorSource::roughness, em::ErrorSource::temperature,
                                  em::ErrorSource::probe, em::ErrorSource::noise}) {
    const std::string name(em::to_string(s));
    const auto r = evaluate_ring_uncertainty(only(s), ring(), options(60));
    ASSERT_TRUE(r.budget.has_value()) << name;
    const UncertaintyBudget& b = *r.budget;
    ASSERT_EQ(b.sources.size(), 5u);
    EXPECT_EQ(b.trials, 60u);
    const auto& full = r.monte_carlo.summaries;
    EXPECT_GT(full[diameter].standard_uncertainty, 0.0) << name;
    EXPECT_EQ(of(b, s).diameter_u_mm, full[diameter].standard_uncertainty) << name;
    EXPECT_EQ(of(b, s).roundness_u_mm, full[roundness].standard_uncertainty) << name;
    EXPECT_EQ(b.diameter_full_u_mm, full[diameter].standard_uncertainty) << name;
    EXPECT_EQ(of(b, s).diameter_share, 1.0) << name;
    for (const SourceContribution& c : b.sources) {
      EXPECT_TRUE(c.evaluated);
      if (c.source == s) continue;
      // Identical samples: the sample sd is the rounding of their mean, ≤ 1e-16 · 171 mm.
      EXPECT_LT(c.diameter_u_mm, 1e-12) << name << " / " << em::to_string(c.source);
      EXPECT_LT(c.roundness_u_mm, 1e-12) << name << " / " << em::to_string(c.source);
    }
    EXPECT_DOUBLE_EQ(b.diameter_quadrature_mm, full[diameter].standard_uncertainty) << name;
  }
}

// All sources on (the bundled example model, with its kinematic errors) at 20.4 °C. The LS
// diameter is linear in the errors to ~1e-6 relative, so u² = Σ u_i² + 2 Σ cov_ij, the sample
// covariances of independent sources: |u_Σ/u − 1| has a standard deviation ≤ 1/√(2M) (the
// relative standard error of u); allow 4 of them.
TEST(UncertaintyBudget, DiameterUncertaintiesAddInQuadrature) {
  const em::DigitalModel model =
      em::read_digital_model_file(std::string(VCMM_SOURCE_DIR) + "/examples/cmm_model.json");
  auto m = ring(20.4);
  m.stylus_offset_mm = {0.0, 0.0, -100.0};
  const std::uint64_t trials = 400;
  const auto r = evaluate_ring_uncertainty(model, m, options(trials));
  ASSERT_TRUE(r.budget.has_value());
  const UncertaintyBudget& b = *r.budget;
  for (const SourceContribution& c : b.sources)
    EXPECT_GT(c.diameter_u_mm, 0.0) << em::to_string(c.source);
  const double u = r.monte_carlo.summaries[diameter].standard_uncertainty;
  const double tolerance = 4.0 / std::sqrt(2.0 * (trials - 1));
  EXPECT_NEAR(b.diameter_quadrature_mm / u, 1.0, tolerance);
  double shares = 0.0;
  for (const SourceContribution& c : b.sources) shares += c.roundness_share;
  EXPECT_NEAR(shares, 1.0, 1e-12);
  EXPECT_GT(b.roundness_quadrature_mm, 0.0);
}

TEST(UncertaintyBudget, ASourceSwitchedOffGivesZero) {
  em::DigitalModel model = only(em::ErrorSource::noise);
  model.probe.tip_radius_error_mm = {0.0, 0.1e-3};
  // Zero in the model: the noise source's run repeats the estimate.
  model.noise.scanning_sigma_mm = 0.0;
  auto o = options(40);
  auto r = evaluate_ring_uncertainty(model, ring(), o);
  EXPECT_LT(of(*r.budget, em::ErrorSource::noise).diameter_u_mm, 1e-12);
  EXPECT_LT(of(*r.budget, em::ErrorSource::noise).roundness_u_mm, 1e-12);
  EXPECT_GT(of(*r.budget, em::ErrorSource::probe).diameter_u_mm, 0.0);
  // Off in the evaluation's stages: not run, reported as such with u = 0.
  o.stages.set(em::ErrorSource::probe, false);
  r = evaluate_ring_uncertainty(model, ring(), o);
  EXPECT_FALSE(of(*r.budget, em::ErrorSource::probe).evaluated);
  EXPECT_EQ(of(*r.budget, em::ErrorSource::probe).diameter_u_mm, 0.0);
  EXPECT_EQ(of(*r.budget, em::ErrorSource::probe).diameter_share, 0.0);
}

TEST(UncertaintyBudget, SameNumbersWhateverTheThreadCount) {
  em::DigitalModel model = only(em::ErrorSource::noise);
  model.probe.tip_radius_error_mm = {0.0, 0.1e-3};
  model.roughness.sigma_mm = 0.1e-3;
  auto o = options(50);
  o.monte_carlo.threads = 1;
  const auto one = evaluate_ring_uncertainty(model, ring(), o);
  o.monte_carlo.threads = 3;
  const auto three = evaluate_ring_uncertainty(model, ring(), o);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(one.budget->sources[i].diameter_u_mm, three.budget->sources[i].diameter_u_mm);
    EXPECT_EQ(one.budget->sources[i].roundness_u_mm, three.budget->sources[i].roundness_u_mm);
  }
  EXPECT_EQ(one.budget->roundness_quadrature_mm, three.budget->roundness_quadrature_mm);
}

// Budget runs of fewer trials than the full run compare with the full run's first trials
// (the same numbers): its u over them is the u of a full run of that many trials.
TEST(UncertaintyBudget, FewerTrialsCompareWithTheSameTrialsOfTheFullRun) {
  const em::DigitalModel model = only(em::ErrorSource::noise);
  auto o = options(80);
  o.budget->trials = 30;
  const auto r = evaluate_ring_uncertainty(model, ring(), o);
  EXPECT_EQ(r.budget->trials, 30u);
  const auto short_run = evaluate_ring_uncertainty(model, ring(), options(30));
  EXPECT_EQ(r.budget->roundness_full_u_mm,
            short_run.monte_carlo.summaries[roundness].standard_uncertainty);
  EXPECT_EQ(of(*r.budget, em::ErrorSource::noise).roundness_u_mm,
            short_run.monte_carlo.summaries[roundness].standard_uncertainty);
  // More than the full run's: cut to them.
  EXPECT_EQ(budget_trials(BudgetOptions{500}, 80), 80u);
  EXPECT_EQ(budget_trials(BudgetOptions{}, 80), 80u);
}

TEST(UncertaintyBudget, AnAppliedStageMustBeDrawn) {
  const em::DigitalModel model = only(em::ErrorSource::noise);
  auto prepared = std::make_shared<const em::PreparedMeasurement>(ring(), model);
  EXPECT_THROW(RingTrial(model, prepared, {}, em::Stages::only(em::ErrorSource::probe),
                         em::Stages::only(em::ErrorSource::noise)),
               geometry::InvalidInput);
  uncertainty::MonteCarloResult empty;
  EXPECT_THROW(ring_uncertainty_budget(model, ring(), {}, em::Stages::all(), empty, {}, {}),
               uncertainty::InvalidInput);
}

}  // namespace
}  // namespace vcmm::validation
