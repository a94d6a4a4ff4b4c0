// read_points_csv: formats accepted and every rejection with file and line in the message.
#include <gtest/gtest.h>

#include <bit>
#include <charconv>
#include <cstdint>
#include <sstream>
#include <string>
#include <system_error>

#include "../../geometry/src/internal/csv_fields.h"
#include "vcmm/geometry/point_io.h"

namespace {

using vcmm::geometry::InvalidInput;
using vcmm::geometry::PointTable;
using vcmm::geometry::read_points_csv;

PointTable read(const std::string& text) {
  std::istringstream in(text);
  return read_points_csv(in, "p.csv");
}

std::string error_of(const std::string& text) {
  try {
    read(text);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

TEST(ReadPointsCsv, ReadsXYWithHeaderCommentsAndBlankLines) {
  const auto t = read("# ring\nx,y\n\n1.5, 2\n  -3e-3 ,4.25 # tail\n");
  ASSERT_EQ(t.points.size(), 2u);
  EXPECT_DOUBLE_EQ(t.points[0].x, 1.5);
  EXPECT_DOUBLE_EQ(t.points[1].x, -3e-3);
  EXPECT_DOUBLE_EQ(t.points[1].y, 4.25);
  EXPECT_TRUE(t.z.empty());
  EXPECT_EQ(t.line[0], 4u);
  EXPECT_EQ(t.line[1], 5u);
}

TEST(ReadPointsCsv, ReadsXYZAndOtherSeparators) {
  const auto t = read("1;2;3\n4;5;6\n");
  ASSERT_EQ(t.points.size(), 2u);
  EXPECT_DOUBLE_EQ(t.z[1], 6.0);
  const auto w = read("1 2\n3\t4\r\n+5 6\n");
  ASSERT_EQ(w.points.size(), 3u);
  EXPECT_DOUBLE_EQ(w.points[2].x, 5.0);
}

TEST(ReadPointsCsv, KeepsFullDoublePrecision) {
  const auto t = read("412.50003340112345,305.2500000000001\n");
  EXPECT_EQ(t.points[0].x, 412.50003340112345);
  EXPECT_EQ(t.points[0].y, 305.2500000000001);
}

TEST(ReadPointsCsv, RejectsEmptyInput) {
  EXPECT_EQ(error_of(""), "p.csv: no points (empty input)");
  EXPECT_EQ(error_of("# only a comment\nx,y\n"), "p.csv: no points (empty input)");
}

TEST(ReadPointsCsv, RejectsNonFiniteValuesWithLine) {
  EXPECT_EQ(error_of("1,2\n3,nan\n"), "p.csv:2: field 2 is not finite ('nan')");
  EXPECT_EQ(error_of("inf,2\n"), "p.csv:1: field 1 is not finite ('inf')");
  EXPECT_EQ(error_of("1,2\n1e999,2\n"), "p.csv:2: field 1 overflows the double range (|x| > 1.8e308): '1e999'");
}

// Issue 12: 1e-400 was called "not finite"; it is finite as written, and too small for a
// double.
TEST(ReadPointsCsv, UnderflowIsCalledUnderflow) {
  EXPECT_EQ(error_of("1,0\n0,1\n-1,1e-400\n"),
            "p.csv:3: field 2 underflows: non-zero but below the smallest double (4.9e-324): "
            "'1e-400'");
  EXPECT_EQ(read("1,0\n0,1e-310\n-1,0\n").points[1].y, 1e-310);  // subnormal: kept
}

// Issue 12: a file with CR-only line ends was "no points (empty input)". Every line end is
// read: \n, \r\n and a lone \r, also mixed, with the line numbers counted alike.
TEST(ReadPointsCsv, ReadsEveryLineEnd) {
  for (const std::string eol : {"\n", "\r\n", "\r"}) {
    const PointTable t = read("x,y" + eol + "1,2" + eol + "3,4" + eol + "5,6");
    ASSERT_EQ(t.points.size(), 3u) << static_cast<int>(eol.back());
    EXPECT_EQ(t.points[2].y, 6.0);
    EXPECT_EQ(t.line[2], 4u);
    EXPECT_EQ(error_of("1,2" + eol + "3,x" + eol), "p.csv:2: field 2 is not a number ('x')");
  }
  EXPECT_EQ(read("1,2\r3,4\r\n5,6\n7,8\r").points.size(), 4u);
  EXPECT_EQ(read("1,2\r\r\r3,4").line[1], 4u);  // blank CR lines still count
}

TEST(ReadPointsCsv, RejectsGarbageAndWrongColumnCounts) {
  EXPECT_EQ(error_of("1,2\n3,abc\n"), "p.csv:2: field 2 is not a number ('abc')");
  EXPECT_EQ(error_of("1,2\n3\n"), "p.csv:2: expected 2 or 3 fields (x,y or x,y,z in mm), found 1");
  EXPECT_EQ(error_of("1,2,3,4\n"),
            "p.csv:1: expected 2 or 3 fields (x,y or x,y,z in mm), found 4 (more columns need "
            "a header naming x and y: x or x_mm, y or y_mm)");
  // A header that names no x and y columns picks nothing: the plain rule applies.
  EXPECT_EQ(error_of("a,b,c,d\n1,2,3,4\n"),
            "p.csv:2: expected 2 or 3 fields (x,y or x,y,z in mm), found 4 (more columns need "
            "a header naming x and y: x or x_mm, y or y_mm)");
  EXPECT_EQ(error_of("1,2\n1,2,3\n"), "p.csv:2: has 3 fields but the first data line has 2");
  EXPECT_EQ(error_of("1,2\n,2\n"), "p.csv:2: field 1 is not a number ('')");
}

// A header naming its columns picks them: the measurement CSV `vcmm simulate` writes (x, y, z
// and the normals), reordered columns, any case, other fields not read; the header's count
// is every line's count and errors name the field's own column.
TEST(ReadPointsCsv, HeaderNamingColumnsPicksThem) {
  const PointTable m = read(
      "# vcmm measurement\n# format: vcmm.measurement 1\nx_mm,y_mm,z_mm,nx,ny,nz\n"
      "85.5,-0.25,0.5,-1,0,0\n0.125,85.5,0.75,0,-1,0\n");
  ASSERT_EQ(m.points.size(), 2u);
  EXPECT_EQ(m.points[0].x, 85.5);
  EXPECT_EQ(m.points[0].y, -0.25);
  EXPECT_EQ(m.points[1].x, 0.125);
  EXPECT_EQ(m.z, (std::vector<double>{0.5, 0.75}));
  EXPECT_EQ(m.line, (std::vector<std::size_t>{4, 5}));
  const PointTable r = read("label;Y;X\nP1;2;1\nP2;4;3\n");
  ASSERT_EQ(r.points.size(), 2u);
  EXPECT_EQ(r.points[1].x, 3.0);
  EXPECT_EQ(r.points[1].y, 4.0);
  EXPECT_TRUE(r.z.empty());
  // Reordered within three columns (y, x, z) is picked by name too.
  const PointTable o = read("y,x,z\n2,1,7\n");
  EXPECT_EQ(o.points[0].x, 1.0);
  EXPECT_EQ(o.points[0].y, 2.0);
  EXPECT_EQ(o.z, (std::vector<double>{7.0}));
  EXPECT_EQ(error_of("x,y,nx\n1,2,0\n1,2\n"), "p.csv:3: has 2 fields but the header has 3");
  EXPECT_EQ(error_of("nx,x_mm,y_mm\n0,1,nan\n"), "p.csv:2: field 3 is not finite ('nan')");
}

TEST(ReadPointsCsv, MissingFileIsAClearError) {
  try {
    vcmm::geometry::read_points_csv_file("/nonexistent/ring.csv");
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/ring.csv: cannot read the points file: no such file");
  }
}

}  // namespace

// The reader's fast path for short plain decimals (internal/csv_fields.h, Clinger's fast
// path) must give bit for bit what std::from_chars gives, and hand everything else over.
TEST(PointIoFastPath, ShortDecimalsParseBitForBitLikeFromChars) {
  namespace internal = vcmm::geometry::internal;
  std::uint64_t state = 20261126;
  auto next = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return state >> 33;
  };
  int accepted = 0;
  for (int trial = 0; trial < 200000; ++trial) {
    std::string s;
    if (next() % 4 == 0) s += '-';
    const int int_digits = static_cast<int>(next() % 8);
    const int frac_digits = static_cast<int>(next() % 12);
    for (int k = 0; k < int_digits; ++k) s += static_cast<char>('0' + next() % 10);
    if (next() % 8 != 0) s += '.';
    for (int k = 0; k < frac_digits; ++k) s += static_cast<char>('0' + next() % 10);
    if (next() % 16 == 0) s += "e3";
    if (next() % 16 == 0) s += ",1";
    double fast = 0.0, reference = 0.0;
    const char* end = s.data() + s.size();
    const char* p = internal::parse_short_decimal(s.data(), end, fast);
    const auto [q, ec] = std::from_chars(s.data(), end, reference);
    if (p == nullptr) continue;
    ++accepted;
    ASSERT_EQ(ec, std::errc()) << s;
    ASSERT_EQ(p, q) << s;
    ASSERT_EQ(std::bit_cast<std::uint64_t>(fast), std::bit_cast<std::uint64_t>(reference)) << s;
  }
  EXPECT_GT(accepted, 100000);
  double v = 0.0;
  const std::string long_one = "0.1234567890123456";  // 16 digits: not for the fast path
  EXPECT_EQ(internal::parse_short_decimal(long_one.data(), long_one.data() + long_one.size(), v),
            nullptr);
}
