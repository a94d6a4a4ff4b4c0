// internal/csv_fields.h — the field rules shared by the CSV readers of vcmm::geometry
// (docs/formats.md): trimming, splitting a line on ',' / ';' or on runs of blanks and tabs,
// parsing a field as a finite double (number_field.h). Used by point_io.cpp and roundness_profile.cpp. Not public
// API.
#pragma once

#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "vcmm/geometry/number_field.h"

namespace vcmm::geometry::internal {

/// `s` without leading and trailing blanks (space, tab, CR, FF, VT).
inline std::string_view trim_blanks(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\f\v");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\f\v");
  return s.substr(b, e - b + 1);
}

/// The fields of a (comment-free, trimmed) line: split on ',' or ';' when the line has one
/// (fields trimmed; empty fields kept, so "1,,2" has three), else on runs of blanks/tabs.
inline std::vector<std::string_view> split_csv_fields(std::string_view s) {
  std::vector<std::string_view> out;
  if (s.find_first_of(",;") != std::string_view::npos) {
    std::size_t start = 0;
    while (true) {
      const auto pos = s.find_first_of(",;", start);
      out.push_back(
          trim_blanks(s.substr(start, pos == std::string_view::npos ? s.npos : pos - start)));
      if (pos == std::string_view::npos) break;
      start = pos + 1;
    }
    return out;
  }
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
    if (i >= s.size()) break;
    std::size_t j = i;
    while (j < s.size() && s[j] != ' ' && s[j] != '\t') ++j;
    out.push_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

using FieldStatus = NumberFieldStatus;

/// Parses a whole field as a double (number_field.h).
inline FieldStatus parse_double_field(std::string_view f, double& value) {
  return parse_number_field(f, value);
}

/// ASCII lower case.
inline std::string ascii_lower(std::string_view s) {
  std::string out(s);
  for (char& ch : out)
    if (ch >= 'A' && ch <= 'Z') ch = static_cast<char>(ch - 'A' + 'a');
  return out;
}

}  // namespace vcmm::geometry::internal
