// cli/option_values.cpp — see option_values.h.
#include "option_values.h"

#include "vcmm/geometry/number_field.h"
#include "vcmm/uncertainty/statistics.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace vcmm::cli {

namespace {

/// Parses a whole option value as a double with the text readers' field parser
/// (geometry/number_field.h): empty when it is not a finite number, `problem` then says why.
std::optional<double> option_number(const std::string& text, std::string& problem) {
  double v = 0.0;
  const geometry::NumberFieldStatus status = geometry::parse_number_field(text, v);
  if (status == geometry::NumberFieldStatus::ok) return v;
  problem = geometry::number_field_problem(status, text);
  return std::nullopt;
}

std::string shortest(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace

CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::string problem;
        return option_number(text, problem) ? std::string() : problem;
      },
      "FINITE");
}

CLI::Validator finite_in_range(double min, double max, bool open) {
  return CLI::Validator(
      [min, max, open](std::string& text) -> std::string {
        std::string problem;
        const std::optional<double> v = option_number(text, problem);
        if (!v) return problem;
        if (open ? !(*v > min && *v < max) : !(*v >= min && *v <= max))
          return "must lie in " + std::string(open ? "(" : "[") + shortest(min) + ", " +
                 shortest(max) + (open ? ")" : "]") + "; got '" + text + "'";
        return {};
      },
      "FINITE");
}

CLI::Validator physical_value(const errormodel::PhysicalRange& range, bool open_below) {
  return CLI::Validator(
      [&range, open_below](std::string& text) -> std::string {
        std::string problem;
        const std::optional<double> v = option_number(text, problem);
        if (!v) return problem;
        return open_below ? errormodel::range_problem_above_min(range, *v)
                          : errormodel::range_problem(range, *v);
      },
      std::string(range.unit));
}

CLI::Validator thread_count() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const bool digits =
            !text.empty() && text.size() <= 5 && text.find_first_not_of("0123456789") == std::string::npos;
        if (!digits || std::stoul(text) > max_threads)
          return "must be a whole number of threads from 0 (all cores) to " +
                 std::to_string(max_threads) + "; got '" + text + "'";
        return {};
      },
      "0.." + std::to_string(max_threads));
}

CLI::Validator unsigned_64() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        static const std::string kMax = "18446744073709551615";
        const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
        std::string trimmed = text.substr(std::min(text.find_first_not_of('0'), text.size()));
        if (trimmed.empty()) trimmed = "0";
        if (!digits || trimmed.size() > kMax.size() ||
            (trimmed.size() == kMax.size() && trimmed > kMax))
          return "'" + text + "' is not an unsigned 64-bit integer (0 to " + kMax + ")";
        return {};
      },
      "UINT64");
}

void check_trials_for_coverage(std::uint64_t trials, double coverage) {
  std::uint64_t least = 0;
  try {
    least = uncertainty::minimum_sample_count(coverage);
  } catch (const std::invalid_argument&) {  // beyond 2^62 trials
    throw std::invalid_argument("--coverage " + shortest(coverage) +
                                " needs more than 2^62 trials for a coverage interval: use a "
                                "probability between 1e-6 and 1 - 1e-6");
  }
  if (trials != 0 && trials < least)
    throw std::invalid_argument("--trials must be >= " + std::to_string(least) + " for a " +
                                shortest(100.0 * coverage) +
                                " % coverage interval (JCGM 101 7.7.1); got " +
                                std::to_string(trials));
}

Eigen::Vector3d parse_triple(const std::string& text, const char* option) {
  Eigen::Vector3d v;
  std::size_t start = 0;
  for (int k = 0; k < 3; ++k) {
    const std::size_t comma = text.find(',', start);
    if ((k < 2) != (comma != std::string::npos))
      throw std::invalid_argument(std::string(option) + " needs three comma-separated numbers " +
                                  "X,Y,Z (mm); got '" + text + "'");
    std::string field = text.substr(start, k < 2 ? comma - start : std::string::npos);
    while (!field.empty() && field.front() == ' ') field.erase(0, 1);
    while (!field.empty() && field.back() == ' ') field.pop_back();
    if (!field.empty() && field.front() == '+') field.erase(0, 1);
    const auto r = std::from_chars(field.data(), field.data() + field.size(), v[k]);
    if (field.empty() || r.ec != std::errc() || r.ptr != field.data() + field.size() ||
        !std::isfinite(v[k]))
      throw std::invalid_argument(std::string(option) + ": component " + std::to_string(k + 1) +
                                  " is not a finite number ('" + field + "')");
    if (const std::string problem =
            errormodel::range_problem(errormodel::physical_range::coordinate_mm, v[k]);
        !problem.empty())
      throw std::invalid_argument(std::string(option) + ": component " + std::to_string(k + 1) +
                                  " " + problem);
    start = comma + 1;
  }
  return v;
}

std::optional<double> parse_filter_upr(const std::string& text) {
  if (upper_case(text) == "NONE") return std::nullopt;
  std::string problem;
  const std::optional<double> upr = option_number(text, problem);
  if (!upr || *upr <= 0.0)
    throw std::invalid_argument("--filter-upr must be a positive number of UPR or 'none'; got '" +
                                text + "'");
  return upr;
}

double millimetres_per_unit(const std::string& unit) {
  if (unit == "mm") return 1.0;
  if (unit == "um") return 1e-3;
  if (unit == "in") return 25.4;
  throw std::invalid_argument("--unit must be mm, um or in; got '" + unit + "'");
}

std::string upper_case(std::string text) {
  for (char& c : text) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return text;
}

std::string csv_cell(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += "\"\"";
    else if (c == '\n' || c == '\r') out += ' ';
    else out += c;
  }
  return out + "\"";
}

}  // namespace vcmm::cli
