// correct_bias: the reflection arithmetic on hand examples, the non-negativity guard (refused,
// note, widened interval), known biases recovered through the Monte Carlo engine within
// their Monte Carlo standard error, and one bad-input test per precondition.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "vcmm/uncertainty/bias.h"
#include "vcmm/uncertainty/monte_carlo.h"
#include "vcmm/uncertainty/random_stream.h"

namespace {

using namespace vcmm::uncertainty;

MeasurandSummary summary(double mean, double u, double low, double high,
                         std::uint64_t count = 10'000) {
  MeasurandSummary s;
  s.count = count;
  s.mean = mean;
  s.standard_uncertainty = u;
  s.probabilistically_symmetric = {low, high, 0.95};
  s.shortest = {low, high, 0.95};
  return s;
}

template <class F>
void expect_invalid(F f, std::initializer_list<std::string> parts) {
  try {
    f();
    ADD_FAILURE() << "no exception";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    for (const std::string& p : parts) EXPECT_NE(what.find(p), std::string::npos) << what;
  }
}

double normal_pdf(double x) { return std::exp(-0.5 * x * x) / std::sqrt(2.0 * std::numbers::pi); }
double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::numbers::sqrt2); }

TEST(CorrectBias, ReflectionArithmeticByHand) {
  // x = 1, ȳ = 1.2, u = 0.1, M = 10 000, MC interval [1.0, 1.45]: b = 0.2, x − b = 0.8,
  // u/√M = 0.001, u_c = √(0.01 + 1e-6), interval [2 − 1.45, 2 − 1.0] = [0.55, 1.0].
  const BiasCorrection c = correct_bias(1.0, summary(1.2, 0.1, 1.0, 1.45), true);
  EXPECT_TRUE(c.applied);
  EXPECT_FALSE(c.refused);
  EXPECT_EQ(c.estimate, 1.0);
  EXPECT_EQ(c.monte_carlo_mean, 1.2);
  EXPECT_DOUBLE_EQ(c.bias, 0.2);
  EXPECT_DOUBLE_EQ(c.corrected, 0.8);
  EXPECT_DOUBLE_EQ(c.bias_standard_error, 0.001);
  EXPECT_DOUBLE_EQ(c.standard_uncertainty, std::sqrt(0.01 + 1e-6));
  EXPECT_DOUBLE_EQ(c.interval.low, 0.55);
  EXPECT_DOUBLE_EQ(c.interval.high, 1.0);
  EXPECT_EQ(c.interval.probability, 0.95);
  EXPECT_NE(c.note.find("subtracted"), std::string::npos) << c.note;
  EXPECT_NE(c.note.find("reflected"), std::string::npos) << c.note;
  // A negative bias moves the value up; the reflection is symmetric about x.
  const BiasCorrection d = correct_bias(2.0, summary(1.9, 0.1, 1.7, 2.05), false);
  EXPECT_DOUBLE_EQ(d.corrected, 2.1);
  EXPECT_DOUBLE_EQ(d.interval.low, 1.95);
  EXPECT_DOUBLE_EQ(d.interval.high, 2.3);
}

TEST(CorrectBias, NegativeCorrectionOfANonNegativeQuantityIsRefused) {
  // x = 0.1, ȳ = 0.35 (b = 0.25 > x): x − b = −0.15 < 0 → refused. Reported 0.1 with
  // u = √(0.05² + 0.25²) and the wide interval [max(0, 0.26 − 0.25), 0.45 + 0.25].
  const BiasCorrection c = correct_bias(0.1, summary(0.35, 0.05, 0.26, 0.45), true);
  EXPECT_TRUE(c.refused);
  EXPECT_FALSE(c.applied);
  EXPECT_EQ(c.corrected, 0.1);
  EXPECT_DOUBLE_EQ(c.bias, 0.25);
  EXPECT_DOUBLE_EQ(c.standard_uncertainty, std::sqrt(0.0025 + 0.0625));
  EXPECT_NEAR(c.interval.low, 0.01, 1e-15);
  EXPECT_DOUBLE_EQ(c.interval.high, 0.70);
  EXPECT_NE(c.note.find("refused"), std::string::npos) << c.note;
  EXPECT_NE(c.note.find("uncorrected"), std::string::npos) << c.note;
  // The widened low end is clamped at 0.
  const BiasCorrection z = correct_bias(0.1, summary(0.35, 0.05, 0.2, 0.45), true);
  EXPECT_EQ(z.interval.low, 0.0);
  // The same numbers for a signed quantity: applied, negative value allowed.
  const BiasCorrection s = correct_bias(0.1, summary(0.35, 0.05, 0.26, 0.45), false);
  EXPECT_TRUE(s.applied);
  EXPECT_DOUBLE_EQ(s.corrected, -0.15);
  EXPECT_DOUBLE_EQ(s.interval.low, -0.25);
  EXPECT_DOUBLE_EQ(s.interval.high, -0.06);
  // Exactly zero after correction is not negative: applied.
  EXPECT_TRUE(correct_bias(0.25, summary(0.5, 0.05, 0.4, 0.6), true).applied);
}

TEST(CorrectBias, AppliedReflectionIsClampedAtZeroForANonNegativeQuantity) {
  // x = 0.3, ȳ = 0.35, interval [0.1, 0.7]: x − b = 0.25 ≥ 0 → applied; reflection
  // [−0.1, 0.5] → [0, 0.5] with a note.
  const BiasCorrection c = correct_bias(0.3, summary(0.35, 0.15, 0.1, 0.7), true);
  EXPECT_TRUE(c.applied);
  EXPECT_DOUBLE_EQ(c.corrected, 0.25);
  EXPECT_EQ(c.interval.low, 0.0);
  EXPECT_DOUBLE_EQ(c.interval.high, 0.5);
  EXPECT_NE(c.note.find("clamped at 0"), std::string::npos) << c.note;
}

TEST(CorrectBias, KnownBiasesAreRecoveredWithinTheirMonteCarloStandardError) {
  // (1) Y = max of 5 values x + e_i, e_i ~ N(0, 1), x = 0: b = E max = ∫ 5 z φ(z) Φ(z)⁴ dz
  // (= 1.16296…, trapezoid rule below, error < 1e-9). (2) Y = |x + e|, x = 0.3, e ~ N(0, 0.5²):
  // folded normal, E Y = σ√(2/π) e^{−x²/2σ²} + x(1 − 2Φ(−x/σ)), b = E Y − x.
  // Tolerance: 5 Monte Carlo standard errors u/√M.
  constexpr std::uint64_t m = 100'000;
  double expected_max = 0.0;
  for (int i = 0; i <= 20'000; ++i) {
    const double z = -10.0 + 0.001 * i;
    const double w = (i == 0 || i == 20'000) ? 0.5 : 1.0;
    expected_max += w * 0.001 * z * 5.0 * normal_pdf(z) * std::pow(normal_cdf(z), 4);
  }
  const Experiment max_of_5 = [](RandomStream& rng, std::span<double> y) {
    double e[5];
    rng.fill_standard_normal(e);
    y[0] = *std::max_element(e, e + 5);
  };
  MonteCarloOptions o;
  o.trials = m;
  o.threads = 2;
  const MonteCarloResult r1 = run_monte_carlo(max_of_5, 1, o);
  const BiasCorrection c1 = correct_bias(0.0, r1.summaries.at(0), false);
  EXPECT_NEAR(c1.bias, expected_max, 5.0 * c1.bias_standard_error);
  EXPECT_NEAR(c1.corrected, -expected_max, 5.0 * c1.bias_standard_error);
  EXPECT_NEAR(c1.bias_standard_error, r1.summaries[0].standard_uncertainty / std::sqrt(1e5), 1e-18);

  constexpr double x = 0.3, sigma = 0.5;
  const Experiment folded = [](RandomStream& rng, std::span<double> y) {
    y[0] = std::abs(x + sigma * rng.standard_normal());
  };
  const double mean = sigma * std::sqrt(2.0 / std::numbers::pi) * std::exp(-x * x / (2 * sigma * sigma)) +
                      x * (1.0 - 2.0 * normal_cdf(-x / sigma));
  const MonteCarloResult r2 = run_monte_carlo(folded, 1, o);
  const BiasCorrection c2 = correct_bias(x, r2.summaries.at(0), true);
  EXPECT_NEAR(c2.bias, mean - x, 5.0 * c2.bias_standard_error);
  EXPECT_TRUE(c2.applied);  // x − b = 0.6 − E Y ≈ 0.13 > 0
}

TEST(CorrectBias, BadInput) {
  const MeasurandSummary ok = summary(1.0, 0.1, 0.8, 1.2);
  expect_invalid([&] { correct_bias(std::nan(""), ok, false); }, {"correct_bias", "estimate", "finite"});
  expect_invalid([&] { correct_bias(INFINITY, ok, false); }, {"estimate", "inf"});
  MeasurandSummary s = ok;
  s.mean = std::nan("");
  expect_invalid([&] { correct_bias(1.0, s, false); }, {"summary.mean"});
  s = ok;
  s.probabilistically_symmetric.high = INFINITY;
  expect_invalid([&] { correct_bias(1.0, s, false); }, {"probabilistically_symmetric.high"});
  s = ok;
  s.count = 0;
  expect_invalid([&] { correct_bias(1.0, s, false); }, {"summary.count must be >= 1"});
  s = ok;
  s.standard_uncertainty = -0.1;
  expect_invalid([&] { correct_bias(1.0, s, false); }, {"standard_uncertainty must be >= 0"});
  s = ok;
  s.probabilistically_symmetric = {1.3, 1.2, 0.95};
  expect_invalid([&] { correct_bias(1.0, s, false); }, {"low <= high"});
  expect_invalid([&] { correct_bias(-0.5, ok, true); }, {"non-negative", "estimate >= 0", "-0.5"});
}

}  // namespace

// ---- correct_bias_at_surrogate and standard_normal_quantile -------------------------------

namespace {

TEST(StandardNormalQuantile, MatchesTheCdfToRounding) {
  for (double p : {1e-300, 1e-12, 0.001, 0.02425, 0.025, 0.3, 0.5, 0.8, 0.975, 0.999, 1 - 1e-12}) {
    const double x = standard_normal_quantile(p);
    // Φ(x) = p to a few ulp of p (relative), or of 1 − p in the upper tail.
    const double tail = p < 0.5 ? normal_cdf(x) : 1.0 - normal_cdf(x);
    const double want = p < 0.5 ? p : 1.0 - p;
    EXPECT_NEAR(tail / want, 1.0, 1e-9) << "p = " << p;
  }
  EXPECT_NEAR(standard_normal_quantile(0.975), 1.959963984540054, 1e-14);
  EXPECT_EQ(standard_normal_quantile(0.5), 0.0);
  expect_invalid([] { standard_normal_quantile(0.0); }, {"standard_normal_quantile", "(0, 1)"});
  expect_invalid([] { standard_normal_quantile(1.0); }, {"(0, 1)"});
  expect_invalid([] { standard_normal_quantile(NAN); }, {"(0, 1)"});
}

TEST(CorrectBiasAtSurrogate, ArithmeticByHand) {
  // y = 1.0, f(ŝ) = 0.2, ȳ* = 0.9 (b = 0.7), s(y*) = 0.3, s(z*) = 0.4, M = 10 000,
  // interval of y* [0.4, 1.5]: corrected 0.3, u_c = √(0.09 + 0.16 + 0.09/1e4),
  // interval [0.3 − √(0.6² + (1.96·0.4)²), 0.3 + √(0.5² + (1.96·0.4)²)], low clamped at 0.
  const BiasCorrection c = correct_bias_at_surrogate(1.0, 0.2, summary(0.9, 0.3, 0.4, 1.5),
                                                     summary(0.25, 0.4, 0.0, 1.0), true);
  const double kp = standard_normal_quantile(0.975);
  EXPECT_TRUE(c.applied);
  EXPECT_FALSE(c.refused);
  EXPECT_FALSE(c.clamped);
  EXPECT_DOUBLE_EQ(c.bias, 0.7);
  EXPECT_DOUBLE_EQ(c.corrected, 0.3);
  EXPECT_DOUBLE_EQ(c.bias_uncertainty, 0.4);
  EXPECT_DOUBLE_EQ(c.bias_standard_error, 0.003);
  EXPECT_DOUBLE_EQ(c.standard_uncertainty, std::sqrt(0.09 + 0.16 + 0.09e-4));
  EXPECT_EQ(c.interval.low, 0.0);  // 0.3 − 0.99 < 0: clamped
  EXPECT_DOUBLE_EQ(c.interval.high, 0.3 + std::hypot(0.5, kp * 0.4));
  EXPECT_NE(c.note.find("surrogate"), std::string::npos) << c.note;
  EXPECT_NE(c.note.find("clamped at 0"), std::string::npos) << c.note;
}

TEST(CorrectBiasAtSurrogate, NegativeCorrectedValueIsClampedAndSaid) {
  const BiasCorrection c = correct_bias_at_surrogate(0.5, 0.1, summary(1.0, 0.2, 0.7, 1.4),
                                                     summary(0.1, 0.1, 0.0, 0.3), true);
  EXPECT_TRUE(c.clamped);
  EXPECT_EQ(c.corrected, 0.0);
  EXPECT_NE(c.note.find("reported as 0"), std::string::npos) << c.note;
  // The reflected interval would be [0, −0.4 + √(0.3² + (1.96·0.1)²)] = [0, −0.042]: its upper
  // end is that of N(−0.4, u_c²) truncated at 0 instead: P(0 ≤ X ≤ q) = 0.95·P(X ≥ 0).
  EXPECT_EQ(c.interval.low, 0.0);
  EXPECT_GT(c.interval.high, 0.0);
  const double uc = c.standard_uncertainty;
  const double above = 1.0 - normal_cdf(0.4 / uc);
  const double inside = normal_cdf((c.interval.high + 0.4) / uc) - normal_cdf(0.4 / uc);
  EXPECT_NEAR(inside / above, 0.95, 1e-9);
  EXPECT_NE(c.note.find("truncated at 0"), std::string::npos) << c.note;
  // A signed quantity is not clamped.
  const BiasCorrection d = correct_bias_at_surrogate(0.5, 0.1, summary(1.0, 0.2, 0.7, 1.4),
                                                     summary(0.1, 0.1, 0.0, 0.3), false);
  EXPECT_FALSE(d.clamped);
  EXPECT_DOUBLE_EQ(d.corrected, -0.4);
}

TEST(CorrectBiasAtSurrogate, IntervalFarBelowZeroStillEndsAboveZero) {
  // Corrected −50 with u_c ≈ 0.22 (223 standard uncertainties below 0): the truncated normal's
  // tail underflows; its exponential limit gives q = u_c² ln 20 / 50.
  const BiasCorrection c = correct_bias_at_surrogate(0.0, 0.0, summary(50.0, 0.2, 49.6, 50.4),
                                                     summary(0.0, 0.1, 0.0, 0.3), true);
  EXPECT_TRUE(c.clamped);
  EXPECT_EQ(c.interval.low, 0.0);
  const double uc = c.standard_uncertainty;
  EXPECT_NEAR(c.interval.high, uc * uc * std::log(20.0) / 50.0, 1e-12);
  EXPECT_LT(c.interval.low, c.interval.high);
  // A clamped lower end with a positive reflected upper end keeps the reflected one.
  const BiasCorrection d = correct_bias_at_surrogate(1.0, 0.2, summary(0.9, 0.3, 0.4, 1.5),
                                                     summary(0.25, 0.4, 0.0, 1.0), true);
  EXPECT_DOUBLE_EQ(d.interval.high, 0.3 + std::hypot(0.5, standard_normal_quantile(0.975) * 0.4));
}

TEST(CorrectBiasAtSurrogate, RejectsBadInputNamingIt) {
  const auto s = summary(1.0, 0.2, 0.7, 1.4);
  expect_invalid([&] { correct_bias_at_surrogate(NAN, 0.1, s, s, true); }, {"estimate"});
  expect_invalid([&] { correct_bias_at_surrogate(1.0, INFINITY, s, s, true); },
                 {"surrogate_value"});
  expect_invalid([&] { correct_bias_at_surrogate(1.0, -0.1, s, s, true); }, {"non-negative"});
  expect_invalid([&] { correct_bias_at_surrogate(1.0, 0.1, summary(1, 0.2, 2, 1), s, true); },
                 {"low <= high"});
  expect_invalid([&] { correct_bias_at_surrogate(1.0, 0.1, summary(1, -0.2, 0, 1), s, true); },
                 {">= 0"});
  expect_invalid([&] { correct_bias_at_surrogate(1.0, 0.1, s, summary(1, 0.2, 0, 1, 0), true); },
                 {"count"});
}

TEST(DerivedSeed, DistinctForPurposesAndSeedsAndFixed) {
  EXPECT_NE(derived_seed(1, 1), derived_seed(1, 2));
  EXPECT_NE(derived_seed(1, 1), derived_seed(2, 1));
  EXPECT_NE(derived_seed(0, 0), 0u);
  EXPECT_EQ(derived_seed(1, 1), derived_seed(1, 1));
  // Pinned (the value of the formula in random_stream.h, computed independently in Python) so
  // that a change of the mixing, which would change every shrinkage result, shows.
  EXPECT_EQ(derived_seed(1, 1), 0x45c35442d09f4cd3ull);
}

}  // namespace
