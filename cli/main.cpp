// vcmm — command-line front end of the vcmm library (docs/cli.md).
#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>
#include <string>

#include "commands.h"
#include "vcmm/validation/provenance.h"

int main(int argc, char** argv) {
  CLI::App app{"vcmm: exact ISO 12181-2 roundness evaluation and a validated virtual CMM"};
  app.require_subcommand(1);
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
  } catch (const std::exception& e) {
    std::cerr << "vcmm: internal error: " << e.what() << "\n";
    return vcmm::cli::kFailure;
  }
  return exit_code;
}
