// examples/characterization/hole_plate/hole_plate_example.h — the bundled hole-plate example
// data set (README.md in this folder), as a function: used by make_hole_plate_example.cpp to
// write the files and by tests/characterization/hole_plate_test.cpp to check that the bundled
// files are what the code produces.
//
// A moving-bridge CMM with the kinematic model of examples/cmm_model.json (a truth drawn from
// it, seed 7) measures a 4×4 hole plate (pitch 200 mm, calibrated to u = 0.3 µm per coordinate)
// in 4 setups and 10 placements (docs/characterization.md, "Measurement plan"):
//   xy_low   plate horizontal at z = -100 mm, styli t1 = (0,0,-150), t2 = (100,0,-150),
//            t3 = (0,100,-150) without moving the plate (one setup, three placements);
//   xy_high  plate horizontal at z = 600 mm, stylus t1;
//   xz       plate vertical in an XZ plane (normal along y) at y = 200 mm, horizontal styli
//            (0,-150,-50), (100,-150,-50), (0,-150,-150);
//   yz       plate vertical in a YZ plane (normal along x) at x = 200 mm, styli
//            (-150,0,-50), (-150,100,-50), (-150,0,-150).
// Feature centres carry N(0, (0.2 µm)²) probing noise per coordinate; the plate's true
// geometry differs from its calibration by N(0, (0.3 µm)²) per coordinate.
#pragma once

#include <Eigen/Core>

#include <array>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "vcmm/characterization/hole_plate.h"
#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/random_source.h"

namespace vcmm::examples {

/// The example's parameters (shared with its test).
struct HolePlateExample {
  static constexpr double pitch_mm = 200.0;
  static constexpr int features_per_side = 4;
  static constexpr double plate_u_mm = 0.3e-3;         // calibration u per coordinate
  static constexpr double plate_deviation_mm = 5e-3;  // the plate's deviations from the nominal grid
  static constexpr double probing_sigma_mm = 0.2e-3;   // per coordinate of a measured centre
  static constexpr unsigned plate_seed = 2024, truth_seed = 7, noise_seed = 11;
};

/// The simulation plan of the example (true poses; unknown to the estimator).
inline std::vector<characterization::SimulatedPlacement> hole_plate_example_plan() {
  using characterization::RigidPose;
  const double deg = std::numbers::pi / 180.0;
  auto pose = [&](double ax, double ay, double az, Eigen::Vector3d t) {
    return RigidPose::from_rotation_vector(Eigen::Vector3d(ax, ay, az) * deg, t);
  };
  const RigidPose xy_low = pose(0, 0, 0, {600, 500, -100}), xy_high = pose(0, 0, 0, {600, 500, 600});
  const RigidPose xz = pose(90, 0, 0, {600, 200, 300}), yz = pose(0, -90, 0, {200, 500, 300});
  return {
      {"xy_low_t1", "xy_low", xy_low, {0, 0, -150}, {}},
      {"xy_low_t2", "xy_low", xy_low, {100, 0, -150}, {}},
      {"xy_low_t3", "xy_low", xy_low, {0, 100, -150}, {}},
      {"xy_high_t1", "xy_high", xy_high, {0, 0, -150}, {}},
      {"xz_t1", "xz", xz, {0, -150, -50}, {}},
      {"xz_t2", "xz", xz, {100, -150, -50}, {}},
      {"xz_t3", "xz", xz, {0, -150, -150}, {}},
      {"yz_t1", "yz", yz, {-150, 0, -50}, {}},
      {"yz_t2", "yz", yz, {-150, 100, -50}, {}},
      {"yz_t3", "yz", yz, {-150, 0, -150}, {}},
  };
}

/// The calibrated plate: the nominal grid plus fixed "manufacturing" deviations (seeded).
inline characterization::HolePlate hole_plate_example_plate() {
  using E = HolePlateExample;
  characterization::HolePlate plate =
      characterization::grid_hole_plate(E::features_per_side, E::pitch_mm, E::plate_u_mm);
  errormodel::SeededRandomSource rng(E::plate_seed);
  Eigen::Matrix3Xd dev(3, plate.calibrated_mm.cols());
  rng.fill_standard_normal({dev.data(), static_cast<std::size_t>(dev.size())});
  dev.row(2).setZero();  // a hole plate: centres in its surface
  plate.calibrated_mm += E::plate_deviation_mm * dev;
  return plate;
}

/// The truth drawn from the model's kinematics (seed truth_seed), as a model without
/// uncertainty (its mean is the truth).
inline errormodel::KinematicModel hole_plate_example_truth(const errormodel::KinematicModel& km) {
  errormodel::SeededRandomSource rng(HolePlateExample::truth_seed);
  const errormodel::KinematicErrors truth = km.draw(rng);
  std::array<errormodel::ErrorFunctionEstimate, errormodel::axis_error_count> fns;
  for (int f = 0; f < errormodel::axis_error_count; ++f) {
    const auto c = truth.coefficients(km, static_cast<errormodel::AxisError>(f));
    fns[static_cast<std::size_t>(f)].coefficients.assign(c.begin(), c.end());
    fns[static_cast<std::size_t>(f)].standard_uncertainties.assign(c.size(), 0.0);
  }
  std::array<errormodel::EstimatedValue, errormodel::squareness_count> sq{};
  for (int s = 0; s < errormodel::squareness_count; ++s)
    sq[static_cast<std::size_t>(s)] = {truth.squareness(km, static_cast<errormodel::Squareness>(s)), 0.0};
  std::array<errormodel::AxisRange, 3> ranges{};
  for (int k = 0; k < 3; ++k) ranges[static_cast<std::size_t>(k)] = km.range(static_cast<errormodel::Axis>(k));
  return errormodel::KinematicModel(km.chain(), ranges, fns, sq);
}

/// The example's files, (file name, content), in writing order: plate.csv, truth_kinematics.json,
/// then one CSV per placement. `model` is examples/cmm_model.json.
inline std::vector<std::pair<std::string, std::string>> hole_plate_example_files(
    const errormodel::DigitalModel& model) {
  using E = HolePlateExample;
  const characterization::HolePlate plate = hole_plate_example_plate();
  const errormodel::KinematicModel truth_model = hole_plate_example_truth(model.kinematics);
  const errormodel::KinematicErrors truth = truth_model.nominal();
  const auto plan = hole_plate_example_plan();
  errormodel::SeededRandomSource rng(E::noise_seed);
  const auto data = characterization::simulate_hole_plate_measurements(
      truth_model, truth, plate, plan, E::probing_sigma_mm, rng);
  std::vector<std::pair<std::string, std::string>> files;
  const std::vector<std::string> plate_comments = {
      "example data set: examples/characterization/hole_plate/README.md (synthetic, seeded)"};
  files.emplace_back("plate.csv", characterization::hole_plate_csv(plate, plate_comments));
  files.emplace_back(
      "truth_kinematics.json",
      "{\"kinematics\": " +
          characterization::kinematics_json(
              truth_model, "The truth of the example (drawn from examples/cmm_model.json, seed 7): "
                           "what vcmm characterize hole-plate should recover") +
          "}\n");
  for (std::size_t j = 0; j < plan.size(); ++j) {
    const Eigen::Vector3d t = plan[j].true_pose.translation_mm;
    const std::vector<std::string> comments = {
        "example data set: examples/characterization/hole_plate/README.md (synthetic, seeded)",
        "true plate position (simulation only; unknown in a real calibration): translation " +
            std::to_string(t.x()) + ", " + std::to_string(t.y()) + ", " + std::to_string(t.z()) +
            " mm"};
    files.emplace_back(plan[j].name + ".csv",
                       characterization::hole_plate_placement_csv(data.placements[j], comments));
  }
  return files;
}

}  // namespace vcmm::examples
