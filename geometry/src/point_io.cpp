#include "vcmm/geometry/point_io.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string_view>

#include "internal/csv_fields.h"
#include "vcmm/geometry/text_lines.h"

namespace vcmm::geometry {
namespace {

using internal::FieldStatus;
using internal::parse_double_field;
using internal::split_csv_fields;
using internal::trim_blanks;

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
  while (geometry::read_text_line(in, raw)) {
    ++line_no;
    std::string_view s = raw;
    if (line_no == 1 && s.size() >= 3 && s.substr(0, 3) == "\xEF\xBB\xBF") s.remove_prefix(3);
    if (const auto hash = s.find('#'); hash != std::string_view::npos) s = s.substr(0, hash);
    s = trim_blanks(s);
    if (s.empty()) continue;
    const auto fields = split_csv_fields(s);
    double v[3] = {0, 0, 0};
    bool numeric = true;  // every field parses as a finite number
    std::size_t bad_field = 0;
    FieldStatus bad_status = FieldStatus::ok;
    for (std::size_t k = 0; numeric && k < fields.size(); ++k) {
      double value = 0.0;
      const FieldStatus st = parse_double_field(fields[k], value);
      if (k < 3) v[k] = value;
      if (st != FieldStatus::ok) {
        numeric = false;
        bad_field = k;
        bad_status = st;
      }
    }
    if (!seen_content) {
      seen_content = true;
      // A first line with a field that is not a number is a header; numbers gone wrong
      // (nan/inf) or a wrong count of numbers are errors.
      if (!numeric && bad_status == FieldStatus::not_a_number) continue;
    }
    if (fields.size() < 2 || fields.size() > 3) {
      fail(source_name, line_no,
           "expected 2 or 3 fields (x,y or x,y,z in mm), found " +
               std::to_string(fields.size()));
    }
    if (!numeric)
      fail(source_name, line_no,
           "field " + std::to_string(bad_field + 1) + " " +
               number_field_problem(bad_status, fields[bad_field]));
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
