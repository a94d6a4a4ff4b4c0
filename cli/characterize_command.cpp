// cli/characterize_command.cpp — `vcmm characterize`: the group of commands that estimate
// the digital model's parameters from calibration measurements (docs/characterization.md).
#include "commands.h"

namespace vcmm::cli {

void add_characterize_command(CLI::App& app, int* exit_code) {
  CLI::App* group = app.add_subcommand(
      "characterize",
      "Estimate a section of the digital model from calibration measurements");
  group->require_subcommand(1);
  add_characterize_hole_plate_command(*group, exit_code);
  add_characterize_sphere_command(*group, exit_code);
  add_characterize_noise_command(*group, exit_code);
}

}  // namespace vcmm::cli
