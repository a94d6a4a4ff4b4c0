#include "vcmm/geometry/point_io.h"

#include <charconv>
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "internal/csv_fields.h"
#include "vcmm/geometry/text_file.h"

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

/// The common line — 2 or 3 plain numbers separated by single commas, no blanks, no sign '+' —
/// in one pass of std::from_chars. Returns the number of fields, or 0 to send the line to
/// the general rules (which give the same values for every line accepted here: the same
/// from_chars on the same, already trimmed, fields).
std::size_t parse_plain_line(std::string_view s, double v[3]) {
  const char* p = s.data();
  const char* const end = s.data() + s.size();
  for (std::size_t k = 0; k < 3; ++k) {
    const char* next = internal::parse_short_decimal(p, end, v[k]);
    if (next == nullptr) {
      const auto [after, ec] = std::from_chars(p, end, v[k]);
      if (ec != std::errc() || after == p || !std::isfinite(v[k])) return 0;
      next = after;
    }
    if (next == end) return k >= 1 ? k + 1 : 0;
    if (*next != ',') return 0;
    p = next + 1;
  }
  return 0;
}

/// Columns picked by a header that names them (point_io.h): field positions of x, y and z
/// (z: npos when absent) and the header's field count, which every data line must have.
struct NamedColumns {
  static constexpr std::size_t npos = static_cast<std::size_t>(-1);
  std::size_t x = npos, y = npos, z = npos, fields = 0;
};

/// True when header field f names coordinate c ('x', 'y' or 'z'): `c` or `c_mm`, any case.
bool names_coordinate(std::string_view f, char c) {
  if (f.empty() || (f[0] != c && f[0] != c - 'a' + 'A')) return false;
  f.remove_prefix(1);
  return f.empty() || f == "_mm" || f == "_MM" || f == "_Mm" || f == "_mM";
}

/// The named columns of a header line, when it names x and y in another layout than the
/// plain `x,y[,z]` (e.g. `x_mm,y_mm,z_mm,nx,ny,nz`, what `vcmm simulate` writes).
std::optional<NamedColumns> named_columns(const std::vector<std::string_view>& fields) {
  NamedColumns c;
  c.fields = fields.size();
  for (std::size_t k = 0; k < fields.size(); ++k) {
    const std::string_view f = trim_blanks(fields[k]);
    std::size_t* slot = names_coordinate(f, 'x')   ? &c.x
                        : names_coordinate(f, 'y') ? &c.y
                        : names_coordinate(f, 'z') ? &c.z
                                                   : nullptr;
    if (slot && *slot == NamedColumns::npos) *slot = k;
  }
  if (c.x == NamedColumns::npos || c.y == NamedColumns::npos) return std::nullopt;
  const bool plain = c.x == 0 && c.y == 1 && fields.size() <= 3 &&
                     (fields.size() == 2 || c.z == 2);
  if (plain) return std::nullopt;
  return c;
}

/// The rules of read_points_csv on a whole text (read at once: one pass, no stream per line).
PointTable parse_points_csv(std::string_view text, const std::string& source_name) {
  PointTable table;
  // ~30 characters a line in practice; an estimate, not a limit.
  table.points.reserve(text.size() / 24 + 1);
  table.line.reserve(text.size() / 24 + 1);
  std::size_t line_no = 0;
  std::size_t columns = 0;  // fixed by the first data line
  bool seen_content = false;
  std::optional<NamedColumns> named;  // set by a header naming its x, y (z) columns
  std::vector<std::string_view> fields;
  internal::for_each_line(text, [&](std::string_view s) {
    ++line_no;
    if (line_no == 1 && s.size() >= 3 && s.substr(0, 3) == "\xEF\xBB\xBF") s.remove_prefix(3);
    if (const auto hash = s.find('#'); hash != std::string_view::npos) s = s.substr(0, hash);
    s = trim_blanks(s);
    if (s.empty()) return;
    double v[3] = {0, 0, 0};
    if (named) {
      split_csv_fields(s, fields);
      if (fields.size() != named->fields) {
        fail(source_name, line_no,
             "has " + std::to_string(fields.size()) + " fields but the header has " +
                 std::to_string(named->fields));
      }
      const std::size_t picked[3] = {named->x, named->y, named->z};
      for (std::size_t k = 0; k < 3; ++k) {
        if (picked[k] == NamedColumns::npos) continue;
        const FieldStatus st = parse_double_field(fields[picked[k]], v[k]);
        if (st != FieldStatus::ok)
          fail(source_name, line_no,
               "field " + std::to_string(picked[k] + 1) + " " +
                   number_field_problem(st, fields[picked[k]]));
      }
      table.points.push_back({v[0], v[1]});
      if (named->z != NamedColumns::npos) table.z.push_back(v[2]);
      table.line.push_back(line_no);
      return;
    }
    if (const std::size_t count = parse_plain_line(s, v);
        count != 0 && (columns == 0 || count == columns)) {
      seen_content = true;
      if (columns == 0) columns = count;
      table.points.push_back({v[0], v[1]});
      if (columns == 3) table.z.push_back(v[2]);
      table.line.push_back(line_no);
      return;
    }
    split_csv_fields(s, fields);
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
      if (!numeric && bad_status == FieldStatus::not_a_number) {
        named = named_columns(fields);
        return;
      }
    }
    if (fields.size() < 2 || fields.size() > 3) {
      fail(source_name, line_no,
           "expected 2 or 3 fields (x,y or x,y,z in mm), found " +
               std::to_string(fields.size()) +
               (fields.size() > 3
                    ? " (more columns need a header naming x and y: x or x_mm, y or y_mm)"
                    : ""));
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
  });
  if (table.points.empty()) throw InvalidInput(source_name + ": no points (empty input)");
  return table;
}

}  // namespace

PointTable read_points_csv(std::istream& in, const std::string& source_name) {
  std::string text;
  char buf[1 << 16];
  while (in.read(buf, sizeof buf) || in.gcount() > 0)
    text.append(buf, static_cast<std::size_t>(in.gcount()));
  if (in.bad()) throw InvalidInput(source_name + ": read error");
  return parse_points_csv(text, source_name);
}

PointTable read_points_csv_file(const std::string& path) {
  if (path == "-") return read_points_csv(std::cin, "<stdin>");
  // One read of the whole file (C stdio: no stream construction or locale per call).
  return parse_points_csv(read_text_file(path, "points file"), path);
}

}  // namespace vcmm::geometry
