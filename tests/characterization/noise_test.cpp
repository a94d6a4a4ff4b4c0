// Noise and roughness from CMM profiles and a reference (characterization/noise.h): the
// variance the low-pass removes (against the explicit filter matrix), the coverage factor
// (against an independent computation), pure-noise recovery at n = 3600 and 16 touch points,
// honesty over seeds, round trips through the full virtual CMM (phase estimation, repeated
// scans and roughness), the equiangular rule on top of the geometry profile reader, the JSON
// sections in a model file, bad input.
#include "vcmm/characterization/noise.h"

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/errors.h"
#include "vcmm/errormodel/random_source.h"
#include "vcmm/errormodel/ring_gauge.h"
#include "vcmm/errormodel/virtual_cmm.h"
#include "vcmm/geometry/gaussian_filter.h"

namespace {

using namespace vcmm::characterization;
namespace em = vcmm::errormodel;
using vcmm::geometry::Point2;
constexpr double kPi = std::numbers::pi;
constexpr double kUm = 1e-3;  // mm per µm

const std::string kExample = std::string(VCMM_SOURCE_DIR) + "/examples/cmm_model.json";
const std::array<em::AxisRange, 3> kRanges = {{{0.0, 1200.0}, {0.0, 1000.0}, {0.0, 800.0}}};
const Eigen::Vector3d kLocation(600.0, 500.0, 250.0);

em::DigitalModel perfect_machine() {
  return em::DigitalModel(em::KinematicModel::zero(em::KinematicChain::moving_bridge(), kRanges));
}

/// The nominal 171 mm ring (seed-study form unless `form` is false), turned by ψ.
em::Measurement ring(Eigen::Index n, em::ProbingMode mode, double psi, bool form = true) {
  em::RingGauge g;
  if (form) g.form = em::seed_study_ring_form();
  em::RingSampling s;
  s.points = n;
  s.mode = mode;
  s.placement.location_mm = kLocation;
  s.placement.orientation_rad = psi;
  return em::ring_gauge_measurement(g, s);
}

/// The roundness-instrument reference of the ring: its form at M equiangular angles from 0
/// (workpiece angle = reference angle), plus optional white instrument noise.
ReferenceProfile reference(std::size_t m, bool form = true, double noise_mm = 0.0,
                           std::uint64_t seed = 99) {
  ReferenceProfile r;
  em::SeededRandomSource rng(seed);
  for (std::size_t j = 0; j < m; ++j) {
    const double a = 2.0 * kPi * static_cast<double>(j) / static_cast<double>(m);
    double d = 0.0;
    if (form)
      for (const em::FormHarmonic& h : em::seed_study_ring_form())
        d += h.amplitude_mm * std::cos(h.order * a + h.phase_rad);
    r.angle_rad.push_back(a);
    r.deviation_mm.push_back(d + noise_mm * rng.standard_normal());
  }
  return r;
}

/// Machine XY of a measurement.
std::vector<Point2> xy(const em::Measurement& m) {
  const Eigen::Matrix3Xd p = em::machine_coordinates(m);
  std::vector<Point2> out(static_cast<std::size_t>(p.cols()));
  for (Eigen::Index i = 0; i < p.cols(); ++i) out[static_cast<std::size_t>(i)] = {p(0, i), p(1, i)};
  return out;
}

/// One simulated measurement of `nominal` with `model` and `stages`, seeded.
em::Measurement simulate(const em::Measurement& nominal, const em::DigitalModel& model,
                         em::Stages stages, std::uint64_t seed) {
  em::SeededRandomSource rng(seed);
  const em::ErrorDraw draw = em::draw_errors(model, nominal, rng, stages);
  return em::simulate(nominal, model, draw, stages);
}

em::Stages only(std::initializer_list<em::ErrorSource> sources) {
  em::Stages s = em::Stages::none();
  for (em::ErrorSource x : sources) s.set(x, true);
  return s;
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

// ---- the variance correction ----

TEST(NoiseFactor, MatchesTheExplicitFilterMatrix) {
  // M = (I − L)(I − P), L the Gaussian filter (applied to unit vectors), P the projection on
  // harmonics 0 and 1 (orthonormal on the grid). Λ = trace(MᵀM) = ‖M‖_F², Σλ² = ‖MᵀM‖_F².
  for (const auto& [n, cutoff] :
       {std::pair<std::size_t, double>{64, 5.0}, {63, 7.5}, {100, 50.0}}) {
    Eigen::MatrixXd p(n, 3);
    for (std::size_t i = 0; i < n; ++i) {
      const double t = 2.0 * kPi * static_cast<double>(i) / static_cast<double>(n);
      p.row(static_cast<Eigen::Index>(i)) << 1.0, std::cos(t), std::sin(t);
    }
    const Eigen::MatrixXd q = p.householderQr().householderQ() * Eigen::MatrixXd::Identity(n, 3);
    const Eigen::MatrixXd proj = Eigen::MatrixXd::Identity(n, n) - q * q.transpose();
    Eigen::MatrixXd m(n, n);
    for (std::size_t j = 0; j < n; ++j) {
      const Eigen::VectorXd col = proj.col(static_cast<Eigen::Index>(j));
      const std::vector<double> d(col.data(), col.data() + n);
      const std::vector<double> low = vcmm::geometry::gaussian_filter_closed(d, cutoff);
      for (std::size_t i = 0; i < n; ++i)
        m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = d[i] - low[i];
    }
    const double lambda = m.squaredNorm();
    const double lambda2 = (m.transpose() * m).squaredNorm();
    const HighPassNoiseFactor f = high_pass_noise_factor(n, cutoff);
    EXPECT_NEAR(f.variance_factor, lambda / static_cast<double>(n), 1e-12) << n;
    EXPECT_NEAR(f.degrees_of_freedom, lambda * lambda / lambda2, 1e-9 * f.degrees_of_freedom) << n;
    // The low-pass part L P: per-point white-noise variance (1/n) Σ H².
    EXPECT_NEAR(f.low_pass_variance_factor, (proj - m).squaredNorm() / static_cast<double>(n),
                1e-12)
        << n;
  }
  // Hand case: a cut-off far below harmonic 2 removes nothing above harmonic 1: λ = 1 for the
  // n − 3 remaining functions.
  const HighPassNoiseFactor none = high_pass_noise_factor(3600, 1e-3);
  EXPECT_NEAR(none.variance_factor, 3597.0 / 3600.0, 1e-15);
  EXPECT_NEAR(none.degrees_of_freedom, 3597.0, 1e-9);
  const HighPassNoiseFactor f50 = high_pass_noise_factor(3600, 50.0);
  const HighPassNoiseFactor f500 = high_pass_noise_factor(3600, 500.0);
  std::cout << "[factor] n = 3600: f_c = 50: " << f50.variance_factor << " (nu "
            << f50.degrees_of_freedom << "), f_c = 500: " << f500.variance_factor << " (nu "
            << f500.degrees_of_freedom << ")\n";
  expect_invalid([] { (void)high_pass_noise_factor(7, 2.0); }, "n >= 8");
  expect_invalid([] { (void)high_pass_noise_factor(100, 51.0); }, "cut-off");
  expect_invalid([] { (void)high_pass_noise_factor(100, std::nan("")); }, "cut-off");
}

TEST(NoiseFactor, CoverageFactorAgainstIndependentValues) {
  // Reference values: bisection on the χ² CDF in double precision, written independently in
  // Python (series / continued fraction of the incomplete gamma function), to 1e-9.
  EXPECT_NEAR(sigma_coverage_factor(1.0), 11.685867764, 1e-7);
  EXPECT_NEAR(sigma_coverage_factor(2.0), 3.634006257, 1e-7);
  EXPECT_NEAR(sigma_coverage_factor(13.0), 1.281137725, 1e-7);
  EXPECT_NEAR(sigma_coverage_factor(100.0), 1.026806680, 1e-7);
  EXPECT_NEAR(sigma_coverage_factor(3500.0), 1.000715699, 1e-7);
  expect_invalid([] { (void)sigma_coverage_factor(0.5); }, ">= 1");
}

// ---- pure noise: scanning n = 3600 and 16 touch points ----

TEST(ScanningNoise, PureNoiseHonestOverSeeds) {
  // A perfect circle, isotropic 3D noise σ = 0.5 µm, zero reference, f_c = 500 UPR (which
  // removes ~40 % of the white variance, so an uncorrected estimate would be ~20 % low).
  // Per seed σ̂/σ has sd 1/√(2ν) ≈ 0.017 (ν ≈ 1800): over 200 seeds the mean has sd 0.0012,
  // tolerance 0.005 (4 sd); the fraction with |σ̂ − σ| ≤ 2u is 0.9545 ± 3.5·0.0147.
  const double sigma = 0.5 * kUm;
  em::DigitalModel model = perfect_machine();
  model.noise.scanning_sigma_mm = sigma;
  const em::Measurement nominal = ring(3600, em::ProbingMode::scanning, 0.0, false);
  const ReferenceProfile zero = reference(360, false);
  ScanNoiseOptions opt;
  opt.cutoff_upr = 500.0;
  opt.phase_rad = 0.0;
  constexpr int kSeeds = 200;
  double sum_ratio = 0.0;
  int within = 0;
  for (int seed = 0; seed < kSeeds; ++seed) {
    const em::Measurement m =
        simulate(nominal, model, only({em::ErrorSource::noise}), static_cast<std::uint64_t>(seed));
    const ScanNoiseResult r = scanning_noise(xy(m), zero, opt);
    sum_ratio += r.sigma.sigma_mm / sigma;
    within += std::abs(r.sigma.sigma_mm - sigma) <= 2.0 * r.sigma.u_mm;
    if (seed == 0) {
      EXPECT_EQ(r.points, 3600u);
      EXPECT_LT(r.factor.variance_factor, 0.7);
      EXPECT_NEAR(r.high_pass_rms_mm / r.sigma.sigma_mm, std::sqrt(r.factor.variance_factor),
                  1e-12);
    }
  }
  std::cout << "[scan 3600, f_c 500] mean sigma/sigma_true = " << sum_ratio / kSeeds
            << ", within 2u: " << within << "/" << kSeeds << "\n";
  EXPECT_NEAR(sum_ratio / kSeeds, 1.0, 0.005);
  EXPECT_NEAR(static_cast<double>(within) / kSeeds, 0.9545, 0.052);
}

TEST(ScanningNoise, PureNoiseAtFiftyUpr) {
  // The usual cut-off: one seed, σ̂ within 3u (u/σ ≈ 1.2 %).
  const double sigma = 0.7 * kUm;
  em::DigitalModel model = perfect_machine();
  model.noise.scanning_sigma_mm = sigma;
  const em::Measurement m = simulate(ring(3600, em::ProbingMode::scanning, 0.0, false), model,
                                     only({em::ErrorSource::noise}), 11);
  ScanNoiseOptions opt;
  opt.phase_rad = 0.0;
  const ScanNoiseResult r = scanning_noise(xy(m), reference(360, false), opt);
  EXPECT_NEAR(r.sigma.sigma_mm, sigma, 3.0 * r.sigma.u_mm);
  EXPECT_NEAR(r.sigma.u_mm / r.sigma.sigma_mm,
              sigma_coverage_factor(r.factor.degrees_of_freedom) /
                  std::sqrt(2.0 * r.factor.degrees_of_freedom),
              1e-15);
  EXPECT_GT(r.factor.degrees_of_freedom, 3400.0);
}

TEST(TouchNoise, SixteenPointsHonestOverSeeds) {
  // The ring with its form (rms ≈ 40 nm) and touch noise σ = 50 nm: without the reference the
  // form would dominate. ν = 13; per seed σ̂²/σ² ~ χ²_13/13 (sd 0.39): the mean over 400 seeds
  // has sd 0.020, tolerance 0.08 (4 sd); the fraction within 2u is 0.9545 ± 3.5·0.0104.
  const double sigma = 0.05 * kUm;
  em::DigitalModel model = perfect_machine();
  model.noise.touch_trigger_sigma_mm = sigma;
  const double psi = 0.4;  // the ring turned: the phase of the reference is ψ
  const em::Measurement nominal = ring(16, em::ProbingMode::touch_trigger, psi);
  const ReferenceProfile ref = reference(720);
  constexpr int kSeeds = 400;
  double sum_var = 0.0;
  int within = 0;
  for (int seed = 0; seed < kSeeds; ++seed) {
    const em::Measurement m =
        simulate(nominal, model, only({em::ErrorSource::noise}), static_cast<std::uint64_t>(seed));
    const TouchNoiseResult r = touch_trigger_noise(xy(m), ref, psi);
    ASSERT_EQ(r.sigma.degrees_of_freedom, 13.0);
    sum_var += (r.sigma.sigma_mm / sigma) * (r.sigma.sigma_mm / sigma);
    within += std::abs(r.sigma.sigma_mm - sigma) <= 2.0 * r.sigma.u_mm;
  }
  std::cout << "[touch 16] mean sigma^2/sigma_true^2 = " << sum_var / kSeeds
            << ", within 2u: " << within << "/" << kSeeds << "\n";
  EXPECT_NEAR(sum_var / kSeeds, 1.0, 0.08);
  EXPECT_NEAR(static_cast<double>(within) / kSeeds, 0.9545, 0.037);
  // Without the form subtracted (zero reference) the estimate is far too large.
  const em::Measurement m = simulate(nominal, model, only({em::ErrorSource::noise}), 1);
  EXPECT_GT(touch_trigger_noise(xy(m), reference(720, false), psi).sigma.sigma_mm, 1.5 * sigma);
}

// ---- round trips through the full virtual CMM ----

TEST(ScanningNoise, RoundTripExampleModel) {
  // The example model with every source (kinematic, probe lobing, temperature, roughness
  // 0.05 µm, scanning noise 0.7 µm); the ring turned 37°. One scan estimates
  // σ_total = √(σ_n² + σ_r²) (one scan cannot separate them); the systematic errors are
  // low-order and stay in the low-pass part. The seed-study form has no harmonic above 17
  // UPR: at f_c = 50 the phase cannot be estimated (and does not matter for the scan).
  const em::DigitalModel model = em::read_digital_model_file(kExample);
  const double psi = 37.0 * kPi / 180.0;
  const em::Measurement m =
      simulate(ring(3600, em::ProbingMode::scanning, psi), model, em::Stages::all(), 21);
  const ScanNoiseResult r = scanning_noise(xy(m), reference(3600));
  EXPECT_TRUE(r.phase_estimated);
  EXPECT_FALSE(r.phase_determined);
  EXPECT_LT(r.phase_snr, 1.0);
  const double total = std::hypot(model.noise.scanning_sigma_mm, model.roughness.sigma_mm);
  EXPECT_NEAR(r.sigma.sigma_mm, total, 3.0 * r.sigma.u_mm);
  EXPECT_GT(r.low_pass_rms_mm, 0.05 * kUm);  // the CMM's systematic errors were there
  // Given the true phase the estimate is the same to a small fraction of u.
  ScanNoiseOptions given;
  given.phase_rad = psi;
  EXPECT_NEAR(scanning_noise(xy(m), reference(3600), given).sigma.sigma_mm, r.sigma.sigma_mm,
              0.1 * r.sigma.u_mm);
}

TEST(TouchNoise, ScanSystematicsRemovedHonestOverSeeds) {
  // The example model, every source, ring turned 37°. Per seed one realisation of the
  // systematic sources serves a 1440-point scan and 16 touch points (the same machine state);
  // the touch σ is evaluated (a) with the scan's phase and systematic profile, (b) alone with
  // the true phase. Truth: √(σ_t² + σ_r²) = √(0.45² + 0.05²) µm. Over 100 seeds:
  //  (a) fraction within 2u 0.9545 ± 3.5·√(0.9545·0.0455/100) = ± 0.073, mean σ̂²/σ² = 1 ± 0.16
  //      (sd √(2/13)/√100 = 0.039; 4 sd);
  //  (b) the systematic errors the example model draws (probe lobing u 0.15 µm per
  //      coefficient, kinematics) stay in: mean σ̂²/σ² clearly above 1 (> 1.2).
  const em::DigitalModel model = em::read_digital_model_file(kExample);
  const double psi = 37.0 * kPi / 180.0;
  const em::Measurement scan_nominal = ring(1440, em::ProbingMode::scanning, psi);
  const em::Measurement touch_nominal = ring(16, em::ProbingMode::touch_trigger, psi);
  const ReferenceProfile ref = reference(720);
  const double truth = std::hypot(model.noise.touch_trigger_sigma_mm, model.roughness.sigma_mm);
  constexpr int kSeeds = 100;
  int within = 0;
  double sum_var = 0.0, sum_var_alone = 0.0;
  for (int seed = 0; seed < kSeeds; ++seed) {
    em::SeededRandomSource rng_scan(3000 + static_cast<std::uint64_t>(seed));
    em::SeededRandomSource rng_touch(5000 + static_cast<std::uint64_t>(seed));
    const em::ErrorDraw ds = em::draw_errors(model, scan_nominal, rng_scan);
    em::ErrorDraw dt = em::draw_errors(model, touch_nominal, rng_touch);
    dt.temperature_c = ds.temperature_c;
    dt.expansion_coefficient_per_k = ds.expansion_coefficient_per_k;
    dt.kinematic = ds.kinematic;
    dt.probe = ds.probe;
    const em::Measurement s = em::simulate(scan_nominal, model, ds);
    const em::Measurement t = em::simulate(touch_nominal, model, dt);
    const ScanNoiseResult sr = scanning_noise(xy(s), ref);
    const TouchNoiseResult a = touch_trigger_noise(xy(t), ref, sr.phase_rad, &sr.systematic);
    const TouchNoiseResult b = touch_trigger_noise(xy(t), ref, psi);
    EXPECT_TRUE(a.scan_systematics_removed);
    EXPECT_GT(a.scan_noise_variance_mm2, 0.0);
    within += std::abs(a.sigma.sigma_mm - truth) <= 2.0 * a.sigma.u_mm;
    sum_var += (a.sigma.sigma_mm / truth) * (a.sigma.sigma_mm / truth);
    sum_var_alone += (b.sigma.sigma_mm / truth) * (b.sigma.sigma_mm / truth);
  }
  std::cout << "[touch + scan systematics] within 2u " << within << "/" << kSeeds
            << ", mean sigma^2/truth^2 " << sum_var / kSeeds << " (touch alone "
            << sum_var_alone / kSeeds << ")\n";
  EXPECT_NEAR(within / double(kSeeds), 0.9545, 0.073);
  EXPECT_NEAR(sum_var / kSeeds, 1.0, 0.16);
  EXPECT_GT(sum_var_alone / kSeeds, 1.2);
}

TEST(TouchNoise, SystematicProfileChecks) {
  const std::vector<Point2> touch = xy(ring(16, em::ProbingMode::touch_trigger, 0.0));
  SystematicProfile s;
  for (int i = 0; i < 8; ++i) {
    s.angle_rad.push_back(-kPi + i * kPi / 4.0);
    s.deviation_mm.push_back(0.0);
  }
  EXPECT_NO_THROW((void)touch_trigger_noise(touch, reference(360), 0.0, &s));
  SystematicProfile few = s;
  few.angle_rad.pop_back();
  expect_invalid([&] { (void)touch_trigger_noise(touch, reference(360), 0.0, &few); }, ">= 8");
  SystematicProfile unsorted = s;
  std::swap(unsorted.angle_rad[2], unsorted.angle_rad[3]);
  expect_invalid([&] { (void)touch_trigger_noise(touch, reference(360), 0.0, &unsorted); },
                 "increase");
  SystematicProfile negative = s;
  negative.noise_variance_mm2 = -1.0;
  expect_invalid([&] { (void)touch_trigger_noise(touch, reference(360), 0.0, &negative); },
                 "variance");
  // A constant profile shifts the radius only: σ̂ unchanged.
  SystematicProfile constant = s;
  for (double& d : constant.deviation_mm) d = 1e-3;
  EXPECT_NEAR(touch_trigger_noise(touch, reference(360), 0.0, &constant).sigma.sigma_mm,
              touch_trigger_noise(touch, reference(360), 0.0).sigma.sigma_mm, 1e-12);
}

TEST(ScanningNoise, PhaseEstimatedFromFormAboveTheCutoff) {
  // A ring with chatter marks at 60, 97 and 150 UPR (100, 80, 60 nm) on top of the seed form,
  // scanned with 0.2 µm noise, turned 123°. E ≈ n Σ a²/2 ≈ 36 µm², so the phase SNR √E/σ ≈ 25
  // (weights (1 − H)² < 1 lower it a little). The phase comes back to
  // sd ≈ σ/√(Σ_k k² n a_k²/2) ≈ 0.2 µm / 565 µm ≈ 3.5e-4 rad = 0.02° (allowed 0.1°, 5 sd) and σ̂
  // is right — while a zero reference leaves ≈ 0.0067 µm² of chatter variance in the
  // high-pass part: σ̂ ≈ 0.216 µm, ~6.7 u too large (checked > 5 u).
  em::RingGauge g;
  g.form = em::seed_study_ring_form();
  g.form.push_back({60, 0.100 * kUm, 0.4});
  g.form.push_back({97, 0.080 * kUm, 2.2});
  g.form.push_back({150, 0.060 * kUm, 5.0});
  em::RingSampling s;
  s.points = 3600;
  s.placement.location_mm = kLocation;
  const double psi = 123.0 * kPi / 180.0;
  s.placement.orientation_rad = psi;
  em::DigitalModel model = perfect_machine();
  model.noise.scanning_sigma_mm = 0.2 * kUm;
  const em::Measurement m =
      simulate(em::ring_gauge_measurement(g, s), model, only({em::ErrorSource::noise}), 31);
  ReferenceProfile ref;
  for (int j = 0; j < 2000; ++j) {
    const double a = 2.0 * kPi * j / 2000.0;
    double d = 0.0;
    for (const em::FormHarmonic& h : g.form)
      d += h.amplitude_mm * std::cos(h.order * a + h.phase_rad);
    ref.angle_rad.push_back(a);
    ref.deviation_mm.push_back(d);
  }
  const ScanNoiseResult r = scanning_noise(xy(m), ref);
  EXPECT_TRUE(r.phase_determined);
  EXPECT_GT(r.phase_snr, 20.0);
  EXPECT_NEAR(r.phase_rad, psi, 0.1 * kPi / 180.0);
  EXPECT_NEAR(r.sigma.sigma_mm, 0.2 * kUm, 3.0 * r.sigma.u_mm);
  ScanNoiseOptions o;
  o.phase_rad = 0.0;
  const ScanNoiseResult wrong = scanning_noise(xy(m), reference(360, false), o);
  EXPECT_GT(wrong.sigma.sigma_mm, r.sigma.sigma_mm + 5.0 * r.sigma.u_mm);
}

/// Two scans of the same track: the same draw of every source except the noise.
std::pair<em::Measurement, em::Measurement> repeated_scans(const em::DigitalModel& model,
                                                           double psi, std::uint64_t seed) {
  const em::Measurement nominal = ring(3600, em::ProbingMode::scanning, psi);
  em::SeededRandomSource rng1(seed), rng2(seed + 1000003);
  const em::ErrorDraw d1 = em::draw_errors(model, nominal, rng1);
  em::ErrorDraw d2 = d1;
  d2.noise_mm = em::draw_errors(model, nominal, rng2).noise_mm;
  return {em::simulate(nominal, model, d1), em::simulate(nominal, model, d2)};
}

TEST(RepeatedScans, SeparateNoiseAndRoughnessHonestly) {
  // σ_n = 0.3 µm, σ_r = 0.25 µm (identifiable: u(σ̂_r²) ≈ 4e-3 µm² ≪ σ_r² = 0.0625 µm²),
  // reference with 2 nm instrument noise, f_c = 50, phase given. 100 seeds: the fraction of
  // |error| ≤ 2u per quantity is 0.95 ± 3.5·√(0.95·0.05/100) = ± 0.076.
  em::DigitalModel model = em::read_digital_model_file(kExample);
  model.noise.scanning_sigma_mm = 0.3 * kUm;
  model.roughness.sigma_mm = 0.25 * kUm;
  const ReferenceProfile ref = reference(720, true, 0.002 * kUm);
  ScanNoiseOptions opt;
  opt.phase_rad = 0.2;
  constexpr int kSeeds = 100;
  int within_noise = 0, within_rough = 0, within_single = 0;
  for (int seed = 0; seed < kSeeds; ++seed) {
    const auto [a, b] = repeated_scans(model, 0.2, 500 + static_cast<std::uint64_t>(seed));
    const RepeatedScanResult r = repeated_scan_noise(xy(a), xy(b), ref, opt);
    ASSERT_EQ(r.roughness_status, RoughnessStatus::identified) << seed;
    within_noise += std::abs(r.noise.sigma_mm - 0.3 * kUm) <= 2.0 * r.noise.u_mm;
    within_rough += std::abs(r.roughness.sigma_mm - 0.25 * kUm) <= 2.0 * r.roughness.u_mm;
    within_single +=
        std::abs(r.first.sigma.sigma_mm - std::hypot(0.3, 0.25) * kUm) <= 2.0 * r.first.sigma.u_mm;
  }
  std::cout << "[repeat] within 2u: noise " << within_noise << ", roughness " << within_rough
            << ", single-scan total " << within_single << " of " << kSeeds << "\n";
  EXPECT_NEAR(within_noise / double(kSeeds), 0.95, 0.076);
  EXPECT_NEAR(within_rough / double(kSeeds), 0.95, 0.076);
  EXPECT_NEAR(within_single / double(kSeeds), 0.95, 0.076);
}

TEST(RepeatedScans, NoRoughnessIsNotSignificant) {
  em::DigitalModel model = perfect_machine();
  model.noise.scanning_sigma_mm = 0.5 * kUm;
  const auto [a, b] = repeated_scans(model, 0.0, 7);
  ScanNoiseOptions opt;
  opt.phase_rad = 0.0;
  const RepeatedScanResult r = repeated_scan_noise(xy(a), xy(b), reference(360), opt);
  EXPECT_EQ(r.roughness_status, RoughnessStatus::not_significant);
  EXPECT_GT(r.roughness_upper_bound_mm, r.roughness.sigma_mm);
  EXPECT_LT(r.roughness_upper_bound_mm, 0.15 * kUm);
  EXPECT_NEAR(r.noise.sigma_mm, 0.5 * kUm, 3.0 * r.noise.u_mm);
}

// ---- the reference profile ----

TEST(ReferenceProfile, ReaderAndInterpolation) {
  std::ostringstream csv;
  csv.precision(17);
  csv << "# roundness instrument\nangle_deg,deviation_um\n";
  const ReferenceProfile ref = reference(72);
  for (std::size_t j = 0; j < 72; ++j)
    csv << ref.angle_rad[j] * 180.0 / kPi << "," << ref.deviation_mm[j] / kUm << "\n";
  csv << "360," << ref.deviation_mm[0] / kUm << "\n";  // a closed trace: dropped
  std::istringstream in(csv.str());
  const ReferenceProfile r = read_reference_profile_csv(in, "ref.csv");
  ASSERT_EQ(r.angle_rad.size(), 72u);
  // Band-limited (harmonics ≤ 17 < 36): the interpolant is the form itself at any angle.
  std::vector<double> angles;
  for (int i = 0; i < 50; ++i) angles.push_back(0.1234 + 0.377 * i);
  const std::vector<double> g = reference_deviation_mm(r, angles);
  for (std::size_t i = 0; i < angles.size(); ++i) {
    double truth = 0.0;
    for (const em::FormHarmonic& h : em::seed_study_ring_form())
      truth += h.amplitude_mm * std::cos(h.order * angles[i] + h.phase_rad);
    EXPECT_NEAR(g[i], truth, 1e-14);
  }
  // Harmonics capped: up to 5 only drops the 7th, 11th and 17th.
  const std::vector<double> g5 = reference_deviation_mm(r, angles, 5);
  EXPECT_GT(std::abs(g5[3] - g[3]), 1e-7);
}

// The file rules (header, units, separators, the 360° repeat, line numbers, closedness) are
// geometry::read_roundness_profile_csv's, tested in tests/geometry/roundness_profile_test.cpp;
// here the noise code's own rule on top: equiangular.
TEST(ReferenceProfile, EquiangularOnTopOfTheProfileRules) {
  auto read = [](const std::string& text) {
    std::istringstream in(text);
    return read_reference_profile_csv(in, "ref.csv");
  };
  auto message = [](auto&& f) -> std::string {
    try {
      f();
    } catch (const em::InvalidInput& e) {
      return e.what();
    }
    return "(no exception)";
  };
  std::string eight;
  for (int j = 0; j < 8; ++j) eight += std::to_string(45 * j) + ",0.1\n";
  const ReferenceProfile r = read("angle_deg,deviation_um\n" + eight);
  EXPECT_EQ(r.angle_rad.size(), 8u);
  EXPECT_EQ(r.source, "ref.csv");
  EXPECT_EQ(r.line.front(), 2u);
  // Any start angle within the first step: 2.5°, 47.5°, …, 317.5°.
  std::string shifted;
  for (int j = 0; j < 8; ++j) shifted += std::to_string(2.5 + 45 * j) + ",0\n";
  EXPECT_NEAR(read(shifted).angle_rad.front(), 2.5 * kPi / 180.0, 1e-15);
  // Closed but uneven: geometry accepts it, the noise code does not, naming the file line.
  std::string uneven = eight;
  uneven.replace(uneven.find("90,"), 3, "91,");
  std::istringstream in(uneven);
  EXPECT_NO_THROW((void)vcmm::geometry::read_roundness_profile_csv(in, "ref.csv"));
  EXPECT_EQ(message([&] { (void)read(uneven); }),
            "ref.csv:3: the reference must be equiangular over one turn (8 samples, step 45 deg); "
            "angle 91 deg, expected 90 deg");
  // Within 1e-3 of a step (0.045° at 45°) is equiangular; 0.05° off is not.
  std::string near = eight;
  near.replace(near.find("90,"), 3, "90.04,");
  EXPECT_NO_THROW((void)read(near));
  near = eight;
  near.replace(near.find("90,"), 3, "90.05,");
  EXPECT_NE(message([&] { (void)read(near); }).find("ref.csv:3: the reference must be equiangular"),
            std::string::npos);
  // Profiles built in code: the caller and "reference" head every message, the geometry rules
  // included.
  ReferenceProfile bad = reference(16);
  EXPECT_NO_THROW(validate_reference_profile(bad, "f"));
  bad.angle_rad[3] += 0.01;
  EXPECT_EQ(message([&] { validate_reference_profile(bad, "f"); }),
            "f: reference: sample 3: the reference must be equiangular over one turn (16 samples, "
            "step 22.5 deg); angle 68.072958 deg, expected 67.5 deg");
  bad = reference(16);
  bad.deviation_mm.pop_back();
  EXPECT_EQ(message([&] { validate_reference_profile(bad, "f"); }),
            "f: reference: angle_rad and deviation_mm differ in size (16 vs 15)");
  bad = reference(16);
  bad.angle_rad[15] = 2.0 * kPi + 0.1;
  EXPECT_EQ(message([&] { validate_reference_profile(bad, "f"); }),
            "f: reference: sample 15: angle must lie in [0, 360) degrees; got 365.729577951 deg");
  // Every noise entry point checks its reference.
  expect_invalid([&] { (void)reference_deviation_mm(bad, std::vector<double>{0.0}); },
                 "reference_deviation_mm: reference: sample 15");
  // A file that is not a reference at all (a points file, three columns).
  expect_invalid([&] { (void)read("x_mm,y_mm,z_mm\n1,2,3\n"); },
                 "ref.csv:1: header must be 'angle_deg,deviation_um'");
}

// ---- the model sections ----

TEST(NoiseSections, LoadIntoTheDigitalModel) {
  em::DigitalModel truth = em::read_digital_model_file(kExample);
  truth.roughness.sigma_mm = 0.2 * kUm;
  const auto [a, b] = repeated_scans(truth, 0.0, 3);
  const em::Measurement t =
      simulate(ring(16, em::ProbingMode::touch_trigger, 0.0), truth, em::Stages::all(), 4);
  const ReferenceProfile ref = reference(360);
  NoiseCharacterization c;
  c.repeated = repeated_scan_noise(xy(a), xy(b), ref);
  c.touch = touch_trigger_noise(xy(t), ref, c.repeated->first.phase_rad);
  c.scan_source = "a.csv";
  c.repeat_source = "b.csv";
  c.touch_source = "t.csv";
  c.reference_source = "ref.csv";
  const nlohmann::json out = nlohmann::json::parse(noise_characterization_json(c));
  std::ifstream f(kExample);
  nlohmann::json model = nlohmann::json::parse(f);
  model["noise"] = out["noise"];
  model["roughness"] = out["roughness"];
  const em::DigitalModel loaded = em::parse_digital_model(model.dump(), "merged");
  EXPECT_NEAR(loaded.noise.scanning_sigma_mm, c.repeated->noise.sigma_mm, 1e-15);
  EXPECT_NEAR(loaded.noise.touch_trigger_sigma_mm, c.touch->sigma.sigma_mm, 1e-15);
  EXPECT_NEAR(loaded.roughness.sigma_mm, c.repeated->roughness.sigma_mm, 1e-15);
  EXPECT_NE(out["noise"]["source"].get<std::string>().find("a.csv"), std::string::npos);
  EXPECT_EQ(out["characterization"]["repeat"]["roughness_status"],
            std::string(to_string(c.repeated->roughness_status)));

  // A single scan: no roughness section, the diagnostics say why; without touch data and
  // without a fallback the section is incomplete and says so (and does not load alone) …
  NoiseCharacterization single;
  single.scan = c.repeated->first;
  single.scan_source = "a.csv";
  const nlohmann::json s = nlohmann::json::parse(noise_characterization_json(single));
  EXPECT_FALSE(s.contains("roughness"));
  EXPECT_NE(s["characterization"]["roughness"].get<std::string>().find("not identifiable"),
            std::string::npos);
  EXPECT_FALSE(s["noise"].contains("touch_trigger_sigma_um"));
  EXPECT_NE(s["noise"]["comment"].get<std::string>().find("touch_trigger_sigma_um"),
            std::string::npos);
  model["noise"] = s["noise"];
  try {
    (void)em::parse_digital_model(model.dump(), "merged");
    ADD_FAILURE() << "an incomplete noise section must not load";
  } catch (const em::InvalidParameter& e) {
    EXPECT_EQ(e.key_path(), "noise.touch_trigger_sigma_um");
  }
  // … and with the current model's value as fallback it is complete.
  model["noise"] = nlohmann::json::parse(noise_section_json(single, std::nullopt, 0.45 * kUm));
  EXPECT_NEAR(em::parse_digital_model(model.dump(), "merged").noise.touch_trigger_sigma_mm,
              0.45 * kUm, 1e-15);
  EXPECT_FALSE(roughness_section_json(single).has_value());
  expect_invalid([] { (void)noise_section_json(NoiseCharacterization{}); }, "no scan");
}

// ---- bad input ----

TEST(NoiseBadInput, ScansTouchAndRepeats) {
  const ReferenceProfile ref = reference(360);
  std::vector<Point2> scan = xy(ring(3600, em::ProbingMode::scanning, 0.0));
  ScanNoiseOptions opt;
  opt.phase_rad = 0.0;
  // Too few points.
  expect_invalid([&] { (void)scanning_noise(std::span(scan).first(15), ref, opt); }, "16");
  // NaN.
  std::vector<Point2> nan = scan;
  nan[100].y = std::nan("");
  expect_invalid([&] { (void)scanning_noise(nan, ref, opt); }, "100");
  // Cut-off above n/2.
  ScanNoiseOptions high = opt;
  high.cutoff_upr = 2000.0;
  expect_invalid([&] { (void)scanning_noise(scan, ref, high); }, "cut-off");
  ScanNoiseOptions nan_phase = opt;
  nan_phase.phase_rad = std::nan("");
  expect_invalid([&] { (void)scanning_noise(scan, ref, nan_phase); }, "phase");
  // Not equiangular: every other point moved by a third of a step.
  std::vector<Point2> uneven = scan;
  for (std::size_t i = 1; i < uneven.size(); i += 2) {
    const double t = 2.0 * kPi * (static_cast<double>(i) + 0.33) / 3600.0;
    uneven[i] = {kLocation.x() + 85.5 * std::cos(t), kLocation.y() + 85.5 * std::sin(t)};
  }
  expect_invalid([&] { (void)scanning_noise(uneven, ref, opt); }, "equiangular");
  // Repeats that do not match: other size, other start.
  std::vector<Point2> other = xy(ring(3000, em::ProbingMode::scanning, 0.0));
  expect_invalid([&] { (void)repeated_scan_noise(scan, other, ref, opt); }, "same points");
  std::vector<Point2> shifted = xy(ring(3600, em::ProbingMode::scanning, 0.01));
  expect_invalid([&] { (void)repeated_scan_noise(scan, shifted, ref, opt); }, "same angles");
  // Touch: too few, phase.
  const std::vector<Point2> touch = xy(ring(16, em::ProbingMode::touch_trigger, 0.0));
  expect_invalid([&] { (void)touch_trigger_noise(std::span(touch).first(4), ref, 0.0); }, "5");
  expect_invalid([&] { (void)touch_trigger_noise(touch, ref, INFINITY); }, "phase");
  // A closed scan repeating its first point is accepted (the repeat is dropped).
  std::vector<Point2> closed = scan;
  closed.push_back(scan.front());
  EXPECT_EQ(scanning_noise(closed, ref, opt).points, 3600u);
}

}  // namespace
