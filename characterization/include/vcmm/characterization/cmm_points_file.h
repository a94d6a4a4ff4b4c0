// vcmm/characterization/cmm_points_file.h — reading the points a CMM reported for a
// calibration artefact, from either of the two point formats of vcmm (docs/formats.md,
// docs/errormodel.md "Measurement CSV"), in machine coordinates.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "vcmm/errormodel/measurement.h"

namespace vcmm::characterization {

/// Points as the CMM reported them, in machine coordinates (mm).
struct CmmPoints {
  Eigen::Matrix3Xd points_mm;  ///< 3×N, machine coordinates
  /// The probing mode when the file says it (measurement CSV), else nullopt.
  std::optional<errormodel::ProbingMode> mode;
  bool from_measurement_csv = false;  ///< which of the two formats the file had
};

/// Reads `path` as
///  - a measurement CSV (`# format: vcmm.measurement 1`, what `vcmm simulate` writes): its
///    workpiece points are mapped to machine coordinates, m = location + Rz(orientation)·p
///    (errormodel::machine_coordinates); the normals are ignored (a calibration estimates
///    probing directions from the fitted artefact), the mode is kept;
///  - otherwise a points CSV `x,y,z` (geometry::read_points_csv: header, `#` comments), taken
///    as machine coordinates; `x,y` files are accepted only when `require_z` is false and
///    then get z = 0.
/// The format is decided by the metadata line `# format: vcmm.measurement …` before the first
/// data line. Throws InvalidInput naming the file, 1-based line and problem (unreadable file,
/// unparsable or non-finite field, wrong column count, no points; a 2-column file when
/// `require_z`). O(N).
CmmPoints read_cmm_points_file(const std::string& path, bool require_z);

}  // namespace vcmm::characterization
