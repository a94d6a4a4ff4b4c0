// vcmm/errormodel/digital_model.h — the digital model of the CMM: the parameters of every
// error source with their standard uncertainties, and the versioned JSON file that holds them
// (schema: docs/errormodel.md, "Digital-model file"; example: examples/cmm_model.json).
//
// Units inside the library: mm, rad, K, °C. The file uses µm / µrad where a key says so
// ("sigma_um"); the loader converts. Every estimated value comes with its standard
// uncertainty u (GUM); entries that are themselves standard deviations (σ of roughness and
// noise, u of the thermometer) are plain numbers.
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "vcmm/errormodel/kinematic_errors.h"
#include "vcmm/errormodel/measurement.h"

namespace vcmm::errormodel {

/// An estimated value and its standard uncertainty u ≥ 0 (same unit).
struct UncertainValue {
  double value = 0.0;
  double u = 0.0;
};

/// Stage 1. Workpiece surface roughness: a deviation N(0, σ²) along the normal, independent
/// per point (the part of the surface texture a probe of the given tip samples).
struct RoughnessModel {
  double sigma_mm = 0.0;  ///< ≥ 0
};

/// Stage 2. Workpiece temperature: homogeneous, true value N(reading, u_T²); linear expansion
/// coefficient N(α, u(α)²). The workpiece expands about its own origin by α·(T − 20 °C).
struct TemperatureModel {
  UncertainValue expansion_coefficient_per_k{11.5e-6, 0.0};  ///< α (1/K), steel by default
  double thermometer_u_k = 0.0;  ///< standard uncertainty of the temperature reading (K), ≥ 0
};

/// One harmonic of the probe's directional error: c·cos(kφ) + s·sin(kφ), φ the azimuth of the
/// probing direction in the machine XY plane (see virtual_cmm.h for the 3D extension).
struct ProbeHarmonic {
  int order = 1;              ///< k ≥ 1 (k = 0 is the tip radius error)
  UncertainValue cos_mm;      ///< c (mm)
  UncertainValue sin_mm;      ///< s (mm)
};

/// Stage 4. Probe errors, as an effective radius error along the normal: the tip radius
/// error (actual − calibrated radius) plus a directional error, a low-order Fourier series
/// in the probing direction. Positive = the point is reported displaced into the air.
struct ProbeModel {
  UncertainValue tip_radius_error_mm;
  std::vector<ProbeHarmonic> directional;  ///< distinct orders 1 … max_probe_harmonic_order
};
/// Highest harmonic order accepted (a "low-order" series: lobing of a kinematic probe head
/// has 3 or 6 lobes; 16 leaves ample room and bounds the per-point cost).
inline constexpr int max_probe_harmonic_order = 16;

/// Stage 5. Random noise: isotropic 3D Gaussian, σ per Cartesian component, by probing mode.
struct NoiseModel {
  double scanning_sigma_mm = 0.0;       ///< ≥ 0
  double touch_trigger_sigma_mm = 0.0;  ///< ≥ 0
};

/// All parameters of the virtual CMM. Default values describe a perfect machine (every error
/// and uncertainty zero, α of steel), given the kinematic model (which fixes the axis ranges).
struct DigitalModel {
  explicit DigitalModel(KinematicModel kinematic_model) : kinematics(std::move(kinematic_model)) {}

  std::string description;  ///< free text from the file
  RoughnessModel roughness;
  TemperatureModel temperature;
  KinematicModel kinematics;
  ProbeModel probe;
  NoiseModel noise;
};

/// The model used when the kinematic errors are left uncorrected and only taken into account
/// in the uncertainty: `model` with kinematics = model.kinematics.uncorrected() (correction
/// then removes nothing, and each trial draws the whole kinematic error about zero). O(k³).
DigitalModel with_kinematics_uncorrected(const DigitalModel& model);

/// Checks a model built in code, as the loader checks a file: every value finite, σ and u
/// ≥ 0, harmonic orders in 1…max_probe_harmonic_order and distinct. Throws InvalidParameter
/// naming the field (with the file's key path, e.g. "noise.scanning_sigma_um") and value.
/// (The kinematic model validates itself on construction.)
void validate_digital_model(const DigitalModel& model);

/// Parses a digital-model file (`"schema": "vcmm.digital_model"`, `"schema_version": 1`).
/// `source_name` prefixes every message. Throws InvalidParameter whose key_path() is the full
/// dotted path of the offending entry and whose message names the source, path, value and
/// rule: invalid JSON (key path "", with the line), wrong schema or version, missing key,
/// unknown key, wrong type, non-finite, negative σ or u, bad harmonic order; errors of the
/// "kinematics" section are passed on with their own key path. O(size of the file).
DigitalModel parse_digital_model(std::string_view json_text, const std::string& source_name);
DigitalModel read_digital_model(std::istream& in, const std::string& source_name);
/// Opens `path` and parses it; an unreadable file is InvalidParameter with key path "".
DigitalModel read_digital_model_file(const std::string& path);

}  // namespace vcmm::errormodel
