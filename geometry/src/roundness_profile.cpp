// roundness_profile.cpp — the roundness-meter profile reader and the closed-profile rules
// (vcmm/geometry/roundness_profile.h, docs/formats.md "Roundness-meter profile").
//
// Closedness. A profile goes round the axis when no two neighbours (the last and the first
// across 360° included) are half a revolution or more apart: with a gap g ≥ π the samples lie
// in a closed half-plane through the axis, and every circle fitted to them is that of an arc.
// The Gaussian filter's stricter rule (no gap wider than λc/2) depends on the cut-off and is
// checked by its users.
//
// Messages use 17 significant digits for values (they read back to the same double) and 12
// for angles converted from radians (so 11° computed from radians reads "11", not
// "10.999999999999998").
#include "vcmm/geometry/text_file.h"
#include "vcmm/geometry/text_lines.h"
#include "vcmm/geometry/roundness_profile.h"

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "internal/csv_fields.h"
#include "vcmm/geometry/point.h"

namespace vcmm::geometry {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kMmPerUm = 1e-3;

std::string degree_text(double rad) {
  std::ostringstream os;
  os.precision(12);
  os << rad * 180.0 / kPi;
  return os.str();
}

std::string number_text(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

/// "caller: <sample location>", or the location alone when caller is null.
std::string where(const RoundnessProfile& p, const char* caller, std::size_t j) {
  return (caller ? std::string(caller) + ": " : std::string()) + profile_sample_location(p, j);
}

/// "caller: source", "caller", "source" — the prefix of whole-profile messages.
std::string head(const RoundnessProfile& p, const char* caller) {
  std::string out = caller ? std::string(caller) : std::string();
  if (!p.source.empty()) out += (out.empty() ? "" : ": ") + p.source;
  return out;
}

}  // namespace

std::string profile_sample_location(const RoundnessProfile& p, std::size_t j) {
  if (j < p.line.size())
    return (p.source.empty() ? std::string("line ") : p.source + ":") + std::to_string(p.line[j]);
  return (p.source.empty() ? std::string() : p.source + ": ") + "sample " + std::to_string(j);
}

void validate_roundness_profile(const RoundnessProfile& p, const char* caller) {
  const std::size_t n = p.angle_rad.size();
  const std::string h = head(p, caller);
  if (p.deviation_mm.size() != n)
    throw InvalidInput(h + ": angle_rad and deviation_mm differ in size (" + std::to_string(n) +
                       " vs " + std::to_string(p.deviation_mm.size()) + ")");
  if (!p.line.empty() && p.line.size() != n)
    throw InvalidInput(h + ": line must be empty or hold one entry per sample (" +
                       std::to_string(p.line.size()) + " for " + std::to_string(n) +
                       " samples)");
  if (n < min_roundness_profile_points)
    throw InvalidInput(h + ": a closed profile needs at least " +
                       std::to_string(min_roundness_profile_points) + " samples; got " +
                       std::to_string(n));
  for (std::size_t j = 0; j < n; ++j) {
    if (!std::isfinite(p.angle_rad[j]) || !std::isfinite(p.deviation_mm[j]))
      throw InvalidInput(where(p, caller, j) + ": non-finite sample (angle " +
                         number_text(p.angle_rad[j]) + " rad, deviation " +
                         number_text(p.deviation_mm[j]) + " mm)");
    if (!(p.angle_rad[j] >= 0.0 && p.angle_rad[j] < 2 * kPi))
      throw InvalidInput(where(p, caller, j) + ": angle must lie in [0, 360) degrees; got " +
                         degree_text(p.angle_rad[j]) + " deg");
    if (j > 0 && !(p.angle_rad[j] > p.angle_rad[j - 1]))
      throw InvalidInput(where(p, caller, j) + ": angles must increase strictly; got " +
                         degree_text(p.angle_rad[j]) + " deg after " +
                         degree_text(p.angle_rad[j - 1]) + " deg");
  }
  // Closedness (file comment): every gap, the wrap included, below half a revolution.
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t k = j + 1 < n ? j + 1 : 0;
    const double gap = (k == 0 ? p.angle_rad[0] + 2 * kPi : p.angle_rad[k]) - p.angle_rad[j];
    if (!(gap < kPi))
      throw InvalidInput(where(p, caller, j) + ": profile is not closed: an angular gap of " +
                         degree_text(gap) + " deg from " + degree_text(p.angle_rad[j]) +
                         " deg to " + degree_text(p.angle_rad[k]) +
                         " deg (a closed profile has no gap of 180 deg or more)");
  }
}

RoundnessProfile read_roundness_profile_csv(std::istream& in, const std::string& source_name) {
  using internal::FieldStatus;
  static constexpr const char* kFieldName[2] = {"angle_deg", "deviation_um"};
  RoundnessProfile p;
  p.source = source_name;
  std::vector<double> angle_deg, deviation_um;
  std::string raw;
  std::size_t line_no = 0;
  bool seen_content = false;
  const auto fail = [&](std::size_t line, const std::string& what) -> void {
    throw InvalidInput(source_name + ":" + std::to_string(line) + ": " + what);
  };
  while (geometry::read_text_line(in, raw)) {
    ++line_no;
    std::string_view s = raw;
    if (line_no == 1 && s.size() >= 3 && s.substr(0, 3) == "\xEF\xBB\xBF") s.remove_prefix(3);
    if (const auto hash = s.find('#'); hash != std::string_view::npos) s = s.substr(0, hash);
    s = internal::trim_blanks(s);
    if (s.empty()) continue;
    const auto fields = internal::split_csv_fields(s);
    double v[2] = {0.0, 0.0};
    std::size_t bad = fields.size();  // index of the first field that is not a finite number
    FieldStatus bad_status = FieldStatus::ok;
    for (std::size_t k = 0; k < fields.size() && bad == fields.size(); ++k) {
      double value = 0.0;
      const FieldStatus st = internal::parse_double_field(fields[k], value);
      if (k < 2) v[k] = value;
      if (st != FieldStatus::ok) {
        bad = k;
        bad_status = st;
      }
    }
    if (!seen_content) {
      seen_content = true;
      if (bad < fields.size() && bad_status == FieldStatus::not_a_number) {
        // A header: it must name the columns and their units.
        if (fields.size() != 2 || internal::ascii_lower(fields[0]) != kFieldName[0] ||
            internal::ascii_lower(fields[1]) != kFieldName[1])
          fail(line_no, "header must be 'angle_deg,deviation_um' (angles in degrees, "
                        "deviations in µm); got '" + std::string(s) + "'");
        continue;
      }
    }
    if (fields.size() != 2)
      fail(line_no, "expected 2 fields (angle_deg,deviation_um), found " +
                        std::to_string(fields.size()));
    if (bad < fields.size())
      fail(line_no, "field " + std::to_string(bad + 1) + " (" + kFieldName[bad] + ") " +
                        number_field_problem(bad_status, fields[bad]));
    if (!(v[0] >= 0.0 && v[0] <= 360.0))
      fail(line_no, "field 1 (angle_deg) must lie in [0, 360); got '" + std::string(fields[0]) +
                        "'");
    if (!angle_deg.empty() && !(v[0] > angle_deg.back()))
      fail(line_no, "field 1 (angle_deg): angles must increase strictly; got '" +
                        std::string(fields[0]) + "' after " + number_text(angle_deg.back()));
    angle_deg.push_back(v[0]);
    deviation_um.push_back(v[1]);
    p.line.push_back(line_no);
  }
  if (in.bad()) throw InvalidInput(source_name + ": read error");
  if (angle_deg.empty()) throw InvalidInput(source_name + ": no samples (empty profile)");
  if (angle_deg.back() == 360.0) {
    // A meter's closing sample repeating the first one: dropped when it is exactly that.
    const std::size_t last = angle_deg.size() - 1;
    if (angle_deg.front() != 0.0 || deviation_um.front() != deviation_um.back())
      fail(p.line[last],
           "field 1 (angle_deg): a sample at 360 deg is accepted only as the repeat of a 0 deg "
           "sample with the same deviation; got deviation " + number_text(deviation_um[last]) +
               " um, first sample " + number_text(angle_deg.front()) + " deg, " +
               number_text(deviation_um.front()) + " um");
    angle_deg.pop_back();
    deviation_um.pop_back();
    p.line.pop_back();
  }
  p.angle_rad.resize(angle_deg.size());
  p.deviation_mm.resize(angle_deg.size());
  for (std::size_t j = 0; j < angle_deg.size(); ++j) {
    p.angle_rad[j] = angle_deg[j] / 180.0 * kPi;  // exact for 0, 90, 180, 270
    p.deviation_mm[j] = deviation_um[j] * kMmPerUm;
  }
  validate_roundness_profile(p, nullptr);
  return p;
}

RoundnessProfile read_roundness_profile_csv_file(const std::string& path) {
  std::istringstream f(read_text_file(path, "roundness profile file"));
  return read_roundness_profile_csv(f, path);
}

}  // namespace vcmm::geometry
