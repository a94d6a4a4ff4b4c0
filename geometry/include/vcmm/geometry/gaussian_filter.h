// vcmm/geometry/gaussian_filter.h — the ISO 16610-21 Gaussian profile filter for closed
// (roundness) profiles.
//
// Transmission of harmonic k (undulations per revolution, UPR) for cut-off f_c:
//   H(k) = exp(−π (α k / f_c)²) = 2^−(k/f_c)²,   α = sqrt(ln 2 / π) ≈ 0.4697
// Weighting function in angle θ (rad), with cut-off wavelength λ_c = 2π / f_c:
//   s(θ) = 1/(α λ_c) · exp(−π (θ / (α λ_c))²), wrapped periodically.
#pragma once

#include <span>
#include <vector>

#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/point.h"

namespace vcmm::geometry {

/// The standard cut-offs of ISO 12181-2 (UPR).
inline constexpr double kStandardCutoffsUpr[] = {15.0, 50.0, 150.0, 500.0, 1500.0};

/// How a profile was filtered.
enum class FilterPath {
  fft,           ///< equiangular samples in angular order: exact per-harmonic transmission
  nonuniform,    ///< uneven spacing: weighted convolution with quadrature weights
  open_profile,  ///< a partial arc: gaussian_filtered_open_profile
};

/// Which path gaussian_filtered_profile may take.
enum class FilterPathChoice {
  automatic,   ///< FFT when the samples are on an equiangular grid (see below), else nonuniform
  nonuniform,  ///< always the convolution with the true angles (for cross-checks)
};

struct FilteredProfile {
  /// Filtered points, same count and order as the input: point i lies on the ray from the
  /// filter centre through input point i, at the filtered radius.
  std::vector<Point2> points;
  Point2 filter_center;   ///< LS centre about which radial deviations were taken
  double mean_radius = 0.0;
  FilterPath path = FilterPath::fft;
};

/// Gaussian filter of a closed profile's radial deviations (about its LS centre).
/// Samples whose directions lie on an equiangular grid (in angular order, any start angle,
/// either sense; real scans sit off the grid about the LS centre by eccentricity and noise,
/// accepted up to just under half a step) are filtered by
/// FFT with the exact transmission, kept when the grid displacement's first-order effect is
/// below 1e-3 of the filtered peak-to-valley (bounded in one pass, or computed by one more
/// FFT when the bound is not enough: gaussian_filter.cpp); other data by direct convolution
/// with the wrapped weighting function (truncated at ±4 α λ_c) and trapezoidal quadrature weights,
/// normalised so a constant deviation passes unchanged. A repeated closing point is detected.
/// Input order does not matter: points that are not equiangular in the order given are tried
/// in angular order about the LS centre (ties by x, y, index) before the nonuniform path is
/// taken, so a shuffled scan is filtered exactly as the scan (to rounding of the LS fit's
/// sums); the output keeps the input order.
/// Preconditions (InvalidInput): ≥ 8 finite points, cut-off in (0, n/2], and the profile
/// closed: it must go once round its centre with no angular gap wider than λ_c / 2.
/// Complexity: O(n log n) (FFT) or O(n · m) with m points under ±4 α λ_c; 3600 points at
/// 50 UPR: ~65 µs on the FFT path, ~40 µs given the LS circle (2.1 GHz Xeon with AVX2,
/// docs/performance.md), ~3 ms on the nonuniform path.
FilteredProfile gaussian_filtered_profile(std::span<const Point2> points, double cutoff_upr,
                                          FilterPathChoice choice = FilterPathChoice::automatic);

/// The same filter about a least-squares circle the caller already has — typically
/// least_squares_circle(points), fitted anyway for the diameter — instead of fitting it again
/// (the fit is ~25 % of the filter's time at n = 3600). With `least_squares` equal to
/// least_squares_circle(points) the result is bit-for-bit that of the overload above (only
/// its centre and radius are read; tests/geometry/gaussian_filter_trial_test.cpp). Any other circle
/// gives the filter about that circle: deviations, the closedness test and the output rays
/// refer to its centre, which the caller is then responsible for.
/// Preconditions (InvalidInput): those above, and a finite centre and finite radius > 0.
/// Complexity: as above without the LS fit.
FilteredProfile gaussian_filtered_profile(std::span<const Point2> points, double cutoff_upr,
                                          const LeastSquaresCircle& least_squares,
                                          FilterPathChoice choice = FilterPathChoice::automatic);

/// The overload above into `out`, whose storage is reused (a Monte Carlo loop filtering
/// profiles of one size allocates nothing after its first call), and, when
/// `filtered_least_squares` is not null, the least-squares circle of the filtered points with
/// RONt, RONp, RONv, RONq about it (ISO 12181-2 LSCI of the mean-line profile) into
/// *filtered_least_squares. The filter builds each output point on its input ray from the
/// given centre, so that circle takes one Gauss-Newton step from the centre, without square
/// roots or divisions (exact to 2⁻⁶⁰ of the radius; least_squares.cpp, "Points on rays"):
/// two light passes instead of a ~20 µs fit at n = 3600. Against
/// least_squares_circle(out.points): the same circle to ~1e-14 mm (the rounding of the output
/// points; iterations = 1), and the same contacts except between residuals equal to that
/// level (tests/geometry/gaussian_filter_trial_test.cpp). `out.points` equals the other overload's
/// output bit for bit. Preconditions and exceptions: as above. `points_validated`: as for
/// gaussian_filtered_least_squares_circle below (true only for points that have just passed
/// least_squares_circle; the same result, one O(n) check less).
void gaussian_filtered_profile(std::span<const Point2> points, double cutoff_upr,
                               const LeastSquaresCircle& least_squares, FilteredProfile& out,
                               LeastSquaresCircle* filtered_least_squares = nullptr,
                               FilterPathChoice choice = FilterPathChoice::automatic,
                               bool points_validated = false);

/// The least-squares circle of the filtered profile alone: *filtered_least_squares of the
/// overload above, bit for bit, without forming the filtered points where the one step on the
/// filter's rays applies (they are formed, into per-thread storage, for the full fit where it
/// does not): the Monte Carlo trial with the LS reference needs only this circle (~4 µs less
/// at n = 3600). `points_validated`: true only when the caller has passed these very points
/// to least_squares_circle (which checked them: ≥ 3 finite points, not all collinear); then
/// this call checks only the count (≥ 8), the cut-off and the circle, not every point again
/// (one O(n) pass less, ~1.2 µs at n = 3600) — points the filter cannot take near the circle
/// are still checked in full, so a non-finite point still throws InvalidInput naming it.
/// Preconditions and exceptions otherwise: as above.
LeastSquaresCircle gaussian_filtered_least_squares_circle(std::span<const Point2> points,
                                                          double cutoff_upr,
                                                          const LeastSquaresCircle& least_squares,
                                                          bool points_validated = false);

/// The Gaussian filter of an open profile (ISO 16610-21, clause 4): a partial arc, taken in
/// its angle about the LS centre from one end to the other (the ends: either side of the
/// largest angular gap). Interior: the weighted mean with the Gaussian weighting function and
/// trapezoidal quadrature weights, truncated at ±4 α λ_c. End effects: the mean line is the
/// value of the Gaussian-weighted least-squares line through the window, which keeps the
/// weighting's zeroth and first moments where the window is cut by an end (constant and
/// linear components pass unchanged up to the ends; in the interior it equals the weighted
/// mean). Output: same count and order, each point on its ray from the LS centre; path
/// open_profile. Preconditions (InvalidInput): ≥ 8 finite points not all collinear, a finite
/// cut-off > 0, no angular gap inside the arc wider than λ_c/2. O(n log n + n·m), m the
/// points within ±4 α λ_c (gaussian_filter_open.cpp).
FilteredProfile gaussian_filtered_open_profile(std::span<const Point2> points, double cutoff_upr);

/// Filters an equiangular closed sequence of radial deviations (any unit) by the exact
/// transmission H(k). Precondition: ≥ 2 finite values, cut-off > 0 (InvalidInput).
std::vector<double> gaussian_filter_closed(std::span<const double> deviations,
                                           double cutoff_upr);

}  // namespace vcmm::geometry
