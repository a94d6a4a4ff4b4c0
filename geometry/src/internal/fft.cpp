// geometry/src/internal/fft.cpp — the complex FFT (see fft.h).
#include "internal/fft.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "internal/isa.h"
#include "internal/vec.h"

namespace vcmm::geometry::internal {

Cx unit_root(std::size_t j, std::size_t n) {
  j %= n;
  const long double angle = -2.0L * std::numbers::pi_v<long double> * static_cast<long double>(j) /
                            static_cast<long double>(n);
  return {static_cast<double>(std::cos(angle)), static_cast<double>(std::sin(angle))};
}

namespace {

// ---- complex FFT on split storage ------------------------------------------------------------
// Real and imaginary parts live in separate arrays so that each butterfly is computed on
// vectors across independent sub-transforms (the q loops below, or p in the first pass).

/// Radix-R DFT butterfly in place: b_u = Σ_t a_t e^{−2πi tu/R}.
template <std::size_t R>
struct Butterfly;
// Each apply is a template on the element type T: double, or a vector of doubles (below) whose
// lanes see exactly the operations of the scalar version.

template <>
struct Butterfly<2> {
  template <class T>
  [[gnu::always_inline]] static void apply(T (&r)[2], T (&i)[2]) {
    const T r0 = r[0], i0 = i[0];
    r[0] = r0 + r[1];
    i[0] = i0 + i[1];
    r[1] = r0 - r[1];
    i[1] = i0 - i[1];
  }
};

template <>
struct Butterfly<3> {
  template <class T>
  [[gnu::always_inline]] static void apply(T (&r)[3], T (&i)[3]) {
    constexpr double kS3 = 0.86602540378443864676;  // sin(2π/3)
    const T sr = r[1] + r[2], si = i[1] + i[2];
    const T tr = r[0] - 0.5 * sr, ti = i[0] - 0.5 * si;
    const T vr = kS3 * (i[1] - i[2]), vi = -kS3 * (r[1] - r[2]);  // −i (√3/2)(a1 − a2)
    r[0] += sr;
    i[0] += si;
    r[1] = tr + vr;
    i[1] = ti + vi;
    r[2] = tr - vr;
    i[2] = ti - vi;
  }
};

template <>
struct Butterfly<4> {
  template <class T>
  [[gnu::always_inline]] static void apply(T (&r)[4], T (&i)[4]) {
    const T t0r = r[0] + r[2], t0i = i[0] + i[2], t1r = r[0] - r[2], t1i = i[0] - i[2];
    const T t2r = r[1] + r[3], t2i = i[1] + i[3];
    const T t3r = i[1] - i[3], t3i = r[3] - r[1];  // −i (a1 − a3)
    r[0] = t0r + t2r;
    i[0] = t0i + t2i;
    r[1] = t1r + t3r;
    i[1] = t1i + t3i;
    r[2] = t0r - t2r;
    i[2] = t0i - t2i;
    r[3] = t1r - t3r;
    i[3] = t1i - t3i;
  }
};

template <>
struct Butterfly<5> {
  template <class T>
  [[gnu::always_inline]] static void apply(T (&r)[5], T (&i)[5]) {
    constexpr double kC1 = 0.30901699437494742410;   // cos(2π/5)
    constexpr double kC2 = -0.80901699437494742410;  // cos(4π/5)
    constexpr double kS1 = 0.95105651629515357212;   // sin(2π/5)
    constexpr double kS2 = 0.58778525229247312917;   // sin(4π/5)
    const T t1r = r[1] + r[4], t1i = i[1] + i[4], t2r = r[2] + r[3], t2i = i[2] + i[3];
    const T t3r = r[1] - r[4], t3i = i[1] - i[4], t4r = r[2] - r[3], t4i = i[2] - i[3];
    const T c1r = r[0] + kC1 * t1r + kC2 * t2r, c1i = i[0] + kC1 * t1i + kC2 * t2i;
    const T c2r = r[0] + kC2 * t1r + kC1 * t2r, c2i = i[0] + kC2 * t1i + kC1 * t2i;
    // s1 = −i (S1 t3 + S2 t4), s2 = −i (S2 t3 − S1 t4)
    const T s1r = kS1 * t3i + kS2 * t4i, s1i = -(kS1 * t3r + kS2 * t4r);
    const T s2r = kS2 * t3i - kS1 * t4i, s2i = -(kS2 * t3r - kS1 * t4r);
    r[0] += t1r + t2r;
    i[0] += t1i + t2i;
    r[1] = c1r + s1r;
    i[1] = c1i + s1i;
    r[2] = c2r + s2r;
    i[2] = c2i + s2i;
    r[3] = c2r - s2r;
    i[3] = c2i - s2i;
    r[4] = c1r - s1r;
    i[4] = c1i - s1i;
  }
};

// Radix 9 as 3 × 3: with t = t2 + 3 t1 and u = u1 + 3 u2, ω_9^{tu} = ω_3^{t1 u1} ω_9^{t2 u1}
// ω_3^{t2 u2}: radix 3 over t1 for each t2, the twiddles ω_9^{t2 u1}, radix 3 over t2.
template <>
struct Butterfly<9> {
  template <class T>
  [[gnu::always_inline]] static void apply(T (&r)[9], T (&i)[9]) {
    constexpr double kC1 = 0.76604444311897803520, kS1 = 0.64278760968653932632;  // 2π/9
    constexpr double kC2 = 0.17364817766693034885, kS2 = 0.98480775301220805936;  // 4π/9
    constexpr double kC4 = -0.93969262078590838405, kS4 = 0.34202014332566873304;  // 8π/9
    T br[3][3], bi[3][3];  // [t2][u1]
    for (int t2 = 0; t2 < 3; ++t2) {
      T ar[3] = {r[t2], r[t2 + 3], r[t2 + 6]}, ai[3] = {i[t2], i[t2 + 3], i[t2 + 6]};
      Butterfly<3>::apply(ar, ai);
      for (int u1 = 0; u1 < 3; ++u1) {
        br[t2][u1] = ar[u1];
        bi[t2][u1] = ai[u1];
      }
    }
    // (x + iy)(c − is) = (xc + ys) + i(yc − xs)
    const auto rotate = [](T& x, T& y, double c, double sn) {
      const T x0 = x;
      x = x0 * c + y * sn;
      y = y * c - x0 * sn;
    };
    rotate(br[1][1], bi[1][1], kC1, kS1);
    rotate(br[1][2], bi[1][2], kC2, kS2);
    rotate(br[2][1], bi[2][1], kC2, kS2);
    rotate(br[2][2], bi[2][2], kC4, kS4);
    for (int u1 = 0; u1 < 3; ++u1) {
      T ar[3] = {br[0][u1], br[1][u1], br[2][u1]}, ai[3] = {bi[0][u1], bi[1][u1], bi[2][u1]};
      Butterfly<3>::apply(ar, ai);
      for (int u2 = 0; u2 < 3; ++u2) {
        r[u1 + 3 * u2] = ar[u2];
        i[u1 + 3 * u2] = ai[u2];
      }
    }
  }
};

// Radix 8 as 2 × 4: b_t = a_t + a_{t+4}, c_t = (a_t − a_{t+4}) ω_8^t (t < 4); then
// X_{2u} = Σ_t b_t ω_4^{tu} and X_{2u+1} = Σ_t c_t ω_4^{tu}.
template <>
struct Butterfly<8> {
  template <class T>
  [[gnu::always_inline]] static void apply(T (&r)[8], T (&i)[8]) {
    constexpr double kH = 0.70710678118654752440;  // 1/√2
    T br[4], bi[4], cr[4], ci[4];
    for (int t = 0; t < 4; ++t) {
      br[t] = r[t] + r[t + 4];
      bi[t] = i[t] + i[t + 4];
      cr[t] = r[t] - r[t + 4];
      ci[t] = i[t] - i[t + 4];
    }
    {  // ω_8 = (1 − i)/√2, ω_8² = −i, ω_8³ = −(1 + i)/√2
      const T r1 = cr[1], i1 = ci[1], r3 = cr[3], i3 = ci[3];
      cr[1] = kH * (r1 + i1);
      ci[1] = kH * (i1 - r1);
      const T r2 = cr[2];
      cr[2] = ci[2];
      ci[2] = -r2;
      cr[3] = kH * (i3 - r3);
      ci[3] = -kH * (r3 + i3);
    }
    Butterfly<4>::apply(br, bi);
    Butterfly<4>::apply(cr, ci);
    for (int u = 0; u < 4; ++u) {
      r[2 * u] = br[u];
      i[2 * u] = bi[u];
      r[2 * u + 1] = cr[u];
      i[2 * u + 1] = ci[u];
    }
  }
};



// ---- vectors of W doubles: internal/vec.h ----------------------------------------------------

/// Stores the W × W block rows: out[l·stride + u] = a[u][l] for u, l < W (a transpose).
template <int W, class V>
[[gnu::always_inline]] inline void store_transposed(double* out, std::size_t stride,
                                                    const V* a) {
  if constexpr (W == 2) {
    store(out, V(__builtin_shufflevector(a[0], a[1], 0, 2)));
    store(out + stride, V(__builtin_shufflevector(a[0], a[1], 1, 3)));
  } else if constexpr (W == 4) {
    const V t0 = __builtin_shufflevector(a[0], a[1], 0, 4, 2, 6);  // a0₀ a1₀ a0₂ a1₂
    const V t1 = __builtin_shufflevector(a[0], a[1], 1, 5, 3, 7);
    const V t2 = __builtin_shufflevector(a[2], a[3], 0, 4, 2, 6);
    const V t3 = __builtin_shufflevector(a[2], a[3], 1, 5, 3, 7);
    store(out, V(__builtin_shufflevector(t0, t2, 0, 1, 4, 5)));
    store(out + stride, V(__builtin_shufflevector(t1, t3, 0, 1, 4, 5)));
    store(out + 2 * stride, V(__builtin_shufflevector(t0, t2, 2, 3, 6, 7)));
    store(out + 3 * stride, V(__builtin_shufflevector(t1, t3, 2, 3, 6, 7)));
  } else {
    static_assert(W == 8);
    V t[8], u[8];
    for (int k = 0; k < 8; k += 2) {  // pairs: t[k] = a_k₀ a_{k+1}₀ a_k₂ a_{k+1}₂ …
      t[k] = __builtin_shufflevector(a[k], a[k + 1], 0, 8, 2, 10, 4, 12, 6, 14);
      t[k + 1] = __builtin_shufflevector(a[k], a[k + 1], 1, 9, 3, 11, 5, 13, 7, 15);
    }
    for (int k = 0; k < 8; k += 4) {  // quads: u[k] = lanes 0 and 4 of a_k … a_{k+3}, …
      u[k] = __builtin_shufflevector(t[k], t[k + 2], 0, 1, 8, 9, 4, 5, 12, 13);
      u[k + 1] = __builtin_shufflevector(t[k + 1], t[k + 3], 0, 1, 8, 9, 4, 5, 12, 13);
      u[k + 2] = __builtin_shufflevector(t[k], t[k + 2], 2, 3, 10, 11, 6, 7, 14, 15);
      u[k + 3] = __builtin_shufflevector(t[k + 1], t[k + 3], 2, 3, 10, 11, 6, 7, 14, 15);
    }
    for (int l = 0; l < 4; ++l) {  // u[l]: lanes l and l + 4 of a_0 … a_3; u[l + 4]: of a_4 … a_7
      store(out + l * stride,
            V(__builtin_shufflevector(u[l], u[l + 4], 0, 1, 2, 3, 8, 9, 10, 11)));
      store(out + (l + 4) * stride,
            V(__builtin_shufflevector(u[l], u[l + 4], 4, 5, 6, 7, 12, 13, 14, 15)));
    }
  }
}

/// Stores a and b interleaved: out[2l] = a[l], out[2l + 1] = b[l] for l < W.
template <int W, class V>
[[gnu::always_inline]] inline void store_interleaved(double* out, const V& a, const V& b) {
  if constexpr (W == 2) {
    store(out, V(__builtin_shufflevector(a, b, 0, 2)));
    store(out + 2, V(__builtin_shufflevector(a, b, 1, 3)));
  } else if constexpr (W == 4) {
    store(out, V(__builtin_shufflevector(a, b, 0, 4, 1, 5)));
    store(out + 4, V(__builtin_shufflevector(a, b, 2, 6, 3, 7)));
  } else {
    static_assert(W == 8);
    store(out, V(__builtin_shufflevector(a, b, 0, 8, 1, 9, 2, 10, 3, 11)));
    store(out + 8, V(__builtin_shufflevector(a, b, 4, 12, 5, 13, 6, 14, 7, 15)));
  }
}

/// a[l] = in[2l], b[l] = in[2l + 1] for l < W.
template <int W, class V>
[[gnu::always_inline]] inline void load_deinterleaved(const double* in, V& a, V& b) {
  const V lo = load<V>(in), hi = load<V>(in + W);
  if constexpr (W == 2) {
    a = __builtin_shufflevector(lo, hi, 0, 2);
    b = __builtin_shufflevector(lo, hi, 1, 3);
  } else if constexpr (W == 4) {
    a = __builtin_shufflevector(lo, hi, 0, 2, 4, 6);
    b = __builtin_shufflevector(lo, hi, 1, 3, 5, 7);
  } else {
    static_assert(W == 8);
    a = __builtin_shufflevector(lo, hi, 0, 2, 4, 6, 8, 10, 12, 14);
    b = __builtin_shufflevector(lo, hi, 1, 3, 5, 7, 9, 11, 13, 15);
  }
}

// ---- the passes ---------------------------------------------------------------------------------
// Stockham autosort, decimation in frequency: with stride s and m = L / R, for p < m, q < s,
//   y[q + s (R p + u)] = ω_L^{p u} Σ_t x[q + s (p + t m)] ω_R^{t u}.
// Vectorised across q (W consecutive q at a time, scalar for the rest) when s > 1; the first
// pass (s = 1) is vectorised across p instead, with the R outputs of W consecutive p transposed
// into place. Every element sees the same operations in the same order on every path.

/// a_t = x[t · stride] for t < R, transformed by the radix-R butterfly.
template <std::size_t R, class T>
[[gnu::always_inline]] inline void load_and_transform(const double* xr, const double* xi,
                                                      std::size_t stride, T (&ar)[R],
                                                      T (&ai)[R]) {
  for (std::size_t t = 0; t < R; ++t) {
    ar[t] = load<T>(xr + t * stride);
    ai[t] = load<T>(xi + t * stride);
  }
  Butterfly<R>::apply(ar, ai);
}

/// One butterfly of the general pass at (p, q), on element type T (double or a vector).
template <std::size_t R, class T>
[[gnu::always_inline]] inline void general_butterfly(const double* __restrict xr,
                                                     const double* __restrict xi,
                                                     double* __restrict yr,
                                                     double* __restrict yi, std::size_t s,
                                                     std::size_t sm, const double (&c)[R],
                                                     const double (&d)[R], bool twiddled) {
  T ar[R], ai[R];
  load_and_transform(xr, xi, sm, ar, ai);
  store(yr, ar[0]);
  store(yi, ai[0]);
  for (std::size_t u = 1; u < R; ++u) {
    if (twiddled) {
      store(yr + s * u, T(ar[u] * c[u] - ai[u] * d[u]));
      store(yi + s * u, T(ar[u] * d[u] + ai[u] * c[u]));
    } else {
      store(yr + s * u, ar[u]);
      store(yi + s * u, ai[u]);
    }
  }
}

/// A pass with s > 1 (or any pass of radix without a first-pass kernel below). The last pass
/// (m = 1) has only the twiddle ω^0 = 1: no multiplication (the same values).
template <std::size_t R, int W>
[[gnu::always_inline]] inline void strided_pass(const double* __restrict xr,
                                                const double* __restrict xi,
                                                double* __restrict yr, double* __restrict yi,
                                                std::size_t s, const ComplexFft::Stage& st) {
  using V = typename VecOf<W>::type;
  const std::size_t m = st.m, sm = s * m;
  const double* __restrict wr = st.tw_re.data();
  const double* __restrict wi = st.tw_im.data();
  const bool twiddled = m > 1;
  for (std::size_t p = 0; p < m; ++p) {
    double c[R] = {}, d[R] = {};
    if (twiddled) {
      for (std::size_t u = 1; u < R; ++u) {
        c[u] = wr[(u - 1) * m + p];
        d[u] = wi[(u - 1) * m + p];
      }
    }
    const double* __restrict ar = xr + s * p;
    const double* __restrict ai = xi + s * p;
    double* __restrict br = yr + s * R * p;
    double* __restrict bi = yi + s * R * p;
    std::size_t q = 0;
    for (; q + W <= s; q += W)
      general_butterfly<R, V>(ar + q, ai + q, br + q, bi + q, s, sm, c, d, twiddled);
    if constexpr (W >= 8) {
      using V4 = typename VecOf<4>::type;
      for (; q + 4 <= s; q += 4)
        general_butterfly<R, V4>(ar + q, ai + q, br + q, bi + q, s, sm, c, d, twiddled);
    }
    if constexpr (W >= 4) {
      using V2 = typename VecOf<2>::type;
      for (; q + 2 <= s; q += 2)
        general_butterfly<R, V2>(ar + q, ai + q, br + q, bi + q, s, sm, c, d, twiddled);
    }
    for (; q < s; ++q)
      general_butterfly<R, double>(ar + q, ai + q, br + q, bi + q, s, sm, c, d, twiddled);
  }
}

/// The first pass (s = 1) for R a multiple of W (or R = 2, W ≥ 4): W consecutive p at a time,
/// contiguous loads x[p + t m] and twiddles, the outputs y[R p + u] stored by W × W
/// transposes; scalar for the last p.
/// With `in` not null, x_j = in[2j] + i in[2j + 1] instead (xr, xi unused): the split into
/// real and imaginary parts done by the loads (the same values).
template <std::size_t R, int W>
[[gnu::always_inline]] inline void first_pass(const double* __restrict xr,
                                              const double* __restrict xi,
                                              double* __restrict yr, double* __restrict yi,
                                              const ComplexFft::Stage& st,
                                              const double* __restrict in) {
  using V = typename VecOf<W>::type;
  const std::size_t m = st.m;
  const double* __restrict wr = st.tw_re.data();
  const double* __restrict wi = st.tw_im.data();
  // Same operations as general_butterfly with the twiddles per element.
  const auto butterfly = [&]<class T>(std::size_t p, T (&ar)[R], T (&ai)[R]) {
    for (std::size_t t = 0; t < R; ++t) {
      if (in == nullptr) {
        ar[t] = load<T>(xr + p + t * m);
        ai[t] = load<T>(xi + p + t * m);
      } else if constexpr (std::is_same_v<T, double>) {
        ar[t] = in[2 * (p + t * m)];
        ai[t] = in[2 * (p + t * m) + 1];
      } else {
        load_deinterleaved<W>(in + 2 * (p + t * m), ar[t], ai[t]);
      }
    }
    Butterfly<R>::apply(ar, ai);
    for (std::size_t u = 1; u < R; ++u) {
      const T c = load<T>(wr + (u - 1) * m + p), d = load<T>(wi + (u - 1) * m + p);
      const T a = ar[u], b = ai[u];
      ar[u] = a * c - b * d;
      ai[u] = a * d + b * c;
    }
  };
  std::size_t p = 0;
  for (; p + W <= m; p += W) {
    V ar[R], ai[R];
    butterfly(p, ar, ai);
    if constexpr (R % W == 0) {
      for (std::size_t u = 0; u < R; u += W) {
        store_transposed<W>(yr + R * p + u, R, ar + u);
        store_transposed<W>(yi + R * p + u, R, ai + u);
      }
    } else {  // R = 2, W ≥ 4: interleave
      static_assert(R == 2);
      store_interleaved<W>(yr + 2 * p, ar[0], ar[1]);
      store_interleaved<W>(yi + 2 * p, ai[0], ai[1]);
    }
  }
  for (; p < m; ++p) {
    double ar[R], ai[R];
    butterfly(p, ar, ai);
    for (std::size_t u = 0; u < R; ++u) {
      yr[R * p + u] = ar[u];
      yi[R * p + u] = ai[u];
    }
  }
}

/// The last pass (m = 1, no twiddles) in place: each q reads its R values before writing them
/// back to the same places. Used when the pass count is odd, instead of a copy at the end.
template <std::size_t R, int W>
[[gnu::always_inline]] inline void last_pass_in_place(double* xr, double* xi, std::size_t s) {
  using V = typename VecOf<W>::type;
  const auto butterfly = [&]<class T>(std::size_t q) {
    T ar[R], ai[R];
    load_and_transform(xr + q, xi + q, s, ar, ai);
    for (std::size_t u = 0; u < R; ++u) {
      store(xr + q + s * u, ar[u]);
      store(xi + q + s * u, ai[u]);
    }
  };
  std::size_t q = 0;
  for (; q + W <= s; q += W) butterfly.template operator()<V>(q);
  if constexpr (W >= 8)
    for (; q + 4 <= s; q += 4) butterfly.template operator()<typename VecOf<4>::type>(q);
  if constexpr (W >= 4)
    for (; q + 2 <= s; q += 2) butterfly.template operator()<typename VecOf<2>::type>(q);
  for (; q < s; ++q) butterfly.template operator()<double>(q);
}

/// The last pass (m = 1, no twiddles) writing interleaved output: out[2j + first] and
/// out[2j + 1 − first] take the results of the xr and xi sides (first = 0 for a forward
/// transform, 1 for the inverse, which runs the forward with the parts exchanged).
template <std::size_t R, int W>
[[gnu::always_inline]] inline void last_pass_interleaved(const double* __restrict xr,
                                                         const double* __restrict xi,
                                                         std::size_t s, int first,
                                                         double* __restrict out) {
  const auto vectors = [&]<int VW>(std::size_t q) {  // q … q + VW − 1
    using V = typename VecOf<VW>::type;
    V ar[R], ai[R];
    load_and_transform(xr + q, xi + q, s, ar, ai);
    for (std::size_t u = 0; u < R; ++u) {
      double* o = out + 2 * (q + s * u);
      if (first == 0)
        store_interleaved<VW>(o, ar[u], ai[u]);
      else
        store_interleaved<VW>(o, ai[u], ar[u]);
    }
  };
  std::size_t q = 0;
  for (; q + W <= s; q += W) vectors.template operator()<W>(q);
  if constexpr (W >= 8)
    for (; q + 4 <= s; q += 4) vectors.template operator()<4>(q);
  for (; q < s; ++q) {
    double ar[R], ai[R];
    load_and_transform(xr + q, xi + q, s, ar, ai);
    for (std::size_t u = 0; u < R; ++u) {
      out[2 * (q + s * u) + first] = ar[u];
      out[2 * (q + s * u) + 1 - first] = ai[u];
    }
  }
}

/// Whether the first pass of this radix has a kernel of its own (first_pass), which can also
/// read interleaved input: radices 2, 4 and 8 at every width W ≤ 8.
constexpr bool has_first_pass_kernel(std::size_t radix) {
  return radix == 2 || radix == 4 || radix == 8;
}

template <std::size_t R, int W>
[[gnu::always_inline]] inline void radix_pass(const double* __restrict xr,
                                              const double* __restrict xi,
                                              double* __restrict yr, double* __restrict yi,
                                              std::size_t s, const ComplexFft::Stage& st,
                                              const double* in = nullptr) {
  static_assert(!has_first_pass_kernel(R) || R % W == 0 || R == 2 || (W == 8 && R % 4 == 0));
  if (s == 1 && st.m > 1) {
    if constexpr (R % W == 0 || R == 2)
      return first_pass<R, W>(xr, xi, yr, yi, st, in);
    else if constexpr (W == 8 && R % 4 == 0)  // radix 4 in the AVX-512 variant
      return first_pass<R, 4>(xr, xi, yr, yi, st, in);
  }
  strided_pass<R, W>(xr, xi, yr, yi, s, st);
}

[[gnu::always_inline]] inline void generic_pass(const double* xr, const double* xi, double* yr, double* yi, std::size_t s,
                  const ComplexFft::Stage& st) {
  const std::size_t r = st.radix, m = st.m;
  std::array<Cx, 13> a{};
  for (std::size_t p = 0; p < m; ++p) {
    for (std::size_t q = 0; q < s; ++q) {
      for (std::size_t t = 0; t < r; ++t) a[t] = {xr[q + s * (p + t * m)], xi[q + s * (p + t * m)]};
      for (std::size_t u = 0; u < r; ++u) {
        Cx acc = a[0];
        for (std::size_t t = 1; t < r; ++t) acc = acc + a[t] * st.roots[(t * u) % r];
        if (u > 0)
          acc = acc * Cx{st.tw_re[(u - 1) * m + p], st.tw_im[(u - 1) * m + p]};
        yr[q + s * (r * p + u)] = acc.re;
        yi[q + s * (r * p + u)] = acc.im;
      }
    }
  }
}

/// All stages of a plan: x → y → x …, the result in (re, im). Inlined into each
/// instruction-set variant below.
/// re[j] = in[2j], im[j] = in[2j + 1] for j < n.
inline void deinterleave(const double* in, std::size_t n, double* re, double* im) {
  for (std::size_t j = 0; j < n; ++j) {
    re[j] = in[2 * j];
    im[j] = in[2 * j + 1];
  }
}

/// out[2j + first] = xr[j], out[2j + 1 − first] = xi[j] (see last_pass_interleaved).
inline void interleave(const double* xr, const double* xi, std::size_t n, int first,
                       double* out) {
  for (std::size_t j = 0; j < n; ++j) {
    out[2 * j + first] = xr[j];
    out[2 * j + 1 - first] = xi[j];
  }
}

/// All stages of a plan: x → y → x …, the result in (re, im) or, when `interleaved` is not
/// null, in interleaved[2j + first], interleaved[2j + 1 − first] (re and im then scratch).
/// Inlined into each instruction-set variant below.
/// With `in` not null the input is in[2j] + i in[2j + 1] (re and im only receive the result):
/// read by the first pass where it has a kernel of its own, else split into (re, im) first.
template <int W>
[[gnu::always_inline]] inline void run_stages(const ComplexFft::Stage* stages,
                                              std::size_t count, double* re, double* im,
                                              double* sr, double* si,
                                              const ComplexFft::PassIo& io) {
  double* const interleaved = io.out;
  const int first = io.first;
  double *xr = re, *xi = im, *yr = sr, *yi = si;
  std::size_t s = 1, n = 1;
  for (std::size_t k = 0; k < count; ++k) n *= stages[k].radix;
  std::size_t k0 = 0;  // the passes done before the loop below
  if (io.in != nullptr) {
    if (count >= 2 && has_first_pass_kernel(stages[0].radix)) {
      const ComplexFft::Stage& st = stages[0];  // (a size-1 plan has no stages: no reference)
      switch (st.radix) {
        case 2: radix_pass<2, W>(xr, xi, yr, yi, 1, st, io.in); break;
        case 4: radix_pass<4, W>(xr, xi, yr, yi, 1, st, io.in); break;
        default: radix_pass<8, W>(xr, xi, yr, yi, 1, st, io.in); break;
      }
      std::swap(xr, yr);
      std::swap(xi, yi);
      s = st.radix;
      k0 = 1;
    } else {
      deinterleave(io.in, n, re, im);
    }
  }
  const std::size_t last_radix = count > 0 ? stages[count - 1].radix : 0;
  const bool fused_output = interleaved != nullptr && count > 0 && last_radix != 7 &&
                            last_radix != 11 && last_radix != 13;
  // The last pass (m = 1) writes the interleaved output, or runs in place when the pass count
  // is odd (else the result would end in the scratch), or is an ordinary pass.
  const std::size_t ordinary = fused_output || count % 2 == 1 ? count - 1 : count;
  for (std::size_t k = k0; k < ordinary; ++k) {
    const ComplexFft::Stage& st = stages[k];
    switch (st.radix) {
      case 2: radix_pass<2, W>(xr, xi, yr, yi, s, st); break;
      case 3: radix_pass<3, W>(xr, xi, yr, yi, s, st); break;
      case 4: radix_pass<4, W>(xr, xi, yr, yi, s, st); break;
      case 5: radix_pass<5, W>(xr, xi, yr, yi, s, st); break;
      case 8: radix_pass<8, W>(xr, xi, yr, yi, s, st); break;
      case 9: radix_pass<9, W>(xr, xi, yr, yi, s, st); break;
      default: generic_pass(xr, xi, yr, yi, s, st); break;
    }
    std::swap(xr, yr);
    std::swap(xi, yi);
    s *= st.radix;
  }
  if (ordinary < count && fused_output) {
    switch (last_radix) {
      case 2: last_pass_interleaved<2, W>(xr, xi, s, first, interleaved); break;
      case 3: last_pass_interleaved<3, W>(xr, xi, s, first, interleaved); break;
      case 4: last_pass_interleaved<4, W>(xr, xi, s, first, interleaved); break;
      case 5: last_pass_interleaved<5, W>(xr, xi, s, first, interleaved); break;
      case 8: last_pass_interleaved<8, W>(xr, xi, s, first, interleaved); break;
      default: last_pass_interleaved<9, W>(xr, xi, s, first, interleaved); break;
    }
    return;
  }
  if (ordinary < count) {  // xr == re here
    const ComplexFft::Stage& st = stages[count - 1];
    switch (st.radix) {
      case 2: last_pass_in_place<2, W>(xr, xi, s); break;
      case 3: last_pass_in_place<3, W>(xr, xi, s); break;
      case 4: last_pass_in_place<4, W>(xr, xi, s); break;
      case 5: last_pass_in_place<5, W>(xr, xi, s); break;
      case 8: last_pass_in_place<8, W>(xr, xi, s); break;
      case 9: last_pass_in_place<9, W>(xr, xi, s); break;
      default: generic_pass(xr, xi, xr, xi, s, st); break;  // reads a q's inputs first
    }
  }
  if (interleaved != nullptr) interleave(re, im, n, first, interleaved);
}

// The instruction-set variants (internal/isa.h): the same source, so the same operations in the
// same order on every element, hence bit-identical results.
void passes_baseline(const ComplexFft::Stage* stages, std::size_t count, double* re,
                     double* im, double* sr, double* si, const ComplexFft::PassIo& io) {
  run_stages<2>(stages, count, re, im, sr, si, io);
}

#if VCMM_GEOMETRY_X86
__attribute__((target("avx2"))) void passes_avx2(const ComplexFft::Stage* stages,
                                                 std::size_t count, double* re, double* im,
                                                 double* sr, double* si,
                                                 const ComplexFft::PassIo& io) {
  run_stages<4>(stages, count, re, im, sr, si, io);
}

__attribute__((target("avx512f,avx512dq,avx512vl"))) void passes_avx512(
    const ComplexFft::Stage* stages, std::size_t count, double* re, double* im, double* sr,
    double* si, const ComplexFft::PassIo& io) {
  run_stages<8>(stages, count, re, im, sr, si, io);
}
#endif

const std::vector<FftVariant>& fft_variants_on_this_cpu() {
  static const std::vector<FftVariant> variants = [] {
    std::vector<FftVariant> out = {{"baseline", passes_baseline}};
#if VCMM_GEOMETRY_X86
    if (cpu_has_avx2()) out.push_back({"avx2", passes_avx2});
    if (cpu_has_avx2() && cpu_has_avx512()) out.push_back({"avx512", passes_avx512});
#endif
    return out;
  }();
  return variants;
}

}  // namespace

const std::vector<FftVariant>& fft_variants() { return fft_variants_on_this_cpu(); }

ComplexFft::ComplexFft(std::size_t n) : n_(n), scratch_re_(n), scratch_im_(n) {
  std::size_t rest = n;
  std::vector<std::size_t> radices;
  // Powers of two: radix 4, with one radix 8 when the exponent is odd (≥ 3): fewer passes.
  std::size_t twos = 0;
  for (std::size_t v = n; v % 2 == 0 && v > 0; v /= 2) ++twos;
  if (twos % 2 == 1 && twos >= 3) {
    radices.push_back(8);
    rest /= 8;
  }
  while (rest % 4 == 0) {
    radices.push_back(4);
    rest /= 4;
  }
  for (std::size_t p : {2, 5, 9, 3, 7, 11, 13}) {
    while (rest % p == 0) {
      radices.push_back(p);
      rest /= p;
    }
  }
  if (rest != 1) {
    setup_bluestein();
    return;
  }
  std::size_t length = n;  // length of the sub-transforms at this stage
  for (std::size_t r : radices) {
    Stage st;
    st.radix = r;
    st.m = length / r;
    st.tw_re.resize((r - 1) * st.m);
    st.tw_im.resize((r - 1) * st.m);
    for (std::size_t u = 1; u < r; ++u) {
      for (std::size_t p = 0; p < st.m; ++p) {
        const Cx w = unit_root(p * u * (n / length), n);
        st.tw_re[(u - 1) * st.m + p] = w.re;
        st.tw_im[(u - 1) * st.m + p] = w.im;
      }
    }
    if (r == 7 || r == 11 || r == 13) {  // the generic radices
      st.roots.resize(r);
      for (std::size_t t = 0; t < r; ++t) st.roots[t] = unit_root(t, r);
    }
    stages_.push_back(std::move(st));
    length /= r;
  }
}

ComplexFft::StagePasses ComplexFft::selected_passes() {  // internal/isa.h
#if VCMM_GEOMETRY_X86
  if (use_avx512()) return passes_avx512;
  if (use_avx2()) return passes_avx2;
#endif
  return passes_baseline;
}

void ComplexFft::forward(double* re, double* im) { run(selected_passes(), re, im, {}); }

void ComplexFft::forward_from_interleaved(const double* in, double* re, double* im) {
  run(selected_passes(), re, im, {in, nullptr, 0});
}

void ComplexFft::inverse_interleaved(double* re, double* im, double* out) {
  run(selected_passes(), im, re, {nullptr, out, 1});  // the inverse: see inverse()
}

void ComplexFft::forward_with(std::string_view variant, double* re, double* im) {
  for (const FftVariant& v : fft_variants())
    if (v.name == variant) return run(v.passes, re, im, {});
  throw std::invalid_argument("ComplexFft::forward_with: no variant " + std::string(variant));
}

void ComplexFft::run(StagePasses passes, double* re, double* im, const PassIo& io) {
  if (conv_) {
    if (io.in != nullptr) deinterleave(io.in, n_, re, im);
    bluestein(passes, re, im);
    if (io.out != nullptr) interleave(re, im, n_, io.first, io.out);
    return;
  }
  passes(stages_.data(), stages_.size(), re, im, scratch_re_.data(), scratch_im_.data(), io);
}

// Bluestein: jk = (j² + k² − (k − j)²)/2, so X_k = c_k Σ_j (x_j c_j) conj(c_{k−j}) with the
// chirp c_j = e^{−πi j²/n}: a convolution, done by FFTs of a smooth size M ≥ 2n − 1.
std::size_t ComplexFft::smooth_size_at_least(std::size_t v) {
  std::size_t best = std::numeric_limits<std::size_t>::max();
  for (std::size_t p2 = 4; p2 < 2 * v; p2 *= 2)  // a multiple of 4: every pass vectorises
    for (std::size_t p3 = p2; p3 < 2 * v; p3 *= 3)
      for (std::size_t p5 = p3; p5 < 2 * v; p5 *= 5)
        if (p5 >= v) best = std::min(best, p5);
  return best;
}

void ComplexFft::setup_bluestein() {
  const std::size_t m = smooth_size_at_least(2 * n_ - 1);
  conv_ = std::make_unique<ComplexFft>(m);
  chirp_.resize(n_);
  for (std::size_t j = 0; j < n_; ++j) {
    const auto j2 = static_cast<std::size_t>((static_cast<unsigned long long>(j) * j) %
                                             (2ULL * n_));
    chirp_[j] = unit_root(j2, 2 * n_);  // e^{−2πi j²/(2n)}
  }
  std::vector<double> hr(m, 0.0), hi(m, 0.0);
  hr[0] = chirp_[0].re;
  hi[0] = -chirp_[0].im;
  for (std::size_t j = 1; j < n_; ++j) {
    hr[j] = hr[m - j] = chirp_[j].re;
    hi[j] = hi[m - j] = -chirp_[j].im;
  }
  conv_->forward(hr.data(), hi.data());
  const double inv_m = 1.0 / static_cast<double>(m);  // the inverse transform's 1/M
  chirp_hat_.resize(m);
  for (std::size_t k = 0; k < m; ++k) chirp_hat_[k] = {hr[k] * inv_m, hi[k] * inv_m};
  work_re_.resize(m);
  work_im_.resize(m);
}

void ComplexFft::bluestein(StagePasses passes, double* re, double* im) {
  const std::size_t m = conv_->size();
  for (std::size_t j = 0; j < n_; ++j) {
    const Cx v = Cx{re[j], im[j]} * chirp_[j];
    work_re_[j] = v.re;
    work_im_[j] = v.im;
  }
  std::fill(work_re_.begin() + static_cast<std::ptrdiff_t>(n_), work_re_.end(), 0.0);
  std::fill(work_im_.begin() + static_cast<std::ptrdiff_t>(n_), work_im_.end(), 0.0);
  conv_->run(passes, work_re_.data(), work_im_.data(), {});
  for (std::size_t k = 0; k < m; ++k) {
    const Cx v = Cx{work_re_[k], work_im_[k]} * chirp_hat_[k];
    work_re_[k] = v.re;
    work_im_[k] = v.im;
  }
  conv_->run(passes, work_im_.data(), work_re_.data(), {});  // the inverse (fft.h)
  for (std::size_t k = 0; k < n_; ++k) {
    const Cx v = Cx{work_re_[k], work_im_[k]} * chirp_[k];
    re[k] = v.re;
    im[k] = v.im;
  }
}

}  // namespace vcmm::geometry::internal
