// Tests of the spectral trial (validation/spectral_trial.h) against the exact point-wise trial
// (ring_experiment.h): per trial with the same parameter values (deterministic, to the
// documented bound), and in distribution (mean, u and the 2.5/97.5 % quantiles within four
// combined Monte Carlo standard errors) for scanning and touch, centre and corner, LS/MZ/MI.
// Fixed seeds; the tolerances are derived from the trial counts.
#include "vcmm/validation/spectral_trial.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/random_source.h"
#include "vcmm/errormodel/ring_gauge.h"
#include "vcmm/validation/ring_experiment.h"

namespace vcmm::validation {
namespace {

namespace em = vcmm::errormodel;

const em::DigitalModel& example_model() {
  static const em::DigitalModel model =
      em::read_digital_model_file(std::string(VCMM_SOURCE_DIR) + "/examples/cmm_model.json");
  return model;
}

const Eigen::Vector3d kCentre{600.0, 500.0, 250.0};  // the demo's location C
const Eigen::Vector3d kCorner{1000.0, 850.0, 600.0};  // the demo's E2: far corner, high

em::Measurement ring(em::ProbingMode mode, Eigen::Index n, const Eigen::Vector3d& location) {
  em::RingGauge g;
  g.form = em::seed_study_ring_form();
  em::RingSampling s;
  s.mode = mode;
  s.points = n;
  s.placement.location_mm = location;
  s.placement.orientation_rad = 0.3;
  s.start_angle_rad = 0.01;
  s.temperature_c = 20.4;
  s.stylus_offset_mm = {0.0, 0.0, -120.0};
  return em::ring_gauge_measurement(g, s);
}

RingEvaluationOptions with_reference(ReferenceCircle c) {
  RingEvaluationOptions o;
  o.reference = c;
  return o;
}

// ---- deterministic: the same parameter values, per trial --------------------------------------

struct PerTrial {
  double diameter = 0.0, roundness = 0.0;  // largest |spectral − exact| (mm)
};

/// Draws `trials` realisations of the systematic stages in `stages` and evaluates both trials
/// on each (no roughness or noise: their numbers cannot be shared between the two paths).
PerTrial per_trial_difference(const em::Measurement& best, const RingEvaluationOptions& o,
                              const em::Stages& stages, int trials, const SpectralBound** bound) {
  const em::DigitalModel& model = example_model();
  static std::shared_ptr<const SpectralRingModel> keep;
  keep = std::make_shared<const SpectralRingModel>(model, best, o, stages);
  *bound = &keep->bound();
  SpectralRingTrial spectral(keep);
  const em::PreparedMeasurement prepared(best, model);
  em::SeededRandomSource rng(20261127);
  em::ErrorDraw draw;
  std::vector<geometry::Point2> xy;
  PerTrial worst;
  for (int t = 0; t < trials; ++t) {
    em::draw_errors(model, prepared, rng, stages, draw);
    em::simulate_corrected(prepared, model, draw, stages, em::Formula::first_order, xy);
    const RingMeasurands exact = evaluate_ring(xy, o);
    const RingMeasurands fast = spectral.measurands(draw, {});
    worst.diameter = std::max(worst.diameter, std::abs(fast.diameter_mm - exact.diameter_mm));
    worst.roundness = std::max(worst.roundness, std::abs(fast.roundness_mm - exact.roundness_mm));
  }
  return worst;
}

// Each systematic source alone, then all three, in the centre and in the corner: the spectral
// trial reproduces the exact trial's measurands within the documented bound (and below 1 nm).
TEST(SpectralTrial, MatchesTheExactTrialPerTrialForTheSameParameterValues) {
  const std::vector<em::Stages> cases = {
      em::Stages::only(em::ErrorSource::temperature), em::Stages::only(em::ErrorSource::probe),
      em::Stages::only(em::ErrorSource::kinematic),
      em::Stages::none()
          .set(em::ErrorSource::temperature, true)
          .set(em::ErrorSource::probe, true)
          .set(em::ErrorSource::kinematic, true)};
  for (const Eigen::Vector3d& where : {kCentre, kCorner}) {
    const auto best = ring(em::ProbingMode::scanning, 3600, where);
    for (const ReferenceCircle c : {ReferenceCircle::least_squares, ReferenceCircle::minimum_zone,
                                    ReferenceCircle::maximum_inscribed}) {
      for (std::size_t i = 0; i < cases.size(); ++i) {
        const SpectralBound* bound = nullptr;
        const PerTrial d = per_trial_difference(best, with_reference(c), cases[i], 12, &bound);
        const std::string what = "case " + std::to_string(i) + " " + std::string(to_string(c)) +
                                 " at x = " + std::to_string(where.x());
        EXPECT_LE(d.diameter, bound->diameter_mm + 1e-12) << what;
        EXPECT_LE(d.roundness, bound->roundness_mm + 1e-12) << what;
        EXPECT_LT(d.diameter, 1e-6) << what;
        EXPECT_LT(d.roundness, 1e-6) << what;
        std::printf("[ per-trial ] %-40s |dD| %.2e mm (bound %.2e)  |dRONt| %.2e mm (bound %.2e)\n",
                    what.c_str(), d.diameter, bound->diameter_mm, d.roundness,
                    bound->roundness_mm);
      }
    }
  }
}

TEST(SpectralTrial, BoundIsBelowOneNanometreForTheExampleRing) {
  for (const auto mode : {em::ProbingMode::scanning, em::ProbingMode::touch_trigger}) {
    const auto best = ring(mode, mode == em::ProbingMode::scanning ? 3600 : 360, kCorner);
    const SpectralRingModel m(example_model(), best, {}, em::Stages::all());
    EXPECT_LT(m.bound().diameter_mm, 1e-6);
    EXPECT_LT(m.bound().roundness_mm, 1e-6);
    EXPECT_GE(m.bound().white_order, 2u);
    std::printf("[ bound ] %s: K_s %zu, K_w %zu, truncation %.1e, second order %.1e, "
                "kinematic position %.1e, grid %.1e; diameter %.1e, RONt %.1e mm\n",
                mode == em::ProbingMode::scanning ? "scanning 3600" : "touch 360",
                m.bound().systematic_order, m.bound().white_order, m.bound().truncation_mm,
                m.bound().second_order_mm, m.bound().kinematic_position_mm,
                m.bound().grid_offset_mm, m.bound().diameter_mm, m.bound().roundness_mm);
  }
}

// ---- in distribution ---------------------------------------------------------------------------

struct Moments {
  double mean = 0.0, u = 0.0, low = 0.0, high = 0.0;              // statistics
  double se_mean = 0.0, se_u = 0.0, se_low = 0.0, se_high = 0.0;  // their standard errors
};

/// Mean, u and the 2.5/97.5 % quantiles of one measurand with their Monte Carlo standard
/// errors: s/√M; s·√((κ − 1)/(4M)) (κ the sample kurtosis: the delta method for s); and for a
/// quantile, half the spread of the order statistics pM ± √(p(1 − p)M) (binomial).
Moments moments(const uncertainty::MonteCarloResult& r, std::size_t measurand) {
  std::vector<double> x(r.trials);
  for (std::size_t t = 0; t < r.trials; ++t) x[t] = r.samples[t * r.measurand_count + measurand];
  const double m = static_cast<double>(x.size());
  Moments out;
  for (double v : x) out.mean += v;
  out.mean /= m;
  double m2 = 0.0, m4 = 0.0;
  for (double v : x) {
    const double d2 = (v - out.mean) * (v - out.mean);
    m2 += d2;
    m4 += d2 * d2;
  }
  out.u = std::sqrt(m2 / (m - 1.0));
  const double kurtosis = (m4 / m) / ((m2 / m) * (m2 / m));
  out.se_mean = out.u / std::sqrt(m);
  out.se_u = out.u * std::sqrt(std::max(kurtosis - 1.0, 0.5) / (4.0 * m));
  std::sort(x.begin(), x.end());
  const auto at = [&](double index) {
    const auto i = static_cast<std::size_t>(std::clamp(index, 0.0, m - 1.0));
    return x[i];
  };
  const auto quantile = [&](double p, double& q, double& se) {
    const double k = p * m, w = std::sqrt(p * (1.0 - p) * m);
    q = at(k);
    se = 0.5 * (at(k + w) - at(k - w));
  };
  quantile(0.025, out.low, out.se_low);
  quantile(0.975, out.high, out.se_high);
  return out;
}

uncertainty::MonteCarloResult run(const uncertainty::ExperimentFactory& f, std::uint64_t trials,
                                  std::uint64_t seed) {
  uncertainty::MonteCarloOptions o;
  o.trials = trials;
  o.seed = seed;
  o.threads = 2;
  return uncertainty::run_monte_carlo(f, ring_measurand_count, o);
}

/// Runs both trials on the same best estimate (independent numbers) and checks every statistic
/// of both measurands within 4 combined standard errors.
void expect_same_distribution(em::ProbingMode mode, Eigen::Index n, const Eigen::Vector3d& where,
                              ReferenceCircle c, std::uint64_t exact_trials,
                              std::uint64_t spectral_trials,
                              const em::Stages& stages = em::Stages::all()) {
  const em::DigitalModel& model = example_model();
  const auto best = ring(mode, n, where);
  const RingEvaluationOptions o = with_reference(c);
  const auto exact = run(ring_experiment_factory(model, best, o, stages), exact_trials, 11);
  const auto spectral =
      run(spectral_ring_experiment_factory(model, best, o, stages), spectral_trials, 12);
  for (const std::size_t q : {std::size_t{diameter}, std::size_t{roundness}}) {
    const Moments e = moments(exact, q), s = moments(spectral, q);
    const auto check = [&](const char* what, double ve, double vs, double se_e, double se_s) {
      const double se = std::hypot(se_e, se_s);
      EXPECT_LE(std::abs(vs - ve), 4.0 * se)
          << (q == diameter ? "diameter " : "roundness ") << what << ": exact " << ve
          << " spectral " << vs << " (combined SE " << se << " mm), " << to_string(c) << ", "
          << n << " points at x = " << where.x();
      std::printf("[ distribution ] %-4s %-9s %-5s exact %.7f spectral %.7f diff %+.2e (%.1f SE)\n",
                  std::string(to_string(c)).c_str(), q == diameter ? "diameter" : "roundness",
                  what, ve, vs, vs - ve, (vs - ve) / se);
    };
    check("mean", e.mean, s.mean, e.se_mean, s.se_mean);
    check("u", e.u, s.u, e.se_u, s.se_u);
    check("q2.5", e.low, s.low, e.se_low, s.se_low);
    check("q97.5", e.high, s.high, e.se_high, s.se_high);
  }
}

TEST(SpectralTrialDistribution, ScanningCentreLeastSquares) {
  expect_same_distribution(em::ProbingMode::scanning, 3600, kCentre,
                           ReferenceCircle::least_squares, 6000, 40000);
}
TEST(SpectralTrialDistribution, ScanningCentreMinimumZone) {
  expect_same_distribution(em::ProbingMode::scanning, 3600, kCentre,
                           ReferenceCircle::minimum_zone, 6000, 30000);
}
TEST(SpectralTrialDistribution, ScanningCornerMaximumInscribed) {
  expect_same_distribution(em::ProbingMode::scanning, 3600, kCorner,
                           ReferenceCircle::maximum_inscribed, 5000, 20000);
}
TEST(SpectralTrialDistribution, ScanningCornerMinimumZone) {
  expect_same_distribution(em::ProbingMode::scanning, 3600, kCorner,
                           ReferenceCircle::minimum_zone, 5000, 20000);
}
TEST(SpectralTrialDistribution, TouchCentreMinimumZone) {
  expect_same_distribution(em::ProbingMode::touch_trigger, 360, kCentre,
                           ReferenceCircle::minimum_zone, 20000, 40000);
}
TEST(SpectralTrialDistribution, TouchCornerLeastSquaresAndMaximumInscribed) {
  expect_same_distribution(em::ProbingMode::touch_trigger, 360, kCorner,
                           ReferenceCircle::least_squares, 20000, 40000);
  expect_same_distribution(em::ProbingMode::touch_trigger, 360, kCorner,
                           ReferenceCircle::maximum_inscribed, 20000, 40000);
}

// The white parts alone (roughness and noise: where the spectral trial draws other numbers
// than the exact one, as exact Gaussian harmonics): a wrong variance would show at once (the
// diameter's u is 2√(v/n), the roundness is all noise).
TEST(SpectralTrialDistribution, WhitePartsAloneScanningAndTouch) {
  const em::Stages white = em::Stages::none()
                               .set(em::ErrorSource::roughness, true)
                               .set(em::ErrorSource::noise, true);
  expect_same_distribution(em::ProbingMode::scanning, 3600, kCentre,
                           ReferenceCircle::minimum_zone, 6000, 30000, white);
  expect_same_distribution(em::ProbingMode::touch_trigger, 360, kCorner,
                           ReferenceCircle::least_squares, 20000, 40000, white);
}

// Same seed, any thread count: the same samples.
TEST(SpectralTrial, SamplesDoNotDependOnTheThreadCount) {
  const auto best = ring(em::ProbingMode::scanning, 3600, kCentre);
  const auto f = spectral_ring_experiment_factory(example_model(), best, {}, em::Stages::all());
  uncertainty::MonteCarloOptions o;
  o.trials = 200;
  o.seed = 5;
  o.threads = 1;
  const auto one = uncertainty::run_monte_carlo(f, ring_measurand_count, o);
  o.threads = 2;
  const auto two = uncertainty::run_monte_carlo(f, ring_measurand_count, o);
  EXPECT_EQ(one.samples, two.samples);
}

// ---- applicability ------------------------------------------------------------------------------

TEST(SpectralTrial, RefusesWhereItDoesNotApplyAndSaysWhy) {
  const em::DigitalModel& model = example_model();
  const auto best = ring(em::ProbingMode::scanning, 720, kCentre);
  EXPECT_TRUE(spectral_trial_applicability(model, best, {}, em::Stages::all()).applicable);

  RingEvaluationOptions unfiltered;
  unfiltered.filter_cutoff_upr.reset();
  const auto no_filter = spectral_trial_applicability(model, best, unfiltered, em::Stages::all());
  EXPECT_FALSE(no_filter.applicable);
  EXPECT_NE(no_filter.reason.find("filter"), std::string::npos) << no_filter.reason;
  EXPECT_THROW(SpectralRingModel(model, best, unfiltered, em::Stages::all()),
               geometry::InvalidInput);

  em::Measurement shuffled = best;  // two points swapped: not equiangular in file order
  shuffled.points_mm.col(10).swap(shuffled.points_mm.col(500));
  shuffled.normals.col(10).swap(shuffled.normals.col(500));
  const auto grid = spectral_trial_applicability(model, shuffled, {}, em::Stages::all());
  EXPECT_FALSE(grid.applicable);
  EXPECT_NE(grid.reason.find("point 10"), std::string::npos) << grid.reason;
  try {
    SpectralRingModel(model, shuffled, {}, em::Stages::all());
    ADD_FAILURE() << "no exception";
  } catch (const geometry::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("equiangular"), std::string::npos) << e.what();
  }
}

// The evaluation picks the trial (auto: spectral where it applies), records it, and refuses
// spectral with the budget or where it does not apply.
TEST(SpectralTrial, EvaluationChoosesAndRecordsTheTrial) {
  const em::DigitalModel& model = example_model();
  const auto best = ring(em::ProbingMode::scanning, 720, kCentre);
  RingUncertaintyOptions o;
  o.roundness_bias = RoundnessBiasTreatment::paper;
  o.monte_carlo.trials = 200;
  o.monte_carlo.threads = 1;
  const auto automatic = evaluate_ring_uncertainty_on_surface(model, best, o);
  EXPECT_EQ(automatic.trial.kind, TrialKind::spectral) << automatic.trial.reason;
  o.trial = TrialKind::exact;
  EXPECT_EQ(evaluate_ring_uncertainty_on_surface(model, best, o).trial.kind, TrialKind::exact);
  o.trial = TrialKind::automatic;
  o.budget = BudgetOptions{};
  const auto with_budget = evaluate_ring_uncertainty_on_surface(model, best, o);
  EXPECT_EQ(with_budget.trial.kind, TrialKind::exact);
  EXPECT_NE(with_budget.trial.reason.find("budget"), std::string::npos);
  o.trial = TrialKind::spectral;
  EXPECT_THROW(evaluate_ring_uncertainty_on_surface(model, best, o), geometry::InvalidInput);
  o.budget.reset();
  o.evaluation.filter_cutoff_upr.reset();
  EXPECT_THROW(evaluate_ring_uncertainty_on_surface(model, best, o), geometry::InvalidInput);
  o.trial = TrialKind::automatic;
  const auto unfiltered = evaluate_ring_uncertainty_on_surface(model, best, o);
  EXPECT_EQ(unfiltered.trial.kind, TrialKind::exact);
  EXPECT_NE(unfiltered.trial.reason.find("filter"), std::string::npos);
}

TEST(SpectralTrial, TrialKindNamesRoundTrip) {
  for (const TrialKind k : {TrialKind::automatic, TrialKind::exact, TrialKind::spectral})
    EXPECT_EQ(trial_kind_from_string(to_string(k)), k);
  EXPECT_FALSE(trial_kind_from_string("fast").has_value());
}

}  // namespace
}  // namespace vcmm::validation
