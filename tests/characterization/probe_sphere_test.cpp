// Probe errors from a calibrated sphere (characterization/probe_sphere.h): hand cases (δr only,
// one harmonic), identifiability (order 1, rank-deficient plans), round trips through the
// virtual CMM with known truth, honesty of the uncertainties over 200 seeds, the form
// contribution, the JSON section loading into a model file, plans, the points-file reader and
// bad input.
#include "vcmm/characterization/probe_sphere.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>

#include "vcmm/characterization/cmm_points_file.h"
#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/errors.h"
#include "vcmm/errormodel/random_source.h"
#include "vcmm/errormodel/virtual_cmm.h"

namespace {

using namespace vcmm::characterization;
namespace em = vcmm::errormodel;
constexpr double kPi = std::numbers::pi;
constexpr double kUm = 1e-3;  // mm per µm

const std::string kExample = std::string(VCMM_SOURCE_DIR) + "/examples/cmm_model.json";
const std::array<em::AxisRange, 3> kRanges = {{{0.0, 1200.0}, {0.0, 1000.0}, {0.0, 800.0}}};
const Eigen::Vector3d kCentre(612.5, 401.25, 255.0);  // machine coordinates of the sphere
constexpr double kDiameter = 25.0;

em::DigitalModel perfect_machine() {
  return em::DigitalModel(em::KinematicModel::zero(em::KinematicChain::moving_bridge(), kRanges));
}

em::Placement placement(double orientation_rad = 0.0) {
  em::Placement p;
  p.location_mm = kCentre;
  p.orientation_rad = orientation_rad;
  return p;
}

/// Points (machine coordinates) a CMM with probe errors `truth` and touch-trigger noise σ
/// reports on a sphere of true diameter `true_diameter` (stages probe and noise only).
Eigen::Matrix3Xd simulate_sphere(const em::ProbeModel& truth, double sigma_mm,
                                 const Eigen::Matrix3Xd& directions, double true_diameter,
                                 std::uint64_t seed, double orientation_rad = 0.0) {
  em::DigitalModel model = perfect_machine();
  model.probe = truth;
  model.noise.touch_trigger_sigma_mm = sigma_mm;
  const em::Measurement m = sphere_measurement(
      true_diameter, directions, placement(orientation_rad), em::ProbingMode::touch_trigger);
  em::Stages stages = em::Stages::none();
  stages.set(em::ErrorSource::probe, true).set(em::ErrorSource::noise, true);
  em::SeededRandomSource rng(seed);
  const em::ErrorDraw draw = em::draw_errors(model, m, rng, stages);
  return em::machine_coordinates(em::simulate(m, model, draw, stages));
}

em::ProbeModel probe_truth(double dr_um, std::initializer_list<std::array<double, 3>> h) {
  em::ProbeModel p;
  p.tip_radius_error_mm = {dr_um * kUm, 0.0};
  for (const auto& [k, c, s] : h) {
    em::ProbeHarmonic ph;
    ph.order = static_cast<int>(k);
    ph.cos_mm = {c * kUm, 0.0};
    ph.sin_mm = {s * kUm, 0.0};
    p.directional.push_back(ph);
  }
  return p;
}

/// Truth value of parameter "cos_k"/"sin_k" (0 when the order is not in the truth).
double truth_of(const em::ProbeModel& truth, const std::string& name) {
  if (name == "tip_radius_error") return truth.tip_radius_error_mm.value;
  const bool is_cos = name.starts_with("cos_");
  const int k = std::stoi(name.substr(4));
  for (const em::ProbeHarmonic& h : truth.directional)
    if (h.order == k) return is_cos ? h.cos_mm.value : h.sin_mm.value;
  return 0.0;
}

template <class F>
void expect_invalid(F&& f, const std::string& fragment) {
  try {
    f();
    ADD_FAILURE() << "expected InvalidInput containing '" << fragment << "'";
  } catch (const em::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

// ---- hand cases ----

TEST(ProbeSphere, PerfectSphereWithTipRadiusErrorOnly) {
  // Points exactly at R_cal + δr: δr back to rounding (1e-12 mm), every coefficient 0, no
  // residual. With s = 0 the statistical part vanishes: u(δr)² = (u_D/2)² + u_form².
  const Eigen::Matrix3Xd dirs = iso10360_5_directions();
  const double dr = 0.8 * kUm;
  const Eigen::Matrix3Xd pts = (0.5 * kDiameter + dr) * dirs + kCentre.replicate(1, dirs.cols());
  CalibratedSphere sphere{kDiameter, 0.1 * kUm, 0.0};
  const SphereProbeCharacterization r = characterize_probe_sphere(pts, sphere);
  ASSERT_TRUE(r.usable) << r.message;
  EXPECT_EQ(r.status, SphereFitStatus::ok);
  EXPECT_NEAR(r.tip_radius_error.value_mm, dr, 1e-12);
  EXPECT_NEAR(r.diameter_mm, kDiameter + 2.0 * dr, 2e-12);
  EXPECT_LT((r.center_mm - kCentre).norm(), 1e-12);
  for (const ProbeParameterEstimate& e : r.directional) EXPECT_NEAR(e.value_mm, 0.0, 1e-12);
  EXPECT_LT(r.residual_sigma_mm, 1e-12);
  EXPECT_NEAR(r.tip_radius_error.u_diameter_mm, 0.05 * kUm, 1e-15);
  EXPECT_NEAR(r.tip_radius_error.u_mm, 0.05 * kUm, 1e-12);
  EXPECT_EQ(r.degrees_of_freedom, 25 - 10);
  EXPECT_NEAR(r.t_factor, std::sqrt(15.0 / 13.0), 1e-15);
  EXPECT_EQ(r.orders, (std::vector<int>{2, 3, 4}));
  std::cout << "[ISO 10360-5 plan, orders 2-4] smallest singular value of A/sqrt(N) = "
            << r.min_singular_value << ", Gauss-Newton iterations " << r.iterations << "\n";
}

TEST(ProbeSphere, OneHarmonicOnly) {
  // D(d) = c_3 Re(z³) only, dense plan, no noise: c_3 recovered, everything else 0. The
  // sphere is turned 30° about Z: the directions the model sees are machine directions.
  const em::ProbeModel truth = probe_truth(0.0, {{3.0, 0.25, 0.0}});
  const Eigen::Matrix3Xd pts =
      simulate_sphere(truth, 0.0, dense_hemisphere_directions(), kDiameter, 1, kPi / 6.0);
  const SphereProbeCharacterization r =
      characterize_probe_sphere(pts, {kDiameter, 0.0, 0.0}, {{2, 3, 4, 5}, std::nullopt});
  ASSERT_TRUE(r.usable) << r.message;
  EXPECT_NEAR(r.tip_radius_error.value_mm, 0.0, 1e-12);
  for (const ProbeParameterEstimate& e : r.directional)
    EXPECT_NEAR(e.value_mm, e.name == "cos_3" ? 0.25 * kUm : 0.0, 1e-11) << e.name;
  EXPECT_LT(r.residual_sigma_mm, 1e-11);
}

// ---- identifiability ----

TEST(ProbeSphere, OrderOneIsReportedNotIdentifiableAndNeverOutput) {
  const em::ProbeModel truth = probe_truth(0.3, {{2.0, 0.1, -0.1}});
  const Eigen::Matrix3Xd pts =
      simulate_sphere(truth, 0.05 * kUm, dense_hemisphere_directions(), kDiameter, 2);
  const SphereProbeCharacterization r =
      characterize_probe_sphere(pts, {kDiameter, 0.0, 0.0}, {{1, 2}, std::nullopt});
  ASSERT_TRUE(r.usable) << r.message;
  ASSERT_EQ(r.not_identifiable.size(), 1u);
  EXPECT_EQ(r.not_identifiable[0].what, "order 1");
  EXPECT_NE(r.not_identifiable[0].reason.find("centre"), std::string::npos);
  ASSERT_EQ(r.probe.directional.size(), 1u);
  EXPECT_EQ(r.probe.directional[0].order, 2);
  const nlohmann::json j = nlohmann::json::parse(probe_characterization_json(r, "test"));
  for (const auto& h : j["probe"]["directional_error"]) EXPECT_NE(h["order"], 1);
  EXPECT_EQ(j["characterization"]["not_identifiable"][0]["what"], "order 1");
  EXPECT_NE(j["probe"]["source"].get<std::string>().find("order 1"), std::string::npos);
}

TEST(ProbeSphere, Order8OnTheIsoPlanIsRankDeficient) {
  // sin 8φ vanishes at every azimuth of the 25-point plan (multiples of 22.5°): Im z⁸ ≡ 0.
  const Eigen::Matrix3Xd dirs = iso10360_5_directions();
  const Eigen::Matrix3Xd pts = simulate_sphere(probe_truth(0.2, {}), 0.1 * kUm, dirs, kDiameter, 3);
  const SphereProbeCharacterization r =
      characterize_probe_sphere(pts, {kDiameter, 0.0, 0.0}, {{2, 8}, std::nullopt});
  EXPECT_EQ(r.status, SphereFitStatus::rank_deficient);
  EXPECT_FALSE(r.usable);
  EXPECT_NE(r.message.find("sin_8"), std::string::npos) << r.message;
  EXPECT_LT(r.min_singular_value, kMinSingularValue);
  expect_invalid([&] { (void)probe_section_json(r, "x"); }, "not usable");
}

TEST(ProbeSphere, SingleLatitudeCircleConfoundsCentreZWithTipRadius) {
  // All points at 45° from the pole: u_z is the same for all, so the centre's z column is a
  // multiple of the tip-radius column.
  const SphereCircle circle[] = {{kPi / 4.0, 24, 0.0}};
  const Eigen::Matrix3Xd pts =
      simulate_sphere(probe_truth(0.2, {}), 0.1 * kUm, sphere_directions(circle), kDiameter, 4);
  const SphereProbeCharacterization r =
      characterize_probe_sphere(pts, {kDiameter, 0.0, 0.0}, {{2}, std::nullopt});
  EXPECT_EQ(r.status, SphereFitStatus::rank_deficient);
  EXPECT_NE(r.message.find("centre_z"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("tip_radius_error"), std::string::npos) << r.message;
}

// ---- round trips and honesty ----

TEST(ProbeSphere, RoundTripRecoversKnownProbeModel) {
  // The example model's probe section as truth (δr 0.05 µm, orders 2-4 ≤ 0.08 µm) plus a
  // larger lobing, dense plan, touch-trigger noise 0.2 µm, sphere turned 50°. Fixed seed:
  // every parameter within 3 u (a deterministic check; the honesty test is the statistics).
  em::ProbeModel truth = em::read_digital_model_file(kExample).probe;
  for (em::ProbeHarmonic& h : truth.directional) {
    h.cos_mm.u = h.sin_mm.u = 0.0;
    h.cos_mm.value *= 3.0;
  }
  truth.tip_radius_error_mm.u = 0.0;
  const Eigen::Matrix3Xd pts = simulate_sphere(truth, 0.2 * kUm, dense_hemisphere_directions(),
                                               kDiameter, 5, 50.0 * kPi / 180.0);
  const SphereProbeCharacterization r =
      characterize_probe_sphere(pts, {kDiameter, 0.02 * kUm, 0.0});
  ASSERT_TRUE(r.usable) << r.message;
  EXPECT_NEAR(r.tip_radius_error.value_mm, truth.tip_radius_error_mm.value,
              3.0 * r.tip_radius_error.u_mm);
  for (const ProbeParameterEstimate& e : r.directional)
    EXPECT_NEAR(e.value_mm, truth_of(truth, e.name), 3.0 * e.u_mm) << e.name;
  EXPECT_NEAR(r.residual_sigma_mm, 0.2 * kUm, 0.05 * kUm);  // s of 61 dof: sd ≈ 9 %
}

TEST(ProbeSphere, UncertaintiesAreHonestOver200Seeds) {
  // ISO 10360-5 plan (25 points, ν = 15), orders 2-4. Per seed: truth δr ~ N(0, 0.5 µm),
  // c_k, s_k ~ N(0, 0.2 µm); the true sphere diameter ~ N(D_cal, u_D²) with u_D = 0.1 µm;
  // touch noise σ = 0.3 µm. For an honest u, e = (estimate − truth)/u follows t_15 rescaled to
  // unit variance (statistical part) mixed with the normal diameter part:
  //  - P(|e| ≤ 2) ≈ 0.95 per parameter: over M = 200 seeds the fraction has binomial
  //    sd √(0.95·0.05/200) = 0.0154; tolerance 3.5 sd = 0.054 each way (a test at 3.5 sd fails
  //    by chance with probability 5e-4 per parameter);
  //  - mean of e² = 1: for t_15 with unit variance E e⁴ = 3(ν−2)/(ν−4) = 3.55, so the mean of
  //    1400 values has sd √(2.55/1400) = 0.043 if independent; the 7 parameters of one seed
  //    share s, so allow 0.2 (≈ 4.7 independent sd, ≥ 2.5 sd with full within-seed
  //    correlation). It fails if u is over- or understated by more than ~10 %.
  const Eigen::Matrix3Xd dirs = iso10360_5_directions();
  const double u_d = 0.1 * kUm;
  constexpr int kSeeds = 200;
  std::array<int, 7> within{};
  double sum_e2 = 0.0;
  int count = 0;
  for (int seed = 0; seed < kSeeds; ++seed) {
    em::SeededRandomSource truth_rng(1000 + static_cast<std::uint64_t>(seed));
    std::array<double, 8> z{};
    truth_rng.fill_standard_normal(z);
    const em::ProbeModel truth = probe_truth(0.5 * z[0], {{2.0, 0.2 * z[1], 0.2 * z[2]},
                                                          {3.0, 0.2 * z[3], 0.2 * z[4]},
                                                          {4.0, 0.2 * z[5], 0.2 * z[6]}});
    const double true_diameter = kDiameter + u_d * z[7];
    const Eigen::Matrix3Xd pts = simulate_sphere(truth, 0.3 * kUm, dirs, true_diameter,
                                                 static_cast<std::uint64_t>(seed), 0.3 * seed);
    const SphereProbeCharacterization r = characterize_probe_sphere(pts, {kDiameter, u_d, 0.0});
    ASSERT_TRUE(r.usable) << "seed " << seed << ": " << r.message;
    std::vector<ProbeParameterEstimate> all = {r.tip_radius_error};
    all.insert(all.end(), r.directional.begin(), r.directional.end());
    ASSERT_EQ(all.size(), 7u);
    for (std::size_t j = 0; j < all.size(); ++j) {
      const double e = (all[j].value_mm - truth_of(truth, all[j].name)) / all[j].u_mm;
      within[j] += std::abs(e) <= 2.0;
      sum_e2 += e * e;
      ++count;
    }
  }
  for (std::size_t j = 0; j < within.size(); ++j) {
    const double fraction = static_cast<double>(within[j]) / kSeeds;
    std::cout << "[honesty] parameter " << j << ": fraction |e| <= 2 = " << fraction << "\n";
    EXPECT_NEAR(fraction, 0.95, 0.054) << "parameter " << j;
  }
  std::cout << "[honesty] mean e^2 = " << sum_e2 / count << " over " << count << "\n";
  EXPECT_NEAR(sum_e2 / count, 1.0, 0.2);
}

TEST(ProbeSphere, FormBoundCoversAFormDeviationWithinF) {
  // No noise; a form deviation f = (F/2)·(cos 2φ·sin²θ)… scaled into ±F/2, on the sphere
  // itself (the sphere's, not the probe's). Every parameter's error must lie within the
  // rectangular bound (F/2)‖w‖₁ = √3·u_form, and u_form must be > 0.
  const Eigen::Matrix3Xd dirs = iso10360_5_directions();
  const double form = 0.2 * kUm;
  Eigen::Matrix3Xd pts(3, dirs.cols());
  for (Eigen::Index i = 0; i < dirs.cols(); ++i) {
    const Eigen::Vector3d u = dirs.col(i);
    const double f = 0.5 * form * std::cos(2.0 * std::atan2(u.y(), u.x()) + 0.3) *
                     (1.0 - u.z() * u.z());  // |f| ≤ F/2
    pts.col(i) = kCentre + (0.5 * kDiameter + f) * u;
  }
  const SphereProbeCharacterization r = characterize_probe_sphere(pts, {kDiameter, 0.0, form});
  ASSERT_TRUE(r.usable) << r.message;
  std::vector<ProbeParameterEstimate> all = {r.tip_radius_error};
  all.insert(all.end(), r.directional.begin(), r.directional.end());
  for (const ProbeParameterEstimate& e : all) {
    EXPECT_GT(e.u_form_mm, 0.0) << e.name;
    EXPECT_LE(std::abs(e.value_mm), std::sqrt(3.0) * e.u_form_mm * (1.0 + 1e-9)) << e.name;
  }
  // ‖w_δr‖₁ ≥ 1 (its weights sum to 1): u_form(δr) ≥ F/(2√3).
  EXPECT_GE(r.tip_radius_error.u_form_mm, 0.5 * form / std::sqrt(3.0) * (1.0 - 1e-12));
}

// ---- the JSON section ----

TEST(ProbeSphere, SectionLoadsIntoTheDigitalModel) {
  const em::ProbeModel truth = probe_truth(0.4, {{2.0, 0.1, -0.05}, {3.0, 0.15, 0.02}});
  const Eigen::Matrix3Xd pts =
      simulate_sphere(truth, 0.1 * kUm, dense_hemisphere_directions(), kDiameter, 7);
  const SphereProbeCharacterization r =
      characterize_probe_sphere(pts, {kDiameter, 0.05 * kUm, 0.03 * kUm}, {{2, 3}, std::nullopt});
  ASSERT_TRUE(r.usable) << r.message;
  std::ifstream f(kExample);
  nlohmann::json model = nlohmann::json::parse(f);
  model["probe"] = nlohmann::json::parse(probe_section_json(r, "sphere.csv"));
  const em::DigitalModel loaded = em::parse_digital_model(model.dump(), "merged");
  EXPECT_NEAR(loaded.probe.tip_radius_error_mm.value, r.probe.tip_radius_error_mm.value, 1e-15);
  EXPECT_NEAR(loaded.probe.tip_radius_error_mm.u, r.probe.tip_radius_error_mm.u, 1e-15);
  ASSERT_EQ(loaded.probe.directional.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(loaded.probe.directional[i].order, r.probe.directional[i].order);
    EXPECT_NEAR(loaded.probe.directional[i].cos_mm.value, r.probe.directional[i].cos_mm.value,
                1e-15);
    EXPECT_NEAR(loaded.probe.directional[i].sin_mm.u, r.probe.directional[i].sin_mm.u, 1e-15);
  }
  // The whole output parses and carries the budget.
  const nlohmann::json out = nlohmann::json::parse(probe_characterization_json(r, "sphere.csv"));
  EXPECT_EQ(out["characterization"]["status"], "ok");
  EXPECT_EQ(out["characterization"]["budget"].size(), 5u);
  EXPECT_NE(out["probe"]["source"].get<std::string>().find("sphere.csv"), std::string::npos);
}

// ---- plans, simulated data and the points file ----

TEST(ProbeSphere, Plans) {
  const Eigen::Matrix3Xd iso = iso10360_5_directions();
  ASSERT_EQ(iso.cols(), 25);
  EXPECT_NEAR(iso(2, 0), 1.0, 1e-15);  // the pole
  for (Eigen::Index i = 0; i < iso.cols(); ++i) {
    EXPECT_NEAR(iso.col(i).norm(), 1.0, 1e-15);
    EXPECT_GE(iso(2, i), -1e-15);  // upper hemisphere
  }
  EXPECT_NEAR(std::acos(iso(2, 1)), kPi / 8.0, 1e-12);  // 22.5° below the pole
  EXPECT_NEAR(iso(2, 24), 0.0, 1e-15);                  // equator
  EXPECT_EQ(dense_hemisphere_directions().cols(), 73);
  const SphereCircle bad[] = {{0.1, 0, 0.0}};
  expect_invalid([&] { (void)sphere_directions(bad); }, "at least 1 point");
  expect_invalid(
      [&] { (void)sphere_measurement(-1.0, iso, placement(), em::ProbingMode::scanning); },
      "diameter");
  Eigen::Matrix3Xd not_unit = iso;
  not_unit.col(3) *= 1.01;
  expect_invalid(
      [&] { (void)sphere_measurement(25.0, not_unit, placement(), em::ProbingMode::scanning); },
      "direction 3");
}

TEST(ProbeSphere, PointsFileInBothFormatsGivesMachineCoordinates) {
  const em::Measurement m = sphere_measurement(kDiameter, iso10360_5_directions(), placement(0.7),
                                               em::ProbingMode::touch_trigger);
  const auto dir = std::filesystem::temp_directory_path();
  const std::string csv = (dir / "vcmm_sphere_meas_test.csv").string();
  const std::string xyz = (dir / "vcmm_sphere_xyz_test.csv").string();
  em::write_measurement_csv_file(csv, m);
  const Eigen::Matrix3Xd machine = em::machine_coordinates(m);
  {
    std::ofstream out(xyz);
    out.precision(17);
    out << "# machine coordinates\nx_mm,y_mm,z_mm\n";
    for (Eigen::Index i = 0; i < machine.cols(); ++i)
      out << machine(0, i) << "," << machine(1, i) << "," << machine(2, i) << "\n";
  }
  const CmmPoints a = read_cmm_points_file(csv, true);
  const CmmPoints b = read_cmm_points_file(xyz, true);
  EXPECT_TRUE(a.from_measurement_csv);
  EXPECT_FALSE(b.from_measurement_csv);
  ASSERT_TRUE(a.mode.has_value());
  EXPECT_EQ(*a.mode, em::ProbingMode::touch_trigger);
  EXPECT_LT((a.points_mm - machine).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((b.points_mm - machine).cwiseAbs().maxCoeff(), 1e-12);
  {
    std::ofstream out(xyz);
    out << "1,2\n3,4\n5,6\n";
  }
  expect_invalid([&] { (void)read_cmm_points_file(xyz, true); }, "three columns");
  EXPECT_EQ(read_cmm_points_file(xyz, false).points_mm(2, 1), 0.0);
  expect_invalid(
      [&] { (void)read_cmm_points_file((dir / "no_such_vcmm_file.csv").string(), true); },
      "no_such_vcmm_file.csv: cannot read the points file: no such file");
  std::filesystem::remove(csv);
  std::filesystem::remove(xyz);
}

// ---- bad input ----

TEST(ProbeSphere, BadInput) {
  const Eigen::Matrix3Xd dirs = iso10360_5_directions();
  const Eigen::Matrix3Xd good = 0.5 * kDiameter * dirs + kCentre.replicate(1, dirs.cols());
  const CalibratedSphere sphere{kDiameter, 0.0, 0.0};
  // Too few points: orders 2-4 need p + 3 = 13.
  expect_invalid([&] { (void)characterize_probe_sphere(good.leftCols(12), sphere); },
                 "needs at least 13 points");
  // NaN.
  Eigen::Matrix3Xd nan = good;
  nan(1, 7) = std::nan("");
  expect_invalid([&] { (void)characterize_probe_sphere(nan, sphere); }, "point 7");
  // Not on a sphere: the corners and face centres of a cube … and a mis-stated diameter.
  Eigen::Matrix3Xd cube(3, 20);
  int c = 0;
  for (int x = -1; x <= 1; x += 2)
    for (int y = -1; y <= 1; y += 2)
      for (int z = -1; z <= 1; z += 2) cube.col(c++) = Eigen::Vector3d(x, y, z) * 10.0;
  for (int a = 0; a < 3; ++a)
    for (int s = -1; s <= 1; s += 2) {
      Eigen::Vector3d v = Eigen::Vector3d::Zero();
      v[a] = 10.0 * s;
      cube.col(c++) = v;
    }
  for (; c < 20; ++c) cube.col(c) = Eigen::Vector3d(7.0, -3.0, 2.0 + c);
  expect_invalid(
      [&] {
        (void)characterize_probe_sphere(cube, {20.0, 0.0, 0.0}, {{2}, std::nullopt});
      },
      "do not lie on a sphere");
  Eigen::Matrix3Xd huge = good;
  huge(0, 3) = 1e300;
  expect_invalid([&] { (void)characterize_probe_sphere(huge, sphere); }, "too large");
  expect_invalid(
      [&] {
        (void)characterize_probe_sphere(good, {2.0 * kDiameter, 0.0, 0.0});
      },
      "differs from the calibrated");
  // Certificate and options.
  expect_invalid(
      [&] {
        (void)characterize_probe_sphere(good, {0.0, 0.0, 0.0});
      },
      "calibrated diameter");
  expect_invalid(
      [&] {
        (void)characterize_probe_sphere(good, {kDiameter, -1e-4, 0.0});
      },
      "standard uncertainty");
  expect_invalid(
      [&] {
        (void)characterize_probe_sphere(good, {kDiameter, 0.0, std::nan("")});
      },
      "form deviation");
  expect_invalid(
      [&] {
        (void)characterize_probe_sphere(good, sphere, {{2, 17}, std::nullopt});
      },
      "harmonic orders must be 1 to 16; got 17");
}

}  // namespace
