// Noise and roughness from CMM profiles of a calibrated artefact and its reference profile:
// notation, model and the derivation of the variance correction in
// vcmm/characterization/noise.h; method and limits in docs/characterization.md.
#include "vcmm/characterization/noise.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "output_checks.h"
#include "vcmm/errormodel/errors.h"
#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"

namespace vcmm::characterization {
namespace {

using errormodel::InvalidInput;
using geometry::Point2;
constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kUmPerMm = 1e3;

std::string number(double v) {
  std::ostringstream os;
  os.precision(8);
  os << v;
  return os.str();
}

/// Angle wrapped into (−π, π].
double wrap(double a) {
  a = std::remainder(a, kTwoPi);
  return a <= -kPi ? a + kTwoPi : a;
}

/// The noise code's own rule on top of geometry::validate_roundness_profile (which `p` has
/// passed): equiangular, every angle within 1e-3 of a step of the grid α_0 + 2πj/M — to the
/// file's precision (a 3600-point trace written with 4 decimals of a degree is within 5e-4 of
/// a step). `prefix` ("" or "caller: reference: ") starts each message; the sample is named by
/// geometry::profile_sample_location (its file line when read from a file).
void check_equiangular(const ReferenceProfile& p, const std::string& prefix) {
  const std::vector<double>& angle = p.angle_rad;
  const std::size_t m = angle.size();
  const double step = kTwoPi / static_cast<double>(m);
  for (std::size_t j = 0; j < m; ++j) {
    const double expected = angle[0] + step * static_cast<double>(j);
    if (!(std::abs(angle[j] - expected) <= 1e-3 * step))
      throw InvalidInput(prefix + geometry::profile_sample_location(p, j) +
                         ": the reference must be equiangular over one turn (" +
                         std::to_string(m) + " samples, step " +
                         number(360.0 / static_cast<double>(m)) + " deg); angle " +
                         number(angle[j] * 180.0 / kPi) + " deg, expected " +
                         number(expected * 180.0 / kPi) + " deg");
  }
}

// The largest reference deviation accepted (mm): a roundness instrument's gauge range is about
// ±1 mm, and a calibrated ring's form is a few µm; 1e300 µm (a corrupt file) would overflow
// every square downstream.
constexpr double kMaxReferenceDeviationMm = 1.0;

void check_reference_range(const ReferenceProfile& p, const std::string& prefix) {
  for (std::size_t j = 0; j < p.deviation_mm.size(); ++j)
    if (!(std::abs(p.deviation_mm[j]) <= kMaxReferenceDeviationMm))
      throw InvalidInput(prefix + geometry::profile_sample_location(p, j) + ": the deviation " +
                         number(p.deviation_mm[j] * kUmPerMm) +
                         " um lies outside a roundness instrument's range (at most 1000 um "
                         "from the mean radius; mm given as um?)");
}

// The largest noise σ written (mm): a CMM's probing noise is 0.01–10 µm; 1 mm is no noise but
// the wrong artefact, reference or units.
constexpr double kMaxNoiseSigmaMm = 1.0;

/// Fourier coefficients a_k, b_k (k = 2 … K) of the reference about α_0.
struct ReferenceSeries {
  double alpha0 = 0.0;
  std::vector<double> a, b;  // index k; 0 and 1 unused
  int order() const { return static_cast<int>(a.size()) - 1; }
};

ReferenceSeries reference_series(const ReferenceProfile& ref, int max_order) {
  const std::size_t m = ref.angle_rad.size();
  const int k_max = std::min(static_cast<int>((m - 1) / 2), std::max(max_order, 1));
  ReferenceSeries s;
  s.alpha0 = ref.angle_rad.front();
  s.a.assign(static_cast<std::size_t>(k_max) + 1, 0.0);
  s.b.assign(static_cast<std::size_t>(k_max) + 1, 0.0);
  std::vector<double> cos_table(m), sin_table(m);
  for (std::size_t j = 0; j < m; ++j) {
    const double t = kTwoPi * static_cast<double>(j) / static_cast<double>(m);
    cos_table[j] = std::cos(t);
    sin_table[j] = std::sin(t);
  }
  const double scale = 2.0 / static_cast<double>(m);
  for (int k = 2; k <= k_max; ++k) {
    double a = 0.0, b = 0.0;
    std::size_t idx = 0;  // (j·k) mod m
    for (std::size_t j = 0; j < m; ++j) {
      a += ref.deviation_mm[j] * cos_table[idx];
      b += ref.deviation_mm[j] * sin_table[idx];
      idx += static_cast<std::size_t>(k);
      if (idx >= m) idx -= m;
    }
    s.a[static_cast<std::size_t>(k)] = scale * a;
    s.b[static_cast<std::size_t>(k)] = scale * b;
  }
  return s;
}

/// g(α) = Σ_k a_k cos k(α − α_0) + b_k sin k(α − α_0), powers of e^{iβ} by recurrence.
double evaluate_series(const ReferenceSeries& s, double alpha) {
  const double beta = alpha - s.alpha0;
  const double c1 = std::cos(beta), s1 = std::sin(beta);
  double c = c1, sn = s1, g = 0.0;
  for (int k = 2; k <= s.order(); ++k) {
    const double next_c = c * c1 - sn * s1;
    sn = sn * c1 + c * s1;
    c = next_c;
    g += s.a[static_cast<std::size_t>(k)] * c + s.b[static_cast<std::size_t>(k)] * sn;
  }
  return g;
}

/// A scan about its least-squares centre.
struct PreparedProfile {
  std::vector<double> theta, e;  // angle (rad) and radial deviation (mm)
  Point2 center;
  double radius = 0.0;
};

PreparedProfile prepare(std::span<const Point2> pts, const geometry::LeastSquaresCircle& ls) {
  PreparedProfile p;
  p.center = ls.center;
  p.radius = ls.radius;
  p.theta.resize(pts.size());
  p.e.resize(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double dx = pts[i].x - ls.center.x, dy = pts[i].y - ls.center.y;
    p.theta[i] = std::atan2(dy, dx);
    p.e[i] = std::hypot(dx, dy) - ls.radius;
  }
  return p;
}

/// The equiangular scan of scanning_noise (validated, closing point dropped).
PreparedProfile prepare_scan(std::span<const Point2> scan, const char* caller) {
  geometry::validate_profile(scan, 16, caller);
  geometry::LeastSquaresCircle ls = geometry::least_squares_circle(scan);
  std::size_t n = scan.size();
  {
    const Point2& a = scan.front();
    const Point2& b = scan.back();
    const double ta = std::atan2(a.y - ls.center.y, a.x - ls.center.x);
    const double tb = std::atan2(b.y - ls.center.y, b.x - ls.center.x);
    if (std::abs(wrap(tb - ta)) < 0.25 * kTwoPi / static_cast<double>(n - 1)) {
      --n;  // a closed scan repeating its first point
      ls = geometry::least_squares_circle(scan.first(n));
    }
  }
  PreparedProfile p = prepare(scan.first(n), ls);
  const double step = kTwoPi / static_cast<double>(n);
  const double sense = wrap(p.theta[1] - p.theta[0]) >= 0.0 ? 1.0 : -1.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double off = wrap(p.theta[i] - p.theta[0] - sense * step * static_cast<double>(i));
    if (!(std::abs(off) <= 0.25 * step))
      throw InvalidInput(std::string(caller) +
                         ": a scan must be equiangular about its "
                         "least-squares centre (point " +
                         std::to_string(i) + " is " + number(off / step) +
                         " steps off the grid of " + std::to_string(n) +
                         " points); use touch-trigger evaluation for sparse or uneven points");
  }
  return p;
}

void check_cutoff(double cutoff, std::size_t n, const char* caller) {
  if (!std::isfinite(cutoff) || cutoff <= 0.0 || cutoff > 0.5 * static_cast<double>(n))
    throw InvalidInput(std::string(caller) + ": the cut-off must be finite in (0, n/2] = (0, " +
                       number(0.5 * static_cast<double>(n)) + "] UPR for " + std::to_string(n) +
                       " points; got " + number(cutoff));
}

/// φ maximising the weighted correlation C_w(φ) = Σ_k w_k Re(G_k e^{−ikφ}) (noise.h,
/// "Phase"): with w_k = (1 − H(k))² the φ that minimises the high-pass residual energy.
double estimate_phase(const PreparedProfile& p, const ReferenceSeries& s,
                      const std::vector<double>& w) {
  const int k_max = s.order();
  if (k_max < 2) return 0.0;
  // F_k = Σ_i e_i e^{ikθ_i};  G_k = R_k e^{−ikα_0} F_k with R_k = a_k − i b_k.
  std::vector<double> fr(static_cast<std::size_t>(k_max) + 1, 0.0), fi(fr.size(), 0.0);
  for (std::size_t i = 0; i < p.theta.size(); ++i) {
    const double c1 = std::cos(p.theta[i]), s1 = std::sin(p.theta[i]);
    double c = c1, sn = s1;
    for (int k = 2; k <= k_max; ++k) {
      const double next_c = c * c1 - sn * s1;
      sn = sn * c1 + c * s1;
      c = next_c;
      fr[static_cast<std::size_t>(k)] += p.e[i] * c;
      fi[static_cast<std::size_t>(k)] += p.e[i] * sn;
    }
  }
  std::vector<double> gr(fr.size(), 0.0), gi(fr.size(), 0.0);
  for (int k = 2; k <= k_max; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    const double rr = s.a[kk], ri = -s.b[kk];
    const double wr = std::cos(k * s.alpha0), wi = -std::sin(k * s.alpha0);
    const double qr = rr * wr - ri * wi, qi = rr * wi + ri * wr;  // R_k e^{−ikα_0}
    gr[kk] = w[kk] * (qr * fr[kk] - qi * fi[kk]);
    gi[kk] = w[kk] * (qr * fi[kk] + qi * fr[kk]);
  }
  // C(φ) = Σ_k gr_k cos kφ + gi_k sin kφ.
  auto c_at = [&](double phi) {
    const double c1 = std::cos(phi), s1 = std::sin(phi);
    double c = c1, sn = s1, sum = 0.0;
    for (int k = 2; k <= k_max; ++k) {
      const double next_c = c * c1 - sn * s1;
      sn = sn * c1 + c * s1;
      c = next_c;
      sum += gr[static_cast<std::size_t>(k)] * c + gi[static_cast<std::size_t>(k)] * sn;
    }
    return sum;
  };
  // Grid of 4 K steps (a quarter of the shortest period), then golden section within ±1 step.
  const std::size_t grid = std::max<std::size_t>(360, 4 * static_cast<std::size_t>(k_max));
  std::vector<double> cos_table(grid), sin_table(grid);
  for (std::size_t m = 0; m < grid; ++m) {
    const double t = kTwoPi * static_cast<double>(m) / static_cast<double>(grid);
    cos_table[m] = std::cos(t);
    sin_table[m] = std::sin(t);
  }
  double best = -std::numeric_limits<double>::infinity();
  std::size_t best_m = 0;
  for (std::size_t m = 0; m < grid; ++m) {
    double sum = 0.0;
    std::size_t idx = (2 * m) % grid;
    for (int k = 2; k <= k_max; ++k) {
      sum += gr[static_cast<std::size_t>(k)] * cos_table[idx] +
             gi[static_cast<std::size_t>(k)] * sin_table[idx];
      idx += m;
      if (idx >= grid) idx -= grid;
    }
    if (sum > best) {
      best = sum;
      best_m = m;
    }
  }
  const double h = kTwoPi / static_cast<double>(grid);
  double lo = h * static_cast<double>(best_m) - h, hi = lo + 2.0 * h;
  const double r = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - r * (hi - lo), x2 = lo + r * (hi - lo);
  double f1 = c_at(x1), f2 = c_at(x2);
  // 60 golden-section steps shrink 2h by 0.618^60 ≈ 3e-13: below 1e-12 rad.
  for (int it = 0; it < 60; ++it) {
    if (f1 > f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - r * (hi - lo);
      f1 = c_at(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + r * (hi - lo);
      f2 = c_at(x2);
    }
  }
  double phi = std::fmod(0.5 * (lo + hi), kTwoPi);
  return phi < 0.0 ? phi + kTwoPi : phi;
}

double rms(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return v.empty() ? 0.0 : std::sqrt(s / static_cast<double>(v.size()));
}

/// Σ h² of the high-pass residual h = d − L d.
double high_pass_sum_squares(const std::vector<double>& d, double cutoff,
                             std::vector<double>* low_out = nullptr) {
  const std::vector<double> low = geometry::gaussian_filter_closed(d, cutoff);
  double s = 0.0;
  for (std::size_t i = 0; i < d.size(); ++i) s += (d[i] - low[i]) * (d[i] - low[i]);
  if (low_out) *low_out = low;
  return s;
}

// The outlier test of residuals r_i with one variance per point (known up to the scale they
// determine themselves): studentized, Bonferroni over the points at kNoiseOutlierLevel
// (consistency.h). `sd` is the per-point standard deviation the residuals imply (only ratios
// matter; it makes the reported u a length), `leverage` empty for 0.
ConsistencyTest residual_outliers(const std::vector<double>& r, const std::vector<double>& theta,
                                  double sd, double nu, const Eigen::VectorXd& leverage = {}) {
  std::vector<FitResidual> res(r.size());
  for (std::size_t i = 0; i < r.size(); ++i) {
    FitResidual& f = res[i];
    f.value = r[i];
    f.uncertainty = sd > 0.0 ? sd : 1.0;
    f.leverage = leverage.size() > 0 ? leverage[static_cast<Eigen::Index>(i)] : 0.0;
    f.where = "point " + std::to_string(i + 1) + " (at " + number(theta[i] * 180.0 / kPi) + " deg)";
  }
  if (!(sd > 0.0)) return test_consistency(res, 0.0, false);  // nothing scatters: no test
  return test_consistency(res, nu, false, {0.5 * kFalseRefusalLevel, kNoiseOutlierLevel});
}

// High-pass residuals d − low and their per-point standard deviation √(variance·Λ/n).
ConsistencyTest high_pass_outliers(const std::vector<double>& d, const std::vector<double>& low,
                                   const std::vector<double>& theta, double variance,
                                   double variance_factor) {
  std::vector<double> h(d.size());
  for (std::size_t i = 0; i < d.size(); ++i) h[i] = d[i] - low[i];
  return residual_outliers(h, theta, std::sqrt(variance * variance_factor),
                           static_cast<double>(d.size()));
}

SigmaEstimate sigma_from_variance(double variance, double nu) {
  SigmaEstimate s;
  s.sigma_mm = std::sqrt(std::max(variance, 0.0));
  s.degrees_of_freedom = nu;
  s.u_mm = sigma_coverage_factor(nu) * s.sigma_mm / std::sqrt(2.0 * nu);
  return s;
}

/// Regularised lower incomplete gamma P(a, x) (Numerical Recipes 6.2: the series below
/// x < a + 1, Lentz's continued fraction for Q above), relative accuracy ~1e-14 per term sum.
double gamma_p(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_prefactor = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 1000000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (term < 1e-16 * sum) break;
    }
    return sum * std::exp(log_prefactor);
  }
  constexpr double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 1000000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return 1.0 - std::exp(log_prefactor) * h;
}

/// P(|σ̂ − σ| ≤ 2kσ̂/√(2ν)) under νσ̂²/σ² ~ χ²_ν.
double sigma_coverage(double nu, double k) {
  const double a = 2.0 * k / std::sqrt(2.0 * nu);
  const double lo = nu / ((1.0 + a) * (1.0 + a));
  const double p_lo = gamma_p(0.5 * nu, 0.5 * lo);
  if (a >= 1.0) return 1.0 - p_lo;
  const double hi = nu / ((1.0 - a) * (1.0 - a));
  return gamma_p(0.5 * nu, 0.5 * hi) - p_lo;
}

/// The low-pass profile sorted by angle, with the noise variance v it carries.
SystematicProfile systematic_profile(const std::vector<double>& theta,
                                     const std::vector<double>& low, double variance) {
  std::vector<std::size_t> order(theta.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return theta[a] < theta[b]; });
  SystematicProfile s;
  s.noise_variance_mm2 = variance;
  for (std::size_t i : order) {
    s.angle_rad.push_back(theta[i]);
    s.deviation_mm.push_back(low[i]);
  }
  return s;
}

/// Periodic linear interpolation of a sorted profile at angle a.
double interpolate(const SystematicProfile& s, double a) {
  const std::vector<double>& t = s.angle_rad;
  const double first = t.front();
  a = first + std::fmod(std::fmod(a - first, kTwoPi) + kTwoPi, kTwoPi);  // [first, first + 2π)
  const std::size_t m = t.size();
  std::size_t hi = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), a) - t.begin());
  const std::size_t lo = hi - 1;  // hi ≥ 1 since a ≥ first
  const double t_lo = t[lo];
  const double t_hi = hi < m ? t[hi] : first + kTwoPi;
  if (hi == m) hi = 0;
  const double w = t_hi > t_lo ? (a - t_lo) / (t_hi - t_lo) : 0.0;
  return (1.0 - w) * s.deviation_mm[lo] + w * s.deviation_mm[hi];
}

void check_systematic_profile(const SystematicProfile& s, const char* caller) {
  const std::string c(caller);
  if (s.angle_rad.size() != s.deviation_mm.size() || s.angle_rad.size() < 8)
    throw InvalidInput(c +
                       ": the scan's systematic profile needs >= 8 samples, angles and "
                       "deviations alike; got " +
                       std::to_string(s.angle_rad.size()) + " and " +
                       std::to_string(s.deviation_mm.size()));
  for (std::size_t i = 0; i < s.angle_rad.size(); ++i) {
    if (!std::isfinite(s.angle_rad[i]) || !std::isfinite(s.deviation_mm[i]))
      throw InvalidInput(c + ": systematic profile sample " + std::to_string(i) + " is not finite");
    if (i > 0 && !(s.angle_rad[i] > s.angle_rad[i - 1]))
      throw InvalidInput(c + ": systematic profile angles must increase strictly (sample " +
                         std::to_string(i) + ")");
  }
  if (!(s.angle_rad.back() - s.angle_rad.front() < kTwoPi))
    throw InvalidInput(c + ": systematic profile must span less than one turn");
  if (!std::isfinite(s.noise_variance_mm2) || s.noise_variance_mm2 < 0.0)
    throw InvalidInput(c + ": systematic profile noise variance must be finite and >= 0; got " +
                       number(s.noise_variance_mm2));
}

ScanNoiseResult scan_core(const PreparedProfile& p, const ReferenceProfile& reference,
                          const ScanNoiseOptions& options, const char* caller,
                          std::vector<double>* reference_at_scan) {
  const std::size_t n = p.theta.size();
  check_cutoff(options.cutoff_upr, n, caller);
  if (options.phase_rad && !std::isfinite(*options.phase_rad))
    throw InvalidInput(std::string(caller) + ": the phase must be finite; got " +
                       number(*options.phase_rad));
  const ReferenceSeries series = reference_series(reference, static_cast<int>((n - 1) / 2));
  ScanNoiseResult r;
  r.points = n;
  r.cutoff_upr = options.cutoff_upr;
  r.center_mm = p.center;
  r.radius_mm = p.radius;
  r.phase_estimated = !options.phase_rad.has_value();
  if (options.phase_rad) {
    r.phase_rad = *options.phase_rad;
  } else {
    std::vector<double> w(static_cast<std::size_t>(series.order()) + 1, 0.0);
    for (std::size_t k = 2; k < w.size(); ++k) {
      const double ratio = static_cast<double>(k) / options.cutoff_upr;
      w[k] = std::pow(1.0 - std::exp2(-ratio * ratio), 2);
    }
    r.phase_rad = estimate_phase(p, series, w);
  }
  std::vector<double> g(n), d(n);
  for (std::size_t i = 0; i < n; ++i) {
    g[i] = evaluate_series(series, p.theta[i] - r.phase_rad);
    d[i] = p.e[i] - g[i];
  }
  std::vector<double> low;
  const double ss = high_pass_sum_squares(d, options.cutoff_upr, &low);
  r.factor = high_pass_noise_factor(n, options.cutoff_upr);
  const double lambda = r.factor.variance_factor * static_cast<double>(n);
  r.sigma = sigma_from_variance(ss / lambda, r.factor.degrees_of_freedom);
  // Phase signal-to-noise ratio √E/σ̂, E the high-pass energy of the reference at the scan.
  const double energy = high_pass_sum_squares(g, options.cutoff_upr);
  r.phase_snr = r.sigma.sigma_mm > 0.0 ? std::sqrt(energy) / r.sigma.sigma_mm
                                       : std::numeric_limits<double>::infinity();
  r.phase_determined = !r.phase_estimated || r.phase_snr >= kPhaseSnr;
  r.systematic = systematic_profile(p.theta, low, ss / lambda * r.factor.low_pass_variance_factor);
  r.consistency = high_pass_outliers(d, low, p.theta, ss / lambda, r.factor.variance_factor);
  r.raw_rms_mm = rms(p.e);
  r.reference_rms_mm = rms(g);
  r.low_pass_rms_mm = rms(low);
  r.high_pass_rms_mm = std::sqrt(ss / static_cast<double>(n));
  if (reference_at_scan) *reference_at_scan = std::move(g);
  return r;
}

nlohmann::json sigma_json(const SigmaEstimate& s) {
  return {{"sigma_um", s.sigma_mm * kUmPerMm},
          {"uncertainty_um", s.u_mm * kUmPerMm},
          {"degrees_of_freedom", s.degrees_of_freedom}};
}

nlohmann::json scan_json(const ScanNoiseResult& r, const std::string& source) {
  return {{"file", source},
          {"points", r.points},
          {"estimate", sigma_json(r.sigma)},
          {"cutoff_upr", r.cutoff_upr},
          {"variance_factor", r.factor.variance_factor},
          {"phase_deg", r.phase_rad * 180.0 / kPi},
          {"phase_estimated", r.phase_estimated},
          {"phase_snr", r.phase_snr},
          {"phase_determined", r.phase_determined},
          {"center_mm", {r.center_mm.x, r.center_mm.y}},
          {"radius_mm", r.radius_mm},
          {"raw_rms_um", r.raw_rms_mm * kUmPerMm},
          {"reference_rms_um", r.reference_rms_mm * kUmPerMm},
          {"low_pass_rms_um", r.low_pass_rms_mm * kUmPerMm},
          {"high_pass_rms_um", r.high_pass_rms_mm * kUmPerMm}};
}

std::string sigma_text(const SigmaEstimate& s) {
  std::ostringstream os;
  os.precision(3);
  os << "sigma " << s.sigma_mm * kUmPerMm << " um, u " << s.u_mm * kUmPerMm << " um, nu "
     << std::fixed << std::setprecision(0) << s.degrees_of_freedom;
  return os.str();
}

// "reference r.csv, scan s.csv, …": what a result was computed from, for refusals.
std::string inputs_text(const NoiseCharacterization& c) {
  std::string s = "reference " + c.reference_source;
  if (c.scan || c.repeated) s += ", scan " + c.scan_source;
  if (c.repeated) s += ", repeat scan " + c.repeat_source;
  if (c.touch) s += ", touch points " + c.touch_source;
  return s;
}

// σ finite and in the physical range of a CMM's noise, naming what it came from.
void check_sigma(double sigma_mm, const char* what, const NoiseCharacterization& c) {
  if (!(sigma_mm >= 0.0 && sigma_mm <= kMaxNoiseSigmaMm))
    throw InvalidInput(std::string("the ") + what + " sigma " + number(sigma_mm * kUmPerMm) +
                       " um is outside the range of a CMM's noise (0 to 1000 um): computed from " +
                       inputs_text(c) + " — the wrong artefact, reference or units; nothing written");
}

nlohmann::json noise_section(const NoiseCharacterization& c, std::optional<double> fb_scan,
                             std::optional<double> fb_touch) {
  if (c.repeated) {
    check_sigma(c.repeated->noise.sigma_mm, "scanning", c);
    check_sigma(c.repeated->roughness.sigma_mm, "roughness", c);
  }
  if (c.scan) check_sigma(c.scan->sigma.sigma_mm, "scanning", c);
  if (c.touch) check_sigma(c.touch->sigma.sigma_mm, "touch-trigger", c);
  if (!c.scan && !c.repeated && !c.touch)
    throw InvalidInput("noise_section_json: no scan or touch-trigger data were characterised");
  for (const auto& [v, name] : {std::pair{fb_scan, "scanning"}, std::pair{fb_touch, "touch"}})
    if (v && (!std::isfinite(*v) || *v < 0.0))
      throw InvalidInput(std::string("noise_section_json: the ") + name +
                         " fallback sigma must be finite and >= 0; got " + number(*v));
  nlohmann::json out;
  std::string src = "vcmm characterize noise against reference " + c.reference_source +
                    " (radial sigma = sigma per Cartesian component of isotropic noise)";
  std::string missing;
  if (c.repeated) {
    out["scanning_sigma_um"] = c.repeated->noise.sigma_mm * kUmPerMm;
    src += "; scanning: difference of repeated scans " + c.scan_source + ", " + c.repeat_source +
           " (high-pass, cut-off " + number(c.repeated->first.cutoff_upr) + " UPR; " +
           sigma_text(c.repeated->noise) + "; free of roughness)";
  } else if (c.scan) {
    out["scanning_sigma_um"] = c.scan->sigma.sigma_mm * kUmPerMm;
    src += "; scanning: " + c.scan_source + " minus reference, high-pass (cut-off " +
           number(c.scan->cutoff_upr) + " UPR; " + sigma_text(c.scan->sigma) +
           "; includes the roughness the tip sees: one scan cannot separate it)";
  } else if (fb_scan) {
    out["scanning_sigma_um"] = *fb_scan * kUmPerMm;
    src += "; scanning: no data, value kept from the existing model";
  } else {
    missing += "scanning_sigma_um";
  }
  if (c.touch) {
    out["touch_trigger_sigma_um"] = c.touch->sigma.sigma_mm * kUmPerMm;
    if (c.touch->scan_systematics_removed)
      src += "; touch-trigger: " + c.touch_source +
             " minus reference and the scan's "
             "low-frequency systematic profile, least-squares circle (" +
             sigma_text(c.touch->sigma) +
             "; assumes the systematic errors below the cut-off "
             "are common to both modes)";
    else
      src += "; touch-trigger: " + c.touch_source + " minus reference, least-squares circle (" +
             sigma_text(c.touch->sigma) +
             "; includes any systematic error beyond "
             "centre/radius)";
  } else if (fb_touch) {
    out["touch_trigger_sigma_um"] = *fb_touch * kUmPerMm;
    src += "; touch-trigger: no data, value kept from the existing model";
  } else {
    if (!missing.empty()) missing += " and ";
    missing += "touch_trigger_sigma_um";
  }
  out["source"] = src;
  if (!missing.empty())
    out["comment"] = "incomplete section: " + missing +
                     " not characterised (no data); take it from the existing model before "
                     "loading (vcmm characterize noise --model MODEL.json does)";
  return out;
}

std::optional<nlohmann::json> roughness_section(const NoiseCharacterization& c) {
  if (!c.repeated) return std::nullopt;
  const RepeatedScanResult& r = *c.repeated;
  std::ostringstream src;
  src.precision(3);
  src << "vcmm characterize noise: repeated scans " << c.scan_source << ", " << c.repeat_source
      << " against reference " << c.reference_source
      << ": sigma_rough^2 = high-pass variance of the mean scan - (difference variance)/4 = "
      << r.roughness_variance_mm2 * 1e6 << " um^2 (u " << r.roughness_variance_u_mm2 * 1e6
      << " um^2); " << to_string(r.roughness_status);
  if (r.roughness_status == RoughnessStatus::not_significant)
    src << " (clamped at 0 if negative; upper bound " << r.roughness_upper_bound_mm * kUmPerMm
        << " um)";
  else
    src << " (u(sigma) " << r.roughness.u_mm * kUmPerMm << " um)";
  return nlohmann::json{{"source", src.str()}, {"sigma_um", r.roughness.sigma_mm * kUmPerMm}};
}

}  // namespace

// ---- reference profile ----

void validate_reference_profile(const ReferenceProfile& profile, const char* caller) {
  const std::string prefix = std::string(caller) + ": reference";
  geometry::validate_roundness_profile(profile, prefix.c_str());
  check_equiangular(profile, prefix + ": ");
  check_reference_range(profile, prefix + ": ");
}

ReferenceProfile read_reference_profile_csv(std::istream& in, const std::string& source) {
  ReferenceProfile p = geometry::read_roundness_profile_csv(in, source);
  check_equiangular(p, "");
  check_reference_range(p, "");
  return p;
}

ReferenceProfile read_reference_profile_csv_file(const std::string& path) {
  ReferenceProfile p = geometry::read_roundness_profile_csv_file(path);
  check_equiangular(p, "");
  check_reference_range(p, "");
  return p;
}

std::vector<double> reference_deviation_mm(const ReferenceProfile& profile,
                                           std::span<const double> angle_rad, int max_order) {
  validate_reference_profile(profile, "reference_deviation_mm");
  for (std::size_t i = 0; i < angle_rad.size(); ++i)
    if (!std::isfinite(angle_rad[i]))
      throw InvalidInput("reference_deviation_mm: angle " + std::to_string(i) + " is not finite (" +
                         number(angle_rad[i]) + ")");
  const ReferenceSeries s = reference_series(profile, max_order);
  std::vector<double> out(angle_rad.size());
  for (std::size_t i = 0; i < angle_rad.size(); ++i) out[i] = evaluate_series(s, angle_rad[i]);
  return out;
}

// ---- variance factor and coverage factor ----

double sigma_coverage_factor(double nu) {
  if (!std::isfinite(nu) || nu < 1.0)
    throw InvalidInput(
        "sigma_coverage_factor: the degrees of freedom must be finite and >= 1; "
        "got " +
        number(nu));
  const double target = std::erf(std::numbers::sqrt2);  // P(|z| ≤ 2), 95.45 %
  // The coverage rises with k; at k = 1 it is below the target (it tends to it from below as
  // ν → ∞). Bracket by doubling, then bisect.
  double lo = 1.0, hi = 2.0;
  if (sigma_coverage(nu, lo) >= target) return 1.0;
  while (sigma_coverage(nu, hi) < target) {
    lo = hi;
    hi *= 2.0;
  }
  for (int it = 0; it < 100 && hi - lo > 1e-10; ++it) {
    const double mid = 0.5 * (lo + hi);
    (sigma_coverage(nu, mid) < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

HighPassNoiseFactor high_pass_noise_factor(std::size_t n, double cutoff_upr) {
  if (n < 8)
    throw InvalidInput("high_pass_noise_factor: needs n >= 8 points; got " + std::to_string(n));
  check_cutoff(cutoff_upr, n, "high_pass_noise_factor");
  double sum = 0.0, sum2 = 0.0, low = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t kk = std::min(k, n - k);
    if (kk <= 1) continue;  // removed by the least-squares circle
    const double ratio = static_cast<double>(kk) / cutoff_upr;
    const double h = std::exp2(-ratio * ratio);
    const double lambda = (1.0 - h) * (1.0 - h);
    sum += lambda;
    sum2 += lambda * lambda;
    low += h * h;
  }
  const double nd = static_cast<double>(n);
  return {sum / nd, sum * sum / sum2, low / nd};
}

// ---- estimates ----

ScanNoiseResult scanning_noise(std::span<const Point2> scan, const ReferenceProfile& reference,
                               const ScanNoiseOptions& options) {
  constexpr const char* kCaller = "scanning_noise";
  validate_reference_profile(reference, kCaller);
  const PreparedProfile p = prepare_scan(scan, kCaller);
  return scan_core(p, reference, options, kCaller, nullptr);
}

TouchNoiseResult touch_trigger_noise(std::span<const Point2> points,
                                     const ReferenceProfile& reference, double phase_rad,
                                     const SystematicProfile* scan_systematics) {
  constexpr const char* kCaller = "touch_trigger_noise";
  validate_reference_profile(reference, kCaller);
  geometry::validate_profile(points, 5, kCaller);
  if (!std::isfinite(phase_rad))
    throw InvalidInput(std::string(kCaller) + ": the phase must be finite; got " +
                       number(phase_rad));
  if (scan_systematics) check_systematic_profile(*scan_systematics, kCaller);
  const geometry::LeastSquaresCircle ls0 = geometry::least_squares_circle(points);
  const PreparedProfile p0 = prepare(points, ls0);
  const ReferenceSeries series = reference_series(reference, 1 << 30);
  // Subtract the reference along the radius from the first centre, then refit.
  std::vector<Point2> corrected(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    double r = p0.radius + p0.e[i] - evaluate_series(series, p0.theta[i] - phase_rad);
    if (scan_systematics) r -= interpolate(*scan_systematics, p0.theta[i]);
    corrected[i] = {ls0.center.x + r * std::cos(p0.theta[i]),
                    ls0.center.y + r * std::sin(p0.theta[i])};
  }
  const geometry::LeastSquaresCircle ls = geometry::least_squares_circle(corrected);
  const PreparedProfile p = prepare(corrected, ls);
  TouchNoiseResult out;
  out.points = points.size();
  out.phase_rad = phase_rad;
  out.center_mm = ls.center;
  out.radius_mm = ls.radius;
  out.residuals_mm = p.e;
  double ss = 0.0;
  for (double x : p.e) ss += x * x;
  const double nu = static_cast<double>(points.size()) - 3.0;
  out.scan_systematics_removed = scan_systematics != nullptr;
  out.scan_noise_variance_mm2 = scan_systematics ? scan_systematics->noise_variance_mm2 : 0.0;
  out.sigma = sigma_from_variance(ss / nu - out.scan_noise_variance_mm2, nu);
  {
    Eigen::MatrixXd j(static_cast<Eigen::Index>(points.size()), 3);
    for (std::size_t i = 0; i < points.size(); ++i)
      j.row(static_cast<Eigen::Index>(i)) << std::cos(p.theta[i]), std::sin(p.theta[i]), 1.0;
    out.consistency = residual_outliers(p.e, p.theta, std::sqrt(ss / nu), nu, leverages(j));
  }
  return out;
}

std::string_view to_string(RoughnessStatus status) {
  return status == RoughnessStatus::identified ? "identified" : "not_significant";
}

RepeatedScanResult repeated_scan_noise(std::span<const Point2> scan, std::span<const Point2> repeat,
                                       const ReferenceProfile& reference,
                                       const ScanNoiseOptions& options) {
  constexpr const char* kCaller = "repeated_scan_noise";
  validate_reference_profile(reference, kCaller);
  const PreparedProfile p1 = prepare_scan(scan, kCaller);
  const PreparedProfile p2 = prepare_scan(repeat, kCaller);
  const std::size_t n = p1.theta.size();
  if (p2.theta.size() != n)
    throw InvalidInput(std::string(kCaller) +
                       ": the repeat scan must have the same points as "
                       "the first (same track); got " +
                       std::to_string(p2.theta.size()) + " vs " + std::to_string(n) + " points");
  const double step = kTwoPi / static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i)
    if (!(std::abs(wrap(p2.theta[i] - p1.theta[i])) <= 0.25 * step))
      throw InvalidInput(std::string(kCaller) +
                         ": the repeat scan must sample the same angles "
                         "(same track, same start, same sense); point " +
                         std::to_string(i) + " differs by " +
                         number(wrap(p2.theta[i] - p1.theta[i]) / step) + " steps");
  // A scan given twice (the same file, or a copy) would give σ_noise = 0 and call the whole
  // scatter roughness.
  bool identical = true;
  for (std::size_t i = 0; i < n && identical; ++i)
    identical = scan[i].x == repeat[i].x && scan[i].y == repeat[i].y;
  if (identical)
    throw InvalidInput(std::string(kCaller) +
                       ": the repeat scan is point for point identical to the first: one scan "
                       "given twice; the repeat must be a second measurement of the track");
  RepeatedScanResult out;
  std::vector<double> g;
  out.first = scan_core(p1, reference, options, kCaller, &g);
  const double cutoff = options.cutoff_upr;
  std::vector<double> diff(n), mean(n);
  for (std::size_t i = 0; i < n; ++i) {
    diff[i] = p1.e[i] - p2.e[i];
    mean[i] = 0.5 * (p1.e[i] + p2.e[i]) - g[i];
  }
  const HighPassNoiseFactor f = out.first.factor;
  const double lambda = f.variance_factor * static_cast<double>(n), nu = f.degrees_of_freedom;
  std::vector<double> low_mean;
  std::vector<double> low_diff;
  const double s_minus = high_pass_sum_squares(diff, cutoff, &low_diff) / lambda;  // 2 σ_n²
  const double s_plus = high_pass_sum_squares(mean, cutoff, &low_mean) / lambda;  // σ_r² + σ_n²/2
  if (!(s_minus > 0.0))
    throw InvalidInput(std::string(kCaller) +
                       ": the two scans do not differ above the cut-off (noise sigma 0): the same "
                       "measurement given twice?");
  out.systematic = systematic_profile(p1.theta, low_mean, s_plus * f.low_pass_variance_factor);
  out.noise = sigma_from_variance(0.5 * s_minus, nu);
  out.difference_consistency = high_pass_outliers(diff, low_diff, p1.theta, s_minus, f.variance_factor);
  const double var_r = s_plus - 0.25 * s_minus;
  const double u_var =
      std::sqrt(2.0 * s_plus * s_plus / nu + 2.0 * (0.25 * s_minus) * (0.25 * s_minus) / nu);
  out.roughness_variance_mm2 = var_r;
  out.roughness_variance_u_mm2 = u_var;
  out.roughness_upper_bound_mm = std::sqrt(std::max(var_r + 2.0 * u_var, 0.0));
  out.roughness.degrees_of_freedom = nu;
  out.roughness.sigma_mm = std::sqrt(std::max(var_r, 0.0));
  if (var_r >= 2.0 * u_var) {
    out.roughness_status = RoughnessStatus::identified;
    out.roughness.u_mm = u_var / (2.0 * out.roughness.sigma_mm);
  } else {
    // Not significant: the delta method breaks down near 0; √u(σ²) is the σ at which a
    // variance of one standard uncertainty would be seen.
    out.roughness_status = RoughnessStatus::not_significant;
    out.roughness.u_mm = std::sqrt(u_var);
  }
  return out;
}

// ---- sections ----

std::string noise_section_json(const NoiseCharacterization& c,
                               std::optional<double> fallback_scanning_sigma_mm,
                               std::optional<double> fallback_touch_sigma_mm) {
  const nlohmann::json sec = noise_section(c, fallback_scanning_sigma_mm, fallback_touch_sigma_mm);
  internal::require_finite_numbers(sec, inputs_text(c), "noise");
  return sec.dump(2);
}

std::optional<std::string> roughness_section_json(const NoiseCharacterization& c) {
  const auto s = roughness_section(c);
  if (!s) return std::nullopt;
  return s->dump(2);
}

std::string noise_characterization_json(const NoiseCharacterization& c,
                                        std::optional<double> fallback_scanning_sigma_mm,
                                        std::optional<double> fallback_touch_sigma_mm,
                                        bool accepted_inconsistent) {
  nlohmann::json out;
  out["noise"] = noise_section(c, fallback_scanning_sigma_mm, fallback_touch_sigma_mm);
  if (const auto r = roughness_section(c)) out["roughness"] = *r;
  nlohmann::json d;
  d["method"] =
      "CMM profile minus reference profile; Gaussian high-pass (scanning) or "
      "least-squares circle (touch); docs/characterization.md";
  d["reference"] = c.reference_source;
  if (c.scan) {
    d["scan"] = scan_json(*c.scan, c.scan_source);
    d["scan"]["consistency"] =
        internal::consistency_json<nlohmann::json>(c.scan->consistency, accepted_inconsistent);
  }
  if (c.repeated) {
    const RepeatedScanResult& r = *c.repeated;
    d["scan"] = scan_json(r.first, c.scan_source);
    d["scan"]["consistency"] =
        internal::consistency_json<nlohmann::json>(r.first.consistency, accepted_inconsistent);
    d["scan"]["note"] = "single-scan sigma: noise and roughness together";
    d["repeat"] = {{"file", c.repeat_source},
                   {"noise_from_difference", sigma_json(r.noise)},
                   {"roughness", sigma_json(r.roughness)},
                   {"roughness_status", std::string(to_string(r.roughness_status))},
                   {"roughness_variance_um2", r.roughness_variance_mm2 * 1e6},
                   {"roughness_variance_uncertainty_um2", r.roughness_variance_u_mm2 * 1e6},
                   {"roughness_upper_bound_um", r.roughness_upper_bound_mm * kUmPerMm},
                   {"consistency", internal::consistency_json<nlohmann::json>(
                                       r.difference_consistency, accepted_inconsistent)}};
  } else if (c.scan) {
    d["roughness"] =
        "not identifiable from a single scan (noise and roughness are both white "
        "along the track); give a repeat scan of the same track";
  }
  if (c.touch)
    d["touch"] = {{"file", c.touch_source},
                  {"points", c.touch->points},
                  {"estimate", sigma_json(c.touch->sigma)},
                  {"phase_deg", c.touch->phase_rad * 180.0 / kPi},
                  {"scan_systematics_removed", c.touch->scan_systematics_removed},
                  {"scan_noise_variance_um2", c.touch->scan_noise_variance_mm2 * 1e6},
                  {"center_mm", {c.touch->center_mm.x, c.touch->center_mm.y}},
                  {"radius_mm", c.touch->radius_mm},
                  {"consistency", internal::consistency_json<nlohmann::json>(
                                      c.touch->consistency, accepted_inconsistent)}};
  out["characterization"] = d;
  internal::require_finite_numbers(out, inputs_text(c));
  return out.dump(2) + "\n";
}

}  // namespace vcmm::characterization
