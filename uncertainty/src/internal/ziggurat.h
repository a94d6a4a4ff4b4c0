// uncertainty/src/internal/ziggurat.h — the tables of the 256-layer normal ziggurat used by
// RandomStream::standard_normal (docs/uncertainty.md, "Normal variates").
//
// Notation (unnormalised density f(x) = exp(−x²/2), x ≥ 0; N = 256 layers of equal area v):
//   x[1] = r, the start of the tail;  v = r·f(r) + T(r),  T(r) = ∫_r^∞ f(t) dt;
//   x[0] = v / f(r)                     (the base layer: rectangle [0, r]×[0, f(r)] + tail,
//                                        sampled as a box of width x[0]);
//   x[i+1] = f⁻¹(v / x[i] + f(x[i])) = √(−2 ln(v / x[i] + f(x[i]))),  i = 1 … N − 2;
//   x[N] = 0, f(x[N]) = 1.
// Layer i ≥ 1 is the box [0, x[i]] × [f(x[i]), f(x[i+1])] of area v; r is the root of the
// closure condition  c(r) = v / x[N−1] + f(x[N−1]) − 1 = 0  (the top layer has area v too),
// found by bisection on doubles until the bracket cannot shrink. T(r) comes from Laplace's
// continued fraction for the Mills ratio, T(r) = f(r) / (r + 1/(r + 2/(r + 3/(r + …)))),
// evaluated bottom-up with 2 000 terms (converged to < 1 ulp for r > 3; it is checked
// against std::erfc in the tests). exp/log are the portable ones (portable_math.h), so the
// tables are the same bits everywhere. Result: r = 3.65415288536101, v = 4.928673233992e-3,
// as published by Marsaglia & Tsang (2000) to their 12–17 digits (tested).
#pragma once

#include <array>
#include <cstddef>

namespace vcmm::uncertainty::internal {

struct ZigguratTables {
  static constexpr int layers = 256;
  double r = 0.0;  ///< start of the tail
  double v = 0.0;  ///< area of every layer
  double closure_residual = 0.0;     ///< c(r) at the chosen r (≈ 1e-16)
  std::array<double, layers + 1> x{};  ///< x[0] = v/f(r), x[1] = r, …, x[N] = 0
  std::array<double, layers + 1> f{};  ///< f[i] = exp(−x[i]²/2), f[N] = 1
};

/// ∫_r^∞ exp(−t²/2) dt for r ≥ 1 (continued fraction above; relative error ~1e-16).
double gaussian_tail_area(double r);

/// Computes the tables from scratch (bisection; ~0.5 ms).
ZigguratTables compute_ziggurat_tables();

/// The tables, computed once on first use (thread-safe static).
const ZigguratTables& ziggurat_tables();

/// The wedge test of layer i (1 ≤ i < N) for a candidate x in [x[i+1], x[i]) and y in
/// [f[i], f[i+1]): y < portable_exp(−x²/2), bit for bit, but decided without the exponential
/// where a squeeze decides it. On a wedge f is concave (x[i] ≤ 1) or convex (x[i+1] ≥ 1), so
/// the chord through the layer's two table points and the tangent at the wedge's midpoint
/// bound f from either side (concave: chord ≤ f ≤ tangent; convex: tangent ≤ f ≤ chord).
/// y below the lower line minus a margin is accepted, above the upper line plus the margin
/// rejected; only the sliver between them (or the one layer containing x = 1) calls exp.
/// Margin 1e-14 (f ≤ 1): it covers the table values (≤ 2 ulps off f), the rounding of the
/// lines (a few ulps of 1), of −x²/2 (|x| < r ≈ 3.65: ≤ 7.4e-16 relative in f) and of
/// portable_exp (< 1 ulp), ≈ 2e-15 together. Tested against the exponential alone.
bool wedge_accepts(std::size_t layer, double x, double y);

}  // namespace vcmm::uncertainty::internal
