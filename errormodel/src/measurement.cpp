// Measurement: validation, placement and the measurement CSV (docs/errormodel.md).
#include "vcmm/errormodel/measurement.h"

#include "vcmm/errormodel/atomic_file.h"

#include <unistd.h>

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <istream>
#include <map>
#include <numbers>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "vcmm/errormodel/errors.h"
#include "vcmm/errormodel/physical_ranges.h"
#include "vcmm/geometry/number_field.h"
#include "vcmm/geometry/text_lines.h"
#include "vcmm/geometry/text_file.h"

namespace vcmm::errormodel {
namespace {

constexpr std::string_view kFormat = "vcmm.measurement 1";
constexpr std::string_view kHeader = "x_mm,y_mm,z_mm,nx,ny,nz";
const std::array<std::string, 6> kMetadataKeys = {"format",          "mode",
                                                  "temperature_C",   "location_mm",
                                                  "orientation_deg", "stylus_offset_mm"};
bool is_metadata_key(const std::string& key) {
  for (const auto& k : kMetadataKeys)
    if (k == key) return true;
  return false;
}
// A normal read from a file may carry fewer digits than a double; 1e-6 accepts 7 significant
// digits and still rejects a direction that is not a unit vector at all.
constexpr double kFileUnitTolerance = 1e-6;
// Normals are computed, not measured: 1e-9 is far above rounding (1e-16) and far below any
// error a wrong normal would cause (a 1e-9 relative error moves a point by < 1e-12 mm).
constexpr double kUnitTolerance = 1e-9;

std::string format_double(double v) {
  std::array<char, 32> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), r.ptr);
}

/// The angle in degrees as the shortest decimal that the reader (degrees × π/180) turns back
/// into exactly `rad`: 30, not 29.999999999999996, for an orientation given as 30°.
std::string degrees_text(double rad) {
  const double deg = rad * 180.0 / std::numbers::pi;
  std::array<char, 32> buf{};
  for (int decimals = 0; decimals <= 17; ++decimals) {
    const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), deg,
                                 std::chars_format::fixed, decimals);
    double back = 0.0;
    std::from_chars(buf.data(), r.ptr, back);
    if (back * std::numbers::pi / 180.0 == rad) return std::string(buf.data(), r.ptr);
  }
  return format_double(deg);
}

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

std::vector<std::string_view> split_commas(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  while (true) {
    const auto comma = s.find(',', start);
    out.push_back(trim(s.substr(start, comma == std::string_view::npos ? s.npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

[[noreturn]] void fail(const std::string& source, std::size_t line, const std::string& what) {
  throw InvalidInput(source + ":" + std::to_string(line) + ": " + what);
}

double parse_field(std::string_view field, const std::string& source, std::size_t line,
                   const std::string& what) {
  double v = 0.0;
  const geometry::NumberFieldStatus status = geometry::parse_number_field(field, v);
  if (status != geometry::NumberFieldStatus::ok)
    fail(source, line, what + " " + geometry::number_field_problem(status, field));
  return v;
}

/// A metadata value in its physical range (physical_ranges.h): names the file, line, key and
/// unit.
void check_range(double v, const PhysicalRange& range, const std::string& source,
                 std::size_t line, const std::string& what) {
  if (const std::string problem = range_problem(range, v); !problem.empty())
    fail(source, line, what + " " + problem);
}

std::vector<double> parse_list(std::string_view value, std::size_t count,
                               const std::string& source, std::size_t line,
                               const std::string& key) {
  const auto fields = split_commas(value);
  if (fields.size() != count)
    fail(source, line,
         key + " needs " + std::to_string(count) + " comma-separated value(s), got " +
             std::to_string(fields.size()) + " ('" + std::string(value) + "')");
  std::vector<double> out;
  for (std::size_t i = 0; i < fields.size(); ++i)
    out.push_back(parse_field(fields[i], source, line,
                              count == 1 ? key : key + " component " + std::to_string(i + 1)));
  return out;
}

void check_finite(double v, const char* caller, const std::string& what) {
  if (!std::isfinite(v))
    throw InvalidInput(std::string(caller) + ": " + what + " must be finite; got " +
                       format_double(v));
}

}  // namespace

std::string_view to_string(ProbingMode mode) {
  return mode == ProbingMode::scanning ? "scanning" : "touch_trigger";
}

std::optional<ProbingMode> probing_mode_from_string(std::string_view text) {
  if (text == "scanning") return ProbingMode::scanning;
  if (text == "touch_trigger" || text == "touch" || text == "touch-trigger")
    return ProbingMode::touch_trigger;
  return std::nullopt;
}

Eigen::Matrix3d Placement::rotation() const {
  const double c = std::cos(orientation_rad), s = std::sin(orientation_rad);
  Eigen::Matrix3d r;
  r << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
  return r;
}

void validate_measurement(const Measurement& m, const char* caller) {
  const std::string c(caller);
  if (m.points_mm.cols() == 0) throw InvalidInput(c + ": the measurement has no points");
  if (m.normals.cols() != m.points_mm.cols())
    throw InvalidInput(c + ": points and normals must have the same count; got " +
                       std::to_string(m.points_mm.cols()) + " points and " +
                       std::to_string(m.normals.cols()) + " normals");
  for (Eigen::Index i = 0; i < m.points_mm.cols(); ++i) {
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(m.points_mm(k, i)))
        throw InvalidInput(c + ": point " + std::to_string(i) + " has a non-finite coordinate (" +
                           "xyz"[k] + " = " + format_double(m.points_mm(k, i)) + ")");
      if (!std::isfinite(m.normals(k, i)))
        throw InvalidInput(c + ": normal " + std::to_string(i) + " has a non-finite component (n" +
                           "xyz"[k] + " = " + format_double(m.normals(k, i)) + ")");
    }
    const double norm = m.normals.col(i).norm();
    if (std::abs(norm - 1.0) > kUnitTolerance)
      throw InvalidInput(c + ": normal " + std::to_string(i) +
                         " must be a unit vector (|n| - 1 within 1e-9); |n| = " +
                         format_double(norm));
  }
  for (int k = 0; k < 3; ++k) {
    check_finite(m.placement.location_mm(k), caller, "placement.location_mm");
    check_finite(m.stylus_offset_mm(k), caller, "stylus_offset_mm");
  }
  check_finite(m.placement.orientation_rad, caller, "placement.orientation_rad");
  check_finite(m.temperature_c, caller, "temperature_c");
  // The same physical ranges as the file readers (a Measurement built in code gets no
  // kelvin or absolute-zero temperature, no location outside any CMM volume past them).
  const auto in_range = [&](const PhysicalRange& range, double v,
                            const char* what) {
    if (const std::string p = range_problem(range, v); !p.empty())
      throw InvalidInput(std::string(caller) + ": " + what + " " + p);
  };
  in_range(physical_range::temperature_c, m.temperature_c, "temperature_c");
  for (int k = 0; k < 3; ++k) {
    in_range(physical_range::coordinate_mm, m.placement.location_mm(k), "placement.location_mm");
    in_range(physical_range::coordinate_mm, m.stylus_offset_mm(k), "stylus_offset_mm");
  }
}

Eigen::Matrix3Xd machine_coordinates(const Measurement& m) {
  return (m.placement.rotation() * m.points_mm).colwise() + m.placement.location_mm;
}

void write_measurement_csv(std::ostream& out, const Measurement& m,
                           std::span<const std::string> comments) {
  validate_measurement(m, "write_measurement_csv");
  for (std::size_t i = 0; i < comments.size(); ++i) {
    const std::string& c = comments[i];
    if (c.find_first_of("\r\n") != std::string::npos)
      throw InvalidInput("write_measurement_csv: comment " + std::to_string(i) +
                         " contains a line break");
    const auto colon = c.find(':');
    if (colon != std::string::npos && is_metadata_key(std::string(trim(c.substr(0, colon)))))
      throw InvalidInput("write_measurement_csv: comment " + std::to_string(i) +
                         " starts with the metadata key '" + std::string(trim(c.substr(0, colon))) +
                         ":' and would be read as metadata");
  }
  const auto& loc = m.placement.location_mm;
  const auto& t = m.stylus_offset_mm;
  std::string s;
  s.reserve(static_cast<std::size_t>(m.size()) * 96 + 512);
  s += "# vcmm measurement (docs/errormodel.md): workpiece coordinates, unit normals "
       "material -> air\n";
  s += "# format: " + std::string(kFormat) + "\n";
  s += "# mode: " + std::string(to_string(m.mode)) + "\n";
  s += "# temperature_C: " + format_double(m.temperature_c) + "\n";
  s += "# location_mm: " + format_double(loc.x()) + ", " + format_double(loc.y()) + ", " +
       format_double(loc.z()) + "\n";
  s += "# orientation_deg: " + degrees_text(m.placement.orientation_rad) + "\n";
  s += "# stylus_offset_mm: " + format_double(t.x()) + ", " + format_double(t.y()) + ", " +
       format_double(t.z()) + "\n";
  for (const std::string& c : comments) s += "# " + c + "\n";
  s += std::string(kHeader) + "\n";
  for (Eigen::Index i = 0; i < m.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      s += format_double(m.points_mm(k, i));
      s += ',';
    }
    for (int k = 0; k < 3; ++k) {
      s += format_double(m.normals(k, i));
      s += k < 2 ? ',' : '\n';
    }
  }
  out << s;
}

std::string measurement_csv(const Measurement& m, std::span<const std::string> comments) {
  std::ostringstream os;
  write_measurement_csv(os, m, comments);
  return os.str();
}

void write_measurement_csv_file(const std::string& path, const Measurement& m,
                                std::span<const std::string> comments) {
  try {
    write_file_atomically(path, measurement_csv(m, comments));
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string("write_measurement_csv_file: ") + e.what());
  }
}

Measurement read_measurement_csv(std::istream& in, const std::string& source) {
  Measurement m;
  std::map<std::string, std::size_t> seen;  // metadata key -> line
  const auto& required = kMetadataKeys;
  std::vector<double> values;  // row-major x,y,z,nx,ny,nz
  bool header_seen = false;
  std::string raw;
  std::size_t line = 0;
  while (geometry::read_text_line(in, raw)) {
    ++line;
    std::string_view text(raw);
    if (line == 1 && text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
    text = trim(text);
    if (text.empty()) continue;
    if (text.front() == '#') {
      if (header_seen) continue;  // comments among the data
      const std::string_view body = trim(text.substr(1));
      const auto colon = body.find(':');
      if (colon == std::string_view::npos) continue;
      const std::string key(trim(body.substr(0, colon)));
      const std::string_view value = trim(body.substr(colon + 1));
      if (!is_metadata_key(key)) continue;  // free-text comment that happens to contain ':'
      if (const auto it = seen.find(key); it != seen.end())
        fail(source, line,
             "metadata key '" + key + "' repeated (first on line " + std::to_string(it->second) +
                 ")");
      seen[key] = line;
      if (key == "format") {
        if (value != kFormat)
          fail(source, line,
               "unsupported format '" + std::string(value) + "' (this reader: '" +
                   std::string(kFormat) + "')");
      } else if (key == "mode") {
        const auto mode = probing_mode_from_string(value);
        if (!mode)
          fail(source, line,
               "mode must be 'scanning' or 'touch_trigger'; got '" + std::string(value) + "'");
        m.mode = *mode;
      } else if (key == "temperature_C") {
        m.temperature_c = parse_list(value, 1, source, line, key)[0];
        check_range(m.temperature_c, physical_range::temperature_c, source, line, key);
      } else if (key == "orientation_deg") {
        m.placement.orientation_rad =
            parse_list(value, 1, source, line, key)[0] * std::numbers::pi / 180.0;
      } else {
        const auto v = parse_list(value, 3, source, line, key);
        for (std::size_t k = 0; k < 3; ++k)
          check_range(v[k], physical_range::coordinate_mm, source, line,
                      key + " component " + std::to_string(k + 1));
        (key == "location_mm" ? m.placement.location_mm : m.stylus_offset_mm) =
            Eigen::Vector3d(v[0], v[1], v[2]);
      }
      continue;
    }
    if (!header_seen) {
      for (const auto& r : required)
        if (!seen.contains(r))
          fail(source, line, "metadata line '# " + r + ": ...' missing before the header");
      std::string compact;
      for (char ch : text)
        if (ch != ' ' && ch != '\t') compact += ch;
      if (compact != kHeader)
        fail(source, line,
             "expected the header '" + std::string(kHeader) + "'; got '" + std::string(text) +
                 "'");
      header_seen = true;
      continue;
    }
    const auto fields = split_commas(text);
    if (fields.size() != 6)
      fail(source, line,
           "expected 6 fields (x_mm,y_mm,z_mm,nx,ny,nz); got " + std::to_string(fields.size()));
    static const char* const names[6] = {"x_mm", "y_mm", "z_mm", "nx", "ny", "nz"};
    double row[6];
    for (int k = 0; k < 6; ++k)
      row[k] = parse_field(fields[static_cast<std::size_t>(k)], source, line,
                           "field " + std::to_string(k + 1) + " (" + names[k] + ")");
    const double norm = std::sqrt(row[3] * row[3] + row[4] * row[4] + row[5] * row[5]);
    if (std::abs(norm - 1.0) > kFileUnitTolerance)
      fail(source, line,
           "the normal (nx,ny,nz) must be a unit vector (|n| - 1 within 1e-6); |n| = " +
               format_double(norm));
    // Renormalise only a normal written with few digits: one written in full round-trips
    // bit-exactly (and is within rounding of unit length already).
    if (std::abs(norm - 1.0) > kUnitTolerance)
      for (int k = 3; k < 6; ++k) row[k] /= norm;
    values.insert(values.end(), row, row + 6);
  }
  if (!header_seen) {
    for (const auto& r : required)
      if (!seen.contains(r))
        fail(source, line + 1, "metadata line '# " + r + ": ...' missing (end of file)");
    fail(source, line + 1, "no header '" + std::string(kHeader) + "' (end of file)");
  }
  if (values.empty()) fail(source, line + 1, "no points after the header (end of file)");
  const Eigen::Index n = static_cast<Eigen::Index>(values.size() / 6);
  const Eigen::Map<const Eigen::Matrix<double, 6, Eigen::Dynamic>> table(values.data(), 6, n);
  m.points_mm = table.topRows<3>();
  m.normals = table.bottomRows<3>();
  return m;
}

Measurement read_measurement_csv_file(const std::string& path) {
  std::istringstream f(geometry::read_text_file(path, "measurement file"));
  return read_measurement_csv(f, path);
}

}  // namespace vcmm::errormodel
