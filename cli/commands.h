// cli/commands.h — the subcommands of the `vcmm` command. The CLI holds no logic of its own:
// each command parses options, calls the library and formats the result.
#pragma once

#include <CLI/CLI.hpp>

namespace vcmm::cli {

/// Exit codes shared by all commands (docs/cli.md).
enum ExitCode : int {
  kOk = 0,
  kFailure = 1,        ///< unexpected internal error
  kUsage = 2,          ///< bad command line
  kInvalidInput = 3,   ///< input file or values rejected (message names file/line/value)
  kUndefined = 4,      ///< valid input, but the quantity does not exist for it
  kClaimFails = 5,     ///< `vcmm check`: the claimed circle is infeasible or not optimal
  kInterrupted = 130,  ///< stopped by Ctrl-C (128 + SIGINT, the shell convention)
};

/// Registers `vcmm roundness`; the callback stores its exit code in `*exit_code`.
void add_roundness_command(CLI::App& app, int* exit_code);

/// Registers `vcmm check` (another program's reference circle against the exact one).
void add_check_command(CLI::App& app, int* exit_code);

/// Registers `vcmm simulate` (a ring-gauge measurement on the virtual CMM).
void add_simulate_command(CLI::App& app, int* exit_code);

/// Registers `vcmm uncertainty` (Monte Carlo uncertainty of one ring measurement).
void add_uncertainty_command(CLI::App& app, int* exit_code);

/// Registers `vcmm validate` (a validation campaign) and `vcmm demo` (the synthetic world).
void add_validate_command(CLI::App& app, int* exit_code);
void add_demo_command(CLI::App& app, int* exit_code);

/// Registers `vcmm characterize` and its subcommands (hole-plate, sphere, noise), each
/// writing one section of the digital-model JSON.
void add_characterize_command(CLI::App& app, int* exit_code);
void add_characterize_hole_plate_command(CLI::App& characterize, int* exit_code);
void add_characterize_sphere_command(CLI::App& characterize, int* exit_code);
void add_characterize_noise_command(CLI::App& characterize, int* exit_code);

/// Registers `vcmm report` (runs python/vcmm_report.py with a Python that has matplotlib).
void add_report_command(CLI::App& app, int* exit_code);

}  // namespace vcmm::cli
