// cli/processes.h — the processes of an MPI job that one `vcmm` command runs in (docs/mpi.md).
// `vcmm-mpi` (built with MPI) sets them in main() when an MPI launcher started it; the
// uncertainty, validate and demo commands spread their Monte Carlo runs over them, and only
// the output process (rank 0) writes files, reports and progress. Everywhere else — the plain
// `vcmm`, or `vcmm-mpi` run alone — there is one process and this changes nothing.
#pragma once

#include <optional>

#include "vcmm/uncertainty/process_group.h"

namespace vcmm::cli {

/// Called once by main() before the command runs: the job's processes and how many of them
/// share this node's cores.
void set_processes(uncertainty::ProcessGroup* group, unsigned processes_on_this_node);

/// The job's processes, or null when this process runs alone.
uncertainty::ProcessGroup* process_group();

/// True where this process writes outputs, reports and progress: rank 0, or alone.
bool is_output_process();

/// --threads as given, or for 0 (all cores) this process's share of the node's cores: the
/// hardware threads divided by the job's processes on this node (at least 1).
unsigned threads_per_process(unsigned requested);

/// The number of processes of the MPI job an MPI launcher (mpirun, mpiexec, srun) started this
/// process in, from the launcher's environment (OMPI_COMM_WORLD_SIZE, PMI_SIZE); 0 when no
/// launcher started it; std::nullopt when one did but the size is not in the environment
/// (PMIx: PMIX_RANK only).
std::optional<unsigned> launcher_process_count();

}  // namespace vcmm::cli
