// validate_profile: one test per precondition, checking the exception and its message.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

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
