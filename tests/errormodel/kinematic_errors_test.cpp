// Kinematic errors: hand-derived cases, closed forms on a ring, chain configurations,
// exact vs first order, draw statistics, JSON errors, bad input.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include <array>
#include <bit>
#include <cmath>
#include <fstream>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "internal/kinematics_json.h"
#include "vcmm/errormodel/kinematic_errors.h"

namespace {

using namespace vcmm::errormodel;

constexpr std::array<AxisRange, 3> kRanges = {{{-500.0, 500.0}, {-600.0, 600.0}, {-400.0, 400.0}}};

// All 18 functions with `n` coefficients, all values and uncertainties zero.
KinematicModel model_with(KinematicChain chain, int n) {
  std::array<ErrorFunctionEstimate, axis_error_count> fns;
  for (auto& f : fns) {
    f.coefficients.assign(static_cast<std::size_t>(n), 0.0);
    f.standard_uncertainties.assign(static_cast<std::size_t>(n), 0.0);
  }
  return KinematicModel(std::move(chain), kRanges, fns, {});
}

void set(const KinematicModel& m, KinematicErrors& e, AxisError f, std::vector<double> c) {
  c.resize(static_cast<std::size_t>(m.coefficient_count(f)), 0.0);
  e.set_coefficients(m, f, c);
}

// A circle of radius r about `centre` in the plane z = centre.z, n equiangular points.
Eigen::Matrix3Xd circle(const Eigen::Vector3d& centre, double r, int n) {
  Eigen::Matrix3Xd p(3, n);
  for (int i = 0; i < n; ++i) {
    const double th = 2.0 * std::numbers::pi * i / n;
    p.col(i) = centre + Eigen::Vector3d(r * std::cos(th), r * std::sin(th), 0.0);
  }
  return p;
}

// Radial deviations in the xy plane about the centroid (≈ LS centre for equiangular points),
// minus their mean.
Eigen::VectorXd radial_deviations(const Eigen::Matrix3Xd& p) {
  const Eigen::Vector2d c = p.topRows<2>().rowwise().mean();
  Eigen::VectorXd r = (p.topRows<2>().colwise() - c).colwise().norm().transpose();
  return r.array() - r.mean();
}
double mean_radius(const Eigen::Matrix3Xd& p) {
  const Eigen::Vector2d c = p.topRows<2>().rowwise().mean();
  return (p.topRows<2>().colwise() - c).colwise().norm().mean();
}
// Fourier coefficients (cos, sin) of harmonic k of equiangular samples.
std::pair<double, double> harmonic(const Eigen::VectorXd& d, int k) {
  double a = 0.0, b = 0.0;
  const auto n = d.size();
  for (Eigen::Index i = 0; i < n; ++i) {
    const double th = 2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
    a += d[i] * std::cos(k * th);
    b += d[i] * std::sin(k * th);
  }
  return {2.0 * a / static_cast<double>(n), 2.0 * b / static_cast<double>(n)};
}

// Realistic-size values (µm, µrad) for every parameter of `m`, fixed seed.
KinematicErrors random_errors_for_layout(const KinematicModel& m, std::uint64_t seed = 11) {
  SeededRandomSource rng(seed);
  Eigen::VectorXd v(m.parameter_count());
  rng.fill_standard_normal({v.data(), static_cast<std::size_t>(v.size())});
  for (int f = 0; f < axis_error_count; ++f) {
    const auto e = static_cast<AxisError>(f);
    v.segment(m.parameter_offset(e), m.coefficient_count(e)) *= is_rotation(e) ? 1e-6 : 1e-3;
  }
  v.tail(squareness_count) *= 1e-6;
  return KinematicErrors(m, v);
}

template <class F>
std::string thrown_message(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no exception)";
}

// ---- names and layout ----------------------------------------------------------------------

TEST(KinematicNames, IsoNamesAndLayout) {
  EXPECT_EQ(name(AxisError::E_XX), "E_XX");
  EXPECT_EQ(name(AxisError::E_BX), "E_BX");
  EXPECT_EQ(name(AxisError::E_XY), "E_XY");
  EXPECT_EQ(name(AxisError::E_CZ), "E_CZ");
  EXPECT_EQ(name(Squareness::E_B0Z), "E_B0Z");
  EXPECT_EQ(axis_of(AxisError::E_ZY), Axis::y);
  EXPECT_EQ(direction_of(AxisError::E_ZY), 2);
  EXPECT_TRUE(is_rotation(AxisError::E_AZ));
  EXPECT_FALSE(is_rotation(AxisError::E_ZZ));
  EXPECT_EQ(axis_error(Axis::z, 4), AxisError::E_BZ);
  const auto m = model_with(KinematicChain::moving_bridge(), 3);
  EXPECT_EQ(m.parameter_count(), 18 * 3 + 3);
  EXPECT_EQ(m.parameter_offset(AxisError::E_YX), 3);
  EXPECT_EQ(m.parameter_offset(Squareness::E_A0Z), 18 * 3 + 2);
}

// ---- error functions -----------------------------------------------------------------------

TEST(ErrorFunction, LegendreSeriesByHand) {
  const auto m = model_with(KinematicChain::moving_bridge(), 3);
  auto e = m.nominal();
  set(m, e, AxisError::E_ZX, {1.0, 2.0, 3.0});
  // X range [-500, 500]: u = q/500.  f = 1 + 2u + 3(3u² − 1)/2.
  for (double q : {-500.0, -123.0, 0.0, 250.0, 500.0}) {
    const double u = q / 500.0;
    EXPECT_NEAR(error_function_value(m, e, AxisError::E_ZX, q),
                1.0 + 2.0 * u + 1.5 * (3.0 * u * u - 1.0), 1e-14);
  }
  EXPECT_NE(thrown_message([&] { (void)error_function_value(m, e, AxisError::E_ZX, 600.0); })
                .find("outside the axis range"),
            std::string::npos);
}

// The vectorised power-basis evaluation inside tip_errors equals the Legendre recurrence for
// every degree up to the maximum.
TEST(ErrorFunction, BlockEvaluationMatchesRecurrenceUpToMaxDegree) {
  const auto m = model_with(KinematicChain::moving_bridge(), max_legendre_degree + 1);
  SeededRandomSource rng(2024);
  auto e = m.nominal();
  std::vector<double> c(static_cast<std::size_t>(max_legendre_degree + 1));
  rng.fill_standard_normal(c);
  for (double& v : c) v *= 1e-3;  // µm-level coefficients
  set(m, e, AxisError::E_YY, c);
  const int n = 200;  // more than one block, with a partial tail
  Eigen::Matrix3Xd p = Eigen::Matrix3Xd::Zero(3, n);
  for (int i = 0; i < n; ++i) p(1, i) = -600.0 + 1200.0 * i / (n - 1);
  const Eigen::Matrix3Xd err = tip_errors(m, e, p, Eigen::Vector3d::Zero());
  for (int i = 0; i < n; ++i) {
    // e = −v = −E_YY; 1e-15 mm: power-basis conversion loses < 3 digits at degree 10.
    EXPECT_NEAR(err(1, i), -error_function_value(m, e, AxisError::E_YY, p(1, i)), 1e-15) << i;
    EXPECT_EQ(err(0, i), 0.0);
    EXPECT_EQ(err(2, i), 0.0);
  }
}

// Inputs and outputs that are not packed 3 × n (rows of a larger matrix) give the same result.
TEST(ErrorFunction, StridedInputAndOutput) {
  const auto m = model_with(KinematicChain::fixed_bridge(), 3);
  const auto e = random_errors_for_layout(m);
  Eigen::MatrixXd big = Eigen::MatrixXd::Zero(5, 300);
  big.topRows<3>() = circle({100.0, 50.0, -20.0}, 85.5, 300);
  const Eigen::Vector3d t(0.0, 0.0, -100.0);
  for (const Formula formula : {Formula::first_order, Formula::exact}) {
    const Eigen::Matrix3Xd packed = tip_errors(m, e, Eigen::Matrix3Xd(big.topRows<3>()), t, formula);
    Eigen::MatrixXd out_big = Eigen::MatrixXd::Zero(4, 300);
    tip_errors(m, e, big.topRows<3>(), t, formula, out_big.bottomRows<3>());
    EXPECT_EQ(Eigen::Matrix3Xd(out_big.bottomRows<3>()), packed);
    EXPECT_EQ(out_big.row(0).cwiseAbs().maxCoeff(), 0.0);
  }
}

// ---- hand-derived rigid-body cases ---------------------------------------------------------

// Pitch of X, E_BX = β (constant), moving bridge, stylus t = (0, 0, −L), Z at q_z = 0 so the
// tip reads p = (x, y, −L). The X carriage carries Z; it turns by β about +y about its
// reference point (= ram reference point at q_z = 0). The tip sits at r = q_z ẑ + t = −L ẑ
// from that point, so it truly moves by β ŷ × (−L ẑ) = −βL x̂ (ŷ × ẑ = x̂): the tip is βL
// short in x of where the machine believes it is. Measured − true: e = +βL x̂.
// Exact: R_y(β)(0, 0, −L) = (−L sin β, 0, −L cos β), so e = (L sin β, 0, −L(1 − cos β)):
// first order has no z error, exact has the second-order −Lβ²/2.
TEST(RigidBody, PitchOfXWithAbbeArmByHand) {
  const auto m = model_with(KinematicChain::moving_bridge(), 1);
  auto e = m.nominal();
  const double beta = 2e-6, L = 150.0;
  set(m, e, AxisError::E_BX, {beta});
  const Eigen::Vector3d t(0.0, 0.0, -L);
  Eigen::Matrix3Xd p(3, 2);
  p.col(0) << 100.0, -50.0, -L;          // q_z = 0: arm L
  p.col(1) << 100.0, -50.0, -L - 200.0;  // q_z = −200: arm L + 200
  const Eigen::Matrix3Xd first = tip_errors(m, e, p, t, Formula::first_order);
  EXPECT_NEAR(first(0, 0), beta * L, 1e-18);
  EXPECT_EQ(first(1, 0), 0.0);
  EXPECT_EQ(first(2, 0), 0.0);
  EXPECT_NEAR(first(0, 1), beta * (L + 200.0), 1e-18);
  const Eigen::Matrix3Xd exact = tip_errors(m, e, p, t, Formula::exact);
  EXPECT_NEAR(exact(0, 0), L * std::sin(beta), 1e-18);
  // −3e-10 mm, second order; 1 − cos β written as 2 sin²(β/2) to avoid cancellation.
  EXPECT_NEAR(exact(2, 0), -2.0 * L * std::pow(std::sin(0.5 * beta), 2), 1e-22);
}

// Yaw of Z, E_CZ = γ, horizontal stylus t = (T, 0, 0): the tip moves by γ ẑ × T x̂ = γT ŷ,
// so e = −γT ŷ; no other axis carries an arm for it.
TEST(RigidBody, YawOfZWithHorizontalStylusByHand) {
  const auto m = model_with(KinematicChain::moving_bridge(), 1);
  auto e = m.nominal();
  const double gamma = 3e-6, T = 80.0;
  set(m, e, AxisError::E_CZ, {gamma});
  Eigen::Matrix3Xd p(3, 1);
  p << 10.0, 20.0, -30.0;
  const Eigen::Matrix3Xd err = tip_errors(m, e, p, Eigen::Vector3d(T, 0.0, 0.0));
  EXPECT_NEAR(err(1, 0), -gamma * T, 1e-18);
  EXPECT_EQ(err(0, 0), 0.0);
  EXPECT_EQ(err(2, 0), 0.0);
}

// Squareness convention, pinned: E_C0Y = γ > 0 turns Y's direction of motion about +z to
// (−γ, 1, 0); a tip truly at (0, y, 0) is reached with the X reading +γy, so it is measured
// at x = +γ·y. E_B0Z = β: Z moves along (β, 0, 1), a true (0, 0, z) is measured at x = −β·z.
// E_A0Z = α: Z moves along (0, −α, 1), a true (0, 0, z) is measured at y = +α·z.
TEST(RigidBody, SquarenessSignConventionPinned) {
  for (const Formula formula : {Formula::first_order, Formula::exact}) {
    const auto m = model_with(KinematicChain::moving_bridge(), 1);
    auto e = m.nominal();
    const double g = 1e-6;
    e.set_squareness(m, Squareness::E_C0Y, g);
    Eigen::Matrix3Xd w(3, 1);
    w << 0.0, 400.0, 0.0;
    Eigen::Matrix3Xd p = measured_tip_positions(m, e, w, Eigen::Vector3d::Zero(), formula);
    EXPECT_NEAR(p(0, 0), g * 400.0, 1e-15);
    EXPECT_NEAR(p(1, 0), 400.0, 1e-9);  // exact: 400/cos γ = 400 + 2e-10 (second order)

    e.set_squareness(m, Squareness::E_C0Y, 0.0);
    e.set_squareness(m, Squareness::E_B0Z, g);
    w << 0.0, 0.0, 300.0;
    p = measured_tip_positions(m, e, w, Eigen::Vector3d::Zero(), formula);
    EXPECT_NEAR(p(0, 0), -g * 300.0, 1e-15);
    EXPECT_NEAR(p(1, 0), 0.0, 1e-15);

    e.set_squareness(m, Squareness::E_B0Z, 0.0);
    e.set_squareness(m, Squareness::E_A0Z, g);
    p = measured_tip_positions(m, e, w, Eigen::Vector3d::Zero(), formula);
    EXPECT_NEAR(p(1, 0), g * 300.0, 1e-15);
    EXPECT_NEAR(p(0, 0), 0.0, 1e-15);
  }
}

// ---- closed forms on a ring ----------------------------------------------------------------

// Measured x = x + γy: Δr = γ y cos θ = (γR/2) sin 2θ, a 2-lobe form of peak-to-valley γR.
TEST(Ring, SquarenessGivesTwoLobesOfPeakToValleyGammaR) {
  const auto m = model_with(KinematicChain::moving_bridge(), 1);
  auto e = m.nominal();
  const double gamma = 1e-6, R = 85.5;
  e.set_squareness(m, Squareness::E_C0Y, gamma);
  const Eigen::Matrix3Xd w = circle({120.0, -200.0, -100.0}, R, 3600);
  for (const Formula formula : {Formula::first_order, Formula::exact}) {
    const Eigen::Matrix3Xd p = measured_tip_positions(m, e, w, Eigen::Vector3d(0, 0, -50), formula);
    const Eigen::VectorXd d = radial_deviations(p);
    const auto [a2, b2] = harmonic(d, 2);
    // 2-lobe amplitude γR/2 in sin 2θ; relative tolerance 1e-4 covers the O(γ) terms.
    EXPECT_NEAR(b2, gamma * R / 2.0, 1e-4 * gamma * R);
    EXPECT_NEAR(a2, 0.0, 1e-4 * gamma * R);
    EXPECT_NEAR(d.maxCoeff() - d.minCoeff(), gamma * R, 1e-3 * gamma * R);
  }
}

// E_XX = s·q_x, E_YY = s·q_y (positive: carriages overshoot): measured = true/(1 + s), so the
// measured diameter is smaller by ≈ 2Rs and the form is unchanged.
TEST(Ring, ScaleChangesDiameterNotForm) {
  const auto m = model_with(KinematicChain::moving_bridge(), 2);
  auto e = m.nominal();
  const double s = 1e-6, R = 85.5;
  set(m, e, AxisError::E_XX, {0.0, s * 500.0});  // u = q/500 on [−500, 500]
  set(m, e, AxisError::E_YY, {0.0, s * 600.0});  // u = q/600 on [−600, 600]
  const Eigen::Matrix3Xd w = circle({150.0, 250.0, 0.0}, R, 720);
  const Eigen::Matrix3Xd p = measured_tip_positions(m, e, w, Eigen::Vector3d::Zero());
  EXPECT_NEAR(2.0 * mean_radius(p) - 2.0 * R, -2.0 * R * s, 1e-6 * 2.0 * R * s);
  const Eigen::VectorXd d = radial_deviations(p);
  EXPECT_LT(d.maxCoeff() - d.minCoeff(), 1e-12);  // rounding of 85 mm coordinates
}

// An affine error map (translations linear in position, rotations constant) gives the same
// deviations anywhere; a quadratic straightness does not.
TEST(Ring, AffineMapIsLocationIndependentNonLinearIsNot) {
  const auto m = model_with(KinematicChain::moving_bridge(), 3);
  const Eigen::Vector3d t(0.0, 0.0, -120.0);
  const double R = 85.5;
  const Eigen::Matrix3Xd wa = circle({-300.0, -350.0, -200.0}, R, 360);
  const Eigen::Matrix3Xd wb = circle({300.0, 400.0, -200.0}, R, 360);

  auto affine = m.nominal();
  set(m, affine, AxisError::E_XX, {1e-4, 3e-4});
  set(m, affine, AxisError::E_YX, {0.0, 2e-4});
  set(m, affine, AxisError::E_XY, {-1e-4, 2.5e-4});
  set(m, affine, AxisError::E_YY, {0.0, -4e-4});
  set(m, affine, AxisError::E_CY, {1e-6});
  set(m, affine, AxisError::E_AX, {0.5e-6});
  set(m, affine, AxisError::E_CZ, {0.7e-6});
  affine.set_squareness(m, Squareness::E_C0Y, 0.8e-6);
  const Eigen::VectorXd da = radial_deviations(measured_tip_positions(m, affine, wa, t));
  const Eigen::VectorXd db = radial_deviations(measured_tip_positions(m, affine, wb, t));
  EXPECT_GT(da.maxCoeff() - da.minCoeff(), 1e-5);      // a visible form (tens of nm)
  EXPECT_LT((da - db).cwiseAbs().maxCoeff(), 1e-12);  // same at both locations

  auto bow = m.nominal();
  set(m, bow, AxisError::E_YX, {0.0, 0.0, 0.3e-3});  // 0.3 µm quadratic straightness of X
  const Eigen::VectorXd qa = radial_deviations(measured_tip_positions(m, bow, wa, t));
  const Eigen::VectorXd qb = radial_deviations(measured_tip_positions(m, bow, wb, t));
  EXPECT_GT((qa - qb).cwiseAbs().maxCoeff(), 1e-6);  // differs by > 1 nm
}

// ---- chain configuration -------------------------------------------------------------------

// Moving bridge (base→Y→X→Z) vs fixed bridge (Y table): identical for every X and Z error
// and for Y's translations and roll; Y's pitch and yaw gain the arm q_y ŷ on the table:
// Δv = ε_Y × q_y ŷ, i.e. e_fixed − e_bridge = −(E_AY q_y ẑ − E_CY q_y x̂).
TEST(Chain, MovingBridgeVersusMovingTable) {
  const auto bridge = model_with(KinematicChain::moving_bridge(), 2);
  const auto table = model_with(KinematicChain::fixed_bridge(), 2);
  const Eigen::Vector3d t(15.0, -20.0, -100.0);
  Eigen::Matrix3Xd p(3, 5);
  p << 0.0, 100.0, -300.0, 400.0, 10.0,  //
      0.0, -500.0, 200.0, 550.0, -20.0,  //
      -100.0, -300.0, 100.0, 250.0, -400.0;
  for (int f = 0; f < axis_error_count; ++f) {
    const auto ef = static_cast<AxisError>(f);
    auto eb = bridge.nominal();
    auto et = table.nominal();
    const double scale = is_rotation(ef) ? 1e-6 : 1e-3;
    set(bridge, eb, ef, {0.7 * scale, 0.4 * scale});
    set(table, et, ef, {0.7 * scale, 0.4 * scale});
    const Eigen::Matrix3Xd db = tip_errors(bridge, eb, p, t);
    const Eigen::Matrix3Xd dt = tip_errors(table, et, p, t);
    Eigen::Matrix3Xd expected_diff = Eigen::Matrix3Xd::Zero(3, p.cols());
    for (Eigen::Index i = 0; i < p.cols(); ++i) {
      if (ef != AxisError::E_AY && ef != AxisError::E_CY) continue;
      const double qy = p(1, i) - t.y();
      const double eps = error_function_value(bridge, eb, ef, qy);
      if (ef == AxisError::E_AY) expected_diff(2, i) = -eps * qy;
      if (ef == AxisError::E_CY) expected_diff(0, i) = eps * qy;
    }
    EXPECT_LT((dt - db - expected_diff).cwiseAbs().maxCoeff(), 1e-17) << name(ef);
    if (ef == AxisError::E_AY || ef == AxisError::E_CY) {
      EXPECT_GT(expected_diff.cwiseAbs().maxCoeff(), 1e-4) << name(ef);  // really differs
    }
  }
}

// Another chain: X under Y (base → X → Y → Z) moves the arm of E_CX (yaw of X) by q_y ŷ.
TEST(Chain, AxisOrderSetsTheAbbeArms) {
  const auto yxz = model_with(KinematicChain::moving_bridge(), 1);
  const auto xyz = model_with(KinematicChain{{Axis::x, Axis::y, Axis::z}, {}}, 1);
  auto e1 = yxz.nominal();
  auto e2 = xyz.nominal();
  const double g = 1e-6;
  set(yxz, e1, AxisError::E_CX, {g});
  set(xyz, e2, AxisError::E_CX, {g});
  Eigen::Matrix3Xd p(3, 1);
  p << 100.0, 300.0, -50.0;
  const Eigen::Vector3d t = Eigen::Vector3d::Zero();
  // base→X→Y→Z: arm of X's yaw = q_y ŷ + q_z ẑ: v = g ẑ × 300 ŷ = −300 g x̂ → e_x = +300 g.
  EXPECT_NEAR(tip_errors(xyz, e2, p, t)(0, 0), 300.0 * g, 1e-18);
  // base→Y→X→Z: arm of X's yaw = q_z ẑ only: no x error.
  EXPECT_NEAR(tip_errors(yxz, e1, p, t)(0, 0), 0.0, 1e-18);
}

// ---- exact vs first order ------------------------------------------------------------------

KinematicErrors random_errors(const KinematicModel& m, std::uint64_t seed) {
  SeededRandomSource rng(seed);
  Eigen::VectorXd v(m.parameter_count());
  rng.fill_standard_normal({v.data(), static_cast<std::size_t>(v.size())});
  return KinematicErrors(m, v);  // O(1) mm and O(1) rad: scaled down by s below
}

TEST(ExactVsFirstOrder, AgreeToSecondOrder) {
  const std::uint64_t seed = 77;
  SCOPED_TRACE("seed " + std::to_string(seed));
  for (const auto& chain : {KinematicChain::moving_bridge(), KinematicChain::fixed_bridge(),
                            KinematicChain{{Axis::z}, {Axis::x, Axis::y}}}) {
    const auto m = model_with(chain, 3);
    const KinematicErrors base = random_errors(m, seed);
    Eigen::Matrix3Xd p(3, 4);
    p << -400.0, 0.0, 300.0, 450.0,  //
        500.0, 0.0, -250.0, 100.0,   //
        -200.0, 0.0, 200.0, 240.0;
    const Eigen::Vector3d t(20.0, -30.0, -150.0);
    double prev = 0.0, prev_s = 0.0;
    for (const double s : {1e-3, 1e-4, 1e-5}) {
      const auto e = base.scaled(s);
      const double d = (tip_errors(m, e, p, t, Formula::exact) -
                        tip_errors(m, e, p, t, Formula::first_order))
                           .cwiseAbs()
                           .maxCoeff();
      EXPECT_GT(d, 0.0);
      if (prev > 0.0) {
        // Second order: d falls by 1e-2 per decade of s. Third-order terms make the ratio
        // off by a relative O(s) (observed ≈ 15·s with these O(1) base errors): allow 50·s.
        EXPECT_NEAR(d / prev, 1e-2, 1e-2 * 50.0 * prev_s) << "s = " << s;
      }
      prev_s = s;
      prev = d;
    }
  }
}

TEST(ExactVsFirstOrder, FirstOrderIsExactWithoutRotations) {
  const auto m = model_with(KinematicChain::fixed_bridge(), 4);
  auto e = random_errors(m, 5).scaled(1e-2);
  for (int f = 0; f < axis_error_count; ++f) {
    if (is_rotation(static_cast<AxisError>(f))) {
      set(m, e, static_cast<AxisError>(f), {0.0});
    }
  }
  for (int s = 0; s < squareness_count; ++s) e.set_squareness(m, static_cast<Squareness>(s), 0.0);
  const Eigen::Matrix3Xd p = circle({100.0, -200.0, 50.0}, 85.0, 100);
  const Eigen::Vector3d t(5.0, 5.0, -100.0);
  const Eigen::Matrix3Xd d =
      tip_errors(m, e, p, t, Formula::exact) - tip_errors(m, e, p, t, Formula::first_order);
  EXPECT_LT(d.cwiseAbs().maxCoeff(), 1e-13);  // rounding of ~300 mm coordinates
}

// ---- realisations --------------------------------------------------------------------------

KinematicModel uncertain_model() {
  std::array<ErrorFunctionEstimate, axis_error_count> fns;
  for (auto& f : fns) {
    f.coefficients = {0.0, 0.0};
    f.standard_uncertainties = {0.0, 0.0};
  }
  auto& exx = fns[static_cast<int>(AxisError::E_XX)];
  exx.coefficients = {1e-4, 2e-4};
  exx.standard_uncertainties = {1e-4, 2e-4};
  exx.correlation = Eigen::MatrixXd{{1.0, 0.6}, {0.6, 1.0}};
  auto& ebx = fns[static_cast<int>(AxisError::E_BX)];
  ebx.coefficients = {-0.3e-6, 0.1e-6};
  ebx.standard_uncertainties = {0.2e-6, 0.0};  // second coefficient known exactly
  std::array<EstimatedValue, squareness_count> sq{};
  sq[0] = {0.5e-6, 0.3e-6};
  return KinematicModel(KinematicChain::moving_bridge(), kRanges, fns, sq);
}

TEST(Draw, NominalIsTheMean) {
  const auto m = uncertain_model();
  EXPECT_EQ(m.nominal().parameters(), m.mean());
  EXPECT_DOUBLE_EQ(m.nominal().coefficients(m, AxisError::E_XX)[1], 2e-4);
  EXPECT_DOUBLE_EQ(m.nominal().squareness(m, Squareness::E_C0Y), 0.5e-6);
}

TEST(Draw, SampleMeanAndCovarianceMatchTheModel) {
  const auto m = uncertain_model();
  const std::uint64_t seed = 12345;
  SCOPED_TRACE("seed " + std::to_string(seed));
  SeededRandomSource rng(seed);
  const int n = 20000;
  const Eigen::Index np = m.parameter_count();
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(np);
  Eigen::MatrixXd sum2 = Eigen::MatrixXd::Zero(np, np);
  KinematicErrors e;
  const Eigen::VectorXd sd = m.covariance().diagonal().cwiseSqrt();
  for (int i = 0; i < n; ++i) {
    m.draw(rng, e);
    for (Eigen::Index k = 0; k < np; ++k) {
      if (sd[k] == 0.0) {
        ASSERT_EQ(e.parameters()[k], m.mean()[k]) << k;  // known exactly: never moves
      }
    }
    sum += e.parameters();
    const Eigen::VectorXd d = e.parameters() - m.mean();
    sum2 += d * d.transpose();
  }
  const Eigen::VectorXd mean = sum / n;
  const Eigen::MatrixXd cov = sum2 / n;  // about the true mean
  for (Eigen::Index i = 0; i < np; ++i) {
    if (sd[i] == 0.0) continue;
    // 5 standard errors: a false alarm has probability ~6e-7 per check.
    EXPECT_NEAR(mean[i], m.mean()[i], 5.0 * sd[i] / std::sqrt(n)) << i;
    // Sample variance: relative standard error √(2/n).
    EXPECT_NEAR(cov(i, i) / (sd[i] * sd[i]), 1.0, 5.0 * std::sqrt(2.0 / n)) << i;
  }
  const Eigen::Index a = m.parameter_offset(AxisError::E_XX);
  const double r = cov(a, a + 1) / std::sqrt(cov(a, a) * cov(a + 1, a + 1));
  EXPECT_NEAR(r, 0.6, 5.0 * (1.0 - 0.36) / std::sqrt(n));  // s.e. of r ≈ (1 − ρ²)/√n
  const Eigen::Index b = m.parameter_offset(AxisError::E_BX);
  EXPECT_NEAR(cov(a, b) / (sd[a] * sd[b]), 0.0, 5.0 / std::sqrt(n));  // independent functions
}

// Left uncorrected, only in the uncertainty: estimate 0, variance u² + m², covariances kept.
TEST(Draw, UncorrectedModelHasZeroMeanAndTheWholeErrorAsVariance) {
  const auto m = uncertain_model();
  const auto u = m.uncorrected();
  EXPECT_TRUE(u.mean().isZero(0.0));
  for (Eigen::Index i = 0; i < m.parameter_count(); ++i) {
    EXPECT_DOUBLE_EQ(u.covariance()(i, i),
                     m.covariance()(i, i) + m.mean()[i] * m.mean()[i]) << i;
    for (Eigen::Index j = 0; j < m.parameter_count(); ++j)
      if (j != i) {
        EXPECT_EQ(u.covariance()(i, j), m.covariance()(i, j)) << i << "," << j;
      }
  }
  // The second coefficient of E_BX was known exactly (u = 0, m = 1e-7): it now varies.
  const Eigen::Index b = m.parameter_offset(AxisError::E_BX) + 1;
  EXPECT_EQ(m.covariance()(b, b), 0.0);
  EXPECT_DOUBLE_EQ(u.covariance()(b, b), 1e-14);
  SeededRandomSource rng(4);
  double sum2 = 0.0;
  for (int i = 0; i < 4000; ++i) {
    const double v = u.draw(rng).parameters()[b];
    sum2 += v * v;
  }
  // Sample second moment: relative standard error √(2/n) ≈ 2.2 %; 5 of them.
  EXPECT_NEAR(sum2 / 4000.0 / 1e-14, 1.0, 5.0 * std::sqrt(2.0 / 4000.0));
  // Correction with the uncorrected model removes nothing.
  EXPECT_TRUE(u.nominal().parameters().isZero(0.0));
}

// draw() = mean + L z, L the Cholesky factor of the covariance of the parameters with
// non-zero variance, z the source's next normals — checked for both of its loops: the
// uncertain parameters scattered (uncertain_model) and all of them one run (every parameter
// given a variance, as the example model).
TEST(Draw, IsTheMeanPlusTheCholeskyFactorTimesTheNormals) {
  KinematicModel all = uncertain_model();
  Eigen::MatrixXd cov = all.covariance();
  for (Eigen::Index i = 0; i < cov.rows(); ++i)
    if (cov(i, i) == 0.0) cov(i, i) = 1e-14;
  all.set_covariance(cov);
  for (const KinematicModel& m : {uncertain_model(), all}) {
    std::vector<Eigen::Index> uncertain;
    for (Eigen::Index i = 0; i < m.parameter_count(); ++i)
      if (m.covariance()(i, i) > 0.0) uncertain.push_back(i);
    const auto k = static_cast<Eigen::Index>(uncertain.size());
    SCOPED_TRACE(std::to_string(k) + " of " + std::to_string(m.parameter_count()) +
                 " parameters uncertain");
    Eigen::MatrixXd sub(k, k);
    for (Eigen::Index a = 0; a < k; ++a)
      for (Eigen::Index b = 0; b < k; ++b)
        sub(a, b) = m.covariance()(uncertain[static_cast<std::size_t>(a)],
                                   uncertain[static_cast<std::size_t>(b)]);
    const Eigen::MatrixXd l = sub.llt().matrixL();
    SeededRandomSource r1(21), r2(21);
    std::vector<double> z(static_cast<std::size_t>(k));
    r2.fill_standard_normal(z);
    Eigen::VectorXd want = m.mean();
    for (Eigen::Index a = 0; a < k; ++a)
      for (Eigen::Index b = 0; b <= a; ++b)
        want[uncertain[static_cast<std::size_t>(a)]] += l(a, b) * z[static_cast<std::size_t>(b)];
    const Eigen::VectorXd got = m.draw(r1).parameters();
    for (Eigen::Index i = 0; i < m.parameter_count(); ++i) {  // rounding only
      const double tolerance =
          1e-12 * (std::sqrt(m.covariance()(i, i)) + std::abs(want[i]));
      EXPECT_NEAR(got[i], want[i], tolerance) << i;
    }
  }
}

// draw() skips the zeros below each block of the Cholesky factor (a block-diagonal
// covariance: no correlation between functions). The full-triangle sum in the same order must
// come out bit for bit (sign of zero included), also where an estimate is −0 — the one case
// where adding a zero term changes a value (−0 + +0 = +0), so there nothing is skipped.
TEST(Draw, SkippingTheFactorsZeroBlocksGivesTheSameBits) {
  for (const bool negative_zero : {false, true}) {
    SCOPED_TRACE(negative_zero ? "an estimate of -0" : "no estimate -0");
    std::array<ErrorFunctionEstimate, axis_error_count> fns;
    for (int f = 0; f < axis_error_count; ++f) {
      auto& e = fns[static_cast<std::size_t>(f)];
      e.coefficients = {1e-4 * (f + 1), -2e-5 * f, 0.0};
      e.standard_uncertainties = {1e-4, 5e-5, 2e-5};
      e.correlation = Eigen::MatrixXd{{1.0, 0.5, 0.1}, {0.5, 1.0, 0.3}, {0.1, 0.3, 1.0}};
    }
    if (negative_zero) fns[4].coefficients[2] = -0.0;
    std::array<EstimatedValue, squareness_count> sq{};
    sq[0] = {0.5e-6, 0.3e-6};
    sq[1] = {-1e-7, 0.1e-6};
    sq[2] = {0.0, 0.2e-6};
    const KinematicModel m(KinematicChain::moving_bridge(), kRanges, fns, sq);
    const Eigen::Index k = m.parameter_count();  // every parameter uncertain
    const Eigen::MatrixXd l = m.covariance().llt().matrixL();
    for (std::uint64_t seed = 31; seed < 36; ++seed) {
      SeededRandomSource r1(seed), r2(seed);
      std::vector<double> z(static_cast<std::size_t>(k));
      r2.fill_standard_normal(z);
      Eigen::VectorXd want = m.mean();
      for (Eigen::Index a = 0; a < k; ++a)
        for (Eigen::Index b = 0; b <= a; ++b) want[a] += l(a, b) * z[static_cast<std::size_t>(b)];
      const Eigen::VectorXd got = m.draw(r1).parameters();
      for (Eigen::Index i = 0; i < k; ++i)
        EXPECT_EQ(std::bit_cast<std::uint64_t>(got[i]), std::bit_cast<std::uint64_t>(want[i]))
            << "parameter " << i << ": " << got[i] << " vs " << want[i];
    }
  }
}

TEST(Draw, IntoReusedStorageGivesTheSameStream) {
  const auto m = uncertain_model();
  SeededRandomSource r1(9), r2(9);
  KinematicErrors reused;
  for (int i = 0; i < 3; ++i) {
    m.draw(r1, reused);
    EXPECT_EQ(reused.parameters(), m.draw(r2).parameters());
  }
}

TEST(Draw, JointCovarianceIsValidated) {
  auto m = uncertain_model();
  Eigen::MatrixXd c = m.covariance();
  const Eigen::Index a = m.parameter_offset(AxisError::E_XX);
  const Eigen::Index s = m.parameter_offset(Squareness::E_C0Y);
  c(a, s) = c(s, a) = 0.5 * std::sqrt(c(a, a) * c(s, s));
  EXPECT_NO_THROW(m.set_covariance(c));
  c(a, s) = c(s, a) = 1.5 * std::sqrt(c(a, a) * c(s, s));
  EXPECT_NE(thrown_message([&] { m.set_covariance(c); }).find("not positive definite"),
            std::string::npos);
  const Eigen::Index known = m.parameter_offset(AxisError::E_BX) + 1;
  c = m.covariance();
  c(known, a) = c(a, known) = 1e-12;
  EXPECT_NE(thrown_message([&] { m.set_covariance(c); }).find("zero variance"), std::string::npos);
}

// ---- simulation and correction -------------------------------------------------------------

TEST(Positions, CorrectionUndoesSimulation) {
  const auto m = uncertain_model();
  SeededRandomSource rng(3);
  const auto e = m.draw(rng);
  const Eigen::Matrix3Xd w = circle({-200.0, 300.0, -150.0}, 85.5, 100);
  const Eigen::Vector3d t(0.0, 0.0, -100.0);
  for (const Formula formula : {Formula::first_order, Formula::exact}) {
    const Eigen::Matrix3Xd p = measured_tip_positions(m, e, w, t, formula);
    EXPECT_GT((p - w).cwiseAbs().maxCoeff(), 1e-5);  // the errors are there (> 10 nm)
    EXPECT_LT((true_tip_positions(m, e, p, t, formula) - w).cwiseAbs().maxCoeff(), 1e-12);
  }
}

// ---- bad input -----------------------------------------------------------------------------

TEST(BadInput, PointsOutsideTheRangeOrNotFinite) {
  const auto m = model_with(KinematicChain::moving_bridge(), 1);
  const auto e = m.nominal();
  Eigen::Matrix3Xd p = Eigen::Matrix3Xd::Zero(3, 100);
  p(1, 70) = 700.0;
  const std::string msg = thrown_message([&] { (void)tip_errors(m, e, p, Eigen::Vector3d::Zero()); });
  EXPECT_NE(msg.find("tip_errors: point 70"), std::string::npos) << msg;
  EXPECT_NE(msg.find("Y axis"), std::string::npos) << msg;
  EXPECT_NE(msg.find("[-600, 600]"), std::string::npos) << msg;
  // The stylus offset shifts the reading: z tip −450 with t_z = −100 is q_z = −350, inside.
  p(1, 70) = 0.0;
  p(2, 3) = -450.0;
  EXPECT_NO_THROW((void)tip_errors(m, e, p, Eigen::Vector3d(0.0, 0.0, -100.0)));
  p(2, 3) = std::nan("");
  EXPECT_NE(thrown_message([&] { (void)tip_errors(m, e, p, Eigen::Vector3d::Zero()); })
                .find("point 3 has a non-finite z coordinate"),
            std::string::npos);
  p(2, 3) = 0.0;
  EXPECT_NE(thrown_message([&] {
              (void)tip_errors(m, e, p, Eigen::Vector3d(0.0, std::nan(""), 0.0));
            }).find("stylus offset must be finite"),
            std::string::npos);
  const auto other = model_with(KinematicChain::moving_bridge(), 2);
  EXPECT_NE(thrown_message([&] { (void)tip_errors(other, e, p, Eigen::Vector3d::Zero()); })
                .find("another model"),
            std::string::npos);
}

TEST(BadInput, ModelConstruction) {
  std::array<ErrorFunctionEstimate, axis_error_count> fns;
  for (auto& f : fns) {
    f.coefficients = {0.0};
    f.standard_uncertainties = {0.0};
  }
  auto ranges = kRanges;
  ranges[2] = {10.0, 10.0};
  EXPECT_NE(thrown_message([&] { KinematicModel(KinematicChain::moving_bridge(), ranges, fns, {}); })
                .find("range of axis Z"),
            std::string::npos);
  KinematicChain twice{{Axis::y, Axis::x, Axis::z}, {Axis::y}};
  EXPECT_NE(thrown_message([&] { twice.validate(); }).find("axis Y appears 2 times"),
            std::string::npos);
  fns[4].standard_uncertainties = {-1.0};
  EXPECT_NE(thrown_message([&] { KinematicModel(KinematicChain::moving_bridge(), kRanges, fns, {}); })
                .find("E_BX: standard uncertainty 0 must be finite and >= 0"),
            std::string::npos);
  fns[4].standard_uncertainties = {0.0};
  fns[7].coefficients.assign(12, 0.0);
  fns[7].standard_uncertainties.assign(12, 0.0);
  EXPECT_NE(thrown_message([&] { KinematicModel(KinematicChain::moving_bridge(), kRanges, fns, {}); })
                .find("E_YY: needs 1 to 11 Legendre coefficients; got 12"),
            std::string::npos);
}

// ---- JSON ----------------------------------------------------------------------------------

nlohmann::json example_section() {
  nlohmann::json j = R"({
    "comment": "residual errors after compensation",
    "chain": "moving_bridge",
    "axis_range_mm": {"X": [0, 800], "Y": [0, 1000], "Z": [-600, 0]},
    "errors": {},
    "squareness": {
      "E_C0Y": {"value_urad": 0.5, "uncertainty_urad": 0.3},
      "E_B0Z": {"value_urad": -0.2, "uncertainty_urad": 0.3},
      "E_A0Z": {"value_urad": 0.0, "uncertainty_urad": 0.3}
    }
  })"_json;
  for (int f = 0; f < axis_error_count; ++f) {
    const auto e = static_cast<AxisError>(f);
    const std::string n(name(e));
    if (is_rotation(e)) {
      j["errors"][n] = {{"legendre_urad", {0.0, 0.2}}, {"uncertainty_urad", {0.1, 0.1}}};
    } else {
      j["errors"][n] = {{"legendre_um", {0.0, 0.3, 0.05}}, {"uncertainty_um", {0.05, 0.1, 0.05}}};
    }
  }
  j["errors"]["E_XX"]["correlation"] = {{1.0, 0.3, 0.0}, {0.3, 1.0, 0.0}, {0.0, 0.0, 1.0}};
  return j;
}

TEST(Json, ParsesAndConvertsUnits) {
  const auto m = kinematic_model_from_json(example_section(), "kinematics");
  EXPECT_EQ(m.chain(), KinematicChain::moving_bridge());
  EXPECT_EQ(m.range(Axis::z).min, -600.0);
  EXPECT_EQ(m.coefficient_count(AxisError::E_XX), 3);
  EXPECT_EQ(m.coefficient_count(AxisError::E_AX), 2);
  const auto e = m.nominal();
  EXPECT_DOUBLE_EQ(e.coefficients(m, AxisError::E_ZY)[1], 0.3e-3);   // µm → mm
  EXPECT_DOUBLE_EQ(e.coefficients(m, AxisError::E_CZ)[1], 0.2e-6);   // µrad → rad
  EXPECT_DOUBLE_EQ(e.squareness(m, Squareness::E_B0Z), -0.2e-6);
  const Eigen::Index a = m.parameter_offset(AxisError::E_XX);
  EXPECT_DOUBLE_EQ(m.covariance()(a, a + 1), 0.3 * 0.05e-3 * 0.1e-3);
  EXPECT_DOUBLE_EQ(m.covariance()(a + 1, a + 1), 0.1e-3 * 0.1e-3);

  auto j = example_section();
  j["chain"] = "fixed_bridge";
  EXPECT_EQ(kinematic_model_from_json(j, "k").chain(), KinematicChain::fixed_bridge());
  j["chain"] = {{"tool_side", {"X", "Y", "Z"}}, {"workpiece_side", nlohmann::json::array()}};
  EXPECT_EQ(kinematic_model_from_json(j, "k").chain(),
            (KinematicChain{{Axis::x, Axis::y, Axis::z}, {}}));
}

// Each broken rule: the message names the full key path, the rule and the value.
TEST(Json, ErrorsNameTheKeyPath) {
  struct Case {
    const char* what;
    std::function<void(nlohmann::json&)> edit;
    const char* expected;
  };
  const std::vector<Case> cases = {
      {"missing function", [](auto& j) { j["errors"].erase("E_ZY"); },
       "model.kinematics.errors.E_ZY: required key is missing"},
      {"missing section key", [](auto& j) { j.erase("squareness"); },
       "model.kinematics.squareness: required key is missing"},
      {"non-numeric", [](auto& j) { j["errors"]["E_XX"]["legendre_um"][1] = "abc"; },
       "model.kinematics.errors.E_XX.legendre_um[1]: must be a number; got \"abc\""},
      {"negative uncertainty", [](auto& j) { j["errors"]["E_AX"]["uncertainty_urad"][0] = -0.2; },
       "model.kinematics.errors.E_AX.uncertainty_urad[0]: must lie in [0, 10000] µrad (a standard "
       "uncertainty); got -0.2 µrad"},
      // Issue 12: values far outside any CMM are refused under their own key, with the unit.
      {"huge coefficient", [](auto& j) { j["errors"]["E_XX"]["legendre_um"][1] = 1e300; },
       "model.kinematics.errors.E_XX.legendre_um[1]: must lie in [-1000, 1000] µm (a kinematic "
       "error coefficient); got 1e+300 µm"},
      {"huge uncertainty", [](auto& j) { j["errors"]["E_YX"]["uncertainty_um"][0] = 2000; },
       "model.kinematics.errors.E_YX.uncertainty_um[0]: must lie in [0, 1000] µm"},
      {"huge rotation", [](auto& j) { j["errors"]["E_AX"]["legendre_urad"][0] = -2e4; },
       "model.kinematics.errors.E_AX.legendre_urad[0]: must lie in [-10000, 10000] µrad"},
      {"huge squareness", [](auto& j) { j["squareness"]["E_C0Y"]["value_urad"] = 1e300; },
       "model.kinematics.squareness.E_C0Y.value_urad: must lie in [-10000, 10000] µrad"},
      {"wrong length", [](auto& j) { j["errors"]["E_YX"]["uncertainty_um"] = {0.1, 0.1}; },
       "model.kinematics.errors.E_YX.uncertainty_um: must have 3 elements; got 2"},
      {"too many coefficients",
       [](auto& j) { j["errors"]["E_YX"]["legendre_um"] = std::vector<double>(12, 0.0); },
       "model.kinematics.errors.E_YX.legendre_um: must have 1 to 11 elements; got 12"},
      {"non-PD correlation",
       [](auto& j) {
         j["errors"]["E_XX"]["correlation"] = {{1.0, 0.9, 0.9}, {0.9, 1.0, -0.9}, {0.9, -0.9, 1.0}};
       },
       "model.kinematics.errors.E_XX.correlation: must be positive definite"},
      {"asymmetric correlation",
       [](auto& j) { j["errors"]["E_XX"]["correlation"][0][1] = 0.2; },
       "model.kinematics.errors.E_XX.correlation[0][1]: correlation must be symmetric"},
      {"correlation shape", [](auto& j) { j["errors"]["E_XX"]["correlation"] = {{1.0}}; },
       "model.kinematics.errors.E_XX.correlation: must be an array of 3 rows"},
      {"unknown axis", [](auto& j) { j["axis_range_mm"]["W"] = {0, 1}; },
       "model.kinematics.axis_range_mm.W: unknown axis name"},
      {"range order", [](auto& j) { j["axis_range_mm"]["Y"] = {10, -10}; },
       "model.kinematics.axis_range_mm.Y: must be [min, max] with min < max; got [10,-10]"},
      {"unknown error", [](auto& j) { j["errors"]["E_QX"] = nlohmann::json::object(); },
       "model.kinematics.errors.E_QX: unknown error name"},
      {"wrong unit", [](auto& j) { j["errors"]["E_AX"]["legendre_um"] = {0.0}; },
       "model.kinematics.errors.E_AX.legendre_um: unknown key"},
      {"chain missing an axis",
       [](auto& j) {
         j["chain"] = {{"tool_side", {"Y", "X"}}, {"workpiece_side", nlohmann::json::array()}};
       },
       "model.kinematics.chain: every axis must appear exactly once"},
      {"chain unknown axis",
       [](auto& j) {
         j["chain"] = {{"tool_side", {"Y", "X", "Q"}}, {"workpiece_side", nlohmann::json::array()}};
       },
       "model.kinematics.chain.tool_side[2]: unknown axis name"},
      {"unknown preset", [](auto& j) { j["chain"] = "horizontal_arm"; },
       "model.kinematics.chain: unknown chain preset"},
      {"squareness uncertainty", [](auto& j) { j["squareness"]["E_B0Z"].erase("uncertainty_urad"); },
       "model.kinematics.squareness.E_B0Z.uncertainty_urad: required key is missing"},
      {"squareness non-numeric", [](auto& j) { j["squareness"]["E_C0Y"]["value_urad"] = true; },
       "model.kinematics.squareness.E_C0Y.value_urad: must be a number; got true"},
      {"section not an object", [](auto& j) { j = nlohmann::json::array(); },
       "model.kinematics: must be a JSON object"},
  };
  for (const auto& c : cases) {
    auto j = example_section();
    c.edit(j);
    const std::string msg =
        thrown_message([&] { (void)kinematic_model_from_json(j, "model.kinematics"); });
    EXPECT_NE(msg.find(c.expected), std::string::npos)
        << c.what << "\n  got:      " << msg << "\n  expected: " << c.expected;
  }
}

// The kinematics section of the shipped example model parses, and its draws give tip errors
// of the size the seed study expects (sub-µm kinematic part of ~0.8 µm single-point u).
TEST(Json, ShippedExampleModel) {
  std::ifstream in(std::string(VCMM_SOURCE_DIR) + "/examples/cmm_model.json");
  if (!in) GTEST_SKIP() << "examples/cmm_model.json not found";
  const auto root = nlohmann::json::parse(in);
  const auto m = kinematic_model_from_json(root.at("kinematics"), "kinematics");
  const Eigen::Vector3d centre(0.5 * (m.range(Axis::x).min + m.range(Axis::x).max),
                               0.5 * (m.range(Axis::y).min + m.range(Axis::y).max),
                               0.5 * (m.range(Axis::z).min + m.range(Axis::z).max));
  const Eigen::Matrix3Xd p = circle(centre, 85.5, 360);
  const Eigen::Vector3d t = Eigen::Vector3d::Zero();
  SeededRandomSource rng(1);
  double sum2 = 0.0;
  const int draws = 200;
  for (int i = 0; i < draws; ++i) {
    sum2 += tip_errors(m, m.draw(rng), p, t).squaredNorm();
  }
  const double rms_per_point = std::sqrt(sum2 / (draws * 360.0));  // 3D, mm
  EXPECT_GT(rms_per_point, 0.02e-3);
  EXPECT_LT(rms_per_point, 1.0e-3);
}

}  // namespace
