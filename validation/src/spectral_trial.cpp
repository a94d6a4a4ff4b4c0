// validation/src/spectral_trial.cpp — the spectral Monte Carlo trial of a ring measurement
// (notation, derivation and what it neglects: the header and docs/validation.md, "The spectral
// trial").
#include "vcmm/validation/spectral_trial.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>

#include "internal/spectral_kernels.h"
#include "internal/stream_random_source.h"
#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/maximum_inscribed_from_extremes.h"
#include "vcmm/geometry/minimum_zone_from_extremes.h"

namespace vcmm::validation {
namespace {

namespace em = vcmm::errormodel;
using internal::StreamRandomSource;

constexpr double kPi = std::numbers::pi;

/// Harmonics are drawn up to the order where what is left above it stays below this at every
/// point, at 5 standard deviations of every parameter: 1 pm, a thousandth of the smallest
/// uncertainty a CMM reports (1 nm), so the truncation never shows in any statistic.
constexpr double kTruncationToleranceMm = 1e-9;
/// Quantities are bounded at this many standard deviations (a per-trial bound that holds but
/// for a ~6e-7 fraction of the draws of any one Gaussian quantity).
constexpr double kSigmas = 5.0;
/// Normals may deviate from radial by this much in (n·u)² before the white radial variance
/// differs between points (then the harmonics are no longer independent): 1e-3 changes the
/// white harmonics' variance by at most 0.1 %, far below what 10⁶ trials resolve (0.14 % on u).
constexpr double kRadialNormalTolerance = 1e-3;

double transmission(std::size_t k, double cutoff_upr) {
  const double r = static_cast<double>(k) / cutoff_upr;
  return std::exp2(-r * r);
}

double wrap_angle(double a) {  // to (−π, π]
  a = std::remainder(a, 2 * kPi);
  return a;
}

/// The estimate's geometry: LS circle and directions, and the grid check.
struct EstimateGeometry {
  std::vector<geometry::Point2> profile;
  geometry::LeastSquaresCircle ls;
  std::vector<double> cos, sin;
  double grid_offset_rad = 0.0;  ///< ε: half the spread of the offsets from the grid
  std::string grid_problem;      ///< empty: on the grid
};

EstimateGeometry estimate_geometry(const em::Measurement& m) {
  EstimateGeometry g;
  g.profile = ring_profile(m);
  g.ls = geometry::least_squares_circle(g.profile);
  const std::size_t n = g.profile.size();
  g.cos.resize(n);
  g.sin.resize(n);
  std::vector<double> angle(n);
  for (std::size_t j = 0; j < n; ++j) {
    const double dx = g.profile[j].x - g.ls.center.x, dy = g.profile[j].y - g.ls.center.y;
    const double r = std::hypot(dx, dy);
    g.cos[j] = dx / r;
    g.sin[j] = dy / r;
    angle[j] = std::atan2(dy, dx);
  }
  const double step = 2 * kPi / static_cast<double>(n);
  const double sense = wrap_angle(angle[1 % n] - angle[0]) >= 0.0 ? 1.0 : -1.0;
  double lo = 0.0, hi = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    const double off = wrap_angle(angle[j] - angle[0] - sense * step * static_cast<double>(j));
    if (std::abs(off) > 0.25 * step) {
      std::ostringstream os;
      os << "the points are not an equiangular closed profile in file order: point " << j
         << " lies " << std::abs(off) * 180.0 / kPi << "° off the " << n
         << "-point grid (at most a quarter step, " << 45.0 / static_cast<double>(n)
         << "°; a repeated closing point also breaks the grid)";
      g.grid_problem = os.str();
      return g;
    }
    lo = std::min(lo, off);
    hi = std::max(hi, off);
  }
  g.grid_offset_rad = 0.5 * (hi - lo);
  return g;
}

/// Mean of (n·u)² and of |n_xy|² − (n·u)² (the normal's radial and tangential parts in XY),
/// and the largest deviation of (n·u)² from its mean.
struct NormalProjection {
  double radial2 = 0.0, tangential2 = 0.0, spread = 0.0;
};

NormalProjection normal_projection(const em::Measurement& m, const EstimateGeometry& g) {
  NormalProjection p;
  const std::size_t n = g.cos.size();
  std::vector<double> r2(n);
  for (std::size_t j = 0; j < n; ++j) {
    const auto i = static_cast<Eigen::Index>(j);
    const double nx = m.normals(0, i), ny = m.normals(1, i);
    const double radial = nx * g.cos[j] + ny * g.sin[j];
    r2[j] = radial * radial;
    p.radial2 += r2[j];
    p.tangential2 += nx * nx + ny * ny - r2[j];
  }
  p.radial2 /= static_cast<double>(n);
  p.tangential2 /= static_cast<double>(n);
  for (double v : r2) p.spread = std::max(p.spread, std::abs(v - p.radial2));
  return p;
}

double noise_sigma(const em::DigitalModel& model, em::ProbingMode mode) {
  return mode == em::ProbingMode::scanning ? model.noise.scanning_sigma_mm
                                           : model.noise.touch_trigger_sigma_mm;
}

SpectralApplicability check_applicability(const em::DigitalModel& model,
                                          const em::Measurement& best,
                                          const RingEvaluationOptions& options,
                                          const em::Stages& stages, const EstimateGeometry& g) {
  if (!options.filter_cutoff_upr)
    return {false, "no Gaussian filter (--filter-upr none): the unfiltered RONt needs every "
                   "harmonic, which is the exact trial"};
  if (!g.grid_problem.empty()) return {false, g.grid_problem};
  const auto filtered =
      geometry::gaussian_filtered_profile(g.profile, *options.filter_cutoff_upr, g.ls);
  if (filtered.path != geometry::FilterPath::fft)
    return {false, "the Gaussian filter does not take its FFT path on these points (they sit "
                   "too far off the equiangular grid about their LS centre)"};
  if (stages.is_enabled(em::ErrorSource::roughness) && model.roughness.sigma_mm > 0.0) {
    const NormalProjection p = normal_projection(best, g);
    if (p.spread > kRadialNormalTolerance) {
      std::ostringstream os;
      os << "the normals are not radial: (n·u)² varies by " << p.spread
         << " between points (at most " << kRadialNormalTolerance
         << "), so the roughness's radial variance is not the same at every point";
      return {false, os.str()};
    }
  }
  return {true, "the roundness is filtered and the profile is equiangular: the spectral trial "
                "applies (docs/validation.md, \"The spectral trial\")"};
}

}  // namespace

std::string_view to_string(TrialKind kind) {
  switch (kind) {
    case TrialKind::automatic: return "auto";
    case TrialKind::exact: return "exact";
    case TrialKind::spectral: return "spectral";
  }
  return "?";
}

std::optional<TrialKind> trial_kind_from_string(std::string_view text) {
  for (TrialKind k : {TrialKind::automatic, TrialKind::exact, TrialKind::spectral})
    if (to_string(k) == text) return k;
  return std::nullopt;
}

SpectralApplicability spectral_trial_applicability(const em::DigitalModel& model,
                                                   const em::Measurement& best,
                                                   const RingEvaluationOptions& options,
                                                   const em::Stages& stages) {
  em::validate_measurement(best, "spectral_trial_applicability");
  return check_applicability(model, best, options, stages, estimate_geometry(best));
}

TrialChoice choose_ring_trial(const em::DigitalModel& model, const em::Measurement& best,
                              const RingEvaluationOptions& options, const em::Stages& stages,
                              TrialKind requested, bool budget) {
  if (requested == TrialKind::exact) return {TrialKind::exact, "the exact trial was asked for"};
  constexpr const char* kBudget =
      "the uncertainty budget's one-at-a-time runs share the exact trial's random numbers";
  if (requested == TrialKind::spectral && budget)
    throw geometry::InvalidInput(std::string("the spectral trial cannot run with the uncertainty "
                                             "budget: ") + kBudget + " (use the exact trial)");
  if (budget) return {TrialKind::exact, kBudget};
  const SpectralApplicability a = spectral_trial_applicability(model, best, options, stages);
  if (a.applicable) return {TrialKind::spectral, a.reason};
  if (requested == TrialKind::spectral)
    throw geometry::InvalidInput("the spectral trial does not apply: " + a.reason);
  return {TrialKind::exact, "the spectral trial does not apply: " + a.reason};
}

double SpectralRingModel::parameter_value(const Parameter& p, const em::ErrorDraw& d) const {
  switch (p.kind) {
    case Parameter::Kind::tip_radius: return d.probe.tip_radius_error_mm;
    case Parameter::Kind::probe_cos: return d.probe.cos_mm[static_cast<std::size_t>(p.index)];
    case Parameter::Kind::probe_sin: return d.probe.sin_mm[static_cast<std::size_t>(p.index)];
    case Parameter::Kind::kinematic: return d.kinematic.parameters()[p.index];
  }
  return 0.0;
}

SpectralRingModel::SpectralRingModel(const em::DigitalModel& model, const em::Measurement& best,
                                     const RingEvaluationOptions& options,
                                     const em::Stages& stages)
    : model_(&model), options_(options) {
  em::validate_measurement(best, "SpectralRingModel");
  const EstimateGeometry g = estimate_geometry(best);
  const SpectralApplicability applicability =
      check_applicability(model, best, options, stages, g);
  if (!applicability.applicable)
    throw geometry::InvalidInput("the spectral trial does not apply: " + applicability.reason);
  prepared_ = std::make_shared<const em::PreparedMeasurement>(best, model);
  n_ = g.profile.size();
  const double cutoff = *options.filter_cutoff_upr;
  const std::size_t half = n_ / 2;
  radius_ = g.ls.radius;
  cos_ = g.cos;
  sin_ = g.sin;
  if (n_ >= 8) directions_.emplace(cos_, sin_);  // the MZ fast path's (geometry::PolarProfile)

  // The estimate's filtered deviations, exactly as the exact trial filters (about c₀, R₀), and
  // about the filtered profile's own LS circle (the LS reference).
  const auto filtered = geometry::gaussian_filtered_profile(g.profile, cutoff, g.ls);
  const auto ls_filtered = geometry::least_squares_circle(filtered.points);
  filtered_.resize(n_);
  filtered_ls_.resize(n_);
  for (std::size_t j = 0; j < n_; ++j) {
    const geometry::Point2 q = filtered.points[j];
    filtered_[j] = std::hypot(q.x - g.ls.center.x, q.y - g.ls.center.y) - radius_;
    filtered_ls_[j] =
        std::hypot(q.x - ls_filtered.center.x, q.y - ls_filtered.center.y) - ls_filtered.radius;
  }

  // Stages: the systematic ones are drawn by draw_errors, the white ones here.
  temperature_ = stages.is_enabled(em::ErrorSource::temperature);
  systematic_stages_ = stages;
  systematic_stages_.set(em::ErrorSource::roughness, false).set(em::ErrorSource::noise, false);
  const auto& alpha = model.temperature.expansion_coefficient_per_k;
  if (temperature_)
    estimated_scale_ = 1.0 + alpha.value * (best.temperature_c - em::reference_temperature_c);

  // The drawn systematic parameters, each with its standard uncertainty h (the step of its
  // response: the first-order model is linear in it, so any step gives the same response).
  const em::ErrorDraw nominal = em::nominal_errors(model, best);
  std::vector<double> step;
  if (stages.is_enabled(em::ErrorSource::probe)) {
    const auto& probe = model.probe;
    if (probe.tip_radius_error_mm.u > 0.0) {
      parameters_.push_back({Parameter::Kind::tip_radius, 0, nominal.probe.tip_radius_error_mm});
      step.push_back(probe.tip_radius_error_mm.u);
    }
    for (const em::ProbeHarmonic& h : probe.directional) {
      const auto k = static_cast<std::size_t>(h.order);
      if (h.cos_mm.u > 0.0) {
        parameters_.push_back({Parameter::Kind::probe_cos, h.order, nominal.probe.cos_mm[k]});
        step.push_back(h.cos_mm.u);
      }
      if (h.sin_mm.u > 0.0) {
        parameters_.push_back({Parameter::Kind::probe_sin, h.order, nominal.probe.sin_mm[k]});
        step.push_back(h.sin_mm.u);
      }
    }
  }
  if (stages.is_enabled(em::ErrorSource::kinematic)) {
    const auto& km = model.kinematics;
    for (Eigen::Index i = 0; i < km.parameter_count(); ++i) {
      const double var = km.covariance()(i, i);
      if (var > 0.0) {
        parameters_.push_back({Parameter::Kind::kinematic, i, km.mean()[i]});
        step.push_back(std::sqrt(var));
      }
    }
  }

  // Responses of the radial deviation, u_j · ∂p_j/∂θ_i, by finite steps of the fused trial with
  // only the parameter's stage on (exact: the stage is linear in θ), and their harmonics.
  const std::size_t count = parameters_.size();
  geometry::EquiangularTransform transform(n_);
  Eigen::MatrixXd a(half + 1, count), b(half + 1, count);  // per unit of θ
  std::vector<double> radial(n_), ca(half + 1), cb(half + 1);
  std::vector<geometry::Point2> moved;
  // Displacements per standard uncertainty (for the second-order bound; point j's row, one
  // column per parameter: each parameter's displacements are written contiguously) and
  // Σ_i 5 h_i |∇Δp| (the largest change of a displacement between neighbours per unit of
  // their distance: squares compared, one square root per parameter).
  Eigen::MatrixXd move_x(static_cast<Eigen::Index>(n_), static_cast<Eigen::Index>(count));
  Eigen::MatrixXd move_y(static_cast<Eigen::Index>(n_), static_cast<Eigen::Index>(count));
  std::vector<double> inverse_distance2(n_, 0.0);  // 1/|p_{j+1} − p_j|² (0: coincident)
  for (std::size_t j = 0; j < n_; ++j) {
    const std::size_t next = (j + 1) % n_;
    const double ux = g.profile[next].x - g.profile[j].x, uy = g.profile[next].y - g.profile[j].y;
    const double d2 = ux * ux + uy * uy;
    if (d2 > 0.0) inverse_distance2[j] = 1.0 / d2;
  }
  double gradient_5sd = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const Parameter& p = parameters_[i];
    em::ErrorDraw d = nominal;
    const double h = step[i];
    em::ErrorSource source = em::ErrorSource::probe;
    switch (p.kind) {
      case Parameter::Kind::tip_radius: d.probe.tip_radius_error_mm += h; break;
      case Parameter::Kind::probe_cos: d.probe.cos_mm[static_cast<std::size_t>(p.index)] += h; break;
      case Parameter::Kind::probe_sin: d.probe.sin_mm[static_cast<std::size_t>(p.index)] += h; break;
      case Parameter::Kind::kinematic: {
        Eigen::VectorXd v = model.kinematics.mean();
        v[p.index] += h;
        d.kinematic = em::KinematicErrors(model.kinematics, std::move(v));
        source = em::ErrorSource::kinematic;
        break;
      }
    }
    em::simulate_corrected(*prepared_, model, d, em::Stages::only(source),
                           em::Formula::first_order, moved);
    double* mx = move_x.col(static_cast<Eigen::Index>(i)).data();
    double* my = move_y.col(static_cast<Eigen::Index>(i)).data();
    for (std::size_t j = 0; j < n_; ++j) {
      const double dx = moved[j].x - g.profile[j].x, dy = moved[j].y - g.profile[j].y;
      radial[j] = (dx * cos_[j] + dy * sin_[j]) / h;
      mx[j] = dx;  // at 1 sd
      my[j] = dy;
    }
    if (p.kind == Parameter::Kind::kinematic) {
      double gradient2 = 0.0;
      for (std::size_t j = 0; j < n_; ++j) {
        const std::size_t next = j + 1 == n_ ? 0 : j + 1;
        const double ex = mx[next] - mx[j], ey = my[next] - my[j];
        gradient2 = std::max(gradient2, (ex * ex + ey * ey) * inverse_distance2[j]);
      }
      gradient_5sd += kSigmas * std::sqrt(gradient2);
    }
    transform.coefficients(radial, ca, cb);
    for (std::size_t k = 0; k <= half; ++k) {
      a(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i)) = ca[k];
      b(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i)) = cb[k];
    }
  }

  // K_s: the smallest order ≥ 2 whose neglected tail Σ_i 5 h_i Σ_{k>K} H(k) |c_ik| is below
  // the tolerance (|a cos + b sin| ≤ √(a² + b²) at any point).
  std::vector<double> amplitude_5sd(half + 1, 0.0);  // Σ_i 5 h_i H(k) |c_ik|
  std::vector<double> h_of_k(half + 1);
  for (std::size_t k = 0; k <= half; ++k) h_of_k[k] = transmission(k, cutoff);
  for (std::size_t i = 0; i < count; ++i) {  // each sum still over increasing i
    const auto c = static_cast<Eigen::Index>(i);
    for (std::size_t k = 0; k <= half; ++k) {
      const auto r = static_cast<Eigen::Index>(k);
      amplitude_5sd[k] += kSigmas * step[i] * h_of_k[k] * std::hypot(a(r, c), b(r, c));
    }
  }
  std::vector<double> tail(half + 2, 0.0);  // tail[K] = Σ_{k>K}
  for (std::size_t k = half; k-- > 0;) tail[k] = tail[k + 1] + amplitude_5sd[k + 1];
  systematic_order_ = 1;
  if (count > 0) {
    systematic_order_ = std::min<std::size_t>(2, half);
    while (systematic_order_ < half && tail[systematic_order_] > kTruncationToleranceMm)
      ++systematic_order_;
  }
  double systematic_in_band_5sd = 0.0;  // Σ_{k=2}^{K_s} of the amplitudes: max |g_sys|
  for (std::size_t k = 2; k <= systematic_order_ && k <= half; ++k)
    systematic_in_band_5sd += amplitude_5sd[k];

  // White parts: radial variance v of one point and the variance of each coefficient.
  const double sigma_noise =
      stages.is_enabled(em::ErrorSource::noise) ? noise_sigma(model, best.mode) : 0.0;
  const double sigma_rough =
      stages.is_enabled(em::ErrorSource::roughness) ? model.roughness.sigma_mm : 0.0;
  const NormalProjection np = normal_projection(best, g);
  const double v = sigma_noise * sigma_noise + sigma_rough * sigma_rough * np.radial2;
  white_ = v > 0.0;
  const double nn = static_cast<double>(n_);
  const auto coefficient_variance = [&](std::size_t k) {
    return (k == 0 || 2 * k == n_) ? v / nn : 2.0 * v / nn;
  };
  double white_tail = 0.0, white_in_band = 0.0;
  white_order_ = 1;
  if (white_) {
    std::vector<double> wtail(half + 2, 0.0);  // Σ_{k>K} var_k H(k)²
    for (std::size_t k = half; k-- > 0;) {
      const double h = transmission(k + 1, cutoff);
      wtail[k] = wtail[k + 1] + coefficient_variance(k + 1) * h * h;
    }
    white_order_ = std::min<std::size_t>(2, half);
    while (white_order_ < half && kSigmas * std::sqrt(wtail[white_order_]) > kTruncationToleranceMm)
      ++white_order_;
    white_tail = kSigmas * std::sqrt(wtail[white_order_]);
    white_in_band = kSigmas * std::sqrt(wtail[1] - wtail[white_order_]);
    white_sd_a_.assign(white_order_ + 1, 0.0);
    white_sd_b_.assign(white_order_ + 1, 0.0);
    for (std::size_t k = 2; k <= white_order_; ++k) {
      const double sd = std::sqrt(coefficient_variance(k)) * transmission(k, cutoff);
      white_sd_a_[k] = sd;
      white_sd_b_[k] = 2 * k == n_ ? 0.0 : sd;
    }
    white_mean_sd_ = std::sqrt(v / nn);
    // E|δ_t|² of one point in XY: the noise's tangential component and the roughness's.
    white_tangential_mm_ =
        (sigma_noise * sigma_noise + sigma_rough * sigma_rough * np.tangential2) / (2.0 * radius_);
  }
  order_ = std::max(systematic_order_, white_order_);

  // The in-band response matrix (H applied) and the responses' means.
  const std::size_t rows = systematic_order_ >= 2 ? 2 * (systematic_order_ - 1) : 0;
  response_.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(count));
  response_mean_.resize(static_cast<Eigen::Index>(count));
  for (std::size_t i = 0; i < count; ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    response_mean_[c] = a(0, c);
    for (std::size_t k = 2; k <= systematic_order_ && rows > 0; ++k) {
      const double h = transmission(k, cutoff);
      const auto r = static_cast<Eigen::Index>(2 * (k - 2));
      response_(r, c) = h * a(static_cast<Eigen::Index>(k), c);
      response_(r + 1, c) = h * b(static_cast<Eigen::Index>(k), c);
    }
  }

  // The bound (header; docs/validation.md, "The spectral trial").
  bound_.systematic_order = systematic_order_;
  bound_.white_order = white_order_;
  bound_.truncation_mm = (count > 0 ? tail[systematic_order_] : 0.0) + white_tail;
  // 5 sd of the systematic displacement at the worst point: √(vᵀ C v) per coordinate, C the
  // parameters' covariance (probe terms independent; the kinematic model's covariance).
  double displacement_5sd = 0.0;
  if (count > 0) {
    Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(count),
                                                static_cast<Eigen::Index>(count));
    for (std::size_t i = 0; i < count; ++i)
      for (std::size_t k = 0; k < count; ++k) {
        const auto &pi = parameters_[i], &pk = parameters_[k];
        const auto r = static_cast<Eigen::Index>(i), c = static_cast<Eigen::Index>(k);
        if (pi.kind == Parameter::Kind::kinematic && pk.kind == Parameter::Kind::kinematic)
          cov(r, c) = model.kinematics.covariance()(pi.index, pk.index) / (step[i] * step[k]);
        else if (i == k)
          cov(r, c) = 1.0;  // a probe term in units of its own u
      }
    // Independent parameters (the example model's): Σ_i C_ii m_ij², O(nP) instead of O(nP²).
    const Eigen::ArrayXd var =
        cov.isDiagonal(0.0)
            ? ((move_x.array().square().matrix() * cov.diagonal()).array() +
               (move_y.array().square().matrix() * cov.diagonal()).array())
                  .eval()
            : ((move_x.cwiseProduct(move_x * cov)).rowwise().sum().array() +
               (move_y.cwiseProduct(move_y * cov)).rowwise().sum().array())
                  .eval();
    displacement_5sd = kSigmas * std::sqrt(var.maxCoeff());
  }
  const double white_5sd = kSigmas * std::sqrt(2.0 * sigma_noise * sigma_noise +
                                                sigma_rough * sigma_rough);
  const double disp = displacement_5sd + white_5sd;
  bound_.second_order_mm = disp * disp / radius_;
  double max_radius = 0.0;
  for (const auto& pt : g.profile) max_radius = std::max(max_radius, std::hypot(pt.x, pt.y));
  const double dt = temperature_ ? std::abs(best.temperature_c - em::reference_temperature_c) +
                                       kSigmas * model.temperature.thermometer_u_k
                                 : 0.0;
  const double ds = (std::abs(alpha.value) + kSigmas * alpha.u) * dt;
  bound_.kinematic_position_mm = gradient_5sd * (max_radius * ds + kSigmas * sigma_rough);
  bound_.grid_offset_mm =
      4.0 * g.grid_offset_rad * (systematic_in_band_5sd + white_in_band);
  double mean_u = 0.0;
  {
    double sx = 0.0, sy = 0.0;
    for (std::size_t j = 0; j < n_; ++j) {
      sx += cos_[j];
      sy += sin_[j];
    }
    mean_u = std::hypot(sx, sy) / nn;
  }
  double centre_5sd = white_ ? kSigmas * std::sqrt(2.0 * v / nn) : 0.0;
  if (half >= 1)
    for (std::size_t i = 0; i < count; ++i)
      centre_5sd += kSigmas * step[i] *
                    std::hypot(a(1, static_cast<Eigen::Index>(i)), b(1, static_cast<Eigen::Index>(i)));
  bound_.diameter_mm = bound_.second_order_mm + 2.0 * bound_.kinematic_position_mm +
                       2.0 * mean_u * centre_5sd;
  bound_.roundness_mm = 2.0 * bound_.truncation_mm + bound_.second_order_mm +
                        2.0 * bound_.kinematic_position_mm + bound_.grid_offset_mm;
}

SpectralRingTrial::SpectralRingTrial(std::shared_ptr<const SpectralRingModel> model)
    : model_(std::move(model)), transform_(model_ ? model_->n_ : 2) {
  if (!model_) throw geometry::InvalidInput("SpectralRingTrial: no SpectralRingModel");
  theta_.resize(static_cast<Eigen::Index>(model_->parameters_.size()));
  white_.resize(model_->white_normal_count());
  a_.assign(model_->order_ + 1, 0.0);
  b_.assign(model_->order_ + 1, 0.0);
  synthesized_.assign(model_->n_, 0.0);
  harmonics_.resize(model_->response_.rows());  // the product's output, sized once
  points_.resize(model_->n_);
}

void SpectralRingTrial::operator()(uncertainty::RandomStream& rng, std::span<double> out) {
  const SpectralRingModel& m = *model_;
  StreamRandomSource source(rng);
  em::draw_errors(*m.model_, *m.prepared_, source, m.systematic_stages_, draw_);
  if (!white_.empty()) rng.fill_standard_normal(white_);
  const RingMeasurands y = measurands(draw_, white_);
  out[diameter] = y.diameter_mm;
  out[roundness] = y.roundness_mm;
}

RingMeasurands SpectralRingTrial::measurands(const em::ErrorDraw& draw,
                                             std::span<const double> white_normals) {
  const SpectralRingModel& m = *model_;
  if (!white_normals.empty() && white_normals.size() != m.white_normal_count())
    throw geometry::InvalidInput("SpectralRingTrial::measurands: expected " +
                                 std::to_string(m.white_normal_count()) +
                                 " white normals (or none); got " +
                                 std::to_string(white_normals.size()));
  for (std::size_t i = 0; i < m.parameters_.size(); ++i) {
    const auto& p = m.parameters_[i];
    theta_[static_cast<Eigen::Index>(i)] = m.parameter_value(p, draw) - p.nominal;
  }
  double kappa = 1.0, inverse_scale = 1.0;
  if (m.temperature_) {
    const double s = 1.0 + draw.expansion_coefficient_per_k *
                               (draw.temperature_c - em::reference_temperature_c);
    inverse_scale = 1.0 / m.estimated_scale_;
    kappa = s * inverse_scale;
  }
  std::fill(a_.begin(), a_.end(), 0.0);
  std::fill(b_.begin(), b_.end(), 0.0);
  if (m.response_.rows() > 0) {
    internal::column_major_product(m.response_.data(),
                                   static_cast<std::size_t>(m.response_.rows()),
                                   static_cast<std::size_t>(m.response_.cols()), theta_.data(),
                                   harmonics_.data());  // = response_ · θ, bit for bit
    for (std::size_t k = 2; k <= m.systematic_order_; ++k) {
      a_[k] = harmonics_[static_cast<Eigen::Index>(2 * (k - 2))];
      b_[k] = harmonics_[static_cast<Eigen::Index>(2 * (k - 2) + 1)];
    }
  }
  double mean = theta_.size() > 0 ? m.response_mean_.dot(theta_) : 0.0;
  double tangential = 0.0;
  if (!white_normals.empty()) {
    mean += m.white_mean_sd_ * white_normals[0];
    for (std::size_t k = 2; k <= m.white_order_; ++k) {
      a_[k] += m.white_sd_a_[k] * white_normals[1 + 2 * (k - 2)];
      b_[k] += m.white_sd_b_[k] * white_normals[2 + 2 * (k - 2)];
    }
    tangential = m.white_tangential_mm_ * inverse_scale * inverse_scale;
  }
  RingMeasurands y;
  y.diameter_mm = 2.0 * (kappa * m.radius_ + mean * inverse_scale + tangential);
  if (m.order_ >= 2) {
    for (std::size_t k = 2; k <= m.order_; ++k) {
      a_[k] *= inverse_scale;
      b_[k] *= inverse_scale;
    }
    transform_.values(a_, b_, synthesized_);
  } else {
    std::fill(synthesized_.begin(), synthesized_.end(), 0.0);
  }
  const std::size_t n = m.n_;
  if (m.options_.reference == ReferenceCircle::least_squares) {
    // One vectorised pass, nothing stored.
    y.roundness_mm =
        internal::scaled_sum_peak_to_valley(kappa, m.filtered_ls_.data(), synthesized_.data(), n);
    return y;
  }
  for (std::size_t j = 0; j < n; ++j)
    synthesized_[j] += kappa * m.filtered_[j];  // the deviation about (c₀, R₀)
  if (m.directions_ && (m.options_.reference == ReferenceCircle::minimum_zone ||
                        m.options_.reference == ReferenceCircle::maximum_inscribed)) {
    const geometry::PolarProfile profile{m.radius_, synthesized_, &*m.directions_};
    y.roundness_mm =
        m.options_.reference == ReferenceCircle::minimum_zone
            ? geometry::minimum_zone_ront_from_extremes(profile, extremes_)
            : geometry::maximum_inscribed_ront_from_extremes(profile, extremes_);
    return y;
  }
  for (std::size_t j = 0; j < n; ++j) {
    const double r = m.radius_ + synthesized_[j];
    points_[j] = {r * m.cos_[j], r * m.sin_[j]};
  }
  y.roundness_mm = ront_about(points_, m.options_.reference);
  return y;
}

uncertainty::ExperimentFactory spectral_ring_experiment_factory(
    const em::DigitalModel& model, const em::Measurement& best,
    const RingEvaluationOptions& options, const em::Stages& stages) {
  auto shared = std::make_shared<const SpectralRingModel>(model, best, options, stages);
  return [shared]() -> uncertainty::Experiment {
    auto trial = std::make_shared<SpectralRingTrial>(shared);
    return [trial](uncertainty::RandomStream& rng, std::span<double> out) { (*trial)(rng, out); };
  };
}

}  // namespace vcmm::validation
