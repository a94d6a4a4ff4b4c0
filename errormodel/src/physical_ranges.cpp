// The physical ranges of model and measurement values (physical_ranges.h).
#include "vcmm/errormodel/physical_ranges.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace vcmm::errormodel {
namespace {

std::string shortest(double v) {
  std::array<char, 32> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), r.ptr);
}

/// Six significant digits: a converted value (293.45 K → 20.3 °C) without rounding noise.
std::string rounded(double v) {
  std::array<char, 32> buf{};
  std::snprintf(buf.data(), buf.size(), "%.6g", v);
  return buf.data();
}

std::string interval(const PhysicalRange& r, bool open_below) {
  return std::string(open_below ? "(" : "[") + shortest(r.min) + ", " + shortest(r.max) + "] " +
         r.unit;
}

std::string problem(const PhysicalRange& r, double v, bool open_below) {
  const bool inside = std::isfinite(v) && (open_below ? v > r.min : v >= r.min) && v <= r.max;
  if (inside) return {};
  const std::string got = "; got " + shortest(v) + " " + r.unit;
  if (!std::isfinite(v))
    return "must be a finite number in " + interval(r, open_below) + " (" + r.meaning + ")" + got;
  if (&r == &physical_range::temperature_c) {
    if (v < physical_range::absolute_zero_c)
      return "is below absolute zero (" + shortest(physical_range::absolute_zero_c) +
             " °C): not a temperature in °C" + got;
    // A room temperature in kelvin is 223 … 373 K; in °F it is −58 … 212 °F.
    const double kelvin_as_c = v + physical_range::absolute_zero_c;
    if (kelvin_as_c >= r.min && kelvin_as_c <= r.max)
      return "must lie in " + interval(r, open_below) + " (" + r.meaning +
             " in °C; kelvin given? " + shortest(v) + " K = " + rounded(kelvin_as_c) + " °C)" +
             got;
    return "must lie in " + interval(r, open_below) + " (" + r.meaning +
           " in °C; kelvin or °F given?)" + got;
  }
  return "must lie in " + interval(r, open_below) + " (" + r.meaning + ")" + got;
}

}  // namespace

std::string range_problem(const PhysicalRange& range, double value) {
  return problem(range, value, false);
}

std::string range_problem_above_min(const PhysicalRange& range, double value) {
  return problem(range, value, true);
}

}  // namespace vcmm::errormodel
