// The roundness-meter profile (vcmm/geometry/roundness_profile.h): the CSV reader `angle_deg,
// deviation_um` — units, header, separators, comments, the closing 360° repeat, one message
// per rule naming file, line and field — the closed-profile validation of profiles built in
// code, and the names of samples in messages. Expected values are worked out by hand.
#include "vcmm/geometry/roundness_profile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <unistd.h>
#include <utility>
#include <vector>

#include "vcmm/geometry/point.h"

namespace {

using namespace vcmm::geometry;
constexpr double kPi = std::numbers::pi;

RoundnessProfile read(const std::string& text) {
  std::istringstream in(text);
  return read_roundness_profile_csv(in, "p.csv");
}

template <class F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "(no exception)";
}

/// Eight samples every 45°, deviations 0, 0.1, …, 0.7 µm.
std::string eight_samples() {
  std::string s;
  for (int j = 0; j < 8; ++j) s += std::to_string(45 * j) + "," + std::to_string(0.1 * j) + "\n";
  return s;
}

/// n equiangular samples from 0, deviation a·cos 3θ (mm), built in code (no lines, no source).
RoundnessProfile three_lobes(std::size_t n, double a) {
  RoundnessProfile p;
  for (std::size_t j = 0; j < n; ++j) {
    const double theta = 2 * kPi * static_cast<double>(j) / static_cast<double>(n);
    p.angle_rad.push_back(theta);
    p.deviation_mm.push_back(a * std::cos(3 * theta));
  }
  return p;
}

// ---- reading -----------------------------------------------------------------------------

TEST(RoundnessProfileCsv, ReadsHeaderCommentsAndConvertsUnits) {
  const RoundnessProfile p = read(
      "# roundness meter export\n"
      "Angle_deg , Deviation_um\n"
      "\n" +
      eight_samples() + "# end\n");
  ASSERT_EQ(p.angle_rad.size(), 8u);
  EXPECT_EQ(p.source, "p.csv");
  EXPECT_EQ(p.angle_rad[0], 0.0);
  EXPECT_EQ(p.angle_rad[2], kPi / 2);  // 90° is exact: 90/180·π
  EXPECT_EQ(p.angle_rad[4], kPi);      // 180° is exact
  EXPECT_EQ(p.angle_rad[6], 1.5 * kPi);
  // 0.3 µm → 0.3e-3 mm: one correctly rounded product, within an ulp of the decimal.
  EXPECT_DOUBLE_EQ(p.deviation_mm[3], 0.3e-3);
  EXPECT_EQ(p.line.front(), 4u);
  EXPECT_EQ(p.line.back(), 11u);
  EXPECT_NO_THROW(validate_roundness_profile(p, "caller"));
}

TEST(RoundnessProfileCsv, AcceptsOtherSeparatorsBomAndNoHeader) {
  const RoundnessProfile a = read("0;1\n45;2\n90;3\n135;4\n180;5\n225;6\n270;7\n315;8\n");
  const RoundnessProfile b = read("0 1\n45\t2\n90 3\n135 4\n180 5\n225 6\n270 7\n315 8\n");
  const RoundnessProfile c =
      read("\xEF\xBB\xBF" "angle_deg,deviation_um\r\n0, 1\r\n45 ,2\r\n90,3\r\n135,4\r\n"
           "180,5\r\n225,6\r\n270,7 # trailing comment\r\n+315,8\r\n");
  EXPECT_EQ(a.deviation_mm, b.deviation_mm);
  EXPECT_EQ(a.deviation_mm, c.deviation_mm);
  EXPECT_EQ(a.angle_rad, c.angle_rad);
  EXPECT_DOUBLE_EQ(a.deviation_mm[7], 8e-3);
  EXPECT_EQ(c.line.front(), 2u);  // the BOM line is the header
}

TEST(RoundnessProfileCsv, DropsAClosingRepeatOfTheFirstSample) {
  const RoundnessProfile p = read(eight_samples() + "360,0.0\n");
  EXPECT_EQ(p.angle_rad.size(), 8u);
  EXPECT_EQ(p.line.size(), 8u);
  EXPECT_EQ(p.line.back(), 8u);
  EXPECT_EQ(message_of([] { read(eight_samples() + "360,0.05\n"); }),
            "p.csv:9: field 1 (angle_deg): a sample at 360 deg is accepted only as the repeat of "
            "a 0 deg sample with the same deviation; got deviation 0.050000000000000003 um, first "
            "sample 0 deg, 0 um");
  // A trace starting at 10°: 360° is not its repeat (that would be 370°, outside the range).
  std::string from10;
  for (int j = 0; j < 8; ++j) from10 += std::to_string(10 + 45 * j) + ",0\n";
  EXPECT_EQ(read(from10).angle_rad.size(), 8u);
  EXPECT_EQ(message_of([&] { read(from10 + "360,0\n"); }),
            "p.csv:9: field 1 (angle_deg): a sample at 360 deg is accepted only as the repeat of "
            "a 0 deg sample with the same deviation; got deviation 0 um, first sample 10 deg, "
            "0 um");
}

TEST(RoundnessProfileCsv, EveryRuleBrokenGivesFileLineAndField) {
  EXPECT_EQ(message_of([] { read("0,1\n45,2\n90,3\n"); }),
            "p.csv: a closed profile needs at least 8 samples; got 3");
  EXPECT_EQ(message_of([] { read("0,1\n45,nan\n"); }),
            "p.csv:2: field 2 (deviation_um) is not finite ('nan')");
  EXPECT_EQ(message_of([] { read("0,1\n45,1e999\n"); }),
            "p.csv:2: field 2 (deviation_um) overflows the double range (|x| > 1.8e308): '1e999'");
  EXPECT_EQ(message_of([] { read("0,1\ninf,2\n"); }),
            "p.csv:2: field 1 (angle_deg) is not finite ('inf')");
  EXPECT_EQ(message_of([] { read("0,1\nabc,2\n"); }),
            "p.csv:2: field 1 (angle_deg) is not a number ('abc')");
  EXPECT_EQ(message_of([] { read("0,1\n45,\n"); }),
            "p.csv:2: field 2 (deviation_um) is not a number ('')");
  EXPECT_EQ(message_of([] { read("0,1\n45,2,3\n"); }),
            "p.csv:2: expected 2 fields (angle_deg,deviation_um), found 3");
  EXPECT_EQ(message_of([] { read("0,1\n45\n"); }),
            "p.csv:2: expected 2 fields (angle_deg,deviation_um), found 1");
  EXPECT_EQ(message_of([] { read("0,1\n90,2\n45,3\n"); }),
            "p.csv:3: field 1 (angle_deg): angles must increase strictly; got '45' after 90");
  EXPECT_EQ(message_of([] { read("0,1\n90,2\n90,3\n"); }),
            "p.csv:3: field 1 (angle_deg): angles must increase strictly; got '90' after 90");
  EXPECT_EQ(message_of([] { read("0,1\n370,2\n"); }),
            "p.csv:2: field 1 (angle_deg) must lie in [0, 360); got '370'");
  EXPECT_EQ(message_of([] { read("-5,1\n"); }),
            "p.csv:1: field 1 (angle_deg) must lie in [0, 360); got '-5'");
  // A header must name the units: a file in mm or radians is never read as µm and degrees.
  EXPECT_EQ(message_of([] { read("angle_deg,deviation_mm\n" + eight_samples()); }),
            "p.csv:1: header must be 'angle_deg,deviation_um' (angles in degrees, deviations "
            "in µm); got 'angle_deg,deviation_mm'");
  EXPECT_EQ(message_of([] { read("x_mm,y_mm,z_mm\n" + eight_samples()); }),
            "p.csv:1: header must be 'angle_deg,deviation_um' (angles in degrees, deviations "
            "in µm); got 'x_mm,y_mm,z_mm'");
  // Only the first content line may be a header.
  EXPECT_EQ(message_of([] { read(eight_samples() + "angle_deg,deviation_um\n"); }),
            "p.csv:9: field 1 (angle_deg) is not a number ('angle_deg')");
  EXPECT_EQ(message_of([] { read("# only a comment\n"); }), "p.csv: no samples (empty profile)");
  EXPECT_EQ(message_of([] { read("angle_deg,deviation_um\n"); }),
            "p.csv: no samples (empty profile)");
  // Not closed: samples over 0…170° only leave a gap of 190° from 170° back to 360°.
  EXPECT_EQ(message_of([] {
              read("0,0\n20,0\n40,0\n60,0\n80,0\n100,0\n120,0\n140,0\n170,0\n");
            }),
            "p.csv:9: profile is not closed: an angular gap of 190 deg from 170 deg to 0 deg (a "
            "closed profile has no gap of 180 deg or more)");
  // Exactly half a turn is not closed either (gap 180° from 0° to 180°).
  EXPECT_EQ(message_of([] {
              read("0,0\n180,0\n200,0\n220,0\n240,0\n260,0\n280,0\n300,0\n");
            }),
            "p.csv:1: profile is not closed: an angular gap of 180 deg from 0 deg to 180 deg (a "
            "closed profile has no gap of 180 deg or more)");
  EXPECT_EQ(message_of([] { read_roundness_profile_csv_file("/nonexistent/ref.csv"); }),
            "/nonexistent/ref.csv: cannot read the roundness profile file: no such file");
}

TEST(RoundnessProfileCsv, ReadsAFileAndNamesItInMessages) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("vcmm_roundness_profile_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::filesystem::path good = dir / "good.csv";
  std::ofstream(good) << "angle_deg,deviation_um\n" << eight_samples();
  const RoundnessProfile p = read_roundness_profile_csv_file(good.string());
  EXPECT_EQ(p.source, good.string());
  ASSERT_EQ(p.angle_rad.size(), 8u);
  EXPECT_EQ(p.line[1], 3u);
  const std::filesystem::path bad = dir / "bad.csv";
  std::ofstream(bad) << "0,0\n45,NaN\n";
  EXPECT_EQ(message_of([&] { read_roundness_profile_csv_file(bad.string()); }),
            bad.string() + ":2: field 2 (deviation_um) is not finite ('NaN')");
  std::filesystem::remove_all(dir);
}

// ---- profiles built in code --------------------------------------------------------------

TEST(RoundnessProfile, ValidationOfProfilesBuiltInCode) {
  RoundnessProfile p = three_lobes(16, 1e-3);
  EXPECT_NO_THROW(validate_roundness_profile(p, "caller"));
  RoundnessProfile q = p;
  q.deviation_mm.pop_back();
  EXPECT_EQ(message_of([&] { validate_roundness_profile(q, "caller"); }),
            "caller: angle_rad and deviation_mm differ in size (16 vs 15)");
  q = p;
  q.deviation_mm[5] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(message_of([&] { validate_roundness_profile(q, "caller"); }),
            "caller: sample 5: non-finite sample (angle 1.9634954084936207 rad, deviation nan mm)");
  q = p;
  q.angle_rad[0] = -std::numeric_limits<double>::infinity();
  EXPECT_EQ(message_of([&] { validate_roundness_profile(q, "caller"); }),
            "caller: sample 0: non-finite sample (angle -inf rad, deviation 0.001 mm)");
  q = p;
  q.angle_rad[15] = 2 * kPi;
  EXPECT_EQ(message_of([&] { validate_roundness_profile(q, "caller"); }),
            "caller: sample 15: angle must lie in [0, 360) degrees; got 360 deg");
  q = p;
  q.angle_rad[0] = -1e-9;
  EXPECT_NE(message_of([&] { validate_roundness_profile(q, "caller"); })
                .find("caller: sample 0: angle must lie in [0, 360) degrees"),
            std::string::npos);
  q = p;
  std::swap(q.angle_rad[3], q.angle_rad[4]);
  EXPECT_EQ(message_of([&] { validate_roundness_profile(q, "caller"); }),
            "caller: sample 4: angles must increase strictly; got 67.5 deg after 90 deg");
  q = p;
  q.line = {1, 2};
  EXPECT_EQ(message_of([&] { validate_roundness_profile(q, "caller"); }),
            "caller: line must be empty or hold one entry per sample (2 for 16 samples)");
  q = three_lobes(7, 1e-3);
  EXPECT_EQ(message_of([&] { validate_roundness_profile(q, "caller"); }),
            "caller: a closed profile needs at least 8 samples; got 7");
  EXPECT_EQ(min_roundness_profile_points, 8u);
  // A null caller: the message starts with the sample.
  q = p;
  q.angle_rad[4] = q.angle_rad[3];
  EXPECT_EQ(message_of([&] { validate_roundness_profile(q, nullptr); }),
            "sample 4: angles must increase strictly; got 67.5 deg after 67.5 deg");
}

TEST(RoundnessProfile, ClosednessIsDecidedOnTheWrapToo) {
  // Samples 0°, 10°, …, 170° and 185°: the largest gap is the wrap, 175° < 180°: closed.
  RoundnessProfile p;
  for (int d = 0; d <= 170; d += 10) {
    p.angle_rad.push_back(d / 180.0 * kPi);
    p.deviation_mm.push_back(0.0);
  }
  p.angle_rad.push_back(185.0 / 180.0 * kPi);
  p.deviation_mm.push_back(0.0);
  EXPECT_NO_THROW(validate_roundness_profile(p, "caller"));
  // Without the sample at 185° the wrap from 170° is 190°: an arc.
  p.angle_rad.pop_back();
  p.deviation_mm.pop_back();
  EXPECT_EQ(message_of([&] { validate_roundness_profile(p, "caller"); }),
            "caller: sample 17: profile is not closed: an angular gap of 190 deg from 170 deg to "
            "0 deg (a closed profile has no gap of 180 deg or more)");
}

TEST(RoundnessProfile, SampleLocationNamesFileLineOrIndex) {
  RoundnessProfile p = three_lobes(8, 0.0);
  EXPECT_EQ(profile_sample_location(p, 3), "sample 3");
  p.source = "ref.csv";
  EXPECT_EQ(profile_sample_location(p, 3), "ref.csv: sample 3");
  p.line = {3, 4, 5, 7, 8, 9, 10, 12};
  EXPECT_EQ(profile_sample_location(p, 3), "ref.csv:7");
  EXPECT_EQ(profile_sample_location(p, 8), "ref.csv: sample 8");  // beyond the table
  p.source.clear();
  EXPECT_EQ(profile_sample_location(p, 7), "line 12");
  // The validation uses it, with the caller and the source.
  p.source = "ref.csv";
  p.deviation_mm[3] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(message_of([&] { validate_roundness_profile(p, "f"); }),
            "f: ref.csv:7: non-finite sample (angle 2.3561944901923448 rad, deviation inf mm)");
}

}  // namespace
