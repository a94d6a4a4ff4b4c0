// The virtual CMM: each error source alone against its closed form, stage order and
// switches, the correct(simulate(x)) round trip, reproducibility, location dependence, and
// the single-point uncertainty of the example model at the ring (printed; docs/errormodel.md).
//
// Radial deviations are taken about the centroid of the points: for an equiangular closed
// profile whose deviations have no first harmonic, the centroid is the centre (to second
// order), so no fitter is needed here (errormodel does not use geometry's fitters).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <iostream>
#include <numbers>
#include <string>

#include "vcmm/errormodel/errors.h"
#include "vcmm/errormodel/random_source.h"
#include "vcmm/errormodel/ring_gauge.h"
#include "vcmm/errormodel/virtual_cmm.h"

namespace {

using namespace vcmm::errormodel;
constexpr double kPi = std::numbers::pi;

const std::string kExample = std::string(VCMM_SOURCE_DIR) + "/examples/cmm_model.json";
const std::array<AxisRange, 3> kRanges = {{{0.0, 1200.0}, {0.0, 1000.0}, {0.0, 800.0}}};
const Eigen::Vector3d kCentre(600.0, 500.0, 250.0);
const Eigen::Vector3d kCorner(100.0, 120.0, 40.0);
const Eigen::Vector3d kStylus(0.0, 0.0, -150.0);

DigitalModel perfect_machine() {
  return DigitalModel(KinematicModel::zero(KinematicChain::moving_bridge(), kRanges));
}

Measurement ring(Eigen::Index n, const Eigen::Vector3d& location = kCentre,
                 double orientation_rad = 0.0, bool with_form = true,
                 ProbingMode mode = ProbingMode::scanning, double temperature_c = 20.0) {
  RingGauge g;
  if (with_form) g.form = seed_study_ring_form();
  RingSampling s;
  s.points = n;
  s.mode = mode;
  s.placement.location_mm = location;
  s.placement.orientation_rad = orientation_rad;
  s.temperature_c = temperature_c;
  s.stylus_offset_mm = kStylus;
  return ring_gauge_measurement(g, s);
}

/// Radial distances from the centroid (workpiece XY).
Eigen::ArrayXd radii(const Eigen::Matrix3Xd& p) {
  const Eigen::Vector2d c = p.topRows<2>().rowwise().mean();
  return (p.topRows<2>().colwise() - c).colwise().norm().transpose().array();
}

double peak_to_valley(const Eigen::ArrayXd& a) { return a.maxCoeff() - a.minCoeff(); }

double std_dev(const Eigen::ArrayXd& a) {
  return std::sqrt((a - a.mean()).square().sum() / static_cast<double>(a.size() - 1));
}

/// Normal components of the displacement of every point.
Eigen::ArrayXd along_normals(const Eigen::Matrix3Xd& d, const Eigen::Matrix3Xd& n) {
  return (d.array() * n.array()).colwise().sum().transpose();
}

TEST(VirtualCmmSingleSource, SquarenessGammaGivesTwoLobesOfPeakToValleyGammaR) {
  const DigitalModel model = perfect_machine();
  const Measurement m = ring(3600, kCentre, 0.0, /*with_form=*/false);
  const double gamma = 5e-6;  // rad; exaggerated so that γR = 0.43 µm dominates rounding
  ErrorDraw d = nominal_errors(model, m);
  d.kinematic.set_squareness(model.kinematics, Squareness::E_C0Y, gamma);
  const Measurement s = simulate(m, model, d, Stages::only(ErrorSource::kinematic));
  const Eigen::ArrayXd r = radii(s.points_mm) - 85.5;
  const double R = 85.5;
  EXPECT_NEAR(peak_to_valley(r), gamma * R, 1e-3 * gamma * R);
  // e_x = +γ·y (kinematic_errors.h): x' = R cos θ + γ R sin θ → r − R = (γR/2) sin 2θ + O(γ²R).
  for (Eigen::Index i = 0; i < m.size(); i += 97) {
    const double theta = 2.0 * kPi * static_cast<double>(i) / 3600.0;
    EXPECT_NEAR(r(i), 0.5 * gamma * R * std::sin(2.0 * theta), 1e-8) << "point " << i;
  }
}

TEST(VirtualCmmSingleSource, TemperatureScalesTheDiameterAndNotTheRoundness) {
  DigitalModel model = perfect_machine();
  model.temperature.expansion_coefficient_per_k = {11.5e-6, 0.0};
  const double t = 25.0;
  const Measurement m = ring(3600, kCentre, 0.3, true, ProbingMode::scanning, t);
  const Measurement s =
      simulate(m, model, nominal_errors(model, m), Stages::only(ErrorSource::temperature));
  const double scale = 11.5e-6 * (t - 20.0);
  const Eigen::ArrayXd r0 = radii(m.points_mm), r1 = radii(s.points_mm);
  const double diameter_change = 2.0 * (r1.mean() - r0.mean());
  EXPECT_NEAR(diameter_change, scale * 171.0, 1e-12);  // 9.83 µm
  EXPECT_NEAR(peak_to_valley(r1), peak_to_valley(r0) * (1.0 + scale), 1e-13);
  EXPECT_EQ(s.normals, m.normals);
}

TEST(VirtualCmmSingleSource, ProbeRadiusErrorShiftsEveryPointAlongItsNormal) {
  DigitalModel model = perfect_machine();
  model.probe.tip_radius_error_mm = {0.3e-3, 0.0};
  const Measurement m = ring(360, kCentre, 1.1);
  const Measurement s =
      simulate(m, model, nominal_errors(model, m), Stages::only(ErrorSource::probe));
  const Eigen::Matrix3Xd shift = s.points_mm - m.points_mm;
  // 3e-14 mm: the rounding of an 85 mm coordinate (ulp 1.4e-14 mm) in s − m.
  EXPECT_LT((shift - 0.3e-3 * m.normals).cwiseAbs().maxCoeff(), 3e-14);
  // Normals point into the bore: a larger tip makes the ring look smaller by 2δr.
  EXPECT_NEAR(2.0 * (radii(s.points_mm).mean() - radii(m.points_mm).mean()), -0.6e-3, 1e-12);
}

TEST(VirtualCmmSingleSource, DirectionalProbeErrorFollowsTheMachineAzimuthOfProbing) {
  DigitalModel model = perfect_machine();
  model.probe.directional = {{3, {0.2e-3, 0.0}, {0.0, 0.0}}, {2, {0.0, 0.0}, {-0.1e-3, 0.0}}};
  const double psi = 0.4;  // orientation: the probing azimuth in the machine is θ + ψ
  const Measurement m = ring(720, kCentre, psi, /*with_form=*/false);
  const Measurement s =
      simulate(m, model, nominal_errors(model, m), Stages::only(ErrorSource::probe));
  const Eigen::Matrix3Xd shift = s.points_mm - m.points_mm;
  for (Eigen::Index i = 0; i < m.size(); ++i) {
    const double phi = 2.0 * kPi * static_cast<double>(i) / 720.0 + psi;
    const double expected = 0.2e-3 * std::cos(3 * phi) - 0.1e-3 * std::sin(2 * phi);
    // 3e-14 mm: the rounding of an 85 mm coordinate (ulp 1.4e-14 mm) in s − m.
    EXPECT_NEAR((shift.col(i) - expected * m.normals.col(i)).norm(), 0.0, 3e-14) << i;
  }
  // Vertical probing: sectoral harmonics vanish, only the radius error would remain.
  ProbeErrors p;
  p.tip_radius_error_mm = 1e-4;
  p.cos_mm[2] = 5e-4;
  p.max_order = 2;
  EXPECT_EQ(probe_error_mm(p, Eigen::Vector3d(0, 0, -1)), 1e-4);
  EXPECT_NEAR(probe_error_mm(p, Eigen::Vector3d(0, 1, 0)), 1e-4 - 5e-4, 1e-18);
}

TEST(VirtualCmmSingleSource, NoiseOfSigmaGivesResidualsOfSigma) {
  DigitalModel model = perfect_machine();
  model.noise = {0.5e-3, 0.2e-3};
  for (const ProbingMode mode : {ProbingMode::scanning, ProbingMode::touch_trigger}) {
    const double sigma = mode == ProbingMode::scanning ? 0.5e-3 : 0.2e-3;
    const Measurement m = ring(3600, kCentre, 0.0, true, mode);
    SeededRandomSource rng(20260101);
    const Stages only = Stages::only(ErrorSource::noise);
    const Measurement s = simulate(m, model, draw_errors(model, m, rng, only), only);
    const Eigen::Matrix3Xd d = s.points_mm - m.points_mm;
    const Eigen::ArrayXd all = d.reshaped().array();
    // Standard error of a sample standard deviation: σ/√(2n); 5 of them (fixed seed).
    const double n_all = static_cast<double>(all.size());
    EXPECT_NEAR(std_dev(all), sigma, 5.0 * sigma / std::sqrt(2.0 * n_all));
    EXPECT_NEAR(all.mean(), 0.0, 5.0 * sigma / std::sqrt(n_all));
    const Eigen::ArrayXd normal = along_normals(d, m.normals);
    EXPECT_NEAR(std_dev(normal), sigma, 5.0 * sigma / std::sqrt(2.0 * 3600.0));
  }
}

TEST(VirtualCmmSingleSource, RoughnessActsAlongTheNormalOnlyWithItsSigma) {
  DigitalModel model = perfect_machine();
  model.roughness.sigma_mm = 0.1e-3;
  const Measurement m = ring(3600, kCentre, 0.2);
  SeededRandomSource rng(7);
  const Stages only = Stages::only(ErrorSource::roughness);
  const Measurement s = simulate(m, model, draw_errors(model, m, rng, only), only);
  const Eigen::Matrix3Xd d = s.points_mm - m.points_mm;
  // Tangential part of the displacement: only the rounding of 85 mm coordinates (3e-14 mm).
  for (Eigen::Index i = 0; i < d.cols(); ++i)
    ASSERT_LT(d.col(i).cross(m.normals.col(i)).norm(), 3e-14) << i;
  EXPECT_NEAR(std_dev(along_normals(d, m.normals)), 0.1e-3, 5.0 * 0.1e-3 / std::sqrt(7200.0));
}

TEST(VirtualCmmStages, OrderRoughnessThenTemperatureThenProbe) {
  DigitalModel model = perfect_machine();
  model.temperature.expansion_coefficient_per_k = {10e-6, 0.0};
  model.probe.tip_radius_error_mm = {1e-4, 0.0};
  const Measurement m = ring(64, kCentre, 0.0, true, ProbingMode::scanning, 30.0);
  ErrorDraw d = nominal_errors(model, m);
  d.roughness_mm.setConstant(2e-4);
  Stages st = Stages::all();
  st.set(ErrorSource::kinematic, false).set(ErrorSource::noise, false);
  const Measurement s = simulate(m, model, d, st);
  const double f = 1.0 + 10e-6 * 10.0;
  const Eigen::Matrix3Xd expected = (m.points_mm + 2e-4 * m.normals) * f + 1e-4 * m.normals;
  EXPECT_LT((s.points_mm - expected).cwiseAbs().maxCoeff(), 1e-13);
}

TEST(VirtualCmmStages, NoStageReturnsTheInputAndDrawsNothing) {
  const DigitalModel model = read_digital_model_file(kExample);
  const Measurement m = ring(100);
  SeededRandomSource rng(3), fresh(3);
  const ErrorDraw d = draw_errors(model, m, rng, Stages::none());
  EXPECT_EQ(rng.standard_normal(), fresh.standard_normal());  // no number consumed
  EXPECT_EQ(simulate(m, model, d, Stages::none()).points_mm, m.points_mm);
  EXPECT_EQ(correct(m, model, Stages::none()).points_mm, m.points_mm);
}

TEST(VirtualCmmStages, NamesRoundTrip) {
  for (ErrorSource s : all_error_sources) EXPECT_EQ(error_source_from_string(to_string(s)), s);
  EXPECT_FALSE(error_source_from_string("thermal").has_value());
  EXPECT_TRUE(Stages::only(ErrorSource::probe).is_enabled(ErrorSource::probe));
  EXPECT_FALSE(Stages::only(ErrorSource::probe).is_enabled(ErrorSource::noise));
}

TEST(VirtualCmmRoundTrip, CorrectUndoesSimulateWithTheNominalErrors) {
  // The example's estimated (nominal) errors are all non-zero; T reading 23.2 °C.
  const DigitalModel model = read_digital_model_file(kExample);
  for (const Eigen::Vector3d& where : {kCentre, kCorner}) {
    const Measurement m = ring(3600, where, 0.7, true, ProbingMode::scanning, 23.2);
    const ErrorDraw d = nominal_errors(model, m);
    for (const Formula f : {Formula::first_order, Formula::exact}) {
      const Measurement s = simulate(m, model, d, Stages::all(), f);
      EXPECT_GT((s.points_mm - m.points_mm).cwiseAbs().maxCoeff(), 1e-4);  // it did something
      const Measurement back = correct(s, model, Stages::all(), f);
      EXPECT_LT((back.points_mm - m.points_mm).cwiseAbs().maxCoeff(), 1e-12);
    }
  }
}

TEST(VirtualCmmRoundTrip, ZeroUncertaintiesAndNoiseReturnTheInputFromARandomDraw) {
  DigitalModel model = read_digital_model_file(kExample);
  model.roughness.sigma_mm = 0.0;
  model.noise = {0.0, 0.0};
  model.temperature.thermometer_u_k = 0.0;
  model.temperature.expansion_coefficient_per_k.u = 0.0;
  model.probe.tip_radius_error_mm.u = 0.0;
  for (auto& h : model.probe.directional) h.cos_mm.u = h.sin_mm.u = 0.0;
  const Eigen::Index k = model.kinematics.parameter_count();
  model.kinematics.set_covariance(Eigen::MatrixXd::Zero(k, k));
  const Measurement m = ring(3600, kCorner, -0.3, true, ProbingMode::scanning, 18.5);
  SeededRandomSource rng(11);
  const Measurement back = correct(simulate(m, model, draw_errors(model, m, rng)), model);
  EXPECT_LT((back.points_mm - m.points_mm).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(VirtualCmm, SameSeedSameSimulationDifferentSeedDifferent) {
  const DigitalModel model = read_digital_model_file(kExample);
  const Measurement m = ring(360);
  SeededRandomSource a(42), b(42), c(43);
  const Measurement sa = simulate(m, model, draw_errors(model, m, a));
  const Measurement sb = simulate(m, model, draw_errors(model, m, b));
  const Measurement sc = simulate(m, model, draw_errors(model, m, c));
  EXPECT_EQ(sa.points_mm, sb.points_mm);
  EXPECT_GT((sa.points_mm - sc.points_mm).cwiseAbs().maxCoeff(), 1e-5);
}

TEST(VirtualCmm, ExactAndFirstOrderKinematicsAgreeToSecondOrder) {
  const DigitalModel model = read_digital_model_file(kExample);
  const Measurement m = ring(720, kCorner, 0.5);
  SeededRandomSource rng(5);
  const ErrorDraw d = draw_errors(model, m, rng);
  const Measurement a = simulate(m, model, d, Stages::all(), Formula::first_order);
  const Measurement b = simulate(m, model, d, Stages::all(), Formula::exact);
  // Second-order terms: |ε|·(|δ| + |ε|·|arm|) ≈ 1e-6 · 1e-3 mm.
  EXPECT_LT((a.points_mm - b.points_mm).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(VirtualCmmLocation, SameModelTwoLocationsGiveDifferentResidualPatterns) {
  const DigitalModel model = read_digital_model_file(kExample);
  const Stages only = Stages::only(ErrorSource::kinematic);
  auto pattern = [&](const Eigen::Vector3d& where) {
    const Measurement m = ring(720, where, 0.0, false);
    const Eigen::ArrayXd r = radii(simulate(m, model, nominal_errors(model, m), only).points_mm);
    return Eigen::ArrayXd(r - r.mean());
  };
  const Eigen::ArrayXd centre = pattern(kCentre), corner = pattern(kCorner);
  const double rms_difference = std::sqrt((centre - corner).square().mean());
  std::cout << "[ info ] kinematic residual pattern: RMS "
            << std::sqrt(centre.square().mean()) * 1e6 << " nm at the centre, " << std::sqrt(corner.square().mean()) * 1e6
            << " nm in the corner, RMS difference " << rms_difference * 1e6 << " nm\n";
  EXPECT_GT(rms_difference, 5e-6);  // 5 nm: far above rounding (1e-13 mm)
}

TEST(VirtualCmmLocation, AnAffineErrorMapGivesTheSamePatternEverywhere) {
  // Linear positioning/straightness terms and squareness only: the tip error is affine in
  // the position, so the form it adds to a ring does not depend on where the ring is.
  std::array<ErrorFunctionEstimate, axis_error_count> fns;
  for (int f = 0; f < axis_error_count; ++f) {
    const bool translation = !is_rotation(static_cast<AxisError>(f));
    fns[static_cast<std::size_t>(f)].coefficients = {0.0, translation ? 0.3e-3 : 0.0};
    fns[static_cast<std::size_t>(f)].standard_uncertainties = {0.0, 0.0};
  }
  const std::array<EstimatedValue, squareness_count> sq = {{{1e-6, 0}, {-2e-6, 0}, {0.5e-6, 0}}};
  const DigitalModel model(KinematicModel(KinematicChain::moving_bridge(), kRanges, fns, sq));
  const Stages only = Stages::only(ErrorSource::kinematic);
  auto pattern = [&](const Eigen::Vector3d& where) {
    const Measurement m = ring(720, where, 0.0, false);
    const Eigen::ArrayXd r = radii(simulate(m, model, nominal_errors(model, m), only).points_mm);
    return Eigen::ArrayXd(r - 85.5);
  };
  const Eigen::ArrayXd centre = pattern(kCentre), corner = pattern(kCorner);
  EXPECT_GT(peak_to_valley(centre), 5e-6);  // the map does add form (~12 nm)
  EXPECT_LT((centre - corner).abs().maxCoeff(), 1e-11);
}

TEST(VirtualCmmErrors, BadDrawsAndPointsOutsideTheMachineAreRejected) {
  const DigitalModel model = read_digital_model_file(kExample);
  const Measurement m = ring(100);
  ErrorDraw d = nominal_errors(model, m);
  d.noise_mm.resize(3, 0);
  EXPECT_THROW(simulate(m, model, d), InvalidInput);
  const Measurement outside = ring(100, Eigen::Vector3d(20.0, 500.0, 250.0));  // x < 0 at θ = π
  EXPECT_THROW(simulate(outside, model, nominal_errors(model, outside)), std::invalid_argument);
  Measurement bad = m;
  bad.points_mm(0, 7) = NAN;
  SeededRandomSource rng(1);
  try {
    draw_errors(model, bad, rng);
    FAIL() << "no exception";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("draw_errors: point 7"), std::string::npos) << e.what();
  }
}

/// The figure the example model is tuned for: the standard deviation, over Monte Carlo
/// trials, of the normal component of correct(simulate(nominal ring)) − nominal ring, per
/// point, RMS over the points.
struct SinglePointU {
  double along_normal_um;
  double three_d_um;
};
SinglePointU single_point_uncertainty(const DigitalModel& model, const Measurement& m, int trials,
                                      std::uint64_t seed) {
  SeededRandomSource rng(seed);
  ErrorDraw d;
  Measurement s, c;
  Eigen::ArrayXd sum_n = Eigen::ArrayXd::Zero(m.size()), sum_n2 = sum_n;
  Eigen::ArrayXd sum_3d2 = sum_n;
  Eigen::Matrix3Xd sum_d = Eigen::Matrix3Xd::Zero(3, m.size());
  for (int t = 0; t < trials; ++t) {
    draw_errors(model, m, rng, Stages::all(), d);
    simulate(m, model, d, Stages::all(), Formula::first_order, s);
    correct(s, model, Stages::all(), Formula::first_order, c);
    const Eigen::Matrix3Xd delta = c.points_mm - m.points_mm;
    const Eigen::ArrayXd dn = along_normals(delta, m.normals);
    sum_n += dn;
    sum_n2 += dn.square();
    sum_d += delta;
    sum_3d2 += delta.colwise().squaredNorm().transpose().array();
  }
  const double mm = static_cast<double>(trials);
  const Eigen::ArrayXd var_n = (sum_n2 - sum_n.square() / mm) / (mm - 1.0);
  const Eigen::ArrayXd var_3d =
      (sum_3d2 - (sum_d.colwise().squaredNorm().transpose().array()) / mm) / (mm - 1.0);
  return {std::sqrt(var_n.mean()) * 1e3, std::sqrt(var_3d.mean()) * 1e3};
}

TEST(VirtualCmmExampleModel, SinglePointUncertaintyAtTheRingIsAboutPoint8Micrometre) {
  const DigitalModel model = read_digital_model_file(kExample);
  // 4000 trials: the relative standard error of a standard deviation is 1/√(2M) = 1.1 %.
  const SinglePointU scan = single_point_uncertainty(model, ring(360), 4000, 2026);
  const SinglePointU touch = single_point_uncertainty(
      model, ring(16, kCentre, 0.0, true, ProbingMode::touch_trigger), 4000, 2027);
  const SinglePointU corner = single_point_uncertainty(model, ring(360, kCorner), 4000, 2028);
  std::cout << "[ info ] single-point standard uncertainty, example model, 171 mm ring:\n"
            << "         scanning, volume centre: " << scan.along_normal_um
            << " um along the normal, " << scan.three_d_um << " um 3D\n"
            << "         touch-trigger, centre:   " << touch.along_normal_um
            << " um along the normal, " << touch.three_d_um << " um 3D\n"
            << "         scanning, corner:        " << corner.along_normal_um
            << " um along the normal, " << corner.three_d_um << " um 3D\n";
  RecordProperty("u_point_scanning_um", std::to_string(scan.along_normal_um));
  EXPECT_GT(scan.along_normal_um, 0.7);
  EXPECT_LT(scan.along_normal_um, 0.9);
}

}  // namespace
