// MpiSession and the ProcessGroup over MPI_COMM_WORLD (vcmm/mpi/mpi_session.h).
#include "vcmm/mpi/mpi_session.h"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdlib>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace vcmm::mpi {
namespace {

void check(int code, const char* what) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw std::runtime_error(std::string("MPI: ") + what + " failed: " + std::string(text, length));
}

/// Completes a non-blocking collective, testing it every 100 µs instead of MPI's busy wait: a
/// process that finished its part early sleeps while the others compute, so it takes no core
/// from them (cores shared by several processes or other jobs). Costs well under a
/// millisecond per exchange, a few exchanges per run.
void wait_sleeping(MPI_Request& request, const char* what) {
  for (;;) {
    int done = 0;
    check(MPI_Test(&request, &done, MPI_STATUS_IGNORE), what);
    if (done) return;
    std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
}

class WorldGroup final : public uncertainty::ProcessGroup {
 public:
  WorldGroup(unsigned rank, unsigned size) : rank_(rank), size_(size) {}
  unsigned rank() const override { return rank_; }
  unsigned size() const override { return size_; }

  void all_gather(std::span<double> buffer, std::span<const std::size_t> offsets,
                  std::span<const std::size_t> counts) override {
    const bool fits_int = buffer.size() <= static_cast<std::size_t>(INT_MAX);
    if (fits_int) {
      std::vector<int> c(size_), o(size_);
      for (unsigned r = 0; r < size_; ++r) {
        c[r] = static_cast<int>(counts[r]);
        o[r] = static_cast<int>(offsets[r]);
      }
      MPI_Request request;
      check(MPI_Iallgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, buffer.data(), c.data(),
                            o.data(), MPI_DOUBLE, MPI_COMM_WORLD, &request),
            "MPI_Iallgatherv of the samples");
      wait_sleeping(request, "MPI_Iallgatherv of the samples");
      return;
    }
    // More than INT_MAX doubles (16 GiB): each part from its owner, in pieces.
    constexpr std::size_t piece = std::size_t{1} << 30;
    for (unsigned r = 0; r < size_; ++r) {
      for (std::size_t done = 0; done < counts[r]; done += piece) {
        const std::size_t n = std::min(piece, counts[r] - done);
        check(MPI_Bcast(buffer.data() + offsets[r] + done, static_cast<int>(n), MPI_DOUBLE,
                        static_cast<int>(r), MPI_COMM_WORLD),
              "MPI_Bcast of the samples");
      }
    }
  }

  std::vector<std::uint64_t> all_gather(std::span<const std::uint64_t> mine) override {
    std::vector<std::uint64_t> all(mine.size() * size_);
    const int n = static_cast<int>(mine.size());
    MPI_Request request;
    check(MPI_Iallgather(mine.data(), n, MPI_UINT64_T, all.data(), n, MPI_UINT64_T,
                         MPI_COMM_WORLD, &request),
          "MPI_Iallgather of the run status");
    wait_sleeping(request, "MPI_Iallgather of the run status");
    return all;
  }

 private:
  unsigned rank_, size_;
};

}  // namespace

struct MpiSession::State {
  unsigned rank = 0, size = 1, on_node = 1;
  std::unique_ptr<WorldGroup> group;
};

MpiSession::MpiSession(int& argc, char**& argv) : state_(std::make_unique<State>()) {
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (initialised) throw std::runtime_error("MPI: already initialised (one session a process)");
  int provided = MPI_THREAD_SINGLE;
  check(MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  if (provided < MPI_THREAD_FUNNELED) {
    MPI_Finalize();
    throw std::runtime_error("MPI: the library gives no MPI_THREAD_FUNNELED support (got level " +
                             std::to_string(provided) + ")");
  }
  int rank = 0, size = 1, on_node = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  MPI_Comm node;
  if (MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &node) ==
      MPI_SUCCESS) {
    MPI_Comm_size(node, &on_node);
    MPI_Comm_free(&node);
  }
  state_->rank = static_cast<unsigned>(rank);
  state_->size = static_cast<unsigned>(size);
  state_->on_node = static_cast<unsigned>(std::max(1, on_node));
  state_->group = std::make_unique<WorldGroup>(state_->rank, state_->size);
}

MpiSession::~MpiSession() { MPI_Finalize(); }

unsigned MpiSession::rank() const { return state_->rank; }
unsigned MpiSession::size() const { return state_->size; }
unsigned MpiSession::processes_on_this_node() const { return state_->on_node; }
uncertainty::ProcessGroup& MpiSession::group() { return *state_->group; }

void MpiSession::abort(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);  // MPI_Abort does not return; should it, end this process anyway
}

}  // namespace vcmm::mpi
