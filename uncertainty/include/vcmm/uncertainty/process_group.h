// vcmm/uncertainty/process_group.h — the processes one Monte Carlo run is spread over (e.g. the
// ranks of an MPI job, vcmm::mpi), as the engine sees them: a rank, a size and two collective
// exchanges. The module knows no MPI; MonteCarloOptions::process_group points to an
// implementation, or is null for one process (the default: no exchange at all).
//
// How the engine uses it (monte_carlo.h): every range of trials [b, e) it would run (all M of a
// fixed run, each block of an adaptive one) is cut into size() contiguous parts in rank order
// (trial_part); each process runs its part on its own threads — trial t still draws
// RandomStream(seed, t) — and the parts are gathered in trial order into the same array on
// every process. Summaries and the adaptive stopping rule are then computed from that array, so
// every process holds the same doubles, bit for bit, for any number of processes and threads.
// Before the samples move, the processes exchange a few words per part (trials done, lowest
// failing trial, cancel flag) so that all of them take the same decision: carry on, stop with
// the prefix done (cancel), or throw the same ExperimentError.
//
// Contract of an implementation: every call of a collective below must be made by every
// process of the group, in the same order, with the same sizes; calls come from one thread per
// process (the caller's; the worker threads never call). A failure (e.g. a lost process) may
// throw std::runtime_error or end the job; it must not return partial data.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace vcmm::uncertainty {

class ProcessGroup {
 public:
  virtual ~ProcessGroup() = default;

  /// This process's index, 0 ≤ rank() < size(). Rank 0 reports progress (and, by convention
  /// of the callers, writes the outputs).
  virtual unsigned rank() const = 0;
  /// The number of processes, ≥ 1.
  virtual unsigned size() const = 0;

  /// Collective: `buffer` has the same length on every process; process r has filled
  /// buffer[offsets[r], offsets[r] + counts[r]) (the parts do not overlap). On return every
  /// process holds every part. offsets and counts have size() entries, equal everywhere.
  virtual void all_gather(std::span<double> buffer, std::span<const std::size_t> offsets,
                          std::span<const std::size_t> counts) = 0;

  /// Collective: every process passes `mine` of the same length n; returns the size()·n words
  /// in rank order (process r's at [r·n, (r + 1)·n)).
  virtual std::vector<std::uint64_t> all_gather(std::span<const std::uint64_t> mine) = 0;
};

/// The part [first, last) of the trials [begin, end) that process `rank` of `size` runs:
/// contiguous, in rank order, sizes differing by at most one (the first (end − begin) mod size
/// parts have the extra trial). Throws InvalidInput if size is 0, rank ≥ size or end < begin.
struct TrialPart {
  std::uint64_t first = 0, last = 0;
};
TrialPart trial_part(std::uint64_t begin, std::uint64_t end, unsigned rank, unsigned size);

/// Collective: true on every process iff `flag` is true on process 0 (its decision, taken by
/// all). With a null group: `flag`.
bool decision_of_first(ProcessGroup* group, bool flag);

/// Collective: true on every process iff `flag` is true on at least one. Null group: `flag`.
bool any_process(ProcessGroup* group, bool flag);

}  // namespace vcmm::uncertainty
