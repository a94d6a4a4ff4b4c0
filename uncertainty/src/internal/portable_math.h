// uncertainty/src/internal/portable_math.h — exp and log written out in IEEE-754 double
// arithmetic, so that the random streams do not depend on the C library's libm.
//
// The C and C++ standards leave the accuracy of std::exp / std::log unspecified, and libms do
// differ in the last bit; the ziggurat tables and its slow paths (wedge test, tail) would then
// give different normal variates on different systems. These two functions use only integer
// operations on the bit pattern and correctly rounded +, −, ×, ÷ (no FMA contraction: the
// including translation units are compiled with -ffp-contract=off, top-level CMakeLists.txt),
// so they return the same bits everywhere.
//
// Algorithms and coefficients: fdlibm 5.3 (Sun Microsystems, 1993; e_exp.c and e_log.c —
// "Developed at SunSoft, a Sun Microsystems, Inc. business. Permission to use, copy, modify,
// and distribute this software is freely granted, provided that this notice is preserved."):
//   exp: x = k·ln2 + r, |r| ≤ ½ln2 (ln2 split in a 32-bit-exact high part and a low part),
//        exp(r) = 1 + r + r·c/(2 − c) with c = r − r²·P(r²), P a degree-5 Remez polynomial
//        (error < 2⁻⁵⁹); then scaled by 2^k. Error < 1 ulp.
//   log: x = 2^k·(1 + f) with √2/2 < 1 + f < √2, s = f/(2 + f),
//        log(1 + f) = f − s·(f − R(s²)) (or the hfsq form), R a degree-7 Remez polynomial
//        (error < 2⁻⁵⁸·⁴⁵); plus k·ln2 in two parts. Error < 1 ulp.
// Tested against std::exp / std::log to ≤ 1 ulp (tests/uncertainty/random_test.cpp).
#pragma once

#include <bit>
#include <cstdint>
#include <limits>

namespace vcmm::uncertainty::internal {

inline std::uint32_t high_word(double x) {
  return static_cast<std::uint32_t>(std::bit_cast<std::uint64_t>(x) >> 32);
}
inline std::uint32_t low_word(double x) {
  return static_cast<std::uint32_t>(std::bit_cast<std::uint64_t>(x));
}
inline double with_high_word(double x, std::uint32_t high) {
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
  return std::bit_cast<double>((static_cast<std::uint64_t>(high) << 32) | (bits & 0xffffffffu));
}

/// e^x for every double x (NaN → NaN, +inf → +inf, −inf → 0, overflow → +inf,
/// underflow → 0 or subnormal). Error < 1 ulp. ~15 ns.
inline double portable_exp(double x) {
  constexpr double o_threshold = 7.09782712893383973096e+02;   // 0x40862E42 FEFA39EF
  constexpr double u_threshold = -7.45133219101941108420e+02;  // 0xC0874910 D52D3051
  constexpr double ln2_hi[2] = {6.93147180369123816490e-01, -6.93147180369123816490e-01};
  constexpr double ln2_lo[2] = {1.90821492927058770002e-10, -1.90821492927058770002e-10};
  constexpr double half[2] = {0.5, -0.5};
  constexpr double inv_ln2 = 1.44269504088896338700e+00;       // 0x3FF71547 652B82FE
  constexpr double two_m1000 = 9.33263618503218878990e-302;    // 2^-1000
  constexpr double P1 = 1.66666666666666019037e-01;   // 0x3FC55555 5555553E
  constexpr double P2 = -2.77777777770155933842e-03;  // 0xBF66C16C 16BEBD93
  constexpr double P3 = 6.61375632143793436117e-05;   // 0x3F11566A AF25DE2C
  constexpr double P4 = -1.65339022054652515390e-06;  // 0xBEBBBD41 C5D26BF1
  constexpr double P5 = 4.13813679705723846039e-08;   // 0x3E663769 72BEA4D0

  std::uint32_t hx = high_word(x);
  const int xsb = static_cast<int>(hx >> 31);
  hx &= 0x7fffffffu;
  if (hx >= 0x40862E42u) {  // |x| ≥ 709.78…: overflow, underflow, inf or NaN
    if (hx >= 0x7ff00000u) {
      if (((hx & 0xfffffu) | low_word(x)) != 0) return x + x;  // NaN
      return xsb == 0 ? x : 0.0;                                 // exp(±inf)
    }
    if (x > o_threshold) return std::numeric_limits<double>::infinity();
    if (x < u_threshold) return 0.0;
  }
  double hi = 0.0, lo = 0.0;
  int k = 0;
  if (hx > 0x3fd62e42u) {      // |x| > ½ ln2
    if (hx < 0x3FF0A2B2u) {    // and |x| < 1.5 ln2
      hi = x - ln2_hi[xsb];
      lo = ln2_lo[xsb];
      k = 1 - xsb - xsb;
    } else {
      k = static_cast<int>(inv_ln2 * x + half[xsb]);
      const double t = k;
      hi = x - t * ln2_hi[0];  // exact: ln2_hi has 32 significant bits, |k| < 1100
      lo = t * ln2_lo[0];
    }
    x = hi - lo;
  } else if (hx < 0x3e300000u) {  // |x| < 2^-28: 1 + x is correctly rounded
    return 1.0 + x;
  }
  const double t = x * x;
  const double c = x - t * (P1 + t * (P2 + t * (P3 + t * (P4 + t * P5))));
  if (k == 0) return 1.0 - ((x * c) / (c - 2.0) - x);
  const double y = 1.0 - ((lo - (x * c) / (2.0 - c)) - hi);
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(y);
  if (k >= -1021) {  // add k to the exponent (result normal)
    return std::bit_cast<double>(bits + (static_cast<std::uint64_t>(static_cast<std::int64_t>(k))
                                         << 52));
  }
  return std::bit_cast<double>(
             bits + (static_cast<std::uint64_t>(static_cast<std::int64_t>(k + 1000)) << 52)) *
         two_m1000;
}

/// Natural logarithm for every double x (x < 0 or NaN → NaN, ±0 → −inf, +inf → +inf;
/// subnormals handled). Error < 1 ulp. ~15 ns.
inline double portable_log(double x) {
  constexpr double ln2_hi = 6.93147180369123816490e-01;  // 0x3FE62E42 FEE00000
  constexpr double ln2_lo = 1.90821492927058770002e-10;  // 0x3DEA39EF 35793C76
  constexpr double two54 = 0x1p54;
  constexpr double Lg1 = 6.666666666666735130e-01;  // 0x3FE55555 55555593
  constexpr double Lg2 = 3.999999999940941908e-01;  // 0x3FD99999 9997FA04
  constexpr double Lg3 = 2.857142874366239149e-01;  // 0x3FD24924 94229359
  constexpr double Lg4 = 2.222219843214978396e-01;  // 0x3FCC71C5 1D8E78AF
  constexpr double Lg5 = 1.818357216161805012e-01;  // 0x3FC74664 96CB03DE
  constexpr double Lg6 = 1.531383769920937332e-01;  // 0x3FC39A09 D078C69F
  constexpr double Lg7 = 1.479819860511658591e-01;  // 0x3FC2F112 DF3E5244

  std::int32_t hx = static_cast<std::int32_t>(high_word(x));
  const std::uint32_t lx = low_word(x);
  int k = 0;
  if (hx < 0x00100000) {  // x < 2^-1022: zero, negative or subnormal
    if (((hx & 0x7fffffff) | static_cast<std::int32_t>(lx)) == 0) {
      return -std::numeric_limits<double>::infinity();
    }
    if (hx < 0) return std::numeric_limits<double>::quiet_NaN();
    k -= 54;
    x *= two54;  // scale the subnormal up
    hx = static_cast<std::int32_t>(high_word(x));
  }
  if (hx >= 0x7ff00000) return x + x;  // +inf or NaN
  k += (hx >> 20) - 1023;
  hx &= 0x000fffff;
  const std::int32_t i = (hx + 0x95f64) & 0x100000;
  x = with_high_word(x, static_cast<std::uint32_t>(hx | (i ^ 0x3ff00000)));  // x or x/2
  k += i >> 20;
  const double f = x - 1.0;
  const double dk = k;
  if ((0x000fffff & (2 + hx)) < 3) {  // |f| < 2^-20
    if (f == 0.0) return k == 0 ? 0.0 : dk * ln2_hi + dk * ln2_lo;
    const double R = f * f * (0.5 - 0.33333333333333333 * f);
    return k == 0 ? f - R : dk * ln2_hi - ((R - dk * ln2_lo) - f);
  }
  const double s = f / (2.0 + f);
  const double z = s * s;
  std::int32_t ii = hx - 0x6147a;
  const double w = z * z;
  const std::int32_t j = 0x6b851 - hx;
  const double t1 = w * (Lg2 + w * (Lg4 + w * Lg6));
  const double t2 = z * (Lg1 + w * (Lg3 + w * (Lg5 + w * Lg7)));
  ii |= j;
  const double R = t2 + t1;
  if (ii > 0) {
    const double hfsq = 0.5 * f * f;
    return k == 0 ? f - (hfsq - s * (hfsq + R))
                  : dk * ln2_hi - ((hfsq - (s * (hfsq + R) + dk * ln2_lo)) - f);
  }
  return k == 0 ? f - s * (f - R) : dk * ln2_hi - ((s * (f - R) - dk * ln2_lo) - f);
}

}  // namespace vcmm::uncertainty::internal
