// An outside project using the installed package (vcmm::vcmm, every module):
// 1. the minimum-zone circle of four points against the analytic answer: inner pair (±1, 0),
//    outer pair (0, ±1.1), alternating about the origin: centre (0, 0), RONt = 0.1;
// 2. a Monte Carlo run of Y = X1 + X2 (standard normals): u = √2 within 5 standard errors;
// 3. an E_n by hand: (10 − 9) / (2·√(0.3² + 0.4²)) = 1.
#include <cmath>
#include <cstdio>
#include <vector>

#include <vcmm/geometry/minimum_zone.h>
#include <vcmm/uncertainty/monte_carlo.h>
#include <vcmm/validation/comparison.h>

int main() {
  using vcmm::geometry::Point2;
  const std::vector<Point2> pts{{1.0, 0.0}, {0.0, 1.1}, {-1.0, 0.0}, {0.0, -1.1}};
  const auto mz = vcmm::geometry::minimum_zone_circle(pts);
  const bool mz_ok = std::abs(mz.center.x) < 1e-15 && std::abs(mz.center.y) < 1e-15 &&
                     std::abs(mz.ron.ront - 0.1) < 1e-15 && verify(pts, mz).valid;

  vcmm::uncertainty::MonteCarloOptions o;
  o.trials = 20000;
  o.seed = 3;
  const auto mc = vcmm::uncertainty::run_monte_carlo(
      [](vcmm::uncertainty::RandomStream& rng, std::span<double> y) {
        y[0] = rng.standard_normal() + rng.standard_normal();
      },
      1, o);
  const double u = mc.summaries[0].standard_uncertainty;
  // Standard error of a sample sd: u/√(2(M−1)) = 0.5 %; allow 5 of them.
  const bool mc_ok = std::abs(u - std::sqrt(2.0)) < 5 * std::sqrt(2.0) / std::sqrt(2.0 * 19999);

  const bool en_ok = std::abs(vcmm::validation::en_score(10.0, 0.3, 9.0, 0.4) - 1.0) < 1e-15;
  std::printf("consumer: MZ RONt = %.17g (%d), MC u = %.6f (%d), E_n (%d)\n", mz.ron.ront,
              mz_ok ? 1 : 0, u, mc_ok ? 1 : 0, en_ok ? 1 : 0);
  return mz_ok && mc_ok && en_ok ? 0 : 1;
}
