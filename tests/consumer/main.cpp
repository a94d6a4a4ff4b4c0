// Fits the minimum-zone circle of four points through the installed package and checks the
// analytic answer: inner pair (±1, 0), outer pair (0, ±1.1), alternating about the origin:
// centre (0, 0), r = 1, R = 1.1, RONt = 0.1 (to within the rounding of 1.1).
#include <cmath>
#include <cstdio>
#include <vector>

#include <vcmm/geometry/minimum_zone.h>

int main() {
  using vcmm::geometry::Point2;
  const std::vector<Point2> pts{{1.0, 0.0}, {0.0, 1.1}, {-1.0, 0.0}, {0.0, -1.1}};
  const auto mz = vcmm::geometry::minimum_zone_circle(pts);
  const bool ok = std::abs(mz.center.x) < 1e-15 && std::abs(mz.center.y) < 1e-15 &&
                  std::abs(mz.ron.ront - 0.1) < 1e-15 && verify(pts, mz).valid;
  std::printf("consumer: MZ RONt = %.17g, certified = %d\n", mz.ron.ront, ok ? 1 : 0);
  return ok ? 0 : 1;
}
