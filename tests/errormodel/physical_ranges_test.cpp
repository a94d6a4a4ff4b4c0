// range_problem: every physical range of errormodel/physical_ranges.h accepts its inside
// (ends included), refuses NaN/inf and values outside with the unit and the meaning, and says
// "kelvin given?" / "below absolute zero" for temperatures where that is the likely cause.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "vcmm/errormodel/physical_ranges.h"

namespace {

using vcmm::errormodel::range_problem;
using vcmm::errormodel::range_problem_above_min;
namespace pr = vcmm::errormodel::physical_range;

TEST(PhysicalRanges, InsideAndEndsAreAccepted) {
  for (const double t : {-50.0, 0.0, 20.0, 100.0}) EXPECT_EQ(range_problem(pr::temperature_c, t), "");
  EXPECT_EQ(range_problem(pr::length_sigma_um, 0.0), "");
  EXPECT_EQ(range_problem(pr::length_sigma_um, 1000.0), "");
  EXPECT_EQ(range_problem(pr::length_sigma_mm, 1.0), "");
  EXPECT_EQ(range_problem(pr::expansion_coefficient_per_k, 11.5e-6), "");
  EXPECT_EQ(range_problem(pr::expansion_coefficient_per_k, -1e-6), "");
  EXPECT_EQ(range_problem(pr::coordinate_mm, -1e5), "");
  EXPECT_EQ(range_problem_above_min(pr::diameter_mm, 171.0), "");
}

TEST(PhysicalRanges, OutsideNamesRangeUnitMeaningAndValue) {
  EXPECT_EQ(range_problem(pr::length_sigma_um, 1e300),
            "must lie in [0, 1000] µm (a standard deviation); got 1e+300 µm");
  EXPECT_EQ(range_problem(pr::length_sigma_um, -0.2),
            "must lie in [0, 1000] µm (a standard deviation); got -0.2 µm");
  EXPECT_EQ(range_problem(pr::expansion_coefficient_per_k, 1e300),
            "must lie in [-0.001, 0.001] /K (a linear expansion coefficient); got 1e+300 /K");
  EXPECT_EQ(range_problem(pr::thermometer_u_k, 11.0),
            "must lie in [0, 10] K (a standard uncertainty); got 11 K");
  EXPECT_EQ(range_problem_above_min(pr::diameter_mm, 0.0),
            "must lie in (0, 1e+05] mm (a diameter on a CMM); got 0 mm");
  EXPECT_EQ(range_problem(pr::diameter_mm, 0.0), "");  // the closed form includes 0
}

TEST(PhysicalRanges, NonFiniteIsRefused) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(range_problem(pr::length_sigma_um, nan),
            "must be a finite number in [0, 1000] µm (a standard deviation); got nan µm");
  EXPECT_NE(range_problem(pr::temperature_c, inf).find("must be a finite number"),
            std::string::npos);
  EXPECT_NE(range_problem(pr::coordinate_mm, -inf), "");
}

TEST(PhysicalRanges, TemperatureSaysKelvinOrAbsoluteZero) {
  EXPECT_EQ(range_problem(pr::temperature_c, 293.15),
            "must lie in [-50, 100] °C (a workpiece temperature in °C; kelvin given? 293.15 K = "
            "20 °C); got 293.15 °C");
  EXPECT_EQ(range_problem(pr::temperature_c, -300.0),
            "is below absolute zero (-273.15 °C): not a temperature in °C; got -300 °C");
  EXPECT_EQ(range_problem(pr::temperature_c, 150.0),
            "must lie in [-50, 100] °C (a workpiece temperature in °C; kelvin or °F given?); got "
            "150 °C");
  EXPECT_EQ(range_problem(pr::temperature_c, -60.0),
            "must lie in [-50, 100] °C (a workpiece temperature in °C; kelvin or °F given?); got "
            "-60 °C");
}

}  // namespace
