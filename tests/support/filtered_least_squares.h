// tests/support/filtered_least_squares.h — the expectation shared by the tests of the
// filtered profile's LS circle (the filter's one-step circle on its rays, and
// evaluate_roundness, which takes it): equal to the full fit of the filtered points to a
// tolerance. Header-only (GoogleTest expectations).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <vector>

#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/point.h"

namespace vcmm::test {

/// The filtered profile's LS circle from the filter against the full fit of its points:
/// centre and radius within `tol` mm, RONt/RONp/RONv/RONq within `tol`; the contacts are the
/// same points or points whose residuals differ by at most `tol`.
inline void expect_same_least_squares(const geometry::LeastSquaresCircle& on_rays,
                                      const std::vector<geometry::Point2>& filtered,
                                      double tol) {
  const geometry::LeastSquaresCircle full = geometry::least_squares_circle(filtered);
  EXPECT_NEAR(on_rays.center.x, full.center.x, tol);
  EXPECT_NEAR(on_rays.center.y, full.center.y, tol);
  EXPECT_NEAR(on_rays.radius, full.radius, tol);
  EXPECT_NEAR(on_rays.ron.ront, full.ron.ront, tol);
  EXPECT_NEAR(on_rays.ron.ronp, full.ron.ronp, tol);
  EXPECT_NEAR(on_rays.ron.ronv, full.ron.ronv, tol);
  EXPECT_NEAR(on_rays.ron.ronq, full.ron.ronq, tol);
  ASSERT_EQ(on_rays.contacts.size(), 2u);
  const auto residual = [&](std::size_t i) {
    return std::hypot(filtered[i].x - full.center.x, filtered[i].y - full.center.y) - full.radius;
  };
  for (std::size_t k = 0; k < 2; ++k)
    EXPECT_NEAR(residual(on_rays.contacts[k]), residual(full.contacts[k]), tol) << k;
}

}  // namespace vcmm::test
