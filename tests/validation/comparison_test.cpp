// E_n and zeta scores (vcmm/validation/comparison.h): hand-computed values, the sign
// convention, the relation E_n = zeta / k, every precondition, and the distribution of E_n
// under honest uncertainties (the campaign's yardstick: RMS ≈ 1/k, |E_n| > 1 in 4.55 %).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include "vcmm/errormodel/errors.h"
#include "vcmm/geometry/point.h"
#include "vcmm/validation/comparison.h"

namespace {

using namespace vcmm::validation;
using vcmm::geometry::InvalidInput;

template <class F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "(no exception)";
}

TEST(Comparison, HandComputedEnAndZeta) {
  // u_ref = 0.3, u_meas = 0.4: sqrt(0.09 + 0.16) = 0.5; difference 10 − 9 = 1.
  EXPECT_NEAR(zeta_score(10.0, 0.3, 9.0, 0.4), 2.0, 1e-15);
  EXPECT_NEAR(en_score(10.0, 0.3, 9.0, 0.4), 1.0, 1e-15);     // k = 2: 1 / (2 · 0.5)
  EXPECT_NEAR(en_score(10.0, 0.3, 9.0, 0.4, 1.0), 2.0, 1e-15);
  EXPECT_NEAR(en_score(10.0, 0.3, 9.0, 0.4, 2.5), 0.8, 1e-15);
  // Roundness in mm, as the campaign uses it: ref 0.205 µm ± 0.010, measured 0.180 ± 0.0125.
  // u = sqrt(0.010² + 0.0125²) µm = 0.016008 µm; E_n = 0.025 / (2 · 0.016008) = 0.780868.
  EXPECT_NEAR(en_score(0.205e-3, 0.010e-3, 0.180e-3, 0.0125e-3), 0.7808688094430304, 1e-12);
}

TEST(Comparison, SignIsReferenceMinusMeasured) {
  EXPECT_GT(en_score(1.0, 0.1, 0.9, 0.1), 0.0);   // CMM reads below the reference
  EXPECT_LT(en_score(1.0, 0.1, 1.1, 0.1), 0.0);   // CMM reads above
  EXPECT_EQ(en_score(1.0, 0.1, 0.9, 0.1), -en_score(0.9, 0.1, 1.0, 0.1));
  EXPECT_EQ(en_score(3.0, 0.2, 3.0, 0.1), 0.0);
}

TEST(Comparison, OneUncertaintyMayBeZero) {
  EXPECT_NEAR(en_score(1.0, 0.0, 0.0, 0.5), 1.0, 1e-15);
  EXPECT_NEAR(zeta_score(1.0, 0.25, 0.0, 0.0), 4.0, 1e-15);
}

TEST(Comparison, ExpandedFormAndTheInflatedTreatment) {
  // U given directly: 1 / sqrt(0.6² + 0.8²) = 1.
  EXPECT_NEAR(en_score_expanded(10.0, 0.6, 9.0, 0.8), 1.0, 1e-15);
  // With U = k·u it equals en_score.
  EXPECT_NEAR(en_score_expanded(10.0, 2 * 0.3, 9.0, 2 * 0.4), en_score(10.0, 0.3, 9.0, 0.4),
              1e-15);
  // Treatment (c): U_meas = k·u + |b| — ref 5 ± 0.1, estimate 4.5 ± 0.2, bias 0.1, k = 2:
  // 0.5 / sqrt(0.2² + 0.5²) = 0.5 / 0.538516… = 0.928476690885259.
  EXPECT_NEAR(en_score_expanded(5.0, 2 * 0.1, 4.5, 2 * 0.2 + 0.1), 0.928476690885259, 1e-14);
}

TEST(Comparison, CompareGivesBothScores) {
  const Comparison c = compare(10.0, 0.3, 9.0, 0.4, 2.0);
  EXPECT_DOUBLE_EQ(c.difference, 1.0);
  EXPECT_NEAR(c.u_difference, 0.5, 1e-16);
  EXPECT_EQ(c.k, 2.0);
  EXPECT_NEAR(c.zeta, 2.0, 1e-15);
  EXPECT_NEAR(c.en, 1.0, 1e-15);
  EXPECT_EQ(c.en, en_score(10.0, 0.3, 9.0, 0.4, 2.0));
  EXPECT_EQ(c.zeta, zeta_score(10.0, 0.3, 9.0, 0.4));
}

TEST(Comparison, HugeAndTinyUncertaintiesNeitherOverflowNorUnderflow) {
  // u² would overflow (1e200² = inf) or underflow (1e-200² = 0) without hypot.
  EXPECT_NEAR(zeta_score(3e200, 3e200, 0.0, 4e200), 0.6, 1e-15);
  EXPECT_NEAR(zeta_score(3e-200, 3e-200, 0.0, 4e-200), 0.6, 1e-15);
}

TEST(Comparison, EveryPreconditionIsCheckedWithAMessage) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(message_of([] { en_score(1, 0, 2, 0); }),
            "en_score: u_ref and u_meas are both 0; the score is undefined");
  EXPECT_EQ(message_of([] { zeta_score(1, 0, 2, 0); }),
            "zeta_score: u_ref and u_meas are both 0; the score is undefined");
  EXPECT_EQ(message_of([] { en_score_expanded(1, 0, 2, 0); }),
            "en_score_expanded: expanded_u_ref and expanded_u_meas are both 0; the score is "
            "undefined");
  EXPECT_EQ(message_of([] { en_score(1, -0.1, 2, 0.1); }),
            "en_score: u_ref must be >= 0; got -0.10000000000000001");
  EXPECT_EQ(message_of([] { zeta_score(1, 0.1, 2, -1); }),
            "zeta_score: u_meas must be >= 0; got -1");
  EXPECT_EQ(message_of([&] { en_score(nan, 0.1, 2, 0.1); }),
            "en_score: x_ref must be finite; got nan");
  EXPECT_EQ(message_of([&] { en_score(1, 0.1, inf, 0.1); }),
            "en_score: x_meas must be finite; got inf");
  EXPECT_EQ(message_of([&] { en_score(1, inf, 2, 0.1); }),
            "en_score: u_ref must be finite; got inf");
  EXPECT_EQ(message_of([&] { compare(1, 0.1, 2, nan); }),
            "compare: u_meas must be finite; got nan");
  EXPECT_EQ(message_of([] { en_score(1, 0.1, 2, 0.1, 0.0); }),
            "en_score: coverage factor k must be > 0; got 0");
  EXPECT_EQ(message_of([] { compare(1, 0.1, 2, 0.1, -2.0); }),
            "compare: coverage factor k must be > 0; got -2");
  EXPECT_EQ(message_of([&] { en_score(1, 0.1, 2, 0.1, nan); }),
            "en_score: k must be finite; got nan");
  EXPECT_EQ(message_of([] { zeta_score(1.7e308, 1e-300, -1.7e308, 1e-300); }),
            "zeta_score: the score overflows (inf); inputs too large for double");
  // The exception is the library's one "bad input" type.
  EXPECT_THROW(en_score(1, 0, 2, 0), vcmm::errormodel::InvalidInput);
}

// With honest standard uncertainties, x_ref ~ N(μ, u_r²) and x_meas ~ N(μ, u_m²) independent,
// zeta ~ N(0, 1) and E_n = zeta/2 ~ N(0, 1/4): E[E_n²] = 0.25 and P(|E_n| > 1) = P(|z| > 2) =
// erfc(√2) = 0.0455. Tolerances for M = 20 000 draws (fixed seed, own Box–Muller so the numbers
// do not depend on the standard library): the share has standard error sqrt(p(1−p)/M) =
// 0.00147, the mean of E_n² has standard error 0.25·sqrt(2/M) = 0.0025, the mean of E_n has
// 0.5/sqrt(M) = 0.0035; each is tested at 5 standard errors.
TEST(Comparison, EnUnderHonestUncertaintiesHasRms1OverK) {
  constexpr int kDraws = 20000;
  const std::uint64_t seed = 20240517;
  std::mt19937_64 rng(seed);
  const auto uniform = [&] { return (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53; };
  const auto normal = [&] {
    return std::sqrt(-2.0 * std::log(uniform())) * std::cos(2 * std::numbers::pi * uniform());
  };
  const double mu = 171.0, u_ref = 0.05e-3, u_meas = 0.12e-3;
  double sum = 0.0, sum_sq = 0.0;
  int beyond = 0;
  for (int i = 0; i < kDraws; ++i) {
    const double x_ref = mu + u_ref * normal();
    const double x_meas = mu + u_meas * normal();
    const double en = en_score(x_ref, u_ref, x_meas, u_meas);
    sum += en;
    sum_sq += en * en;
    beyond += std::abs(en) > 1.0;
  }
  const double share = static_cast<double>(beyond) / kDraws;
  SCOPED_TRACE("seed " + std::to_string(seed));
  EXPECT_NEAR(share, std::erfc(std::numbers::sqrt2), 5 * 0.00147);
  EXPECT_NEAR(sum_sq / kDraws, 0.25, 5 * 0.0025);
  EXPECT_NEAR(sum / kDraws, 0.0, 5 * 0.0035);
}

}  // namespace
