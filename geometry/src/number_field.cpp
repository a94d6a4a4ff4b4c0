// One number field of a text file (number_field.h).
#include "vcmm/geometry/number_field.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <system_error>

namespace vcmm::geometry {

NumberFieldStatus parse_number_field(std::string_view field, double& value) {
  if (field.empty()) return NumberFieldStatus::not_a_number;
  if (field.front() == '+') {  // one '+' before a digit or '.': from_chars takes no sign but '-'
    field.remove_prefix(1);
    if (field.empty() || field.front() == '+' || field.front() == '-')
      return NumberFieldStatus::not_a_number;
  }
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
  if (ptr != field.data() + field.size() || ec == std::errc::invalid_argument)
    return NumberFieldStatus::not_a_number;
  if (ec == std::errc::result_out_of_range) {
    // from_chars leaves the value alone here; strtod tells overflow (±HUGE_VAL) from
    // underflow (a result at or below the smallest normal double).
    const std::string text(field);
    const double r = std::strtod(text.c_str(), nullptr);
    return std::abs(r) < 1.0 ? NumberFieldStatus::underflow : NumberFieldStatus::overflow;
  }
  if (ec != std::errc()) return NumberFieldStatus::not_a_number;
  if (!std::isfinite(v)) return NumberFieldStatus::not_finite;
  value = v;
  return NumberFieldStatus::ok;
}

std::string number_field_problem(NumberFieldStatus status, std::string_view field) {
  std::string quoted;  // built by append: GCC 12 warns (-Wrestrict) on "'" + string + "'"
  quoted.reserve(field.size() + 2);
  quoted.append(1, '\'').append(field).append(1, '\'');
  switch (status) {
    case NumberFieldStatus::ok:
      return {};
    case NumberFieldStatus::not_a_number:
      return "is not a number (" + quoted + ")";
    case NumberFieldStatus::not_finite:
      return "is not finite (" + quoted + ")";
    case NumberFieldStatus::overflow:
      return "overflows the double range (|x| > 1.8e308): " + quoted;
    case NumberFieldStatus::underflow:
      return "underflows: non-zero but below the smallest double (4.9e-324): " + quoted;
  }
  return {};
}

}  // namespace vcmm::geometry
