// internal/spectral_kernels.cpp — see internal/spectral_kernels.h.
#include "internal/spectral_kernels.h"

#include <algorithm>
#include <limits>

#include "vcmm/internal/simd_clones.h"

namespace vcmm::validation::internal {
namespace {

// Eight vertical lanes as one GCC vector (lowered to narrower registers where AVX-512 is not
// available); the helpers are inlined, so the ABI note about such vectors does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"  // (GCC reports it at the end of the file)
using V8 = double __attribute__((vector_size(64)));

inline V8 load8(const double* p) {
  V8 v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}

/// Columns [first, end) of rows [0, m) of a (leading dimension ld): c_i = Σ_j a_ij x_j from 0
/// in column order, then y_i += c_i. Four (then one) vectors of eight rows stay in registers
/// over all the block's columns, as in Eigen's kernel; the last rows one by one.
VCMM_SIMD_CLONES void product_block(const double* a, std::size_t ld, std::size_t m,
                                    std::size_t first, std::size_t end, const double* x,
                                    double* y) {
  std::size_t i = 0;
  for (; i + 32 <= m; i += 32) {
    V8 c0 = {}, c1 = {}, c2 = {}, c3 = {};
    for (std::size_t j = first; j < end; ++j) {
      const double* col = a + j * ld + i;
      const double xj = x[j];
      c0 = c0 + load8(col) * xj;
      c1 = c1 + load8(col + 8) * xj;
      c2 = c2 + load8(col + 16) * xj;
      c3 = c3 + load8(col + 24) * xj;
    }
    const V8 y0 = load8(y + i) + c0, y1 = load8(y + i + 8) + c1;
    const V8 y2 = load8(y + i + 16) + c2, y3 = load8(y + i + 24) + c3;
    __builtin_memcpy(y + i, &y0, sizeof y0);
    __builtin_memcpy(y + i + 8, &y1, sizeof y1);
    __builtin_memcpy(y + i + 16, &y2, sizeof y2);
    __builtin_memcpy(y + i + 24, &y3, sizeof y3);
  }
  for (; i + 8 <= m; i += 8) {
    V8 c0 = {};
    for (std::size_t j = first; j < end; ++j) c0 = c0 + load8(a + j * ld + i) * x[j];
    const V8 y0 = load8(y + i) + c0;
    __builtin_memcpy(y + i, &y0, sizeof y0);
  }
  for (; i < m; ++i) {
    double c = 0.0;
    for (std::size_t j = first; j < end; ++j) c = c + a[j * ld + i] * x[j];
    y[i] = y[i] + c;
  }
}

VCMM_SIMD_CLONES void scaled_sum_range(double k, const double* f, const double* s,
                                       std::size_t n, double* hi, double* lo) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  V8 h = V8{} - kInf, l = V8{} + kInf;
  std::size_t j = 0;
  for (; j + 8 <= n; j += 8) {
    const V8 x = load8(f + j) * k + load8(s + j);
    h = x > h ? x : h;
    l = x < l ? x : l;
  }
  double top = -kInf, bottom = kInf;
  for (int q = 0; q < 8; ++q) {
    top = std::max(top, h[q]);
    bottom = std::min(bottom, l[q]);
  }
  for (; j < n; ++j) {
    const double x = k * f[j] + s[j];
    top = std::max(top, x);
    bottom = std::min(bottom, x);
  }
  *hi = top;
  *lo = bottom;
}

}  // namespace

void column_major_product(const double* a, std::size_t rows, std::size_t cols, const double* x,
                          double* y) {
  // Eigen 3.4, GeneralMatrixVector.h: block_cols = cols < 128 ? cols
  //   : (lhsStride * sizeof(double) < 32000 ? 16 : 4).
  const std::size_t block = cols < 128 ? cols : (rows * sizeof(double) < 32000 ? 16 : 4);
  if (rows == 1) {  // Eigen: a dot product of a strided row, summed in order (scalar)
    double c = cols > 0 ? a[0] * x[0] : 0.0;
    for (std::size_t j = 1; j < cols; ++j) c = c + a[j] * x[j];
    y[0] = c;
    return;
  }
  for (std::size_t i = 0; i < rows; ++i) y[i] = 0.0;
  for (std::size_t j = 0; j < cols; j += block)
    product_block(a, rows, rows, j, std::min(cols, j + block), x, y);
}

double scaled_sum_peak_to_valley(double k, const double* f, const double* s, std::size_t n) {
  double hi = 0.0, lo = 0.0;
  scaled_sum_range(k, f, s, n, &hi, &lo);
  return hi - lo;
}

}  // namespace vcmm::validation::internal
