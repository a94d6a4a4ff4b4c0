// internal/csv_fields.h — the field rules shared by the CSV readers of vcmm::geometry
// (docs/formats.md): trimming, splitting a line on ',' / ';' or on runs of blanks and tabs,
// parsing a field as a finite double (number_field.h). Used by point_io.cpp and roundness_profile.cpp. Not public
// API.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "vcmm/geometry/number_field.h"

namespace vcmm::geometry::internal {

/// Blank: space, tab, CR, FF, VT.
inline bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

/// `s` without leading and trailing blanks (space, tab, CR, FF, VT). Plain loops: a profile
/// has thousands of short lines, and find_first_not_of costs a memchr per character.
inline std::string_view trim_blanks(std::string_view s) {
  std::size_t b = 0, e = s.size();
  while (b < e && is_blank(s[b])) ++b;
  while (e > b && is_blank(s[e - 1])) --e;
  return s.substr(b, e - b);
}

/// The fields of a (comment-free, trimmed) line into `out` (cleared first; reuse it across
/// lines to avoid an allocation per line): split on ',' or ';' when the line has one (fields
/// trimmed; empty fields kept, so "1,,2" has three), else on runs of blanks/tabs.
inline void split_csv_fields(std::string_view s, std::vector<std::string_view>& out) {
  out.clear();
  bool separated = false;
  for (const char c : s) {
    if (c == ',' || c == ';') {
      separated = true;
      break;
    }
  }
  if (separated) {
    std::size_t start = 0;
    for (std::size_t i = 0; i <= s.size(); ++i) {
      if (i == s.size() || s[i] == ',' || s[i] == ';') {
        out.push_back(trim_blanks(s.substr(start, i - start)));
        start = i + 1;
      }
    }
    return;
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
}

inline std::vector<std::string_view> split_csv_fields(std::string_view s) {
  std::vector<std::string_view> out;
  split_csv_fields(s, out);
  return out;
}

/// The lines of a whole text, whatever their ends: "\n", "\r\n" or a lone "\r" (as
/// text_lines.h's read_text_line; a final line without an end counts). Calls
/// `line(text_of_line)` for each, in order, without its end.
template <class OnLine>
void for_each_line(std::string_view text, OnLine line) {
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = start;
    while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
    line(text.substr(start, end - start));
    if (end < text.size() && text[end] == '\r' && end + 1 < text.size() && text[end + 1] == '\n')
      ++end;
    start = end + 1;
  }
}

using FieldStatus = NumberFieldStatus;

/// Parses a whole field as a double (number_field.h).
inline FieldStatus parse_double_field(std::string_view f, double& value) {
  return parse_number_field(f, value);
}

/// A plain decimal "[-]digits[.digits]" of at most 15 digits at the start of [p, end), as
/// std::from_chars would give it: the integer of its digits m < 10¹⁵ < 2⁵³ and 10^f (f ≤ 15)
/// are exact doubles, so m / 10^f is correctly rounded by one IEEE division (Clinger's fast
/// path, 1990). Returns the end of the number, or nullptr (nothing consumed) for anything
/// else — more digits, an exponent, no digit — which the caller hands to std::from_chars.
inline const char* parse_short_decimal(const char* p, const char* end, double& value) {
  static constexpr double kPow10[16] = {1e0, 1e1, 1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                        1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15};
  const bool negative = p != end && *p == '-';
  const char* q = negative ? p + 1 : p;
  std::uint64_t m = 0;
  int digits = 0, fraction = -1;  // fraction: digits after '.', -1 before it
  for (; q != end; ++q) {
    if (*q >= '0' && *q <= '9') {
      m = m * 10 + static_cast<std::uint64_t>(*q - '0');
      ++digits;
      if (fraction >= 0) ++fraction;
    } else if (*q == '.' && fraction < 0) {
      fraction = 0;
    } else {
      break;
    }
  }
  if (digits == 0 || digits > 15) return nullptr;
  if (q != end && (*q == 'e' || *q == 'E' || *q == 'x' || *q == 'X' || *q == 'p' ||
                   *q == 'P' || *q == '.'))
    return nullptr;
  const double v = static_cast<double>(m) / kPow10[fraction > 0 ? fraction : 0];
  value = negative ? -v : v;
  return q;
}

/// ASCII lower case.
inline std::string ascii_lower(std::string_view s) {
  std::string out(s);
  for (char& ch : out)
    if (ch >= 'A' && ch <= 'Z') ch = static_cast<char>(ch - 'A' + 'a');
  return out;
}

}  // namespace vcmm::geometry::internal
