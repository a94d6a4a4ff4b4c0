// summarize / correlation_matrix: JCGM 101 7.7 index rules on hand-checkable cases,
// numerical stability, the shortest vs symmetric interval on a skewed law, correlation, and
// one bad-input test per precondition. Statistical tolerances are derived from M where used.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

#include "vcmm/uncertainty/errors.h"
#include "vcmm/uncertainty/random_stream.h"
#include "vcmm/uncertainty/statistics.h"

namespace {

using namespace vcmm::uncertainty;

/// Expects `f()` to throw InvalidInput whose message contains every piece of `parts`.
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

/// 1, 2, …, m in a scrambled order (the summary must not depend on the order).
std::vector<double> scrambled_ramp(std::size_t m) {
  std::vector<double> y(m);
  for (std::size_t i = 0; i < m; ++i) y[i] = static_cast<double>((i * 7 + 3) % m + 1);
  return y;
}

TEST(CoverageIndex, Jcgm101RoundingRule) {
  EXPECT_EQ(coverage_index(1'000'000, 0.95), 950'000u);  // pM integer
  EXPECT_EQ(coverage_index(20, 0.95), 19u);
  EXPECT_EQ(coverage_index(11, 0.95), 10u);   // 10.45 → ⌊10.95⌋
  EXPECT_EQ(coverage_index(10, 0.95), 10u);   // 9.5 → ⌊10.0⌋
  EXPECT_EQ(coverage_index(10, 0.65), 7u);    // 6.5 → 7
  EXPECT_EQ(coverage_index(9, 0.6), 5u);      // 5.4 → 5
  EXPECT_EQ(minimum_sample_count(0.95), 11u);
  EXPECT_EQ(minimum_sample_count(0.99), 51u);
  EXPECT_EQ(minimum_sample_count(0.999), 501u);
  EXPECT_EQ(minimum_sample_count(0.5), 2u);
  EXPECT_EQ(minimum_sample_count(0.1), 5u);
}

TEST(Summarize, HandExamplesOfTheIntervalIndices) {
  // M = 20, p = 0.9: q = 18, r = (M − q)/2 = 1: [y(1), y(19)] = [1, 19]; shortest: widths
  // y(19) − y(1) = y(20) − y(2) = 18, tie → smallest r: [1, 19].
  MeasurandSummary s = summarize(scrambled_ramp(20), 0.9);
  EXPECT_EQ(s.count, 20u);
  EXPECT_EQ(s.probabilistically_symmetric.low, 1.0);
  EXPECT_EQ(s.probabilistically_symmetric.high, 19.0);
  EXPECT_EQ(s.shortest.low, 1.0);
  EXPECT_EQ(s.shortest.high, 19.0);
  EXPECT_EQ(s.probabilistically_symmetric.probability, 0.9);
  // M = 10, p = 0.65: q = 7, M − q = 3 odd → r = ⌊(3 + 1)/2⌋ = 2: [y(2), y(9)].
  s = summarize(scrambled_ramp(10), 0.65);
  EXPECT_EQ(s.probabilistically_symmetric.low, 2.0);
  EXPECT_EQ(s.probabilistically_symmetric.high, 9.0);
  // M = 9, p = 0.6: q = 5, r = 2: [y(2), y(7)].
  s = summarize(scrambled_ramp(9), 0.6);
  EXPECT_EQ(s.probabilistically_symmetric.low, 2.0);
  EXPECT_EQ(s.probabilistically_symmetric.high, 7.0);
  // Shortest differs from symmetric: {−100, 1, …, 9}, p = 0.8: q = 8, r = 1:
  // symmetric [y(1), y(9)] = [−100, 8]; shortest r* = 2 (width 8 < 108): [1, 9].
  std::vector<double> y = {5, 1, 9, -100, 3, 7, 2, 8, 4, 6};
  s = summarize(y, 0.8);
  EXPECT_EQ(s.probabilistically_symmetric.low, -100.0);
  EXPECT_EQ(s.probabilistically_symmetric.high, 8.0);
  EXPECT_EQ(s.shortest.low, 1.0);
  EXPECT_EQ(s.shortest.high, 9.0);
  EXPECT_EQ(s.shortest.probability, 0.8);
}

TEST(Summarize, MeanAndStandardUncertaintyByHandAndStableUnderOffset) {
  MeasurandSummary s = summarize(std::vector<double>{4, 1, 3, 2}, 0.5);
  EXPECT_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.standard_uncertainty, std::sqrt(5.0 / 3.0));
  // Offset 1e9 (ring diameters in nm would be like this): the two-pass formula loses nothing
  // (one-pass Σy² − (Σy)²/M would lose ~all digits).
  s = summarize(std::vector<double>{1e9 + 4, 1e9 + 1, 1e9 + 3, 1e9 + 2}, 0.5);
  EXPECT_EQ(s.mean, 1e9 + 2.5);
  EXPECT_DOUBLE_EQ(s.standard_uncertainty, std::sqrt(5.0 / 3.0));
  // Constant samples: u exactly 0, intervals degenerate.
  s = summarize(std::vector<double>(50, 0.125), 0.95);
  EXPECT_EQ(s.mean, 0.125);
  EXPECT_EQ(s.standard_uncertainty, 0.0);
  EXPECT_EQ(s.shortest.low, 0.125);
  EXPECT_EQ(s.shortest.high, 0.125);
}

TEST(Summarize, SampleOrderDoesNotMatter) {
  std::vector<double> y(10'001);
  RandomStream(5, 0).fill_standard_normal(y);
  const MeasurandSummary a = summarize(y, 0.95);
  std::reverse(y.begin(), y.end());
  const MeasurandSummary b = summarize(y, 0.95);
  EXPECT_NEAR(a.mean, b.mean, 1e-17);  // compensated sums: equal to an ulp of the scale
  EXPECT_NEAR(a.standard_uncertainty, b.standard_uncertainty, 4e-16);
  EXPECT_EQ(a.probabilistically_symmetric.low, b.probabilistically_symmetric.low);
  EXPECT_EQ(a.probabilistically_symmetric.high, b.probabilistically_symmetric.high);
  EXPECT_EQ(a.shortest.low, b.shortest.low);
  EXPECT_EQ(a.shortest.high, b.shortest.high);
}

TEST(Summarize, ExponentialShortestVersusSymmetricInterval) {
  // Y ~ Exp(1) (y = −ln(1 − U)), M = 10⁶, p = 0.95. Shortest interval of a decreasing density:
  // [0, −ln 0.05] = [0, 2.9957]; symmetric: [−ln 0.975, −ln 0.025] = [0.02532, 3.6889].
  // An order statistic near quantile x_P has sd √(P(1 − P)/M)/f(x_P), f(x_P) = 1 − P:
  // x_0.025: 1.6e-4; x_0.95: 4.4e-3; x_0.975: 6.2e-3. Tolerance 5 sd. The shortest interval's
  // low end is the minimum of M exponentials (mean 1/M): below 1e-4 but with prob. e^-100.
  constexpr std::size_t m = 1'000'000;
  std::vector<double> y(m);
  RandomStream rng(11, 0);
  rng.fill_uniform(y);
  for (double& v : y) v = -std::log1p(-v);
  const MeasurandSummary s = summarize(y, 0.95);
  const double rm = std::sqrt(static_cast<double>(m));
  auto sd = [rm](double p) { return std::sqrt(p * (1 - p)) / rm / (1 - p); };
  EXPECT_NEAR(s.mean, 1.0, 5.0 / rm);  // sd of the mean of Exp(1): 1/√M
  EXPECT_NEAR(s.standard_uncertainty, 1.0, 5.0 * std::sqrt(2.0) / rm);  // √((μ₄ − σ⁴)/(4σ²M)), μ₄ = 9
  EXPECT_GE(s.shortest.low, 0.0);
  EXPECT_LT(s.shortest.low, 1e-4);
  EXPECT_NEAR(s.shortest.high, -std::log(0.05), 5.0 * sd(0.95));
  EXPECT_NEAR(s.probabilistically_symmetric.low, -std::log(0.975), 5.0 * sd(0.025));
  EXPECT_NEAR(s.probabilistically_symmetric.high, -std::log(0.025), 5.0 * sd(0.975));
  // Both contain q + 1 = 950 001 order statistics; the shortest is shorter.
  EXPECT_LT(s.shortest.high - s.shortest.low,
            s.probabilistically_symmetric.high - s.probabilistically_symmetric.low - 0.6);
}

TEST(SummarizeMeasurand, PicksTheColumnOfTrialMajorSamples) {
  // Trial t: (t, 100 − t, 7).
  std::vector<double> samples;
  for (int t = 0; t < 40; ++t) {
    samples.push_back(t);
    samples.push_back(100 - t);
    samples.push_back(7);
  }
  const MeasurandSummary a = summarize_measurand(samples, 3, 0, 0.9);
  const MeasurandSummary b = summarize_measurand(samples, 3, 1, 0.9);
  EXPECT_EQ(a.mean, 19.5);
  EXPECT_EQ(b.mean, 80.5);
  EXPECT_EQ(a.count, 40u);
  // q = 36, r = 2: [y(2), y(38)] = [1, 37] and [62, 98].
  EXPECT_EQ(a.probabilistically_symmetric.low, 1.0);
  EXPECT_EQ(a.probabilistically_symmetric.high, 37.0);
  EXPECT_EQ(b.probabilistically_symmetric.low, 62.0);
  EXPECT_EQ(b.probabilistically_symmetric.high, 98.0);
  EXPECT_EQ(summarize_measurand(samples, 3, 2, 0.9).standard_uncertainty, 0.0);
}

TEST(CorrelationMatrix, HandCasesAndAKnownCorrelation) {
  // Exact linear relations: +1 and −1; a constant measurand: 0 off the diagonal.
  std::vector<double> s;
  for (int t = 0; t < 10; ++t) {
    s.push_back(t);
    s.push_back(2.0 * t + 1.0);
    s.push_back(-t);
    s.push_back(3.0);
  }
  const std::vector<double> r = correlation_matrix(s, 4);
  ASSERT_EQ(r.size(), 16u);
  EXPECT_DOUBLE_EQ(r[0 * 4 + 1], 1.0);
  EXPECT_DOUBLE_EQ(r[0 * 4 + 2], -1.0);
  EXPECT_DOUBLE_EQ(r[1 * 4 + 2], -1.0);
  EXPECT_EQ(r[0 * 4 + 3], 0.0);
  EXPECT_EQ(r[3 * 4 + 1], 0.0);
  for (int j = 0; j < 4; ++j) EXPECT_EQ(r[static_cast<std::size_t>(j * 5)], 1.0);
  for (int j = 0; j < 4; ++j) {
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(r[static_cast<std::size_t>(j * 4 + k)], r[static_cast<std::size_t>(k * 4 + j)]);
    }
  }
  // Y1 = Z1, Y2 = ρ Z1 + √(1 − ρ²) Z2 with ρ = 0.6, M = 10⁵: the sample correlation has sd
  // ≈ (1 − ρ²)/√M = 2.0e-3; tolerance 5 sd.
  constexpr std::size_t m = 100'000;
  std::vector<double> z(2 * m);
  RandomStream(3, 0).fill_standard_normal(z);
  std::vector<double> y(2 * m);
  for (std::size_t t = 0; t < m; ++t) {
    y[2 * t] = z[2 * t];
    y[2 * t + 1] = 0.6 * z[2 * t] + 0.8 * z[2 * t + 1];
  }
  const std::vector<double> c = correlation_matrix(y, 2);
  EXPECT_NEAR(c[1], 0.6, 5.0 * 0.64 / std::sqrt(static_cast<double>(m)));
  EXPECT_EQ(c[1], c[2]);
}

TEST(Summarize, BadInput) {
  const std::vector<double> ok = scrambled_ramp(20);
  expect_invalid([] { summarize(std::vector<double>{}); }, {"summarize", "empty"});
  std::vector<double> with_nan = ok;
  with_nan[13] = std::nan("");
  expect_invalid([&] { summarize(with_nan); }, {"summarize", "finite", "sample 13", "nan"});
  with_nan[13] = -INFINITY;
  expect_invalid([&] { summarize(with_nan); }, {"sample 13", "inf"});
  for (const double p : {0.0, 1.0, -0.5, 1.5, std::nan("")}) {
    expect_invalid([&] { summarize(ok, p); }, {"summarize", "coverage probability", "(0, 1)"});
  }
  expect_invalid([] { summarize(scrambled_ramp(10), 0.95); },
                 {"summarize", "too few samples", "M >= 11", "M = 10"});
  expect_invalid([] { coverage_index(10, 1.0); }, {"coverage_index", "(0, 1)"});
  expect_invalid([] { minimum_sample_count(0.0); }, {"minimum_sample_count", "(0, 1)"});
}

TEST(SummarizeMeasurand, BadInput) {
  std::vector<double> s(60, 1.0);
  expect_invalid([&] { summarize_measurand(s, 0, 0); }, {"summarize_measurand", "q must be >= 1"});
  expect_invalid([&] { summarize_measurand(s, 3, 3); }, {"summarize_measurand", "< q = 3", "got 3"});
  expect_invalid([&] { summarize_measurand(s, 7, 0); }, {"multiple of q = 7", "got 60"});
  s[3 * 5 + 2] = std::nan("");
  expect_invalid([&] { summarize_measurand(s, 3, 2); }, {"trial 5", "measurand 2", "nan"});
  expect_invalid([&] { summarize_measurand(s, 3, 0, 2.0); }, {"(0, 1)"});
}

TEST(CorrelationMatrix, BadInput) {
  std::vector<double> s(30, 1.0);
  expect_invalid([&] { correlation_matrix(s, 0); }, {"correlation_matrix", "q must be >= 1"});
  expect_invalid([&] { correlation_matrix(s, 4); }, {"correlation_matrix", "multiple of q = 4"});
  expect_invalid([&] { correlation_matrix(std::vector<double>{1, 2}, 2); }, {"at least 2 trials"});
  s[2 * 3 + 1] = INFINITY;
  expect_invalid([&] { correlation_matrix(s, 3); }, {"trial 2", "measurand 1", "inf"});
}

}  // namespace
