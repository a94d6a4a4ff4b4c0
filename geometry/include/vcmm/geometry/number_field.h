// vcmm/geometry/number_field.h — one number field of a text file (a CSV cell, a metadata
// value): the single parser every vcmm text reader uses, so "1e-400", "1e999", "nan" and
// "1.5x" get the same verdict and the same words in every file format.
#pragma once

#include <string>
#include <string_view>

namespace vcmm::geometry {

enum class NumberFieldStatus {
  ok,
  not_a_number,  ///< empty, or not a number in full ("abc", "1.5x")
  not_finite,    ///< "nan", "inf", "infinity" (any case)
  overflow,      ///< finite as written but beyond the double range ("1e999")
  underflow,     ///< non-zero as written but below the smallest double ("1e-400")
};

/// Parses the whole of `field` as a double (std::from_chars rules; an optional leading '+').
/// `value` is set only when the status is ok. Never throws.
NumberFieldStatus parse_number_field(std::string_view field, double& value);

/// The problem as a phrase to follow the field's name: "is not a number ('1.5x')", "is not
/// finite ('nan')", "overflows the double range (|x| > 1.8e308): '1e999'", "underflows: non-zero
/// but below the smallest double (4.9e-324): '1e-400'". Empty for ok.
std::string number_field_problem(NumberFieldStatus status, std::string_view field);

}  // namespace vcmm::geometry
