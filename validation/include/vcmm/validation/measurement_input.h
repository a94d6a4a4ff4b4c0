// vcmm/validation/measurement_input.h — measurement data as labs have it (docs/formats.md,
// "Plain point files for the uncertainty step"): a CMM export of plain points (x,y[,z] mm) or
// a roundness-meter profile (angle_deg,deviation_um), with the metadata the virtual CMM needs —
// probing mode, workpiece temperature, where and how the ring sat in the machine, the stylus —
// given by the caller instead of `#` lines. vcmm's own measurement CSV (docs/errormodel.md)
// carries its metadata and is read as before; giving metadata for it is an error.
//
// Composition (ARCHITECTURE.md: validation is where geometry and errormodel meet): the surface
// normals of plain points come from the least-squares circle of the points in the workpiece
// plane — towards its centre for an inner surface (a ring gauge's bore), away from it for an
// outer one (a shaft) — as the probing direction of a CMM measuring a circle is radial.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "vcmm/errormodel/measurement.h"
#include "vcmm/geometry/point_io.h"
#include "vcmm/geometry/roundness_profile.h"

namespace vcmm::validation {

/// The coordinate frame of the points in a plain file. A CMM export is usually in machine
/// coordinates; a file aligned to the part (ring centre at the origin) is in workpiece ones.
enum class PointFrame { machine, workpiece };
/// Which side of the material the circle was probed on: normals towards the centre (inner:
/// a bore, the ring gauge) or away from it (outer).
enum class SurfaceSide { inner, outer };

/// The metadata a plain file lacks. Required: mode, temperature_c, stylus_offset_mm (the Abbe
/// arm of every kinematic error: no silent default). location_mm: required for workpiece
/// frames and two-column files; for machine-frame files with z it defaults to the points'
/// least-squares centre and their mean z (so the workpiece z of the points is their height
/// about that mean). orientation_deg defaults to 0.
struct MeasurementSetup {
  std::optional<errormodel::ProbingMode> mode;
  std::optional<double> temperature_c;
  std::optional<Eigen::Vector3d> location_mm;
  std::optional<double> orientation_deg;
  std::optional<Eigen::Vector3d> stylus_offset_mm;
  PointFrame frame = PointFrame::machine;
  SurfaceSide side = SurfaceSide::inner;
  /// Roundness-meter profiles only: the nominal radius (mm) the deviations are about, and the
  /// workpiece height z (mm) of the profile (default 0).
  std::optional<double> radius_mm;
  double height_mm = 0.0;

  /// True when any metadata field is set (used to refuse metadata for vcmm's own CSV).
  bool any() const;
};

/// A Measurement from plain points. Throws InvalidInput (geometry/point.h) naming `source` and
/// every missing item at once ("ring.csv: plain points carry no metadata; give --mode …,
/// --temperature … and --stylus-offset …"; the location counts as missing where it is
/// required, above), or a rule broken (too few points for a circle, non-finite setup values).
/// O(n).
errormodel::Measurement measurement_from_points(const geometry::PointTable& table,
                                                const MeasurementSetup& setup,
                                                const std::string& source);

/// A Measurement from a roundness-meter profile: point j at workpiece (r_j cos θ_j,
/// r_j sin θ_j, height) with r_j = radius_mm + d_j (inner: normals towards the axis). The
/// frame is the workpiece one by construction: location_mm is required. Throws InvalidInput
/// as measurement_from_points (radius missing or not positive among the items).
errormodel::Measurement measurement_from_roundness_profile(const geometry::RoundnessProfile& profile,
                                                           const MeasurementSetup& setup,
                                                           const std::string& source);

/// The kind of a measurement file, from its content: vcmm's own measurement CSV (a
/// "# format: vcmm.measurement" line), a roundness-meter profile (header angle_deg,...), or
/// plain points.
enum class MeasurementFileKind { vcmm_measurement, roundness_profile, plain_points };
MeasurementFileKind detect_measurement_file_kind(const std::string& text);

/// Reads any of the three kinds from `path`. vcmm's measurement CSV with `setup.any()` is an
/// error (the file carries its own metadata); the other kinds need `setup` as above.
/// Throws InvalidInput naming the path.
errormodel::Measurement read_measurement_file(const std::string& path,
                                              const MeasurementSetup& setup);

}  // namespace vcmm::validation
