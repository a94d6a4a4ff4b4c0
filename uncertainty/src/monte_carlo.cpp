// The Monte Carlo engine: a pool of std::thread workers over trial chunks, fixed-M runs and the
// adaptive procedure of JCGM 101 7.9.4. Contract and determinism argument:
// vcmm/uncertainty/monte_carlo.h; method: docs/uncertainty.md.
//
// One range of trials [begin, end) is run by T workers. Chunks of c consecutive trials are
// handed out by an atomic counter in increasing order; worker w calls its own experiment
// (shared or from the factory). Each chunk records how many of its trials completed (a
// contiguous run from its start), written only by the worker that took it and read after
// join(), so the completed PREFIX after a cancellation is well defined: whole chunks from the
// start, then the partial run of the first incomplete chunk.
//
// Errors: the first failing trial index e is kept in an atomic (lowered under a mutex that
// also guards the exception); a worker skips trials > e but finishes trials < e, and since
// chunks are taken in increasing order every chunk below e has been taken when e fails, so
// the lowest failing trial is found whatever the scheduling.
#include "vcmm/uncertainty/monte_carlo.h"

#include "internal/format.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <utility>

namespace vcmm::uncertainty {
namespace {

constexpr unsigned kMaxThreads = 1024;
constexpr std::uint64_t kNoError = std::numeric_limits<std::uint64_t>::max();

using internal::format_double;
using internal::format_short;

void validate_common(std::size_t q, const MonteCarloOptions& options, const char* caller) {
  if (q == 0) {
    throw InvalidInput(std::string(caller) + ": measurand_count must be >= 1; got 0");
  }
  if (!(options.coverage_probability > 0.0 && options.coverage_probability < 1.0)) {
    throw InvalidInput(std::string(caller) + ": coverage_probability must be in (0, 1); got " +
                       format_double(options.coverage_probability));
  }
  if (const ProcessGroup* g = options.process_group;
      g != nullptr && (g->size() == 0 || g->rank() >= g->size())) {
    throw InvalidInput(std::string(caller) + ": the process group must have rank < size; got rank " +
                       std::to_string(g->rank()) + " of " + std::to_string(g->size()));
  }
  if (options.threads > kMaxThreads) {
    throw InvalidInput(std::string(caller) + ": threads must be <= " + std::to_string(kMaxThreads) +
                       " (0 = hardware concurrency); got " + std::to_string(options.threads));
  }
}

void check_sample_room(std::uint64_t trials, std::size_t q, const char* caller) {
  if (trials > std::numeric_limits<std::size_t>::max() / sizeof(double) / q) {
    throw InvalidInput(std::string(caller) + ": trials x measurand_count overflows memory; got " +
                       std::to_string(trials) + " x " + std::to_string(q));
  }
}

unsigned worker_count(unsigned requested, std::uint64_t max_useful) {
  unsigned t = requested != 0 ? requested : std::thread::hardware_concurrency();
  if (t == 0) t = 1;
  return static_cast<unsigned>(std::min<std::uint64_t>(t, std::max<std::uint64_t>(1, max_useful)));
}

/// The experiments the workers call: shared, or one per worker from a factory.
class Experiments {
 public:
  Experiments(const Experiment& shared, unsigned workers, const char* caller)
      : callables_(workers, &shared) {
    if (!shared) throw InvalidInput(std::string(caller) + ": the experiment must not be empty");
  }
  Experiments(const ExperimentFactory& factory, unsigned workers, const char* caller) {
    if (!factory) {
      throw InvalidInput(std::string(caller) + ": the experiment factory must not be empty");
    }
    owned_.reserve(workers);
    for (unsigned w = 0; w < workers; ++w) {
      owned_.push_back(factory());
      if (!owned_.back()) {
        throw InvalidInput(std::string(caller) + ": the experiment factory returned an empty "
                           "experiment (call " + std::to_string(w + 1) + ")");
      }
    }
    for (const Experiment& e : owned_) callables_.push_back(&e);
  }
  Experiments(const Experiments&) = delete;
  Experiments& operator=(const Experiments&) = delete;

  unsigned size() const { return static_cast<unsigned>(callables_.size()); }
  const Experiment& operator[](unsigned w) const { return *callables_[w]; }

 private:
  std::vector<Experiment> owned_;
  std::vector<const Experiment*> callables_;
};

struct RangeOutcome {
  std::uint64_t completed = 0;  ///< trials [begin, begin + completed) are done
  bool cancelled = false;       ///< the cancel flag stopped the range before its end
};

/// Runs ranges of trials on the workers — of this process alone, or spread over the processes
/// of options.process_group — and keeps the count of trials done before the current range for
/// progress reports.
class TrialRunner {
 public:
  TrialRunner(const Experiments& experiments, std::size_t q, const MonteCarloOptions& options,
              std::uint64_t planned, const char* caller)
      : experiments_(experiments),
        q_(q),
        options_(options),
        group_(options.process_group != nullptr && options.process_group->size() > 1
                   ? options.process_group
                   : nullptr),
        progress_(group_ == nullptr || group_->rank() == 0 ? options.progress : nullptr),
        planned_(planned),
        caller_(caller) {}

  /// Runs trials [begin, end); trial t writes samples[(t − begin)·q …] (on every process when
  /// spread). Throws ExperimentError for the lowest failing trial (the same on every process).
  RangeOutcome run(std::uint64_t begin, std::uint64_t end, double* samples);

  std::uint64_t done_before() const { return done_before_; }

 private:
  struct Shared;
  /// Runs [begin, end) on this process's workers; progress counts its trials × `scale`.
  RangeOutcome run_local(std::uint64_t begin, std::uint64_t end, double* samples,
                         std::uint64_t scale);
  RangeOutcome run_spread(std::uint64_t begin, std::uint64_t end, double* samples);
  void work(Shared& s, unsigned worker) const;
  [[noreturn]] void throw_error(const Shared& s) const;

  const Experiments& experiments_;
  std::size_t q_;
  const MonteCarloOptions& options_;
  ProcessGroup* group_;  // null unless spread over two or more processes
  std::function<void(std::uint64_t, std::uint64_t)> progress_;  // rank 0's only
  std::uint64_t planned_;
  const char* caller_;
  std::uint64_t done_before_ = 0;
};

struct TrialRunner::Shared {
  std::uint64_t begin = 0, end = 0, chunk = 1, chunks = 0;
  double* samples = nullptr;
  std::vector<std::uint64_t> chunk_completed;  // written by the chunk's worker, read after join
  std::atomic<std::uint64_t> next_chunk{0};
  std::atomic<std::uint64_t> done{0};
  std::atomic<std::uint64_t> first_error{kNoError};
  std::atomic<bool> cancelled{false};
  std::atomic<bool> abort{false};  // the progress callback threw: stop everything
  std::mutex error_mutex;
  std::exception_ptr error;                      // the experiment's exception, or null
  std::size_t error_measurand = ExperimentError::no_measurand;
  double error_value = 0.0;
  // Monitor (progress) support.
  std::mutex active_mutex;
  std::condition_variable active_cv;
  unsigned active = 0;
};

void TrialRunner::work(Shared& s, unsigned worker) const {
  const Experiment& experiment = experiments_[worker];
  const std::atomic<bool>* cancel = options_.cancel;
  for (;;) {
    const std::uint64_t c = s.next_chunk.fetch_add(1, std::memory_order_relaxed);
    if (c >= s.chunks || s.abort.load(std::memory_order_relaxed)) break;
    const std::uint64_t t0 = s.begin + c * s.chunk;
    const std::uint64_t t1 = std::min(s.end, t0 + s.chunk);
    std::uint64_t completed = 0;
    for (std::uint64_t t = t0; t < t1; ++t) {
      if (t > s.first_error.load(std::memory_order_relaxed)) break;
      if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) {
        s.cancelled.store(true, std::memory_order_relaxed);
        break;
      }
      double* slot = s.samples + (t - s.begin) * q_;
      std::fill(slot, slot + q_, std::numeric_limits<double>::quiet_NaN());
      std::exception_ptr thrown;
      try {
        RandomStream rng(options_.seed, t);
        experiment(rng, std::span<double>(slot, q_));
      } catch (...) {
        thrown = std::current_exception();
      }
      std::size_t bad = ExperimentError::no_measurand;
      if (!thrown) {
        for (std::size_t j = 0; j < q_; ++j) {
          if (!std::isfinite(slot[j])) {
            bad = j;
            break;
          }
        }
      }
      if (thrown || bad != ExperimentError::no_measurand) {
        std::lock_guard<std::mutex> lock(s.error_mutex);
        if (t < s.first_error.load(std::memory_order_relaxed)) {
          s.error = thrown;
          s.error_measurand = bad;
          s.error_value = thrown ? 0.0 : slot[bad];
          s.first_error.store(t, std::memory_order_relaxed);
        }
        break;
      }
      ++completed;
    }
    s.chunk_completed[c] = completed;
    s.done.fetch_add(completed, std::memory_order_relaxed);
  }
}

void TrialRunner::throw_error(const Shared& s) const {
  const std::uint64_t t = s.first_error.load();
  const std::string where = std::string(caller_) + ": trial " + std::to_string(t) + " (seed " +
                            std::to_string(options_.seed) + ")";
  if (!s.error) {
    throw ExperimentError(where + ": measurand " + std::to_string(s.error_measurand) + " is " +
                              format_double(s.error_value) +
                              " (the experiment must write every measurand a finite value)",
                          t, s.error_measurand);
  }
  try {
    std::rethrow_exception(s.error);
  } catch (const std::exception& e) {
    std::throw_with_nested(ExperimentError(where + ": the experiment threw: " + e.what(), t));
  } catch (...) {
    std::throw_with_nested(
        ExperimentError(where + ": the experiment threw a non-standard exception", t));
  }
}

RangeOutcome TrialRunner::run(std::uint64_t begin, std::uint64_t end, double* samples) {
  const RangeOutcome out =
      group_ != nullptr ? run_spread(begin, end, samples) : run_local(begin, end, samples, 1);
  done_before_ += out.completed;
  if (progress_) progress_(done_before_, planned_);
  return out;
}

RangeOutcome TrialRunner::run_local(std::uint64_t begin, std::uint64_t end, double* samples,
                                    std::uint64_t scale) {
  Shared s;
  s.begin = begin;
  s.end = end;
  s.samples = samples;
  const std::uint64_t n = end - begin;
  const unsigned workers = static_cast<unsigned>(
      std::min<std::uint64_t>(experiments_.size(), std::max<std::uint64_t>(1, n)));
  // Chunks: at most 64 trials (so a cancel or error is seen soon and the load balances), at
  // least 16 chunks a worker when the range is small.
  s.chunk = std::clamp<std::uint64_t>(n / (16ull * workers), 1, 64);
  s.chunks = (n + s.chunk - 1) / s.chunk;
  s.chunk_completed.assign(s.chunks, 0);

  const bool monitor = static_cast<bool>(progress_);
  std::vector<std::thread> threads;
  std::exception_ptr monitor_error;
  auto worker_main = [this, &s](unsigned w) {
    work(s, w);
    std::lock_guard<std::mutex> lock(s.active_mutex);
    --s.active;
    s.active_cv.notify_all();
  };
  try {
    const unsigned spawned = monitor ? workers : workers - 1;
    s.active = spawned;
    threads.reserve(spawned);
    for (unsigned w = 0; w < spawned; ++w) {
      threads.emplace_back(worker_main, monitor ? w : w + 1);
    }
    if (monitor) {
      std::unique_lock<std::mutex> lock(s.active_mutex);
      while (!s.active_cv.wait_for(lock, std::chrono::milliseconds(100),
                                   [&s] { return s.active == 0; })) {
        lock.unlock();
        progress_(done_before_ + scale * s.done.load(std::memory_order_relaxed), planned_);
        lock.lock();
      }
    } else {
      work(s, 0);
    }
  } catch (...) {  // thread creation failed or the progress callback threw
    monitor_error = std::current_exception();
    s.abort.store(true);
    s.first_error.store(0);  // every worker stops at its next trial
  }
  for (std::thread& t : threads) t.join();
  if (monitor_error) std::rethrow_exception(monitor_error);
  if (s.first_error.load() != kNoError) throw_error(s);

  RangeOutcome out;
  for (std::uint64_t c = 0; c < s.chunks; ++c) {
    const std::uint64_t size = std::min(s.chunk, n - c * s.chunk);
    out.completed += s.chunk_completed[c];
    if (s.chunk_completed[c] != size) break;
  }
  out.cancelled = out.completed < n;
  return out;
}

// Spread over the processes: each runs its part, then they exchange (trials done, failure) per
// part so that all decide alike, then the samples. The lowest failing trial is in the first
// part that reports a failure (parts are in trial order and each finds its own lowest); the
// process that owns it rethrows its exception, every other one repeats that one trial — the
// experiment being a deterministic function of its stream, it fails the same way — so every
// process throws the same ExperimentError (message, trial, nested exception type) and none is
// left waiting in an exchange.
RangeOutcome TrialRunner::run_spread(std::uint64_t begin, std::uint64_t end, double* samples) {
  enum : std::uint64_t { kOk = 0, kTrialFailed = 1, kOtherFailure = 2 };
  const unsigned size = group_->size(), me = group_->rank();
  const TrialPart mine = trial_part(begin, end, me, size);
  RangeOutcome local;
  std::exception_ptr error;
  std::array<std::uint64_t, 3> status{0, kNoError, kOk};  // completed, failing trial, kind
  try {
    local = run_local(mine.first, mine.last, samples + (mine.first - begin) * q_, size);
    status[0] = local.completed;
  } catch (const ExperimentError& e) {
    error = std::current_exception();
    status[1] = e.trial();
    status[2] = kTrialFailed;
  } catch (...) {  // the progress callback threw, or threads could not be created
    error = std::current_exception();
    status[2] = kOtherFailure;
  }
  const std::vector<std::uint64_t> all = group_->all_gather(status);
  for (unsigned r = 0; r < size; ++r) {
    const std::uint64_t kind = all[3 * r + 2], trial = all[3 * r + 1];
    if (kind == kOk) continue;
    if (r == me) std::rethrow_exception(error);
    if (kind == kOtherFailure) {
      throw std::runtime_error(std::string(caller_) + ": process " + std::to_string(r) + " of " +
                               std::to_string(size) + " failed (its error output says why)");
    }
    std::vector<double> slot(q_);
    run_local(trial, trial + 1, slot.data(), 1);  // throws the same ExperimentError
    throw ExperimentError(std::string(caller_) + ": trial " + std::to_string(trial) +
                              " failed in process " + std::to_string(r) + " of " +
                              std::to_string(size) + " but not when repeated in process " +
                              std::to_string(me) + ": the experiment is not a deterministic "
                              "function of its random stream",
                          trial);
  }
  // The completed prefix: whole parts in rank order, then the done run of the first one cut
  // short (a cancel stops each process at its own point).
  std::vector<std::size_t> offsets(size), counts(size);
  RangeOutcome out;
  bool whole = true;
  for (unsigned r = 0; r < size; ++r) {
    const TrialPart part = trial_part(begin, end, r, size);
    const std::uint64_t done = all[3 * r];
    offsets[r] = static_cast<std::size_t>((part.first - begin) * q_);
    counts[r] = static_cast<std::size_t>(done * q_);
    if (whole) out.completed += done;
    whole = whole && done == part.last - part.first;
  }
  group_->all_gather(std::span<double>(samples, static_cast<std::size_t>((end - begin) * q_)),
                     offsets, counts);
  out.cancelled = out.completed < end - begin;
  return out;
}

/// Fills summaries and correlation from `samples` (trials × q) if there are enough trials;
/// measurands are summarised in parallel (each a sort), results independent of the threads.
void summarize_result(MonteCarloResult& r, double p, unsigned threads) {
  const std::size_t q = r.measurand_count;
  if (r.trials < minimum_sample_count(p)) return;
  r.summaries.assign(q, MeasurandSummary{});
  const unsigned t = static_cast<unsigned>(std::min<std::size_t>(std::max(1u, threads), q));
  std::vector<std::exception_ptr> errors(t);
  auto job = [&r, &errors, p, q, t](unsigned w) {
    try {
      for (std::size_t j = w; j < q; j += t) {
        r.summaries[j] = summarize_measurand(r.samples, q, j, p);
      }
    } catch (...) {
      errors[w] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (unsigned w = 1; w < t; ++w) pool.emplace_back(job, w);
  job(0);
  for (std::thread& th : pool) th.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
  r.correlation = correlation_matrix(r.samples, q);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

MonteCarloResult run_fixed(const Experiments& experiments, std::size_t q,
                           const MonteCarloOptions& options,
                           std::chrono::steady_clock::time_point t0) {
  const char* caller = "run_monte_carlo";
  MonteCarloResult r;
  r.measurand_count = q;
  r.threads_used = experiments.size();
  r.ranks = options.process_group != nullptr ? options.process_group->size() : 1;
  r.samples.resize(options.trials * q);
  TrialRunner runner(experiments, q, options, options.trials, caller);
  const RangeOutcome out = runner.run(0, options.trials, r.samples.data());
  r.trials = out.completed;
  r.samples.resize(r.trials * q);
  r.samples.shrink_to_fit();
  if (out.cancelled) {
    r.status = RunStatus::cancelled;
    r.message = "cancelled after " + std::to_string(r.trials) + " of " +
                std::to_string(options.trials) + " trials";
  } else {
    r.status = RunStatus::completed;
    r.message = "completed " + std::to_string(r.trials) + " trials";
  }
  summarize_result(r, options.coverage_probability, r.threads_used);
  if (r.summaries.empty()) {
    r.message += "; too few for a coverage interval (need " +
                 std::to_string(minimum_sample_count(options.coverage_probability)) +
                 "): no summaries";
  }
  r.wall_seconds = seconds_since(t0);
  return r;
}

void validate_fixed(std::size_t q, const MonteCarloOptions& options) {
  const char* caller = "run_monte_carlo";
  validate_common(q, options, caller);
  const std::uint64_t least = minimum_sample_count(options.coverage_probability);
  if (options.trials < least) {
    throw InvalidInput(std::string(caller) + ": trials must be >= " + std::to_string(least) +
                       " for a " + format_double(100.0 * options.coverage_probability) +
                       " % coverage interval (JCGM 101 7.7.1); got " +
                       std::to_string(options.trials));
  }
  check_sample_room(options.trials, q, caller);
}

// ---- adaptive (JCGM 101 7.9.4) ----------------------------------------------------------------

/// Mean and sum of squared deviations of all trials so far, merged block by block (Chan,
/// Golub & LeVeque 1983): deterministic, O(q) per block.
struct PooledMoments {
  double count = 0.0, mean = 0.0, m2 = 0.0;
  void merge(double n, double block_mean, double block_m2) {
    const double total = count + n;
    const double delta = block_mean - mean;
    mean += delta * (n / total);
    m2 += block_m2 + delta * delta * (count * n / total);
    count = total;
  }
  double standard_deviation() const { return count > 1.0 ? std::sqrt(m2 / (count - 1.0)) : 0.0; }
};

/// s of the average of the h values (JCGM 101 7.9.4): √(Σ (v − v̄)² / (h(h − 1))).
double standard_deviation_of_average(const std::vector<double>& v) {
  const double h = static_cast<double>(v.size());
  double mean = 0.0;
  for (const double x : v) mean += x;
  mean /= h;
  double ss = 0.0;
  for (const double x : v) ss += (x - mean) * (x - mean);
  return std::sqrt(ss / (h * (h - 1.0)));
}

void validate_adaptive(std::size_t q, const AdaptiveOptions& a, const MonteCarloOptions& options,
                       std::uint64_t block) {
  const char* caller = "run_adaptive_monte_carlo";
  validate_common(q, options, caller);
  if (!std::isfinite(a.numerical_tolerance) || a.numerical_tolerance < 0.0) {
    throw InvalidInput(std::string(caller) + ": numerical_tolerance must be finite and >= 0; got " +
                       format_double(a.numerical_tolerance));
  }
  if (a.numerical_tolerance == 0.0 && (a.significant_digits < 1 || a.significant_digits > 15)) {
    throw InvalidInput(std::string(caller) +
                       ": give numerical_tolerance > 0 or significant_digits in 1..15; got "
                       "numerical_tolerance = 0, significant_digits = " +
                       std::to_string(a.significant_digits));
  }
  const std::uint64_t least = minimum_sample_count(options.coverage_probability);
  if (block < least) {
    throw InvalidInput(std::string(caller) + ": block_size must be >= " + std::to_string(least) +
                       " (each block needs its own coverage interval); got " +
                       std::to_string(block));
  }
  if (a.max_trials < block) {
    throw InvalidInput(std::string(caller) + ": max_trials must be >= the block size " +
                       std::to_string(block) + "; got " + std::to_string(a.max_trials));
  }
  check_sample_room(a.max_trials, q, caller);
}

MonteCarloResult run_adaptive(const Experiments& experiments, std::size_t q,
                              const AdaptiveOptions& a, const MonteCarloOptions& options,
                              std::uint64_t block, std::chrono::steady_clock::time_point t0) {
  const char* caller = "run_adaptive_monte_carlo";
  const double p = options.coverage_probability;
  MonteCarloResult r;
  r.measurand_count = q;
  r.threads_used = experiments.size();
  r.ranks = options.process_group != nullptr ? options.process_group->size() : 1;
  r.block_size = block;
  TrialRunner runner(experiments, q, options, a.max_trials, caller);
  // Per measurand: the block values of ȳ, u, y_low, y_high (JCGM 101 7.9.4).
  std::vector<std::array<std::vector<double>, 4>> block_values(q);
  std::vector<PooledMoments> pooled(q);
  r.status = RunStatus::not_converged;
  double projected_trials = 0.0;  // set when the tolerance is out of reach (below)
  ProcessGroup* group = options.process_group;
  for (std::uint64_t h = 0;; ++h) {
    if (any_process(group, options.cancel != nullptr && options.cancel->load())) {
      r.status = RunStatus::cancelled;
      break;
    }
    if ((h + 1) * block > a.max_trials) break;  // not converged within max_trials
    const std::uint64_t begin = h * block;
    r.samples.resize((begin + block) * q);
    const RangeOutcome out = runner.run(begin, begin + block, r.samples.data() + begin * q);
    if (out.cancelled) {
      r.samples.resize((begin + out.completed) * q);
      r.status = RunStatus::cancelled;
      break;
    }
    r.blocks = h + 1;
    const std::span<const double> block_samples(r.samples.data() + begin * q, block * q);
    for (std::size_t j = 0; j < q; ++j) {
      const MeasurandSummary s = summarize_measurand(block_samples, q, j, p);
      block_values[j][0].push_back(s.mean);
      block_values[j][1].push_back(s.standard_uncertainty);
      block_values[j][2].push_back(s.probabilistically_symmetric.low);
      block_values[j][3].push_back(s.probabilistically_symmetric.high);
      const double n = static_cast<double>(block);
      pooled[j].merge(n, s.mean, s.standard_uncertainty * s.standard_uncertainty * (n - 1.0));
    }
    if (r.blocks < 2) continue;  // 7.9.4: the first check needs two blocks
    bool converged = true;
    r.numerical_tolerance.assign(q, 0.0);
    r.stability.assign(q, 0.0);
    for (std::size_t j = 0; j < q; ++j) {
      double s_max = 0.0;
      for (const std::vector<double>& v : block_values[j]) {
        s_max = std::max(s_max, standard_deviation_of_average(v));
      }
      r.stability[j] = 2.0 * s_max;
      r.numerical_tolerance[j] =
          a.numerical_tolerance > 0.0
              ? a.numerical_tolerance
              : numerical_tolerance_from_digits(pooled[j].standard_deviation(), a.significant_digits);
      converged = converged && r.stability[j] <= r.numerical_tolerance[j];
    }
    // Every process computed the same numbers from the same samples; process 0's decision is
    // taken by all all the same, so that no process can ever wait for a block the others skip.
    if (decision_of_first(group, converged)) {
      r.status = RunStatus::converged;
      break;
    }
    // Hopeless? 2s falls like 1/√h, so about h·(2s/δ)² blocks would be needed. From the third
    // block on, a projection beyond four times max_trials stops the run now instead of
    // spending max_trials on a tolerance it cannot reach (e.g. δ = 1e-300).
    if (r.blocks >= 3) {
      double worst = 0.0;
      for (std::size_t j = 0; j < q; ++j)
        if (r.numerical_tolerance[j] > 0.0)
          worst = std::max(worst, r.stability[j] / r.numerical_tolerance[j]);
        else if (r.stability[j] > 0.0)
          worst = std::numeric_limits<double>::infinity();
      const double needed = static_cast<double>(r.blocks) * worst * worst * static_cast<double>(block);
      if (decision_of_first(group, needed > 4.0 * static_cast<double>(a.max_trials))) {
        projected_trials = needed;
        break;
      }
    }
  }
  r.trials = r.samples.size() / q;
  r.samples.shrink_to_fit();
  switch (r.status) {
    case RunStatus::converged:
      r.message = "converged after " + std::to_string(r.blocks) + " blocks of " +
                  std::to_string(block) + " trials: 2s <= delta for every measurand (JCGM 101 7.9.4)";
      break;
    case RunStatus::cancelled:
      r.message = "cancelled after " + std::to_string(r.trials) + " trials";
      break;
    default: {
      r.message = projected_trials > 0.0
                      ? "stopped after " + std::to_string(r.blocks) + " blocks of " +
                            std::to_string(block) + ": the numerical tolerance cannot be reached "
                            "within max_trials = " + std::to_string(a.max_trials) +
                            " (about " + format_short(projected_trials) + " trials would be needed)"
                      : "not converged within max_trials = " + std::to_string(a.max_trials) +
                            " (" + std::to_string(r.blocks) + " blocks of " +
                            std::to_string(block) + ")";
      for (std::size_t j = 0; j < r.stability.size(); ++j) {
        if (r.stability[j] > r.numerical_tolerance[j]) {
          r.message += "; measurand " + std::to_string(j) + ": 2s = " + format_short(r.stability[j]) +
                       " > delta = " + format_short(r.numerical_tolerance[j]);
        }
      }
      break;
    }
  }
  summarize_result(r, p, r.threads_used);
  if (r.summaries.empty()) {
    r.message += "; too few for a coverage interval (need " +
                 std::to_string(minimum_sample_count(p)) + "): no summaries";
  }
  r.wall_seconds = seconds_since(t0);
  return r;
}

}  // namespace

std::string_view to_string(RunStatus status) {
  switch (status) {
    case RunStatus::completed: return "completed";
    case RunStatus::converged: return "converged";
    case RunStatus::not_converged: return "not_converged";
    case RunStatus::cancelled: return "cancelled";
  }
  return "unknown";
}

std::uint64_t default_block_size(double coverage_probability) {
  if (!(coverage_probability > 0.0 && coverage_probability < 1.0)) {
    throw InvalidInput("default_block_size: coverage probability must be in (0, 1); got " +
                       format_double(coverage_probability));
  }
  // ⌈100/(1 − p)⌉ in double: 1 − p is exact for p ≥ ½ (Sterbenz), the quotient correctly
  // rounded; for p = 0.99 it is 9999.99999999999 → 10 000, as intended.
  const double j = std::ceil(100.0 / (1.0 - coverage_probability));
  if (!(j < 9.0e18)) {
    throw InvalidInput("default_block_size: 100/(1 - p) is too large; p = " +
                       format_double(coverage_probability));
  }
  return std::max<std::uint64_t>(static_cast<std::uint64_t>(j), 10'000);
}

double numerical_tolerance_from_digits(double u, int digits) {
  if (!std::isfinite(u) || u < 0.0) {
    throw InvalidInput("numerical_tolerance_from_digits: standard uncertainty must be finite and "
                       ">= 0; got " + format_double(u));
  }
  if (digits < 1 || digits > 15) {
    throw InvalidInput("numerical_tolerance_from_digits: significant digits must be in 1..15; got " +
                       std::to_string(digits));
  }
  if (u == 0.0) return 0.0;
  // u = c·10^l with c rounded to an integer of exactly `digits` digits. The first guess of l
  // from log10 is corrected when the rounding carries into one more digit (0.0999 to 2
  // digits is 0.10: l = −2) or log10 rounded up just below a power of ten; each correction
  // moves c by a factor 10 and cannot undo the other, so two passes suffice.
  const double c_max = std::pow(10.0, digits), c_min = std::pow(10.0, digits - 1);
  int l = static_cast<int>(std::floor(std::log10(u))) - digits + 1;
  for (int pass = 0; pass < 2; ++pass) {
    const double c = std::round(u / std::pow(10.0, l));
    if (c >= c_max) {
      ++l;
    } else if (c < c_min) {
      --l;
    } else {
      break;
    }
  }
  return 0.5 * std::pow(10.0, l);
}

MonteCarloResult run_monte_carlo(const Experiment& experiment, std::size_t measurand_count,
                                 const MonteCarloOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  validate_fixed(measurand_count, options);
  const Experiments experiments(experiment, worker_count(options.threads, options.trials),
                                "run_monte_carlo");
  return run_fixed(experiments, measurand_count, options, t0);
}

MonteCarloResult run_monte_carlo(const ExperimentFactory& factory, std::size_t measurand_count,
                                 const MonteCarloOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  validate_fixed(measurand_count, options);
  const Experiments experiments(factory, worker_count(options.threads, options.trials),
                                "run_monte_carlo");
  return run_fixed(experiments, measurand_count, options, t0);
}

MonteCarloResult run_adaptive_monte_carlo(const Experiment& experiment,
                                          std::size_t measurand_count,
                                          const AdaptiveOptions& adaptive,
                                          const MonteCarloOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  validate_common(measurand_count, options, "run_adaptive_monte_carlo");
  const std::uint64_t block = adaptive.block_size != 0
                                  ? adaptive.block_size
                                  : default_block_size(options.coverage_probability);
  validate_adaptive(measurand_count, adaptive, options, block);
  const Experiments experiments(experiment, worker_count(options.threads, block),
                                "run_adaptive_monte_carlo");
  return run_adaptive(experiments, measurand_count, adaptive, options, block, t0);
}

MonteCarloResult run_adaptive_monte_carlo(const ExperimentFactory& factory,
                                          std::size_t measurand_count,
                                          const AdaptiveOptions& adaptive,
                                          const MonteCarloOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  validate_common(measurand_count, options, "run_adaptive_monte_carlo");
  const std::uint64_t block = adaptive.block_size != 0
                                  ? adaptive.block_size
                                  : default_block_size(options.coverage_probability);
  validate_adaptive(measurand_count, adaptive, options, block);
  const Experiments experiments(factory, worker_count(options.threads, block),
                                "run_adaptive_monte_carlo");
  return run_adaptive(experiments, measurand_count, adaptive, options, block, t0);
}

}  // namespace vcmm::uncertainty
