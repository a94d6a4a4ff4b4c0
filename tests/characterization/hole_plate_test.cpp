// Kinematic errors from a hole plate: hand-checkable cases (scale, squareness, shifted and
// turned placements), identifiability (plate only in XY, no Abbe arms), the invisible
// directions really are invisible, round trip with a truth drawn from examples/cmm_model.json
// (and the written section loads as a digital model), honest uncertainties over 200 seeds,
// files, the bundled example, bad input.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "hole_plate_example.h"
#include "vcmm/characterization/hole_plate.h"
#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/errors.h"

namespace {

namespace em = vcmm::errormodel;
using namespace vcmm::characterization;
using Eigen::Index;

const std::string kSource = VCMM_SOURCE_DIR;

// A small machine: X 0…600, Y 0…600, Z 0…500 mm.
constexpr std::array<em::AxisRange, 3> kSmall = {{{0.0, 600.0}, {0.0, 600.0}, {0.0, 500.0}}};

RigidPose pose_deg(double ax, double ay, double az, Eigen::Vector3d t) {
  return RigidPose::from_rotation_vector(Eigen::Vector3d(ax, ay, az) * std::numbers::pi / 180.0, t);
}

// All functions of degree `d` (translations) / `dr` (rotations), zero values and uncertainty.
em::KinematicModel zero_model(int d, int dr, const std::array<em::AxisRange, 3>& ranges = kSmall,
                              em::KinematicChain chain = em::KinematicChain::moving_bridge()) {
  std::array<em::ErrorFunctionEstimate, em::axis_error_count> fns;
  for (int f = 0; f < em::axis_error_count; ++f) {
    const auto n = static_cast<std::size_t>((em::is_rotation(static_cast<em::AxisError>(f)) ? dr : d) + 1);
    fns[static_cast<std::size_t>(f)].coefficients.assign(n, 0.0);
    fns[static_cast<std::size_t>(f)].standard_uncertainties.assign(n, 0.0);
  }
  return em::KinematicModel(std::move(chain), ranges, fns, {});
}

HolePlateFitOptions options_for(const em::KinematicModel& m, double sigma_mm) {
  HolePlateFitOptions o;
  o.chain = m.chain();
  for (int k = 0; k < 3; ++k) o.axis_ranges[static_cast<std::size_t>(k)] = m.range(static_cast<em::Axis>(k));
  o.degrees = degrees_of(m);
  o.probing_sigma_mm = sigma_mm;
  return o;
}

Index index_of(const KinematicCharacterization& r, const std::string& name) {
  for (std::size_t i = 0; i < r.parameters.size(); ++i)
    if (r.parameters[i].name == name) return static_cast<Index>(i);
  ADD_FAILURE() << "no parameter " << name;
  return 0;
}
const KinematicParameter& param(const KinematicCharacterization& r, const std::string& name) {
  return r.parameters[static_cast<std::size_t>(index_of(r, name))];
}
int count(const KinematicCharacterization& r, ParameterStatus s) {
  int n = 0;
  for (const auto& p : r.parameters) n += p.status == s;
  return n;
}

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

em::DigitalModel example_model() {
  return em::read_digital_model_file(kSource + "/examples/cmm_model.json");
}

// examples/cmm_model.json with its kinematics section replaced by `section` (JSON text).
em::DigitalModel model_with_kinematics(const std::string& section, const std::string& name) {
  nlohmann::json j = nlohmann::json::parse(read_text(kSource + "/examples/cmm_model.json"));
  j["kinematics"] = nlohmann::json::parse(section);
  return em::parse_digital_model(j.dump(), name);
}

// A truth: the model's kinematic errors set to the given coefficients (rest zero).
em::KinematicErrors errors_with(const em::KinematicModel& m,
                                std::vector<std::pair<em::AxisError, std::vector<double>>> fns,
                                std::array<double, 3> squareness = {0, 0, 0}) {
  em::KinematicErrors e = m.nominal();
  for (auto& [f, c] : fns) {
    c.resize(static_cast<std::size_t>(m.coefficient_count(f)), 0.0);
    e.set_coefficients(m, f, c);
  }
  for (int s = 0; s < 3; ++s)
    e.set_squareness(m, static_cast<em::Squareness>(s), squareness[static_cast<std::size_t>(s)]);
  return e;
}

// The compact complete plan on the small machine for a 3×3 plate of pitch 150 mm: XY at two
// heights (the low one with three styli in one setup), XZ and YZ with three styli each.
std::vector<SimulatedPlacement> small_complete_plan() {
  const RigidPose xy_low = pose_deg(0, 0, 0, {300, 300, -50}), xy_high = pose_deg(0, 0, 0, {300, 300, 350});
  const RigidPose xz = pose_deg(90, 0, 0, {300, 100, 250}), yz = pose_deg(0, -90, 0, {100, 300, 250});
  return {
      {"xy_low_t1", "xy_low", xy_low, {0, 0, -100}, {}},
      {"xy_low_t2", "xy_low", xy_low, {80, 0, -100}, {}},
      {"xy_low_t3", "xy_low", xy_low, {0, 80, -100}, {}},
      {"xy_high_t1", "xy_high", xy_high, {0, 0, -100}, {}},
      {"xz_t1", "xz", xz, {0, -100, -30}, {}},
      {"xz_t2", "xz", xz, {80, -100, -30}, {}},
      {"xz_t3", "xz", xz, {0, -100, -100}, {}},
      {"yz_t1", "yz", yz, {-100, 0, -30}, {}},
      {"yz_t2", "yz", yz, {-100, 80, -30}, {}},
      {"yz_t3", "yz", yz, {-100, 0, -100}, {}},
  };
}

// A model for the statistical tests: the example model's magnitudes (mean and u of
// examples/cmm_model.json) truncated to degree 2 (translations) / 1 (rotations), small machine.
em::KinematicModel small_truth_model() {
  const em::KinematicModel& km = example_model().kinematics;
  std::array<em::ErrorFunctionEstimate, em::axis_error_count> fns;
  for (int f = 0; f < em::axis_error_count; ++f) {
    const auto e = static_cast<em::AxisError>(f);
    const int n = em::is_rotation(e) ? 2 : 3;
    for (int i = 0; i < n; ++i) {
      const Index p = km.parameter_offset(e) + i;
      fns[static_cast<std::size_t>(f)].coefficients.push_back(km.mean()[p]);
      fns[static_cast<std::size_t>(f)].standard_uncertainties.push_back(std::sqrt(km.covariance()(p, p)));
    }
  }
  std::array<em::EstimatedValue, 3> sq{};
  for (int s = 0; s < 3; ++s) {
    const Index p = km.parameter_offset(static_cast<em::Squareness>(s));
    sq[static_cast<std::size_t>(s)] = {km.mean()[p], std::sqrt(km.covariance()(p, p))};
  }
  return em::KinematicModel(em::KinematicChain::moving_bridge(), kSmall, fns, sq);
}

// Estimated parameters (not pivots): indices, error against the truth in the gauge, and the
// data covariance.
struct GaugeErrors {
  std::vector<Index> index;
  Eigen::VectorXd error;
  Eigen::MatrixXd covariance;
};
GaugeErrors gauge_errors(const KinematicCharacterization& r, const Eigen::VectorXd& truth) {
  const Eigen::VectorXd tg = express_in_gauge(r, truth);
  GaugeErrors g;
  for (std::size_t p = 0; p < r.parameters.size(); ++p) {
    const auto s = r.parameters[p].status;
    if (s == ParameterStatus::identifiable || s == ParameterStatus::in_combination)
      g.index.push_back(static_cast<Index>(p));
  }
  const auto k = static_cast<Index>(g.index.size());
  g.error.resize(k);
  g.covariance.resize(k, k);
  for (Index a = 0; a < k; ++a) {
    const Index pa = g.index[static_cast<std::size_t>(a)];
    g.error[a] = r.parameters[static_cast<std::size_t>(pa)].value - tg[pa];
    for (Index b = 0; b < k; ++b) g.covariance(a, b) = r.data_covariance(pa, g.index[static_cast<std::size_t>(b)]);
  }
  return g;
}

// ---- hand-checkable cases ------------------------------------------------------------------

// Only E_XX c1 = s: e_x = −E_XX(q_x) = −s·u_x, u_x = (2 q_x − 600)/600, evaluated at the
// reading: p = w − s(2p − 600)/600, so p = (w + s)/(1 + 2s/600) and a true length L along x is
// measured L/(1 + 2s/600). The estimator evaluates the first-order model at the fitted true
// positions (hole_plate.h, accuracy), so it finds the scale that maps w to p there:
// ŝ = s/(1 + 2s/600), 1.3e-8 mm (the second-order |e|·|∇e|) below s. One XY placement of a
// perfect plate, no noise.
TEST(HolePlateHand, PureScaleErrorOfXIsRecovered) {
  const em::KinematicModel m = zero_model(1, 1);
  const double s = 2e-3;  // mm: E_XX changes by 4 µm over the 600 mm travel
  const em::KinematicErrors truth = errors_with(m, {{em::AxisError::E_XX, {0.0, s}}});
  const HolePlate plate = grid_hole_plate(4, 100.0, 0.0);
  for (const RigidPose& pose : {pose_deg(0, 0, 0, {300, 300, 0}), pose_deg(0, 0, 30, {250, 320, 0})}) {
    const std::vector<SimulatedPlacement> plan = {{"xy", "", pose, {0, 0, -100}, {}}};
    em::SeededRandomSource rng(1);
    const auto data = simulate_hole_plate_measurements(m, truth, plate, plan, 0.0, rng,
                                                       em::Formula::first_order, false);
    // By hand: R1C1 and R1C4 are 300 mm apart along the plate's x axis.
    const Eigen::Vector3d d = data.placements[0].measured_mm.col(3) - data.placements[0].measured_mm.col(0);
    const Eigen::Vector3d nominal = pose.rotation * Eigen::Vector3d(300, 0, 0);
    EXPECT_NEAR(d.x(), nominal.x() / (1.0 + 2.0 * s / 600.0), 1e-12);
    EXPECT_NEAR(d.y(), nominal.y(), 1e-12);

    const KinematicCharacterization r =
        estimate_kinematic_errors(data.placements, plate, options_for(m, 1e-4));
    ASSERT_TRUE(r.usable) << r.message;
    EXPECT_EQ(r.status, HolePlateFitStatus::converged);
    EXPECT_EQ(param(r, "E_XX c1").status, ParameterStatus::identifiable);
    EXPECT_NEAR(param(r, "E_XX c1").value, s / (1.0 + 2.0 * s / 600.0), 1e-12);
    EXPECT_EQ(param(r, "E_YY c1").status, ParameterStatus::identifiable);
    EXPECT_NEAR(param(r, "E_YY c1").value, 0.0, 1e-12);
    EXPECT_LT(r.residual_rms_mm, 1e-12);
    EXPECT_LT((r.setups[0].pose.rotation - pose.rotation).norm(), 1e-13);
  }
}

// Only E_C0Y = γ: a point truly at (x, y) is measured at x + γ q_y (docs/kinematics.md). The
// squareness is estimated "in combination" (E_XY c1 is fixed at 0 by convention; the truth has
// E_XY c1 = 0, so the gauge changes nothing here).
TEST(HolePlateHand, SquarenessIsRecovered) {
  const em::KinematicModel m = zero_model(1, 1);
  const double g = 5e-6;
  const em::KinematicErrors truth = errors_with(m, {}, {g, 0, 0});
  const HolePlate plate = grid_hole_plate(4, 100.0, 0.0);
  const std::vector<SimulatedPlacement> plan = {{"xy", "", pose_deg(0, 0, 0, {300, 300, 0}), {0, 0, -100}, {}}};
  em::SeededRandomSource rng(1);
  const auto data = simulate_hole_plate_measurements(m, truth, plate, plan, 0.0, rng,
                                                     em::Formula::first_order, false);
  // R4C1 lies 300 mm above R1C1 in y: its x is measured γ·300 further.
  EXPECT_NEAR(data.placements[0].measured_mm(0, 12) - data.placements[0].measured_mm(0, 0), g * 300.0, 1e-13);
  const KinematicCharacterization r = estimate_kinematic_errors(data.placements, plate, options_for(m, 1e-4));
  ASSERT_TRUE(r.usable) << r.message;
  EXPECT_EQ(param(r, "E_C0Y").status, ParameterStatus::in_combination);
  EXPECT_EQ(param(r, "E_XY c1").status, ParameterStatus::by_convention);
  EXPECT_NEAR(param(r, "E_C0Y").value, g, 1e-13);
}

// ---- identifiability -----------------------------------------------------------------------

// The plate only in XY planes (two heights, vertical stylus): the Z axis is never moved within
// a setup, so every Z function and the two squareness errors of Z are invisible.
TEST(HolePlateIdentifiability, PlateOnlyInXYLeavesZUnidentified) {
  const em::KinematicModel m = zero_model(2, 2);
  const HolePlate plate = grid_hole_plate(3, 150.0, 0.3e-3);
  const std::vector<SimulatedPlacement> plan = {
      {"low", "", pose_deg(0, 0, 0, {300, 300, -50}), {0, 0, -100}, {}},
      {"high", "", pose_deg(0, 0, 0, {300, 300, 350}), {0, 0, -100}, {}},
      {"low_turned", "", pose_deg(0, 0, 90, {300, 300, -50}), {0, 0, -100}, {}}};
  em::SeededRandomSource rng(3);
  const auto data = simulate_hole_plate_measurements(m, m.nominal(), plate, plan, 0.2e-3, rng);
  HolePlateFitOptions o = options_for(m, 0.2e-3);
  o.unidentified_translation_u_mm = 2e-3;
  o.unidentified_rotation_u_rad = 3e-6;
  const KinematicCharacterization r = estimate_kinematic_errors(data.placements, plate, o);
  ASSERT_TRUE(r.usable) << r.message;
  for (const char* f : {"E_XZ", "E_YZ", "E_ZZ", "E_AZ", "E_BZ", "E_CZ"}) {
    for (int n = 0; n <= 2; ++n) {
      const auto& p = param(r, std::string(f) + " c" + std::to_string(n));
      EXPECT_TRUE(p.status == ParameterStatus::not_identifiable ||
                  p.status == ParameterStatus::by_convention)
          << p.name << " is " << to_string(p.status);
    }
    EXPECT_EQ(param(r, std::string(f) + " c2").status, ParameterStatus::not_identifiable) << f;
  }
  for (const char* s : {"E_B0Z", "E_A0Z"}) {
    EXPECT_EQ(param(r, s).status, ParameterStatus::not_identifiable) << s;
    EXPECT_DOUBLE_EQ(param(r, s).standard_uncertainty, 3e-6);  // the a-priori u, no estimate
    EXPECT_EQ(param(r, s).value, 0.0);
  }
  EXPECT_EQ(param(r, "E_ZZ c2").standard_uncertainty, 2e-3);
  // The scales of X and Y and the XY squareness are seen.
  EXPECT_EQ(param(r, "E_XX c1").status, ParameterStatus::identifiable);
  EXPECT_EQ(param(r, "E_YY c2").status, ParameterStatus::identifiable);
  EXPECT_NE(r.message.find("not identifiable"), std::string::npos);
  const std::string section = kinematics_json_section(r, "test");
  EXPECT_NE(section.find("NOT identifiable from this plan"), std::string::npos);
  EXPECT_NE(section.find("E_ZZ c2"), std::string::npos);
  // Still loadable; the not-identifiable coefficients carry the a-priori u.
  const em::DigitalModel loaded = model_with_kinematics(section, "xy_only.json");
  const Index p = loaded.kinematics.parameter_offset(em::AxisError::E_ZZ) + 2;
  EXPECT_NEAR(std::sqrt(loaded.kinematics.covariance()(p, p)), 2e-3, 1e-15);
}

// A full 3D plan (XY at two heights, XZ, YZ) measured with the stylus tip at the ram reference
// point (t = 0): the rotations of Z act only through ε_Z × t = 0, and the yaw of X through
// ẑ × (q_z ẑ + t) = 0, so they are invisible; with lateral and vertical stylus offsets (three
// styli per setup) they are identified. The roll of X acts with the Z travel as its arm and is
// seen in both.
TEST(HolePlateIdentifiability, NoAbbeArmHidesRotationsOfZAndYawOfX) {
  const em::KinematicModel m = zero_model(2, 1);
  const HolePlate plate = grid_hole_plate(3, 150.0, 0.3e-3);
  const RigidPose xy_low = pose_deg(0, 0, 0, {300, 300, 50}), xy_high = pose_deg(0, 0, 0, {300, 300, 450});
  const RigidPose xz = pose_deg(90, 0, 0, {300, 100, 250}), yz = pose_deg(0, -90, 0, {100, 300, 250});
  const std::vector<SimulatedPlacement> no_arm = {{"xy_low", "", xy_low, {0, 0, 0}, {}},
                                                  {"xy_high", "", xy_high, {0, 0, 0}, {}},
                                                  {"xz", "", xz, {0, 0, 0}, {}},
                                                  {"yz", "", yz, {0, 0, 0}, {}}};
  em::SeededRandomSource rng(5);
  const auto data = simulate_hole_plate_measurements(m, m.nominal(), plate, no_arm, 0.2e-3, rng);
  const KinematicCharacterization r = estimate_kinematic_errors(data.placements, plate, options_for(m, 0.2e-3));
  ASSERT_TRUE(r.usable) << r.message;
  for (const char* name : {"E_AZ c1", "E_BZ c1", "E_CZ c1", "E_CX c1"})
    EXPECT_EQ(param(r, name).status, ParameterStatus::not_identifiable) << name;
  EXPECT_EQ(param(r, "E_AX c1").status, ParameterStatus::identifiable);

  const auto with_arms = simulate_hole_plate_measurements(m, m.nominal(), plate, small_complete_plan(), 0.2e-3, rng);
  const KinematicCharacterization r2 = estimate_kinematic_errors(with_arms.placements, plate, options_for(m, 0.2e-3));
  ASSERT_TRUE(r2.usable) << r2.message;
  EXPECT_EQ(count(r2, ParameterStatus::not_identifiable), 0) << r2.message;
  for (const char* name : {"E_AZ c1", "E_BZ c1", "E_CZ c1", "E_CX c1", "E_AX c1"})
    EXPECT_EQ(param(r2, name).status, ParameterStatus::identifiable) << name;
}

// Every reported null direction is invisible: the tip errors it causes at the plan's centres
// are, per setup, a rigid motion (which the pose absorbs) — checked by a least-squares rigid
// fit of the displacement field; and the intrinsic ones are the 21 of a moving bridge.
TEST(HolePlateIdentifiability, NullDirectionsAreInvisible) {
  const em::KinematicModel m = zero_model(2, 1);
  const HolePlate plate = grid_hole_plate(3, 150.0, 0.0);
  const auto plan = small_complete_plan();
  em::SeededRandomSource rng(7);
  const auto data = simulate_hole_plate_measurements(m, m.nominal(), plate, plan, 0.2e-3, rng);
  const KinematicCharacterization r = estimate_kinematic_errors(data.placements, plate, options_for(m, 0.2e-3));
  ASSERT_TRUE(r.usable) << r.message;
  EXPECT_EQ(count(r, ParameterStatus::by_convention), 21);
  ASSERT_EQ(r.null_directions.size(), 21u);
  for (const NullDirection& nd : r.null_directions) {
    // Scale to 1 µm / 1 µrad of the pivot.
    const double unit = r.parameters[static_cast<std::size_t>(nd.pivot)].rotation ? 1e-6 : 1e-3;
    const em::KinematicErrors e(m, nd.gauge_direction * unit);
    std::map<std::string, std::pair<std::vector<Eigen::Vector3d>, std::vector<Eigen::Vector3d>>> by_setup;
    for (const SimulatedPlacement& sp : plan) {
      const Eigen::Matrix3Xd w = sp.true_pose.apply(plate.calibrated_mm);
      const Eigen::Matrix3Xd d = em::tip_errors(m, e, w, sp.stylus_offset_mm);
      for (Index i = 0; i < w.cols(); ++i) {
        by_setup[sp.setup].first.push_back(w.col(i));
        by_setup[sp.setup].second.push_back(d.col(i));
      }
    }
    for (const auto& [setup, wd] : by_setup) {
      // d ≈ ω × w + τ: 6 unknowns, linear least squares.
      const auto n = static_cast<Index>(wd.first.size());
      Eigen::MatrixXd a(3 * n, 6);
      Eigen::VectorXd b(3 * n);
      for (Index i = 0; i < n; ++i) {
        const Eigen::Vector3d& w = wd.first[static_cast<std::size_t>(i)];
        Eigen::Matrix3d sk;
        sk << 0, w.z(), -w.y(), -w.z(), 0, w.x(), w.y(), -w.x(), 0;  // −[w]×: ω × w = −[w]× ω
        a.block<3, 3>(3 * i, 0) = sk;
        a.block<3, 3>(3 * i, 3) = Eigen::Matrix3d::Identity();
        b.segment<3>(3 * i) = wd.second[static_cast<std::size_t>(i)];
      }
      const Eigen::VectorXd x = a.colPivHouseholderQr().solve(b);
      // Exact to rounding of µm-size displacements: 1e-12 mm.
      EXPECT_LT((a * x - b).cwiseAbs().maxCoeff(), 1e-12) << nd.text << " in setup " << setup;
    }
  }
  // A parameter reported identifiable is visible: E_XX c2 moves the centres non-rigidly.
  EXPECT_EQ(param(r, "E_XX c2").status, ParameterStatus::identifiable);
}

// ---- round trip ----------------------------------------------------------------------------

// A truth drawn from examples/cmm_model.json's kinematic model (degrees 3/2 on a 1200 × 1000 ×
// 800 mm moving bridge), measured with the example plan (10 placements of a 4×4 plate):
// everything but the 21 intrinsic directions is identified; each estimate lies within 4 u of
// the truth expressed in the gauge (a fixed seed; |z| > 4 has probability 6e-5 per parameter);
// the written section loads as the kinematics of a digital-model file with the same numbers.
TEST(HolePlateRoundTrip, RecoversTruthDrawnFromExampleModel) {
  const em::KinematicModel& km = example_model().kinematics;
  em::SeededRandomSource rng(101);
  const em::KinematicErrors truth = km.draw(rng);
  const HolePlate plate = vcmm::examples::hole_plate_example_plate();
  const auto data = simulate_hole_plate_measurements(km, truth, plate, vcmm::examples::hole_plate_example_plan(),
                                                     0.2e-3, rng);
  const KinematicCharacterization r = estimate_kinematic_errors(data.placements, plate, options_for(km, 0.2e-3));
  ASSERT_TRUE(r.usable) << r.message;
  EXPECT_EQ(count(r, ParameterStatus::not_identifiable), 0);
  EXPECT_EQ(count(r, ParameterStatus::by_convention), 21);
  const GaugeErrors g = gauge_errors(r, truth.parameters());
  ASSERT_EQ(g.index.size(), 45u);
  for (std::size_t a = 0; a < g.index.size(); ++a) {
    const auto& p = r.parameters[static_cast<std::size_t>(g.index[a])];
    EXPECT_LT(std::abs(g.error[static_cast<Index>(a)]), 4.0 * std::sqrt(g.covariance(static_cast<Index>(a), static_cast<Index>(a))))
        << p.name;
  }
  EXPECT_GT(r.variance_factor, 0.7);
  EXPECT_LT(r.variance_factor, 1.3);  // dof ≈ 400: s0² within 1 ± 0.3 is > 4 sd

  const std::string section = kinematics_json_section(r, "test data");
  const em::DigitalModel loaded = model_with_kinematics(section, "estimated.json");
  const em::KinematicModel& lk = loaded.kinematics;
  ASSERT_EQ(lk.parameter_count(), r.model.parameter_count());
  EXPECT_TRUE(lk.chain() == km.chain());
  for (Index p = 0; p < lk.parameter_count(); ++p) {
    // µm/µrad and back: a few ulp.
    EXPECT_NEAR(lk.mean()[p], r.model.mean()[p], 1e-15) << p;
    EXPECT_NEAR(std::sqrt(lk.covariance()(p, p)), std::sqrt(r.model.covariance()(p, p)), 1e-15) << p;
  }
  // The correlation within a function survives; between functions it is dropped.
  const Index a = lk.parameter_offset(em::AxisError::E_XX) + 1, b = a + 2;
  EXPECT_NEAR(lk.covariance()(a, b), r.model.covariance()(a, b),
              1e-9 * std::sqrt(r.model.covariance()(a, a) * r.model.covariance()(b, b)));
}

// ---- honest uncertainties ------------------------------------------------------------------

// 200 seeds: truth drawn from a degree-2/1 model with the example's magnitudes, plate
// calibration error and probing noise drawn too (small machine, 3×3 plate, compact plan).
// (a) The fraction of |error| ≤ 2u over all estimated parameters and seeds should be
//     P(|z| ≤ 2) = 0.9545. Parameters of one seed are correlated, so the pooled fraction varies
//     at most like that of one parameter over 200 independent seeds: sd ≤ √(0.9545·0.0455/200)
//     = 0.0147; we allow 4 sd: [0.896, 1].
// (b) The Mahalanobis distance d² = eᵀC⁻¹e of each seed's error with the covariance *before*
//     the variance-factor scaling is χ²_k: the mean of d²/k over 200 independent seeds is
//     1 ± √(2/(200 k)) (k ≈ 27: sd 0.019); allow 4 sd. This also catches overstated u.
TEST(HolePlateHonesty, UncertaintiesAreHonestOver200Seeds) {
  const em::KinematicModel tm = small_truth_model();
  const HolePlate plate = grid_hole_plate(3, 150.0, 0.3e-3);
  const auto plan = small_complete_plan();
  const HolePlateFitOptions o = options_for(tm, 0.2e-3);
  const int seeds = 200;
  long within = 0, total = 0;
  double d2_over_k = 0.0;
  Index k_seen = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int seed = 1; seed <= seeds; ++seed) {
    em::SeededRandomSource rng(static_cast<std::uint64_t>(seed));
    const em::KinematicErrors truth = tm.draw(rng);
    const auto data = simulate_hole_plate_measurements(tm, truth, plate, plan, 0.2e-3, rng);
    const KinematicCharacterization r = estimate_kinematic_errors(data.placements, plate, o);
    ASSERT_TRUE(r.usable) << "seed " << seed << ": " << r.message;
    ASSERT_EQ(count(r, ParameterStatus::not_identifiable), 0) << "seed " << seed;
    const GaugeErrors g = gauge_errors(r, truth.parameters());
    const auto k = static_cast<Index>(g.index.size());
    for (Index a = 0; a < k; ++a) within += std::abs(g.error[a]) <= 2.0 * std::sqrt(g.covariance(a, a));
    total += k;
    const Eigen::MatrixXd unscaled = g.covariance / (r.covariance_scaled ? r.variance_factor : 1.0);
    d2_over_k += g.error.dot(unscaled.ldlt().solve(g.error)) / static_cast<double>(k);
    k_seen = k;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double fraction = static_cast<double>(within) / static_cast<double>(total);
  const double mean_d2 = d2_over_k / seeds;
  const double sd_d2 = std::sqrt(2.0 / (seeds * static_cast<double>(k_seen)));
  std::printf("[ info ] %d seeds, %ld estimates: fraction within 2u %.4f, mean d2/k %.4f "
              "(k = %ld, sd %.4f), %.1f ms per fit\n",
              seeds, total, fraction, mean_d2, static_cast<long>(k_seen), sd_d2, 1e3 * seconds / seeds);
  EXPECT_GE(fraction, 0.9545 - 4.0 * 0.0147);
  EXPECT_NEAR(mean_d2, 1.0, 4.0 * sd_d2);
}

// ---- other chains --------------------------------------------------------------------------

// The same procedure on a fixed bridge (Y table): converges, identifies everything but its own
// intrinsic directions, and recovers a truth within 4 u.
TEST(HolePlateRoundTrip, FixedBridgeChain) {
  const em::KinematicModel tm0 = small_truth_model();
  std::array<em::ErrorFunctionEstimate, em::axis_error_count> fns;
  for (int f = 0; f < em::axis_error_count; ++f) {
    const auto e = static_cast<em::AxisError>(f);
    for (int i = 0; i < tm0.coefficient_count(e); ++i) {
      const Index p = tm0.parameter_offset(e) + i;
      fns[static_cast<std::size_t>(f)].coefficients.push_back(tm0.mean()[p]);
      fns[static_cast<std::size_t>(f)].standard_uncertainties.push_back(std::sqrt(tm0.covariance()(p, p)));
    }
  }
  const em::KinematicModel tm(em::KinematicChain::fixed_bridge(), kSmall, fns, {});
  em::SeededRandomSource rng(77);
  const em::KinematicErrors truth = tm.draw(rng);
  const HolePlate plate = grid_hole_plate(3, 150.0, 0.3e-3);
  const auto data = simulate_hole_plate_measurements(tm, truth, plate, small_complete_plan(), 0.2e-3, rng);
  const KinematicCharacterization r = estimate_kinematic_errors(data.placements, plate, options_for(tm, 0.2e-3));
  ASSERT_TRUE(r.usable) << r.message;
  EXPECT_EQ(count(r, ParameterStatus::not_identifiable), 0) << r.message;
  const GaugeErrors g = gauge_errors(r, truth.parameters());
  for (Index a = 0; a < g.error.size(); ++a)
    EXPECT_LT(std::abs(g.error[a]), 4.0 * std::sqrt(g.covariance(a, a)))
        << r.parameters[static_cast<std::size_t>(g.index[static_cast<std::size_t>(a)])].name;
  const std::string section = kinematics_json_section(r, "fixed bridge");
  EXPECT_NE(section.find("\"fixed_bridge\""), std::string::npos);
  EXPECT_NO_THROW(model_with_kinematics(section, "fixed.json"));
}

// ---- the bundled example -------------------------------------------------------------------

// The files in examples/characterization/hole_plate are what hole_plate_example_files makes
// (README: regenerate with make_hole_plate_example), to 1e-12 mm; fitting them recovers the
// bundled truth within 4 u.
TEST(HolePlateExample, BundledFilesAreReproducedAndFitRecoversTheTruth) {
  const std::string dir = kSource + "/examples/characterization/hole_plate/";
  const auto files = vcmm::examples::hole_plate_example_files(example_model());
  const HolePlate plate = read_hole_plate_csv_file(dir + "plate.csv");
  std::vector<HolePlatePlacement> placements;
  for (const auto& [name, content] : files) {
    if (name == "plate.csv") {
      std::istringstream in(content);
      const HolePlate generated = read_hole_plate_csv(in, name);
      EXPECT_EQ(generated.ids, plate.ids);
      EXPECT_LT((generated.calibrated_mm - plate.calibrated_mm).cwiseAbs().maxCoeff(), 1e-12);
    } else if (name.ends_with(".csv")) {
      placements.push_back(read_hole_plate_placement_csv_file(dir + name));
      std::istringstream in(content);
      const HolePlatePlacement generated = read_hole_plate_placement_csv(in, name);
      EXPECT_EQ(generated.ids, placements.back().ids) << name;
      EXPECT_EQ(generated.setup, placements.back().setup) << name;
      EXPECT_EQ(generated.stylus_offset_mm, placements.back().stylus_offset_mm) << name;
      EXPECT_LT((generated.measured_mm - placements.back().measured_mm).cwiseAbs().maxCoeff(), 1e-12) << name;
    }
  }
  ASSERT_EQ(placements.size(), 10u);
  const em::DigitalModel truth_model = model_with_kinematics(
      nlohmann::json::parse(read_text(dir + "truth_kinematics.json"))["kinematics"].dump(), "truth");
  const KinematicCharacterization r =
      estimate_kinematic_errors(placements, plate, options_for(truth_model.kinematics, 0.2e-3));
  ASSERT_TRUE(r.usable) << r.message;
  EXPECT_EQ(count(r, ParameterStatus::not_identifiable), 0);
  const GaugeErrors g = gauge_errors(r, truth_model.kinematics.mean());
  for (Index a = 0; a < g.error.size(); ++a)
    EXPECT_LT(std::abs(g.error[a]), 4.0 * std::sqrt(g.covariance(a, a)))
        << r.parameters[static_cast<std::size_t>(g.index[static_cast<std::size_t>(a)])].name;
}

// ---- files ---------------------------------------------------------------------------------

TEST(HolePlateFiles, RoundTripBitExact) {
  HolePlate plate = grid_hole_plate(3, 150.0, 0.3e-3);
  plate.calibrated_mm(0, 4) = 0.1 + 0.2;  // a double with no short decimal
  std::istringstream in(hole_plate_csv(plate, std::vector<std::string>{"a comment"}));
  const HolePlate back = read_hole_plate_csv(in, "plate.csv");
  EXPECT_EQ(back.ids, plate.ids);
  EXPECT_EQ(back.calibrated_mm, plate.calibrated_mm);
  for (std::size_t i = 0; i < plate.ids.size(); ++i)
    EXPECT_NEAR(back.calibration_u_mm[i], plate.calibration_u_mm[i], 1e-18);

  HolePlatePlacement pl;
  pl.name = "p1";
  pl.setup = "s1";
  pl.ids = {"A", "B", "C"};
  pl.measured_mm = Eigen::Matrix3Xd::Random(3, 3) * 500.0;
  pl.stylus_offset_mm = {1.5, -2.25, -150.125};
  std::istringstream pin(hole_plate_placement_csv(pl));
  const HolePlatePlacement pback = read_hole_plate_placement_csv(pin, "ignored.csv");
  EXPECT_EQ(pback.name, "p1");
  EXPECT_EQ(pback.setup, "s1");
  EXPECT_EQ(pback.ids, pl.ids);
  EXPECT_EQ(pback.measured_mm, pl.measured_mm);
  EXPECT_EQ(pback.stylus_offset_mm, pl.stylus_offset_mm);
}

// Each rule of the readers, with the file name and 1-based line in the message.
TEST(HolePlateFiles, BadFilesNameFileLineAndField) {
  auto plate_error = [](const std::string& text) {
    std::istringstream in(text);
    try {
      (void)read_hole_plate_csv(in, "plate.csv");
    } catch (const em::InvalidInput& ex) {
      return std::string(ex.what());
    }
    return std::string("no exception");
  };
  const std::string h = "id,x_mm,y_mm,z_mm,u_um\n";
  const std::string ok3 = "A,0,0,0,0.3\nB,100,0,0,0.3\nC,0,100,0,0.3\n";
  EXPECT_EQ(plate_error(h + ok3), "no exception");
  EXPECT_NE(plate_error("id,x,y,z,u\n" + ok3).find("plate.csv:1: expected the header"), std::string::npos);
  EXPECT_NE(plate_error(h + "A,0,0,0\n").find("plate.csv:2: expected 5 fields"), std::string::npos);
  EXPECT_NE(plate_error(h + "A,0,abc,0,0.3\n").find("plate.csv:2: field 3 (y_mm) is not a number"), std::string::npos);
  EXPECT_NE(plate_error(h + "A,0,0,nan,0.3\n").find("plate.csv:2: field 4 (z_mm) is not finite"), std::string::npos);
  EXPECT_NE(plate_error(h + "A,0,0,0,-1\n").find("plate.csv:2: field 5 (u_um) must lie in [0, 1000] µm"), std::string::npos);
  // Issue 12: a plate u of 1e300 µm was blamed on "collinear features"; it is the value.
  EXPECT_NE(plate_error(h + "A,0,0,0,1e300\n")
                .find("plate.csv:2: field 5 (u_um) must lie in [0, 1000] µm (a standard "
                      "deviation); got 1e+300 µm"),
            std::string::npos);
  EXPECT_NE(plate_error(h + "A,0,0,0,1\nA,1,0,0,1\n").find("plate.csv:3: feature id 'A' repeated (first on line 2)"), std::string::npos);
  EXPECT_NE(plate_error(h + ",0,0,0,1\n").find("plate.csv:2: field 1 (id) is empty"), std::string::npos);
  EXPECT_NE(plate_error(h + "A,0,0,0,1\nB,1,0,0,1\n").find("at least 3 features; got 2"), std::string::npos);
  EXPECT_NE(plate_error("# format: vcmm.hole_plate 2\n" + h + ok3).find("plate.csv:1: unsupported format"), std::string::npos);
  EXPECT_NE(plate_error("# only comments\n").find("no header"), std::string::npos);

  auto placement_error = [](const std::string& text) {
    std::istringstream in(text);
    try {
      (void)read_hole_plate_placement_csv(in, "p.csv");
    } catch (const em::InvalidInput& ex) {
      return std::string(ex.what());
    }
    return std::string("no exception");
  };
  const std::string ph = "id,x_mm,y_mm,z_mm\n";
  const std::string meta = "# stylus_offset_mm: 0, 0, -100\n";
  EXPECT_EQ(placement_error(meta + ph + "A,1,2,3\n"), "no exception");
  EXPECT_NE(placement_error(ph + "A,1,2,3\n").find("p.csv:1: metadata line '# stylus_offset_mm"), std::string::npos);
  EXPECT_NE(placement_error(meta + meta + ph).find("p.csv:2: metadata key 'stylus_offset_mm' repeated"), std::string::npos);
  EXPECT_NE(placement_error("# stylus_offset_mm: 0, 0\n" + ph).find("p.csv:1: stylus_offset_mm needs 3"), std::string::npos);
  EXPECT_NE(placement_error("# stylus_offset_mm: 0, x, 0\n" + ph).find("stylus_offset_mm component 2 is not a number"), std::string::npos);
  EXPECT_NE(placement_error(meta + ph + "A,1,2\n").find("p.csv:3: expected 4 fields"), std::string::npos);
  EXPECT_NE(placement_error(meta + ph + "A,1,inf,3\n").find("p.csv:3: field 3 (y_mm) is not finite"), std::string::npos);
  EXPECT_NE(placement_error(meta + ph + "A,1,2,3\nA,1,2,3\n").find("p.csv:4: feature id 'A' repeated"), std::string::npos);
  EXPECT_NE(placement_error(meta + ph).find("no measured features"), std::string::npos);
  EXPECT_NE(placement_error(meta + "x,y,z\n").find("p.csv:2: expected the header"), std::string::npos);

  EXPECT_THROW((void)read_hole_plate_csv_file("/nonexistent/plate.csv"), em::InvalidInput);
  EXPECT_THROW((void)read_hole_plate_placement_csv_file("/nonexistent/p.csv"), em::InvalidInput);
}

// ---- bad input -----------------------------------------------------------------------------

class HolePlateBadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    plate = grid_hole_plate(3, 150.0, 0.3e-3);
    em::SeededRandomSource rng(9);
    const std::vector<SimulatedPlacement> plan = {
        {"p", "", pose_deg(0, 0, 0, {300, 300, -50}), {0, 0, -100}, {}}};
    placements = simulate_hole_plate_measurements(model, model.nominal(), plate, plan, 0.2e-3, rng).placements;
    options = options_for(model, 0.2e-3);
  }
  // The message of the InvalidInput thrown by the estimate, or "no exception".
  std::string error() const {
    try {
      (void)estimate_kinematic_errors(placements, plate, options);
    } catch (const em::InvalidInput& ex) {
      return ex.what();
    }
    return "no exception";
  }
  em::KinematicModel model = zero_model(1, 1);
  HolePlate plate;
  std::vector<HolePlatePlacement> placements;
  HolePlateFitOptions options;
};

TEST_F(HolePlateBadInput, ValidInputIsAccepted) { EXPECT_EQ(error(), "no exception"); }

TEST_F(HolePlateBadInput, Plate) {
  HolePlate p = plate;
  plate.ids.resize(2);
  plate.calibrated_mm.conservativeResize(3, 2);
  plate.calibration_u_mm.resize(2);
  EXPECT_NE(error().find("the plate needs at least 3 features; got 2"), std::string::npos);
  plate = p;
  plate.ids[4] = plate.ids[3];
  EXPECT_NE(error().find("plate feature id 'R2C1' appears twice (features 3 and 4)"), std::string::npos);
  plate = p;
  plate.calibrated_mm(1, 2) = std::nan("");
  EXPECT_NE(error().find("plate feature 'R1C3' has a non-finite calibrated coordinate"), std::string::npos);
  plate = p;
  plate.calibration_u_mm[0] = -1e-3;
  EXPECT_NE(error().find("calibration uncertainty must be finite and >= 0"), std::string::npos);
  plate = p;
  plate.ids[0] = "";
  EXPECT_NE(error().find("plate feature 0 has an empty id"), std::string::npos);
}

TEST_F(HolePlateBadInput, Placements) {
  const auto good = placements;
  placements.clear();
  EXPECT_NE(error().find("no placements given"), std::string::npos);
  placements = good;
  placements[0].ids[2] = "Z9";
  EXPECT_NE(error().find("placement 'p': feature 'Z9' is not on the plate"), std::string::npos);
  placements = good;
  placements[0].ids[2] = placements[0].ids[1];
  EXPECT_NE(error().find("feature 'R1C2' measured twice (entries 1 and 2)"), std::string::npos);
  placements = good;
  placements[0].measured_mm(2, 5) = std::numeric_limits<double>::infinity();
  EXPECT_NE(error().find("feature 'R2C3' has a non-finite measured coordinate"), std::string::npos);
  placements = good;
  placements[0].ids.resize(2);
  placements[0].measured_mm.conservativeResize(3, 2);
  EXPECT_NE(error().find("needs at least 3 measured features; got 2"), std::string::npos);
  placements = good;
  placements[0].stylus_offset_mm.x() = std::nan("");
  EXPECT_NE(error().find("stylus offset must be finite"), std::string::npos);
  placements = good;
  placements[0].stylus_offset_mm.z() = 100.0;  // q_z = -50 - 100 < 0
  EXPECT_NE(error().find("the Z axis reading -150 mm"), std::string::npos);
  placements = good;
  placements[0].ids = {"R1C1", "R1C2", "R1C3"};  // one row: collinear
  placements[0].measured_mm.conservativeResize(3, 3);
  EXPECT_NE(error().find("setup 'p': its 3 measured features are collinear"), std::string::npos);
}

TEST_F(HolePlateBadInput, Options) {
  const auto good = options;
  options.probing_sigma_mm = 0.0;
  EXPECT_NE(error().find("probing_sigma_mm must be finite and > 0"), std::string::npos);
  options = good;
  options.probing_sigma_mm = std::nan("");
  EXPECT_NE(error().find("probing_sigma_mm must be finite and > 0"), std::string::npos);
  options = good;
  options.degrees[3] = 11;
  EXPECT_NE(error().find("degree of E_AX must be 0 to 10; got 11"), std::string::npos);
  options = good;
  options.rank_tolerance = 0.0;
  EXPECT_NE(error().find("rank_tolerance must lie in (0, 1)"), std::string::npos);
  options = good;
  options.axis_ranges[1] = {600.0, 0.0};
  EXPECT_NE(error().find("axis range of Y must be finite with min < max"), std::string::npos);
  options = good;
  options.unidentified_rotation_u_rad = -1.0;
  EXPECT_NE(error().find("unidentified_rotation_u_rad must be finite and >= 0"), std::string::npos);
  options = good;
  options.max_iterations = 0;
  EXPECT_NE(error().find("max_iterations must be >= 1"), std::string::npos);
  options = good;
  options.chain.tool_side.push_back(em::Axis::x);
  EXPECT_NE(error().find("invalid kinematic chain"), std::string::npos);
}

// Not converged is a report, not an exception: usable false, and no section is written.
TEST_F(HolePlateBadInput, NotConvergedIsReportedNotUsable) {
  options.max_iterations = 1;
  const KinematicCharacterization r = estimate_kinematic_errors(placements, plate, options);
  EXPECT_EQ(r.status, HolePlateFitStatus::not_converged);
  EXPECT_FALSE(r.usable);
  EXPECT_NE(r.message.find("NOT converged"), std::string::npos);
  EXPECT_THROW((void)kinematics_json_section(r, "x"), em::InvalidInput);
  EXPECT_THROW((void)express_in_gauge(r, Eigen::VectorXd::Zero(3)), em::InvalidInput);
}

TEST(HolePlateBadSimulation, Plans) {
  const em::KinematicModel m = zero_model(1, 1);
  const HolePlate plate = grid_hole_plate(3, 150.0, 0.0);
  em::SeededRandomSource rng(1);
  auto err = [&](std::vector<SimulatedPlacement> plan, double sigma = 0.0) {
    try {
      (void)simulate_hole_plate_measurements(m, m.nominal(), plate, plan, sigma, rng);
    } catch (const em::InvalidInput& ex) {
      return std::string(ex.what());
    }
    return std::string("no exception");
  };
  const SimulatedPlacement ok = {"p", "s", pose_deg(0, 0, 0, {300, 300, 0}), {0, 0, -100}, {}};
  EXPECT_EQ(err({ok}), "no exception");
  EXPECT_NE(err({ok}, -1.0).find("probing sigma must be finite and >= 0"), std::string::npos);
  SimulatedPlacement moved = ok;
  moved.true_pose.translation_mm.x() += 1.0;
  EXPECT_NE(err({ok, moved}).find("setup 's' is used with two different poses"), std::string::npos);
  SimulatedPlacement unknown = ok;
  unknown.ids = {"R1C1", "nope"};
  EXPECT_NE(err({unknown}).find("feature 'nope' is not on the plate"), std::string::npos);
  SimulatedPlacement outside = ok;
  outside.true_pose.translation_mm.x() = 550.0;
  EXPECT_NE(err({outside}).find("X axis reading"), std::string::npos);
  SimulatedPlacement bad_rotation = ok;
  bad_rotation.true_pose.rotation(0, 0) = 2.0;
  EXPECT_NE(err({bad_rotation}).find("not a proper rotation"), std::string::npos);
  EXPECT_THROW((void)grid_hole_plate(1, 100.0, 0.0), em::InvalidInput);
  EXPECT_THROW((void)grid_hole_plate(3, -1.0, 0.0), em::InvalidInput);
}

}  // namespace
