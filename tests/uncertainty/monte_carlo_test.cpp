// run_monte_carlo / run_adaptive_monte_carlo: known answers (linear and Rayleigh models),
// determinism over thread counts, cancellation, error reporting, progress, the factory
// overloads, the JCGM 101 7.9.4 stopping rule recomputed from the stored samples, and one
// bad-input test per precondition. Tolerances are derived from M where used.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "vcmm/uncertainty/monte_carlo.h"
#include "varied_experiment.h"

namespace {

using namespace vcmm::uncertainty;

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

MonteCarloOptions options_with(std::uint64_t trials, unsigned threads, std::uint64_t seed = 1) {
  MonteCarloOptions o;
  o.trials = trials;
  o.threads = threads;
  o.seed = seed;
  return o;
}

/// sd of the sample P-quantile: √(P(1 − P)/M) / f(x_P).
double quantile_sd(double p, double density, std::uint64_t m) {
  return std::sqrt(p * (1.0 - p) / static_cast<double>(m)) / density;
}

using vcmm::test::kVariedExperiment;

TEST(MonteCarlo, LinearModelMeanUncertaintyIntervalAndCorrelation) {
  // Y = a X1 + b X2, X1 ~ N(1, 0.1²), X2 ~ N(0.5, 0.2²), a = 2, b = −3: E Y = 0.5,
  // u = √(a²σ1² + b²σ2²) = √0.4. Second measurand X1: corr(Y, X1) = aσ1/u = 0.2/√0.4.
  constexpr std::uint64_t m = 200'000;
  const Experiment linear = [](RandomStream& rng, std::span<double> y) {
    double z[2];
    rng.fill_standard_normal(z);
    const double x1 = 1.0 + 0.1 * z[0], x2 = 0.5 + 0.2 * z[1];
    y[0] = 2.0 * x1 - 3.0 * x2;
    y[1] = x1;
  };
  const MonteCarloResult r = run_monte_carlo(linear, 2, options_with(m, 2));
  ASSERT_EQ(r.status, RunStatus::completed);
  ASSERT_EQ(r.trials, m);
  ASSERT_EQ(r.samples.size(), 2 * m);
  ASSERT_EQ(r.summaries.size(), 2u);
  const double u = std::sqrt(0.4), rm = std::sqrt(static_cast<double>(m));
  const MeasurandSummary& s = r.summaries[0];
  // Standard errors: mean u/√M; u: u/√(2(M − 1)); tolerance 5 standard errors.
  EXPECT_NEAR(s.mean, 0.5, 5.0 * u / rm);
  EXPECT_NEAR(s.standard_uncertainty, u, 5.0 * u / std::sqrt(2.0 * (m - 1)));
  // Interval ends: mean ± 1.959964 u; the order statistic at P = 0.025/0.975 has sd
  // √(P(1 − P)/M)/f(x_P), f(x_P) = φ(1.959964)/u.
  const double k = 1.959963984540054, f = std::exp(-0.5 * k * k) / std::sqrt(2 * std::numbers::pi) / u;
  const double tol = 5.0 * quantile_sd(0.025, f, m);
  EXPECT_NEAR(s.probabilistically_symmetric.low, 0.5 - k * u, tol);
  EXPECT_NEAR(s.probabilistically_symmetric.high, 0.5 + k * u, tol);
  EXPECT_NEAR(s.shortest.low, 0.5 - k * u, 4.0 * tol);  // argmin over a flat width: looser
  EXPECT_NEAR(s.shortest.high, 0.5 + k * u, 4.0 * tol);
  // Correlation: sd ≈ (1 − ρ²)/√M.
  const double rho = 0.2 / u;
  ASSERT_EQ(r.correlation.size(), 4u);
  EXPECT_NEAR(r.correlation[1], rho, 5.0 * (1 - rho * rho) / rm);
  EXPECT_EQ(r.correlation[0], 1.0);
  EXPECT_EQ(r.threads_used, 2u);
  EXPECT_EQ(r.measurand_count, 2u);
  EXPECT_GT(r.wall_seconds, 0.0);
}

TEST(MonteCarlo, RayleighMagnitudeOfA2dGaussian) {
  // Y = σ √(Z1² + Z2²): Rayleigh(σ). Mean σ√(π/2), sd σ√((4 − π)/2), quantile
  // x_P = σ√(−2 ln(1 − P)), density f(x) = x/σ² · exp(−x²/(2σ²)).
  constexpr double sigma = 2.0;
  constexpr std::uint64_t m = 200'000;
  const Experiment rayleigh = [](RandomStream& rng, std::span<double> y) {
    const double a = sigma * rng.standard_normal(), b = sigma * rng.standard_normal();
    y[0] = std::hypot(a, b);
  };
  const MonteCarloResult r = run_monte_carlo(rayleigh, 1, options_with(m, 2, 77));
  const MeasurandSummary& s = r.summaries.at(0);
  auto quantile = [](double p) { return sigma * std::sqrt(-2.0 * std::log1p(-p)); };
  auto density = [](double x) { return x / (sigma * sigma) * std::exp(-x * x / (2 * sigma * sigma)); };
  const double sd = sigma * std::sqrt((4.0 - std::numbers::pi) / 2.0);
  const double rm = std::sqrt(static_cast<double>(m));
  EXPECT_NEAR(s.mean, sigma * std::sqrt(std::numbers::pi / 2.0), 5.0 * sd / rm);
  // sd of the sample sd: √((μ₄/σ⁴ − 1)/(4M))·σ_Y with kurtosis μ₄/σ⁴ = 3.245 for Rayleigh.
  EXPECT_NEAR(s.standard_uncertainty, sd, 5.0 * sd * std::sqrt((3.245 - 1.0) / (4.0 * m)));
  for (const double p : {0.025, 0.975}) {
    const double x = quantile(p);
    const double got = p < 0.5 ? s.probabilistically_symmetric.low : s.probabilistically_symmetric.high;
    EXPECT_NEAR(got, x, 5.0 * quantile_sd(p, density(x), m)) << "P = " << p;
  }
  // Shortest 95 % interval: [x_a, x_{a+0.95}] with a minimising the width (ternary search on
  // the unimodal width). Its width is estimated to about an order statistic's sd; its ends
  // less well (the width is flat at the optimum), so they get a 4× looser tolerance.
  double lo = 0.0, hi = 0.05;
  for (int i = 0; i < 200; ++i) {
    const double a1 = lo + (hi - lo) / 3, a2 = hi - (hi - lo) / 3;
    if (quantile(a1 + 0.95) - quantile(a1) < quantile(a2 + 0.95) - quantile(a2)) {
      hi = a2;
    } else {
      lo = a1;
    }
  }
  const double a = 0.5 * (lo + hi);
  const double x_lo = quantile(a), x_hi = quantile(a + 0.95);
  const double sd_hi = quantile_sd(a + 0.95, density(x_hi), m);
  EXPECT_NEAR(s.shortest.high - s.shortest.low, x_hi - x_lo, 5.0 * std::sqrt(2.0) * sd_hi);
  EXPECT_NEAR(s.shortest.low, x_lo, 4.0 * 5.0 * quantile_sd(a, density(x_lo), m));
  EXPECT_NEAR(s.shortest.high, x_hi, 4.0 * 5.0 * sd_hi);
  EXPECT_LT(s.shortest.high - s.shortest.low,
            s.probabilistically_symmetric.high - s.probabilistically_symmetric.low);
}

TEST(MonteCarlo, BitIdenticalForAnyThreadCountAndSharedOrFactory) {
  constexpr std::uint64_t m = 4'000;
  const MonteCarloResult ref = run_monte_carlo(kVariedExperiment, 3, options_with(m, 1, 9));
  for (const unsigned threads : {2u, 5u, 7u}) {
    const MonteCarloResult r = run_monte_carlo(kVariedExperiment, 3, options_with(m, threads, 9));
    EXPECT_EQ(r.threads_used, threads);
    ASSERT_EQ(r.samples, ref.samples) << threads << " threads";
    for (std::size_t j = 0; j < 3; ++j) {
      EXPECT_EQ(r.summaries[j].mean, ref.summaries[j].mean);
      EXPECT_EQ(r.summaries[j].standard_uncertainty, ref.summaries[j].standard_uncertainty);
      EXPECT_EQ(r.summaries[j].shortest.low, ref.summaries[j].shortest.low);
      EXPECT_EQ(r.summaries[j].probabilistically_symmetric.high,
                ref.summaries[j].probabilistically_symmetric.high);
    }
    EXPECT_EQ(r.correlation, ref.correlation);
  }
  const ExperimentFactory factory = [] { return kVariedExperiment; };
  EXPECT_EQ(run_monte_carlo(factory, 3, options_with(m, 3, 9)).samples, ref.samples);
  // Trial t is RandomStream(seed, t): recompute trial 1234 by hand.
  RandomStream rng(9, 1234);
  double y[3];
  kVariedExperiment(rng, y);
  EXPECT_EQ(ref.samples[1234 * 3 + 0], y[0]);
  EXPECT_EQ(ref.samples[1234 * 3 + 1], y[1]);
  // A different seed gives different samples.
  const MonteCarloResult other = run_monte_carlo(kVariedExperiment, 3, options_with(m, 2, 10));
  EXPECT_NE(other.samples, ref.samples);
}

TEST(MonteCarlo, CancellationReturnsACompletedPrefix) {
  constexpr std::uint64_t m = 5'000;
  const MonteCarloResult full = run_monte_carlo(kVariedExperiment, 3, options_with(m, 1));
  for (const unsigned threads : {1u, 2u, 5u}) {
    std::atomic<bool> cancel{false};
    const Experiment cancelling = [&cancel](RandomStream& rng, std::span<double> y) {
      kVariedExperiment(rng, y);
      if (rng.stream() == 1234) cancel.store(true);
    };
    MonteCarloOptions o = options_with(m, threads);
    o.cancel = &cancel;
    const MonteCarloResult r = run_monte_carlo(cancelling, 3, o);
    EXPECT_EQ(r.status, RunStatus::cancelled) << threads;
    EXPECT_LT(r.trials, m);
    if (threads == 1) {
      EXPECT_EQ(r.trials, 1235u);  // trial 1234 completes, trial 1235 sees the flag
    }
    ASSERT_EQ(r.samples.size(), r.trials * 3);
    EXPECT_TRUE(std::equal(r.samples.begin(), r.samples.end(), full.samples.begin()));
    if (r.trials >= minimum_sample_count(0.95)) {
      ASSERT_EQ(r.summaries.size(), 3u);
      EXPECT_EQ(r.summaries[0].count, r.trials);
    }
    EXPECT_NE(r.message.find("cancelled"), std::string::npos);
  }
  // Cancelled before the first trial: no trials, no summaries, and the message says why.
  std::atomic<bool> already{true};
  MonteCarloOptions o = options_with(m, 2);
  o.cancel = &already;
  const MonteCarloResult r = run_monte_carlo(kVariedExperiment, 3, o);
  EXPECT_EQ(r.status, RunStatus::cancelled);
  EXPECT_EQ(r.trials, 0u);
  EXPECT_TRUE(r.samples.empty());
  EXPECT_TRUE(r.summaries.empty());
  EXPECT_TRUE(r.correlation.empty());
  EXPECT_NE(r.message.find("no summaries"), std::string::npos) << r.message;
}

TEST(MonteCarlo, ExperimentExceptionNamesTheLowestFailingTrialWithTheOriginalNested) {
  const Experiment failing = [](RandomStream& rng, std::span<double> y) {
    if (rng.stream() == 900 || rng.stream() == 300) {
      throw std::runtime_error("boom " + std::to_string(rng.stream()));
    }
    y[0] = rng.uniform();
  };
  for (const unsigned threads : {1u, 2u, 5u}) {
    try {
      run_monte_carlo(failing, 1, options_with(2'000, threads, 4));
      ADD_FAILURE() << "no exception";
    } catch (const ExperimentError& e) {
      EXPECT_EQ(e.trial(), 300u) << threads;
      EXPECT_EQ(e.measurand(), ExperimentError::no_measurand);
      const std::string what = e.what();
      EXPECT_NE(what.find("run_monte_carlo: trial 300 (seed 4)"), std::string::npos) << what;
      EXPECT_NE(what.find("boom 300"), std::string::npos) << what;
      try {
        std::rethrow_if_nested(e);
        ADD_FAILURE() << "nothing nested";
      } catch (const std::runtime_error& inner) {
        EXPECT_EQ(std::string(inner.what()), "boom 300");
      }
    }
  }
  const Experiment odd = [](RandomStream& rng, std::span<double> y) {
    if (rng.stream() == 17) throw 42;
    y[0] = 1.0;
  };
  try {
    run_monte_carlo(odd, 1, options_with(100, 2));
    ADD_FAILURE() << "no exception";
  } catch (const ExperimentError& e) {
    EXPECT_NE(std::string(e.what()).find("non-standard"), std::string::npos);
    EXPECT_EQ(e.trial(), 17u);
  }
}

TEST(MonteCarlo, NonFiniteOrUnwrittenMeasurandIsAnErrorNamingTrialAndMeasurand) {
  const Experiment nan_at_77 = [](RandomStream& rng, std::span<double> y) {
    y[0] = 1.0;
    y[1] = rng.stream() == 77 ? std::nan("") : 2.0;
    y[2] = 3.0;
  };
  const Experiment forgets_at_5 = [](RandomStream& rng, std::span<double> y) {
    y[0] = 1.0;
    y[1] = rng.stream() == 5 ? std::numeric_limits<double>::infinity() : 2.0;
    if (rng.stream() != 5) y[2] = 3.0;
  };
  for (const unsigned threads : {1u, 3u}) {
    try {
      run_monte_carlo(nan_at_77, 3, options_with(500, threads));
      ADD_FAILURE() << "no exception";
    } catch (const ExperimentError& e) {
      EXPECT_EQ(e.trial(), 77u);
      EXPECT_EQ(e.measurand(), 1u);
      EXPECT_NE(std::string(e.what()).find("trial 77"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("measurand 1 is nan"), std::string::npos) << e.what();
    }
    try {
      run_monte_carlo(forgets_at_5, 3, options_with(500, threads));
      ADD_FAILURE() << "no exception";
    } catch (const ExperimentError& e) {
      EXPECT_EQ(e.trial(), 5u);
      EXPECT_EQ(e.measurand(), 1u);  // the first non-finite one: +inf before the unwritten 2
      EXPECT_NE(std::string(e.what()).find("measurand 1 is inf"), std::string::npos) << e.what();
    }
  }
  const Experiment unwritten = [](RandomStream&, std::span<double> y) { y[0] = 1.0; };
  try {
    run_monte_carlo(unwritten, 2, options_with(100, 1));
    ADD_FAILURE() << "no exception";
  } catch (const ExperimentError& e) {
    EXPECT_EQ(e.trial(), 0u);
    EXPECT_EQ(e.measurand(), 1u);
  }
}

TEST(MonteCarlo, ProgressIsCalledFromTheCallersThreadAndEndsWithTheTotal) {
  const std::thread::id caller = std::this_thread::get_id();
  std::vector<std::pair<std::uint64_t, std::uint64_t>> calls;
  bool all_from_caller = true;
  // ~0.3 s in total (2 000 trials × 150 µs on 2 threads) so periodic calls happen too.
  const Experiment slow = [](RandomStream& rng, std::span<double> y) {
    std::this_thread::sleep_for(std::chrono::microseconds(150));
    y[0] = rng.uniform();
  };
  MonteCarloOptions o = options_with(2'000, 2);
  o.progress = [&](std::uint64_t done, std::uint64_t planned) {
    calls.emplace_back(done, planned);
    all_from_caller = all_from_caller && std::this_thread::get_id() == caller;
  };
  const MonteCarloResult r = run_monte_carlo(slow, 1, o);
  EXPECT_EQ(r.status, RunStatus::completed);
  ASSERT_FALSE(calls.empty());
  EXPECT_TRUE(all_from_caller);
  EXPECT_EQ(calls.back(), std::make_pair(std::uint64_t{2'000}, std::uint64_t{2'000}));
  for (std::size_t i = 1; i < calls.size(); ++i) EXPECT_LE(calls[i - 1].first, calls[i].first);
  EXPECT_EQ(r.threads_used, 2u);  // the monitor is not one of the workers

  // A throwing progress callback stops the run; its exception propagates.
  MonteCarloOptions t = options_with(2'000, 2);
  t.progress = [](std::uint64_t, std::uint64_t) { throw std::logic_error("stop"); };
  EXPECT_THROW(run_monte_carlo(slow, 1, t), std::logic_error);
}

TEST(MonteCarlo, FactoryMakesOneExperimentPerWorkerUsedByOneThreadEach) {
  std::mutex mutex;
  int made = 0;
  std::map<int, std::set<std::thread::id>> threads_of;  // experiment id → threads calling it
  const ExperimentFactory factory = [&]() -> Experiment {
    std::lock_guard<std::mutex> lock(mutex);
    const int id = made++;
    return [&, id](RandomStream& rng, std::span<double> y) {
      {
        std::lock_guard<std::mutex> l(mutex);
        threads_of[id].insert(std::this_thread::get_id());
      }
      y[0] = rng.uniform();
    };
  };
  const MonteCarloResult r = run_monte_carlo(factory, 1, options_with(3'000, 3));
  EXPECT_EQ(made, 3);
  EXPECT_EQ(r.threads_used, 3u);
  for (const auto& [id, ids] : threads_of) EXPECT_EQ(ids.size(), 1u) << "experiment " << id;

  expect_invalid([] { run_monte_carlo(ExperimentFactory{}, 1, options_with(100, 1)); },
                 {"run_monte_carlo", "factory must not be empty"});
  const ExperimentFactory empty_maker = [] { return Experiment{}; };
  expect_invalid([&] { run_monte_carlo(empty_maker, 1, options_with(100, 2)); },
                 {"returned an empty experiment"});
}

TEST(MonteCarlo, BadInput) {
  const Experiment e = [](RandomStream& rng, std::span<double> y) { y[0] = rng.uniform(); };
  expect_invalid([&] { run_monte_carlo(e, 0, options_with(100, 1)); },
                 {"run_monte_carlo", "measurand_count must be >= 1"});
  for (const double p : {0.0, 1.0, 1.5, std::nan("")}) {
    MonteCarloOptions o = options_with(100, 1);
    o.coverage_probability = p;
    expect_invalid([&] { run_monte_carlo(e, 1, o); }, {"run_monte_carlo", "coverage_probability", "(0, 1)"});
  }
  expect_invalid([&] { run_monte_carlo(e, 1, options_with(0, 1)); },
                 {"run_monte_carlo", "trials must be >= 11", "got 0"});
  expect_invalid([&] { run_monte_carlo(e, 1, options_with(10, 1)); }, {"trials must be >= 11", "got 10"});
  expect_invalid([&] { run_monte_carlo(e, 1, options_with(100, 5000)); }, {"threads must be <= 1024"});
  expect_invalid([&] { run_monte_carlo(Experiment{}, 1, options_with(100, 1)); },
                 {"run_monte_carlo", "experiment must not be empty"});
  expect_invalid([&] { run_monte_carlo(e, 1u << 20, options_with(~0ULL >> 2, 1)); }, {"overflows"});
}

// ---- adaptive --------------------------------------------------------------------------------

/// Recomputes the 7.9.4 stopping quantity for the first h blocks of the stored samples.
double recomputed_stability(const MonteCarloResult& r, std::size_t j, std::uint64_t h, double p) {
  const std::uint64_t b = r.block_size;
  const std::size_t q = r.measurand_count;
  std::vector<double> values[4];
  for (std::uint64_t k = 0; k < h; ++k) {
    std::vector<double> block(b);
    for (std::uint64_t t = 0; t < b; ++t) block[t] = r.samples[(k * b + t) * q + j];
    const MeasurandSummary s = summarize(block, p);
    values[0].push_back(s.mean);
    values[1].push_back(s.standard_uncertainty);
    values[2].push_back(s.probabilistically_symmetric.low);
    values[3].push_back(s.probabilistically_symmetric.high);
  }
  double worst = 0.0;
  for (const auto& v : values) {
    double mean = 0.0;
    for (const double x : v) mean += x;
    mean /= static_cast<double>(h);
    double ss = 0.0;
    for (const double x : v) ss += (x - mean) * (x - mean);
    const double hd = static_cast<double>(h);
    worst = std::max(worst, std::sqrt(ss / (hd * (hd - 1.0))));
  }
  return 2.0 * worst;
}

// Two measurands on different scales: N(0, 1) and 10 + 0.05·N(0, 1).
const Experiment kTwoScales = [](RandomStream& rng, std::span<double> y) {
  double z[2];
  rng.fill_standard_normal(z);
  y[0] = z[0];
  y[1] = 10.0 + 0.05 * z[1];
};

TEST(AdaptiveMonteCarlo, StopsExactlyWhenTwiceTheBlockSdFallsBelowDelta) {
  AdaptiveOptions a;
  a.numerical_tolerance = 0.03;  // ~ 2·1.3/√(1000 h) for the interval ends → h ≈ 8
  a.block_size = 1'000;
  a.max_trials = 200'000;
  const MonteCarloResult r = run_adaptive_monte_carlo(kTwoScales, 2, a, options_with(0, 2, 21));
  ASSERT_EQ(r.status, RunStatus::converged) << r.message;
  EXPECT_EQ(r.block_size, 1'000u);
  EXPECT_GT(r.blocks, 2u);  // so that the recomputation below checks some "not yet" blocks
  EXPECT_EQ(r.trials, r.blocks * 1'000);
  EXPECT_EQ(r.samples.size(), r.trials * 2);
  ASSERT_EQ(r.summaries.size(), 2u);
  EXPECT_EQ(r.summaries[0].count, r.trials);  // JCGM 101 7.9.4: all trials pooled
  for (std::uint64_t h = 2; h <= r.blocks; ++h) {
    const bool stop = recomputed_stability(r, 0, h, 0.95) <= 0.03 &&
                      recomputed_stability(r, 1, h, 0.95) <= 0.03;
    EXPECT_EQ(stop, h == r.blocks) << "h = " << h;
  }
  EXPECT_NEAR(r.stability[0], recomputed_stability(r, 0, r.blocks, 0.95), 1e-12);
  EXPECT_EQ(r.numerical_tolerance, std::vector<double>({0.03, 0.03}));
  // Same result for another thread count.
  const MonteCarloResult r1 = run_adaptive_monte_carlo(kTwoScales, 2, a, options_with(0, 1, 21));
  EXPECT_EQ(r1.samples, r.samples);
  EXPECT_EQ(r1.blocks, r.blocks);
}

TEST(AdaptiveMonteCarlo, NeverStopsBeforeTwoBlocks) {
  AdaptiveOptions a;
  a.numerical_tolerance = 1e9;
  a.block_size = 500;
  const MonteCarloResult r = run_adaptive_monte_carlo(kTwoScales, 2, a, options_with(0, 2));
  EXPECT_EQ(r.status, RunStatus::converged);
  EXPECT_EQ(r.blocks, 2u);
  EXPECT_EQ(r.trials, 1'000u);
}

TEST(AdaptiveMonteCarlo, NotConvergedWhenMaxTrialsIsReached) {
  AdaptiveOptions a;
  // Out of reach within 5 blocks (2s ≈ 0.18 after 3 blocks, ≈ 0.14 after 5) but not hopeless:
  // the projection after 3 blocks, 3·(0.18/0.1)²·400 ≈ 4 000 trials, is below 4 × max_trials.
  a.numerical_tolerance = 0.1;
  a.block_size = 400;
  a.max_trials = 5 * 400 + 17;  // room for 5 whole blocks only
  const MonteCarloResult r = run_adaptive_monte_carlo(kTwoScales, 2, a, options_with(0, 2));
  EXPECT_EQ(r.status, RunStatus::not_converged);
  EXPECT_EQ(r.blocks, 5u);
  EXPECT_EQ(r.trials, 2'000u);
  EXPECT_EQ(r.summaries.size(), 2u);
  EXPECT_NE(r.message.find("not converged within max_trials = 2017"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("measurand 0"), std::string::npos) << r.message;
  EXPECT_EQ(to_string(r.status), "not_converged");
}

TEST(AdaptiveMonteCarlo, SignificantDigitsToleranceFollowsTheStandardUncertainty) {
  AdaptiveOptions a;
  a.significant_digits = 2;
  a.block_size = 2'000;
  a.max_trials = 1'000'000;
  const MonteCarloResult r = run_adaptive_monte_carlo(kTwoScales, 2, a, options_with(0, 2, 8));
  ASSERT_EQ(r.status, RunStatus::converged) << r.message;
  // u ≈ 1.0 and 0.050 to 2 digits → δ = 0.05 and 0.0005. The interval ends of a block of
  // 2 000 have sd ≈ 0.06 u, so measurand 1 needs h ≈ (2·0.06·0.05/0.0005)² ≈ 144 blocks.
  EXPECT_GT(r.blocks, 50u);
  EXPECT_DOUBLE_EQ(r.numerical_tolerance[0],
                   numerical_tolerance_from_digits(r.summaries[0].standard_uncertainty, 2));
  EXPECT_DOUBLE_EQ(r.numerical_tolerance[1],
                   numerical_tolerance_from_digits(r.summaries[1].standard_uncertainty, 2));
  EXPECT_LE(r.stability[0], r.numerical_tolerance[0]);
  EXPECT_LE(r.stability[1], r.numerical_tolerance[1]);
}

TEST(AdaptiveMonteCarlo, CancelledMidBlockKeepsThePrefix) {
  std::atomic<bool> cancel{false};
  const Experiment cancelling = [&cancel](RandomStream& rng, std::span<double> y) {
    kTwoScales(rng, y);
    if (rng.stream() == 2'500) cancel.store(true);
  };
  AdaptiveOptions a;
  a.numerical_tolerance = 1e-9;
  a.block_size = 1'000;
  MonteCarloOptions o = options_with(0, 1);
  o.cancel = &cancel;
  const MonteCarloResult r = run_adaptive_monte_carlo(cancelling, 2, a, o);
  EXPECT_EQ(r.status, RunStatus::cancelled);
  EXPECT_EQ(r.trials, 2'501u);
  EXPECT_EQ(r.blocks, 2u);
  EXPECT_EQ(r.summaries.at(0).count, 2'501u);
}

TEST(AdaptiveMonteCarlo, ToleranceFromDigitsAndDefaultBlockSize) {
  // JCGM 101 7.9.2: u written to n_dig digits as c·10^l, δ = ½·10^l.
  EXPECT_DOUBLE_EQ(numerical_tolerance_from_digits(0.0234, 2), 0.0005);   // 23·10⁻³
  EXPECT_DOUBLE_EQ(numerical_tolerance_from_digits(0.01, 2), 0.0005);     // 10·10⁻³
  EXPECT_DOUBLE_EQ(numerical_tolerance_from_digits(0.0999, 2), 0.005);    // 0.10 = 10·10⁻²
  EXPECT_DOUBLE_EQ(numerical_tolerance_from_digits(1234.5, 1), 500.0);    // 1·10³
  EXPECT_DOUBLE_EQ(numerical_tolerance_from_digits(0.00016, 1), 0.00005); // 2·10⁻⁴
  EXPECT_DOUBLE_EQ(numerical_tolerance_from_digits(1.0, 1), 0.5);
  EXPECT_EQ(numerical_tolerance_from_digits(0.0, 2), 0.0);
  EXPECT_EQ(default_block_size(0.95), 10'000u);
  EXPECT_EQ(default_block_size(0.99), 10'000u);
  EXPECT_EQ(default_block_size(0.999), 100'000u);
  expect_invalid([] { numerical_tolerance_from_digits(-1.0, 2); }, {"numerical_tolerance_from_digits", ">= 0"});
  expect_invalid([] { numerical_tolerance_from_digits(1.0, 0); }, {"1..15"});
  expect_invalid([] { default_block_size(1.0); }, {"default_block_size", "(0, 1)"});
}

TEST(AdaptiveMonteCarlo, BadInput) {
  AdaptiveOptions a;
  a.block_size = 100;
  const MonteCarloOptions o = options_with(0, 1);
  expect_invalid([&] { run_adaptive_monte_carlo(kTwoScales, 2, a, o); },
                 {"run_adaptive_monte_carlo", "numerical_tolerance > 0 or significant_digits"});
  a.numerical_tolerance = -1.0;
  expect_invalid([&] { run_adaptive_monte_carlo(kTwoScales, 2, a, o); }, {"finite and >= 0"});
  a.numerical_tolerance = std::nan("");
  expect_invalid([&] { run_adaptive_monte_carlo(kTwoScales, 2, a, o); }, {"finite and >= 0", "nan"});
  a.numerical_tolerance = 0.1;
  a.block_size = 10;
  expect_invalid([&] { run_adaptive_monte_carlo(kTwoScales, 2, a, o); }, {"block_size must be >= 11"});
  a.block_size = 1'000;
  a.max_trials = 999;
  expect_invalid([&] { run_adaptive_monte_carlo(kTwoScales, 2, a, o); }, {"max_trials must be >= the block size 1000"});
  a.max_trials = 10'000;
  expect_invalid([&] { run_adaptive_monte_carlo(kTwoScales, 0, a, o); }, {"measurand_count must be >= 1"});
  MonteCarloOptions bad_p = o;
  bad_p.coverage_probability = 1.0;
  expect_invalid([&] { run_adaptive_monte_carlo(kTwoScales, 2, a, bad_p); }, {"run_adaptive_monte_carlo", "coverage_probability"});
  expect_invalid([&] { run_adaptive_monte_carlo(ExperimentFactory{}, 2, a, o); }, {"factory must not be empty"});
}

}  // namespace

namespace {

// Issue 12: an unreachable tolerance (1e-300) no longer runs to the 10⁷-trial cap; the run
// stops after three blocks and says how many trials it would need.
TEST(AdaptiveHopeless, AnUnreachableToleranceStopsEarlyAndSaysWhy) {
  using namespace vcmm::uncertainty;
  AdaptiveOptions a;
  a.numerical_tolerance = 1e-300;
  a.block_size = 100;
  a.max_trials = 1'000'000;
  MonteCarloOptions o;
  o.threads = 2;
  const Experiment normal = [](RandomStream& rng, std::span<double> out) {
    out[0] = rng.standard_normal();
  };
  const MonteCarloResult r = run_adaptive_monte_carlo(normal, 1, a, o);
  EXPECT_EQ(r.status, RunStatus::not_converged);
  EXPECT_EQ(r.blocks, 3u);
  EXPECT_NE(r.message.find("cannot be reached"), std::string::npos) << r.message;
  // A reachable tolerance still converges normally.
  a.numerical_tolerance = 0.05;
  EXPECT_EQ(run_adaptive_monte_carlo(normal, 1, a, o).status, RunStatus::converged);
}

TEST(MinimumSampleCount, TinyProbabilitiesAreRefusedNotOverflowed) {
  using namespace vcmm::uncertainty;
  EXPECT_EQ(minimum_sample_count(0.95), 11u);
  EXPECT_GT(minimum_sample_count(1e-6), 400'000u);
  try {
    minimum_sample_count(1e-20);
    ADD_FAILURE() << "no exception";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("2^62"), std::string::npos) << e.what();
  }
}

}  // namespace
