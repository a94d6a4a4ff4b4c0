#include "vcmm/validation/measurement_input.h"

#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>
#include <optional>
#include <span>
#include <sstream>
#include <vector>

#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/point.h"
#include "vcmm/geometry/text_lines.h"
#include "vcmm/geometry/text_file.h"

namespace vcmm::validation {
namespace {

using geometry::InvalidInput;
namespace em = errormodel;

// Every missing item named at once, in the CLI's spelling.
void require(const MeasurementSetup& s, const std::string& source, const std::string& what,
             bool need_location, bool need_radius) {
  std::vector<std::string> missing;
  if (!s.mode) missing.emplace_back("--mode (scanning or touch)");
  if (!s.temperature_c) missing.emplace_back("--temperature (workpiece temperature reading, °C)");
  if (!s.stylus_offset_mm) missing.emplace_back("--stylus-offset X,Y,Z (tip relative to the ram, mm)");
  if (need_location && !s.location_mm) missing.emplace_back("--location X,Y,Z (machine mm)");
  if (need_radius && !s.radius_mm) missing.emplace_back("--radius (nominal radius of the profile, mm)");
  if (missing.empty()) return;
  std::string m = source + ": " + what + " carry no metadata; give ";
  for (std::size_t i = 0; i < missing.size(); ++i)
    m += (i == 0 ? "" : i + 1 == missing.size() ? " and " : ", ") + missing[i];
  throw InvalidInput(m);
}

void require_finite(const std::string& source, const char* name, double v) {
  if (!std::isfinite(v)) throw InvalidInput(source + ": " + name + " must be finite");
}

em::Measurement base(const MeasurementSetup& s, const std::string& source) {
  em::Measurement m;
  m.mode = *s.mode;
  m.temperature_c = *s.temperature_c;
  m.stylus_offset_mm = *s.stylus_offset_mm;
  m.placement.orientation_rad = s.orientation_deg.value_or(0.0) * std::numbers::pi / 180.0;
  require_finite(source, "--temperature", m.temperature_c);
  require_finite(source, "--orientation", m.placement.orientation_rad);
  for (int k = 0; k < 3; ++k) require_finite(source, "--stylus-offset", m.stylus_offset_mm[k]);
  if (s.location_mm)
    for (int k = 0; k < 3; ++k) require_finite(source, "--location", (*s.location_mm)[k]);
  return m;
}

// The least-squares centre of the points' xy; `purpose` says what it is for in the message.
geometry::Point2 fitted_center(std::span<const geometry::Point2> xy, const std::string& source,
                               const char* purpose) {
  try {
    return geometry::least_squares_circle(xy).center;
  } catch (const InvalidInput& e) {
    throw InvalidInput(source + ": the points do not define a circle for " + purpose + ": " +
                       e.what());
  }
}

// Radial unit normals in the workpiece plane about `center`, or when none is known about the
// LS centre of the points' xy.
void radial_normals(em::Measurement& m, SurfaceSide side, const std::string& source,
                    std::optional<geometry::Point2> center) {
  const Eigen::Index n = m.size();
  if (!center) {
    std::vector<geometry::Point2> xy(static_cast<std::size_t>(n));
    for (Eigen::Index i = 0; i < n; ++i)
      xy[static_cast<std::size_t>(i)] = {m.points_mm(0, i), m.points_mm(1, i)};
    center = fitted_center(xy, source, "the surface normals");
  }
  const geometry::Point2 c = *center;
  const double sign = side == SurfaceSide::inner ? 1.0 : -1.0;
  m.normals.resize(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double dx = c.x - m.points_mm(0, i), dy = c.y - m.points_mm(1, i);
    const double r = std::hypot(dx, dy);
    if (!(r > 0.0))
      throw InvalidInput(source + ": point " + std::to_string(i + 1) +
                         " lies at the fitted centre: no radial normal");
    m.normals.col(i) = Eigen::Vector3d(sign * dx / r, sign * dy / r, 0.0);
  }
}

}  // namespace

bool MeasurementSetup::any() const {
  return mode || temperature_c || location_mm || orientation_deg || stylus_offset_mm ||
         radius_mm || frame != PointFrame::machine || side != SurfaceSide::inner ||
         height_mm != 0.0;
}

em::Measurement measurement_from_points(const geometry::PointTable& table,
                                        const MeasurementSetup& setup, const std::string& source) {
  const bool has_z = !table.z.empty();
  const bool need_location = setup.frame == PointFrame::workpiece || !has_z;
  require(setup, source, "plain points", need_location, false);
  em::Measurement m = base(setup, source);
  const std::size_t n = table.points.size();
  if (n < 3) throw InvalidInput(source + ": " + std::to_string(n) + " points: a circle needs 3");
  std::optional<geometry::Point2> center;  // in the workpiece frame, when already fitted
  Eigen::Matrix3Xd p(3, static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i)
    p.col(static_cast<Eigen::Index>(i)) =
        Eigen::Vector3d(table.points[i].x, table.points[i].y, has_z ? table.z[i] : 0.0);
  if (setup.frame == PointFrame::workpiece) {
    m.placement.location_mm = *setup.location_mm;
    m.points_mm = std::move(p);
  } else {
    if (setup.location_mm) {
      m.placement.location_mm = *setup.location_mm;
      if (!has_z)  // two columns: the points lie in the plane of the given location
        p.row(2).setConstant(setup.location_mm->z());
    } else {  // the ring's machine position from the points themselves
      const geometry::Point2 c = fitted_center(table.points, source, "the location");
      m.placement.location_mm = Eigen::Vector3d(c.x, c.y, p.row(2).mean());
      center = geometry::Point2{0.0, 0.0};  // the location is the fitted centre
    }
    // workpiece = Rz(−θ)·(machine − location)
    const Eigen::Matrix3d rt = m.placement.rotation().transpose();
    m.points_mm = rt * (p.colwise() - m.placement.location_mm);
  }
  radial_normals(m, setup.side, source, center);
  em::validate_measurement(m, source.c_str());
  return m;
}

em::Measurement measurement_from_roundness_profile(const geometry::RoundnessProfile& profile,
                                                   const MeasurementSetup& setup,
                                                   const std::string& source) {
  require(setup, source, "roundness-meter profiles", true, true);
  if (!(*setup.radius_mm > 0.0) || !std::isfinite(*setup.radius_mm))
    throw InvalidInput(source + ": --radius must be a positive number of mm");
  require_finite(source, "--height", setup.height_mm);
  // A profile is in the workpiece frame by construction (setup.frame is not used): the
  // location places it in the machine.
  em::Measurement m = base(setup, source);
  m.placement.location_mm = *setup.location_mm;
  const std::size_t n = profile.angle_rad.size();
  m.points_mm.resize(3, static_cast<Eigen::Index>(n));
  m.normals.resize(3, static_cast<Eigen::Index>(n));
  const double sign = setup.side == SurfaceSide::inner ? -1.0 : 1.0;  // normal = sign·radial
  for (std::size_t j = 0; j < n; ++j) {
    const double c = std::cos(profile.angle_rad[j]), s = std::sin(profile.angle_rad[j]);
    const double r = *setup.radius_mm + profile.deviation_mm[j];
    const auto i = static_cast<Eigen::Index>(j);
    m.points_mm.col(i) = Eigen::Vector3d(r * c, r * s, setup.height_mm);
    m.normals.col(i) = Eigen::Vector3d(sign * c, sign * s, 0.0);
  }
  em::validate_measurement(m, source.c_str());
  return m;
}

MeasurementFileKind detect_measurement_file_kind(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  while (geometry::read_text_line(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    line.erase(0, first);
    if (line[0] == '#') {
      if (line.find("format:") != std::string::npos &&
          line.find("vcmm.measurement") != std::string::npos)
        return MeasurementFileKind::vcmm_measurement;
      continue;
    }
    std::string lower;
    for (const char ch : line) lower.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(ch))));
    if (lower.rfind("angle_deg", 0) == 0) return MeasurementFileKind::roundness_profile;
    return MeasurementFileKind::plain_points;
  }
  return MeasurementFileKind::plain_points;  // empty: the points reader names the problem
}

em::Measurement read_measurement_file(const std::string& path, const MeasurementSetup& setup) {
  const std::string text = geometry::read_text_file(path, "measurement file");
  std::istringstream in(text);
  switch (detect_measurement_file_kind(text)) {
    case MeasurementFileKind::vcmm_measurement:
      if (setup.any())
        throw InvalidInput(path + ": a vcmm measurement CSV carries its own metadata (mode, "
                           "temperature, location, orientation, stylus offset); give no "
                           "metadata options with it");
      return em::read_measurement_csv(in, path);
    case MeasurementFileKind::roundness_profile:
      return measurement_from_roundness_profile(geometry::read_roundness_profile_csv(in, path),
                                                setup, path);
    case MeasurementFileKind::plain_points:
      break;
  }
  return measurement_from_points(geometry::read_points_csv(in, path), setup, path);
}

}  // namespace vcmm::validation
