// Measurement: validation, placement, and the measurement CSV (docs/errormodel.md): a
// bit-exact round trip, and one bad-file test per rule, each naming the line.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "vcmm/errormodel/errors.h"
#include "vcmm/errormodel/measurement.h"
#include "vcmm/errormodel/ring_gauge.h"

namespace {

using namespace vcmm::errormodel;

Measurement small_ring() {
  RingGauge ring;
  ring.form = seed_study_ring_form();
  RingSampling s;
  s.points = 16;
  s.mode = ProbingMode::touch_trigger;
  s.height_mm = -12.5;
  s.placement.location_mm = {412.5, 305.25, 180.0};
  s.placement.orientation_rad = 30.0 * std::numbers::pi / 180.0;
  s.temperature_c = 20.7;
  s.stylus_offset_mm = {0.0, 0.0, -150.0};
  return ring_gauge_measurement(ring, s);
}

std::string message_of(const std::string& csv) {
  std::istringstream in(csv);
  try {
    read_measurement_csv(in, "m.csv");
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "(no exception)";
}

const std::string kMeta =
    "# format: vcmm.measurement 1\n"
    "# mode: scanning\n"
    "# temperature_C: 20.5\n"
    "# location_mm: 500, 300, 200\n"
    "# orientation_deg: 90\n"
    "# stylus_offset_mm: 0, 0, -150\n";

TEST(Measurement, PlacementMapsWorkpieceToMachineByRotationAboutZThenTranslation) {
  Measurement m;
  m.points_mm = Eigen::Matrix3Xd(3, 1);
  m.points_mm.col(0) = Eigen::Vector3d(1.0, 0.0, 2.0);
  m.normals = Eigen::Matrix3Xd(3, 1);
  m.normals.col(0) = Eigen::Vector3d(-1.0, 0.0, 0.0);
  m.placement.location_mm = {100.0, 200.0, 300.0};
  m.placement.orientation_rad = std::numbers::pi / 2;  // workpiece +x → machine +y
  const Eigen::Matrix3Xd w = machine_coordinates(m);
  EXPECT_NEAR(w(0, 0), 100.0, 1e-14);
  EXPECT_NEAR(w(1, 0), 201.0, 1e-14);
  EXPECT_NEAR(w(2, 0), 302.0, 1e-14);
}

TEST(Measurement, CsvRoundTripIsBitExact) {
  const Measurement m = small_ring();
  const std::string csv = measurement_csv(m);
  std::istringstream in(csv);
  const Measurement r = read_measurement_csv(in, "mem");
  EXPECT_EQ(r.points_mm, m.points_mm);
  EXPECT_EQ(r.normals, m.normals);
  EXPECT_EQ(r.mode, m.mode);
  EXPECT_EQ(r.temperature_c, m.temperature_c);
  EXPECT_EQ(r.placement.location_mm, m.placement.location_mm);
  EXPECT_EQ(r.stylus_offset_mm, m.stylus_offset_mm);
  // Degrees in the file, written as the shortest decimal that reads back to the same radians:
  // "30", not "29.999999999999996".
  EXPECT_EQ(r.placement.orientation_rad, m.placement.orientation_rad);
  EXPECT_NE(csv.find("# orientation_deg: 30\n"), std::string::npos) << csv.substr(0, 400);
  // Any angle reads back to within an ulp (exactly where a decimal maps back, as here).
  Measurement a = m;
  for (double deg : {0.1, 17.3, 45.0, 90.0, 123.456789, -60.0, 359.9}) {
    a.placement.orientation_rad = deg * std::numbers::pi / 180.0;
    std::istringstream ain(measurement_csv(a));
    EXPECT_EQ(read_measurement_csv(ain, "mem").placement.orientation_rad,
              a.placement.orientation_rad) << deg;
  }
  EXPECT_NE(csv.find("x_mm,y_mm,z_mm,nx,ny,nz\n"), std::string::npos);
  EXPECT_NE(csv.find("# mode: touch_trigger\n"), std::string::npos);
}

TEST(Measurement, ExtraCommentLinesAreWrittenAndIgnoredOnReading) {
  const Measurement m = small_ring();
  std::ostringstream os;
  const std::vector<std::string> comments = {"simulated: seed 7", "note: anything: here"};
  write_measurement_csv(os, m, comments);
  EXPECT_NE(os.str().find("# simulated: seed 7\n"), std::string::npos);
  std::istringstream in(os.str());
  EXPECT_EQ(read_measurement_csv(in, "mem").points_mm, m.points_mm);
}

TEST(Measurement, ReaderAcceptsBlanksCommentsAndShortNormalsButRenormalises) {
  const std::string csv = kMeta +
                          "# free comment: with a colon\n"
                          "x_mm, y_mm, z_mm, nx, ny, nz\n"
                          "\n"
                          "85.5, 0, 0, -1, 0, 0\n"
                          "# a comment among the data\n"
                          "0,85.5,0,0,-0.9999999,0\n";
  std::istringstream in(csv);
  const Measurement m = read_measurement_csv(in, "m.csv");
  ASSERT_EQ(m.size(), 2);
  EXPECT_EQ(m.mode, ProbingMode::scanning);
  EXPECT_EQ(m.temperature_c, 20.5);
  EXPECT_NEAR(m.placement.orientation_rad, std::numbers::pi / 2, 1e-15);
  EXPECT_EQ(m.stylus_offset_mm, Eigen::Vector3d(0, 0, -150));
  EXPECT_DOUBLE_EQ(m.normals.col(1).norm(), 1.0);
}

TEST(Measurement, AtomicFileWriteLeavesNoTemporaryAndReadsBack) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("vcmm_meas_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "ring.csv";
  const Measurement m = small_ring();
  write_measurement_csv_file(file.string(), m);
  EXPECT_EQ(read_measurement_csv_file(file.string()).points_mm, m.points_mm);
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 1);
  EXPECT_THROW(write_measurement_csv_file((dir / "no" / "such" / "x.csv").string(), m),
               std::runtime_error);
  fs::remove_all(dir);
}

TEST(MeasurementBadFile, MissingMetadataNamesTheKeyAndLine) {
  std::string csv = kMeta;
  csv.erase(csv.find("# temperature_C"), std::string("# temperature_C: 20.5\n").size());
  const std::string msg = message_of(csv + "x_mm,y_mm,z_mm,nx,ny,nz\n1,0,0,-1,0,0\n");
  EXPECT_NE(msg.find("m.csv:6:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("temperature_C"), std::string::npos) << msg;
}

TEST(MeasurementBadFile, EachRuleGivesFileLineAndValue) {
  const std::string h = "x_mm,y_mm,z_mm,nx,ny,nz\n";
  struct Case {
    std::string csv, where, what;
  };
  const Case cases[] = {
      {kMeta + h + "1,0,0,-1,0\n", "m.csv:8:", "expected 6 fields"},
      {kMeta + h + "1,abc,0,-1,0,0\n", "m.csv:8:", "field 2 (y_mm) is not a number ('abc')"},
      {kMeta + h + "1,0,nan,-1,0,0\n", "m.csv:8:", "field 3 (z_mm) is not finite ('nan')"},
      {kMeta + h + "1,0,0,1e999,0,0\n", "m.csv:8:", "field 4 (nx) overflows the double range"},
      {kMeta + h + "1,0,1e-400,-1,0,0\n", "m.csv:8:", "field 3 (z_mm) underflows"},
      {kMeta + h + "1,0,0,-2,0,0\n", "m.csv:8:", "unit vector"},
      {kMeta + h, "m.csv:8:", "no points"},
      {kMeta + "x,y,z\n", "m.csv:7:", "expected the header"},
      {"# format: vcmm.measurement 2\n", "m.csv:1:", "unsupported format"},
      {kMeta + "# mode: scanning\n", "m.csv:7:", "'mode' repeated (first on line 2)"},
      {"# mode: sideways\n", "m.csv:1:", "mode must be"},
      {"# location_mm: 1, 2\n", "m.csv:1:", "location_mm needs 3"},
      {"# temperature_C: warm\n", "m.csv:1:", "temperature_C is not a number ('warm')"},
      // Issue 12: a kelvin value gave a diameter of 170.4647 mm; −300 °C was accepted.
      {"# temperature_C: 293.15\n", "m.csv:1:",
       "temperature_C must lie in [-50, 100] °C (a workpiece temperature in °C; kelvin given? "
       "293.15 K = 20 °C); got 293.15 °C"},
      {"# temperature_C: -300\n", "m.csv:1:",
       "temperature_C is below absolute zero (-273.15 °C): not a temperature in °C; got -300 °C"},
      {"# location_mm: 0, 1e300, 0\n", "m.csv:1:",
       "location_mm component 2 must lie in [-1e+05, 1e+05] mm (a position in a CMM volume); "
       "got 1e+300 mm"},
      {"", "m.csv:1:", "missing"},
  };
  for (const Case& c : cases) {
    const std::string msg = message_of(c.csv);
    EXPECT_NE(msg.find(c.where), std::string::npos) << c.csv << "\n→ " << msg;
    EXPECT_NE(msg.find(c.what), std::string::npos) << c.csv << "\n→ " << msg;
  }
}

TEST(MeasurementBadFile, UnreadableFileIsInvalidInput) {
  EXPECT_THROW(read_measurement_csv_file("/nonexistent/vcmm/m.csv"), InvalidInput);
}

TEST(MeasurementValidation, EachPreconditionThrowsWithIndexAndValue) {
  const Measurement good = small_ring();
  EXPECT_NO_THROW(validate_measurement(good, "f"));
  auto expect_msg = [](const Measurement& m, const std::string& part) {
    try {
      validate_measurement(m, "f");
      ADD_FAILURE() << "no exception, expected " << part;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  Measurement m = good;
  m.points_mm(1, 3) = std::nan("");
  expect_msg(m, "f: point 3 has a non-finite coordinate (y = nan)");
  m = good;
  m.normals.col(5) *= 1.01;
  expect_msg(m, "f: normal 5 must be a unit vector");
  m = good;
  m.normals.conservativeResize(3, 15);
  expect_msg(m, "same count");
  m = good;
  m.temperature_c = INFINITY;
  expect_msg(m, "temperature_c must be finite");
  m = good;
  m.stylus_offset_mm.x() = NAN;
  expect_msg(m, "stylus_offset_mm must be finite");
  // Physical ranges as in the file readers: kelvin, below absolute zero, out of any volume.
  m = good;
  m.temperature_c = 293.15;
  expect_msg(m, "kelvin");
  m = good;
  m.temperature_c = -300.0;
  expect_msg(m, "absolute zero");
  m = good;
  m.placement.location_mm.y() = 1e300;
  expect_msg(m, "placement.location_mm must");
  expect_msg(Measurement{}, "no points");
}

TEST(ProbingMode, NamesRoundTrip) {
  for (ProbingMode p : {ProbingMode::scanning, ProbingMode::touch_trigger})
    EXPECT_EQ(probing_mode_from_string(to_string(p)), p);
  EXPECT_EQ(probing_mode_from_string("touch"), ProbingMode::touch_trigger);
  EXPECT_FALSE(probing_mode_from_string("Scanning").has_value());
}

}  // namespace
