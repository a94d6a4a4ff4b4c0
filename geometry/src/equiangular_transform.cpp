// equiangular_transform.cpp — the real Fourier series of an equiangular closed sequence and its
// inverse (notation in vcmm/geometry/equiangular_transform.h).
//
// Analysis: X_k = Σ v_j e^{−2πijk/n} by one complex FFT of length n; a_k = (2/n) Re X_k,
// b_k = −(2/n) Im X_k (half weight for k = 0 and k = n/2).
// Synthesis: v_j = Σ_k Y_k e^{+2πijk/n} with the Hermitian spectrum Y_0 = a_0,
// Y_k = (a_k − i b_k)/2, Y_{n−k} = conj Y_k, Y_{n/2} = a_{n/2}. For even n = 2N the samples are
// paired, z_j = v_{2j} + i v_{2j+1} = Σ_{k<N} (E_k + i O_k) e^{+2πijk/N} with
//   E_k = Y_k + Y_{k+N},   O_k = (Y_k − Y_{k+N}) e^{+2πik/n},   Y_{k+N} = conj Y_{N−k} (k ≥ 1),
// (split v_j's sum over k into k and k + N: e^{2πi(2j)(k+N)/n} = e^{2πijk/N} and
// e^{2πi(2j+1)(k+N)/n} = −e^{2πi(2j+1)k/n}), so one complex inverse FFT of length N suffices.
#include "vcmm/geometry/equiangular_transform.h"

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "internal/fft.h"
#include "vcmm/geometry/point.h"

namespace vcmm::geometry {

using internal::ComplexFft;
using internal::Cx;
using internal::conj;

struct EquiangularTransform::Plan {
  explicit Plan(std::size_t size) : n(size), full(size), re(size), im(size) {
    if (n % 2 == 0) {
      half = std::make_unique<ComplexFft>(n / 2);
      twiddle.resize(n / 2);
      for (std::size_t k = 0; k < n / 2; ++k) twiddle[k] = conj(internal::unit_root(k, n));
    }
  }
  std::size_t n;
  ComplexFft full;
  std::unique_ptr<ComplexFft> half;
  std::vector<Cx> twiddle;  // e^{+2πik/n}, k < n/2
  std::vector<double> re, im;
};

EquiangularTransform::EquiangularTransform(std::size_t n) {
  if (n < 2)
    throw InvalidInput("EquiangularTransform: at least 2 samples are needed; got " +
                       std::to_string(n));
  plan_ = std::make_unique<Plan>(n);
}
EquiangularTransform::~EquiangularTransform() = default;
EquiangularTransform::EquiangularTransform(EquiangularTransform&&) noexcept = default;
EquiangularTransform& EquiangularTransform::operator=(EquiangularTransform&&) noexcept = default;

std::size_t EquiangularTransform::size() const { return plan_->n; }

void EquiangularTransform::coefficients(std::span<const double> values, std::span<double> cos,
                                        std::span<double> sin) {
  Plan& p = *plan_;
  const std::size_t half = p.n / 2;
  if (values.size() != p.n || cos.size() != half + 1 || sin.size() != half + 1)
    throw InvalidInput("EquiangularTransform::coefficients: expected " + std::to_string(p.n) +
                       " values and " + std::to_string(half + 1) + " coefficients; got " +
                       std::to_string(values.size()) + ", " + std::to_string(cos.size()) +
                       " and " + std::to_string(sin.size()));
  std::copy(values.begin(), values.end(), p.re.begin());
  std::fill(p.im.begin(), p.im.end(), 0.0);
  p.full.forward(p.re.data(), p.im.data());
  const double scale = 2.0 / static_cast<double>(p.n);
  for (std::size_t k = 0; k <= half; ++k) {
    const bool single = k == 0 || 2 * k == p.n;
    cos[k] = (single ? 0.5 : 1.0) * scale * p.re[k];
    sin[k] = single ? 0.0 : -scale * p.im[k];
  }
}

void EquiangularTransform::values(std::span<const double> cos, std::span<const double> sin,
                                  std::span<double> out) {
  Plan& p = *plan_;
  const std::size_t n = p.n, half = n / 2;
  if (cos.empty() || cos.size() > half + 1 || sin.size() != cos.size() || out.size() != n)
    throw InvalidInput("EquiangularTransform::values: expected 1 to " +
                       std::to_string(half + 1) + " coefficients of each kind and " +
                       std::to_string(n) + " outputs; got " + std::to_string(cos.size()) +
                       ", " + std::to_string(sin.size()) + " and " + std::to_string(out.size()));
  const std::size_t count = cos.size();  // harmonics 0 … count − 1
  // Y_k for 0 ≤ k ≤ n/2 (zero above count − 1).
  const auto y = [&](std::size_t k) -> Cx {
    if (k >= count) return {0.0, 0.0};
    if (k == 0 || 2 * k == n) return {cos[k], 0.0};
    return {0.5 * cos[k], -0.5 * sin[k]};
  };
  if (n % 2 == 0) {
    const std::size_t m = half;  // N
    // Only k < count and k + N with N − k < count are non-zero: two runs of k, zero between.
    const auto pair = [&](std::size_t k) {
      const Cx a = y(k);
      const Cx b = k == 0 ? y(m) : conj(y(m - k));  // Y_{k+N}
      const Cx e = a + b;
      const Cx o = (a - b) * p.twiddle[k];
      p.re[k] = e.re - o.im;  // E + i O
      p.im[k] = e.im + o.re;
    };
    const std::size_t low_end = std::min(count, m);
    for (std::size_t k = 0; k < low_end; ++k) pair(k);
    const std::size_t high_start = count > m ? low_end : std::max(low_end, m - count + 1);
    std::fill(p.re.begin() + static_cast<std::ptrdiff_t>(low_end),
              p.re.begin() + static_cast<std::ptrdiff_t>(high_start), 0.0);
    std::fill(p.im.begin() + static_cast<std::ptrdiff_t>(low_end),
              p.im.begin() + static_cast<std::ptrdiff_t>(high_start), 0.0);
    for (std::size_t k = high_start; k < m; ++k) pair(k);
    p.half->inverse_interleaved(p.re.data(), p.im.data(), out.data());  // z_j → v_2j, v_2j+1
    return;
  }
  std::fill(p.re.begin(), p.re.end(), 0.0);
  std::fill(p.im.begin(), p.im.end(), 0.0);
  for (std::size_t k = 0; k < count; ++k) {
    const Cx v = y(k);
    p.re[k] = v.re;
    p.im[k] = v.im;
    if (k > 0) {
      p.re[n - k] = v.re;
      p.im[n - k] = -v.im;
    }
  }
  p.full.inverse(p.re.data(), p.im.data());
  std::copy(p.re.begin(), p.re.end(), out.begin());
}

}  // namespace vcmm::geometry
