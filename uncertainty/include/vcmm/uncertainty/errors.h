// vcmm/uncertainty/errors.h — the exceptions thrown at the public boundary of
// vcmm::uncertainty.
//
// The module knows no metrology and includes no geometry/errormodel header, so it has its own
// "bad input" type; it derives from std::invalid_argument like vcmm::geometry::InvalidInput,
// so a caller that only wants "bad input" catches std::invalid_argument. Messages follow the
// house rule "<function>: <requirement>; <offending value/index>".
#pragma once

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace vcmm::uncertainty {

/// A caller error: empty or non-finite samples, a coverage probability outside (0, 1), zero
/// measurands or trials, too few samples for the requested coverage interval, an empty
/// experiment. The message names the function, the rule broken and the offending value.
class InvalidInput : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// A Monte Carlo trial failed: the experiment threw, or it left a measurand NaN or ±inf (or
/// did not write it: the engine fills each trial's slot with NaN before calling). The run is
/// stopped and this is thrown from run_monte_carlo / run_adaptive_monte_carlo after every
/// worker thread has stopped; it reports the failing trial with the LOWEST index (the same
/// trial for any thread count). When the experiment threw, the original exception is nested:
/// std::rethrow_if_nested(e) rethrows it.
class ExperimentError : public std::runtime_error {
 public:
  static constexpr std::size_t no_measurand = std::numeric_limits<std::size_t>::max();

  ExperimentError(const std::string& message, std::uint64_t trial,
                  std::size_t measurand = no_measurand)
      : std::runtime_error(message), trial_(trial), measurand_(measurand) {}
  /// Index of the failing trial (its RandomStream is RandomStream(seed, trial)).
  std::uint64_t trial() const noexcept { return trial_; }
  /// Index of the non-finite measurand, or no_measurand when the experiment threw.
  std::size_t measurand() const noexcept { return measurand_; }

 private:
  std::uint64_t trial_;
  std::size_t measurand_;
};

}  // namespace vcmm::uncertainty
