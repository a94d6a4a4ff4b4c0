// Monte Carlo spread over processes (process_group.h) without MPI: N processes simulated by
// threads (tests/support/fake_process_group.h). Checks the split of a range into parts, that
// fixed and adaptive runs are bit-identical to the single-process run on every process for
// several process and thread counts, that a failing trial gives every process the same error
// (none waits), that a cancel on one process gives all the same prefix, and that only rank 0
// reports progress.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/fake_process_group.h"
#include "varied_experiment.h"
#include "vcmm/uncertainty/monte_carlo.h"
#include "vcmm/uncertainty/process_group.h"

namespace {

using namespace vcmm::uncertainty;
using vcmm::test::bit_identical;
using vcmm::test::ProcessOutcome;
using vcmm::test::run_as_processes;

const Experiment& kVaried = vcmm::test::kVariedExperiment;

MonteCarloOptions options_with(std::uint64_t trials, unsigned threads) {
  MonteCarloOptions o;
  o.trials = trials;
  o.threads = threads;
  o.seed = 20261127;
  return o;
}

/// The outcomes of `run(options)` on `processes` simulated processes, each with `threads`
/// threads; no contract violation allowed.
std::vector<ProcessOutcome<MonteCarloResult>> spread(
    unsigned processes, unsigned threads, std::uint64_t trials,
    const std::function<MonteCarloResult(const MonteCarloOptions&)>& run) {
  std::string violations;
  auto outcomes = run_as_processes<MonteCarloResult>(
      processes,
      [&](ProcessGroup& group) {
        MonteCarloOptions o = options_with(trials, threads);
        o.process_group = &group;
        return run(o);
      },
      &violations);
  EXPECT_EQ(violations, "");
  return outcomes;
}

void expect_same_result(const MonteCarloResult& a, const MonteCarloResult& b,
                        const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(a.trials, b.trials);
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.message, b.message);
  EXPECT_TRUE(bit_identical(a.samples, b.samples));
  ASSERT_EQ(a.summaries.size(), b.summaries.size());
  for (std::size_t j = 0; j < a.summaries.size(); ++j) {
    const MeasurandSummary &x = a.summaries[j], &y = b.summaries[j];
    const double xs[] = {x.mean, x.standard_uncertainty, x.probabilistically_symmetric.low,
                         x.probabilistically_symmetric.high, x.shortest.low, x.shortest.high};
    const double ys[] = {y.mean, y.standard_uncertainty, y.probabilistically_symmetric.low,
                         y.probabilistically_symmetric.high, y.shortest.low, y.shortest.high};
    EXPECT_TRUE(bit_identical(xs, ys)) << "measurand " << j;
    EXPECT_EQ(x.count, y.count);
  }
  EXPECT_TRUE(bit_identical(a.correlation, b.correlation));
  EXPECT_EQ(a.blocks, b.blocks);
  EXPECT_TRUE(bit_identical(a.stability, b.stability));
  EXPECT_TRUE(bit_identical(a.numerical_tolerance, b.numerical_tolerance));
}

TEST(TrialPart, ContiguousBalancedInRankOrder) {
  for (const std::uint64_t begin : {0ull, 7ull, 1'000'000ull}) {
    for (const std::uint64_t n : {0ull, 1ull, 5ull, 11ull, 1000ull, 1001ull}) {
      for (const unsigned size : {1u, 2u, 3u, 7u, 16u}) {
        std::uint64_t next = begin, smallest = n, largest = 0;
        for (unsigned r = 0; r < size; ++r) {
          const TrialPart p = trial_part(begin, begin + n, r, size);
          ASSERT_EQ(p.first, next) << n << " over " << size << ", rank " << r;
          ASSERT_LE(p.first, p.last);
          smallest = std::min(smallest, p.last - p.first);
          largest = std::max(largest, p.last - p.first);
          next = p.last;
        }
        EXPECT_EQ(next, begin + n);
        EXPECT_LE(largest - smallest, 1u);
      }
    }
  }
  // 10 over 4: 3, 3, 2, 2.
  EXPECT_EQ(trial_part(0, 10, 1, 4).first, 3u);
  EXPECT_EQ(trial_part(0, 10, 3, 4).first, 8u);
}

TEST(TrialPart, RejectsBadRankSizeOrRange) {
  EXPECT_THROW(trial_part(0, 10, 0, 0), InvalidInput);
  EXPECT_THROW(trial_part(0, 10, 2, 2), InvalidInput);
  try {
    trial_part(10, 5, 0, 1);
    ADD_FAILURE() << "no exception";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("[10, 5)"), std::string::npos) << e.what();
  }
}

/// Every outcome is `expected`, bit for bit, from `processes` processes.
void expect_all_same(const std::vector<ProcessOutcome<MonteCarloResult>>& outcomes,
                     const MonteCarloResult& expected, const std::string& what) {
  for (std::size_t r = 0; r < outcomes.size(); ++r) {
    const std::string where = what + ", rank " + std::to_string(r);
    ASSERT_FALSE(outcomes[r].error) << where;
    expect_same_result(outcomes[r].value, expected, where);
    EXPECT_EQ(outcomes[r].value.ranks, outcomes.size()) << where;
  }
}

TEST(ProcessGroupRun, FixedRunIsBitIdenticalForAnyProcessAndThreadCount) {
  constexpr std::uint64_t m = 1001;  // not a multiple of any process count used
  const MonteCarloResult single = run_monte_carlo(kVaried, 3, options_with(m, 1));
  ASSERT_EQ(single.ranks, 1u);
  for (const unsigned processes : {1u, 2u, 3u, 5u}) {
    for (const unsigned threads : {1u, 3u}) {
      const auto outcomes = spread(processes, threads, m, [](const MonteCarloOptions& o) {
        return run_monte_carlo(kVaried, 3, o);
      });
      expect_all_same(outcomes, single,
                      std::to_string(processes) + " processes x " + std::to_string(threads));
      for (const auto& o : outcomes) EXPECT_EQ(o.value.threads_used, threads);
    }
  }
  // More processes than trials: some parts are empty.
  const MonteCarloResult eleven = run_monte_carlo(kVaried, 3, options_with(11, 1));
  expect_all_same(spread(16, 1, 11,
                         [](const MonteCarloOptions& o) { return run_monte_carlo(kVaried, 3, o); }),
                  eleven, "11 trials over 16 processes");
  // One experiment per worker thread (the factory overload).
  const ExperimentFactory factory = [] { return kVaried; };
  expect_all_same(
      spread(3, 2, 600, [&](const MonteCarloOptions& o) { return run_monte_carlo(factory, 3, o); }),
      run_monte_carlo(factory, 3, options_with(600, 2)), "factory, 3 processes");
}

TEST(ProcessGroupRun, AdaptiveRunTakesTheSameBlocksAndDecisions) {
  // Converges after a few blocks (checked below): the measurands' u are ~4 and ~12.
  AdaptiveOptions a;
  a.numerical_tolerance = 0.5;
  a.block_size = 300;
  a.max_trials = 30'000;
  const auto adaptive = [&a](const MonteCarloOptions& o) {
    return run_adaptive_monte_carlo(kVaried, 3, a, o);
  };
  const MonteCarloResult single = adaptive(options_with(0, 2));
  ASSERT_EQ(single.status, RunStatus::converged);
  ASSERT_GE(single.blocks, 3u) << single.message;
  for (const unsigned processes : {2u, 3u}) {
    expect_all_same(spread(processes, 1, 0, adaptive), single,
                    std::to_string(processes) + " processes, adaptive");
  }
  // Not converged (max_trials reached) alike.
  a.numerical_tolerance = 1e-9;
  a.max_trials = 1500;
  const MonteCarloResult hopeless = adaptive(options_with(0, 1));
  ASSERT_EQ(hopeless.status, RunStatus::not_converged);
  expect_all_same(spread(2, 2, 0, adaptive), hopeless, "2 processes, not converged");
}

/// Every process must throw an ExperimentError for `trial` with the same message, with a
/// nested std::domain_error or none.
void expect_same_error(const std::vector<ProcessOutcome<MonteCarloResult>>& outcomes,
                       std::uint64_t trial, bool nested_domain_error) {
  std::string first_message;
  for (std::size_t r = 0; r < outcomes.size(); ++r) {
    SCOPED_TRACE("rank " + std::to_string(r));
    ASSERT_TRUE(outcomes[r].error);
    try {
      std::rethrow_exception(outcomes[r].error);
    } catch (const ExperimentError& e) {
      EXPECT_EQ(e.trial(), trial);
      if (r == 0) first_message = e.what();
      EXPECT_EQ(first_message, e.what());
      bool nested = false;
      try {
        std::rethrow_if_nested(e);
      } catch (const std::domain_error&) {
        nested = true;
      } catch (...) {
      }
      EXPECT_EQ(nested, nested_domain_error);
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not an ExperimentError: " << e.what();
    }
  }
}

TEST(ProcessGroupRun, FailingTrialGivesEveryProcessTheSameError) {
  // Trials 437 and 800 fail; the lowest (437) is in process 1's part of 3 (334…667), and a
  // single process names it too.
  const Experiment failing = [](RandomStream& rng, std::span<double> y) {
    if (rng.stream() == 437 || rng.stream() == 800) throw std::domain_error("bad draw");
    kVaried(rng, y);
  };
  const auto fixed = [&](const MonteCarloOptions& o) { return run_monte_carlo(failing, 3, o); };
  std::string single_message;
  try {
    fixed(options_with(1000, 2));
  } catch (const ExperimentError& e) {
    single_message = e.what();
  }
  ASSERT_NE(single_message, "");
  for (const unsigned processes : {2u, 3u, 4u}) {
    const auto outcomes = spread(processes, 2, 1000, fixed);
    expect_same_error(outcomes, 437, true);
    try {
      std::rethrow_exception(outcomes[0].error);
    } catch (const ExperimentError& e) {
      EXPECT_EQ(single_message, e.what());
    }
  }
  // In an adaptive run's second block.
  AdaptiveOptions a;
  a.numerical_tolerance = 1e-6;
  a.block_size = 300;
  a.max_trials = 3000;
  expect_same_error(spread(3, 1, 0,
                           [&](const MonteCarloOptions& o) {
                             return run_adaptive_monte_carlo(failing, 3, a, o);
                           }),
                    437, true);
}

TEST(ProcessGroupRun, NonFiniteMeasurandGivesEveryProcessTheSameError) {
  const Experiment nan_at_900 = [](RandomStream& rng, std::span<double> y) {
    kVaried(rng, y);
    if (rng.stream() == 900) y[1] = std::nan("");
  };
  expect_same_error(spread(2, 1, 1000,
                           [&](const MonteCarloOptions& o) {
                             return run_monte_carlo(nan_at_900, 3, o);
                           }),
                    900, false);
}

TEST(ProcessGroupRun, CancelOnOneProcessGivesAllTheSamePrefix) {
  // Process 1 of 3 is cancelled before it starts: the result is process 0's whole part
  // (trials 0…333) on every process, whatever the others completed.
  const MonteCarloResult single = run_monte_carlo(kVaried, 3, options_with(1000, 1));
  std::atomic<bool> stop{true}, go{false};
  const auto outcomes = run_as_processes<MonteCarloResult>(3, [&](ProcessGroup& group) {
    MonteCarloOptions o = options_with(1000, 2);
    o.process_group = &group;
    o.cancel = group.rank() == 1 ? &stop : &go;
    return run_monte_carlo(kVaried, 3, o);
  });
  for (const auto& o : outcomes) {
    ASSERT_FALSE(o.error);
    EXPECT_EQ(o.value.status, RunStatus::cancelled);
    ASSERT_EQ(o.value.trials, 334u);
    EXPECT_TRUE(bit_identical(o.value.samples,
                              std::span<const double>(single.samples.data(), 334 * 3)));
    EXPECT_EQ(o.value.message, outcomes[0].value.message);
  }
  // Adaptive: a cancel seen by one process before a block ends the run on all.
  AdaptiveOptions a;
  a.numerical_tolerance = 1e-6;
  a.block_size = 300;
  a.max_trials = 3000;
  const auto adaptive = run_as_processes<MonteCarloResult>(2, [&](ProcessGroup& group) {
    MonteCarloOptions o = options_with(0, 1);
    o.process_group = &group;
    o.cancel = group.rank() == 1 ? &stop : &go;
    return run_adaptive_monte_carlo(kVaried, 3, a, o);
  });
  for (const auto& o : adaptive) {
    ASSERT_FALSE(o.error);
    EXPECT_EQ(o.value.status, RunStatus::cancelled);
    EXPECT_EQ(o.value.trials, 0u);
  }
}

TEST(ProcessGroupRun, OnlyRankZeroReportsProgressAndItReachesThePlannedCount) {
  std::vector<std::uint64_t> last(3, 0), calls(3, 0);
  const auto outcomes = run_as_processes<MonteCarloResult>(3, [&](ProcessGroup& group) {
    MonteCarloOptions o = options_with(1200, 1);
    o.process_group = &group;
    const unsigned r = group.rank();
    o.progress = [&, r](std::uint64_t done, std::uint64_t planned) {
      EXPECT_EQ(planned, 1200u);
      EXPECT_LE(done, planned);
      last[r] = done;
      ++calls[r];
    };
    return run_monte_carlo(kVaried, 3, o);
  });
  for (const auto& o : outcomes) ASSERT_FALSE(o.error);
  EXPECT_GE(calls[0], 1u);
  EXPECT_EQ(last[0], 1200u);
  EXPECT_EQ(calls[1], 0u);
  EXPECT_EQ(calls[2], 0u);
}

TEST(ProcessGroupRun, AgreementsTakeProcessZerosDecisionOrAnyFlag) {
  const auto first = run_as_processes<int>(3, [](ProcessGroup& group) {
    return decision_of_first(&group, group.rank() == 0) ? 1 : 0;
  });
  for (const auto& o : first) EXPECT_EQ(o.value, 1);
  const auto any = run_as_processes<int>(3, [](ProcessGroup& group) {
    return any_process(&group, group.rank() == 2) ? 1 : 0;
  });
  for (const auto& o : any) EXPECT_EQ(o.value, 1);
  const auto none = run_as_processes<int>(3, [](ProcessGroup& group) {
    return any_process(&group, false) ? 1 : 0;
  });
  for (const auto& o : none) EXPECT_EQ(o.value, 0);
  EXPECT_TRUE(decision_of_first(nullptr, true));
  EXPECT_FALSE(any_process(nullptr, false));
}

TEST(ProcessGroupRun, RejectsAGroupWhoseRankIsNotBelowItsSize) {
  struct Broken final : ProcessGroup {
    unsigned rank() const override { return 2; }
    unsigned size() const override { return 2; }
    void all_gather(std::span<double>, std::span<const std::size_t>,
                    std::span<const std::size_t>) override {}
    std::vector<std::uint64_t> all_gather(std::span<const std::uint64_t>) override { return {}; }
  } broken;
  MonteCarloOptions o = options_with(100, 1);
  o.process_group = &broken;
  try {
    run_monte_carlo(kVaried, 3, o);
    ADD_FAILURE() << "no exception";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("rank 2 of 2"), std::string::npos) << e.what();
  }
}

}  // namespace
