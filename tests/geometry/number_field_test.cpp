// parse_number_field / number_field_problem: the one number parser of vcmm's text readers,
// each status with its words; read_text_line: every line end.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "vcmm/geometry/number_field.h"
#include "vcmm/geometry/text_lines.h"

namespace {

using vcmm::geometry::NumberFieldStatus;
using vcmm::geometry::number_field_problem;
using vcmm::geometry::parse_number_field;

NumberFieldStatus status_of(const std::string& text) {
  double v = -7.0;
  const NumberFieldStatus s = parse_number_field(text, v);
  if (s != NumberFieldStatus::ok) {
    EXPECT_EQ(v, -7.0) << text;  // untouched
  }
  return s;
}

TEST(NumberField, EachStatus) {
  double v = 0.0;
  EXPECT_EQ(parse_number_field("+1.5e3", v), NumberFieldStatus::ok);
  EXPECT_EQ(v, 1500.0);
  EXPECT_EQ(parse_number_field("-0", v), NumberFieldStatus::ok);
  EXPECT_EQ(parse_number_field("4.9e-324", v), NumberFieldStatus::ok);  // smallest subnormal
  EXPECT_EQ(status_of(""), NumberFieldStatus::not_a_number);
  EXPECT_EQ(status_of("1.5x"), NumberFieldStatus::not_a_number);
  EXPECT_EQ(status_of("abc"), NumberFieldStatus::not_a_number);
  EXPECT_EQ(status_of("+-1"), NumberFieldStatus::not_a_number);
  EXPECT_EQ(status_of("nan"), NumberFieldStatus::not_finite);
  EXPECT_EQ(status_of("-Infinity"), NumberFieldStatus::not_finite);
  EXPECT_EQ(status_of("1e999"), NumberFieldStatus::overflow);
  EXPECT_EQ(status_of("-1e999"), NumberFieldStatus::overflow);
  EXPECT_EQ(status_of("1e-400"), NumberFieldStatus::underflow);
  EXPECT_EQ(status_of("-2.5e-400"), NumberFieldStatus::underflow);
}

TEST(NumberField, Problems) {
  EXPECT_EQ(number_field_problem(NumberFieldStatus::ok, "1"), "");
  EXPECT_EQ(number_field_problem(NumberFieldStatus::not_a_number, "1.5x"),
            "is not a number ('1.5x')");
  EXPECT_EQ(number_field_problem(NumberFieldStatus::not_finite, "nan"), "is not finite ('nan')");
  EXPECT_EQ(number_field_problem(NumberFieldStatus::overflow, "1e999"),
            "overflows the double range (|x| > 1.8e308): '1e999'");
  EXPECT_EQ(number_field_problem(NumberFieldStatus::underflow, "1e-400"),
            "underflows: non-zero but below the smallest double (4.9e-324): '1e-400'");
}

std::vector<std::string> lines_of(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> out;
  std::string line;
  while (vcmm::geometry::read_text_line(in, line)) out.push_back(line);
  return out;
}

TEST(TextLines, EveryLineEnd) {
  using V = std::vector<std::string>;
  EXPECT_EQ(lines_of("a\nb\n"), (V{"a", "b"}));
  EXPECT_EQ(lines_of("a\r\nb\r\n"), (V{"a", "b"}));
  EXPECT_EQ(lines_of("a\rb\r"), (V{"a", "b"}));
  EXPECT_EQ(lines_of("a\rb"), (V{"a", "b"}));
  EXPECT_EQ(lines_of("a\r\rb\n\nc"), (V{"a", "", "b", "", "c"}));
  EXPECT_EQ(lines_of(""), V{});
  EXPECT_EQ(lines_of("\n"), (V{""}));
}

}  // namespace
