// Consistency of calibration residuals with their stated uncertainties: χ² / Birge ratio and
// the Bonferroni-corrected outlier test (notation and sources in consistency.h).
#include "vcmm/characterization/consistency.h"

#include <Eigen/QR>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <string>

namespace vcmm::characterization {
namespace {

// A residual whose leverage is this close to 1 is fitted exactly by construction (an
// observation that alone fixes an unknown): its residual is 0 ± rounding and carries no test.
constexpr double kExactlyFitted = 1e-9;

std::string num(double v, const char* format = "%.3g") {
  char buf[40];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

[[noreturn]] void fail(const std::string& what) {
  throw std::invalid_argument("test_consistency: " + what);
}

std::string name_of(const ResidualOutlier& o) {
  std::string s = o.group;
  if (!o.where.empty()) s += (s.empty() ? "" : ": ") + o.where;
  return s;
}

}  // namespace

ConsistencyTest test_consistency(std::span<const FitResidual> residuals, double nu,
                                 bool sigma_stated, ConsistencyLevels levels) {
  for (double a : {levels.chi_squared, levels.outlier})
    if (!(a > 0.0 && a < 0.5)) fail("levels must lie in (0, 0.5); got " + num(a));
  if (!std::isfinite(nu) || nu < 0.0 || nu > static_cast<double>(residuals.size()))
    fail("degrees of freedom must lie in [0, " + std::to_string(residuals.size()) + "]; got " +
         num(nu));
  ConsistencyTest t;
  t.sigma_stated = sigma_stated;
  t.levels = levels;
  t.degrees_of_freedom = nu;
  std::map<std::string, GroupShare> groups;
  std::vector<double> w(residuals.size(), 0.0);
  std::vector<char> testable(residuals.size(), 0);
  for (std::size_t i = 0; i < residuals.size(); ++i) {
    const FitResidual& r = residuals[i];
    if (!std::isfinite(r.value)) fail("residual " + std::to_string(i) + " is not finite");
    if (!std::isfinite(r.uncertainty) || !(r.uncertainty > 0.0))
      fail("the uncertainty of residual " + std::to_string(i) + " must be finite and > 0; got " +
           num(r.uncertainty));
    if (!(r.leverage >= -kExactlyFitted && r.leverage <= 1.0 + kExactlyFitted))
      fail("the leverage of residual " + std::to_string(i) + " must lie in [0, 1]; got " +
           num(r.leverage));
    const double z = r.value / r.uncertainty;
    t.chi_squared += z * z;
    GroupShare& g = groups[r.group];
    g.group = r.group;
    ++g.residuals;
    g.chi_squared += z * z;
    const double one_minus_h = 1.0 - std::clamp(r.leverage, 0.0, 1.0);
    if (one_minus_h > kExactlyFitted) {
      w[i] = z / std::sqrt(one_minus_h);
      testable[i] = 1;
      ++t.tested;
    }
  }
  for (auto& [name, g] : groups) t.groups.push_back(g);
  std::stable_sort(t.groups.begin(), t.groups.end(),
                   [](const GroupShare& a, const GroupShare& b) { return a.chi_squared > b.chi_squared; });

  // χ² test (only with stated σ: otherwise χ² = ν by construction of the estimated scale).
  if (nu > 0.0) t.birge_ratio = std::sqrt(t.chi_squared / nu);
  if (sigma_stated && nu > 0.0) {
    const boost::math::chi_squared_distribution<double> chi2(nu);
    t.p_value = boost::math::cdf(boost::math::complement(chi2, t.chi_squared));
    t.chi_squared_passed = t.p_value >= levels.chi_squared;
  }

  // Outlier test, Bonferroni over the tested residuals.
  if (t.tested == 0) return t;
  const double tail = levels.outlier / (2.0 * static_cast<double>(t.tested));
  std::vector<double> stat(residuals.size(), 0.0);
  if (sigma_stated) {
    t.outlier_threshold =
        boost::math::quantile(boost::math::complement(boost::math::normal_distribution<double>(), tail));
    stat = w;
  } else {
    if (nu < 2.0) {
      t.tested = 0;
      return t;
    }
    // Σ w_j²(1 − h_jj) = χ² (the weighted residual sum); s_(i)² removes observation i.
    const double s2 = t.chi_squared / nu;
    t.outlier_threshold = boost::math::quantile(
        boost::math::complement(boost::math::students_t_distribution<double>(nu - 1.0), tail));
    for (std::size_t i = 0; i < residuals.size(); ++i) {
      if (!testable[i]) continue;
      const double rest = std::max((nu * s2 - w[i] * w[i]) / (nu - 1.0), 0.0);
      // rest = 0: every other residual is 0; the statistic is unbounded, shown as 1e300.
      stat[i] = rest > 0.0 ? w[i] / std::sqrt(rest) : std::copysign(1e300, w[i]);
    }
  }
  std::vector<ResidualOutlier> found;
  for (std::size_t i = 0; i < residuals.size(); ++i) {
    if (!testable[i]) continue;
    ResidualOutlier o{i, residuals[i].group, residuals[i].where, residuals[i].value,
                      residuals[i].uncertainty, stat[i]};
    if (!t.largest || std::abs(stat[i]) > std::abs(t.largest->normalized)) t.largest = o;
    if (std::abs(stat[i]) > t.outlier_threshold) found.push_back(std::move(o));
  }
  std::stable_sort(found.begin(), found.end(), [](const ResidualOutlier& a, const ResidualOutlier& b) {
    return std::abs(a.normalized) > std::abs(b.normalized);
  });
  t.outliers = std::move(found);
  t.outliers_passed = t.outliers.empty();
  return t;
}

std::string ConsistencyTest::summary() const {
  std::string s;
  if (sigma_stated) {
    s = "chi2/nu = " + num(degrees_of_freedom > 0.0 ? chi_squared / degrees_of_freedom : 0.0) +
        " (chi2 = " + num(chi_squared, "%.4g") + ", nu = " + num(degrees_of_freedom, "%.0f") +
        "), Birge ratio " + num(birge_ratio) + ", p = " + num(p_value);
    if (degrees_of_freedom == 0.0) s += " (no redundancy: not tested)";
    else if (!chi_squared_passed)
      s += " < " + num(levels.chi_squared) + ": the residuals are inconsistent with the stated "
           "uncertainties";
  } else {
    s = "chi2 not tested (sigma estimated from these residuals)";
  }
  if (tested == 0) return s + "; outliers not tested (no redundancy)";
  if (largest)
    s += "; largest " + std::string(sigma_stated ? "normalized" : "studentized") + " residual " +
         num(largest->normalized) + " (limit " + num(outlier_threshold) + ", " +
         std::to_string(tested) + " tested) at " + name_of(*largest);
  if (!outliers_passed) {
    s += "; OUTLIER" + std::string(outliers.size() > 1 ? "S: " : ": ");
    const std::size_t shown = std::min<std::size_t>(outliers.size(), 3);
    for (std::size_t i = 0; i < shown; ++i) {
      const ResidualOutlier& o = outliers[i];
      s += (i ? "; " : "") + name_of(o) + " (residual " + num(o.value * 1e3, "%.4g") + " um, " +
           num(o.normalized) + " times its standard deviation)";
    }
    if (outliers.size() > shown) s += "; and " + std::to_string(outliers.size() - shown) + " more";
  }
  if (!passed() && groups.size() > 1 && chi_squared > 0.0)
    s += "; largest share of chi2: " + groups.front().group + " (" +
         num(100.0 * groups.front().chi_squared / chi_squared, "%.0f") + " %)";
  return s;
}

Eigen::VectorXd leverages(const Eigen::MatrixXd& j) {
  // The hat matrix does not depend on the column scale; unit columns keep the rank decision of
  // the pivoted QR independent of units (mm against rad columns differ by ~1e3 and more).
  Eigen::MatrixXd scaled = j;
  for (Eigen::Index c = 0; c < scaled.cols(); ++c) {
    const double norm = scaled.col(c).norm();
    if (norm > 0.0) scaled.col(c) /= norm;
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(scaled);
  const Eigen::Index rank = qr.rank();
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(j.rows(), rank);
  return q.rowwise().squaredNorm();
}

}  // namespace vcmm::characterization
