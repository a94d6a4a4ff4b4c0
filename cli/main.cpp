// vcmm — command-line front end of the vcmm library (docs/cli.md).
//
// Two builds of this file: `vcmm` (static PIE, no MPI: a plain start costs ~2 ms, and the
// dynamic loading of an MPI library would add ~2 ms more) and, when CMake finds MPI,
// `vcmm-mpi` (VCMM_CLI_WITH_MPI). Started by an MPI launcher (`mpirun -np N vcmm …`), the plain
// `vcmm` hands over to `vcmm-mpi` beside it, which spreads the Monte Carlo runs over the job's
// processes (docs/mpi.md).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

#include "commands.h"
#include "processes.h"
#include "run_control.h"
#include "vcmm/validation/provenance.h"

#ifdef VCMM_CLI_WITH_MPI
#include <chrono>
#include <optional>
#include <thread>

#include "vcmm/mpi/mpi_session.h"
#else
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <optional>
#endif

namespace {

int run_command(int argc, char** argv) {
  CLI::App app{"vcmm: exact ISO 12181-2 roundness evaluation and a validated virtual CMM"};
  app.require_subcommand(1);
  app.footer(
      "Exit codes (every subcommand; docs/cli.md): 0 success; 1 internal error (a bug); 2 bad\n"
      "command line or option value; 3 invalid input file or I/O failure (the message names\n"
      "the file, line or key, or the path and the OS reason); 4 result undefined for valid\n"
      "input; 5 `check`: a claim is not optimal; 130 interrupted (Ctrl-C).");
  app.set_version_flag("--version", "vcmm " + std::string(vcmm::validation::vcmm_version()) +
                                        " (" + std::string(vcmm::validation::vcmm_revision()) +
                                        ")\nlicence: GPL-3.0-or-later (LICENSE)");
  int exit_code = vcmm::cli::kOk;
  vcmm::cli::add_roundness_command(app, &exit_code);
  vcmm::cli::add_check_command(app, &exit_code);
  vcmm::cli::add_simulate_command(app, &exit_code);
  vcmm::cli::add_uncertainty_command(app, &exit_code);
  vcmm::cli::add_validate_command(app, &exit_code);
  vcmm::cli::add_demo_command(app, &exit_code);
  vcmm::cli::add_characterize_command(app, &exit_code);
  vcmm::cli::add_report_command(app, &exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : vcmm::cli::kUsage;
  } catch (const std::exception&) {  // escaped a command: mapped like every other error
    const auto used = app.get_subcommands();
    const std::string name = used.empty() ? std::string("(no command)") : used.front()->get_name();
    return vcmm::cli::report_current_exception(name.c_str());
  }
  return exit_code;
}

}  // namespace

#ifdef VCMM_CLI_WITH_MPI

int main(int argc, char** argv) {
  // MPI only when a launcher started this process: MPI_Init alone (singleton) costs ~0.3 s.
  const std::optional<unsigned> launched = vcmm::cli::launcher_process_count();
  std::optional<vcmm::mpi::MpiSession> session;
  if (!launched || *launched > 0) {
    try {
      session.emplace(argc, argv);
    } catch (const std::exception& e) {
      std::cerr << "vcmm: error: " << e.what() << "\n";
      return vcmm::cli::kFailure;
    }
    if (session->size() > 1)
      vcmm::cli::set_processes(&session->group(), session->processes_on_this_node());
  }
  const int code = run_command(argc, argv);
  if (session && session->size() > 1 && code != vcmm::cli::kOk &&
      code != vcmm::cli::kInterrupted) {  // a stop (SIGUSR1) is agreed by all: they all end
    // Another process may wait in a collective this one will never enter (e.g. only rank 0
    // writes, and its write failed): end the whole job now, with this exit code.
    // Rank 0 aborts at once; the others wait a moment first, so that when every process
    // failed alike (a bad input) the job ends by rank 0's abort alone.
    std::cout.flush();
    std::fflush(nullptr);
    if (session->rank() != 0) std::this_thread::sleep_for(std::chrono::milliseconds(500));
    session->abort(code);
  }
  return code;  // ~MpiSession: MPI_Finalize
}

#else

int main(int argc, char** argv) {
  const std::optional<unsigned> launched = vcmm::cli::launcher_process_count();
  if (!launched || *launched > 1) {
    // One of several processes of an MPI job: hand over to the MPI build beside this one.
    std::string why = "this vcmm was built without MPI";
#ifdef VCMM_MPI_COMMAND
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    const std::filesystem::path mpi_command =
        (ec ? std::filesystem::path(argv[0]).parent_path() : self.parent_path()) / VCMM_MPI_COMMAND;
    ::execv(mpi_command.c_str(), argv);  // returns only if it failed
    why = "cannot start " + mpi_command.string() + ": " + std::strerror(errno);
#endif
    if (launched) {
      std::cerr << "vcmm: error: started by an MPI launcher as one of " << *launched
                << " processes, but " << why
                << ": each would run the whole computation. Build vcmm with MPI (docs/mpi.md) "
                   "or run it without mpirun.\n";
      return vcmm::cli::kInvalidInput;
    }
    // PMIx without a size in the environment: cannot tell; run alone as before.
  }
  return run_command(argc, argv);
}

#endif
