// internal/inscribed_lp.h — the linearised program behind the maximum-inscribed (MI) fast
// path: the largest circle about a centre near c0 that no candidate point enters, to first
// order. Not part of the public API; a search heuristic only — every result it suggests is
// re-derived exactly by the caller.
//
// Notation (scaled units: lengths × σ, σ a power of two making the profile O(1)):
//   ρ_i = |c0 − p_i|, e_i = (c0 − p_i)/ρ_i,  |c0 + δ − p_i| = ρ_i + e_i·δ + O(|δ|²/2ρ_i).
// Primal:  max r  s.t.  r − e_i·δ ≤ ρ_i  (every candidate i), over (δ, r) — the Chebyshev-
// centre LP of the linearised distances. Costs are taken relative to a shift s:
// c_i = ρ_i − s; when the candidates' radii spread less than 2¹²u·ρ they are computed as
// (ρ_i² − s²)/(ρ_i + s) with the numerator in double-double (internal/precise_distance.h),
// so the program still ranks points whose radii differ by 1e-16 relative (perfect circles,
// ulp-level forms), where the floating Voronoi walk it replaces saw only rounding noise.
// Dual:  min Σ μ_i c_i  s.t.  Σ μ_i (−e_i, 1) = (0, 0, 1),  μ ≥ 0 — three rows; a basis is
// three candidates whose directions e_i hold 0 in their triangle (μ_B ≥ 0), i.e. a
// surrounded vertex of the linearised Voronoi diagram. Revised simplex on the dual with a
// 3×3 basis inverse: entering column = least reduced cost c_j − a_j·y (the candidate the
// model circle enters deepest), y = (δ, r − s) = B⁻ᵀ c_B; Bland's rule after runs of
// degenerate pivots (co-circular candidates).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "vcmm/geometry/point.h"

namespace vcmm::geometry::internal {

class InscribedLp {
 public:
  /// `scale` is σ (a power of two); the points are kept by reference.
  InscribedLp(std::span<const Point2> points, double scale);

  /// Adds candidate point i (no effect when already a candidate).
  void add(std::size_t i);
  /// Whether point i is a candidate already.
  bool contains(std::size_t i) const { return in_[i] != 0; }

  /// Linearises every candidate at c0 (input coordinates) and solves, warm-started from
  /// the previous basis when it is still feasible. False when no three candidates surround
  /// c0 (partial arcs) or on numerical failure.
  bool solve(Point2 c0);

  /// The model's optimum: centre offset δ (input units) and the basis points.
  Point2 delta() const;
  std::array<std::size_t, 3> basis_points() const;
  /// Linearisation error bound |δ|²/(2 ρ_min) relative to the costs' magnitude: re-solve
  /// at c0 + δ while this exceeds ~1e-3 (the model may misorder near-ties below it).
  double relative_linearisation_error() const;
  /// Costs in double-double from the next solve on, whatever their spread: the caller saw the
  /// plain program stall (the same basis again after adding exact violators, which its
  /// rounded costs cannot tell from the contacts).
  void force_precise() { forced_ = true; }

  /// Least candidate distance ρ_min (input units).
  double rho_min() const { return rho_min_ / scale_; }

 private:
  struct Column {
    std::size_t point = 0;
    double cost = 0.0, ex = 0.0, ey = 0.0;
  };
  bool set_basis(const std::array<std::size_t, 3>& b);
  bool feasible_start();
  int pivot(bool bland);
  double tolerance() const;

  std::span<const Point2> points_;
  double scale_ = 1.0;
  std::vector<std::uint8_t> in_;
  std::vector<Column> cols_;
  std::vector<double> rho_;  ///< solve's scratch (kept: no allocation per round)
  double shift_ = 0.0, rho_min_ = 0.0, rho_max_ = 0.0, cost_scale_ = 0.0;
  bool precise_ = false;  ///< costs in double-double (candidates' radii within 2¹²u·ρ)
  bool forced_ = false;   ///< precise costs requested by the caller
  std::array<std::size_t, 3> basis_{};
  bool have_basis_ = false;
  std::array<std::array<double, 3>, 3> binv_{};  ///< B⁻¹
  std::array<double, 3> mu_{}, y_{};
};

}  // namespace vcmm::geometry::internal
