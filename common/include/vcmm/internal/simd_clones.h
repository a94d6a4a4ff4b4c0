// common/include/vcmm/internal/simd_clones.h — the one definition of VCMM_SIMD_CLONES, used by
// the vectorised hot loops of every module (errormodel's kinematic and fused-trial kernels,
// geometry's profile-extremes passes, validation's spectral kernels). Build-tree only: not
// installed, not part of the public API.
//
// With GCC (or Clang) for x86-64 ELF a function marked VCMM_SIMD_CLONES is compiled three times (AVX-512F,
// AVX2, baseline x86-64) and the loader picks the clone the CPU runs. The whole project is
// compiled with -ffp-contract=off (top-level CMakeLists.txt), and the kernels use no
// reductions whose order depends on the vector width, so the three clones round every
// operation alike: results are bit-identical on every CPU. Elsewhere (other compilers and
// targets, ASan builds, where ifunc resolvers and the sanitizer runtime do not mix) one plain
// build.
#pragma once

#if defined(__GNUC__) && defined(__x86_64__) && defined(__ELF__) && !defined(__SANITIZE_ADDRESS__)
#define VCMM_SIMD_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define VCMM_SIMD_CLONES
#endif
