// cli/run_control.h — long runs on the terminal: a progress bar on stderr (shown once a run
// has taken more than a second) and a clean stop on Ctrl-C (SIGINT sets a flag the Monte Carlo
// engine polls; a second Ctrl-C kills the process as usual).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>

namespace vcmm::cli {

/// Installs the SIGINT handler for its lifetime (restores the previous one on destruction);
/// in an MPI job (cli/processes.h) SIGUSR1 too, which mpirun forwards to every process.
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
  /// The flag SIGINT sets (pass it as MonteCarloOptions::cancel).
  const std::atomic<bool>* flag() const;
  bool interrupted() const;
};

/// When to draw the bar: auto = only when stderr is a terminal.
enum class ProgressMode { automatic, always, never };
ProgressMode progress_mode_from_string(const std::string& text);  // throws std::invalid_argument

/// A one-line progress bar on stderr: "label [#####.....] 52 % 5.2e5/1e6 trials, 12 s left".
class ProgressBar {
 public:
  ProgressBar(std::string label, ProgressMode mode);
  ~ProgressBar();  ///< ends the line if anything was drawn
  void update(std::uint64_t done, std::uint64_t planned);
  void finish();

 private:
  std::string label_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace vcmm::cli

namespace vcmm::cli {

/// Call inside a catch block: prints "vcmm COMMAND: error: ..." for the exception in flight
/// and returns its exit code — the one mapping of exception types to the exit codes of
/// docs/cli.md: 4 for geometry::UndefinedResult (the quantity does not exist for valid input);
/// 3 for invalid input (std::invalid_argument: InvalidInput, InvalidParameter, CampaignError)
/// and for I/O failures (errormodel::OutputError, std::filesystem::filesystem_error,
/// std::ios_base::failure: the message names the path and the OS reason); 1 for anything else
/// (a bug, said so). An uncertainty::ExperimentError (a failed Monte Carlo trial) gets the code
/// of the exception nested in it.
int report_current_exception(const char* command);

/// A library message as the user reads it. The library names the function that refused
/// ("maximum_inscribed_circle: …", STYLE.md: for a programmer calling it); a user of `vcmm`
/// never called that function, so each such name becomes the operation it performs
/// ("MI circle: …", "Monte Carlo: …"). Every message the commands print goes through here.
std::string user_message(const std::string& text);

/// The exit code of one exception, by the rule above (for loops that report per file).
int exit_code_of(const std::exception& e);

/// e.what(), marked as an internal error when exit_code_of(e) is 1.
std::string error_text(const std::exception& e);

}  // namespace vcmm::cli
