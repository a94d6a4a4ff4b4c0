#include "vcmm/geometry/point_io.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string_view>

namespace vcmm::geometry {
namespace {

std::string_view trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\f\v");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\f\v");
  return s.substr(b, e - b + 1);
}

// Splits on ',' or ';' when present, else on runs of blanks/tabs.
std::vector<std::string_view> split_fields(std::string_view s) {
  std::vector<std::string_view> out;
  const bool delimited = s.find_first_of(",;") != std::string_view::npos;
  if (delimited) {
    std::size_t start = 0;
    while (true) {
      const auto pos = s.find_first_of(",;", start);
      out.push_back(trim(s.substr(start, pos == std::string_view::npos ? s.npos : pos - start)));
      if (pos == std::string_view::npos) break;
      start = pos + 1;
    }
  } else {
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
  return out;
}

enum class ParseStatus { ok, not_a_number, non_finite };

ParseStatus parse_double(std::string_view f, double& value) {
  if (f.empty()) return ParseStatus::not_a_number;
  if (f.front() == '+') f.remove_prefix(1);
  const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), value);
  if (ptr != f.data() + f.size()) return ParseStatus::not_a_number;
  if (ec == std::errc::result_out_of_range) return ParseStatus::non_finite;
  if (ec != std::errc()) return ParseStatus::not_a_number;
  if (!std::isfinite(value)) return ParseStatus::non_finite;
  return ParseStatus::ok;
}

[[noreturn]] void fail(const std::string& source, std::size_t line, const std::string& what) {
  std::ostringstream os;
  os << source << ":" << line << ": " << what;
  throw InvalidInput(os.str());
}

}  // namespace

PointTable read_points_csv(std::istream& in, const std::string& source_name) {
  PointTable table;
  std::string raw;
  std::size_t line_no = 0;
  std::size_t columns = 0;  // fixed by the first data line
  bool seen_content = false;
  while (std::getline(in, raw)) {
    ++line_no;
    std::string_view s = raw;
    if (line_no == 1 && s.size() >= 3 && s.substr(0, 3) == "\xEF\xBB\xBF") s.remove_prefix(3);
    if (const auto hash = s.find('#'); hash != std::string_view::npos) s = s.substr(0, hash);
    s = trim(s);
    if (s.empty()) continue;
    const auto fields = split_fields(s);
    double v[3] = {0, 0, 0};
    bool numeric = true;  // every field parses as a finite number
    std::size_t bad_field = 0;
    ParseStatus bad_status = ParseStatus::ok;
    for (std::size_t k = 0; numeric && k < fields.size(); ++k) {
      double value = 0.0;
      const ParseStatus st = parse_double(fields[k], value);
      if (k < 3) v[k] = value;
      if (st != ParseStatus::ok) {
        numeric = false;
        bad_field = k;
        bad_status = st;
      }
    }
    if (!seen_content) {
      seen_content = true;
      // A first line with a field that is not a number is a header; numbers gone wrong
      // (nan/inf) or a wrong count of numbers are errors.
      if (!numeric && bad_status == ParseStatus::not_a_number) continue;
    }
    if (fields.size() < 2 || fields.size() > 3) {
      fail(source_name, line_no,
           "expected 2 or 3 fields (x,y or x,y,z in mm), found " +
               std::to_string(fields.size()));
    }
    if (!numeric) {
      const std::string field(fields[bad_field]);
      if (bad_status == ParseStatus::non_finite)
        fail(source_name, line_no,
             "field " + std::to_string(bad_field + 1) + " is not finite ('" + field + "')");
      fail(source_name, line_no,
           "field " + std::to_string(bad_field + 1) + " is not a number ('" + field + "')");
    }
    if (columns == 0) columns = fields.size();
    if (fields.size() != columns) {
      fail(source_name, line_no,
           "has " + std::to_string(fields.size()) + " fields but the first data line has " +
               std::to_string(columns));
    }
    table.points.push_back({v[0], v[1]});
    if (columns == 3) table.z.push_back(v[2]);
    table.line.push_back(line_no);
  }
  if (in.bad()) throw InvalidInput(source_name + ": read error");
  if (table.points.empty()) throw InvalidInput(source_name + ": no points (empty input)");
  return table;
}

PointTable read_points_csv_file(const std::string& path) {
  if (path == "-") return read_points_csv(std::cin, "<stdin>");
  std::ifstream f(path);
  if (!f) throw InvalidInput(path + ": cannot open file for reading");
  return read_points_csv(f, path);
}

}  // namespace vcmm::geometry
