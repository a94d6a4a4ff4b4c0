// Bias estimate and correction with the non-negativity guard; formulas in
// vcmm/uncertainty/bias.h and docs/uncertainty.md.
#include "vcmm/uncertainty/bias.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "internal/format.h"
#include "vcmm/uncertainty/errors.h"

namespace vcmm::uncertainty {
namespace {

using internal::format_double;
using internal::format_short;

void require_finite(double x, const char* name) {
  if (!std::isfinite(x)) {
    throw InvalidInput(std::string("correct_bias: ") + name + " must be finite; got " +
                       format_double(x));
  }
}

}  // namespace

BiasCorrection correct_bias(double estimate, const MeasurandSummary& summary, bool non_negative) {
  require_finite(estimate, "estimate");
  require_finite(summary.mean, "summary.mean");
  require_finite(summary.standard_uncertainty, "summary.standard_uncertainty");
  const CoverageInterval& mc = summary.probabilistically_symmetric;
  require_finite(mc.low, "summary.probabilistically_symmetric.low");
  require_finite(mc.high, "summary.probabilistically_symmetric.high");
  if (summary.count == 0) throw InvalidInput("correct_bias: summary.count must be >= 1; got 0");
  if (summary.standard_uncertainty < 0.0) {
    throw InvalidInput("correct_bias: summary.standard_uncertainty must be >= 0; got " +
                       format_double(summary.standard_uncertainty));
  }
  if (mc.low > mc.high) {
    throw InvalidInput("correct_bias: the interval needs low <= high; got [" + format_double(mc.low) +
                       ", " + format_double(mc.high) + "]");
  }
  if (non_negative && estimate < 0.0) {
    throw InvalidInput("correct_bias: a non-negative quantity needs estimate >= 0; got " +
                       format_double(estimate));
  }

  const double u = summary.standard_uncertainty;
  BiasCorrection c;
  c.estimate = estimate;
  c.monte_carlo_mean = summary.mean;
  c.bias = summary.mean - estimate;
  c.bias_standard_error = u / std::sqrt(static_cast<double>(summary.count));
  const double corrected = estimate - c.bias;
  c.interval.probability = mc.probability;

  if (non_negative && corrected < 0.0) {
    const double b = std::abs(c.bias);
    c.refused = true;
    c.applied = false;
    c.corrected = estimate;
    c.standard_uncertainty = std::hypot(u, b);
    c.interval.low = std::max(0.0, mc.low - b);
    c.interval.high = mc.high + b;
    c.corrected_unclamped = corrected;
    c.note = describe(c);
    return c;
  }
  c.applied = true;
  c.corrected = corrected;
  c.standard_uncertainty = std::hypot(u, c.bias_standard_error);
  c.interval.low = 2.0 * estimate - mc.high;
  c.interval.high = 2.0 * estimate - mc.low;
  c.corrected_unclamped = corrected;
  if (non_negative && c.interval.low < 0.0) {
    c.interval.low = 0.0;
    c.interval_low_clamped = true;
  }
  c.note = describe(c);
  return c;
}

}  // namespace vcmm::uncertainty

namespace vcmm::uncertainty {

double standard_normal_quantile(double p) {
  if (!(p > 0.0 && p < 1.0))
    throw InvalidInput("standard_normal_quantile: p must lie in (0, 1); got " +
                       internal::format_double(p));
  // Acklam's rational approximation (relative error < 1.15e-9), then one Halley step.
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,
                                 -2.759285104469687e+02, 1.383577518672690e+02,
                                 -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02,
                                 -1.556989798598866e+02, 6.680131188771972e+01,
                                 -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01,
                                 -2.400758277161838e+00, -2.549732539343734e+00,
                                 4.374664141464968e+00, 2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01,
                                 2.445134137142996e+00, 3.754408661907416e+00};
  constexpr double low = 0.02425;
  double x = 0.0;
  if (p < low) {
    const double q = std::sqrt(-2.0 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  } else if (p <= 1.0 - low) {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
  } else {
    const double q = std::sqrt(-2.0 * std::log1p(-p));
    x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  }
  // Halley: e = Φ(x) − p with Φ(x) = erfc(−x/√2)/2.
  const double e = 0.5 * std::erfc(-x / std::numbers::sqrt2) - p;
  const double u = e * std::sqrt(2.0 * std::numbers::pi) * std::exp(0.5 * x * x);
  return x - u / (1.0 + 0.5 * x * u);
}

namespace {

/// Upper end q of the interval [0, q] of probability p of N(mean, u²) truncated to [0, ∞):
/// P(0 ≤ X ≤ q) = p · P(X ≥ 0), i.e. the upper tail beyond q is (1 − p) · Q(−mean/u). Where
/// that tail underflows (mean below 0 by more than ~37 u) the truncated normal is an
/// exponential of rate |mean|/u² to first order: q = u² ln(1/(1 − p)) / |mean|. u = 0: 0.
double truncated_normal_upper_end(double mean, double u, double p) {
  if (!(u > 0.0)) return std::max(mean, 0.0);
  const double above_zero = 0.5 * std::erfc(-mean / (u * std::sqrt(2.0)));
  const double tail = (1.0 - p) * above_zero;
  if (tail > 1e-300) return std::max(0.0, mean - u * standard_normal_quantile(tail));
  return u * u * std::log(1.0 / (1.0 - p)) / std::fabs(mean);
}

}  // namespace

BiasCorrection correct_bias_at_surrogate(double estimate, double surrogate_value,
                                         const MeasurandSummary& at_surrogate,
                                         const MeasurandSummary& surrogate_spread,
                                         bool non_negative) {
  const auto finite = [](double x, const char* name) {
    if (!std::isfinite(x))
      throw InvalidInput(std::string("correct_bias_at_surrogate: ") + name +
                         " must be finite; got " + internal::format_double(x));
  };
  finite(estimate, "estimate");
  finite(surrogate_value, "surrogate_value");
  finite(at_surrogate.mean, "at_surrogate.mean");
  finite(at_surrogate.standard_uncertainty, "at_surrogate.standard_uncertainty");
  finite(surrogate_spread.standard_uncertainty, "surrogate_spread.standard_uncertainty");
  const CoverageInterval& mc = at_surrogate.probabilistically_symmetric;
  finite(mc.low, "at_surrogate.probabilistically_symmetric.low");
  finite(mc.high, "at_surrogate.probabilistically_symmetric.high");
  if (at_surrogate.count == 0 || surrogate_spread.count == 0)
    throw InvalidInput("correct_bias_at_surrogate: both summaries need count >= 1; got " +
                       std::to_string(at_surrogate.count) + " and " +
                       std::to_string(surrogate_spread.count));
  if (at_surrogate.standard_uncertainty < 0.0 || surrogate_spread.standard_uncertainty < 0.0)
    throw InvalidInput("correct_bias_at_surrogate: standard uncertainties must be >= 0");
  if (mc.low > mc.high)
    throw InvalidInput("correct_bias_at_surrogate: the interval needs low <= high; got [" +
                       internal::format_double(mc.low) + ", " +
                       internal::format_double(mc.high) + "]");
  if (non_negative && (estimate < 0.0 || surrogate_value < 0.0))
    throw InvalidInput(
        "correct_bias_at_surrogate: a non-negative quantity needs estimate and surrogate "
        "value >= 0; got " + internal::format_double(estimate) + " and " +
        internal::format_double(surrogate_value));

  const double u = at_surrogate.standard_uncertainty;
  const double ub = surrogate_spread.standard_uncertainty;
  BiasCorrection c;
  c.estimate = estimate;
  c.monte_carlo_mean = at_surrogate.mean;
  c.bias = at_surrogate.mean - surrogate_value;
  c.bias_standard_error = u / std::sqrt(static_cast<double>(at_surrogate.count));
  c.bias_uncertainty = ub;
  c.applied = true;
  c.corrected = estimate - c.bias;
  c.standard_uncertainty = std::sqrt(u * u + ub * ub + c.bias_standard_error * c.bias_standard_error);
  const double kp = standard_normal_quantile(0.5 * (1.0 + mc.probability));
  c.interval.probability = mc.probability;
  const double corrected_raw = c.corrected;
  if (non_negative && c.corrected < 0.0) {
    c.clamped = true;
    c.corrected = 0.0;
  }
  c.interval.low = corrected_raw - std::hypot(mc.high - at_surrogate.mean, kp * ub);
  c.interval.high = corrected_raw + std::hypot(at_surrogate.mean - mc.low, kp * ub);
  c.at_surrogate = true;
  c.surrogate_value = surrogate_value;
  c.corrected_unclamped = corrected_raw;
  if (non_negative && c.interval.low < 0.0) {
    c.interval.low = 0.0;
    c.interval_low_clamped = true;
    // Far below 0 the reflected interval can end below 0 too ([0, negative] is no interval):
    // its upper end is then at least that of N(corrected, u_c) truncated to [0, ∞).
    const double floor_high =
        truncated_normal_upper_end(corrected_raw, c.standard_uncertainty, mc.probability);
    if (c.interval.high < floor_high) {
      c.interval.high = floor_high;
      c.interval_high_truncated = true;
    }
  }
  c.note = describe(c);
  return c;
}

std::string describe(const BiasCorrection& c, double scale, std::string_view unit) {
  const auto q = [&](double x) {
    std::string t = format_short(x * scale);
    if (!unit.empty()) (t += ' ') += unit;
    return t;
  };
  std::string n;
  if (c.refused) {
    return "Bias correction refused: the bias " + q(c.bias) + " exceeds the estimate " +
           q(c.estimate) +
           " and would make a non-negative quantity negative, so the estimate is reported "
           "uncorrected with u enlarged by |b| and the Monte Carlo interval widened by |b|.";
  }
  if (c.at_surrogate) {
    n = "Bias " + q(c.bias) +
        " evaluated at the surrogate truth (Monte Carlo mean there minus its value " +
        q(c.surrogate_value) + ") subtracted; its own uncertainty " + q(c.bias_uncertainty) +
        " is a component of u";
    if (c.clamped)
      n += "; the corrected value " + q(c.corrected_unclamped) + " was below 0 and is reported as 0";
    if (c.interval_low_clamped) n += "; the interval's lower end clamped at 0";
    if (c.interval_high_truncated)
      n += ", its upper end that of the normal distribution of the corrected value truncated at 0";
  } else {
    n = "Bias " + q(c.bias) + " (Monte Carlo mean minus estimate, standard error " +
        q(c.bias_standard_error) +
        ") subtracted; the interval is the Monte Carlo interval reflected about the estimate";
    if (c.interval_low_clamped) n += ", its lower end clamped at 0 for this non-negative quantity";
  }
  return n + ".";
}

}  // namespace vcmm::uncertainty
