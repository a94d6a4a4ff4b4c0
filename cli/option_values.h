// cli/option_values.h — the option-value parsers and text helpers every `vcmm` subcommand
// shares (one spelling rule for option values: STYLE.md, "Where things live").
#pragma once

#include <CLI/CLI.hpp>
#include <Eigen/Core>

#include "vcmm/errormodel/physical_ranges.h"

#include <cstdint>
#include <optional>
#include <string>

namespace vcmm::cli {

/// Option check: a finite number (CLI11's Range and PositiveNumber let "nan" through, and
/// "inf" through an open upper end). Combine with a range: ->check(finite_number())->check(...).
CLI::Validator finite_number();

/// Option check: a finite number in [min, max] (its unit in the message: "--coverage must lie
/// in (0, 1)"). `open` excludes both ends. NaN and ±inf are refused.
CLI::Validator finite_in_range(double min, double max, bool open = false);

/// Option check: a value in a physical range of errormodel/physical_ranges.h ("--temperature:
/// must lie in [-50, 100] °C (…; kelvin given? …)"). NaN and ±inf are refused.
CLI::Validator physical_value(const errormodel::PhysicalRange& range, bool open_below = false);

/// Most worker threads an option may ask for (0 = all cores): far above any machine, and low
/// enough that a typo (5000, -1 read as 2³²−1) is refused instead of spawning thousands.
inline constexpr unsigned max_threads = 1024;

/// Option check: `--threads` in 0 … max_threads.
CLI::Validator thread_count();

/// `--trials M` with `--coverage P`: M must reach the JCGM 101 7.7.1 minimum for P (M ≥
/// minimum_sample_count(P); M = 0: adaptive, only P is checked). Throws std::invalid_argument
/// naming the options and the minimum.
void check_trials_for_coverage(std::uint64_t trials, double coverage);

/// Option check: an unsigned 64-bit integer written in decimal digits (0 … 18446744073709551615).
/// CLI11 alone wraps "-1" and saturates 2⁶⁴ to 2⁶⁴ − 1; seeds must be what they say.
CLI::Validator unsigned_64();

/// "X,Y,Z" → three finite doubles (mm), each a coordinate in a CMM volume
/// (physical_range::coordinate_mm); throws std::invalid_argument naming the option.
Eigen::Vector3d parse_triple(const std::string& text, const char* option);

/// `--filter-upr` values: a finite number of UPR > 0, or "none" (any case) for unfiltered.
/// Throws std::invalid_argument with the option and the value otherwise.
std::optional<double> parse_filter_upr(const std::string& text);

/// `--unit` values of input coordinates: "mm" → 1, "um" → 1e-3, "in" → 25.4 (mm per unit).
/// Throws std::invalid_argument otherwise.
double millimetres_per_unit(const std::string& unit);

/// ASCII upper case (reference-circle names are accepted in any case).
std::string upper_case(std::string text);

/// A CSV field: quoted (with doubled quotes) when it holds a comma, a quote or a line break;
/// line breaks become spaces.
std::string csv_cell(const std::string& text);

}  // namespace vcmm::cli
