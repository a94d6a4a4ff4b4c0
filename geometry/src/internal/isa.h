// geometry/src/internal/isa.h — the instruction-set choice of the geometry module's vectorised
// kernels (the FFT passes, internal/fft.cpp; the Gaussian filter's passes, gaussian_filter.cpp
// and internal/closed_filter.cpp; the least-squares fit's passes, least_squares.cpp; the
// distance scans). Each kernel is compiled from one source two or three times: for the
// package's baseline ISA and, on x86-64 with GCC or Clang, with __attribute__((target("avx2")))
// and, for kernels that have one, an AVX-512 target. All run the same operations in the same
// order on every element (reductions only over a fixed split into four lanes — one AVX2 or two
// SSE2 vectors, or the two halves of an AVX-512 vector added in point order — or maxima, exact
// in any grouping; no FMA: the project is compiled with -ffp-contract=off), so results are
// bit-identical whichever runs — MPI ranks on different machines agree. The widest variant the
// CPU has runs, unless a LimitIsa (ForceBaselineIsa) is alive on the calling thread (tests
// compare the variants end to end). Not part of the API.
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

/// True when this CPU runs AVX-512 F, DQ and VL (checked once): the kernels that have an
/// "avx512" variant (the FFT passes, internal/fft.cpp) take it there — 8 doubles a vector, the
/// same element-wise operations (no FMA), so the same bits as the AVX2 and baseline variants.
inline bool cpu_has_avx512() {
#if VCMM_GEOMETRY_X86
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") != 0 && __builtin_cpu_supports("avx512dq") != 0 &&
           __builtin_cpu_supports("avx512vl") != 0;
  }();
  return has;
#else
  return false;
#endif
}

/// The instruction sets a thread's kernels may use, narrowest first.
enum class IsaLevel { baseline = 0, avx2 = 1, avx512 = 2 };

/// The widest level the kernels called on this thread may take (LimitIsa lowers it).
inline IsaLevel& isa_ceiling() {
  thread_local IsaLevel ceiling = IsaLevel::avx512;
  return ceiling;
}

/// Whether the kernels called now on this thread take their AVX2 variant.
inline bool use_avx2() { return cpu_has_avx2() && isa_ceiling() >= IsaLevel::avx2; }
/// Whether the kernels called now on this thread that have an AVX-512 variant take it.
inline bool use_avx512() {
  return cpu_has_avx2() && cpu_has_avx512() && isa_ceiling() >= IsaLevel::avx512;
}

/// While alive, the kernels on this thread take no variant wider than `ceiling` (tests run
/// every variant end to end and compare the bits).
class LimitIsa {
 public:
  explicit LimitIsa(IsaLevel ceiling) : previous_(isa_ceiling()) {
    if (ceiling < previous_) isa_ceiling() = ceiling;
  }
  ~LimitIsa() { isa_ceiling() = previous_; }
  LimitIsa(const LimitIsa&) = delete;
  LimitIsa& operator=(const LimitIsa&) = delete;

 private:
  IsaLevel previous_;
};

/// While alive, the kernels on this thread take their baseline variant.
class ForceBaselineIsa : public LimitIsa {
 public:
  ForceBaselineIsa() : LimitIsa(IsaLevel::baseline) {}
};

}  // namespace vcmm::geometry::internal
