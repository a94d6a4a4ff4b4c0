// geometry/src/internal/isa.h — the instruction-set choice of the geometry module's vectorised
// kernels (the FFT passes, internal/fft.cpp; the Gaussian filter's first pass,
// gaussian_filter.cpp; the least-squares fit's passes, least_squares.cpp). Each kernel is
// compiled from one source two or three times: for the package's baseline ISA and, on x86-64
// with GCC or Clang, with __attribute__((target("avx2"))) and (least_squares.cpp) with
// target("avx512f"). All run the same operations in the same order on every element
// (reductions only over a fixed split into four lanes, one AVX2 or two SSE2 vectors, or the two
// halves of an AVX-512 vector added in point order; no FMA: the project is compiled with
// -ffp-contract=off), so results are bit-identical whichever runs — MPI ranks on different
// machines agree. The widest variant the CPU runs is taken, unless a LimitIsa (e.g.
// ForceBaselineIsa) is alive on the calling thread (tests compare the variants end to end).
// Not part of the API.
#pragma once

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define VCMM_GEOMETRY_X86 1
#else
#define VCMM_GEOMETRY_X86 0
#endif

namespace vcmm::geometry::internal {

/// True when this CPU runs AVX2 (checked once).
inline bool cpu_has_avx2() {
#if VCMM_GEOMETRY_X86
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return has;
#else
  return false;
#endif
}

/// True when this CPU (and the OS) runs AVX-512F (checked once).
inline bool cpu_has_avx512f() {
#if VCMM_GEOMETRY_X86
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") != 0;
  }();
  return has;
#else
  return false;
#endif
}

/// The instruction sets of the kernels' variants, narrowest first.
enum class Isa { baseline = 0, avx2 = 1, avx512 = 2 };

/// The widest variant the kernels may take on this thread (LimitIsa).
inline Isa& isa_limit() {
  thread_local Isa limit = Isa::avx512;
  return limit;
}

/// Whether the kernels called now on this thread take their AVX2 variant (or a wider one).
inline bool use_avx2() { return cpu_has_avx2() && isa_limit() >= Isa::avx2; }

/// Whether the kernels that have one take their AVX-512 variant now on this thread.
inline bool use_avx512() { return cpu_has_avx512f() && isa_limit() >= Isa::avx512; }

/// While alive, the kernels on this thread take no variant wider than `widest`.
class LimitIsa {
 public:
  explicit LimitIsa(Isa widest) : previous_(isa_limit()) { isa_limit() = widest; }
  ~LimitIsa() { isa_limit() = previous_; }
  LimitIsa(const LimitIsa&) = delete;
  LimitIsa& operator=(const LimitIsa&) = delete;

 private:
  Isa previous_;
};

/// While alive, the kernels on this thread take their baseline variant.
class ForceBaselineIsa : public LimitIsa {
 public:
  ForceBaselineIsa() : LimitIsa(Isa::baseline) {}
};

}  // namespace vcmm::geometry::internal
