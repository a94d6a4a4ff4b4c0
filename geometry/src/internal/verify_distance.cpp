// internal/verify_distance.cpp — see verify_distance.h.
#include "internal/verify_distance.h"

#include <atomic>
#include <limits>

namespace vcmm::geometry::internal {
namespace {

std::atomic<bool> filter_enabled{true};

}  // namespace

bool verify_filter_enabled() { return filter_enabled.load(std::memory_order_relaxed); }

void set_verify_filter_enabled(bool enabled) {
  filter_enabled.store(enabled, std::memory_order_relaxed);
}

ApproxCentre approx_centre(std::pair<double, double> x, std::pair<double, double> y) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  const double dx = x.second - x.first, dy = y.second - y.first;
  // x.first ≤ c_x ≤ x.second, so |c_x − x.first| ≤ dx; the same for y.
  const bool usable = verify_filter_enabled() && std::isfinite(dx) && std::isfinite(dy);
  return {x.first, y.first, usable ? std::fmax(dx, dy) : inf};
}

}  // namespace vcmm::geometry::internal
