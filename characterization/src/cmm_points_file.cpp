// Reading calibration points from a points CSV or a measurement CSV (cmm_points_file.h).
#include "vcmm/characterization/cmm_points_file.h"

#include <fstream>
#include <sstream>
#include <string_view>

#include "vcmm/errormodel/errors.h"
#include "vcmm/geometry/point_io.h"
#include "vcmm/geometry/text_lines.h"
#include "vcmm/geometry/text_file.h"

namespace vcmm::characterization {
namespace {

/// True when a `# format: vcmm.measurement` metadata line comes before the first line that
/// is neither blank nor a comment (the measurement CSV's metadata block).
bool looks_like_measurement_csv(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  while (geometry::read_text_line(in, line)) {
    std::string_view v(line);
    if (v.starts_with("\xEF\xBB\xBF")) v.remove_prefix(3);  // UTF-8 BOM
    while (!v.empty() && (v.front() == ' ' || v.front() == '\t')) v.remove_prefix(1);
    if (v.empty() || v == "\r") continue;
    if (v.front() != '#') return false;
    v.remove_prefix(1);
    while (!v.empty() && v.front() == ' ') v.remove_prefix(1);
    if (v.starts_with("format:") && v.find("vcmm.measurement") != std::string_view::npos)
      return true;
  }
  return false;
}

}  // namespace

CmmPoints read_cmm_points_file(const std::string& path, bool require_z) {
  const std::string text = geometry::read_text_file(path, "points file");
  CmmPoints out;
  if (looks_like_measurement_csv(text)) {
    std::istringstream in(text);
    const errormodel::Measurement m = errormodel::read_measurement_csv(in, path);
    out.points_mm = errormodel::machine_coordinates(m);
    out.mode = m.mode;
    out.from_measurement_csv = true;
    return out;
  }
  std::istringstream in(text);
  const geometry::PointTable table = geometry::read_points_csv(in, path);
  if (table.z.empty() && require_z)
    throw errormodel::InvalidInput(path + ":" + std::to_string(table.line.front()) +
                                   ": needs three columns x,y,z (mm, machine coordinates); "
                                   "the file has two");
  const auto n = static_cast<Eigen::Index>(table.points.size());
  out.points_mm.resize(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    out.points_mm.col(i) << table.points[k].x, table.points[k].y,
        table.z.empty() ? 0.0 : table.z[k];
  }
  return out;
}

}  // namespace vcmm::characterization
