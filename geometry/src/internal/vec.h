// internal/vec.h — vectors of W doubles for the geometry module's explicitly vectorised
// kernels (internal/fft.cpp, least_squares.cpp): GCC/Clang vector extensions, element-wise IEEE
// operations, so each lane computes exactly what the scalar code computes. W = 2 in a kernel's
// baseline variant (SSE2), 4 in its AVX2 variant, 8 in an AVX-512 one (internal/isa.h). The
// 4- and 8-wide helpers are always inlined into the AVX2 and AVX-512 variants: no vector
// crosses a call boundary, so GCC's note that such a return "changes the ABI" without AVX does
// not apply (it is reported at the end of the translation unit, hence silenced for the
// including file). Not part of the API.
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
struct VecOf<8> {  // AVX-512 variants only
  using type = double __attribute__((vector_size(64)));
  using mask = long long __attribute__((vector_size(64)));
};

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
