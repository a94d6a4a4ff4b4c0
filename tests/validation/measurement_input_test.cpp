// Measurement data as labs have it (validation/measurement_input.h): plain points in the
// machine or workpiece frame and roundness-meter profiles become the measurement the virtual
// CMM takes, with radial normals; missing metadata is named, item by item.
#include "vcmm/validation/measurement_input.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "vcmm/geometry/point.h"

namespace {

namespace va = vcmm::validation;
namespace em = vcmm::errormodel;
using vcmm::geometry::InvalidInput;
using vcmm::geometry::PointTable;

va::MeasurementSetup full_setup() {
  va::MeasurementSetup s;
  s.mode = em::ProbingMode::scanning;
  s.temperature_c = 20.3;
  s.stylus_offset_mm = Eigen::Vector3d(0.0, 0.0, -100.0);
  return s;
}

// n points of a circle of radius r about (cx, cy) at height z, as a CMM export (x, y, z).
PointTable ring(std::size_t n, double r, double cx, double cy, double z) {
  PointTable t;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
    t.points.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
    t.z.push_back(z);
    t.line.push_back(i + 1);
  }
  return t;
}

std::string message_of(const PointTable& t, const va::MeasurementSetup& s) {
  try {
    va::measurement_from_points(t, s, "ring.csv");
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "no error";
}

TEST(MeasurementInput, EveryMissingItemIsNamedAtOnce) {
  const std::string m = message_of(ring(36, 85.5, 600, 500, 250), va::MeasurementSetup{});
  EXPECT_NE(m.find("ring.csv"), std::string::npos) << m;
  for (const char* option : {"--mode", "--temperature", "--stylus-offset"})
    EXPECT_NE(m.find(option), std::string::npos) << option << ": " << m;
  EXPECT_EQ(m.find("--location"), std::string::npos) << m;  // machine frame with z: optional
  // A two-column file in the machine frame has no height: the location is then required.
  PointTable flat = ring(36, 85.5, 600, 500, 250);
  flat.z.clear();
  EXPECT_NE(message_of(flat, full_setup()).find("--location"), std::string::npos);
  va::MeasurementSetup work = full_setup();
  work.frame = va::PointFrame::workpiece;
  EXPECT_NE(message_of(ring(36, 85.5, 0, 0, 0), work).find("--location"), std::string::npos);
}

TEST(MeasurementInput, MachineFramePointsBecomeWorkpiecePointsWithInwardNormals) {
  va::MeasurementSetup s = full_setup();
  s.location_mm = Eigen::Vector3d(600.0, 500.0, 240.0);
  s.orientation_deg = 30.0;
  const em::Measurement m = va::measurement_from_points(ring(72, 85.5, 600, 500, 250), s, "r");
  ASSERT_EQ(m.size(), 72);
  EXPECT_EQ(m.mode, em::ProbingMode::scanning);
  EXPECT_DOUBLE_EQ(m.temperature_c, 20.3);
  EXPECT_NEAR(m.placement.orientation_rad, std::numbers::pi / 6.0, 1e-15);
  const Eigen::Matrix3Xd back = em::machine_coordinates(m);
  for (Eigen::Index i = 0; i < m.size(); ++i) {
    const Eigen::Vector3d p = m.points_mm.col(i);
    EXPECT_NEAR(std::hypot(p.x(), p.y()), 85.5, 1e-12);
    EXPECT_NEAR(p.z(), 10.0, 1e-12);  // 250 in the machine, location at 240
    const Eigen::Vector3d n = m.normals.col(i);
    EXPECT_NEAR(n.x(), -p.x() / 85.5, 1e-12);  // inner surface: towards the axis
    EXPECT_NEAR(n.y(), -p.y() / 85.5, 1e-12);
    EXPECT_DOUBLE_EQ(n.z(), 0.0);
    EXPECT_NEAR(back(2, i), 250.0, 1e-12);  // the machine coordinates are kept
  }
}

TEST(MeasurementInput, LocationDefaultsToTheFittedCentreAndOuterNormalsPointOut) {
  va::MeasurementSetup s = full_setup();
  s.side = va::SurfaceSide::outer;
  const em::Measurement m = va::measurement_from_points(ring(90, 20.0, 412.5, 305.25, 300), s, "r");
  EXPECT_NEAR(m.placement.location_mm.x(), 412.5, 1e-9);
  EXPECT_NEAR(m.placement.location_mm.y(), 305.25, 1e-9);
  EXPECT_NEAR(m.placement.location_mm.z(), 300.0, 1e-12);
  for (Eigen::Index i = 0; i < m.size(); ++i)
    EXPECT_GT(m.normals.col(i).dot(m.points_mm.col(i)), 0.0) << i;  // away from the axis
}

TEST(MeasurementInput, RoundnessProfileNeedsItsRadiusAndPlacesEverySample) {
  vcmm::geometry::RoundnessProfile profile;
  for (int j = 0; j < 16; ++j) {
    profile.angle_rad.push_back(2.0 * std::numbers::pi * j / 16.0);
    profile.deviation_mm.push_back(j % 2 == 0 ? 1e-4 : -1e-4);
  }
  va::MeasurementSetup s = full_setup();
  s.location_mm = Eigen::Vector3d(600.0, 500.0, 250.0);
  try {
    va::measurement_from_roundness_profile(profile, s, "ref.csv");
    FAIL() << "a profile without --radius must be refused";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("--radius"), std::string::npos) << e.what();
  }
  s.radius_mm = 85.5;
  s.height_mm = -5.0;
  const em::Measurement m = va::measurement_from_roundness_profile(profile, s, "ref.csv");
  ASSERT_EQ(m.size(), 16);
  for (Eigen::Index j = 0; j < 16; ++j) {
    const Eigen::Vector3d p = m.points_mm.col(j);
    EXPECT_NEAR(std::hypot(p.x(), p.y()), 85.5 + profile.deviation_mm[static_cast<std::size_t>(j)],
                1e-12);
    EXPECT_DOUBLE_EQ(p.z(), -5.0);
    EXPECT_LT(m.normals.col(j).dot(p), 0.0);  // inner
  }
}

TEST(MeasurementInput, FileKindsAreDetectedAndOwnMetadataIsNotOverridden) {
  EXPECT_EQ(va::detect_measurement_file_kind("# x\n# format: vcmm.measurement 1\n"),
            va::MeasurementFileKind::vcmm_measurement);
  EXPECT_EQ(va::detect_measurement_file_kind("\xEF\xBB\xBF# meter\nAngle_deg,deviation_um\n0,1\n"),
            va::MeasurementFileKind::roundness_profile);
  EXPECT_EQ(va::detect_measurement_file_kind("x_mm,y_mm,z_mm\n1,2,3\n"),
            va::MeasurementFileKind::plain_points);
  const std::filesystem::path f =
      std::filesystem::temp_directory_path() / "vcmm_measurement_input_own.csv";
  {
    std::ofstream out(f);
    out << "# format: vcmm.measurement 1\n";
  }
  try {
    va::read_measurement_file(f.string(), full_setup());
    FAIL() << "metadata options with vcmm's own CSV must be refused";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("carries its own metadata"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove(f);
}

}  // namespace
