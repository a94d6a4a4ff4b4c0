// vcmm — command-line front end of the vcmm library (docs/cli.md).
#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>
#include <string>

#include "commands.h"
#include "run_control.h"
#include "vcmm/validation/provenance.h"

int main(int argc, char** argv) {
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
