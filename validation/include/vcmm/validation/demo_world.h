// vcmm/validation/demo_world.h — the synthetic "ground truth" world of the demo (docs/demo.md):
// a 171 mm ring gauge with ~200 nm form, a CMM whose true errors are ONE draw from the digital
// model's distributions, the 66-measurement campaign of the seed study's design (7 locations,
// 4 orientations, 3 heights, scanning and touch-trigger), and reference measurements
// (roundness-meter profiles, interferometer diameters) with their own errors and uncertainties.
//
// Because the truth is known here, the demo can score what a real campaign cannot: the error
// of every reported value against the true value.
//
// The plan (the seed study's: 11 set-ups × 3 heights × 2 probing modes = 66 measurements):
//   - the ring at each of the 7 locations at orientation 0°                     7 set-ups
//   - the ring re-mounted at the centre C in 4 orientations 0°, 90°, 180°, 270°  4 set-ups
//   each measured at the top, middle and bottom heights, scanning and touch-trigger.
//   Ids: "<location>-O<deg>-<height>-<mode>" (location series), "C-R<deg>-<height>-<mode>"
//   (orientation series at the centre; C-R000 is a second set-up of C-O000).
// Locations (machine mm, ring centre; the moving-bridge axis ranges of examples/cmm_model.json):
//   C centre (600, 500, 250); corners L1 (200, 150, 150), L2 (1000, 150, 150), L3 (200, 850, 150),
//   L4 (1000, 850, 150); elevated E1 (600, 500, 600), E2 (1000, 850, 600).
// Heights in the ring (workpiece z): top +8 mm, middle 0, bottom −8 mm (a 20 mm thick ring).
// Stylus: vertical, 100 mm (tip 100 mm below the ram reference point).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/measurement.h"
#include "vcmm/errormodel/ring_gauge.h"
#include "vcmm/errormodel/virtual_cmm.h"
#include "vcmm/validation/campaign.h"
#include "vcmm/validation/ring_experiment.h"

namespace vcmm::validation {

/// The demo's knobs (defaults: the seed study's setting).
struct DemoWorldOptions {
  std::uint64_t seed = 20261122;              ///< fixes the world (truth draw, noise, references)
  /// Multiplies the true form of the ring (every harmonic's amplitude), so the bias treatments
  /// are tested where the form dominates the errors as well as where the errors dominate.
  double form_scale = 1.0;
  Eigen::Index scanning_points = 3600;
  /// Touch-trigger points: 360 meets ISO 12181-2's ≥ 7 points per cut-off wavelength at 50 UPR
  /// (a filter is applied to both modes alike).
  Eigen::Index touch_trigger_points = 360;
  double lab_temperature_c = 20.2;            ///< mean temperature reading
  double lab_temperature_spread_k = 0.3;      ///< readings uniform in mean ± spread
  /// Roundness meter: white noise on each profile value and the standard uncertainty of a
  /// roundness value from its budget (the seed study's reference had ~10 nm).
  double roundness_meter_noise_mm = 0.003e-3;
  Eigen::Index roundness_meter_points = 3600;
  double reference_roundness_u_mm = 0.010e-3;
  /// Interferometer: standard uncertainty of the 0°–180° distance.
  double interferometer_u_mm = 0.040e-3;
};

/// One planned measurement of the world, with everything the truth knows about it.
struct DemoMeasurement {
  std::string id;            ///< e.g. "C-O000-middle-scan", "C-R090-top-touch"
  std::string location;      ///< C, L1 … L4, E1, E2
  double orientation_deg = 0.0;
  std::string height;        ///< top, middle, bottom
  errormodel::ProbingMode mode = errormodel::ProbingMode::scanning;
  errormodel::Measurement truth;     ///< the true surface points (reading in temperature_c)
  errormodel::Measurement measured;  ///< what the CMM reported
  double true_temperature_c = 20.0;
  /// The roundness meter's profile of this height: deviations (mm) at equiangular angles from 0,
  /// in the ring's own frame, with the instrument's noise.
  std::vector<double> reference_profile_deviation_mm;
  double interferometer_distance_mm = 0.0;  ///< measured 0°–180° distance at this height
};

/// The world: the ring, the true CMM, the plan.
struct DemoWorld {
  DemoWorldOptions options;
  errormodel::RingGauge ring_middle;         ///< form at the middle height
  std::vector<errormodel::RingGauge> ring_by_height;  ///< top, middle, bottom
  errormodel::ErrorDraw true_cmm;            ///< the true α, kinematic and probe errors
  std::vector<DemoMeasurement> measurements; ///< 66 with the default options
};

/// Builds the world deterministically from options.seed: the form per height (the seed study's
/// harmonics times form_scale, amplitudes and phases varied by ±20 % / ±0.3 rad per height),
/// the true CMM (one
/// draw of temperature coefficient, kinematic and probe errors from `model`), per measurement a
/// temperature reading, the true temperature N(reading, u_T²), fresh roughness and noise, and
/// the reference measurements. Throws as the error model. O(66 · N).
/// Throws std::invalid_argument if form_scale is not finite and ≥ 0, or point counts < 8.
DemoWorld make_demo_world(const errormodel::DigitalModel& model, const DemoWorldOptions& options);

/// Writes the world as a campaign into `dir`: measurements/<id>.csv (what the CMM reported),
/// reference/<height>.csv (the roundness-meter profiles, `angle_deg,deviation_um`), the model
/// file copied as model.json, campaign.json (references: profile-evaluated roundness with
/// u = options.reference_roundness_u_mm, interferometer diameters with the profile), and
/// truth.json (the true temperature, and the true measurands of every measurement under
/// `evaluation`). Returns the true measurands by id. Files are written atomically.
std::map<std::string, RingMeasurands> write_demo_campaign(const DemoWorld& world,
                                                          const std::string& model_json_text,
                                                          const EvaluationSettings& evaluation,
                                                          const std::filesystem::path& dir);

/// The text of the bundled example model, examples/cmm_model.json, compiled into the library
/// (the demo's default model). O(1).
std::string_view bundled_example_model_json();

/// "top", "middle", "bottom" → workpiece z of the section (mm): +8, 0, −8.
double demo_height_mm(const std::string& height);

}  // namespace vcmm::validation
