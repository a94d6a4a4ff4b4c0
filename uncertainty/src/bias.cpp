// Bias estimate and correction with the non-negativity guard; formulas in
// vcmm/uncertainty/bias.h and docs/uncertainty.md.
#include "vcmm/uncertainty/bias.h"

#include <algorithm>
#include <cmath>
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
    c.note = "Bias correction refused: the bias " + format_short(c.bias) +
             " exceeds the estimate " + format_short(estimate) +
             " and would make a non-negative quantity negative, so the estimate is reported "
             "uncorrected with u enlarged by |b| and the Monte Carlo interval widened by |b|.";
    return c;
  }
  c.applied = true;
  c.corrected = corrected;
  c.standard_uncertainty = std::hypot(u, c.bias_standard_error);
  c.interval.low = 2.0 * estimate - mc.high;
  c.interval.high = 2.0 * estimate - mc.low;
  c.note = "Bias " + format_short(c.bias) + " (Monte Carlo mean minus estimate, standard error " +
           format_short(c.bias_standard_error) +
           ") subtracted; the interval is the Monte Carlo interval reflected about the estimate";
  if (non_negative && c.interval.low < 0.0) {
    c.interval.low = 0.0;
    c.note += ", its lower end clamped at 0 for this non-negative quantity";
  }
  c.note += ".";
  return c;
}

}  // namespace vcmm::uncertainty
