// polar_profile.cpp — the checked directions of polar profiles (vcmm/geometry/polar_profile.h).
#include "vcmm/geometry/polar_profile.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace vcmm::geometry {

PolarDirections::PolarDirections(std::vector<double> cos, std::vector<double> sin)
    : cos_(std::move(cos)), sin_(std::move(sin)) {
  if (cos_.size() != sin_.size() || cos_.size() < 8)
    throw InvalidInput("PolarDirections: expected at least 8 directions, as many cosines as "
                       "sines; got " + std::to_string(cos_.size()) + " cosines and " +
                       std::to_string(sin_.size()) + " sines");
  norm2_hi_ = 0.0;
  norm2_lo_ = std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < cos_.size(); ++j) {
    const double q = cos_[j] * cos_[j] + sin_[j] * sin_[j];
    if (!std::isfinite(q) || !(q > 0.0))
      throw InvalidInput("PolarDirections: direction " + std::to_string(j) +
                         " is zero or not finite (cos " + std::to_string(cos_[j]) + ", sin " +
                         std::to_string(sin_[j]) + ")");
    norm2_hi_ = std::max(norm2_hi_, q);
    norm2_lo_ = std::min(norm2_lo_, q);
  }
}

}  // namespace vcmm::geometry
