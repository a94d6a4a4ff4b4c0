// simulate_corrected — the fused Monte Carlo trial — against the two-call composition
// correct(simulate(m, draw)) it replaces (virtual_cmm.h):
//  - the bound of the header, with G (the largest |∇e|) estimated from the model by finite
//    differences and |e|, |δprobe|, |z| taken from the draw: checked on 40 draws of the
//    example model at 3600 points (measured difference ~3e-9 mm);
//  - exactness where no approximation is made: kinematic stage off (rounding only), the
//    exact formula (computed as the composition: bit for bit), the xy form (bit for bit);
//  - the approximation's order: a pure rotation error ε of the draw against a perfect
//    estimate gives a difference G·|e| ∝ ε², so ×10 in ε gives ×100 in the difference;
//  - metadata copied, bad input rejected with the function's name;
//  - PreparedMeasurement (validated once, structure of arrays, stored probe harmonics):
//    draw_errors and simulate_corrected on it are bit for bit the Measurement overloads,
//    for every stage alone and all together, and when a draw's probe order exceeds the
//    stored harmonics (the Measurement path is taken).
// Fixed seeds; all sizes ≤ 3600 points (the whole file runs in well under a second).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/errors.h"
#include "vcmm/errormodel/random_source.h"
#include "vcmm/errormodel/ring_gauge.h"
#include "vcmm/errormodel/virtual_cmm.h"

namespace {

using namespace vcmm::errormodel;

const std::string kExample = std::string(VCMM_SOURCE_DIR) + "/examples/cmm_model.json";
const std::array<AxisRange, 3> kRanges = {{{0.0, 1200.0}, {0.0, 1000.0}, {0.0, 800.0}}};

Measurement ring(Eigen::Index n, double orientation_rad = 0.3) {
  RingGauge g;
  g.form = seed_study_ring_form();
  RingSampling s;
  s.points = n;
  s.placement.location_mm = {600.0, 500.0, 250.0};
  s.placement.orientation_rad = orientation_rad;
  s.temperature_c = 20.4;
  s.stylus_offset_mm = {0.0, 0.0, -50.0};
  return ring_gauge_measurement(g, s);
}

/// The best estimate the Monte Carlo loop starts from: a simulated measurement, corrected.
Measurement best_estimate(const DigitalModel& model, Eigen::Index n, std::uint64_t seed) {
  const Measurement truth = ring(n);
  SeededRandomSource rng(seed);
  return correct(simulate(truth, model, draw_errors(model, truth, rng)), model);
}

Eigen::Matrix3Xd machine_positions(const Measurement& m) {
  return (m.placement.rotation() * m.points_mm).colwise() + m.placement.location_mm;
}

/// max over the points of the Frobenius norm of ∇e (≥ the operator norm |∇e|), by central
/// differences with h = 1 mm: the error functions are cubic polynomials over metre-long
/// axes, so the difference quotient's error (~h²·|e'''|) is far below |∇e| itself.
double max_gradient(const KinematicModel& km, const KinematicErrors& e,
                    const Eigen::Matrix3Xd& w, const Eigen::Vector3d& stylus) {
  constexpr double h = 1.0;
  Eigen::ArrayXd frobenius2 = Eigen::ArrayXd::Zero(w.cols());
  for (int a = 0; a < 3; ++a) {
    Eigen::Matrix3Xd plus = w, minus = w;
    plus.row(a).array() += h;
    minus.row(a).array() -= h;
    const Eigen::Matrix3Xd d =
        (tip_errors(km, e, plus, stylus) - tip_errors(km, e, minus, stylus)) / (2.0 * h);
    frobenius2 += d.colwise().squaredNorm().transpose().array();
  }
  return std::sqrt(frobenius2.maxCoeff());
}

double max_abs_difference(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return (a - b).cwiseAbs().maxCoeff();
}

TEST(SimulateCorrected, WithinTheHeaderBoundOfTheCompositionForTheExampleModel) {
  const DigitalModel model = read_digital_model_file(kExample);
  const Measurement best = best_estimate(model, 3600, 11);
  const Eigen::Matrix3Xd w = machine_positions(best);
  const double g_nominal =
      max_gradient(model.kinematics, model.kinematics.nominal(), w, best.stylus_offset_mm);
  const ErrorDraw nominal = nominal_errors(model, best);
  SeededRandomSource rng(12);
  ErrorDraw draw;
  Measurement composed, fused;
  double worst = 0.0, worst_ratio = 0.0;
  for (int trial = 0; trial < 40; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial) + " (seed 12)");
    draw_errors(model, best, rng, Stages::all(), draw);
    correct(simulate(best, model, draw), model, Stages::all(), Formula::first_order, composed);
    simulate_corrected(best, model, draw, Stages::all(), Formula::first_order, fused);
    // The bound: G·(2|e_draw| + |δprobe_draw − δprobe_nominal| + |z|) + 1e-13 mm, with each
    // magnitude at its maximum over the points (the per-point bound is smaller).
    const double g = std::max(g_nominal, max_gradient(model.kinematics, draw.kinematic, w,
                                                      best.stylus_offset_mm));
    const double e_draw = tip_errors(model.kinematics, draw.kinematic, w, best.stylus_offset_mm)
                              .cwiseAbs()
                              .maxCoeff();
    double probe = 0.0;
    for (Eigen::Index i = 0; i < best.size(); ++i) {
      const Eigen::Vector3d d = -(best.placement.rotation() * best.normals.col(i));
      probe = std::max(probe, std::fabs(probe_error_mm(draw.probe, d) -
                                        probe_error_mm(nominal.probe, d)));
    }
    const double noise = draw.noise_mm.colwise().norm().maxCoeff();
    const double bound = g * (2.0 * e_draw + probe + noise) + 1e-13;
    const double diff = max_abs_difference(composed.points_mm, fused.points_mm);
    EXPECT_LE(diff, bound);
    worst = std::max(worst, diff);
    worst_ratio = std::max(worst_ratio, diff / bound);
  }
  std::cout << "[ info ] fused vs composed, example model, 3600 points, 40 draws: max "
            << worst << " mm, at most " << worst_ratio << " of the header bound\n";
  EXPECT_LT(worst, 1e-8);  // the header's "~1e-11 to 1e-8 mm" for µm-level errors
}

TEST(SimulateCorrected, EqualsTheCompositionToRoundingWithoutKinematics) {
  // Probe, temperature, roughness and noise are applied exactly (differences of linear
  // terms); the two computations round differently at ~1 ulp of 85 mm (1.4e-14 mm) per
  // operation, a few operations each: 1e-13 mm covers it.
  const DigitalModel model = read_digital_model_file(kExample);
  const Measurement best = best_estimate(model, 720, 21);
  Stages stages = Stages::all();
  stages.set(ErrorSource::kinematic, false);
  SeededRandomSource rng(22);
  for (int trial = 0; trial < 5; ++trial) {
    const ErrorDraw draw = draw_errors(model, best, rng, stages);
    const Measurement composed =
        correct(simulate(best, model, draw, stages), model, stages);
    Measurement fused;
    simulate_corrected(best, model, draw, stages, Formula::first_order, fused);
    EXPECT_LT(max_abs_difference(composed.points_mm, fused.points_mm), 1e-13);
  }
  // Every stage off: the input itself, bit for bit.
  const ErrorDraw nothing = draw_errors(model, best, rng, Stages::none());
  Measurement same;
  simulate_corrected(best, model, nothing, Stages::none(), Formula::first_order, same);
  EXPECT_EQ(max_abs_difference(same.points_mm, best.points_mm), 0.0);
}

TEST(SimulateCorrected, KinematicApproximationIsSecondOrderInTheErrors) {
  // A perfect estimate (zero nominal errors) and a draw with squareness E_C0Y = ε (e_x = ε·y)
  // and yaw of the Y carriage E_CY = ε (e_y = ε·q_x, the X travel being its arm): the tip
  // error at m = w + e(w) differs from that at w by ∇e·e(w) = (ε²·x, ε²·y), so the
  // difference of the fused trial from the composition scales as ε². (A single such error
  // would not show it: each moves the point across its own gradient.)
  const DigitalModel model(KinematicModel::zero(KinematicChain::moving_bridge(), kRanges));
  const Measurement best = ring(360);
  const Stages stages = Stages::only(ErrorSource::kinematic);
  auto difference = [&](double epsilon) {
    ErrorDraw draw = nominal_errors(model, best);
    const double c[1] = {epsilon};
    draw.kinematic.set_squareness(model.kinematics, Squareness::E_C0Y, epsilon);
    draw.kinematic.set_coefficients(model.kinematics, AxisError::E_CY, c);
    const Measurement composed = correct(simulate(best, model, draw, stages), model, stages);
    Measurement fused;
    simulate_corrected(best, model, draw, stages, Formula::first_order, fused);
    return max_abs_difference(composed.points_mm, fused.points_mm);
  };
  const double d1 = difference(2e-5), d10 = difference(2e-4);
  // ε = 2e-5 rad at positions of ~600 mm: |e| ~ 1e-2 mm, G ~ 2e-5: G·|e| ~ 2e-7 mm, well
  // above rounding (1e-13), so the ratio shows the order: 100 for ε², 10 for ε.
  EXPECT_GT(d1, 1e-9);
  EXPECT_NEAR(d10 / d1, 100.0, 5.0);
}

TEST(SimulateCorrected, AnyNumberOfPoints) {
  // The per-thread work arrays are placed at fixed offsets from each other for every size
  // (virtual_cmm.cpp, thread_scratch): sizes whose 3N doubles are not a multiple of 64 bytes,
  // changing from call to call, against the composition (bound as above, ≤ 1e-8 mm).
  const DigitalModel model = read_digital_model_file(kExample);
  for (Eigen::Index n : {3, 7, 13, 101, 16, 999}) {
    SCOPED_TRACE("n = " + std::to_string(n));
    const Measurement best = best_estimate(model, n, 91);
    SeededRandomSource rng(92);
    const ErrorDraw draw = draw_errors(model, best, rng);
    const Measurement composed = correct(simulate(best, model, draw), model);
    Measurement fused;
    simulate_corrected(best, model, draw, Stages::all(), Formula::first_order, fused);
    EXPECT_LT(max_abs_difference(composed.points_mm, fused.points_mm), 1e-8);
  }
}

TEST(SimulateCorrected, ExactFormulaAndXyFormAreBitForBit) {
  const DigitalModel model = read_digital_model_file(kExample);
  const Measurement best = best_estimate(model, 360, 31);
  SeededRandomSource rng(32);
  const ErrorDraw draw = draw_errors(model, best, rng);
  // Formula::exact: the composition itself.
  const Measurement composed = correct(simulate(best, model, draw, Stages::all(), Formula::exact),
                                       model, Stages::all(), Formula::exact);
  Measurement fused;
  simulate_corrected(best, model, draw, Stages::all(), Formula::exact, fused);
  EXPECT_EQ(max_abs_difference(composed.points_mm, fused.points_mm), 0.0);
  std::vector<vcmm::geometry::Point2> xy;
  simulate_corrected(best, model, draw, Stages::all(), Formula::exact, xy);
  ASSERT_EQ(xy.size(), static_cast<std::size_t>(best.size()));
  for (Eigen::Index i = 0; i < best.size(); ++i) {
    EXPECT_EQ(xy[static_cast<std::size_t>(i)].x, composed.points_mm(0, i));
    EXPECT_EQ(xy[static_cast<std::size_t>(i)].y, composed.points_mm(1, i));
  }
  // First order: the xy form equals the x, y rows of the full form.
  simulate_corrected(best, model, draw, Stages::all(), Formula::first_order, fused);
  simulate_corrected(best, model, draw, Stages::all(), Formula::first_order, xy);
  for (Eigen::Index i = 0; i < best.size(); ++i) {
    EXPECT_EQ(xy[static_cast<std::size_t>(i)].x, fused.points_mm(0, i));
    EXPECT_EQ(xy[static_cast<std::size_t>(i)].y, fused.points_mm(1, i));
  }
}

TEST(SimulateCorrected, KeepsTheMeasurementsMetadataAndReusesStorage) {
  const DigitalModel model = read_digital_model_file(kExample);
  Measurement best = best_estimate(model, 360, 41);
  best.mode = ProbingMode::touch_trigger;
  SeededRandomSource rng(42);
  const ErrorDraw draw = draw_errors(model, best, rng);
  Measurement out;
  simulate_corrected(best, model, draw, Stages::all(), Formula::first_order, out);
  EXPECT_EQ(out.normals, best.normals);
  EXPECT_EQ(out.placement.location_mm, best.placement.location_mm);
  EXPECT_EQ(out.placement.orientation_rad, best.placement.orientation_rad);
  EXPECT_EQ(out.mode, best.mode);
  EXPECT_EQ(out.temperature_c, best.temperature_c);
  EXPECT_EQ(out.stylus_offset_mm, best.stylus_offset_mm);
  const double* storage = out.points_mm.data();
  simulate_corrected(best, model, draw, Stages::all(), Formula::first_order, out);
  EXPECT_EQ(out.points_mm.data(), storage);
}

TEST(SimulateCorrectedBadInput, RejectedWithTheFunctionsName) {
  const DigitalModel model = read_digital_model_file(kExample);
  const Measurement best = best_estimate(model, 64, 51);
  SeededRandomSource rng(52);
  auto expect_invalid = [](auto&& call, const std::string& fragment) {
    try {
      call();
      ADD_FAILURE() << "expected InvalidInput mentioning '" << fragment << "'";
    } catch (const InvalidInput& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("simulate_corrected"), std::string::npos) << what;
      EXPECT_NE(what.find(fragment), std::string::npos) << what;
    }
  };
  // A draw made with the noise stage off lacks the noise vectors the full run needs.
  Stages no_noise = Stages::all();
  no_noise.set(ErrorSource::noise, false);
  const ErrorDraw partial = draw_errors(model, best, rng, no_noise);
  Measurement out;
  expect_invalid([&] { simulate_corrected(best, model, partial, Stages::all(),
                                          Formula::first_order, out); },
                 "noise has 0 columns but the measurement has 64 points");
  const ErrorDraw draw = draw_errors(model, best, rng);
  Measurement self = best;
  expect_invalid([&] { simulate_corrected(self, model, draw, Stages::all(),
                                          Formula::first_order, self); },
                 "may not be the input");
  Measurement bad = best;
  bad.points_mm(1, 7) = std::nan("");
  std::vector<vcmm::geometry::Point2> xy;
  expect_invalid([&] { simulate_corrected(bad, model, draw, Stages::all(),
                                          Formula::first_order, xy); },
                 "point 7");
  ErrorDraw bad_probe = draw;
  bad_probe.probe.max_order = max_probe_harmonic_order + 1;
  expect_invalid([&] { simulate_corrected(best, model, bad_probe, Stages::all(),
                                          Formula::first_order, xy); },
                 "max_order");
  // Kinematic errors of another model (a different parameter count).
  const DigitalModel other(KinematicModel::zero(KinematicChain::moving_bridge(), kRanges));
  ErrorDraw foreign = draw;
  foreign.kinematic = other.kinematics.nominal();
  EXPECT_THROW(simulate_corrected(best, model, foreign, Stages::all(), Formula::first_order, xy),
               std::invalid_argument);
}

/// simulate_corrected on `prepared` (the one-pass kernel) against the Measurement overload on
/// `best` (three passes), first order: x, y, z and the xy form bit for bit, normals kept.
void expect_prepared_is_bit_for_bit(const DigitalModel& model, const Measurement& best,
                                    const PreparedMeasurement& prepared, const ErrorDraw& draw,
                                    const Stages& stages) {
  Measurement plain, fast;
  simulate_corrected(best, model, draw, stages, Formula::first_order, plain);
  simulate_corrected(prepared, model, draw, stages, Formula::first_order, fast);
  EXPECT_EQ(max_abs_difference(plain.points_mm, fast.points_mm), 0.0);
  EXPECT_EQ(fast.normals, best.normals);
  std::vector<vcmm::geometry::Point2> xy_plain, xy_fast;
  simulate_corrected(best, model, draw, stages, Formula::first_order, xy_plain);
  simulate_corrected(prepared, model, draw, stages, Formula::first_order, xy_fast);
  EXPECT_EQ(xy_plain, xy_fast);
}

TEST(PreparedMeasurement, DrawAndFusedTrialAreBitForBitTheMeasurementOverloads) {
  const DigitalModel model = read_digital_model_file(kExample);
  const Measurement best = best_estimate(model, 720, 61);
  const PreparedMeasurement prepared(best, model);
  EXPECT_EQ(prepared.size(), best.size());
  EXPECT_EQ(prepared.probe_order(), 4);  // the example model's directional orders 2, 3, 4
  std::vector<Stages> cases = {Stages::all(), Stages::none()};
  for (ErrorSource source : all_error_sources) cases.push_back(Stages::only(source));
  for (const Stages& stages : cases) {
    SCOPED_TRACE("stages " + std::to_string(stages.enabled[0]) +
                 std::to_string(stages.enabled[1]) + std::to_string(stages.enabled[2]) +
                 std::to_string(stages.enabled[3]) + std::to_string(stages.enabled[4]));
    SeededRandomSource rng_a(62), rng_b(62);
    ErrorDraw a, b;
    draw_errors(model, best, rng_a, stages, a);
    draw_errors(model, prepared, rng_b, stages, b);
    EXPECT_EQ(a.temperature_c, b.temperature_c);
    EXPECT_EQ(a.expansion_coefficient_per_k, b.expansion_coefficient_per_k);
    EXPECT_EQ(a.kinematic.parameters(), b.kinematic.parameters());
    EXPECT_EQ(a.roughness_mm, b.roughness_mm);
    EXPECT_EQ(a.noise_mm, b.noise_mm);
    expect_prepared_is_bit_for_bit(model, best, prepared, a, stages);
  }
  // The exact formula goes through the composition, as for a Measurement.
  SeededRandomSource rng(63);
  const ErrorDraw draw = draw_errors(model, best, rng);
  Measurement plain, fast;
  simulate_corrected(best, model, draw, Stages::all(), Formula::exact, plain);
  simulate_corrected(prepared, model, draw, Stages::all(), Formula::exact, fast);
  EXPECT_EQ(max_abs_difference(plain.points_mm, fast.points_mm), 0.0);
}

// NoiseComponents::xy: the same draw of every other source, 2N noise numbers (the first 2N
// of the 3N stream, point i's x, y at 2i, 2i + 1), and the x, y form gives exactly what a
// 3-row draw carrying those x, y (any z) gives — z is never read there. Forms that need z
// refuse a 2-row draw with a message naming the function.
TEST(PreparedMeasurement, AnXyNoiseDrawIsTheXyFormsInputBitForBit) {
  const DigitalModel model = read_digital_model_file(kExample);
  const Measurement best = best_estimate(model, 720, 64);
  const PreparedMeasurement prepared(best, model);
  SeededRandomSource rng_xyz(65), rng_xy(65);
  ErrorDraw xyz, xy;
  draw_errors(model, prepared, rng_xyz, Stages::all(), xyz);
  draw_errors(model, prepared, rng_xy, Stages::all(), xy, NoiseComponents::xy);
  EXPECT_EQ(xyz.noise_mm.rows(), 3);
  ASSERT_EQ(xy.noise_mm.rows(), 2);
  ASSERT_EQ(xy.noise_mm.cols(), best.size());
  EXPECT_EQ(xy.temperature_c, xyz.temperature_c);
  EXPECT_EQ(xy.kinematic.parameters(), xyz.kinematic.parameters());
  EXPECT_EQ(xy.roughness_mm, xyz.roughness_mm);
  // The first 2N numbers of the noise call, in the order drawn.
  const Eigen::Map<const Eigen::VectorXd> stream_xy(xy.noise_mm.data(), 2 * best.size());
  const Eigen::Map<const Eigen::VectorXd> stream_xyz(xyz.noise_mm.data(), 2 * best.size());
  EXPECT_EQ(stream_xy, stream_xyz);

  // A 3-row draw holding the same x, y and arbitrary z: the x, y form is bit for bit the same.
  ErrorDraw padded = xy;
  padded.noise_mm.resize(3, best.size());
  padded.noise_mm.topRows<2>() = xy.noise_mm;
  padded.noise_mm.row(2).setConstant(1.0);  // a 1 mm z noise: it must not matter
  for (const Stages& stages : {Stages::all(), Stages::only(ErrorSource::noise)}) {
    std::vector<vcmm::geometry::Point2> from_xy, from_padded, plain;
    simulate_corrected(prepared, model, xy, stages, Formula::first_order, from_xy);
    simulate_corrected(prepared, model, padded, stages, Formula::first_order, from_padded);
    simulate_corrected(best, model, xy, stages, Formula::first_order, plain);
    EXPECT_EQ(from_xy, from_padded);
    EXPECT_EQ(from_xy, plain);
  }

  // Every form that needs z refuses it, naming the function.
  const auto expect_refused = [](const auto& call, const std::string& name) {
    try {
      call();
      ADD_FAILURE() << name << " accepted x, y noise";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(name + ": the draw's noise holds x, y only"),
                std::string::npos)
          << e.what();
    }
  };
  Measurement out;
  std::vector<vcmm::geometry::Point2> out_xy;
  expect_refused([&] { simulate(best, model, xy, Stages::all(), Formula::first_order, out); },
                 "simulate");
  expect_refused([&] {
    simulate_corrected(prepared, model, xy, Stages::all(), Formula::first_order, out);
  }, "simulate_corrected");
  expect_refused([&] {
    simulate_corrected(prepared, model, xy, Stages::all(), Formula::exact, out_xy);
  }, "simulate_corrected");
}

TEST(PreparedMeasurement, DrawsOfAHigherProbeOrderTakeTheMeasurementPath) {
  // Prepared for a model without directional probe terms (no harmonics stored), simulated
  // with the example model's draw (orders 2-4): the same result as the Measurement overload.
  const DigitalModel model = read_digital_model_file(kExample);
  DigitalModel plain_probe = read_digital_model_file(kExample);
  plain_probe.probe.directional.clear();
  const Measurement best = best_estimate(model, 360, 71);
  const PreparedMeasurement prepared(best, plain_probe);
  EXPECT_EQ(prepared.probe_order(), 0);
  SeededRandomSource rng(72);
  const ErrorDraw draw = draw_errors(model, best, rng);
  std::vector<vcmm::geometry::Point2> a, b;
  simulate_corrected(best, model, draw, Stages::all(), Formula::first_order, a);
  simulate_corrected(prepared, model, draw, Stages::all(), Formula::first_order, b);
  EXPECT_EQ(a, b);
}

// The one-pass kernel has an instance per (degree, rotation degree) pair it can shorten: the
// example model's rotations are one degree below its translations; here they are of the same
// degree and of a higher one (the longest padding) — each bit for bit the Measurement overload.
TEST(PreparedMeasurement, AnyRotationDegreeIsBitForBitTheMeasurementOverload) {
  DigitalModel model = read_digital_model_file(kExample);
  for (const int rotation_coefficients : {4, 6}) {
    SCOPED_TRACE(std::to_string(rotation_coefficients) + " rotation coefficients");
    std::array<ErrorFunctionEstimate, axis_error_count> functions;
    for (int f = 0; f < axis_error_count; ++f) {
      const bool rotation = is_rotation(static_cast<AxisError>(f));
      const std::size_t count = rotation ? static_cast<std::size_t>(rotation_coefficients) : 4;
      const double unit = rotation ? 0.2e-6 : 0.1e-3;  // 0.2 µrad, 0.1 µm
      functions[static_cast<std::size_t>(f)].coefficients.assign(count, 0.5 * unit);
      functions[static_cast<std::size_t>(f)].standard_uncertainties.assign(count, unit);
    }
    std::array<EstimatedValue, squareness_count> squareness{};
    squareness[0] = {0.5e-6, 0.3e-6};
    model.kinematics =
        KinematicModel(KinematicChain::moving_bridge(), kRanges, functions, squareness);
    const Measurement best = best_estimate(model, 360, 91);
    const PreparedMeasurement prepared(best, model);
    SeededRandomSource rng(92);
    expect_prepared_is_bit_for_bit(model, best, prepared, draw_errors(model, best, rng),
                                   Stages::all());
  }
}

// The xy kernel has planar forms with the arm masks of the built-in chains as constants
// (every n_z = 0, no z = −0, no stylus component −0): the example's moving bridge, a fixed
// bridge, and the inputs that must take the data-driven form instead — a tilted normal, a z of
// −0, a stylus component of −0 — each bit for bit the Measurement overload (three passes, the
// data-driven kinematic kernel).
TEST(PreparedMeasurement, PlanarAndGeneralKernelFormsAreBitForBitTheMeasurementOverload) {
  const DigitalModel example = read_digital_model_file(kExample);
  DigitalModel fixed = example;  // cubic translations, quadratic rotations, as the example's
  std::array<ErrorFunctionEstimate, axis_error_count> functions;
  for (int f = 0; f < axis_error_count; ++f) {
    const bool rotation = is_rotation(static_cast<AxisError>(f));
    const double unit = rotation ? 0.2e-6 : 0.1e-3;  // 0.2 µrad, 0.1 µm
    auto& e = functions[static_cast<std::size_t>(f)];
    for (int j = 0; j < (rotation ? 3 : 4); ++j) {
      e.coefficients.push_back((0.3 + 0.1 * static_cast<double>(f % 5) - 0.2 * j) * unit);
      e.standard_uncertainties.push_back(unit);
    }
  }
  std::array<EstimatedValue, squareness_count> squareness{};
  squareness[1] = {0.5e-6, 0.3e-6};
  fixed.kinematics =
      KinematicModel(KinematicChain::fixed_bridge(), kRanges, functions, squareness);
  const Measurement best = best_estimate(example, 360, 94);
  Measurement tilted = best;  // one normal out of the plane: not planar
  const double c = std::cos(0.1), s = std::sin(0.1);
  tilted.normals.col(7) = Eigen::Vector3d(c * best.normals(0, 7), c * best.normals(1, 7), s);
  Measurement negative_zero_z = best;
  negative_zero_z.points_mm(2, 11) = -0.0;
  Measurement zero_z = best;  // z = +0 everywhere: planar
  zero_z.points_mm.row(2).setZero();
  Measurement negative_zero_stylus = best;
  negative_zero_stylus.stylus_offset_mm.x() = -0.0;
  const struct {
    const char* name;
    const DigitalModel* model;
    const Measurement* m;
  } cases[] = {{"moving bridge", &example, &best},
               {"fixed bridge", &fixed, &best},
               {"fixed bridge, tilted normal", &fixed, &tilted},
               {"tilted normal", &example, &tilted},
               {"a z of -0", &example, &negative_zero_z},
               {"every z +0", &example, &zero_z},
               {"stylus x of -0", &example, &negative_zero_stylus}};
  for (const auto& t : cases) {
    SCOPED_TRACE(t.name);
    const PreparedMeasurement prepared(*t.m, *t.model);
    SeededRandomSource rng(95);
    expect_prepared_is_bit_for_bit(*t.model, *t.m, prepared,
                                   draw_errors(*t.model, *t.m, rng), Stages::all());
  }
}

TEST(PreparedMeasurementBadInput, AMachinePositionOutOfRangeIsNamed) {
  // The ring centred 40 mm from the end of X's travel: points beyond it need the X axis at
  // up to ~1245 mm of a 0 … 1200 mm range.
  const DigitalModel model = read_digital_model_file(kExample);
  Measurement m = ring(360);
  m.placement.location_mm = {1160.0, 500.0, 250.0};
  const PreparedMeasurement prepared(m, model);
  SeededRandomSource rng(93);
  ErrorDraw draw;
  draw_errors(model, prepared, rng, Stages::all(), draw);
  std::vector<vcmm::geometry::Point2> xy;
  try {
    simulate_corrected(prepared, model, draw, Stages::all(), Formula::first_order, xy);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("simulate_corrected: point "), std::string::npos) << what;
    EXPECT_NE(what.find("needs the X axis"), std::string::npos) << what;
  }
}

TEST(PreparedMeasurementBadInput, ValidatesOnceWithItsName) {
  const DigitalModel model = read_digital_model_file(kExample);
  Measurement bad = best_estimate(model, 64, 81);
  bad.normals(2, 5) = 0.5;  // no longer a unit vector
  try {
    const PreparedMeasurement prepared(bad, model);
    ADD_FAILURE() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("PreparedMeasurement"), std::string::npos) << what;
    EXPECT_NE(what.find("normal 5"), std::string::npos) << what;
  }
  // The draw is still checked on every call.
  const PreparedMeasurement prepared(best_estimate(model, 64, 82), model);
  SeededRandomSource rng(83);
  Stages no_roughness = Stages::all();
  no_roughness.set(ErrorSource::roughness, false);
  ErrorDraw partial;
  draw_errors(model, prepared, rng, no_roughness, partial);
  std::vector<vcmm::geometry::Point2> xy;
  try {
    simulate_corrected(prepared, model, partial, Stages::all(), Formula::first_order, xy);
    ADD_FAILURE() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("simulate_corrected: the draw's roughness"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
