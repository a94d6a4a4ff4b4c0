// profile_harmonics.cpp — harmonic analysis and re-synthesis of a closed profile (notation and
// the two paths: vcmm/geometry/profile_harmonics.h).
//
// fft path. With θ_j = θ_0 + σ·2πj/n and X_k = Σ_j d_j e^{−2πi jk/n}, the complex coefficients
// of d(θ) = Σ_{k∈ℤ} C_k e^{ikθ} (C_{−k} = conj C_k) are
//   σ = +1:  C_k = X_k e^{−ikθ_0} / n,        σ = −1:  C_k = conj(X_k) e^{−ikθ_0} / n,
// and a_k − i b_k = 2 C_k (1 ≤ k < n/2), a_0 = C_0; at k = n/2 (n even) the sampled harmonic
// is (X_{n/2}/n)(−1)^j, i.e. a = (X/n) cos kθ_0, b = (X/n) sin kθ_0 (σ = ±1 alike).
// Synthesis multiplies X_k and X_{n−k} by g_k (k ≤ K), zeroes the rest and inverts: the
// output is real because the gains are real and even in k.
//
// Grid detection (as in gaussian_filter.cpp, without an arctangent per point): with u_0 the
// unit ray of point 0 and σ the sense of rays 0 → 1, ray j rotated back by σ·2πj/n has
// sin δ_j = u_0 × r_j' / |r_j| and must have a positive dot product with u_0 and |δ_j| below a
// quarter step (angular order); the fft path is taken when K·max|δ_j| ≤ 0.01 (header).
#include "vcmm/geometry/profile_harmonics.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>

#include "internal/fft.h"

namespace vcmm::geometry {
namespace {

constexpr double kPi = std::numbers::pi;
/// Largest K·|δ| accepted on the fft path: the phase error of the highest harmonic analysed
/// (header): 1 % of its amplitude.
constexpr double kMaxPhaseError = 0.01;

/// The real DFT of length n: cos/sin of 2πj/n (j < n) for the grid test and the direct sums,
/// and X_k (k ≤ n/2) of real input by one complex FFT of length n/2 for even n (the even and
/// odd samples as real and imaginary parts; X_k = E_k + ω^k O_k, ω = e^{−2πi/n}, with
/// E_k = (Z_k + conj Z_{N−k})/2 and O_k = (Z_k − conj Z_{N−k})/(2i)), of length n for odd n.
/// Cached per thread (grid_plan).
class GridPlan {
 public:
  explicit GridPlan(std::size_t n)
      : n_(n), even_(n % 2 == 0), fft_(even_ ? n / 2 : n), cos(n), sin(n) {
    for (std::size_t j = 0; j < n; ++j) {
      const internal::Cx w = internal::unit_root(j, n);  // e^{−2πij/n}
      cos[j] = w.re;
      sin[j] = -w.im;
    }
  }
  std::size_t size() const { return n_; }

  /// X_k = Σ_j x_j e^{−2πi jk/n} for k = 0 … K (K ≤ n/2).
  void forward(const double* x, std::size_t K, double* re, double* im) {
    const std::size_t m = fft_.size();
    zr_.resize(m);
    zi_.resize(m);
    if (!even_) {
      std::copy(x, x + n_, zr_.begin());
      std::fill(zi_.begin(), zi_.end(), 0.0);
      fft_.forward(zr_.data(), zi_.data());
      std::copy(zr_.begin(), zr_.begin() + static_cast<std::ptrdiff_t>(K + 1), re);
      std::copy(zi_.begin(), zi_.begin() + static_cast<std::ptrdiff_t>(K + 1), im);
      return;
    }
    for (std::size_t j = 0; j < m; ++j) {
      zr_[j] = x[2 * j];
      zi_[j] = x[2 * j + 1];
    }
    fft_.forward(zr_.data(), zi_.data());
    for (std::size_t k = 0; k <= K; ++k) {
      const std::size_t a = k % m, b = (m - k % m) % m;  // Z_k and Z_{N−k} (indices mod N)
      const double er = 0.5 * (zr_[a] + zr_[b]), ei = 0.5 * (zi_[a] - zi_[b]);
      const double or_ = 0.5 * (zi_[a] + zi_[b]), oi = -0.5 * (zr_[a] - zr_[b]);
      const double c = cos[k], sn = -sin[k];  // ω^k = cos − i sin
      re[k] = er + (or_ * c - oi * sn);
      im[k] = ei + (or_ * sn + oi * c);
    }
  }

  /// y_j = (1/n) Σ_k Y_k e^{+2πi jk/n} for the real signal whose spectrum is Y_k (k ≤ K, zero
  /// for K < k ≤ n/2, Y_{n−k} = conj Y_k).
  void inverse(const double* re, const double* im, std::size_t K, double* y) {
    const std::size_t m = fft_.size();
    zr_.assign(m, 0.0);
    zi_.assign(m, 0.0);
    const auto at = [&](std::size_t k, double& r, double& i) {  // Y_k for 0 ≤ k ≤ n
      const std::size_t kk = k <= n_ / 2 ? k : n_ - k;
      if (kk > K) {
        r = i = 0.0;
        return;
      }
      r = re[kk];
      i = k <= n_ / 2 ? im[kk] : -im[kk];
    };
    const double inv_n = 1.0 / static_cast<double>(n_);
    if (!even_) {
      for (std::size_t k = 0; k < n_; ++k) at(k, zr_[k], zi_[k]);
      fft_.inverse(zr_.data(), zi_.data());
      for (std::size_t j = 0; j < n_; ++j) y[j] = zr_[j] * inv_n;
      return;
    }
    // E_k = (Y_k + Y_{k+N})/2, O_k = (Y_k − Y_{k+N}) ω^{−k}/2, Z_k = E_k + i O_k (k < N).
    for (std::size_t k = 0; k < m; ++k) {
      double ar, ai, br, bi;
      at(k, ar, ai);
      at(k + m, br, bi);
      const double er = 0.5 * (ar + br), ei = 0.5 * (ai + bi);
      const double dr = 0.5 * (ar - br), di = 0.5 * (ai - bi);
      const double c = cos[k], sn = sin[k];  // ω^{−k} = cos + i sin
      const double or_ = dr * c - di * sn, oi = dr * sn + di * c;
      zr_[k] = er - oi;
      zi_[k] = ei + or_;
    }
    fft_.inverse(zr_.data(), zi_.data());
    const double inv_m = 1.0 / static_cast<double>(m);
    for (std::size_t j = 0; j < m; ++j) {
      y[2 * j] = zr_[j] * inv_m;
      y[2 * j + 1] = zi_[j] * inv_m;
    }
  }

 private:
  std::size_t n_;
  bool even_;
  internal::ComplexFft fft_;
  std::vector<double> zr_, zi_;

 public:
  std::vector<double> cos, sin;
};

GridPlan& grid_plan(std::size_t n) { return internal::thread_local_plan<GridPlan, 6>(n); }

/// Synthesis by direct sums when at most this many gains are non-zero (each costs ~2n
/// multiply-adds with the rotation recurrence, against ~5 n log₂ n for the inverse FFT).
constexpr std::size_t kDirectSynthesisMaxTerms = 12;

[[noreturn]] void fail(const std::string& message) {
  throw InvalidInput("ProfileHarmonics: " + message);
}

}  // namespace

ProfileHarmonics::ProfileHarmonics(std::span<const Point2> points, Point2 center, double radius,
                                   std::size_t max_order) {
  analyse(points, center, radius, max_order);
}

void ProfileHarmonics::analyse(std::span<const Point2> points, Point2 center, double radius,
                               std::size_t max_order) {
  const std::size_t n = points.size();
  if (n < 8) fail("needs at least 8 points; got " + std::to_string(n));
  if (!(std::isfinite(center.x) && std::isfinite(center.y) && std::isfinite(radius) &&
        radius > 0.0)) {
    std::ostringstream os;
    os << "the circle needs a finite centre and a finite radius > 0; got centre (" << center.x
       << ", " << center.y << "), radius " << radius;
    fail(os.str());
  }
  if (max_order < 1 || max_order > n / 2)
    fail("max_order must lie in 1 … n/2 = " + std::to_string(n / 2) + " for " +
         std::to_string(n) + " points; got " + std::to_string(max_order));
  points_.assign(points.begin(), points.end());
  center_ = center;
  radius_ = radius;
  max_order_ = max_order;
  deviation_.resize(n);
  inv_r_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = points[i].x - center.x, dy = points[i].y - center.y;
    if (!(std::isfinite(dx) && std::isfinite(dy))) {
      std::ostringstream os;
      os << "point " << i << " has a non-finite coordinate (x = " << points[i].x
         << ", y = " << points[i].y << ")";
      fail(os.str());
    }
    const double r = std::sqrt(dx * dx + dy * dy);  // mm-scale data: no overflow to guard
    if (!(r > 0.0)) fail("point " + std::to_string(i) + " lies at the centre: no direction");
    deviation_[i] = r - radius;
    inv_r_[i] = 1.0 / r;
  }
  a_.assign(max_order + 1, 0.0);
  b_.assign(max_order + 1, 0.0);

  // Equiangular? (file comment)
  GridPlan& plan = grid_plan(n);
  const double ux = (points[0].x - center.x) * inv_r_[0], uy = (points[0].y - center.y) * inv_r_[0];
  const double cross01 = ux * (points[1].y - center.y) - uy * (points[1].x - center.x);
  const double sense = cross01 >= 0.0 ? 1.0 : -1.0;
  const double quarter_step = std::sin(0.5 * kPi / static_cast<double>(n));
  double max_sin = 0.0;
  bool on_grid = true;
  for (std::size_t j = 0; j < n && on_grid; ++j) {
    const double dx = points[j].x - center.x, dy = points[j].y - center.y;
    const double c = plan.cos[j], s = sense * plan.sin[j];
    const double xr = dx * c + dy * s, yr = dy * c - dx * s;  // rotated back by σ·2πj/n
    const double sin_delta = (ux * yr - uy * xr) * inv_r_[j];
    const double dot = ux * xr + uy * yr;
    if (!(dot > 0.0) || std::fabs(sin_delta) > quarter_step) on_grid = false;
    max_sin = std::max(max_sin, std::fabs(sin_delta));
  }
  on_grid = on_grid && static_cast<double>(max_order) * std::asin(std::min(1.0, max_sin)) <=
                           kMaxPhaseError;

  if (on_grid) {
    path_ = HarmonicsPath::fft;
    sense_ = sense;
    theta0_ = std::atan2(uy, ux);
    x_re_.resize(max_order + 1);
    x_im_.resize(max_order + 1);
    plan.forward(deviation_.data(), max_order, x_re_.data(), x_im_.data());
    const double inv_n = 1.0 / static_cast<double>(n);
    for (std::size_t k = 0; k <= max_order; ++k) {
      // C_k = X_k e^{−ikθ_0}/n (σ = +1) or conj(X_k) e^{−ikθ_0}/n (σ = −1).
      const double xr = x_re_[k] * inv_n, xi = sense * x_im_[k] * inv_n;
      const double phase = static_cast<double>(k) * theta0_;
      const double c = std::cos(phase), s = std::sin(phase);
      const double cr = xr * c + xi * s, ci = xi * c - xr * s;  // (xr + i xi) e^{−i phase}
      if (k == 0) {
        a_[0] = xr;
      } else if (2 * k == n) {
        a_[k] = xr * c;  // Nyquist (file comment): X real, b = (X/n) sin kθ_0
        b_[k] = xr * s;
      } else {
        a_[k] = 2.0 * cr;
        b_[k] = -2.0 * ci;
      }
    }
    theta_.clear();
    return;
  }

  // Quadrature on the sorted angles.
  path_ = HarmonicsPath::quadrature;
  theta_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    theta_[i] = std::atan2(points[i].y - center.y, points[i].x - center.x);
  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t p, std::size_t q) {
    return theta_[p] < theta_[q] || (theta_[p] == theta_[q] && p < q);
  });
  const double scale = 1.0 / (2.0 * kPi);
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t i = order[j];
    const double next = j + 1 < n ? theta_[order[j + 1]] : theta_[order[0]] + 2.0 * kPi;
    const double prev = j > 0 ? theta_[order[j - 1]] : theta_[order[n - 1]] - 2.0 * kPi;
    const double w = 0.5 * (next - prev) * scale * deviation_[i];
    // Σ over k of w e^{−ikθ} by the rotation recurrence (re-anchored every 64 orders).
    const double c1 = std::cos(theta_[i]), s1 = std::sin(theta_[i]);
    double c = 1.0, s = 0.0;  // cos kθ, sin kθ
    for (std::size_t k = 0; k <= max_order; ++k) {
      if (k % 64 == 0 && k > 0) {
        c = std::cos(static_cast<double>(k) * theta_[i]);
        s = std::sin(static_cast<double>(k) * theta_[i]);
      }
      // C_k += w (cos kθ − i sin kθ);  a_k = 2 Re C_k, b_k = −2 Im C_k (k ≥ 1), a_0 = C_0.
      const double f = k == 0 ? 1.0 : 2.0;
      a_[k] += f * w * c;
      b_[k] += f * w * s;
      const double cn = c * c1 - s * s1;
      s = s * c1 + c * s1;
      c = cn;
    }
  }
  b_[0] = 0.0;
}

void ProfileHarmonics::synthesize(std::span<const double> gains, std::vector<Point2>& out) const {
  const std::size_t n = points_.size();
  if (n == 0) fail("synthesize before analyse");
  if (gains.size() != max_order_ + 1)
    fail("synthesize needs max_order + 1 = " + std::to_string(max_order_ + 1) +
         " gains; got " + std::to_string(gains.size()));
  for (std::size_t k = 0; k < gains.size(); ++k) {
    if (!std::isfinite(gains[k])) {
      std::ostringstream os;
      os << "gain " << k << " is not finite (" << gains[k] << ")";
      fail(os.str());
    }
  }
  out.resize(n);
  thread_local std::vector<double> dev;
  dev.resize(n);
  if (path_ == HarmonicsPath::fft) {
    GridPlan& plan = grid_plan(n);
    std::size_t terms = 0;
    for (double g : gains) terms += g != 0.0 ? 1 : 0;
    if (terms <= kDirectSynthesisMaxTerms) {
      // d'_j = Σ_k g_k Re(X_k e^{+2πi jk/n})/n·(2 for 0 < k < n/2): at grid index j the angle
      // relative to θ_0 is σ·2πj/n, and X_k holds the phase of the grid (file comment).
      std::fill(dev.begin(), dev.end(), 0.0);
      const double inv_n = 1.0 / static_cast<double>(n);
      for (std::size_t k = 0; k <= max_order_; ++k) {
        if (gains[k] == 0.0) continue;
        const double f = gains[k] * inv_n * (k == 0 || 2 * k == n ? 1.0 : 2.0);
        const double xr = f * x_re_[k], xi = f * x_im_[k];
        // Re((xr + i xi) e^{+iφ}) with φ = 2πjk/n from the table (index jk mod n).
        std::size_t idx = 0;
        for (std::size_t j = 0; j < n; ++j) {
          dev[j] += xr * plan.cos[idx] - xi * plan.sin[idx];
          idx += k;
          if (idx >= n) idx -= n;
        }
      }
    } else {
      thread_local std::vector<double> yr, yi;
      yr.resize(max_order_ + 1);
      yi.resize(max_order_ + 1);
      for (std::size_t k = 0; k <= max_order_; ++k) {
        yr[k] = gains[k] * x_re_[k];
        yi[k] = gains[k] * x_im_[k];
      }
      plan.inverse(yr.data(), yi.data(), max_order_, dev.data());
    }
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      const double c1 = std::cos(theta_[i]), s1 = std::sin(theta_[i]);
      double c = 1.0, s = 0.0, sum = 0.0;
      for (std::size_t k = 0; k <= max_order_; ++k) {
        if (k % 64 == 0 && k > 0) {
          c = std::cos(static_cast<double>(k) * theta_[i]);
          s = std::sin(static_cast<double>(k) * theta_[i]);
        }
        sum += gains[k] * (a_[k] * c + b_[k] * s);
        const double cn = c * c1 - s * s1;
        s = s * c1 + c * s1;
        c = cn;
      }
      dev[i] = sum;
    }
  }
  // q_i = p_i + (p_i − c)(d'_i − d_i)/r_i: the input point plus a small correction.
  for (std::size_t i = 0; i < n; ++i) {
    const double f = (dev[i] - deviation_[i]) * inv_r_[i];
    out[i] = {points_[i].x + (points_[i].x - center_.x) * f,
              points_[i].y + (points_[i].y - center_.y) * f};
  }
}

std::vector<Point2> ProfileHarmonics::synthesized(std::span<const double> gains) const {
  std::vector<Point2> out;
  synthesize(gains, out);
  return out;
}

}  // namespace vcmm::geometry
