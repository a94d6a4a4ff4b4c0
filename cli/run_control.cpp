// cli/run_control.cpp — progress bars, Ctrl-C and the exception-to-exit-code mapping of the
// `vcmm` subcommands.
#include "run_control.h"

#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <ios>
#include <iostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "commands.h"
#include "processes.h"
#include "vcmm/errormodel/atomic_file.h"
#include "vcmm/geometry/point.h"
#include "vcmm/uncertainty/errors.h"

namespace vcmm::cli {
namespace {

std::atomic<bool> g_interrupted{false};
using Handler = void (*)(int);
Handler g_previous = SIG_DFL;
Handler g_previous_usr1 = SIG_DFL;

extern "C" void on_sigint(int signal) {
  g_interrupted.store(true);
  std::signal(signal, SIG_DFL);  // a second Ctrl-C ends the process at once
}

}  // namespace

InterruptGuard::InterruptGuard() {
  g_interrupted.store(false);
  g_previous = std::signal(SIGINT, on_sigint);
  // Under mpirun, Ctrl-C ends the job (Open MPI sends SIGTERM, then SIGKILL), but SIGUSR1 sent
  // to mpirun reaches every process: the clean stop there (docs/mpi.md).
  if (process_group() != nullptr) g_previous_usr1 = std::signal(SIGUSR1, on_sigint);
}
InterruptGuard::~InterruptGuard() {
  std::signal(SIGINT, g_previous);
  if (process_group() != nullptr) std::signal(SIGUSR1, g_previous_usr1);
}
const std::atomic<bool>* InterruptGuard::flag() const { return &g_interrupted; }
bool InterruptGuard::interrupted() const { return g_interrupted.load(); }

ProgressMode progress_mode_from_string(const std::string& text) {
  if (text == "auto") return ProgressMode::automatic;
  if (text == "always") return ProgressMode::always;
  if (text == "never") return ProgressMode::never;
  throw std::invalid_argument("--progress must be auto, always or never; got '" + text + "'");
}

ProgressBar::ProgressBar(std::string label, ProgressMode mode)
    : label_(std::move(label)),
      enabled_(mode == ProgressMode::always ||
               (mode == ProgressMode::automatic && ::isatty(STDERR_FILENO) == 1)),
      start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(std::uint64_t done, std::uint64_t planned) {
  if (!enabled_ || planned == 0) return;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (elapsed < 1.0) return;  // short runs stay quiet
  const double f = static_cast<double>(done) / static_cast<double>(planned);
  constexpr int width = 30;
  const int filled = static_cast<int>(f * width);
  char bar[width + 1];
  for (int i = 0; i < width; ++i) bar[i] = i < filled ? '#' : '.';
  bar[width] = '\0';
  const double left = f > 0.0 ? elapsed * (1.0 - f) / f : 0.0;
  std::fprintf(stderr, "\r%s [%s] %3d %% %llu/%llu trials, %.0f s left ", label_.c_str(), bar,
               static_cast<int>(f * 100.0), static_cast<unsigned long long>(done),
               static_cast<unsigned long long>(planned), left);
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (drawn_) {
    std::fputc('\n', stderr);
    drawn_ = false;
  }
}

}  // namespace vcmm::cli

namespace vcmm::cli {

namespace {

/// Library functions whose name can open a message that reaches a user, and the operation
/// the user asked for instead.
constexpr std::pair<std::string_view, std::string_view> kOperations[] = {
    {"least_squares_circle", "LS circle"},
    {"minimum_zone_circle", "MZ circle"},
    {"minimum_zone_overlay", "MZ circle"},
    {"make_minimum_zone_result", "MZ circle"},
    {"make_cocircular_result", "reference circle"},
    {"exact_circumcircle", "reference circle"},
    {"maximum_inscribed_circle", "MI circle"},
    {"minimum_circumscribed_circle", "MC circle"},
    {"gaussian_filtered_profile", "Gaussian filter (ISO 16610-21)"},
    {"gaussian_filter_closed", "Gaussian filter (ISO 16610-21)"},
    {"gaussian_filtered_open_profile", "Gaussian filter (ISO 16610-21, open profile)"},
    {"angular_coverage", "angular coverage"},
    {"roundness_parameters", "roundness parameters"},
    {"check_claimed_circle", "claim check"},
    {"run_monte_carlo", "Monte Carlo"},
    {"run_adaptive_monte_carlo", "adaptive Monte Carlo"},
    {"minimum_sample_count", "Monte Carlo"},
    {"default_block_size", "adaptive Monte Carlo"},
    {"summarize_measurand", "Monte Carlo statistics"},
    {"correct_bias", "bias correction"},
    {"correct_bias_at_surrogate", "bias correction (shrinkage treatment)"},
    {"estimate_harmonic_shrinkage", "shrinkage treatment"},
    {"evaluate_ring", "ring evaluation"},
    {"simulate", "virtual CMM"},
    {"simulate_corrected", "virtual CMM"},
    {"correct", "correction of systematic errors"},
    {"tip_errors", "kinematic errors"},
    {"ring_gauge_measurement", "ring gauge"},
    {"run_campaign", "campaign"},
    {"make_demo_world", "demo world"},
    {"evaluate_roundness_reference", "roundness reference"},
    {"reference_roundness", "roundness reference"},
    {"evaluate_diameter_reference", "diameter reference"},
    {"reference_diameter", "diameter reference"},
    {"en_score", "E_n"},
    {"en_score_expanded", "E_n"},
    {"zeta_score", "zeta score"},
    {"write_measurement_csv_file", "measurement file"},
    {"estimate_kinematic_errors", "hole-plate fit"},
    {"express_in_gauge", "hole-plate fit"},
    {"kinematics_json_section", "kinematics section"},
    {"error_function_value", "kinematic errors"},
    {"correlation_matrix", "kinematics correlation"},
    {"characterize_probe_sphere", "probe characterisation (sphere)"},
    {"probe_section_json", "probe section"},
    {"repeated_scan_noise", "noise from a repeated scan"},
    {"scanning_noise", "scanning noise"},
    {"touch_trigger_noise", "touch-trigger noise"},
    {"reference_deviation_mm", "reference profile"},
    {"high_pass_noise_factor", "noise characterisation"},
    {"sigma_coverage_factor", "noise characterisation"},
    {"noise_section_json", "noise section"},
    {"shrinkage_max_order", "shrinkage treatment"},
    {"numerical_tolerance_from_digits", "adaptive Monte Carlo"},
    {"standard_normal_quantile", "coverage factor"},
};

bool is_name_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '.';
}

}  // namespace

std::string user_message(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  std::size_t i = 0;
  while (i < text.size()) {
    bool replaced = false;
    if (i == 0 || !is_name_char(text[i - 1])) {
      for (const auto& [name, operation] : kOperations) {
        if (text.compare(i, name.size(), name) == 0 &&
            text.compare(i + name.size(), 2, ": ") == 0) {
          out.append(operation).append(": ");
          i += name.size() + 2;
          replaced = true;
          break;
        }
      }
    }
    if (!replaced) out += text[i++];
  }
  return out;
}

int exit_code_of(const std::exception& e) {
  if (dynamic_cast<const geometry::UndefinedResult*>(&e)) return kUndefined;
  if (dynamic_cast<const std::invalid_argument*>(&e)) return kInvalidInput;  // bad input values
  if (dynamic_cast<const errormodel::OutputError*>(&e)) return kInvalidInput;  // an output path
  if (dynamic_cast<const std::filesystem::filesystem_error*>(&e)) return kInvalidInput;
  if (dynamic_cast<const std::ios_base::failure*>(&e)) return kInvalidInput;
  return kFailure;
}

std::string error_text(const std::exception& e) {
  return exit_code_of(e) == kFailure
             ? std::string("internal error (a bug: please report it with the input): ") + e.what()
             : user_message(e.what());
}

int report_current_exception(const char* command) {
  const std::string prefix = std::string("vcmm ") + command + ": error: ";
  try {
    throw;
  } catch (const uncertainty::ExperimentError& e) {
    // A Monte Carlo trial failed: the code is that of the exception inside it (whose words
    // the message already holds).
    int code = kFailure;
    try {
      std::rethrow_if_nested(e);
    } catch (const std::exception& inner) {
      code = exit_code_of(inner);
    } catch (...) {
    }
    std::cerr << prefix << user_message(e.what())
              << (code == kFailure ? " (internal error, a bug: please report it)" : "") << "\n";
    return code;
  } catch (const std::exception& e) {
    const int code = exit_code_of(e);
    std::cerr << prefix << user_message(e.what())
              << (code == kFailure ? " (internal error, a bug: please report it)" : "") << "\n";
    return code;
  } catch (...) {
    std::cerr << prefix << "unknown exception (internal error, a bug: please report it)\n";
    return kFailure;
  }
}

}  // namespace vcmm::cli
