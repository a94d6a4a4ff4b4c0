// tests/fuzz_regressions/fuzz_regressions_test.cpp — every input that ever made a fuzz target
// fail (tests/data/fuzz_regressions/<target>/, README.md there), replayed through the same
// check the fuzz target runs (fuzz/input_checks.h) in the normal build: the reader must parse
// it or refuse it with its documented error, and a parsed result must keep its properties.
// Also: the seeds of the fuzz corpora (fuzz/corpus/, examples/) parse — so the seeds reach
// past the readers' first rules and the round-trip properties hold on real files.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "input_checks.h"
#include "vcmm/characterization/hole_plate.h"
#include "vcmm/geometry/point.h"

namespace {

namespace fs = std::filesystem;
using vcmm::fuzz::Outcome;

const fs::path kSource = VCMM_SOURCE_DIR;

std::string file_bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

const vcmm::fuzz::Target* target_named(const std::string& name) {
  for (const auto& t : vcmm::fuzz::targets())
    if (name == t.name) return &t;
  return nullptr;
}

std::vector<fs::path> files_in(const fs::path& dir) {
  std::vector<fs::path> out;
  if (fs::is_directory(dir))
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_regular_file() && e.path().filename() != "README.md") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

const char* outcome_name(Outcome o) { return o == Outcome::parsed ? "parsed" : "rejected"; }

TEST(FuzzRegressions, EveryDirectoryNamesAFuzzTarget) {
  const fs::path root = kSource / "tests/data/fuzz_regressions";
  ASSERT_TRUE(fs::is_directory(root)) << root;
  for (const auto& e : fs::directory_iterator(root)) {
    if (!e.is_directory()) continue;
    EXPECT_NE(target_named(e.path().filename().string()), nullptr)
        << e.path() << " is not the name of a target of fuzz/input_checks.cpp";
  }
}

// The whole checked-in regression set, each file through its target's check.
TEST(FuzzRegressions, EverySavedInputIsParsedOrRefusedCleanly) {
  const fs::path root = kSource / "tests/data/fuzz_regressions";
  std::size_t replayed = 0;
  for (const auto& t : vcmm::fuzz::targets()) {
    for (const fs::path& p : files_in(root / t.name)) {
      SCOPED_TRACE(p.string());
      const std::string bytes = file_bytes(p);
      try {
        const Outcome o = t.check(bytes);
        std::printf("  %s/%s: %s\n", t.name, p.filename().c_str(), outcome_name(o));
      } catch (const std::exception& e) {
        ADD_FAILURE() << "escaped the reader's error contract: " << e.what();
      }
      ++replayed;
    }
  }
  std::printf("  replayed %zu saved inputs\n", replayed);
}

// Each seed must parse: a seed the reader refuses explores nothing behind its first rule.
TEST(FuzzRegressions, CheckedInSeedsParse) {
  std::size_t seeds = 0;
  for (const auto& t : vcmm::fuzz::targets()) {
    for (const fs::path& p : files_in(kSource / "fuzz/corpus" / t.name)) {
      SCOPED_TRACE(p.string());
      EXPECT_EQ(t.check(file_bytes(p)), Outcome::parsed);
      ++seeds;
    }
  }
  EXPECT_GE(seeds, 2u);  // campaign_json and measurement_csv have no example file to seed from
}

// The examples scripts/fuzz.sh seeds with parse and survive the round trips of the checks.
TEST(FuzzRegressions, ExampleSeedsParse) {
  const fs::path ex = kSource / "examples";
  const struct {
    Outcome (*check)(std::string_view);
    fs::path file;
  } cases[] = {
      {vcmm::fuzz::check_points_csv, ex / "profiles/ring_171mm_touch16.csv"},
      {vcmm::fuzz::check_points_csv, ex / "characterization/sphere/sphere_iso25.csv"},
      {vcmm::fuzz::check_roundness_profile_csv, ex / "characterization/noise/reference_171mm.csv"},
      {vcmm::fuzz::check_digital_model_json, ex / "cmm_model.json"},
      {vcmm::fuzz::check_hole_plate_csv, ex / "characterization/hole_plate/plate.csv"},
      {vcmm::fuzz::check_hole_plate_placement_csv, ex / "characterization/hole_plate/xy_low_t1.csv"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.file.string());
    ASSERT_TRUE(fs::is_regular_file(c.file));
    EXPECT_EQ(c.check(file_bytes(c.file)), Outcome::parsed);
  }
}

// The checks can fail: bad input is refused, not parsed.
TEST(FuzzRegressions, ChecksRefuseBadInput) {
  for (const auto& t : vcmm::fuzz::targets()) {
    SCOPED_TRACE(t.name);
    EXPECT_EQ(t.check(""), Outcome::rejected);
    EXPECT_EQ(t.check("nan,nan\n"), Outcome::rejected);
  }
}


// ---- the bugs the fuzz targets found, each pinned by its exact outcome ---------------------

// hole_plate_csv (docs/fuzzing.md, bug 1): the writer printed u as shortest(u_mm · 1e3), which
// for 13 µm is "13.000000000000002", and reading that back gave another u_mm. Now every
// uncertainty the reader produced is written so that it reads back exactly, as the shortest
// such text.
TEST(FuzzRegressions, HolePlateUncertaintyRoundTripsThroughTheWriter) {
  const fs::path file = kSource / "tests/data/fuzz_regressions/hole_plate_csv/u-um-13-round-trip.csv";
  std::istringstream in(file_bytes(file));
  const auto plate = vcmm::characterization::read_hole_plate_csv(in, "regression");
  ASSERT_EQ(plate.calibration_u_mm.size(), 3u);
  EXPECT_EQ(plate.calibration_u_mm[0], 13 * 1e-3);
  const std::string text = vcmm::characterization::hole_plate_csv(plate);
  EXPECT_NE(text.find("\nR,3,2,0,13\n"), std::string::npos) << text;
  std::istringstream again(text);
  EXPECT_EQ(vcmm::characterization::read_hole_plate_csv(again, "again").calibration_u_mm,
            plate.calibration_u_mm);
  // Every µm value with 1 to 17 significant digits, as files carry them (fixed seed).
  std::mt19937_64 rng(12);
  for (int i = 0; i < 20000; ++i) {
    const double u_um = std::uniform_real_distribution<double>(0.0, 50.0)(rng);
    std::ostringstream os;
    os.precision(1 + i % 17);
    os << u_um;
    std::istringstream one("id,x_mm,y_mm,z_mm,u_um\na,0,0,0," + os.str() + "\nb,1,0,0,0\nc,0,1,0,0\n");
    const auto p = vcmm::characterization::read_hole_plate_csv(one, "generated");
    std::istringstream back(vcmm::characterization::hole_plate_csv(p));
    ASSERT_EQ(vcmm::characterization::read_hole_plate_csv(back, "back").calibration_u_mm[0],
              p.calibration_u_mm[0])
        << "u_um " << os.str();
  }
}

// hole_plate_placement_csv (docs/fuzzing.md, bug 2): `# name:` with a carriage return inside
// ("\x02\rh") was read into the name, which the writer then refused (a name must not contain a
// line break). Every vcmm reader now takes a lone CR as a line end (geometry/text_lines.h,
// issue 12: CR-only files), so no value can hold one: here "h" becomes line 2, where the
// header is due, and the file is refused naming that line; a CRLF ending is still trimmed.
TEST(FuzzRegressions, HolePlatePlacementRefusesACarriageReturnInsideNameOrSetup) {
  const fs::path file =
      kSource / "tests/data/fuzz_regressions/hole_plate_placement_csv/carriage-return-in-name.csv";
  std::istringstream in(file_bytes(file));
  try {
    vcmm::characterization::read_hole_plate_placement_csv(in, "p.csv");
    FAIL() << "a name with a carriage return was accepted";
  } catch (const vcmm::geometry::InvalidInput& e) {
    EXPECT_STREQ(e.what(),
                 "p.csv:2: metadata line '# stylus_offset_mm: x, y, z' missing before the header");
  }
  std::istringstream setup("# stylus_offset_mm: 0,0,0\r\n# setup: a\rb\r\nid,x_mm,y_mm,z_mm\r\nA,1,2,3\r\n");
  EXPECT_THROW(vcmm::characterization::read_hole_plate_placement_csv(setup, "p.csv"),
               vcmm::geometry::InvalidInput);
  std::istringstream crlf("# name: n1\r\n# setup: s1\r\n# stylus_offset_mm: 0,0,0\r\nid,x_mm,y_mm,z_mm\r\nA,1,2,3\r\n");
  const auto pl = vcmm::characterization::read_hole_plate_placement_csv(crlf, "p.csv");
  EXPECT_EQ(pl.name, "n1");
  EXPECT_EQ(pl.setup, "s1");
}

}  // namespace
