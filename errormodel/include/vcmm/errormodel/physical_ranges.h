// vcmm/errormodel/physical_ranges.h — the physically sensible range of every model and
// measurement value, in one place: the digital-model loader, the measurement CSV reader, the
// campaign reader and the `vcmm` options all check against these limits, so the same value is
// accepted or refused (with the same words) wherever it is given.
//
// Finite is not enough: a noise σ of 1e300 µm is a finite number, and simulating with it writes
// points at 1e296 mm; 293.15 under a key in °C is a kelvin value. The limits are generous — far
// outside anything a CMM room, a probe or a calibration produces — and exist to catch wrong
// units and typing errors, not to judge a machine. Each reader turns the problem phrase into
// its own error type with its own location (file:line, JSON key path, option name).
#pragma once

#include <string>

namespace vcmm::errormodel {

/// A closed interval [min, max] of one kind of physical value, with its unit and its meaning.
struct PhysicalRange {
  double min;
  double max;
  const char* unit;     ///< as written after a number ("°C", "µm", "mm", "/K", "K")
  const char* meaning;  ///< what a value in the range is ("a workpiece temperature")
};

namespace physical_range {

/// Absolute zero (°C): no temperature lies below it.
inline constexpr double absolute_zero_c = -273.15;

/// Temperature of a workpiece or of a CMM room (°C). Outside, the value is almost surely in
/// kelvin (293.15) or °F (68); the message says which is likely.
inline constexpr PhysicalRange temperature_c{-50.0, 100.0, "°C", "a workpiece temperature"};

/// Linear thermal expansion coefficient (/K): engineering materials lie within ±3e-4 /K
/// (steel 11.5e-6, aluminium 23e-6, PTFE ~1.3e-4, some composites slightly negative).
inline constexpr PhysicalRange expansion_coefficient_per_k{-1e-3, 1e-3, "/K",
                                                           "a linear expansion coefficient"};

/// Standard uncertainty of an expansion coefficient (/K).
inline constexpr PhysicalRange expansion_coefficient_u_per_k{0.0, 1e-3, "/K",
                                                             "a standard uncertainty"};

/// Standard uncertainty of a temperature reading (K): thermometers in CMM rooms read to
/// 0.01–0.5 K; 10 K would make the temperature unknown.
inline constexpr PhysicalRange thermometer_u_k{0.0, 10.0, "K", "a standard uncertainty"};

/// A standard deviation or standard uncertainty of a length: probing noise, roughness, tip
/// errors, calibrated positions. 1 mm is beyond any CMM error (they are µm), so a larger
/// value is a wrong unit or a typing error. In µm and in mm (the same limit).
inline constexpr PhysicalRange length_sigma_um{0.0, 1000.0, "µm", "a standard deviation"};
inline constexpr PhysicalRange length_sigma_mm{0.0, 1.0, "mm", "a standard deviation"};

/// The value of a small length error (a tip radius error, a probe harmonic amplitude).
inline constexpr PhysicalRange length_error_um{-1000.0, 1000.0, "µm", "a probe error"};

/// A coefficient of a kinematic error function (Legendre, docs/kinematics.md): residual errors
/// of a CMM are µm and µrad; 1 mm and 10 mrad are far beyond any machine still in use.
inline constexpr PhysicalRange kinematic_error_um{-1000.0, 1000.0, "µm",
                                                  "a kinematic error coefficient"};
inline constexpr PhysicalRange kinematic_rotation_urad{-1e4, 1e4, "µrad",
                                                       "a rotation or squareness error"};
inline constexpr PhysicalRange rotation_u_urad{0.0, 1e4, "µrad", "a standard uncertainty"};

/// A coordinate or offset in a CMM volume (mm): the largest CMMs travel ~10 m.
inline constexpr PhysicalRange coordinate_mm{-1e5, 1e5, "mm", "a position in a CMM volume"};

/// A diameter measured on a CMM (mm).
inline constexpr PhysicalRange diameter_mm{0.0, 1e5, "mm", "a diameter on a CMM"};

}  // namespace physical_range

/// Empty when `value` lies in `range`; otherwise the rule it breaks, as a phrase to follow the
/// name of the field: "must lie in [0, 1000] µm (a standard deviation); got 1e+300 µm". NaN
/// and ±inf break every range ("must be a finite number …"). For temperature_c the phrase says
/// "below absolute zero" or "kelvin given?" where that is the likely cause.
std::string range_problem(const PhysicalRange& range, double value);

/// `range_problem` for a range excluding its lower end (a diameter > 0).
std::string range_problem_above_min(const PhysicalRange& range, double value);

}  // namespace vcmm::errormodel
