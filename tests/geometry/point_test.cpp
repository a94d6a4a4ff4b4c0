// validate_profile: one test per precondition, checking the exception and its message.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "internal/isa.h"
#include "vcmm/geometry/point.h"

namespace {

using vcmm::geometry::InvalidInput;
using vcmm::geometry::Point2;
using vcmm::geometry::validate_profile;

std::string message_of(const std::vector<Point2>& pts, std::size_t min_points,
                       bool non_collinear = true) {
  try {
    validate_profile(pts, min_points, "fit", non_collinear);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

TEST(ValidateProfile, AcceptsAGoodProfileAndDuplicates) {
  EXPECT_EQ(message_of({{0, 0}, {1, 0}, {0, 1}}, 3), "");
  EXPECT_EQ(message_of({{0, 0}, {0, 0}, {1, 0}, {0, 1}, {0, 0}}, 3), "");
}

TEST(ValidateProfile, RejectsTooFewPoints) {
  EXPECT_EQ(message_of({}, 3), "fit: needs at least 3 points; got 0");
  EXPECT_EQ(message_of({{0, 0}, {1, 1}}, 3), "fit: needs at least 3 points; got 2");
}

TEST(ValidateProfile, RejectsNonFiniteAndNamesTheIndex) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_NE(message_of({{0, 0}, {1, 0}, {nan, 1}}, 3).find("point 2 has a non-finite"),
            std::string::npos);
  EXPECT_NE(message_of({{0, 0}, {1, -inf}, {0, 1}}, 3).find("point 1"), std::string::npos);
}

// The finiteness pass runs in blocks (16 doubles a step with SSE2, 32 with AVX-512) and a
// tail: a bad coordinate in any position of either, at every ISA level, is found and named;
// large finite values (whose products with 0 are 0) and −0 are accepted.
TEST(ValidateProfile, FindsANonFiniteCoordinateAtEveryPositionAndIsaLevel) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  using vcmm::geometry::internal::IsaLevel;
  for (const IsaLevel isa : {IsaLevel::avx512, IsaLevel::avx2, IsaLevel::baseline}) {
    const vcmm::geometry::internal::LimitIsa limit(isa);
    for (std::size_t n : {3u, 8u, 15u, 16u, 17u, 33u, 64u, 101u}) {
      std::vector<Point2> pts;
      for (std::size_t i = 0; i < n; ++i)
        pts.push_back({std::cos(0.1 * static_cast<double>(i)) * 1e300,
                       -0.0 + std::sin(0.1 * static_cast<double>(i))});
      ASSERT_EQ(message_of(pts, 3), "") << n;
      for (std::size_t at = 0; at < n; ++at) {
        for (const double bad : {nan, inf, -inf}) {
          for (int coordinate = 0; coordinate < 2; ++coordinate) {
            std::vector<Point2> p = pts;
            (coordinate == 0 ? p[at].x : p[at].y) = bad;
            EXPECT_NE(message_of(p, 3).find("point " + std::to_string(at) + " has a non-finite"),
                      std::string::npos)
                << n << " " << at << " " << static_cast<int>(isa);
          }
        }
      }
    }
  }
}

TEST(ValidateProfile, RejectsIdenticalPoints) {
  EXPECT_NE(message_of({{2, 3}, {2, 3}, {2, 3}}, 3).find("all 3 points are identical"),
            std::string::npos);
}

TEST(ValidateProfile, RejectsCollinearPointsExactly) {
  // Exactly collinear in doubles: multiples of a representable direction.
  std::vector<Point2> line;
  for (int i = 0; i < 50; ++i) line.push_back({0.5 * i, 0.25 * i});
  EXPECT_NE(message_of(line, 3).find("collinear"), std::string::npos);
  EXPECT_EQ(message_of(line, 3, /*non_collinear=*/false), "");
  // One point off the line by the smallest representable amount is accepted.
  line.push_back({1.0, std::nextafter(0.5, 1.0)});
  EXPECT_EQ(message_of(line, 3), "");
}

}  // namespace
