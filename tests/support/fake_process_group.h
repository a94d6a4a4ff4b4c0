// tests/support/fake_process_group.h — N "processes" of a uncertainty::ProcessGroup simulated
// by N threads of the test (no MPI): each thread gets its own group object over one shared
// exchange. The exchange checks the ProcessGroup contract (every process makes the same
// collective calls, in the same order, with the same sizes) and records a violation instead of
// deadlocking where it can; a test that breaks the contract in a way that would hang real MPI
// (one process skips a collective) hangs here too — CTest's timeout catches it.
#pragma once

#include <algorithm>
#include <barrier>
#include <cstdint>
#include <cstring>
#include <exception>
#include <functional>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "vcmm/uncertainty/process_group.h"

namespace vcmm::test {

class FakeExchange {
 public:
  explicit FakeExchange(unsigned size)
      : size_(size), barrier_(static_cast<std::ptrdiff_t>(size)), doubles_(size), words_(size),
        shapes_(size) {}

  unsigned size() const { return size_; }
  /// Collective calls made by process 0 so far.
  std::uint64_t collectives() const { return collectives_; }
  /// Contract violations seen ("" when none).
  std::string violations() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return violations_;
  }

  void all_gather(unsigned rank, std::span<double> buffer, std::span<const std::size_t> offsets,
                  std::span<const std::size_t> counts) {
    doubles_[rank] = buffer.data();
    shapes_[rank] = {1, buffer.size()};
    shapes_[rank].insert(shapes_[rank].end(), offsets.begin(), offsets.end());
    shapes_[rank].insert(shapes_[rank].end(), counts.begin(), counts.end());
    barrier_.arrive_and_wait();
    check_same_shape(rank);
    for (unsigned r = 0; r < size_; ++r) {
      if (r == rank || offsets.size() != size_ || counts.size() != size_) continue;
      std::copy_n(doubles_[r] + offsets[r], counts[r], buffer.data() + offsets[r]);
    }
    if (rank == 0) ++collectives_;
    barrier_.arrive_and_wait();  // no buffer changes before every process has copied
  }

  std::vector<std::uint64_t> all_gather(unsigned rank, std::span<const std::uint64_t> mine) {
    words_[rank].assign(mine.begin(), mine.end());
    shapes_[rank] = {2, mine.size()};
    barrier_.arrive_and_wait();
    check_same_shape(rank);
    std::vector<std::uint64_t> all;
    for (unsigned r = 0; r < size_; ++r) all.insert(all.end(), words_[r].begin(), words_[r].end());
    if (rank == 0) ++collectives_;
    barrier_.arrive_and_wait();
    return all;
  }

 private:
  void check_same_shape(unsigned rank) {
    if (rank != 0) return;
    for (unsigned r = 1; r < size_; ++r) {
      if (shapes_[r] != shapes_[0]) {
        std::lock_guard<std::mutex> lock(mutex_);
        violations_ += "collective " + std::to_string(collectives_) + ": process " +
                       std::to_string(r) + " made a different call than process 0; ";
      }
    }
  }

  unsigned size_;
  std::barrier<> barrier_;
  std::vector<double*> doubles_;
  std::vector<std::vector<std::uint64_t>> words_;
  std::vector<std::vector<std::size_t>> shapes_;  // kind, length, then offsets and counts
  std::uint64_t collectives_ = 0;
  mutable std::mutex mutex_;
  std::string violations_;
};

class FakeProcessGroup final : public uncertainty::ProcessGroup {
 public:
  FakeProcessGroup(FakeExchange& exchange, unsigned rank) : exchange_(exchange), rank_(rank) {}
  unsigned rank() const override { return rank_; }
  unsigned size() const override { return exchange_.size(); }
  void all_gather(std::span<double> buffer, std::span<const std::size_t> offsets,
                  std::span<const std::size_t> counts) override {
    exchange_.all_gather(rank_, buffer, offsets, counts);
  }
  std::vector<std::uint64_t> all_gather(std::span<const std::uint64_t> mine) override {
    return exchange_.all_gather(rank_, mine);
  }

 private:
  FakeExchange& exchange_;
  unsigned rank_;
};

/// What one simulated process returned or threw.
template <class R>
struct ProcessOutcome {
  R value{};
  std::exception_ptr error;
};

/// Runs body(group) on `size` threads, one per simulated process, and returns each one's
/// outcome in rank order; `violations`, if given, receives the contract violations seen.
template <class R>
std::vector<ProcessOutcome<R>> run_as_processes(
    unsigned size, const std::function<R(uncertainty::ProcessGroup&)>& body,
    std::string* violations = nullptr) {
  FakeExchange exchange(size);
  std::vector<ProcessOutcome<R>> out(size);
  std::vector<std::thread> threads;
  for (unsigned r = 0; r < size; ++r) {
    threads.emplace_back([&, r] {
      FakeProcessGroup group(exchange, r);
      try {
        out[r].value = body(group);
      } catch (...) {
        out[r].error = std::current_exception();
      }
    });
  }
  for (std::thread& t : threads) t.join();
  if (violations != nullptr) *violations = exchange.violations();
  return out;
}

/// Bitwise equality of two arrays of doubles (== would call −0 and +0 equal).
inline bool bit_identical(std::span<const double> a, std::span<const double> b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

}  // namespace vcmm::test
