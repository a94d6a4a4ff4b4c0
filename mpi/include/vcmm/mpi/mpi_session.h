// vcmm/mpi/mpi_session.h — an MPI job (Open MPI, MPICH) as the processes a Monte Carlo run is
// spread over (vcmm/uncertainty/process_group.h). Built only when CMake finds MPI (option
// VCMM_MPI, docs/mpi.md); the rest of vcmm knows no MPI.
//
// Threads: MPI is initialised with MPI_THREAD_FUNNELED — only the thread that created the
// session calls MPI (the engine's collectives run on the caller's thread; its worker threads
// never call MPI).
#pragma once

#include <memory>

#include "vcmm/uncertainty/process_group.h"

namespace vcmm::mpi {

/// MPI_Init_thread … MPI_Finalize for the lifetime of the object; one per process, created
/// before any other thread. Cost: MPI_Init under mpirun ~0.3 s on the 2-core test machine
/// (docs/mpi.md), so a program that may also run alone should only create a session when an MPI
/// launcher started it.
class MpiSession {
 public:
  /// Throws std::runtime_error if MPI is already initialised, or does not give at least
  /// MPI_THREAD_FUNNELED.
  MpiSession(int& argc, char**& argv);
  ~MpiSession();  ///< MPI_Finalize — every process must get here (or call abort)
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  unsigned rank() const;  ///< in MPI_COMM_WORLD
  unsigned size() const;  ///< of MPI_COMM_WORLD
  /// Processes of this job on this node (MPI_COMM_TYPE_SHARED), ≥ 1: they share its cores.
  unsigned processes_on_this_node() const;
  /// MPI_COMM_WORLD as a uncertainty::ProcessGroup: Iallgatherv of the samples in place (in
  /// pieces of ≤ 2³⁰ doubles by broadcasts when a count or offset exceeds MPI's int), Iallgather
  /// of the status words, each completed by MPI_Test every 100 µs: a process waiting for the
  /// others sleeps instead of spinning on a core they need.
  uncertainty::ProcessGroup& group();
  /// MPI_Abort(MPI_COMM_WORLD, code): ends every process of the job at once (none is left
  /// waiting in a collective), and the launcher exits with `code`.
  [[noreturn]] void abort(int code);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace vcmm::mpi
