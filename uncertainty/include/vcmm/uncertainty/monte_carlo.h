// vcmm/uncertainty/monte_carlo.h — the Monte Carlo method of JCGM 101:2008 (GUM Supplement 1,
// "Propagation of distributions using a Monte Carlo method") for any virtual experiment.
//
// The engine knows no metrology. A *virtual experiment* is a callable that, given the
// random stream of one trial, draws every input quantity it needs and writes the q output
// quantities (measurands) of that trial (JCGM 101 7.3–7.5: sampling the input PDFs and
// evaluating the model). The engine runs trials 0 … M − 1 — trial t always gets
// RandomStream(seed, t), whatever thread runs it — stores the samples trial-major and
// summarises them per JCGM 101 7.6–7.7 (statistics.h). Fixed M (7.2) or the adaptive
// procedure (7.9) in blocks.
//
// Determinism: sample t depends on (seed, t) and the experiment only, each trial writes its
// own slot, and statistics are computed afterwards from the stored samples in index order:
// samples, summaries and correlation are bit-identical for any thread count (tested with
// 1, 2, 5, 7 threads) — provided the experiment is a deterministic function of its stream.
//
// Threads: a pool of std::thread workers takes chunks of consecutive trials from an atomic
// counter. With a single Experiment the SAME callable is invoked from all workers at once: it
// must be safe to call concurrently (no shared mutable state; keep per-call scratch in
// thread_local storage or use the ExperimentFactory overloads, which create one experiment
// per worker thread — e.g. one owning its scratch buffers).
//
// Processes: with MonteCarloOptions::process_group set (e.g. the ranks of an MPI job), every
// range of trials is cut into contiguous parts, one per process, each run on that process's
// threads, and the samples are gathered in trial order on every process (process_group.h).
// Summaries, correlation and every adaptive decision are computed from the same array, so the
// result is bit-identical for any number of processes and threads, on every process.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vcmm/uncertainty/errors.h"
#include "vcmm/uncertainty/process_group.h"
#include "vcmm/uncertainty/random_stream.h"
#include "vcmm/uncertainty/statistics.h"

namespace vcmm::uncertainty {

/// A virtual experiment: given the trial's own random stream, writes the q measurand values.
/// It must write every measurand a finite value (the slot is pre-filled with NaN; a NaN or
/// ±inf left there stops the run with ExperimentError), and must not keep `measurands` or
/// `rng` beyond the call.
using Experiment = std::function<void(RandomStream& rng, std::span<double> measurands)>;

/// Makes one Experiment per worker thread. Called from the caller's thread, once per worker,
/// before any trial runs; each experiment returned is then only ever called from one thread.
using ExperimentFactory = std::function<Experiment()>;

struct MonteCarloOptions {
  std::uint64_t trials = 1'000'000;     ///< M (fixed-M run); ≥ minimum_sample_count(p)
  std::uint64_t seed = 1;
  unsigned threads = 0;                 ///< 0 = std::thread::hardware_concurrency(); ≤ 1024
  double coverage_probability = 0.95;   ///< p in (0, 1)
  /// Called from ONE thread (the caller's) about every 100 ms with (trials done, planned),
  /// and once more when the trials are finished; may be empty. When set, the caller's thread
  /// only monitors and `threads` workers run the trials; when empty, the caller's thread is
  /// one of the workers. An exception thrown by it stops the run and is rethrown.
  std::function<void(std::uint64_t done, std::uint64_t planned)> progress;
  /// When set and it becomes true, the run stops early; the result covers the completed
  /// PREFIX of trials 0..M_done−1 and says cancelled = true (status RunStatus::cancelled).
  /// Workers look at it before each trial. Spread over processes: each process stops its own
  /// part; the result is the prefix that all parts together completed, the same everywhere.
  const std::atomic<bool>* cancel = nullptr;
  /// The processes the trials are spread over (process_group.h); null: this process alone.
  /// Every process of the group must make the same run_… call with the same options (but
  /// `threads`, `progress` and `cancel`, which are its own) and the same experiment. Progress
  /// is reported on rank 0 only: trials done = those of the finished ranges + rank 0's own in
  /// the current range × size() (parts differ by at most one trial). Each process holds all
  /// the samples (8·q·M bytes).
  ProcessGroup* process_group = nullptr;
};

struct AdaptiveOptions {   // JCGM 101 7.9
  /// δ in the measurands' unit for ALL measurands, if > 0 (JCGM 101 7.9.2 allows any δ).
  double numerical_tolerance = 0;
  /// Else n_dig ≥ 1: δ = ½·10^l where u(y) written to n_dig significant digits is c·10^l
  /// (c an n_dig-digit integer; 7.9.2), per measurand, from u of all trials so far.
  int significant_digits = 0;
  std::uint64_t max_trials = 10'000'000;  ///< stop (not_converged) before exceeding this
  std::uint64_t block_size = 0;  ///< 0: max(ceil(100/(1−p)), 10 000) as in JCGM 101 7.9.4
};

enum class RunStatus {
  completed,      ///< fixed-M run: all M trials done
  converged,      ///< adaptive: the 7.9.4 stopping rule was met
  not_converged,  ///< adaptive: max_trials reached first (the result is still usable as a
                  ///< fixed-M result of the trials done; the message says by how much)
  cancelled,      ///< stopped through options.cancel: the result covers a prefix of trials
};

/// "completed", "converged", "not_converged", "cancelled".
std::string_view to_string(RunStatus status);

struct MonteCarloResult {
  std::size_t measurand_count = 0;       ///< q
  std::uint64_t trials = 0;              ///< trials in the result (the prefix)
  RunStatus status = RunStatus::completed;
  std::string message;                   ///< human-readable (why not converged etc.)
  std::vector<double> samples;           ///< trial-major, trials × measurand_count
  /// One per measurand (JCGM 101 7.6–7.7 over all `trials`). EMPTY when the run was
  /// cancelled before minimum_sample_count(p) trials were done (then no coverage interval
  /// exists; the message says so). Check `!summaries.empty()`, not `trials > 0`.
  std::vector<MeasurandSummary> summaries;
  std::vector<double> correlation;       ///< q×q row-major (statistics.h); empty with summaries
  double wall_seconds = 0;
  unsigned threads_used = 0;             ///< worker threads of this process
  unsigned ranks = 1;                    ///< processes the trials were spread over
  // ---- adaptive runs only (zero / empty for fixed-M runs) ----
  std::uint64_t block_size = 0;          ///< B
  std::uint64_t blocks = 0;              ///< h: complete blocks run
  /// δ per measurand at the last stopping check (h ≥ 2).
  std::vector<double> numerical_tolerance;
  /// Per measurand, 2·max(s_ȳ, s_u, s_low, s_high) at the last stopping check (7.9.4);
  /// converged means stability[j] ≤ numerical_tolerance[j] for every j.
  std::vector<double> stability;
};

/// Runs trials 0..M−1; trial t gets RandomStream(seed, t). Exceptions thrown by the
/// experiment are rethrown (first by trial index) after all threads stop, naming the trial:
/// as ExperimentError (errors.h) with the original exception nested; likewise a measurand
/// left NaN/±inf (naming trial and measurand). With an error at trial e every trial < e
/// still runs and trials > e are skipped, so the reported trial is the lowest failing one
/// for any thread count. Spread over processes, every process throws the same ExperimentError:
/// the one whose part holds the lowest failing trial rethrows its own, the others repeat that
/// trial and so fail alike (the experiment being a deterministic function of its stream); a
/// failure that is not a trial's (the progress callback threw) reaches the other processes
/// as std::runtime_error naming the process.
/// Throws InvalidInput (nothing run) if the experiment is empty, measurand_count is 0,
/// trials < minimum_sample_count(p) (11 for p = 0.95) or M·q overflows, p ∉ (0, 1), or
/// threads > 1024, or the process group's rank is not below its size. Cost: the
/// experiment's, plus ~40 ns a trial for the engine (docs/performance.md), plus (spread) one
/// gather of the samples, plus the summaries: O(q M log M) (a sort per measurand, measurands
/// in parallel), O(q² M) for the correlation. Memory: 8·q·M bytes of samples.
MonteCarloResult run_monte_carlo(const Experiment& experiment, std::size_t measurand_count,
                                 const MonteCarloOptions& options);
/// As above with one experiment per worker thread, made by `factory` (an empty factory or an
/// empty experiment from it: InvalidInput; an exception from it propagates unchanged).
MonteCarloResult run_monte_carlo(const ExperimentFactory& factory, std::size_t measurand_count,
                                 const MonteCarloOptions& options);

/// Adaptive procedure (JCGM 101 7.9): blocks of block_size trials (block h = trials
/// [h·B, (h+1)·B)) until for every measurand twice the standard deviation of the block
/// estimates of mean, u, and both ends of the probabilistically symmetric interval is ≤ δ
/// (7.9.4 steps); the result pools all trials (7.9.4, last step). Spread over processes, each
/// block is split like a fixed run and every stop decision is process 0's, taken by all. status converged / not_converged
/// (max_trials hit, or — from the third block on — the tolerance out of reach: 2s falls like
/// 1/√h, and when h·(2s/δ)² blocks exceed four times max_trials the run stops at once, the
/// message giving the projected number of trials) / cancelled. options.trials is ignored.
///
/// The standard deviation is the one 7.9.4 prescribes, that *associated with the average* of the h
/// block values: s² = Σ_r (v_r − v̄)² / (h(h − 1)); the first check is after h = 2 blocks.
/// Block statistics come from each block's own B samples (summarize on the block); δ comes
/// from AdaptiveOptions; u for n_dig from all h·B trials (pooled in block order, Chan's
/// update). The next block is started only if it fits in max_trials, so the result never
/// exceeds max_trials. Throws as run_monte_carlo, and InvalidInput if neither a positive
/// finite numerical_tolerance nor significant_digits in 1 … 15 is given, numerical_tolerance
/// is NaN/inf/negative, block_size < minimum_sample_count(p), or max_trials < block size.
MonteCarloResult run_adaptive_monte_carlo(const Experiment& experiment,
                                          std::size_t measurand_count,
                                          const AdaptiveOptions& adaptive,
                                          const MonteCarloOptions& options);
MonteCarloResult run_adaptive_monte_carlo(const ExperimentFactory& factory,
                                          std::size_t measurand_count,
                                          const AdaptiveOptions& adaptive,
                                          const MonteCarloOptions& options);

/// JCGM 101 7.9.4: max(⌈100/(1 − p)⌉, 10 000) (10 000 for p ≤ 0.99). Throws InvalidInput
/// if p ∉ (0, 1).
std::uint64_t default_block_size(double coverage_probability);

/// JCGM 101 7.9.2: δ = ½·10^l where u written to n_dig significant digits is c·10^l (c an
/// integer of n_dig digits, after rounding: 0.0999 to 2 digits is 0.10, l = −2). 0 for u = 0.
/// Throws InvalidInput if u is negative or not finite, or n_dig ∉ [1, 15].
double numerical_tolerance_from_digits(double standard_uncertainty, int significant_digits);

}  // namespace vcmm::uncertainty
