// JCGM 101 summaries (7.6, 7.7) and correlation matrices; formulas and numerics in
// vcmm/uncertainty/statistics.h.
#include "vcmm/uncertainty/statistics.h"

#include "internal/format.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "vcmm/uncertainty/errors.h"

namespace vcmm::uncertainty {
namespace {

/// Neumaier's compensated sum: error bounded by ~2 ulp of the sum plus O(n ε²) Σ|x|,
/// independent of n to first order (Higham, Accuracy and Stability, 2nd ed., 4.3).
class CompensatedSum {
 public:
  void add(double x) {
    const double t = sum_ + x;
    if (std::abs(sum_) >= std::abs(x)) {
      compensation_ += (sum_ - t) + x;
    } else {
      compensation_ += (x - t) + sum_;
    }
    sum_ = t;
  }
  double value() const { return sum_ + compensation_; }

 private:
  double sum_ = 0.0;
  double compensation_ = 0.0;
};

using internal::format_double;

void check_probability(double p, const char* caller) {
  if (!(p > 0.0 && p < 1.0)) {
    throw InvalidInput(std::string(caller) + ": coverage probability must be in (0, 1); got " +
                       format_double(p));
  }
}

// Mean and standard uncertainty (two-pass, compensated), values in index order.
void mean_and_uncertainty(const std::vector<double>& y, MeasurandSummary& s) {
  const double m = static_cast<double>(y.size());
  CompensatedSum sum;
  for (const double v : y) sum.add(v);
  s.mean = sum.value() / m;
  if (y.size() < 2) {
    s.standard_uncertainty = 0.0;
    return;
  }
  CompensatedSum d1, d2;
  for (const double v : y) {
    const double d = v - s.mean;
    d1.add(d);
    d2.add(d * d);
  }
  const double c = d1.value();
  const double variance = std::max(0.0, (d2.value() - c * c / m) / (m - 1.0));
  s.standard_uncertainty = std::sqrt(variance);
}

// Summary of finite values given in index order (consumed: sorted in place).
MeasurandSummary summarize_values(std::vector<double>& y, double p, const char* caller) {
  const std::uint64_t m = y.size();
  const std::uint64_t q = coverage_index(m, p);
  if (q < 1 || q > m - 1) {
    throw InvalidInput(std::string(caller) + ": too few samples for a " + format_double(100.0 * p) +
                       " % coverage interval (JCGM 101 7.7.1 needs 1 <= q = round(pM) <= M - 1, "
                       "i.e. M >= " + std::to_string(minimum_sample_count(p)) + "); got M = " +
                       std::to_string(m));
  }
  MeasurandSummary s;
  s.count = m;
  mean_and_uncertainty(y, s);
  std::sort(y.begin(), y.end());
  // 1-based order statistics y_(k) = y[k − 1].
  const std::uint64_t r = (m - q + 1) / 2;  // (M − q)/2 if even, else ⌊(M − q + 1)/2⌋
  s.probabilistically_symmetric = {y[r - 1], y[r + q - 1], p};
  std::uint64_t best = 1;
  double best_width = y[q] - y[0];
  for (std::uint64_t k = 2; k <= m - q; ++k) {
    const double width = y[k + q - 1] - y[k - 1];
    if (width < best_width) {
      best_width = width;
      best = k;
    }
  }
  s.shortest = {y[best - 1], y[best + q - 1], p};
  return s;
}

}  // namespace

std::uint64_t coverage_index(std::uint64_t sample_count, double coverage_probability) {
  check_probability(coverage_probability, "coverage_index");
  const double pm = coverage_probability * static_cast<double>(sample_count);
  if (pm == std::floor(pm)) return static_cast<std::uint64_t>(pm);
  return static_cast<std::uint64_t>(std::floor(pm + 0.5));
}

std::uint64_t minimum_sample_count(double coverage_probability) {
  check_probability(coverage_probability, "minimum_sample_count");
  const double p = coverage_probability;
  // q ≥ 1 needs pM ≳ ½ and q ≤ M − 1 needs (1 − p)M ≳ ½; both conditions are monotone in M
  // (q grows by 0 or 1 when M grows by 1), so step up from just below the estimate.
  const double estimate = std::max(0.5 / p, 0.5 / (1.0 - p));
  // Beyond 2⁶² the count is not a number of trials anyone can run, and the cast below would
  // overflow (undefined behaviour): refuse, saying how many trials p would need.
  constexpr double kLimit = 4611686018427387904.0;  // 2⁶²
  if (!(estimate < kLimit)) {
    std::ostringstream os;
    os.precision(3);
    os << "minimum_sample_count: coverage probability " << p << " needs about " << 2.0 * estimate
       << " trials for a coverage interval (more than 2^62): use p between 1e-6 and 1 - 1e-6";
    throw InvalidInput(os.str());
  }
  std::uint64_t m = estimate > 8.0 ? static_cast<std::uint64_t>(estimate) - 4 : 1;
  for (;; ++m) {
    const std::uint64_t q = coverage_index(m, p);
    if (q >= 1 && q + 1 <= m) return m;
  }
}

MeasurandSummary summarize(std::span<const double> samples, double coverage_probability) {
  check_probability(coverage_probability, "summarize");
  if (samples.empty()) throw InvalidInput("summarize: samples must not be empty; got 0 samples");
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!std::isfinite(samples[i])) {
      throw InvalidInput("summarize: samples must be finite; sample " + std::to_string(i) +
                         " is " + format_double(samples[i]));
    }
  }
  std::vector<double> y(samples.begin(), samples.end());
  return summarize_values(y, coverage_probability, "summarize");
}

MeasurandSummary summarize_measurand(std::span<const double> samples, std::size_t q,
                                     std::size_t measurand, double coverage_probability) {
  check_probability(coverage_probability, "summarize_measurand");
  if (q == 0) throw InvalidInput("summarize_measurand: measurand count q must be >= 1; got 0");
  if (measurand >= q) {
    throw InvalidInput("summarize_measurand: measurand index must be < q = " + std::to_string(q) +
                       "; got " + std::to_string(measurand));
  }
  if (samples.empty() || samples.size() % q != 0) {
    throw InvalidInput("summarize_measurand: samples.size() must be a positive multiple of q = " +
                       std::to_string(q) + "; got " + std::to_string(samples.size()));
  }
  const std::size_t m = samples.size() / q;
  std::vector<double> y(m);
  for (std::size_t t = 0; t < m; ++t) {
    y[t] = samples[t * q + measurand];
    if (!std::isfinite(y[t])) {
      throw InvalidInput("summarize_measurand: samples must be finite; trial " + std::to_string(t) +
                         ", measurand " + std::to_string(measurand) + " is " + format_double(y[t]));
    }
  }
  return summarize_values(y, coverage_probability, "summarize_measurand");
}

std::vector<double> correlation_matrix(std::span<const double> samples, std::size_t q) {
  if (q == 0) throw InvalidInput("correlation_matrix: measurand count q must be >= 1; got 0");
  if (samples.size() % q != 0 || samples.size() / q < 2) {
    throw InvalidInput("correlation_matrix: samples.size() must be a multiple of q = " +
                       std::to_string(q) + " with at least 2 trials; got " +
                       std::to_string(samples.size()) + " values");
  }
  const std::size_t m = samples.size() / q;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!std::isfinite(samples[i])) {
      throw InvalidInput("correlation_matrix: samples must be finite; trial " + std::to_string(i / q) +
                         ", measurand " + std::to_string(i % q) + " is " + format_double(samples[i]));
    }
  }
  std::vector<double> mean(q);
  for (std::size_t j = 0; j < q; ++j) {
    CompensatedSum s;
    for (std::size_t t = 0; t < m; ++t) s.add(samples[t * q + j]);
    mean[j] = s.value() / static_cast<double>(m);
  }
  // Upper triangle of Σ (y_j − ỹ_j)(y_k − ỹ_k); q is small (a handful of measurands).
  std::vector<CompensatedSum> cross(q * q);
  std::vector<double> d(q);
  for (std::size_t t = 0; t < m; ++t) {
    for (std::size_t j = 0; j < q; ++j) d[j] = samples[t * q + j] - mean[j];
    for (std::size_t j = 0; j < q; ++j) {
      for (std::size_t k = j; k < q; ++k) cross[j * q + k].add(d[j] * d[k]);
    }
  }
  std::vector<double> r(q * q, 0.0);
  for (std::size_t j = 0; j < q; ++j) {
    r[j * q + j] = 1.0;
    const double sjj = cross[j * q + j].value();
    for (std::size_t k = j + 1; k < q; ++k) {
      const double skk = cross[k * q + k].value();
      double c = 0.0;
      if (sjj > 0.0 && skk > 0.0) {
        c = std::clamp(cross[j * q + k].value() / (std::sqrt(sjj) * std::sqrt(skk)), -1.0, 1.0);
      }
      r[j * q + k] = c;
      r[k * q + j] = c;
    }
  }
  return r;
}

}  // namespace vcmm::uncertainty
