// vcmm/geometry/point_io.h — reading profiles from CSV (docs/formats.md).
//
// Format: one point a line, `x,y` or `x,y,z` (mm; z is read and ignored by the 2D
// evaluation), separators ',' (optionally surrounded by blanks), or ';' / tab / blanks.
// A first line that does not parse as numbers is a header. A header that names its x and y
// columns (`x` or `x_mm`, `y` or `y_mm`, optionally `z`/`z_mm`; any case) in another layout —
// more columns (e.g. `x_mm,y_mm,z_mm,nx,ny,nz`, a `vcmm simulate` measurement) or another
// order — picks those columns; every data line then has the header's field count and the
// other fields are not read. `#` starts a comment; blank lines are skipped. Non-finite values
// (nan, inf) are errors.
#pragma once

#include <istream>
#include <string>
#include <vector>

#include "vcmm/geometry/point.h"

namespace vcmm::geometry {

struct PointTable {
  std::vector<Point2> points;
  std::vector<double> z;         ///< empty when the file has two columns
  std::vector<std::size_t> line; ///< 1-based source line of each point (for messages)
};

/// Reads a profile. `source_name` is used in messages ("profile.csv:12: ..."). Throws
/// InvalidInput naming the source, line and problem: unparsable field, wrong column count,
/// non-finite value, no points.
PointTable read_points_csv(std::istream& in, const std::string& source_name);

/// Opens `path` ("-" for standard input) and reads it as read_points_csv.
PointTable read_points_csv_file(const std::string& path);

}  // namespace vcmm::geometry
