// Accuracy of least_squares_circle against NIST's Algorithm Testing System Circle2d sets:
// 30 public data sets with least-squares reference fits computed in 60-digit arithmetic
// (../shared/data/nist-circle2d, see its README). The sets cover full circles, ~90° and
// ~180° arcs and sparse 3-5 point sets, with centres up to ~900 mm from the origin.
//
// The reference centre and diameter are parsed as long double (64-bit significand), so the
// reported differences are not limited by rounding the reference to double (½ ulp of an
// 811 mm coordinate is 5.7e-14 mm). The floor of any double-precision fitter is set by the
// input itself: the 5-decimal data are rounded to double (up to 5.7e-14 mm per coordinate
// at 900 mm from the origin), which moves the exact LS fit of the double data by ~1e-13 mm
// on the far, short-arc sets.
//
// The data are located through VCMM_SHARED_DATA_DIR (tests/CMakeLists.txt); a clone without
// the shared data directory skips these tests with a message.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "vcmm/geometry/certificate.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/roundness.h"

namespace {

using vcmm::geometry::least_squares_circle;
using vcmm::geometry::LeastSquaresCircle;
using vcmm::geometry::Point2;

constexpr int kSetCount = 30;

/// Differences from the reference (mm) accepted per set. Observed (GCC 12, x86-64): centre
/// ≤ 7.8e-14 mm, diameter ≤ 1.38e-13 mm, both on set 2 (a 90° arc of radius 3.9 mm), where a
/// 50-digit fit of the double-rounded input itself differs from the reference by 7.5e-14 and
/// 1.39e-13 mm: the fitter is at the input-rounding floor. 4e-13 mm leaves room for another
/// compiler's rounding without hiding a real regression (a lost iteration or an unshifted
/// sum costs 1e-10 mm or more on these sets).
constexpr long double kCenterToleranceMm = 4e-13L;
constexpr long double kDiameterToleranceMm = 4e-13L;

std::filesystem::path nist_dir() {
  return std::filesystem::path(VCMM_SHARED_DATA_DIR) / "nist-circle2d";
}

/// All whitespace-separated tokens of a file parsed as long double; fails the test (and
/// returns false) on a token that is not a complete number. Tolerates CR line ends, blank
/// lines and trailing blanks.
bool read_numbers(const std::filesystem::path& path, std::vector<long double>& out) {
  std::ifstream in(path);
  if (!in) {
    ADD_FAILURE() << "cannot open " << path;
    return false;
  }
  std::string token;
  std::size_t index = 0;
  while (in >> token) {
    ++index;
    const char* begin = token.c_str();
    char* end = nullptr;
    const long double v = std::strtold(begin, &end);
    if (end == begin || *end != '\0' || !std::isfinite(v)) {
      ADD_FAILURE() << path << ": token " << index << " is not a finite number: '" << token
                    << "'";
      return false;
    }
    out.push_back(v);
  }
  return true;
}

struct NistSet {
  int id = 0;
  std::vector<Point2> points;
  long double center[2] = {0.0L, 0.0L};  // the two in-plane coordinates, in x, y, z order
  long double diameter = 0.0L;
  double arc_span_deg = 0.0;  // angular coverage about the reference centre
};

/// Reads cir2d<id>.ds / .fit. The .ds file: point count, then x y z per point; the .fit file:
/// centre x y z, normal x y z, diameter. The coordinate along the normal is constant and
/// dropped.
bool load_set(int id, NistSet& set) {
  set.id = id;
  const auto base = nist_dir() / ("cir2d" + std::to_string(id));
  std::vector<long double> ds, fit;
  if (!read_numbers(base.string() + ".ds", ds) || !read_numbers(base.string() + ".fit", fit))
    return false;
  if (ds.empty() || ds[0] < 3 || ds[0] != std::floor(ds[0])) {
    ADD_FAILURE() << base << ".ds: first value must be a point count >= 3";
    return false;
  }
  const auto n = static_cast<std::size_t>(ds[0]);
  if (ds.size() != 1 + 3 * n) {
    ADD_FAILURE() << base << ".ds: header says " << n << " points but the file holds "
                  << ds.size() - 1 << " numbers (expected " << 3 * n << ")";
    return false;
  }
  if (fit.size() != 7) {
    ADD_FAILURE() << base << ".fit: expected 7 numbers (centre, normal, diameter), got "
                  << fit.size();
    return false;
  }
  int normal_axis = 0;
  for (int a = 1; a < 3; ++a)
    if (std::fabs(fit[3 + a]) > std::fabs(fit[3 + normal_axis])) normal_axis = a;
  int axes[2], k = 0;
  for (int a = 0; a < 3; ++a)
    if (a != normal_axis) axes[k++] = a;
  set.points.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const long double* row = &ds[1 + 3 * i];
    if (row[normal_axis] != ds[1 + normal_axis]) {
      ADD_FAILURE() << base << ".ds: point " << i << " leaves the plane normal to axis "
                    << normal_axis;
      return false;
    }
    set.points.push_back({static_cast<double>(row[axes[0]]), static_cast<double>(row[axes[1]])});
  }
  set.center[0] = fit[static_cast<std::size_t>(axes[0])];
  set.center[1] = fit[static_cast<std::size_t>(axes[1])];
  set.diameter = fit[6];
  // Angular coverage: 360° minus the largest gap between consecutive point angles.
  std::vector<double> angles;
  for (const Point2& p : set.points)
    angles.push_back(std::atan2(static_cast<double>(p.y - set.center[1]),
                                static_cast<double>(p.x - set.center[0])));
  std::sort(angles.begin(), angles.end());
  double gap = angles.front() + 2 * std::numbers::pi - angles.back();
  for (std::size_t i = 1; i < angles.size(); ++i) gap = std::max(gap, angles[i] - angles[i - 1]);
  set.arc_span_deg = 360.0 - gap * 180.0 / std::numbers::pi;
  return true;
}

struct SetError {
  long double center_mm = 0.0L;    // |c − c_ref|
  long double diameter_mm = 0.0L;  // |2R − D_ref|
};

std::string scientific(double v) {
  std::ostringstream os;
  os << std::scientific << std::setprecision(3) << v;
  return os.str();
}

SetError compare(const NistSet& set, const LeastSquaresCircle& fit) {
  SetError e;
  const long double ex = static_cast<long double>(fit.center.x) - set.center[0];
  const long double ey = static_cast<long double>(fit.center.y) - set.center[1];
  e.center_mm = std::sqrt(ex * ex + ey * ey);
  e.diameter_mm = std::fabs(2.0L * static_cast<long double>(fit.radius) - set.diameter);
  return e;
}

#define VCMM_SKIP_WITHOUT_NIST_DATA()                                                   \
  do {                                                                                  \
    if (!std::filesystem::is_directory(nist_dir()))                                     \
      GTEST_SKIP() << "NIST Circle2d reference data not found at " << nist_dir()        \
                   << " (it lives in the shared data directory beside the repository, " \
                      "not in a clone); accuracy test skipped";                         \
  } while (false)

class NistCircle2d : public ::testing::TestWithParam<int> {};

TEST_P(NistCircle2d, ReproducesReferenceFit) {
  VCMM_SKIP_WITHOUT_NIST_DATA();
  NistSet set;
  ASSERT_TRUE(load_set(GetParam(), set));
  const LeastSquaresCircle fit = least_squares_circle(set.points);
  const SetError e = compare(set, fit);
  EXPECT_LT(e.center_mm, kCenterToleranceMm)
      << "set " << set.id << " (" << set.points.size() << " points, " << set.arc_span_deg
      << "° arc)";
  EXPECT_LT(e.diameter_mm, kDiameterToleranceMm)
      << "set " << set.id << " (" << set.points.size() << " points, " << set.arc_span_deg
      << "° arc)";
  EXPECT_GE(fit.iterations, 1);
  EXPECT_LE(fit.iterations, 20);
}

INSTANTIATE_TEST_SUITE_P(AllSets, NistCircle2d, ::testing::Range(1, kSetCount + 1),
                         [](const ::testing::TestParamInfo<int>& param_info) {
                           return "cir2d" + std::to_string(param_info.param);
                         });

// One table over all sets, with the worst case recorded as test properties (visible in the
// XML output) and printed.
TEST(NistCircle2dSummary, WorstCaseOverAllSets) {
  VCMM_SKIP_WITHOUT_NIST_DATA();
  long double worst_center = 0.0L, worst_diameter = 0.0L;
  int worst_center_set = 0, worst_diameter_set = 0;
  std::ostringstream table;
  table << "set     n   arc_deg  radius_mm  iter  |dc|_nm      |dD|_nm\n";
  for (int id = 1; id <= kSetCount; ++id) {
    NistSet set;
    ASSERT_TRUE(load_set(id, set));
    const LeastSquaresCircle fit = least_squares_circle(set.points);
    const SetError e = compare(set, fit);
    table << std::setw(3) << id << std::setw(6) << set.points.size() << std::fixed
          << std::setprecision(1) << std::setw(10) << set.arc_span_deg << std::setprecision(4)
          << std::setw(11) << fit.radius << std::setw(6) << fit.iterations
          << std::scientific << std::setprecision(2) << std::setw(13)
          << static_cast<double>(e.center_mm * 1e6L) << std::setw(13)
          << static_cast<double>(e.diameter_mm * 1e6L) << std::defaultfloat << "\n";
    if (e.center_mm > worst_center) {
      worst_center = e.center_mm;
      worst_center_set = id;
    }
    if (e.diameter_mm > worst_diameter) {
      worst_diameter = e.diameter_mm;
      worst_diameter_set = id;
    }
  }
  const double worst_center_nm = static_cast<double>(worst_center * 1e6L);
  const double worst_diameter_nm = static_cast<double>(worst_diameter * 1e6L);
  std::cout << table.str() << "worst centre difference " << worst_center_nm << " nm (set "
            << worst_center_set << "), worst diameter difference " << worst_diameter_nm
            << " nm (set " << worst_diameter_set << ")\n";
  RecordProperty("worst_center_nm", scientific(worst_center_nm));
  RecordProperty("worst_center_set", worst_center_set);
  RecordProperty("worst_diameter_nm", scientific(worst_diameter_nm));
  RecordProperty("worst_diameter_set", worst_diameter_set);
  EXPECT_LT(worst_center, kCenterToleranceMm);
  EXPECT_LT(worst_diameter, kDiameterToleranceMm);
}

// Every set evaluated for all four circles at once: each circle is either defined (and its
// certificate verifies, LS at the reference) or undefined with a reason — one undefined circle
// (MI of the sparse and partial sets) never takes the others down. The coverage agrees with the
// set's own arc span (about the LS centre rather than the reference centre: to 1e-6°).
TEST(NistCircle2dPerCircle, EveryCircleDefinedOrExplained) {
  VCMM_SKIP_WITHOUT_NIST_DATA();
  int undefined = 0;
  for (int id = 1; id <= kSetCount; ++id) {
    NistSet set;
    ASSERT_TRUE(load_set(id, set));
    const auto e = vcmm::geometry::evaluate_roundness(set.points, {});
    ASSERT_TRUE(e.least_squares.has_value()) << id;
    EXPECT_LT(compare(set, *e.least_squares).diameter_mm, kDiameterToleranceMm) << id;
    EXPECT_GE(e.defined_count(), 2u) << "set " << id;  // LS and MC always exist
    EXPECT_EQ(e.defined_count() + e.undefined.size(), 4u) << "set " << id;
    for (const auto& [circle, reason] : e.undefined) {
      EXPECT_FALSE(reason.empty()) << "set " << id;
      ++undefined;
    }
    if (e.minimum_zone) {
      EXPECT_TRUE(vcmm::geometry::verify(set.points, *e.minimum_zone).valid) << id;
    }
    if (e.maximum_inscribed) {
      EXPECT_TRUE(vcmm::geometry::verify(set.points, *e.maximum_inscribed).valid) << id;
    }
    if (e.minimum_circumscribed) {
      EXPECT_TRUE(vcmm::geometry::verify(set.points, *e.minimum_circumscribed).valid) << id;
    }
    EXPECT_NEAR(e.coverage.covered_rad * 180.0 / std::numbers::pi, set.arc_span_deg, 1e-6) << id;
    EXPECT_EQ(e.cautions.count(vcmm::geometry::ReferenceCircle::maximum_inscribed) +
                  e.cautions.count(vcmm::geometry::ReferenceCircle::minimum_circumscribed) > 0,
              set.arc_span_deg < 180.0 && e.defined_count() > 2)
        << id;
  }
  // Sets 2, 3, 5 and 7 (sparse or partial) made the whole evaluation fail before.
  EXPECT_GE(undefined, 4);
}

}  // namespace
