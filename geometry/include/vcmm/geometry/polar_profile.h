// vcmm/geometry/polar_profile.h — a closed profile given by its radii on fixed directions
// about an origin: the form in which a Monte Carlo loop produces one profile per trial
// (validation/spectral_trial.h), read by the *_from_extremes reference-circle functions
// (minimum_zone_from_extremes.h, maximum_inscribed_from_extremes.h) without building all of
// its points.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "vcmm/geometry/point.h"

namespace vcmm::geometry {

/// The fixed directions u_j = (cos_j, sin_j) of polar profiles, checked once: finite and
/// non-zero (unit vectors, e.g. (x, y)/hypot(x, y), in angular order once around the origin,
/// are what the *_from_extremes functions expect; other lengths only scale the radii).
class PolarDirections {
 public:
  /// Throws InvalidInput when the sizes differ, there are fewer than 8 directions, or one is
  /// zero or not finite (naming its index).
  PolarDirections(std::vector<double> cos, std::vector<double> sin);
  std::size_t size() const { return cos_.size(); }
  std::span<const double> cos() const { return cos_; }
  std::span<const double> sin() const { return sin_; }
  /// Range of |u_j|² (each computed in double): the passes' rigorous bounds use it.
  double norm2_hi() const { return norm2_hi_; }
  double norm2_lo() const { return norm2_lo_; }

 private:
  std::vector<double> cos_, sin_;
  double norm2_hi_ = 1.0, norm2_lo_ = 1.0;
};

/// Point j is (r_j cos_j, r_j sin_j) with r_j = base_radius + deviation[j] (mm), each sum and
/// product rounded once, exactly as polar_point computes it. The directions are fixed; the
/// deviations are what changes from one profile to the next. `directions` must outlive the
/// profile.
struct PolarProfile {
  double base_radius = 0.0;               ///< mm
  std::span<const double> deviation;      ///< mm, one per direction
  const PolarDirections* directions = nullptr;
  std::size_t size() const { return deviation.size(); }
};

/// The profile's point j (rounded as documented above).
inline Point2 polar_point(const PolarProfile& p, std::size_t j) {
  const double r = p.base_radius + p.deviation[j];
  return {r * p.directions->cos()[j], r * p.directions->sin()[j]};
}

/// Reusable work arrays of the *_from_extremes functions (one per thread; their sizes only
/// grow, so a Monte Carlo loop allocates nothing after its first trial).
struct ExtremesScratch {
  std::vector<std::size_t> subset_index;   ///< S at the end, in the order it grew
  std::vector<Point2> subset;              ///< its points
  std::vector<unsigned char> member;       ///< per point: in S
  std::vector<double> peak_hi, valley_lo;  ///< per block of 16: highest peak, lowest valley
  std::vector<double> distance2;           ///< per point: D about the origin (points overload)
  int rounds = 0;                          ///< fits on subsets in the last call
  bool fell_back = false;                  ///< the last call fitted all points
  Point2 center;                           ///< the last call's reference centre
};

}  // namespace vcmm::geometry
