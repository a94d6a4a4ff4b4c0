// cli/processes.cpp — the processes of an MPI job (cli/processes.h).
#include "processes.h"

#include <algorithm>
#include <cstdlib>
#include <string>
#include <thread>

namespace vcmm::cli {
namespace {

uncertainty::ProcessGroup* g_group = nullptr;
unsigned g_on_node = 1;

/// A positive count in environment variable `name`, 0 if unset or not a count.
unsigned env_count(const char* name) {
  const char* text = std::getenv(name);
  if (text == nullptr) return 0;
  try {
    std::size_t used = 0;
    const unsigned long v = std::stoul(text, &used);
    return used == std::string(text).size() && v > 0 && v < 1'000'000 ? static_cast<unsigned>(v)
                                                                       : 0;
  } catch (const std::exception&) {
    return 0;
  }
}

}  // namespace

void set_processes(uncertainty::ProcessGroup* group, unsigned processes_on_this_node) {
  g_group = group;
  g_on_node = std::max(1u, processes_on_this_node);
}

uncertainty::ProcessGroup* process_group() { return g_group; }

bool is_output_process() { return g_group == nullptr || g_group->rank() == 0; }

unsigned threads_per_process(unsigned requested) {
  if (requested != 0 || g_group == nullptr) return requested;
  return std::max(1u, std::thread::hardware_concurrency() / g_on_node);
}

std::optional<unsigned> launcher_process_count() {
  // Open MPI's mpirun (ORTE/PRRTE), then the PMI of MPICH's Hydra and of Slurm's srun.
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    if (const unsigned n = env_count(name)) return n;
  }
  if (std::getenv("PMIX_RANK") != nullptr || std::getenv("PMI_RANK") != nullptr)
    return std::nullopt;
  return 0;
}

}  // namespace vcmm::cli
