// vcmm/errormodel/measurement.h — one CMM measurement of a workpiece feature, as the virtual
// CMM consumes and produces it, and its CSV file format (docs/errormodel.md, "Measurement CSV").
//
// Conventions (pinned by tests/errormodel/measurement_test.cpp):
//  - Points are the probed surface points in *workpiece* coordinates, millimetres, one column
//    per point (3×N, no per-point heap objects).
//  - Normals are unit surface normals pointing from the material into the air. On the inner
//    surface of a ring gauge they point towards the ring axis. The probing direction (the
//    direction in which the tip moves onto the surface) is −normal.
//  - Placement: workpiece → machine coordinates is  m = location + Rz(orientation) · p,
//    a rotation about the machine Z axis followed by a translation. The workpiece Z axis (the
//    ring axis) is parallel to machine Z. `location_mm` is the machine position of the
//    workpiece origin (for a ring gauge: the ring centre at workpiece height z = 0).
//  - Lengths in mm, angles in radians (degrees only in the CSV file), temperature in °C.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <iosfwd>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace vcmm::errormodel {

/// The reference temperature of dimensional metrology (ISO 1:2022): coordinates are
/// reported at 20 °C.
inline constexpr double reference_temperature_c = 20.0;

/// How the points were taken; selects the noise level of the digital model.
enum class ProbingMode { scanning, touch_trigger };

/// "scanning" / "touch_trigger" (the CSV and JSON spelling).
std::string_view to_string(ProbingMode mode);
/// Parses "scanning", "touch_trigger" (also "touch", "touch-trigger"); nullopt otherwise.
std::optional<ProbingMode> probing_mode_from_string(std::string_view text);

/// Where the workpiece sits in the machine: m = location_mm + Rz(orientation_rad) · p.
struct Placement {
  Eigen::Vector3d location_mm = Eigen::Vector3d::Zero();  ///< workpiece origin, machine coords
  double orientation_rad = 0.0;  ///< rotation of the workpiece about machine Z (right-handed)

  /// Rz(orientation_rad), the rotation part of workpiece → machine.
  Eigen::Matrix3d rotation() const;
};

struct Measurement {
  Eigen::Matrix3Xd points_mm;  ///< 3×N surface points, workpiece coordinates (mm)
  Eigen::Matrix3Xd normals;    ///< 3×N unit normals, material → air (probing direction = −normal)
  Placement placement;
  ProbingMode mode = ProbingMode::scanning;
  double temperature_c = reference_temperature_c;  ///< workpiece temperature *reading* (°C)
  /// Tip centre relative to the reference point of the last axis (the Z ram), machine
  /// coordinates (mm): the Abbe arm of the probe. A vertical stylus of length L: (0, 0, −L).
  Eigen::Vector3d stylus_offset_mm = Eigen::Vector3d::Zero();

  Eigen::Index size() const { return points_mm.cols(); }
};

/// Checks a measurement at a public boundary (every build): points and normals both 3×N with
/// N ≥ 1, every value finite, every normal of unit length within 1e-9 (normals are computed,
/// not measured; 1e-9 leaves room for rounding of written files, whose shortest round-trip
/// doubles reproduce them exactly anyway), finite placement, temperature and stylus offset.
/// Throws InvalidInput naming `caller`, the rule and the offending index/value. O(N).
void validate_measurement(const Measurement& m, const char* caller);

/// The machine coordinates of every point: location + R · p (3×N). O(N).
Eigen::Matrix3Xd machine_coordinates(const Measurement& m);

/// Writes the measurement CSV (docs/errormodel.md): `#` metadata lines, then `comments` as
/// further `# ` lines (provenance: command, seed, model file), the header
/// `x_mm,y_mm,z_mm,nx,ny,nz`, and one point a line with the shortest decimal text that reads
/// back to the same double (the file round-trips bit-exactly; the orientation, stored in
/// degrees, to 1 ulp). Throws InvalidInput if `m` is invalid or a comment contains a line
/// break or starts with a metadata key ("mode:" …), which a reader would take as metadata.
void write_measurement_csv(std::ostream& out, const Measurement& m,
                           std::span<const std::string> comments = {});
/// The same, as a string.
std::string measurement_csv(const Measurement& m, std::span<const std::string> comments = {});
/// Writes the CSV to `path` atomically (a temporary beside it, flushed, then renamed): an
/// interrupted run never leaves a half-written file. Throws std::runtime_error naming the
/// path when the file cannot be written (the temporary is removed).
void write_measurement_csv_file(const std::string& path, const Measurement& m,
                                std::span<const std::string> comments = {});

/// Reads a measurement CSV. `source_name` prefixes every message ("ring.csv:12: ...").
/// Throws InvalidInput naming the source, 1-based line and problem: missing or duplicated
/// metadata key, unsupported format version, bad header, wrong field count, unparsable or
/// non-finite field, normal not of unit length (tolerance 1e-6: a file written with fewer
/// digits is still accepted, and its normal renormalised if off by more than 1e-9), no points.
Measurement read_measurement_csv(std::istream& in, const std::string& source_name);
/// Opens `path` and reads it as read_measurement_csv; an unreadable file is InvalidInput.
Measurement read_measurement_csv_file(const std::string& path);

}  // namespace vcmm::errormodel
