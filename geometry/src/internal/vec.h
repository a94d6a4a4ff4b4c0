// internal/vec.h — vectors of W doubles for the geometry module's explicitly vectorised
// kernels (internal/fft.cpp, least_squares.cpp): GCC/Clang vector extensions, element-wise IEEE
// operations, so each lane computes exactly what the scalar code computes. W = 2 in a kernel's
// baseline variant (SSE2), 4 in its AVX2 variant, 8 in an AVX-512 variant (internal/isa.h).
// The 4- and 8-wide helpers are always inlined into the AVX2 and AVX-512 variants: no vector crosses a call boundary, so GCC's note that
// such a return "changes the ABI" without AVX does not apply (it is reported at the end of the
// translation unit, hence silenced for the including file). Not part of the API.
#pragma once

#include <type_traits>

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace vcmm::geometry::internal {

/// VecOf<W>::type: W doubles; ::mask: W 64-bit integers (comparisons, bit operations).
/// (Explicit types per width: GCC drops a vector_size attribute whose size depends on a
/// template parameter of an alias template.)
template <int W>
struct VecOf;
template <>
struct VecOf<2> {
  using type = double __attribute__((vector_size(16)));
  using mask = long long __attribute__((vector_size(16)));
};
template <>
struct VecOf<4> {
  using type = double __attribute__((vector_size(32)));
  using mask = long long __attribute__((vector_size(32)));
};
template <>
struct VecOf<8> {
  using type = double __attribute__((vector_size(64)));
  using mask = long long __attribute__((vector_size(64)));
};

/// The low and high four lanes of an 8-wide vector (AVX-512 variants).
[[gnu::always_inline]] inline VecOf<4>::type low_half(const VecOf<8>::type& v) {
  return __builtin_shufflevector(v, v, 0, 1, 2, 3);
}
[[gnu::always_inline]] inline VecOf<4>::type high_half(const VecOf<8>::type& v) {
  return __builtin_shufflevector(v, v, 4, 5, 6, 7);
}
/// acc += the points of v in point order: a four-lane sum (lane j takes the points ≡ j mod 4)
/// fed by a 4- or 8-wide vector — for 8, its low half, then its high half (the same additions
/// in the same order as two 4-wide steps, so the same bits).
template <class V>
[[gnu::always_inline]] inline void add_in_point_order(VecOf<4>::type& acc, const V& v) {
  if constexpr (sizeof(V) == sizeof(VecOf<4>::type)) {
    acc += v;
  } else {
    acc += low_half(v);
    acc += high_half(v);
  }
}
/// [low half of a | low half of b] and [high half of a | high half of b]: two four-lane sums
/// kept side by side in one 8-lane accumulator take the halves of two 8-lane terms in order.
[[gnu::always_inline]] inline VecOf<8>::type low_halves(const VecOf<8>::type& a,
                                                        const VecOf<8>::type& b) {
  return __builtin_shufflevector(a, b, 0, 1, 2, 3, 8, 9, 10, 11);
}
[[gnu::always_inline]] inline VecOf<8>::type high_halves(const VecOf<8>::type& a,
                                                         const VecOf<8>::type& b) {
  return __builtin_shufflevector(a, b, 4, 5, 6, 7, 12, 13, 14, 15);
}
/// [a | b] from two four-lane vectors.
[[gnu::always_inline]] inline VecOf<8>::type concat(const VecOf<4>::type& a,
                                                    const VecOf<4>::type& b) {
  return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7);
}

/// T (a VecOf type, or double) from p (unaligned).
template <class T>
[[gnu::always_inline]] inline T load(const double* p) {
  if constexpr (std::is_same_v<T, double>) {
    return *p;
  } else {
    T v;
    __builtin_memcpy(&v, p, sizeof(T));
    return v;
  }
}
// v by reference: a 32-byte vector passed by value draws GCC's -Wpsabi note in the baseline
// (non-AVX) compilation of this template, although the call is always inlined.
template <class T>
[[gnu::always_inline]] inline void store(double* p, const T& v) {
  if constexpr (std::is_same_v<T, double>) {
    *p = v;
  } else {
    __builtin_memcpy(p, &v, sizeof(T));
  }
}

}  // namespace vcmm::geometry::internal
