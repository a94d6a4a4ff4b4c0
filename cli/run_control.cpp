// cli/run_control.cpp — progress bars, Ctrl-C and the exception-to-exit-code mapping of the
// `vcmm` subcommands.
#include "run_control.h"

#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <exception>
#include <iostream>
#include <stdexcept>
#include <string>

#include "commands.h"
#include "vcmm/errormodel/atomic_file.h"
#include "vcmm/uncertainty/errors.h"

namespace vcmm::cli {
namespace {

std::atomic<bool> g_interrupted{false};
using Handler = void (*)(int);
Handler g_previous = SIG_DFL;

extern "C" void on_sigint(int) {
  g_interrupted.store(true);
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the process at once
}

}  // namespace

InterruptGuard::InterruptGuard() {
  g_interrupted.store(false);
  g_previous = std::signal(SIGINT, on_sigint);
}
InterruptGuard::~InterruptGuard() { std::signal(SIGINT, g_previous); }
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

int report_current_exception(const char* command) {
  const std::string prefix = std::string("vcmm ") + command + ": error: ";
  try {
    throw;
  } catch (const uncertainty::ExperimentError& e) {
    try {
      std::rethrow_if_nested(e);
    } catch (const std::invalid_argument& inner) {
      std::cerr << prefix << e.what() << ": " << inner.what() << "\n";
      return kInvalidInput;
    } catch (const std::exception& inner) {
      std::cerr << prefix << e.what() << ": " << inner.what() << "\n";
      return kFailure;
    }
    std::cerr << prefix << e.what() << "\n";
    return kFailure;
  } catch (const std::invalid_argument& e) {
    std::cerr << prefix << e.what() << "\n";
    return kInvalidInput;
  } catch (const errormodel::OutputError& e) {  // a path the user gave cannot be written
    std::cerr << prefix << e.what() << "\n";
    return kInvalidInput;
  } catch (const std::exception& e) {
    std::cerr << prefix << e.what() << "\n";
    return kFailure;
  }
}

}  // namespace vcmm::cli
