// internal/inscribed_lp.cpp — the linearised maximum-inscribed program (derivation in
// internal/inscribed_lp.h).
#include "internal/inscribed_lp.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "internal/precise_distance.h"

namespace vcmm::geometry::internal {

namespace {
constexpr double kU = 0x1.0p-53;
/// Costs switch to double-double below this many u·ρ of spread (as MZ's pricing: 2¹²u·ρ
/// ≈ 4e-11 mm at 85 mm).
constexpr double kPreciseCosts = 4096.0;
}  // namespace

InscribedLp::InscribedLp(std::span<const Point2> points, double scale)
    : points_(points), scale_(scale), in_(points.size(), 0) {
  cols_.reserve(128);  // the sample's nearest points, refinements, a round of violators
}

void InscribedLp::add(std::size_t i) {
  if (in_[i] != 0) return;
  in_[i] = 1;
  cols_.push_back({i, 0.0, 0.0, 0.0});
}

bool InscribedLp::solve(Point2 c0) {
  if (cols_.size() < 3) return false;
  rho_min_ = std::numeric_limits<double>::infinity();
  rho_max_ = 0.0;
  std::vector<double>& rho = rho_;
  rho.resize(cols_.size());
  for (std::size_t k = 0; k < cols_.size(); ++k) {
    Column& c = cols_[k];
    const double dx = (c0.x - points_[c.point].x) * scale_;
    const double dy = (c0.y - points_[c.point].y) * scale_;
    rho[k] = std::sqrt(dx * dx + dy * dy);
    if (!(rho[k] > 0.0) || !std::isfinite(rho[k])) return false;  // c0 on a point
    c.ex = dx / rho[k];
    c.ey = dy / rho[k];
    rho_min_ = std::min(rho_min_, rho[k]);
    rho_max_ = std::max(rho_max_, rho[k]);
  }
  shift_ = 0.5 * (rho_min_ + rho_max_);
  // Plain costs ρ − s carry ~u·ρ of rounding: enough unless the candidates' radii spread
  // less than 2¹²u·ρ (perfect circles, ulp-level forms); then ρ − s = (ρ² − s²)/(ρ + s) with
  // the numerator in double-double.
  cost_scale_ = 0.0;
  for (std::size_t k = 0; k < cols_.size(); ++k) {
    cols_[k].cost = rho[k] - shift_;
    cost_scale_ = std::max(cost_scale_, std::abs(cols_[k].cost));
  }
  precise_ = forced_ || cost_scale_ < kPreciseCosts * kU * rho_max_;
  if (precise_) {
    cost_scale_ = 0.0;
    for (std::size_t k = 0; k < cols_.size(); ++k) {
      cols_[k].cost =
          precise_power(points_[cols_[k].point], c0, shift_, scale_) / (rho[k] + shift_);
      cost_scale_ = std::max(cost_scale_, std::abs(cols_[k].cost));
    }
  }
  if (!(have_basis_ && set_basis(basis_)) && !feasible_start()) return false;
  int degenerate_run = 0;
  for (int pivots = 0; pivots < 1000; ++pivots) {
    const int step = pivot(degenerate_run > 8);
    if (step < 0) return false;
    if (step == 0) return true;
    degenerate_run = step == 2 ? degenerate_run + 1 : 0;
  }
  return false;
}

Point2 InscribedLp::delta() const { return {y_[0] / scale_, y_[1] / scale_}; }

std::array<std::size_t, 3> InscribedLp::basis_points() const {
  return {cols_[basis_[0]].point, cols_[basis_[1]].point, cols_[basis_[2]].point};
}

double InscribedLp::relative_linearisation_error() const {
  const double step2 = y_[0] * y_[0] + y_[1] * y_[1];
  const double err = step2 / (2.0 * rho_min_);
  return err / std::max(cost_scale_, 64.0 * kU * rho_max_);
}

/// Column a_j = (−e_j, 1). The 3×3 inverse by cofactors (the basis is tiny and refactored
/// at every pivot).
bool InscribedLp::set_basis(const std::array<std::size_t, 3>& b) {
  std::array<std::array<double, 3>, 3> m{};  // m[r][j]: row r of column j
  for (std::size_t j = 0; j < 3; ++j) {
    const Column& c = cols_[b[j]];
    m[0][j] = -c.ex;
    m[1][j] = -c.ey;
    m[2][j] = 1.0;
  }
  std::array<std::array<double, 3>, 3> inv{};
  for (std::size_t r = 0; r < 3; ++r)
    for (std::size_t j = 0; j < 3; ++j) {
      // inv[r][j] = cofactor(j, r) / det
      const std::size_t r1 = (j + 1) % 3, r2 = (j + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
      inv[r][j] = m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1];
    }
  const double det = m[0][0] * inv[0][0] + m[0][1] * inv[1][0] + m[0][2] * inv[2][0];
  // Directions are unit vectors: a determinant below 1e-14 means three nearly parallel or
  // coincident directions, useless as a basis.
  if (!(std::abs(det) >= 1e-14) || !std::isfinite(det)) return false;
  for (auto& row : inv)
    for (double& v : row) v /= det;
  // μ = B⁻¹(0, 0, 1): the last column; 0 must be in the triangle of directions.
  std::array<double, 3> mu{inv[0][2], inv[1][2], inv[2][2]};
  if (std::min({mu[0], mu[1], mu[2]}) < -1e-9) return false;
  basis_ = b;
  have_basis_ = true;
  binv_ = inv;
  for (std::size_t r = 0; r < 3; ++r) mu_[r] = std::max(mu[r], 0.0);
  // y = B⁻ᵀ c_B.
  for (std::size_t r = 0; r < 3; ++r)
    y_[r] = inv[0][r] * cols_[b[0]].cost + inv[1][r] * cols_[b[1]].cost +
            inv[2][r] * cols_[b[2]].cost;
  return true;
}

/// A first feasible basis: i = the nearest candidate, then j, k the candidates whose
/// directions come nearest to e_i turned by 120° and 240° (a fat triangle of directions
/// around 0 on round data; an exactly antipodal pair, as symmetric data give, would make a
/// degenerate one); if 0 is not inside that triangle, the pair (j, k) putting 0 deepest
/// inside (largest least barycentric weight), O(m²).
bool InscribedLp::feasible_start() {
  std::size_t i = 0;
  for (std::size_t c = 1; c < cols_.size(); ++c)
    if (cols_[c].cost < cols_[i].cost) i = c;
  const auto cross = [&](std::size_t a, std::size_t b) {
    return cols_[a].ex * cols_[b].ey - cols_[a].ey * cols_[b].ex;
  };
  // Least barycentric weight of 0 in the triangle of directions (i, j, k): signed areas.
  const auto least_weight = [&](std::size_t a, std::size_t b, std::size_t k) {
    const double wa = cross(b, k), wb = cross(k, a), wk = cross(a, b);
    const double total = wa + wb + wk;
    return total != 0.0 ? std::min({wa, wb, wk}) / total : -1.0;
  };
  std::array<std::size_t, 3> pick{i, i, i};
  {
    const double c120 = -0.5, s120 = 0.8660254037844386;  // cos, sin of 120°
    const Column& e = cols_[i];
    const std::array<std::array<double, 2>, 2> target{
        {{c120 * e.ex - s120 * e.ey, s120 * e.ex + c120 * e.ey},
         {c120 * e.ex + s120 * e.ey, -s120 * e.ex + c120 * e.ey}}};
    std::array<double, 2> best{-2.0, -2.0};
    for (std::size_t c = 0; c < cols_.size(); ++c)
      for (std::size_t t = 0; t < 2; ++t) {
        const double d = cols_[c].ex * target[t][0] + cols_[c].ey * target[t][1];
        if (c != i && d > best[t]) {
          best[t] = d;
          pick[t + 1] = c;
        }
      }
  }
  if (pick[1] != pick[2] && pick[1] != i && least_weight(i, pick[1], pick[2]) > 0.0 &&
      set_basis(pick))
    return true;
  double weight = 0.0;
  pick = {i, i, i};
  for (std::size_t a = 0; a < cols_.size(); ++a)
    for (std::size_t b = a + 1; b < cols_.size(); ++b) {
      if (a == i || b == i) continue;
      const double w = least_weight(i, a, b);
      if (w > weight) {
        weight = w;
        pick = {i, a, b};
      }
    }
  return pick[1] != i && set_basis(pick);
}

/// Ties below the costs' resolution are left to the exact stage. Plain costs carry ~u·ρ:
/// 64u·ρ_max. Precise costs: reduced costs combine a cost (≤ cost_scale_) with unit
/// directions times y, each rounded: 64u of their magnitudes, plus the costs' own error (a
/// few u² of ρ).
double InscribedLp::tolerance() const {
  if (!precise_) return 64.0 * kU * rho_max_;
  return 64.0 * kU * (cost_scale_ + std::abs(y_[0]) + std::abs(y_[1]) + std::abs(y_[2])) +
         1024.0 * kU * kU * rho_max_;
}

/// One step: 0 optimal, 1 step, 2 degenerate step, −1 failure.
int InscribedLp::pivot(bool bland) {
  const double tol = tolerance();
  std::size_t entering = cols_.size();
  double best = -tol;
  for (std::size_t c = 0; c < cols_.size(); ++c) {
    const Column& col = cols_[c];
    const double rc = col.cost + col.ex * y_[0] + col.ey * y_[1] - y_[2];
    if (rc < best) {
      if (std::find(basis_.begin(), basis_.end(), c) != basis_.end()) continue;
      best = rc;
      entering = c;
      if (bland) break;
    }
  }
  if (entering == cols_.size()) return 0;
  const Column& e = cols_[entering];
  const std::array<double, 3> a{-e.ex, -e.ey, 1.0};
  std::array<double, 3> d{};
  for (std::size_t r = 0; r < 3; ++r)
    d[r] = binv_[r][0] * a[0] + binv_[r][1] * a[1] + binv_[r][2] * a[2];
  int leave = -1;
  double theta = std::numeric_limits<double>::infinity();
  for (int r = 0; r < 3; ++r) {
    const auto ru = static_cast<std::size_t>(r);
    if (d[ru] <= 1e-12) continue;
    const double t = mu_[ru] / d[ru];
    if (t < theta - 1e-15 || (t <= theta + 1e-15 && leave >= 0 &&
                              d[ru] > d[static_cast<std::size_t>(leave)])) {
      theta = std::min(theta, t);
      leave = r;
    }
  }
  if (leave < 0) return -1;  // unbounded dual: cannot happen with Σμ = 1
  std::array<std::size_t, 3> next = basis_;
  next[static_cast<std::size_t>(leave)] = entering;
  if (!set_basis(next)) return -1;
  return theta <= 1e-15 ? 2 : 1;
}

}  // namespace vcmm::geometry::internal
